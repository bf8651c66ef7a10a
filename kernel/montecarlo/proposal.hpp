// What a move family proposes to the chain (montecarlo/chain.hpp), and the contract of a family.
//
// A family is a small type with
//   static constexpr const char* kName;                 // its counters' prefix ("" for none)
//   struct Counters { template <class F> void for_each(F&& f); };  // its own counters, named and
//                                                        // described once: f(name, value, meaning)
//   static double probability(const MonteCarloOptions&); // chance of being tried (the last family
//                                                        // of MoveFamilies takes the rest)
//   template <class Chain> bool propose(Chain&, Proposal&, Counters&);   // draws; false: no move
//   template <class Chain> void after_move(Chain&, Proposal&);           // on the moved occupancy
//   void accepted(const Proposal&, Counters&);
// The chain makes the move on the occupancy between `propose` and `after_move`, screens it,
// relaxes the clusters it changed, and accepts it or undoes it: one path for every family.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

namespace pyfrustrate {

struct Proposal {
    // The particle on from[k] goes to to[k] (sites, box.hpp numbering; a target is empty or
    // among the sites left).
    std::vector<int> from, to;
    int bond_change = 0;       // bonds after minus bonds before
    double log_hastings = 0;   // log of the reverse over the forward proposal probability; -inf: no reverse move
    bool carries_displacements = false;  // a rigid shift: the moved particles keep their relaxed displacements
    bool rigid = false;        // shape, bonds and energy unchanged (a whole cluster landing untouched): accepted as is
    // Grand-canonical moves (outline_move.hpp): a particle appears on `inserted`, or the one on
    // `removed` leaves the box (-1: none).
    int inserted = -1, removed = -1;

    void clear() {
        from.clear(), to.clear();
        bond_change = 0, log_hastings = 0, carries_displacements = false, rigid = false;
        inserted = removed = -1;
    }
    // Particles after the move minus before.
    int particle_change() const { return (inserted >= 0) - (removed >= 0); }
    static constexpr double kImpossible = -std::numeric_limits<double>::infinity();
};

// Families without counters of their own.
struct NoCounters {
    template <class F>
    void for_each(F&&) {}
};

}  // namespace pyfrustrate
