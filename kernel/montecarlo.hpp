// Monte Carlo annealing of aggregate topologies (main text, "Monte-Carlo validation of the
// phase diagram", and the snapshots of Fig. 3b).
//
// N particles occupy distinct sites of a periodic L x L box of the triangular lattice (site
// (i, j) at i a1 + j a2, i and j modulo L; see topology.hpp). A move takes a random particle to
// a random empty site. The energy of a configuration is a sum over its connected clusters
// (connectivity through the six lattice neighbours, periodic):
//
//     E = sum_clusters [ -g * bonds(cluster) + relaxed deformation energy(cluster) ],
//
// the deformation energy being minimised at fixed topology (main text Eq. 7) before the
// Metropolis test, so the temperature T acts on the topology only. An isolated particle has
// deformation energy exactly 0 (it takes its rest shape).
//
// Only what a move changes is recomputed: the cluster the particle leaves (possibly split into
// pieces) and the clusters around its new site (merged). Relaxed deformation energies are cached
// by shape up to translations and the particle's point group D3 (rotations by 120 degrees and
// the colour-preserving mirrors; NOT the 60-degree rotations, which swap the yellow and red
// corners). The energy of a shape is always computed from its canonical representative, so it
// is a function of the key alone: results do not depend on the cache (only speed does).
//
// Clusters that wrap around the box are periodic aggregates: the wrap vectors met during the
// breadth-first search span a sublattice; rank 1 is a straight fibre (Periodicity::Fiber along
// the wrap vector), rank 2 a bulk cell (Periodicity::Bulk). Their period vectors relax (the box
// stands for an infinite system). They are keyed without symmetry reduction, box size included.
#pragma once

#include "relax.hpp"
#include "topology.hpp"

#include <cstdint>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

namespace pyfrustrate {

// ------------------------------------------------------------------------------------------
// Geometry of the periodic box and clusters (free functions, montecarlo.cpp)
// ------------------------------------------------------------------------------------------

// The periodic L x L box; site index s = i + L j with 0 <= i, j < L.
struct Box {
    int L = 0;
    std::vector<int> neighbour;  // 6 per site, directions as in topology.cpp

    explicit Box(int L_);
    int n_sites() const { return L * L; }
    int index(int i, int j) const;  // any integers, reduced modulo L
    LatticeVector coords(int s) const { return {s % L, s / L}; }
    int next(int s, int d) const { return neighbour[6 * s + d]; }
};

// Lattice directions of the six neighbours: (1,0), (0,1), (-1,1), (-1,0), (0,-1), (1,-1).
extern const std::array<LatticeVector, 6> kLatticeNeighbours;

// A connected cluster of occupied sites found by breadth-first search on the torus.
struct Cluster {
    std::vector<int> members;              // site indices, in BFS order from the start site
    std::vector<LatticeVector> unwrapped;  // plane coordinates of the members (same order)
    // Lattice of wrap vectors (differences of unwrapped coordinates of the same site), in
    // Hermite normal form: basis (a, b), (0, c) with a, c >= 0 and 0 <= b < c when c > 0.
    int a = 0, b = 0, c = 0;
    int rank() const { return (a != 0) + (c != 0); }
    int size() const { return static_cast<int>(members.size()); }
};

// Scratch space of the searches: visit marks (stamped, never cleared) and unwrapped
// coordinates per site.
struct ClusterWorkspace {
    std::vector<unsigned> mark;
    std::vector<LatticeVector> position;
    unsigned stamp = 0;
    std::vector<int> queue;
    void resize(int n_sites);
    void new_round() { if (++stamp == 0) { std::fill(mark.begin(), mark.end(), 0u); stamp = 1; } }
    bool seen(int s) const { return mark[s] == stamp; }
};

// Cluster of `start` among the sites with occupied[s] >= 0. Marks its members as seen in the
// current round of `ws` (call ws.new_round() to forget earlier searches).
Cluster find_cluster(const Box& box, const std::vector<int>& occupied, int start, ClusterWorkspace& ws);

// The six colour-preserving lattice symmetries about a site (the point group D3 of the
// particle), on lattice coordinates: op 0 identity, 1 and 2 rotations by 120 and 240 degrees,
// 3-5 the mirrors through opposite corners of the hexagon (lines at 90, 30 and 150 degrees;
// op 3 is x -> -x, (i, j) -> (-i-j, j)). Each maps yellow corners to yellow corners.
LatticeVector d3_transform(int op, const LatticeVector& v);

using ShapeKey = std::vector<std::int64_t>;
struct ShapeKeyHash {
    std::size_t operator()(const ShapeKey& key) const;
};

// Canonical key of a finite cluster given by its plane sites: over the six D3 operations,
// transform, translate the lexicographically smallest site to the origin, sort; keep the
// lexicographically smallest list. If `canonical_sites` is given, it receives the sites of
// that representative (sorted), from which the energy of the shape is computed.
ShapeKey finite_shape_key(const std::vector<LatticeVector>& sites,
                          std::vector<LatticeVector>* canonical_sites = nullptr);

// Key of a wrapped cluster: (-rank, L, a, b, c, sorted member site indices). No symmetry
// reduction.
ShapeKey wrapped_shape_key(const Cluster& cluster, int L);

// A cluster as a topology: finite clusters from `sites` (plane coordinates); wrapped ones as a
// straight fibre along (a, b) or (0, c) (rank 1) or as a bulk cell spanned by (a, b), (0, c)
// (rank 2), `sites` being unwrapped coordinates consistent with those periods.
Topology cluster_topology(const std::vector<LatticeVector>& sites, const Cluster& wrap);

// ------------------------------------------------------------------------------------------
// Relaxed deformation energy of one cluster
// ------------------------------------------------------------------------------------------

enum class RelaxMethod { Linear = 0, Lbfgs = 1, Newton = 2 };

struct ClusterRelaxOptions {
    RelaxMethod method = RelaxMethod::Linear;
    MinimizeOptions minimize;  // L-BFGS: absolute gradient tolerance, evaluation cap, step scale
    bool warm_start = true;    // L-BFGS starts from the linear solution (else the bulk reference)
};

struct RelaxCounters {
    std::int64_t minimisations = 0;  // clusters relaxed
    std::int64_t evaluations = 0;    // energy+gradient evaluations (1 per linear solve)
    std::int64_t fallbacks = 0;      // linear solves refused (floppy topology), done by L-BFGS
    std::int64_t unconverged = 0;    // L-BFGS runs stopped short of the tolerance
};

// Minimum deformation energy of `topology` (main text Eq. 7, inner minimisation): the linear
// solve (exact as eps -> 0; a floppy topology falls back to L-BFGS from the bulk reference),
// or L-BFGS started from the linear solution (warm start) or from the bulk reference.
template <class Model>
double relaxed_cluster_energy(const Model& model, const Topology& topology, const ClusterRelaxOptions& options,
                              RelaxCounters& counters) {
    ++counters.minimisations;
    if (options.method == RelaxMethod::Newton) {
        try {
            const MinimizeResult r = relax_newton(model, topology, options.minimize);
            counters.evaluations += r.iterations;
            if (!r.converged) ++counters.unconverged;
            if (r.energy >= 0) return r.energy;
        } catch (const std::runtime_error&) {
            ++counters.fallbacks;  // floppy topology: no factorisation, L-BFGS below
        }
    }
    Vector x0;
    if (options.method == RelaxMethod::Linear || options.warm_start) {
        try {
            MinimizeResult linear = relax_linear(model, topology);
            ++counters.evaluations;
            if (options.method == RelaxMethod::Linear) return linear.energy;
            x0 = std::move(linear.x);
        } catch (const std::runtime_error&) {
            ++counters.fallbacks;
        }
    }
    if (x0.size() == 0) x0 = topology.reference_state();
    const MinimizeResult r = relax_lbfgs(model, topology, x0, options.minimize);
    counters.evaluations += r.iterations;
    if (!r.converged) ++counters.unconverged;
    // Every term is non-negative near the reference: a negative energy means that L-BFGS left
    // the physical basin (k_area < 0), and the Monte Carlo must not go on with it.
    if (!(r.energy >= 0))
        throw std::runtime_error("L-BFGS left the physical minimum of a cluster (energy " + std::to_string(r.energy) +
                                 " < 0); use method='linear' or a smaller tol");
    return r.energy;
}

// ------------------------------------------------------------------------------------------
// The Monte Carlo state
// ------------------------------------------------------------------------------------------

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
    double bond_deformation = 0.0;  // surrogate deformation energy per bond (bulk: e_b / 3)
    // Probability that an attempted move is a cluster translation instead of a particle move: a
    // random particle's (finite) cluster is shifted by a uniformly random lattice vector of the
    // box, and the shift is accepted iff the cluster lands on empty sites without touching any
    // other particle. Shape, bonds and energy are unchanged and the proposal is symmetric, so
    // the Boltzmann distribution is unchanged; aggregates diffuse across the box and meet,
    // where single-particle moves alone leave them to ripen slowly. 0: particle moves only.
    double cluster_moves = 0.0;
    bool cache = true;        // cache relaxed energies by canonical shape
    bool incremental = true;  // false: re-minimise every cluster of the box on every move
                              // (the naive baseline of the benchmark; no cache either)
    std::size_t cache_limit = std::size_t(1) << 24;  // stored key entries (8 bytes each) before the cache is cleared
};

struct MonteCarloCounters {
    std::int64_t attempted = 0, accepted = 0;
    std::int64_t screened = 0;  // rejected by the surrogate, without relaxing anything
    std::int64_t cluster_attempted = 0, cluster_accepted = 0;  // cluster translations (within attempted/accepted)
    std::int64_t cache_hits = 0, cache_misses = 0, cache_clears = 0;
    RelaxCounters relax;
};

// The Monte Carlo state: occupancy, particle list, random generator, counters, cluster table
// and cache. Energies in the units of the particle's springs; g >= 0 is the binding energy per
// bound pair of sides (main text, "Two-dimensional particle model"). Member functions live in
// montecarlo.cpp, instantiated for HexagonModel (another particle model: one more line there).
template <class Model>
class MonteCarlo {
public:
    MonteCarlo(const Model& model, double g, int L, int n, std::uint64_t seed, const MonteCarloOptions& options);

    // Places the particles on `sites` (lattice coordinates, reduced modulo L; particle p at
    // sites[p]); rebuilds the clusters and the energy from scratch.
    void place(const std::vector<LatticeVector>& sites);

    // One attempted move at temperature T >= 0 (Metropolis, or delayed acceptance; at T = 0 a
    // move is accepted iff dE <= 0, resp. dE_s <= 0 and dE <= dE_s), or with probability
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
    void clear_cache() { cache_.clear(); cache_entries_ = 0; }
    // Relaxed deformation energy of a cluster of this box through the cache.
    double cluster_energy(const Cluster& cluster);

private:
    std::uint64_t uniform_index(std::uint64_t n);  // unbiased, in [0, n)
    double uniform01();                            // in [0, 1), 53 bits
    int random_empty_site();
    bool particle_step(double T);
    bool cluster_step();
    double shape_energy(const ShapeKey& key, const Cluster& cluster);  // from the key's representative
    double raw_energy(const Cluster& cluster);                        // from the sites as found
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
    std::unordered_map<ShapeKey, double, ShapeKeyHash> cache_;
    std::size_t cache_entries_ = 0;
    ClusterWorkspace ws_, ws_canonical_;
    std::vector<Cluster> fresh_;         // clusters after the move under test
    std::vector<double> fresh_energy_;
    std::vector<int> old_ids_;
};

}  // namespace pyfrustrate
