// Monte Carlo annealing of aggregate topologies (main text, "Monte-Carlo validation of the
// phase diagram", and the snapshots of Fig. 3b).
//
// N particles occupy distinct sites of a periodic L x L box of cells of the particle's tiling
// (box.hpp). A move takes a random particle to a random empty site (or next to another particle:
// bonded moves), a particle of an aggregate's outline to another site of an outline (surface
// moves), or shifts a set of bonded particles by a random lattice vector (cluster moves); the
// options and Hastings ratios are in MonteCarloOptions. The energy of a
// configuration is a sum over its connected clusters (connectivity through the tiling's edge
// neighbours, periodic):
//
//     E = sum_clusters [ -g * bonds(cluster) + relaxed deformation energy(cluster) ],
//
// the deformation energy being minimised at fixed topology (main text Eq. 7) before the
// Metropolis test, so the temperature T acts on the topology only. An isolated particle has
// deformation energy exactly 0 (it takes its rest shape).
//
// Only what a move changes is recomputed: the cluster the particle leaves (possibly split into
// pieces) and the clusters around its new site (merged). Relaxed deformation energies are cached
// by shape up to translations and the symmetries the particle and its tiling share
// (shape_key.hpp). The energy of a shape is always computed from its canonical representative,
// so it is a function of the key alone: results do not depend on the cache (only speed does).
//
// Clusters that wrap around the box are periodic aggregates (box.hpp): rank 1 a straight fibre
// along the wrap vector, rank 2 a bulk cell. Their period vectors relax (the box stands for an
// infinite system). They are keyed without symmetry reduction, box size included.
//
// Pieces: box.hpp (box and clusters), shape_key.hpp (canonical keys), cluster_energy.hpp
// (relaxed cluster energies and their cache), this file (the chain). Everything is a template
// on the particle model; bind_montecarlo.hpp binds one class per model from one template.
#pragma once

#include "box.hpp"
#include "cluster_energy.hpp"
#include "shape_key.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace pyfrustrate {

// Metropolis acceptance of an energy change at temperature T with the uniform deviate u.
inline bool metropolis(double delta, double T, double u) { return delta <= 0 || (T > 0 && u < std::exp(-delta / T)); }

struct MonteCarloOptions {
    ClusterRelaxOptions relax;
    // Delayed acceptance (Christen & Fox, J. Comput. Graph. Stat. 14, 795 (2005)): a move is
    // first screened with the surrogate energy E_s = -(g - bond_deformation) * bonds, accepted
    // there with min(1, exp(-dE_s / T)); only then are the clusters relaxed and the move
    // accepted with min(1, exp(-(dE - dE_s) / T)). E_s being a function of the configuration,
    // the chain still satisfies detailed balance with respect to exp(-E / T): same Boltzmann
    // distribution at every T, far fewer relaxations at low T (moves that break bonds are
    // mostly screened out). false: plain Metropolis, min(1, exp(-dE / T)).
    bool delayed_acceptance = true;
    double bond_deformation = 0.0;  // surrogate deformation energy per bond (bulk: e_b / bonds per particle)
    // Probability that an attempted move is a cluster translation instead of a particle move: a
    // set S of particles grown from a random one is shifted by a uniformly random lattice vector
    // of the box (a symmetric proposal), rejected if it would overlap another particle.
    // S is grown by bond percolation: each bond from S to an occupied site outside it is
    // followed with probability p = cluster_link. The probability of proposing S is
    // (1/N) F(S) (1 - p)^b, where F depends only on the bonds inside S (which the shift keeps)
    // and b counts the bonds from S to the rest; the reverse shift has the same F and b' (the
    // bonds after the move), so Metropolis-Hastings accepts with min(1, exp(-dE/T) (1-p)^(b'-b))
    // (a cluster move with a fixed link probability; Whitelam & Geissler's virtual-move Monte
    // Carlo, J. Chem. Phys. 127, 154101 (2007), makes links depend on pair energies, which an
    // elastic energy does not split into). With p < 1 aggregates meet and merge in one move,
    // and the reverse move splits them. p = 1: S is the whole cluster and (1 - p)^(b' - b)
    // forbids any new contact, so the move changes neither shape, bonds nor energy and needs no
    // relaxation. cluster_moves = 0: particle moves only.
    double cluster_moves = 0.0;
    double cluster_link = 1.0;
    // Probability that a particle move targets an empty site next to another particle (a random
    // other particle, a random one of its neighbouring sites) instead of a random empty site:
    // aggregation-volume-bias moves (Chen & Siepmann, J. Phys. Chem. B 104, 8725 (2000)), which
    // propose the surface moves that reshape an aggregate far more often. With w this
    // probability, E empty sites, D neighbours per site and c the occupied neighbours of the
    // target (the moving particle excluded), the proposal probability of a move is
    // ((1 - w) / E + w c_target / (D (N - 1))) / N, the reverse one the same with c of the
    // site left; Metropolis-Hastings takes their ratio. 0: random empty sites only; below 1, or
    // a particle could never leave an aggregate (the chain would not be ergodic).
    double bonded_moves = 0.0;
    // Probability that an attempted move (not a cluster move) is a surface move: a random
    // particle among those with an empty neighbour (n_s of them) goes to a random empty site
    // among those with an occupied neighbour (n_p). The reverse move exists iff the site left
    // keeps an occupied neighbour and the site reached has an empty one; Metropolis-Hastings
    // then takes the ratio n_s n_p / (n_s' n_p') of the counts before and after (a move kernel
    // of its own, mixed with the others at a fixed probability, so each keeps detailed balance
    // alone). Where bonded moves propose a given kink-to-kink jump of a 200-particle aggregate
    // with probability ~ w c / (D N^2), this proposes it with ~ 1 / (n_s n_p): the bond-neutral
    // rearrangements that take an aggregate's outline to the one with the most bonds are tried
    // some 50 times as often. 0: none (no deviate drawn).
    double surface_moves = 0.0;
    bool cache = true;        // cache relaxed energies by canonical shape
    bool incremental = true;  // false: re-minimise every cluster of the box on every move
                              // (the naive baseline of the benchmark; no cache either)
    std::size_t cache_limit = std::size_t(1) << 24;  // stored key entries (8 bytes each) before the cache is cleared
    // Newton only: relax the clusters a move makes from the relaxed displacements of the
    // clusters they came from (the particles that stay keep their corners' displacements, the
    // moved one starts rigidly attached), exact Hessian from the first step; the cluster is
    // relaxed as it lies rather than as its canonical representative. Energies then agree with
    // the cold start (the linear solution of the canonical representative) to the solver's
    // tolerance, not to the last bit: they depend on the path (and on the cache) at that level.
    bool parent_start = false;
};

// parent_start: a moved particle whose known corners lie farther than this many step_scale
// (the mismatch) from the rigid fit makes the start cold. Measured in the dense box (300 in
// 30 x 30, ell = 5, nu = 0.4, 200 sweeps), factorisations per minimisation: 4.98 at 0.3, 5.00
// at 1, 4.82 at 3, 5.42 without a limit, 6.23 with cold starts only.
constexpr double kWarmMisfit = 3.0;

struct MonteCarloCounters {
    std::int64_t attempted = 0, accepted = 0;
    std::int64_t screened = 0;  // rejected by the surrogate, without relaxing anything
    std::int64_t cluster_attempted = 0, cluster_accepted = 0;  // cluster translations (within attempted/accepted)
    std::int64_t cluster_rebonded = 0;  // accepted translations that made or broke bonds (aggregates met or split)
    std::int64_t surface_attempted = 0, surface_accepted = 0;  // surface moves (within attempted/accepted)
    CacheCounters cache;
    RelaxCounters relax;
};

// The Monte Carlo state: occupancy, particle list, random generator, counters, cluster table
// and cache. Energies in the units of the particle's springs; g >= 0 is the binding energy per
// bound pair of edges (main text, "Two-dimensional particle model").
template <class Model>
class MonteCarlo {
public:
    MonteCarlo(const Model& model, double g, int L, int n, std::uint64_t seed, const MonteCarloOptions& options);

    // Places the particles on `sites` (lattice coordinates, reduced modulo L; particle p at
    // sites[p]); rebuilds the clusters and the energy from scratch.
    void place(const std::vector<Site>& sites);

    // One attempted move at temperature T >= 0 (Metropolis, or delayed acceptance; at T = 0 a
    // move is accepted iff dE <= 0 either way: a quench), or with probability
    // options.cluster_moves a cluster translation; and `steps` of them; run returns the number
    // accepted.
    bool step(double T);
    std::int64_t run(double T, std::int64_t steps);

    // Current energy (running sum over accepted moves), its parts, and the from-scratch
    // recomputation over every cluster of the box without the cache (canonical: from the
    // canonical representatives, as the cache does; otherwise from the sites as they lie).
    double energy() const { return -g_ * static_cast<double>(bonds_) + deformation_; }
    double deformation() const { return deformation_; }
    std::int64_t bonds() const { return bonds_; }
    double box_energy(bool canonical);

    // Exact-resumption state: the running deformation sum and the generator (its stream
    // representation, std::mt19937_64 operator<<).
    void set_deformation(double e) { deformation_ = e; }
    std::string rng_state() const;
    void set_rng_state(const std::string& state);

    // Site index of each particle. With the generator state this is the whole state of the
    // chain: empty sites are drawn by rejection, so no other ordering needs saving.
    const std::vector<int>& particles() const { return particles_; }
    const Box& box() const { return box_; }
    int n() const { return static_cast<int>(particles_.size()); }
    double g() const { return g_; }
    MonteCarloCounters counters;
    std::size_t cache_size() const { return cache_.size(); }
    void clear_cache() { cache_.clear(); }
    const std::vector<int>& shape_symmetries() const { return symmetries_; }
    // Relaxed deformation energy of a cluster of this box through the cache.
    double cluster_energy(const Cluster& cluster);

private:
    std::uint64_t uniform_index(std::uint64_t n);  // unbiased, in [0, n)
    double uniform01();                            // in [0, 1), 53 bits
    int random_empty_site();
    bool particle_step(double T);
    bool surface_step(double T);
    bool cluster_step(double T);
    // Moves particle p to the empty site b and accepts or undoes it; log_hastings(lost, gained)
    // gives the log ratio of the reverse to the forward proposal probability once the move is
    // made on the occupancy (lost, gained: the bonds at the site left and at b), -inf if the
    // reverse move cannot be proposed.
    template <class Hastings>
    bool try_particle_move(int p, int b, double T, const Hastings& log_hastings);
    // Particles with an empty neighbour and empty sites with an occupied neighbour, among
    // `sites` (each once) as the occupancy stands.
    std::pair<int, int> exposed_counts(const std::vector<int>& sites) const;
    // A move under test, made on the occupancy: particles arrived on `arrived` and left
    // `vacated`. The deformation before (old_ids_, the clusters it changes) and after (fresh_:
    // the clusters through the arrived sites and the pieces next to the vacated ones, relaxed
    // into fresh_energy_); without incremental, the whole box. Once accepted,
    // adopt_fresh_clusters labels fresh_ and stores its displacements in place of old_ids_'.
    void relax_changed_clusters(const int* arrived, std::size_t n_arrived, const int* vacated, std::size_t n_vacated,
                                double& old_deformation, double& new_deformation);
    void adopt_fresh_clusters();
    // Delayed acceptance of a move that changes the bonds by bond_change, log_hastings being the
    // log ratio of its reverse to its forward proposal probability. First stage: the surrogate
    // energy (returned in `surrogate`, 0 unless delayed) with the proposal ratio, before any
    // relaxation; false if the move is screened out. Second stage: on the energy change delta,
    // dE - dE_s when delayed, else plain Metropolis-Hastings. Each draws one deviate (the first
    // only with delayed acceptance on), whatever the energies.
    bool passes_first_stage(int bond_change, double log_hastings, double T, double& surrogate);
    bool passes_second_stage(double delta, double surrogate, double log_hastings, double T);
    double shape_energy(const ShapeKey& key, const Cluster& cluster);  // from the key's representative
    double raw_energy(const Cluster& cluster);                        // from the sites as found
    // Relaxed energy of a fresh cluster of a move through the cache, warm-started from the
    // stored displacements of its particles (parent_start); `displacement` receives the relaxed
    // corner displacements per member and slot (empty if not relaxed here).
    double fresh_cluster_energy(const Cluster& cluster, std::vector<double>& displacement);
    double warm_energy(const Cluster& cluster, std::vector<double>& displacement);
    void forget_displacements(const std::vector<int>& sites);
    double scratch_deformation(bool canonical, bool cached, bool relabel);
    int occupied_neighbours(int s) const;
    int new_cluster_id(double deformation);

    Model model_;
    double g_;
    Box box_;
    MonteCarloOptions options_;
    std::vector<int> occupant_;    // particle at each site, -1 if empty
    std::vector<int> particles_;   // site of each particle
    std::vector<int> label_;       // cluster id of each occupied site
    std::vector<double> cluster_deformation_;  // by cluster id
    std::vector<int> free_ids_;
    std::int64_t bonds_ = 0;
    double deformation_ = 0.0;
    std::mt19937_64 rng_;
    ClusterEnergyCache cache_;
    std::vector<int> symmetries_;  // lattice operations under which shapes are equivalent
    ClusterWorkspace ws_, ws_canonical_, grown_;  // grown_: the set a cluster move shifts
    std::vector<int> surface_, perimeter_, around_;  // surface moves: candidates, and the sites a move can change
    std::vector<Cluster> fresh_;         // clusters after the move under test
    std::vector<double> fresh_energy_;
    // parent_start: the relaxed displacement of every corner slot of the particle on each site
    // (lab frame, rigid motion removed; 2 C doubles per site) and whether it is known (the
    // cluster's energy came from a relaxation, not from the cache). Empty sites are unknown.
    std::vector<double> site_displacement_;
    std::vector<char> site_known_;
    std::vector<std::vector<double>> fresh_displacement_;
    std::vector<int> old_ids_;
    const Tiling& tiling() const { return tiling_of(Model::kTiling); }
};

// ---------------------------------------------------------------------------------------------
// Member functions
// ---------------------------------------------------------------------------------------------

template <class Model>
MonteCarlo<Model>::MonteCarlo(const Model& model, double g, int L, int n, std::uint64_t seed,
                              const MonteCarloOptions& options)
    : model_(model), g_(g), box_(tiling_of(Model::kTiling), L), options_(options), rng_(seed),
      symmetries_(pyfrustrate::shape_symmetries(tiling_of(Model::kTiling), Model::kPointGroup)) {
    cache_.limit = options.cache_limit;
    if (L < 2) throw std::invalid_argument("box must be at least 2, got " + std::to_string(L));
    if (!(g >= 0) || !std::isfinite(g)) throw std::invalid_argument("g must be non-negative and finite, got " + std::to_string(g));
    if (n < 1) throw std::invalid_argument("n must be at least 1, got " + std::to_string(n));
    if (n >= box_.n_sites())
        throw std::invalid_argument("n must be smaller than the box's " + std::to_string(box_.n_sites()) +
                                    " sites (a move needs an empty site), got " + std::to_string(n));
    occupant_.assign(box_.n_sites(), -1);
    label_.assign(box_.n_sites(), -1);
    ws_.resize(box_.n_sites());
    ws_canonical_.resize(box_.n_sites());
    grown_.resize(box_.n_sites());
    if (options_.parent_start) {
        site_displacement_.assign(static_cast<std::size_t>(box_.n_sites()) * 2 * Model::kCornerCount, 0.0);
        site_known_.assign(box_.n_sites(), 0);
    }
    // Random initial placement, drawn with the chain's own generator.
    particles_.assign(n, -1);
    std::vector<Site> sites;
    for (int p = 0; p < n; ++p) {
        const int s = random_empty_site();
        occupant_[s] = p;
        sites.push_back(box_.coords(s));
    }
    place(sites);
}

template <class Model>
inline std::uint64_t MonteCarlo<Model>::uniform_index(std::uint64_t n) {
    const std::uint64_t threshold = (0 - n) % n;  // 2^64 mod n: reject the biased remainder
    for (;;) {
        const std::uint64_t r = rng_();
        if (r >= threshold) return r % n;
    }
}

template <class Model>
inline double MonteCarlo<Model>::uniform01() {
    return static_cast<double>(rng_() >> 11) * 0x1.0p-53;
}

template <class Model>
inline int MonteCarlo<Model>::random_empty_site() {
    for (;;) {
        const int s = static_cast<int>(uniform_index(box_.n_sites()));
        if (occupant_[s] < 0) return s;
    }
}

template <class Model>
inline int MonteCarlo<Model>::occupied_neighbours(int s) const {
    int count = 0;
    for (int d = 0; d < box_.neighbours(); ++d) count += occupant_[box_.next(s, d)] >= 0;
    return count;
}

template <class Model>
inline void MonteCarlo<Model>::place(const std::vector<Site>& sites) {
    if (static_cast<int>(sites.size()) != n())
        throw std::invalid_argument("sites: expected " + std::to_string(n()) + " sites, got " + std::to_string(sites.size()));
    std::vector<int> occupant(box_.n_sites(), -1), particles(sites.size());
    for (std::size_t p = 0; p < sites.size(); ++p) {
        if (sites[p][2] < 0 || sites[p][2] >= tiling().sublattices)
            throw std::invalid_argument("sites: sublattice " + std::to_string(sites[p][2]) + " does not exist");
        const int s = box_.index(sites[p]);
        if (occupant[s] >= 0)
            throw std::invalid_argument("sites: site (" + std::to_string(sites[p][0]) + ", " + std::to_string(sites[p][1]) +
                                        ") is occupied twice (modulo the box)");
        occupant[s] = static_cast<int>(p);
        particles[p] = s;
    }
    occupant_.swap(occupant);
    particles_.swap(particles);
    bonds_ = 0;
    for (const int s : particles_) bonds_ += occupied_neighbours(s);
    bonds_ /= 2;
    std::fill(site_known_.begin(), site_known_.end(), 0);
    deformation_ = scratch_deformation(true, options_.cache, true);
}

template <class Model>
inline double MonteCarlo<Model>::shape_energy(const ShapeKey& key, const Cluster& cl) {
    std::vector<Site> sites;
    Cluster wrap;
    if (cl.rank() == 0) {
        sites = key_sites(key);
    } else {
        // Canonical embedding: the search from the smallest member site, sorted.
        ws_canonical_.new_round();
        wrap = find_cluster(box_, occupant_, static_cast<int>(key[5]), ws_canonical_);
        sites = wrap.unwrapped;
        std::sort(sites.begin(), sites.end());
    }
    return relaxed_cluster_energy(model_, cluster_topology(tiling(), sites, wrap), options_.relax, counters.relax);
}

template <class Model>
inline double MonteCarlo<Model>::raw_energy(const Cluster& cl) {
    if (cl.rank() == 0 && cl.size() == 1) return 0.0;
    return relaxed_cluster_energy(model_, cluster_topology(tiling(), cl.unwrapped, cl), options_.relax, counters.relax);
}

template <class Model>
inline double MonteCarlo<Model>::cluster_energy(const Cluster& cl) {
    if (cl.rank() == 0 && cl.size() == 1) return 0.0;  // an isolated particle takes its rest shape
    const ShapeKey key =
        cl.rank() ? wrapped_shape_key(cl, box_.L) : finite_shape_key(tiling(), symmetries_, cl.unwrapped);
    if (!options_.cache) return shape_energy(key, cl);
    return cache_.get(key, [&] { return shape_energy(key, cl); }, counters.cache);
}

template <class Model>
inline double MonteCarlo<Model>::fresh_cluster_energy(const Cluster& cl, std::vector<double>& displacement) {
    displacement.clear();
    if (!options_.parent_start || cl.rank() != 0) return cluster_energy(cl);
    if (cl.size() == 1) return 0.0;
    const ShapeKey key = finite_shape_key(tiling(), symmetries_, cl.unwrapped);
    if (!options_.cache) return warm_energy(cl, displacement);
    return cache_.get(key, [&] { return warm_energy(cl, displacement); }, counters.cache);
}

template <class Model>
inline double MonteCarlo<Model>::warm_energy(const Cluster& cl, std::vector<double>& displacement) {
    constexpr int C = Model::kCornerCount;
    const Topology topology = cluster_topology(tiling(), cl.unwrapped, cl);
    const int nc = topology.n_corners(), np = topology.n_particles();
    // The start: each corner's stored displacement (corners shared by particles of one parent
    // agree; particles of different parents share none); the one particle allowed without one
    // (the moved particle) takes the rigid motion that best fits its known corners. More
    // unknown particles (a parent's energy came from the cache), or a poor fit: the cold start.
    Vector start = Vector::Zero(2 * nc);
    std::vector<int> count(nc, 0);
    int known = 0;
    for (int p = 0; p < np; ++p) {
        const int site = cl.members[p];
        if (!site_known_[site]) continue;
        ++known;
        const double* d = &site_displacement_[static_cast<std::size_t>(site) * 2 * C];
        for (int s = 0; s < C; ++s) {
            const int c = topology.corner[p][s];
            start[2 * c] += d[2 * s];
            start[2 * c + 1] += d[2 * s + 1];
            ++count[c];
        }
    }
    bool warm = known > 0 && np - known <= 1;
    double misfit = 0;  // largest distance of a known corner of an unknown particle from the rigid fit
    if (warm) {
        for (int c = 0; c < nc; ++c)
            if (count[c] > 1) start.segment<2>(2 * c) /= count[c];
        for (int p = 0; p < np; ++p) {
            if (site_known_[cl.members[p]]) continue;
            // The rigid motion of its reference corners that best fits its known corners
            // (least squares; the translation alone if only one is known).
            Vec2 r_mean = Vec2::Zero(), x_mean = Vec2::Zero();
            int n = 0;
            for (int s = 0; s < C; ++s) {
                const int c = topology.corner[p][s];
                if (count[c] == 0) continue;
                r_mean += topology.reference[c];
                x_mean += topology.reference[c] + start.segment<2>(2 * c);
                ++n;
            }
            if (n == 0) continue;
            r_mean /= n, x_mean /= n;
            double sin_sum = 0, cos_sum = 0;
            for (int s = 0; s < C; ++s) {
                const int c = topology.corner[p][s];
                if (count[c] == 0) continue;
                const Vec2 r = topology.reference[c] - r_mean, x = topology.reference[c] + start.segment<2>(2 * c) - x_mean;
                sin_sum += r.x() * x.y() - r.y() * x.x();
                cos_sum += r.dot(x);
            }
            const double angle = n > 1 ? std::atan2(sin_sum, cos_sum) : 0.0;
            Mat2 rotation;
            rotation << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
            for (int s = 0; s < C; ++s) {
                const int c = topology.corner[p][s];
                if (count[c] > 0) {
                    misfit = std::max(misfit, (x_mean + rotation * (topology.reference[c] - r_mean) - topology.reference[c] -
                                               start.segment<2>(2 * c)).norm());
                    continue;
                }
                if (count[c] != 0) continue;
                start.segment<2>(2 * c) = x_mean + rotation * (topology.reference[c] - r_mean) - topology.reference[c];
                count[c] = 1;
            }
        }
    }
    // A new particle that bridges corners the parents left far from a rigid fit starts under a
    // large strain, from which Newton takes more steps than from the linear solution.
    if (misfit > kWarmMisfit * model_.step_scale()) warm = false;
    Vector u;
    const double e = relaxed_cluster_energy(model_, topology, options_.relax, counters.relax, warm ? &start : nullptr, &u);
    if (u.size() == 2 * nc) {
        remove_rigid_motion(topology, u);
        displacement.resize(static_cast<std::size_t>(np) * 2 * C);
        for (int p = 0; p < np; ++p)
            for (int s = 0; s < C; ++s) {
                const int c = topology.corner[p][s];
                displacement[(static_cast<std::size_t>(p) * C + s) * 2] = u[2 * c];
                displacement[(static_cast<std::size_t>(p) * C + s) * 2 + 1] = u[2 * c + 1];
            }
    }
    return e;
}

template <class Model>
inline void MonteCarlo<Model>::forget_displacements(const std::vector<int>& sites) {
    for (const int s : sites) site_known_[s] = 0;
}

template <class Model>
inline int MonteCarlo<Model>::new_cluster_id(double deformation) {
    if (free_ids_.empty()) {
        cluster_deformation_.push_back(deformation);
        return static_cast<int>(cluster_deformation_.size()) - 1;
    }
    const int id = free_ids_.back();
    free_ids_.pop_back();
    cluster_deformation_[id] = deformation;
    return id;
}

template <class Model>
inline double MonteCarlo<Model>::scratch_deformation(bool canonical, bool cached, bool relabel) {
    const bool saved = options_.cache;
    options_.cache = cached;
    if (relabel) cluster_deformation_.clear(), free_ids_.clear();
    ws_.new_round();
    double total = 0.0;
    try {
        for (const int s : particles_) {
            if (ws_.seen(s)) continue;
            const Cluster cl = find_cluster(box_, occupant_, s, ws_);
            const double e = canonical ? cluster_energy(cl) : raw_energy(cl);
            total += e;
            if (relabel) {
                const int id = new_cluster_id(e);
                for (const int m : cl.members) label_[m] = id;
            }
        }
    } catch (...) {
        options_.cache = saved;
        throw;
    }
    options_.cache = saved;
    return total;
}

template <class Model>
inline double MonteCarlo<Model>::box_energy(bool canonical) {
    return -g_ * static_cast<double>(bonds_) + scratch_deformation(canonical, false, false);
}

template <class Model>
inline bool MonteCarlo<Model>::step(double T) {
    ++counters.attempted;
    // No deviate is drawn without cluster moves, so particle-move chains keep their sequence.
    if (options_.cluster_moves > 0 && uniform01() < options_.cluster_moves) return cluster_step(T);
    if (options_.surface_moves > 0 && uniform01() < options_.surface_moves) return surface_step(T);
    return particle_step(T);
}

template <class Model>
inline void MonteCarlo<Model>::relax_changed_clusters(const int* arrived, std::size_t n_arrived, const int* vacated,
                                                      std::size_t n_vacated, double& old_deformation, double& new_deformation) {
    old_deformation = new_deformation = 0.0;
    if (!options_.incremental) {
        old_deformation = deformation_;
        new_deformation = scratch_deformation(true, false, false);
        return;
    }
    for (const int id : old_ids_) old_deformation += cluster_deformation_[id];
    fresh_.clear();
    ws_.new_round();
    for (std::size_t k = 0; k < n_arrived; ++k)
        if (!ws_.seen(arrived[k])) fresh_.push_back(find_cluster(box_, occupant_, arrived[k], ws_));
    for (std::size_t k = 0; k < n_vacated; ++k)
        for (int d = 0; d < box_.neighbours(); ++d) {
            const int u = box_.next(vacated[k], d);
            if (occupant_[u] >= 0 && !ws_.seen(u)) fresh_.push_back(find_cluster(box_, occupant_, u, ws_));
        }
    fresh_energy_.clear();
    fresh_displacement_.resize(std::max(fresh_displacement_.size(), fresh_.size()));
    for (std::size_t k = 0; k < fresh_.size(); ++k) {
        fresh_energy_.push_back(fresh_cluster_energy(fresh_[k], fresh_displacement_[k]));
        new_deformation += fresh_energy_.back();
    }
}

template <class Model>
inline void MonteCarlo<Model>::adopt_fresh_clusters() {
    for (const int id : old_ids_) free_ids_.push_back(id);
    for (std::size_t k = 0; k < fresh_.size(); ++k) {
        const int id = new_cluster_id(fresh_energy_[k]);
        for (const int m : fresh_[k].members) label_[m] = id;
    }
    if (!options_.parent_start) return;
    constexpr int D = 2 * Model::kCornerCount;
    for (std::size_t k = 0; k < fresh_.size(); ++k) {
        const std::vector<double>& d = fresh_displacement_[k];
        const bool stored = d.size() == fresh_[k].members.size() * D;
        for (std::size_t q = 0; q < fresh_[k].members.size(); ++q) {
            const int m = fresh_[k].members[q];
            site_known_[m] = stored;
            if (stored) std::copy(d.begin() + q * D, d.begin() + (q + 1) * D, site_displacement_.begin() + static_cast<std::ptrdiff_t>(m) * D);
        }
    }
}

template <class Model>
inline bool MonteCarlo<Model>::passes_first_stage(int bond_change, double log_hastings, double T, double& surrogate) {
    // The surrogate costs no relaxation. Its deviate is drawn whatever the energy change, so that
    // roundoff in an energy can never shift the random sequence. At T = 0 there is no
    // distribution to keep, only a descent: every move that lowers the energy is taken, which the
    // two stages would refuse whenever the surrogate overstates a gain (a bound pair of triangles
    // costs far less than e_b per bond, so below the gas threshold pairs would never break).
    const bool delayed = options_.delayed_acceptance && T > 0;
    surrogate = delayed ? -(g_ - options_.bond_deformation) * bond_change : 0.0;
    if (!options_.delayed_acceptance) return true;
    const double u = uniform01();
    if (!delayed || metropolis(surrogate - T * log_hastings, T, u)) return true;
    ++counters.screened;
    return false;
}

template <class Model>
inline bool MonteCarlo<Model>::passes_second_stage(double delta, double surrogate, double log_hastings, double T) {
    // Delayed: the proposal ratio was taken in the first stage.
    const bool delayed = options_.delayed_acceptance && T > 0;
    return metropolis(delayed ? delta - surrogate : delta - T * log_hastings, T, uniform01());
}

template <class Model>
inline bool MonteCarlo<Model>::cluster_step(double T) {
    ++counters.cluster_attempted;
    const int a = particles_[uniform_index(particles_.size())];
    const int L = box_.L;
    const int di = static_cast<int>(uniform_index(L)), dj = static_cast<int>(uniform_index(L));  // a cell shift
    if (di == 0 && dj == 0) return false;
    // The set S, by bond percolation from a: every bond from S to an occupied site outside it
    // is tested once (p = 1 draws no deviate: S is a's whole cluster).
    const double p = options_.cluster_link;
    grown_.new_round();
    std::vector<int> set{a};
    grown_.mark[a] = grown_.stamp;
    for (std::size_t k = 0; k < set.size(); ++k)
        for (int d = 0; d < box_.neighbours(); ++d) {
            const int u = box_.next(set[k], d);
            if (occupant_[u] < 0 || grown_.seen(u)) continue;
            if (p >= 1 || uniform01() < p) {
                grown_.mark[u] = grown_.stamp;
                set.push_back(u);
            }
        }
    // Bonds from S to the rest before (b) and after (b') the shift; targets must be empty or in S.
    // The clusters the move changes: the one S comes from and those its targets touch.
    std::vector<int> targets(set.size());
    int outer_before = 0, outer_after = 0;
    old_ids_.assign(1, label_[a]);
    for (std::size_t k = 0; k < set.size(); ++k) {
        const Site c = box_.coords(set[k]);
        const int t = box_.index({c[0] + di, c[1] + dj, c[2]});
        if (occupant_[t] >= 0 && !grown_.seen(t)) return false;
        targets[k] = t;
        for (int d = 0; d < box_.neighbours(); ++d) {
            const int u = box_.next(set[k], d), v = box_.next(t, d);
            outer_before += occupant_[u] >= 0 && !grown_.seen(u);
            if (occupant_[v] < 0 || grown_.seen(v)) continue;  // the rest does not move
            ++outer_after;
            if (std::find(old_ids_.begin(), old_ids_.end(), label_[v]) == old_ids_.end()) old_ids_.push_back(label_[v]);
        }
    }
    const int new_bonds = outer_after - outer_before;
    if (p >= 1 && new_bonds > 0) return false;  // (1 - p)^(b' - b) = 0
    const double log_hastings = new_bonds == 0 ? 0.0 : new_bonds * std::log1p(-p);

    // The move, undone unless accepted; parent_start: the displacements travel with the particles.
    constexpr int D = 2 * Model::kCornerCount;
    std::vector<int> moved(set.size());
    std::vector<double> saved_displacement, carried;
    std::vector<char> saved_known, carried_known;
    if (options_.parent_start) {
        for (const std::vector<int>* sites : {&set, &targets})
            for (const int s : *sites) {
                saved_displacement.insert(saved_displacement.end(), site_displacement_.begin() + static_cast<std::ptrdiff_t>(s) * D,
                                          site_displacement_.begin() + static_cast<std::ptrdiff_t>(s + 1) * D);
                saved_known.push_back(site_known_[s]);
            }
        carried.assign(saved_displacement.begin(), saved_displacement.begin() + static_cast<std::ptrdiff_t>(set.size()) * D);
        carried_known.assign(saved_known.begin(), saved_known.begin() + static_cast<std::ptrdiff_t>(set.size()));
        forget_displacements(set);
        for (std::size_t k = 0; k < targets.size(); ++k) {
            std::copy(carried.begin() + static_cast<std::ptrdiff_t>(k) * D, carried.begin() + static_cast<std::ptrdiff_t>(k + 1) * D,
                      site_displacement_.begin() + static_cast<std::ptrdiff_t>(targets[k]) * D);
            site_known_[targets[k]] = carried_known[k];
        }
    }
    for (std::size_t k = 0; k < set.size(); ++k) {
        moved[k] = occupant_[set[k]];
        occupant_[set[k]] = -1;
    }
    for (std::size_t k = 0; k < targets.size(); ++k) {
        occupant_[targets[k]] = moved[k];
        particles_[moved[k]] = targets[k];
    }
    const auto undo = [&] {
        for (const int t : targets) occupant_[t] = -1;
        for (std::size_t k = 0; k < set.size(); ++k) {
            occupant_[set[k]] = moved[k];
            particles_[moved[k]] = set[k];
        }
        if (!options_.parent_start) return;
        std::size_t q = 0;
        for (const std::vector<int>* sites : {&set, &targets})
            for (const int s : *sites) {
                std::copy(saved_displacement.begin() + static_cast<std::ptrdiff_t>(q) * D,
                          saved_displacement.begin() + static_cast<std::ptrdiff_t>(q + 1) * D,
                          site_displacement_.begin() + static_cast<std::ptrdiff_t>(s) * D);
                site_known_[s] = saved_known[q++];
            }
    };

    if (outer_before == 0 && outer_after == 0) {
        // S is a whole cluster and touches nothing where it lands: same shape, same bonds, same
        // energy; accepted without relaxing anything.
        const int id = label_[set[0]];
        for (const int s : set) label_[s] = -1;
        for (const int t : targets) label_[t] = id;
        ++counters.accepted;
        ++counters.cluster_accepted;
        return true;
    }

    double surrogate;
    if (!passes_first_stage(new_bonds, log_hastings, T, surrogate)) {
        undo();
        return false;
    }
    double old_deformation = 0.0, new_deformation = 0.0;
    try {
        relax_changed_clusters(targets.data(), targets.size(), set.data(), set.size(), old_deformation, new_deformation);
    } catch (...) {
        undo();
        throw;
    }
    if (!passes_second_stage(-g_ * new_bonds + (new_deformation - old_deformation), surrogate, log_hastings, T)) {
        undo();
        return false;
    }
    ++counters.accepted;
    ++counters.cluster_accepted;
    ++counters.cluster_rebonded;
    bonds_ += new_bonds;
    deformation_ += new_deformation - old_deformation;
    if (!options_.incremental) return true;
    for (const int s : set) label_[s] = -1;
    adopt_fresh_clusters();
    return true;
}

template <class Model>
inline bool MonteCarlo<Model>::particle_step(double T) {
    const int p = static_cast<int>(uniform_index(particles_.size()));
    const int N = n();
    // The target: a random empty site, or (bonded_moves) a random neighbour site of a random
    // other particle, refused if occupied. No deviate is drawn without bonded moves.
    int b;
    if (options_.bonded_moves > 0 && uniform01() < options_.bonded_moves) {
        if (N < 2) return false;
        const int q = static_cast<int>(uniform_index(N - 1));
        b = box_.next(particles_[q >= p ? q + 1 : q], static_cast<int>(uniform_index(box_.neighbours())));
        if (occupant_[b] >= 0) return false;
    } else {
        b = random_empty_site();
    }
    // Bonded moves: the log ratio of the reverse to the forward proposal probability (gained =
    // occupied neighbours of b without the mover, lost = those of the site left).
    return try_particle_move(p, b, T, [&](int lost, int gained) {
        if (options_.bonded_moves <= 0 || N < 2) return 0.0;
        const double w = options_.bonded_moves, uniform = (1 - w) / (box_.n_sites() - N),
                     bonded = w / (static_cast<double>(box_.neighbours()) * (N - 1));
        const double forward = uniform + bonded * gained, reverse = uniform + bonded * lost;
        return std::log(reverse / forward);  // reverse > 0: w < 1
    });
}

template <class Model>
inline std::pair<int, int> MonteCarlo<Model>::exposed_counts(const std::vector<int>& sites) const {
    int surface = 0, perimeter = 0;
    for (const int s : sites) {
        const int c = occupied_neighbours(s);
        if (occupant_[s] >= 0) surface += c < box_.neighbours();
        else perimeter += c > 0;
    }
    return {surface, perimeter};
}

template <class Model>
inline bool MonteCarlo<Model>::surface_step(double T) {
    ++counters.surface_attempted;
    // The candidates, listed afresh (O(N D), small beside a relaxation): particles with an empty
    // neighbour, and the empty sites next to a particle, each once.
    surface_.clear();
    perimeter_.clear();
    grown_.new_round();
    for (const int s : particles_) {
        bool exposed = false;
        for (int d = 0; d < box_.neighbours(); ++d) {
            const int u = box_.next(s, d);
            if (occupant_[u] >= 0) continue;
            exposed = true;
            if (!grown_.seen(u)) {
                grown_.mark[u] = grown_.stamp;
                perimeter_.push_back(u);
            }
        }
        if (exposed) surface_.push_back(s);
    }
    if (surface_.empty() || perimeter_.empty()) return false;  // a full box
    const int a = surface_[uniform_index(surface_.size())];
    const int b = perimeter_[uniform_index(perimeter_.size())];
    // Only a, b and their neighbours can change status: the counts after the move are those
    // before plus the change over these sites.
    around_.assign({a, b});
    for (const int s : {a, b})
        for (int d = 0; d < box_.neighbours(); ++d) around_.push_back(box_.next(s, d));
    std::sort(around_.begin(), around_.end());
    around_.erase(std::unique(around_.begin(), around_.end()), around_.end());
    const std::pair<int, int> before = exposed_counts(around_);
    const double n_surface = static_cast<double>(surface_.size()), n_perimeter = static_cast<double>(perimeter_.size());
    const bool accepted = try_particle_move(occupant_[a], b, T, [&](int, int) {
        if (occupied_neighbours(a) == 0 || occupied_neighbours(b) == box_.neighbours())
            return -std::numeric_limits<double>::infinity();  // no reverse proposal
        const std::pair<int, int> after = exposed_counts(around_);
        const double surface_after = n_surface + after.first - before.first,
                     perimeter_after = n_perimeter + after.second - before.second;
        return std::log(n_surface * n_perimeter / (surface_after * perimeter_after));
    });
    counters.surface_accepted += accepted;
    return accepted;
}

template <class Model>
template <class Hastings>
inline bool MonteCarlo<Model>::try_particle_move(int p, int b, double T, const Hastings& hastings) {
    const int a = particles_[p];
    const int lost = occupied_neighbours(a);  // bonds of the particle at a (b is empty)
    // The move, undone unless accepted.
    const auto undo = [&] {
        occupant_[b] = -1;
        occupant_[a] = p;
        particles_[p] = a;
    };
    occupant_[a] = -1;
    occupant_[b] = p;
    particles_[p] = b;
    const int gained = occupied_neighbours(b);  // bonds at b (a is now empty)
    const double log_hastings = hastings(lost, gained);
    if (std::isinf(log_hastings)) {  // the reverse move cannot be proposed
        undo();
        return false;
    }
    double surrogate;
    if (!passes_first_stage(gained - lost, log_hastings, T, surrogate)) {
        undo();
        return false;
    }
    double old_deformation = 0.0, new_deformation = 0.0;
    try {
        if (options_.incremental) {
            // Clusters before the move: the one left at a, and those next to b.
            old_ids_.assign(1, label_[a]);
            for (int d = 0; d < box_.neighbours(); ++d) {
                const int t = box_.next(b, d);
                if (occupant_[t] >= 0 && std::find(old_ids_.begin(), old_ids_.end(), label_[t]) == old_ids_.end())
                    old_ids_.push_back(label_[t]);
            }
        }
        relax_changed_clusters(&b, 1, &a, 1, old_deformation, new_deformation);
    } catch (...) {
        undo();
        throw;
    }
    if (!passes_second_stage(-g_ * (gained - lost) + (new_deformation - old_deformation), surrogate, log_hastings, T)) {
        undo();
        return false;
    }
    ++counters.accepted;
    bonds_ += gained - lost;
    if (!options_.incremental) {
        deformation_ = new_deformation;
        return true;
    }
    deformation_ += new_deformation - old_deformation;
    if (options_.parent_start) site_known_[a] = 0;
    adopt_fresh_clusters();
    return true;
}

template <class Model>
inline std::int64_t MonteCarlo<Model>::run(double T, std::int64_t steps) {
    if (!(T >= 0) || !std::isfinite(T)) throw std::invalid_argument("T must be non-negative and finite, got " + std::to_string(T));
    std::int64_t accepted = 0;
    for (std::int64_t k = 0; k < steps; ++k) accepted += step(T);
    return accepted;
}

template <class Model>
inline std::string MonteCarlo<Model>::rng_state() const {
    std::ostringstream out;
    out << rng_;
    return out.str();
}

template <class Model>
inline void MonteCarlo<Model>::set_rng_state(const std::string& state) {
    std::istringstream in(state);
    std::mt19937_64 r;
    in >> r;
    if (in.fail()) throw std::invalid_argument("rng_state: not a std::mt19937_64 state");
    rng_ = r;
}

}  // namespace pyfrustrate
