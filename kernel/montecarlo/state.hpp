// The state of a Monte Carlo chain as a value (montecarlo/chain.hpp): passed into `run` and
// returned by it, never set piecewise. With the chain's parameters it determines the rest of the
// chain: the occupancy (the site of each particle), the random generator, the running energy,
// the warm-start store of relaxed displacements and the counters. What the chain derives from it
// (occupant of each site, cluster labels and their energies, the cache) it keeps itself.
#pragma once

#include "cluster_energy.hpp"
#include "montecarlo/moves.hpp"
#include "parent_factor.hpp"

#include <cstdint>
#include <memory>
#include <random>
#include <vector>

namespace pyfrustrate {

// The chain's own counters, each named once; the binding iterates them (and those of each move
// family, montecarlo/*_move.hpp).
struct ChainCounters {
    std::int64_t attempted = 0, accepted = 0;
    std::int64_t screened = 0;  // rejected by the surrogate, without relaxing anything
    std::int64_t bounded = 0;   // rejected at the second stage by a lower bound, without relaxing (chain.hpp)
    CacheCounters cache;
    RelaxCounters relax;

    template <class F>
    void for_each(F&& f) {
        f("attempted", attempted, "moves tried, every family");
        f("accepted", accepted, "moves accepted, every family");
        f("screened", screened, "rejected by the surrogate energy, without relaxing anything");
        f("bounded", bounded, "rejected at the second stage by a lower bound on the relaxed energy, without relaxing");
        f("cache_hits", cache.hits, "cluster energies found in the cache of relaxed shapes");
        f("cache_misses", cache.misses, "cluster energies not in the cache (relaxed)");
        f("cache_clears", cache.clears, "times the full cache was emptied");
        f("minimisations", relax.minimisations, "cluster relaxations");
        f("evaluations", relax.evaluations, "energy and gradient evaluations (1 per linear solve)");
        f("fallbacks", relax.fallbacks, "relaxations the Newton path refused, done by L-BFGS");
        f("unconverged", relax.unconverged, "relaxations that did not meet the gradient tolerance");
        f("factorizations", relax.factorizations, "numeric factorisations of a Hessian");
        f("warm_starts", relax.warm_starts, "Newton relaxations started from the parents' relaxed state");
        f("warm_restarts", relax.warm_restarts, "of those, redone from the linear solution (outside the basin)");
        f("parent_relaxations", relax.parent_factor, "Newton runs on the parent cluster's modified factor (parent_factor.hpp)");
        f("parent_fresh", relax.parent_fresh, "of the relaxations given a parent, those made fresh instead");
        f("parent_chord_steps", relax.parent_chord_steps, "chord steps of the runs on the parent's factor");
        f("parent_refactorizations", relax.parent_refactorizations, "exact Hessians factorised anew along those runs");
    }
};

struct ChainState {
    std::vector<int> particles;  // site index of each particle (box.hpp numbering)
    std::mt19937_64 rng;         // the chain's only random stream
    double deformation = 0.0;    // running sum of the relaxed deformation energies of the clusters
    std::int64_t bonds = 0;      // bound pairs of sides (counted again when a state comes from elsewhere)
    // Warm starts (options.parent_start): each site's relaxed corner displacements (a record of
    // 2 C + 4 doubles per site, lab frame, rigid motion removed, a wrapping cluster's strain kept
    // apart: MonteCarlo::kSiteRecord) and whether they are known; empty otherwise.
    std::vector<double> displacement;
    std::vector<char> known;
    // Parent factors (options.parent_factor): each site's cluster, relaxed and factorised, shared
    // by its members; empty otherwise, and not carried by a state rebuilt from its arrays (the
    // chain then starts without). At most one per cluster of the box: a cluster's members take
    // its children's when a move is accepted, a vacated site drops its own.
    std::vector<std::shared_ptr<RelaxedCluster>> factors;
    ChainCounters counters;
    MoveCounters move_counters;  // each family's own (montecarlo/moves.hpp)
    // Which chain last returned this state, and when: a state handed straight back skips the
    // rebuild of what the chain derives from it (the result is the same either way).
    std::uint64_t chain_id = 0, version = 0;
};

}  // namespace pyfrustrate
