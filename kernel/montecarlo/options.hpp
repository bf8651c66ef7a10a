// The options of a Monte Carlo chain (montecarlo/chain.hpp), checked once in Python
// (pyfrustrate.montecarlo.options) and by the binding's constructor for direct kernel use.
#pragma once

#include "cluster_energy.hpp"

#include <cmath>
#include <cstddef>

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
    // The move families' probabilities and parameters, each explained in its header
    // (montecarlo/cluster_move.hpp, particle_move.hpp, surface_move.hpp). 0: the family is off
    // (no deviate drawn).
    double cluster_moves = 0.0;
    double cluster_link = 1.0;
    double bonded_moves = 0.0;
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
    // parent_start only: a cluster a move changes by at most kMaxChangedParticles particles
    // relaxes by chord steps on its parent cluster's factor, modified (parent_factor.hpp), instead
    // of factorising its own Hessian; each relaxed cluster of at least parent_factor_min_particles
    // particles keeps its factor for its children (one per cluster of the box, dropped with it).
    // false: the warm start alone (the baseline of benchmarks/bench_mc_goals.py).
    bool parent_factor = false;
    int parent_factor_min_particles = 0;
};

// parent_start: a moved particle whose known corners lie farther than this many step_scale
// (the mismatch) from the rigid fit makes the start cold. Measured in the dense box (300 in
// 30 x 30, ell = 5, nu = 0.4, 200 sweeps), factorisations per minimisation: 4.98 at 0.3, 5.00
// at 1, 4.82 at 3, 5.42 without a limit, 6.23 with cold starts only.
constexpr double kWarmMisfit = 3.0;

}  // namespace pyfrustrate
