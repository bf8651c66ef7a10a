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
        f("attempted", attempted), f("accepted", accepted), f("screened", screened), f("bounded", bounded);
        f("cache_hits", cache.hits), f("cache_misses", cache.misses), f("cache_clears", cache.clears);
        f("minimisations", relax.minimisations), f("evaluations", relax.evaluations), f("fallbacks", relax.fallbacks);
        f("unconverged", relax.unconverged), f("factorizations", relax.factorizations);
        f("warm_starts", relax.warm_starts), f("warm_restarts", relax.warm_restarts);
        f("parent_relaxations", relax.parent_factor), f("parent_fresh", relax.parent_fresh);
        f("parent_chord_steps", relax.parent_chord_steps), f("parent_refactorizations", relax.parent_refactorizations);
    }
};

struct ChainState {
    std::vector<int> particles;  // site index of each particle (box.hpp numbering)
    std::mt19937_64 rng;         // the chain's only random stream
    double deformation = 0.0;    // running sum of the relaxed deformation energies of the clusters
    std::int64_t bonds = 0;      // bound pairs of sides (counted again when a state comes from elsewhere)
    // Warm starts (options.parent_start): each site's relaxed corner displacements (2 C doubles
    // per site, lab frame, rigid motion removed) and whether they are known; empty otherwise.
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
