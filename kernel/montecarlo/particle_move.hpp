// Particle moves, with bonded targets: a random particle to a random empty site or, with
// probability options.bonded_moves, to a random neighbour site of a random other particle
// (aggregation-volume-bias moves, Chen & Siepmann, J. Phys. Chem. B 104, 8725 (2000)), refused
// if occupied. With w that probability, E empty sites, D neighbours per site and c the occupied
// neighbours of the target (the mover excluded), the proposal probability of a move is
// ((1 - w) / E + w c_target / (D (N - 1))) / N, the reverse one the same with c of the site
// left; Metropolis-Hastings takes their ratio. w < 1, or a particle could never leave an
// aggregate (the chain would not be ergodic). The default family: tried when no other is.
#pragma once

#include "montecarlo/options.hpp"
#include "montecarlo/proposal.hpp"

#include <cmath>

namespace pyfrustrate {

struct ParticleMove {
    static constexpr const char* kName = "";
    using Counters = NoCounters;
    static double probability(const MonteCarloOptions&) { return 1.0; }

    // Bonds of a particle at `from` before the move: its occupied neighbours (the target is empty).
    int lost = 0;

    template <class Chain>
    bool propose(Chain& c, Proposal& p, Counters&) {
        const int mover = static_cast<int>(c.uniform_index(c.n()));
        const int N = c.n();
        // No deviate is drawn without bonded moves.
        int b;
        if (c.options().bonded_moves > 0 && c.uniform01() < c.options().bonded_moves) {
            if (N < 2) return false;
            const int q = static_cast<int>(c.uniform_index(N - 1));
            b = c.box().next(c.site_of(q >= mover ? q + 1 : q), static_cast<int>(c.uniform_index(c.box().neighbours())));
            if (c.occupied(b)) return false;
        } else {
            b = c.random_empty_site();
        }
        p.from.push_back(c.site_of(mover));
        p.to.push_back(b);
        lost = c.occupied_neighbours(p.from[0]);
        return true;
    }

    // Bonds gained at the target, and the ratio of reverse to forward proposal probabilities.
    template <class Chain>
    void after_move(Chain& c, Proposal& p) {
        const int gained = c.occupied_neighbours(p.to[0]);
        p.bond_change = gained - lost;
        const int N = c.n();
        const double w = c.options().bonded_moves;
        if (w <= 0 || N < 2) return;
        const double uniform = (1 - w) / (c.box().n_sites() - N),
                     bonded = w / (static_cast<double>(c.box().neighbours()) * (N - 1));
        p.log_hastings = std::log((uniform + bonded * lost) / (uniform + bonded * gained));  // > 0: w < 1
    }

    void accepted(const Proposal&, Counters&) {}
};

}  // namespace pyfrustrate
