// Monte Carlo annealing of aggregate topologies (main text, "Monte-Carlo validation of the
// phase diagram", and the snapshots of Fig. 3b): the chain.
//
// N particles occupy distinct sites of a periodic L x L box of cells of the particle's tiling
// (box.hpp). Each attempted move is one of the move families (montecarlo/moves.hpp: particle
// moves with bonded targets, surface moves, linked cluster moves, each a small proposal type in
// its own header). The energy of a configuration is a sum over its connected clusters
// (connectivity through the tiling's edge neighbours, periodic):
//
//     E = sum_clusters [ -g * bonds(cluster) + relaxed deformation energy(cluster) ],
//
// the deformation energy being minimised at fixed topology (main text Eq. 7) before the
// Metropolis test, so the temperature T acts on the topology only. An isolated particle has
// deformation energy exactly 0 (it takes its rest shape).
//
// One path for every move (`attempt`): the family proposes (sites left and reached, bond
// change, log Hastings ratio), the chain makes the move on the occupancy, screens it with the
// bond count (delayed acceptance), relaxes only the clusters it changed (the cluster left,
// possibly split into pieces, and those around the sites reached, merged), then accepts it or
// undoes it. Relaxed deformation energies are cached by shape up to translations and the
// symmetries the particle and its tiling share (shape_key.hpp). The energy of a shape is always
// computed from its canonical representative, so it is a function of the key alone: results do
// not depend on the cache (only speed does).
//
// Clusters that wrap around the box are periodic aggregates (box.hpp): rank 1 a straight fibre
// along the wrap vector, rank 2 a bulk cell. Their period vectors relax (the box stands for an
// infinite system). They are keyed without symmetry reduction, box size included.
//
// The state of the chain is a value (montecarlo/state.hpp), passed into `run` and returned;
// the chain keeps only what it derives from it (occupant of each site, cluster labels and their
// energies, the cache). Everything is a template on the particle model; bind_montecarlo.hpp
// binds one class per model from one template.
#pragma once

#include "box.hpp"
#include "cluster_energy.hpp"
#include "montecarlo/moves.hpp"
#include "montecarlo/options.hpp"
#include "montecarlo/proposal.hpp"
#include "montecarlo/state.hpp"
#include "shape_key.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace pyfrustrate {

// Energies in the units of the particle's springs; g >= 0 is the binding energy per bound pair
// of edges (main text, "Two-dimensional particle model").
template <class Model>
class MonteCarlo {
public:
    MonteCarlo(const Model& model, double g, int L, const MonteCarloOptions& options);

    // A state of n particles at random sites, drawn with the chain's generator seeded by `seed`.
    ChainState initial_state(int n, std::uint64_t seed);
    // `state` with its particles moved to `sites` (particle p at sites[p], reduced modulo L): the
    // energy from scratch, no relaxed displacements known; generator and counters kept.
    ChainState place(ChainState state, const std::vector<Site>& sites);
    // `steps` attempted moves at temperature T >= 0 from `state` (at T = 0 a move is accepted
    // iff dE <= 0: a quench); the state after them, `accepted` the moves accepted.
    ChainState run(ChainState state, double T, std::int64_t steps, std::int64_t& accepted);
    // The energy of `state` recomputed from scratch over every cluster of the box without the
    // cache (canonical: from the canonical representatives, as the cache does; otherwise from
    // the sites as they lie). `state` is handed back unchanged.
    double box_energy(ChainState& state, bool canonical);

    double energy(const ChainState& s) const { return -g_ * static_cast<double>(s.bonds) + s.deformation; }
    const Box& box() const { return box_; }
    double g() const { return g_; }
    const MonteCarloOptions& options() const { return options_; }
    std::size_t cache_size() const { return cache_.size(); }
    void clear_cache() { cache_.clear(); }
    const std::vector<int>& shape_symmetries() const { return symmetries_; }

    // What the move families use while a state is loaded (montecarlo/proposal.hpp).
    int n() const { return static_cast<int>(particles_.size()); }
    int site_of(int particle) const { return particles_[particle]; }
    bool occupied(int s) const { return occupant_[s] >= 0; }
    const std::vector<int>& occupancy() const { return occupant_; }  // particle at each site, -1 if empty
    int occupied_neighbours(int s) const;
    std::uint64_t uniform_index(std::uint64_t n);  // unbiased, in [0, n)
    double uniform01();                            // in [0, 1), 53 bits
    int random_empty_site();

private:
    // The state's parts into the chain, and what it derives from them if the state is not the one
    // this chain returned last; from_scratch: the running deformation recomputed too.
    void load(ChainState& state, bool from_scratch = false);
    void unload(ChainState& state);  // and back, marked as this chain's latest
    template <class F>
    auto with_loaded(ChainState& state, F&& f);  // f() with the state loaded, unloaded even on an exception
    void rebuild(bool from_scratch);
    bool step(double T);
    template <std::size_t I>
    bool step_family(double T);
    template <class Move>
    bool attempt(Move& move, typename Move::Counters& counters, double T);
    void make_move();  // proposal_ on the occupancy (and the warm-start store)
    void undo_move();
    void accept_moved_labels();
    // A move under test, made on the occupancy: particles arrived on `arrived` and left
    // `vacated`. The deformation before (old_ids_, the clusters it changes) and after (fresh_:
    // the clusters through the arrived sites and the pieces next to the vacated ones, relaxed
    // into fresh_energy_); without incremental, the whole box. Once accepted,
    // adopt_fresh_clusters labels fresh_ and stores its displacements in place of old_ids_'.
    // In two parts: find_fresh_clusters (the search, the shape keys, the energies the cache
    // already holds; old_deformation) and relax_fresh_clusters (the others, new_deformation).
    void find_fresh_clusters(const int* arrived, std::size_t n_arrived, const int* vacated, std::size_t n_vacated,
                             double& old_deformation);
    void relax_fresh_clusters(double& new_deformation);
    // A lower bound on the deformation after the move, before relaxing anything: a cluster's
    // relaxed energy is at least the sum of those of any partition of its particles into groups
    // (each group's particles, taken alone, can only relax further: the energy is a sum over
    // particles of non-negative terms), so a fresh cluster's is at least the sum of the old
    // clusters it contains whole (those no particle left); a cached shape gives its energy.
    double fresh_deformation_lower_bound() const;
    void adopt_fresh_clusters();
    // Delayed acceptance of a move that changes the bonds by bond_change (and E - mu n by
    // `reservoir` = -mu dn besides, outline moves), log_hastings being the
    // log ratio of its reverse to its forward proposal probability. First stage: the surrogate
    // energy (returned in `surrogate`, 0 unless delayed) with the proposal ratio, before any
    // relaxation; false if the move is screened out. Second stage: on the energy change delta,
    // dE - dE_s when delayed, else plain Metropolis-Hastings. Each draws one deviate (the first
    // only with delayed acceptance on), whatever the energies.
    bool passes_first_stage(int bond_change, double reservoir, double log_hastings, double T, double& surrogate);
    // The second stage's deviate u is drawn before the relaxation (which draws none), so that a
    // lower bound on delta can decide a rejection without relaxing (second_stage_argument).
    bool passes_second_stage(double delta, double surrogate, double log_hastings, double T, double u) const;
    double second_stage_argument(double delta, double surrogate, double log_hastings, double T) const;
    double shape_energy(const ShapeKey& key, const Cluster& cluster);  // from the key's representative
    double raw_energy(const Cluster& cluster);                        // from the sites as found
    double cluster_energy(const Cluster& cluster);                    // through the cache
    double cluster_energy(const Cluster& cluster, const ShapeKey& key);
    ShapeKey shape_key_of(const Cluster& cluster) const {
        return cluster.rank() ? wrapped_shape_key(cluster, box_.L) : finite_shape_key(tiling(), symmetries_, cluster.unwrapped);
    }
    // Relaxed energy of a fresh cluster of a move through the cache, warm-started from the
    // stored displacements of its particles (parent_start); `displacement` receives the relaxed
    // corner displacements per member and slot (empty if not relaxed here).
    // parent_factor: `factor` receives the cluster relaxed and factorised for its children (null
    // if not relaxed here or too small).
    double fresh_cluster_energy(const Cluster& cluster, const ShapeKey& key, std::vector<double>& displacement,
                                std::shared_ptr<RelaxedCluster>& factor);
    double warm_energy(const Cluster& cluster, std::vector<double>& displacement, std::shared_ptr<RelaxedCluster>& factor);
    // The warm-start store's record per site (parent_start): the particle's relaxed corner
    // displacements less the cluster's affine strain, w = u - A r_ref (2 C doubles), then A (2 x 2,
    // row-major; zero for a finite cluster). A wrapping cluster's displacements grow by dt from one
    // image to the next (its period vectors relax), so they are not a function of the site; with
    // A t_ref = dt for each period vector t_ref, w is, up to a translation, whichever images
    // represent the particles, and u = w + A r_ref with the period parameters' dt = A t_ref restarts it.
    static constexpr int kSiteRecord = 2 * Model::kCornerCount + 4;
    // parent_factor: the stored cluster most of `cluster`'s members belong to, if it differs from
    // it by at most kMaxChangedParticles particles, factorised if it was not yet, and `sites` (the
    // cluster's unwrapped sites) translated by whole boxes onto the parent's own unwrapped sites;
    // nullptr otherwise.
    const RelaxedCluster* parent_of(const Cluster& cluster, std::vector<Site>& sites);
    void forget_displacements(const std::vector<int>& sites);
    // parent_factor: after a rigid move, the factors it carried (make_move) replaced at the sites
    // reached by copies translated with it (translated_cluster), so that parent_of finds the
    // cluster's particles at its factor's sites again. Without it the large box's aggregate,
    // translated whole by a cluster move every few hundred moves at T = 0 (accepted: the energy
    // does not change), lost its parent until its next relaxed move (benchmarks/bench_large_runs.py).
    void translate_factors();
    double scratch_deformation(bool canonical, bool cached, bool relabel);
    int new_cluster_id(double deformation);

    Model model_;
    double g_;
    Box box_;
    MonteCarloOptions options_;
    std::uint64_t id_;            // this chain, in the states it returns
    std::uint64_t version_ = 0;   // of the latest state it returned
    // The loaded state's parts (swapped in by load, out by unload).
    std::vector<int> particles_;  // site of each particle
    std::mt19937_64 rng_;
    double deformation_ = 0.0;
    std::int64_t bonds_ = 0;
    std::vector<double> site_displacement_;
    std::vector<char> site_known_;
    std::vector<std::shared_ptr<RelaxedCluster>> site_factor_;
    ChainCounters counters;
    MoveCounters move_counters_;
    // Derived from the state.
    std::vector<int> occupant_;    // particle at each site, -1 if empty
    std::vector<int> label_;       // cluster id of each occupied site
    std::vector<double> cluster_deformation_;  // by cluster id
    std::vector<int> free_ids_;
    // The chain's own.
    MoveFamilies moves_;
    Proposal proposal_;
    // outline_moves > 0: the box holds one aggregate, which no move may disconnect (outline_move.hpp).
    AggregateGraph aggregate_;
    std::vector<int> arrived_, vacated_;  // the sites a move under test reached and left, insertions and deletions included
    std::vector<int> moved_;  // particles of the move under test, in proposal order
    int removed_particle_ = -1;  // the number of the particle a deletion under test took away
    std::vector<double> saved_displacement_;
    std::vector<char> saved_known_;
    std::vector<std::shared_ptr<RelaxedCluster>> saved_factor_;
    ClusterEnergyCache cache_;
    std::vector<int> symmetries_;  // lattice operations under which shapes are equivalent
    ClusterWorkspace ws_, ws_canonical_;
    std::vector<Cluster> fresh_;         // clusters after the move under test
    std::vector<double> fresh_energy_;
    std::vector<ShapeKey> fresh_key_;       // empty for an isolated particle (energy 0)
    std::vector<double> fresh_cached_;      // the cache's energy of each fresh cluster, NaN if not held
    std::vector<std::vector<double>> fresh_displacement_;
    std::vector<std::shared_ptr<RelaxedCluster>> fresh_factor_;
    std::vector<int> old_ids_;
    const Tiling& tiling() const { return tiling_of(Model::kTiling); }
    static std::uint64_t next_id() {
        static std::atomic<std::uint64_t> ids{0};
        return ++ids;
    }
};

// ---------------------------------------------------------------------------------------------
// State in and out
// ---------------------------------------------------------------------------------------------

template <class Model>
MonteCarlo<Model>::MonteCarlo(const Model& model, double g, int L, const MonteCarloOptions& options)
    : model_(model), g_(g), box_(tiling_of(Model::kTiling), L), options_(options), id_(next_id()),
      symmetries_(pyfrustrate::shape_symmetries(tiling_of(Model::kTiling), Model::kPointGroup)) {
    cache_.limit = options.cache_limit;
    if (L < 2) throw std::invalid_argument("box must be at least 2, got " + std::to_string(L));
    if (!(g >= 0) || !std::isfinite(g)) throw std::invalid_argument("g must be non-negative and finite, got " + std::to_string(g));
    occupant_.assign(box_.n_sites(), -1);
    label_.assign(box_.n_sites(), -1);
    ws_.resize(box_.n_sites());
    ws_canonical_.resize(box_.n_sites());
}

template <class Model>
inline ChainState MonteCarlo<Model>::initial_state(int n, std::uint64_t seed) {
    if (n < 1) throw std::invalid_argument("n must be at least 1, got " + std::to_string(n));
    if (n >= box_.n_sites())
        throw std::invalid_argument("n must be smaller than the box's " + std::to_string(box_.n_sites()) +
                                    " sites (a move needs an empty site), got " + std::to_string(n));
    // Random placement, drawn with the chain's own generator.
    rng_.seed(seed);
    std::fill(occupant_.begin(), occupant_.end(), -1);
    std::vector<Site> sites;
    for (int p = 0; p < n; ++p) {
        const int s = random_empty_site();
        occupant_[s] = p;
        sites.push_back(box_.coords(s));
    }
    ChainState state;
    state.rng = rng_;
    state.particles.assign(n, 0);
    return place(std::move(state), sites);
}

template <class Model>
inline ChainState MonteCarlo<Model>::place(ChainState state, const std::vector<Site>& sites) {
    if (sites.size() != state.particles.size())
        throw std::invalid_argument("sites: expected " + std::to_string(state.particles.size()) + " sites, got " +
                                    std::to_string(sites.size()));
    std::vector<int> occupant(box_.n_sites(), -1);
    for (std::size_t p = 0; p < sites.size(); ++p) {
        if (sites[p][2] < 0 || sites[p][2] >= tiling().sublattices)
            throw std::invalid_argument("sites: sublattice " + std::to_string(sites[p][2]) + " does not exist");
        const int s = box_.index(sites[p]);
        if (occupant[s] >= 0)
            throw std::invalid_argument("sites: site (" + std::to_string(sites[p][0]) + ", " + std::to_string(sites[p][1]) +
                                        ") is occupied twice (modulo the box)");
        occupant[s] = static_cast<int>(p);
        state.particles[p] = s;
    }
    state.displacement.clear(), state.known.clear(), state.factors.clear();
    load(state, true);
    unload(state);
    return state;
}

template <class Model>
inline void MonteCarlo<Model>::load(ChainState& s, bool from_scratch) {
    const bool mine = s.chain_id == id_ && s.version == version_ && !from_scratch;
    particles_.swap(s.particles);
    site_displacement_.swap(s.displacement);
    site_known_.swap(s.known);
    site_factor_.swap(s.factors);
    rng_ = s.rng;
    deformation_ = s.deformation;
    bonds_ = s.bonds;
    counters = s.counters;
    move_counters_ = s.move_counters;
    if (!mine) rebuild(from_scratch);
}

template <class Model>
inline void MonteCarlo<Model>::rebuild(bool from_scratch) {
    const int n = static_cast<int>(particles_.size());
    if (n < 1 || n >= box_.n_sites())
        throw std::invalid_argument("state: " + std::to_string(n) + " particles do not fit the box's " +
                                    std::to_string(box_.n_sites()) + " sites");
    std::fill(occupant_.begin(), occupant_.end(), -1);
    for (int p = 0; p < n; ++p) {
        const int s = particles_[p];
        if (s < 0 || s >= box_.n_sites() || occupant_[s] >= 0)
            throw std::invalid_argument("state: particle " + std::to_string(p) + " on site " + std::to_string(s) +
                                        ", outside the box or taken twice");
        occupant_[s] = p;
    }
    bonds_ = 0;
    for (const int s : particles_) bonds_ += occupied_neighbours(s);
    bonds_ /= 2;
    const std::size_t store = options_.parent_start ? static_cast<std::size_t>(box_.n_sites()) : 0;
    if (site_known_.size() != store || site_displacement_.size() != store * kSiteRecord) {
        site_displacement_.assign(store * kSiteRecord, 0.0);
        site_known_.assign(store, 0);
        site_factor_.clear();
    }
    const std::size_t factors = options_.parent_factor ? store : 0;
    if (site_factor_.size() != factors) site_factor_.assign(factors, nullptr);
    // The clusters' labels and energies; the running deformation stays the state's (a resumed
    // chain continues its own sum) unless asked from scratch.
    const double scratch = scratch_deformation(true, options_.cache, true);
    if (from_scratch) deformation_ = scratch;
}

template <class Model>
inline void MonteCarlo<Model>::unload(ChainState& s) {
    particles_.swap(s.particles);
    site_displacement_.swap(s.displacement);
    site_known_.swap(s.known);
    site_factor_.swap(s.factors);
    s.rng = rng_;
    s.deformation = deformation_;
    s.bonds = bonds_;
    s.counters = counters;
    s.move_counters = move_counters_;
    s.chain_id = id_;
    s.version = ++version_;
}

template <class Model>
template <class F>
inline auto MonteCarlo<Model>::with_loaded(ChainState& state, F&& f) {
    load(state);
    try {
        auto result = f();
        unload(state);
        return result;
    } catch (...) {
        unload(state);
        throw;
    }
}

template <class Model>
inline ChainState MonteCarlo<Model>::run(ChainState state, double T, std::int64_t steps, std::int64_t& accepted) {
    if (!(T >= 0) || !std::isfinite(T)) throw std::invalid_argument("T must be non-negative and finite, got " + std::to_string(T));
    accepted = with_loaded(state, [&] {
        if (options_.outline_moves > 0 && steps > 0 && !aggregate_.connected(*this))
            throw std::invalid_argument("outline moves need the box to hold one connected aggregate, got " +
                                        std::to_string(n()) + " particles in several clusters");
        std::int64_t taken = 0;
        for (std::int64_t k = 0; k < steps; ++k) taken += step(T);
        return taken;
    });
    return state;
}

template <class Model>
inline double MonteCarlo<Model>::box_energy(ChainState& state, bool canonical) {
    return with_loaded(state, [&] { return -g_ * static_cast<double>(bonds_) + scratch_deformation(canonical, false, false); });
}

// ---------------------------------------------------------------------------------------------
// The one path of every move
// ---------------------------------------------------------------------------------------------

template <class Model>
inline bool MonteCarlo<Model>::step(double T) {
    ++counters.attempted;
    return step_family<0>(T);
}

template <class Model>
template <std::size_t I>
inline bool MonteCarlo<Model>::step_family(double T) {
    using Move = std::tuple_element_t<I, MoveFamilies>;
    Move& move = std::get<I>(moves_);
    auto& own = std::get<I>(move_counters_);
    if constexpr (I + 1 == std::tuple_size_v<MoveFamilies>) {
        return attempt(move, own, T);
    } else {
        // No deviate is drawn for a family that is off, so chains without it keep their sequence.
        const double p = Move::probability(options_);
        if (p > 0 && uniform01() < p) return attempt(move, own, T);
        return step_family<I + 1>(T);
    }
}

template <class Model>
template <class Move>
inline bool MonteCarlo<Model>::attempt(Move& move, typename Move::Counters& own, double T) {
    Proposal& p = proposal_;
    p.clear();
    if (!move.propose(*this, p, own)) return false;
    make_move();
    move.after_move(*this, p);
    // Outline moves keep the aggregate connected by construction; a particle moved elsewhere may
    // not disconnect it (outline_move.hpp).
    const bool disconnects = options_.outline_moves > 0 && !p.from.empty() && !aggregate_.connected(*this);
    if (std::isinf(p.log_hastings) || disconnects) {  // the reverse move cannot be proposed, or is out of the state space
        undo_move();
        return false;
    }
    if (p.rigid) {  // nothing to relax: the cluster's label travels with it
        const int id = label_[p.from[0]];
        for (const int s : p.from) label_[s] = -1;
        for (const int t : p.to) label_[t] = id;
        if (options_.parent_factor) translate_factors();
        ++counters.accepted;
        move.accepted(p, own);
        return true;
    }
    // The reservoir's share of the change of E - mu n (outline moves).
    const double reservoir = p.particle_change() == 0 ? 0.0 : -options_.chemical_potential * p.particle_change();
    double surrogate;
    if (!passes_first_stage(p.bond_change, reservoir, p.log_hastings, T, surrogate)) {
        undo_move();
        return false;
    }
    double old_deformation = 0.0, new_deformation = 0.0;
    const double u = uniform01();  // the second stage's deviate
    try {
        if (options_.incremental) {
            // The clusters before the move: those of the sites left, and those of the particles
            // that stay next to the sites reached.
            old_ids_.clear();
            const auto add = [&](int id) {
                if (std::find(old_ids_.begin(), old_ids_.end(), id) == old_ids_.end()) old_ids_.push_back(id);
            };
            for (const int s : vacated_) add(label_[s]);
            for (const int t : arrived_)
                for (int d = 0; d < box_.neighbours(); ++d) {
                    const int v = box_.next(t, d);
                    if (occupant_[v] >= 0 && std::find(arrived_.begin(), arrived_.end(), v) == arrived_.end()) add(label_[v]);
                }
        }
        if (!options_.incremental) {
            old_deformation = deformation_;
            new_deformation = scratch_deformation(true, false, false);
        } else {
            find_fresh_clusters(arrived_.data(), arrived_.size(), vacated_.data(), vacated_.size(), old_deformation);
            // The second stage's test is monotone in the energy change: if even the lower bound
            // on it fails, so does the relaxed one, and the move is rejected without relaxing.
            // Minimised energies only: the linear method's is the energy of the linear response,
            // not a minimum, and no sum of them bounds another.
            if (options_.relax.method != RelaxMethod::Linear) {
                const double lowest = -g_ * p.bond_change + reservoir + (fresh_deformation_lower_bound() - old_deformation);
                if (!metropolis(second_stage_argument(lowest, surrogate, p.log_hastings, T), T, u)) {
                    ++counters.bounded;
                    undo_move();
                    return false;
                }
            }
            relax_fresh_clusters(new_deformation);
        }
    } catch (...) {
        undo_move();
        throw;
    }
    if (!passes_second_stage(-g_ * p.bond_change + reservoir + (new_deformation - old_deformation), surrogate, p.log_hastings,
                             T, u)) {
        undo_move();
        return false;
    }
    ++counters.accepted;
    move.accepted(p, own);
    bonds_ += p.bond_change;
    if (!options_.incremental) {
        deformation_ = new_deformation;
        return true;
    }
    deformation_ += new_deformation - old_deformation;
    accept_moved_labels();
    return true;
}

template <class Model>
inline void MonteCarlo<Model>::make_move() {
    const Proposal& p = proposal_;
    moved_.resize(p.from.size());
    if (options_.parent_start && p.carries_displacements) {
        // The relaxed displacements travel with the particles (saved, to undo).
        constexpr int D = kSiteRecord;
        saved_displacement_.clear(), saved_known_.clear(), saved_factor_.clear();
        for (const std::vector<int>* sites : {&p.from, &p.to})
            for (const int s : *sites) {
                const auto first = site_displacement_.begin() + static_cast<std::ptrdiff_t>(s) * D;
                saved_displacement_.insert(saved_displacement_.end(), first, first + D);
                saved_known_.push_back(site_known_[s]);
                if (options_.parent_factor) saved_factor_.push_back(site_factor_[s]);
            }
        forget_displacements(p.from);
        for (std::size_t k = 0; k < p.to.size(); ++k) {
            std::copy(saved_displacement_.begin() + static_cast<std::ptrdiff_t>(k) * D,
                      saved_displacement_.begin() + static_cast<std::ptrdiff_t>(k + 1) * D,
                      site_displacement_.begin() + static_cast<std::ptrdiff_t>(p.to[k]) * D);
            site_known_[p.to[k]] = saved_known_[k];
            if (options_.parent_factor) site_factor_[p.to[k]] = saved_factor_[k];
        }
    }
    for (std::size_t k = 0; k < p.from.size(); ++k) {
        moved_[k] = occupant_[p.from[k]];
        occupant_[p.from[k]] = -1;
    }
    for (std::size_t k = 0; k < p.to.size(); ++k) {
        occupant_[p.to[k]] = moved_[k];
        particles_[moved_[k]] = p.to[k];
    }
    arrived_.assign(p.to.begin(), p.to.end());
    vacated_.assign(p.from.begin(), p.from.end());
    if (p.removed >= 0) {
        // The last particle takes the removed one's number (undo_move puts it back).
        removed_particle_ = occupant_[p.removed];
        particles_[removed_particle_] = particles_.back();
        occupant_[particles_.back()] = removed_particle_;
        occupant_[p.removed] = -1;
        particles_.pop_back();
        vacated_.push_back(p.removed);
    }
    if (p.inserted >= 0) {
        occupant_[p.inserted] = static_cast<int>(particles_.size());
        particles_.push_back(p.inserted);
        arrived_.push_back(p.inserted);
    }
}

template <class Model>
inline void MonteCarlo<Model>::undo_move() {
    const Proposal& p = proposal_;
    if (p.inserted >= 0) {
        occupant_[p.inserted] = -1;
        particles_.pop_back();
    }
    if (p.removed >= 0) {
        const int last = static_cast<int>(particles_.size());
        if (removed_particle_ < last) {  // the last particle had taken its number
            particles_.push_back(particles_[removed_particle_]);
            occupant_[particles_.back()] = last;
            particles_[removed_particle_] = p.removed;
        } else {
            particles_.push_back(p.removed);
        }
        occupant_[p.removed] = removed_particle_;
    }
    for (const int t : p.to) occupant_[t] = -1;
    for (std::size_t k = 0; k < p.from.size(); ++k) {
        occupant_[p.from[k]] = moved_[k];
        particles_[moved_[k]] = p.from[k];
    }
    if (!(options_.parent_start && p.carries_displacements)) return;
    constexpr int D = kSiteRecord;
    std::size_t q = 0;
    for (const std::vector<int>* sites : {&p.from, &p.to})
        for (const int s : *sites) {
            std::copy(saved_displacement_.begin() + static_cast<std::ptrdiff_t>(q) * D,
                      saved_displacement_.begin() + static_cast<std::ptrdiff_t>(q + 1) * D,
                      site_displacement_.begin() + static_cast<std::ptrdiff_t>(s) * D);
            if (options_.parent_factor) site_factor_[s] = std::move(saved_factor_[q]);
            site_known_[s] = saved_known_[q++];
        }
}

template <class Model>
inline void MonteCarlo<Model>::accept_moved_labels() {
    const Proposal& p = proposal_;
    // A site left is empty now (unless reached again): no label, and no relaxed displacement
    // unless the move carried them along.
    if (options_.parent_start && !p.carries_displacements) forget_displacements(vacated_);
    for (const int s : vacated_) label_[s] = -1;
    adopt_fresh_clusters();
}

// ---------------------------------------------------------------------------------------------
// Random numbers and the occupancy
// ---------------------------------------------------------------------------------------------

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

// ---------------------------------------------------------------------------------------------
// Cluster energies
// ---------------------------------------------------------------------------------------------

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
    return cluster_energy(cl, shape_key_of(cl));
}

template <class Model>
inline double MonteCarlo<Model>::cluster_energy(const Cluster& cl, const ShapeKey& key) {
    if (!options_.cache) return shape_energy(key, cl);
    return cache_.get(key, [&] { return shape_energy(key, cl); }, counters.cache);
}

template <class Model>
inline double MonteCarlo<Model>::fresh_cluster_energy(const Cluster& cl, const ShapeKey& key, std::vector<double>& displacement,
                                                      std::shared_ptr<RelaxedCluster>& factor) {
    displacement.clear();
    factor.reset();
    if (cl.rank() == 0 && cl.size() == 1) return 0.0;  // an isolated particle takes its rest shape
    if (!options_.parent_start) return cluster_energy(cl, key);
    if (!options_.cache) return warm_energy(cl, displacement, factor);
    return cache_.get(key, [&] { return warm_energy(cl, displacement, factor); }, counters.cache);
}

template <class Model>
inline const RelaxedCluster* MonteCarlo<Model>::parent_of(const Cluster& cl, std::vector<Site>& sites) {
    RelaxedCluster* best = nullptr;
    int best_count = 0, best_member = -1;
    for (std::size_t p = 0; p < cl.members.size(); ++p) {
        RelaxedCluster* f = site_factor_[cl.members[p]].get();
        if (!f || f == best) continue;
        int count = 0;
        for (const int m : cl.members) count += site_factor_[m].get() == f;
        if (count > best_count) best = f, best_count = count, best_member = static_cast<int>(p);
    }
    const int np = static_cast<int>(cl.members.size());
    if (!best || best->topology.n_particles() - best_count + np - best_count > kMaxChangedParticles) return nullptr;
    if (!best->factor) {
        // Stored unfactorised (relaxed without a parent): factorised once, on first use, so that
        // the clusters of rejected moves and those never changed again cost no factorisation.
        // The factorised one replaces it at its sites (the stored one may be shared with copies
        // of the state, run elsewhere: never modified); not positive definite: it serves no child.
        ++counters.relax.factorizations;
        const std::shared_ptr<RelaxedCluster> held = site_factor_[cl.members[best_member]];  // alive through the loop
        std::shared_ptr<RelaxedCluster> made = factorised_cluster(model_, best->topology, best->displacement, best->displacement);
        const RelaxedCluster* stored = best;
        best = made.get();
        // At its members' sites (this cluster's, which hold it even when a cluster move carried
        // it away from its own sites, and its own sites').
        for (const int m : cl.members)
            if (site_factor_[m].get() == stored) site_factor_[m] = made;
        for (const Site& q : stored->topology.sites) {
            std::shared_ptr<RelaxedCluster>& at = site_factor_[box_.index(q)];
            if (at.get() == stored) at = made;
        }
        if (!best) return nullptr;
    }
    // The parent was unwrapped from another start: align a shared member (modified_cluster
    // matches particles by site).
    const int m = cl.members[best_member];
    for (const Site& q : best->topology.sites)
        if (box_.index(q) == m) {
            const int di = q[0] - cl.unwrapped[best_member][0], dj = q[1] - cl.unwrapped[best_member][1];
            sites = cl.unwrapped;
            for (Site& s : sites) s[0] += di, s[1] += dj;
            return best;
        }
    return nullptr;  // a cluster move carried the parent's factor to other sites: no parent
}

template <class Model>
inline double MonteCarlo<Model>::warm_energy(const Cluster& cl, std::vector<double>& displacement,
                                             std::shared_ptr<RelaxedCluster>& factor) {
    constexpr int C = Model::kCornerCount;
    constexpr int R = kSiteRecord;
    // The parent's factor serves finite clusters only (parent_factor.hpp).
    const bool keeps_factor = options_.parent_factor && cl.rank() == 0 &&
                              static_cast<int>(cl.members.size()) >= options_.parent_factor_min_particles;
    std::vector<Site> aligned;
    const RelaxedCluster* parent = keeps_factor ? parent_of(cl, aligned) : nullptr;
    const Topology topology = cluster_topology(tiling(), parent ? aligned : cl.unwrapped, cl);
    const int nc = topology.n_corners(), np = topology.n_particles();
    const int n_state = 2 * nc + topology.n_period_parameters();
    const int n_periods = topology.n_period_vectors();
    const Vector period_reference = topology.reference_period_parameters();
    // The start: each corner's stored displacement, u = w + A r_ref (kSiteRecord; corners shared
    // by particles of one parent agree; particles of different parents share none), and for a
    // wrapping cluster the period vectors' dt = A t_ref with the known particles' mean strain A;
    // the one particle allowed without one (the moved particle) takes the rigid motion that best
    // fits its known corners. More unknown particles (a parent's energy came from the cache), or
    // a poor fit: the cold start.
    Vector start = Vector::Zero(n_state);
    std::vector<int> count(nc, 0);
    Mat2 mean_strain = Mat2::Zero();
    int known = 0;
    for (int p = 0; p < np; ++p) {
        const int site = cl.members[p];
        if (!site_known_[site]) continue;
        ++known;
        const double* d = &site_displacement_[static_cast<std::size_t>(site) * R];
        const Mat2 strain = Eigen::Map<const Eigen::Matrix<double, 2, 2, Eigen::RowMajor>>(d + 2 * C);
        mean_strain += strain;
        for (int s = 0; s < C; ++s) {
            const int c = topology.corner[p][s];
            start.segment<2>(2 * c) += Vec2(d[2 * s], d[2 * s + 1]) + strain * topology.reference[c];
            ++count[c];
        }
    }
    bool warm = known > 0 && np - known <= 1 && !topology.curved;
    int unknown_particle = -1;
    std::vector<int> new_dof;  // of the corners only the unknown particle holds
    double misfit = 0;  // largest distance of a known corner of an unknown particle from the rigid fit
    if (warm) {
        for (int c = 0; c < nc; ++c)
            if (count[c] > 1) start.segment<2>(2 * c) /= count[c];
        mean_strain /= known;
        for (int v = 0; v < n_periods; ++v)
            start.segment<2>(2 * nc + 2 * v) = mean_strain * period_reference.segment<2>(2 * v);
        for (int p = 0; p < np; ++p) {
            if (site_known_[cl.members[p]]) continue;
            unknown_particle = p;
            // The rigid fit places corners in the cell, not their periodic images: a particle
            // with a slot across the cell's seam starts cold.
            if (topology.has_image(p)) {
                warm = false;
                break;
            }
            std::vector<int> known_corner(nc);
            for (int c = 0; c < nc; ++c) known_corner[c] = count[c] > 0;
            misfit = fit_particle_corners(topology, p, start, known_corner, &new_dof);
        }
    }
    // A new particle that bridges corners the parents left far from a rigid fit starts under a
    // large strain, from which Newton takes more steps than from the linear solution.
    if (misfit > kWarmMisfit * model_.step_scale()) warm = false;
    // The unknown particle's own corners relaxed with every other corner held, as the parent
    // path does (parent_factor.hpp, relax_new_corners): the rigid fit leaves it strained, and
    // Newton's first exact steps from there are damped or cut short. A dense problem of at most
    // 2 C unknowns; it removes about one factorisation of the whole cluster per relaxation
    // (bench_mc_goals.py, factorizations_per_relaxation against the baseline build).
    if (warm && unknown_particle >= 0 && !parent) {
        const Network<Model> net{model_, topology};
        relax_new_corners(net, start, {unknown_particle}, new_dof, 1e-3 * options_.relax.minimize.gradient_tolerance);
    }
    Vector u;
    std::shared_ptr<RelaxedCluster> own;
    const double e = relaxed_cluster_energy(model_, topology, options_.relax, counters.relax, warm ? &start : nullptr, &u,
                                            parent, parent ? &own : nullptr);
    if (keeps_factor && !own && u.size() == n_state) {
        // Relaxed without its parent's factor: kept unfactorised until a child needs it (parent_of).
        own = std::make_shared<RelaxedCluster>();
        own->topology = topology;
        own->displacement = u;
    }
    factor = std::move(own);
    if (u.size() == n_state) {
        remove_rigid_motion(topology, u);
        // The strain A with A t_ref = dt for each period vector (the least-norm one for a fibre).
        Mat2 strain = Mat2::Zero();
        if (n_periods == 1) {
            const Vec2 t = period_reference.head<2>();
            strain = u.segment<2>(2 * nc) * t.transpose() / t.squaredNorm();
        } else if (n_periods == 2) {
            Mat2 dt, t;
            dt << u.segment<2>(2 * nc), u.segment<2>(2 * nc + 2);
            t << period_reference.head<2>(), period_reference.segment<2>(2);
            strain = dt * t.inverse();
        }
        displacement.resize(static_cast<std::size_t>(np) * R);
        for (int p = 0; p < np; ++p) {
            double* d = &displacement[static_cast<std::size_t>(p) * R];
            for (int s = 0; s < C; ++s) {
                const int c = topology.corner[p][s];
                const Vec2 w = u.segment<2>(2 * c) - strain * topology.reference[c];
                d[2 * s] = w.x(), d[2 * s + 1] = w.y();
            }
            Eigen::Map<Eigen::Matrix<double, 2, 2, Eigen::RowMajor>>(d + 2 * C) = strain;
        }
    }
    return e;
}

template <class Model>
inline void MonteCarlo<Model>::translate_factors() {
    const Proposal& p = proposal_;
    const Site a = box_.coords(p.from[0]), b = box_.coords(p.to[0]);
    // The shortest of the shifts that agree modulo the box (sites match modulo the box anyway).
    const auto nearest = [L = box_.L](int d) { return d - L * static_cast<int>(std::lround(static_cast<double>(d) / L)); };
    const LatticeVector shift{nearest(b[0] - a[0]), nearest(b[1] - a[1])};
    std::vector<std::pair<RelaxedCluster*, std::shared_ptr<RelaxedCluster>>> done;  // each carried factor once
    for (const int t : p.to) {
        std::shared_ptr<RelaxedCluster>& at = site_factor_[t];
        if (!at) continue;
        auto it = std::find_if(done.begin(), done.end(), [&](const auto& d) { return d.first == at.get(); });
        if (it == done.end()) it = done.insert(done.end(), {at.get(), translated_cluster(*at, shift)});
        at = it->second;
    }
}

template <class Model>
inline void MonteCarlo<Model>::forget_displacements(const std::vector<int>& sites) {
    for (const int s : sites) site_known_[s] = 0;
    if (options_.parent_factor)
        for (const int s : sites) site_factor_[s] = nullptr;
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
inline void MonteCarlo<Model>::find_fresh_clusters(const int* arrived, std::size_t n_arrived, const int* vacated,
                                                   std::size_t n_vacated, double& old_deformation) {
    old_deformation = 0.0;
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
    fresh_key_.resize(fresh_.size());
    fresh_cached_.assign(fresh_.size(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t k = 0; k < fresh_.size(); ++k) {
        const Cluster& cl = fresh_[k];
        if (cl.rank() == 0 && cl.size() == 1) {
            fresh_key_[k].clear();
            fresh_cached_[k] = 0.0;
            continue;
        }
        fresh_key_[k] = shape_key_of(cl);
        if (!options_.cache) continue;
        if (const double* e = cache_.peek(fresh_key_[k])) fresh_cached_[k] = *e;
    }
}

template <class Model>
inline double MonteCarlo<Model>::fresh_deformation_lower_bound() const {
    const auto moved_here = [&](int s) { return std::find(arrived_.begin(), arrived_.end(), s) != arrived_.end(); };
    // Old clusters a particle left: their remains are no longer whole, and bound nothing.
    std::vector<int> whole;
    for (const int id : old_ids_) {
        bool left = false;
        for (const int s : vacated_) left = left || label_[s] == id;
        if (!left) whole.push_back(id);
    }
    double lower = 0.0;
    std::vector<char> counted(whole.size(), 0);
    for (std::size_t k = 0; k < fresh_.size(); ++k) {
        if (!std::isnan(fresh_cached_[k])) {
            lower += fresh_cached_[k];
            continue;
        }
        for (const int m : fresh_[k].members) {
            if (moved_here(m)) continue;  // its label is the site's old one, not this particle's
            const auto it = std::find(whole.begin(), whole.end(), label_[m]);
            if (it == whole.end() || counted[it - whole.begin()]) continue;
            counted[it - whole.begin()] = 1;
            lower += cluster_deformation_[*it];
        }
    }
    return lower;
}

template <class Model>
inline void MonteCarlo<Model>::relax_fresh_clusters(double& new_deformation) {
    new_deformation = 0.0;
    fresh_energy_.clear();
    fresh_displacement_.resize(std::max(fresh_displacement_.size(), fresh_.size()));
    fresh_factor_.assign(fresh_.size(), nullptr);  // a rejected move's factors go with the next move
    for (std::size_t k = 0; k < fresh_.size(); ++k) {
        if (!fresh_key_[k].empty() && !std::isnan(fresh_cached_[k])) {
            ++counters.cache.hits;  // found by find_fresh_clusters
            fresh_displacement_[k].clear();
            fresh_energy_.push_back(fresh_cached_[k]);
        } else {
            fresh_energy_.push_back(fresh_cluster_energy(fresh_[k], fresh_key_[k], fresh_displacement_[k], fresh_factor_[k]));
        }
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
    constexpr int D = kSiteRecord;
    for (std::size_t k = 0; k < fresh_.size(); ++k) {
        const std::vector<double>& d = fresh_displacement_[k];
        const bool stored = d.size() == fresh_[k].members.size() * D;
        for (std::size_t q = 0; q < fresh_[k].members.size(); ++q) {
            const int m = fresh_[k].members[q];
            site_known_[m] = stored;
            if (options_.parent_factor) site_factor_[m] = fresh_factor_[k];
            if (stored) std::copy(d.begin() + q * D, d.begin() + (q + 1) * D, site_displacement_.begin() + static_cast<std::ptrdiff_t>(m) * D);
        }
    }
}

template <class Model>
inline bool MonteCarlo<Model>::passes_first_stage(int bond_change, double reservoir, double log_hastings, double T,
                                                  double& surrogate) {
    // The surrogate costs no relaxation. Its deviate is drawn whatever the energy change, so that
    // roundoff in an energy can never shift the random sequence. At T = 0 there is no
    // distribution to keep, only a descent: every move that lowers the energy is taken, which the
    // two stages would refuse whenever the surrogate overstates a gain (a bound pair of triangles
    // costs far less than e_b per bond, so below the gas threshold pairs would never break).
    const bool delayed = options_.delayed_acceptance && T > 0;
    surrogate = delayed ? -(g_ - options_.bond_deformation) * bond_change + reservoir : 0.0;
    if (!options_.delayed_acceptance) return true;
    const double u = uniform01();
    if (!delayed || metropolis(surrogate - T * log_hastings, T, u)) return true;
    ++counters.screened;
    return false;
}

template <class Model>
inline double MonteCarlo<Model>::second_stage_argument(double delta, double surrogate, double log_hastings,
                                                       double T) const {
    // Delayed: the proposal ratio was taken in the first stage.
    const bool delayed = options_.delayed_acceptance && T > 0;
    return delayed ? delta - surrogate : delta - T * log_hastings;
}

template <class Model>
inline bool MonteCarlo<Model>::passes_second_stage(double delta, double surrogate, double log_hastings, double T,
                                                   double u) const {
    return metropolis(second_stage_argument(delta, surrogate, log_hastings, T), T, u);
}

}  // namespace pyfrustrate
