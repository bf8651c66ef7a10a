// Linked cluster moves: with probability options.cluster_moves an attempted move shifts a set S
// of particles grown from a random one by a uniformly random cell vector of the box (a symmetric
// proposal), rejected if it would overlap another particle. S is grown by bond percolation: each
// bond from S to an occupied site outside it is followed with probability p = cluster_link. The
// probability of proposing S is (1/N) F(S) (1 - p)^b, where F depends only on the bonds inside S
// (which the shift keeps) and b counts the bonds from S to the rest; the reverse shift has the
// same F and b' (the bonds after the move), so Metropolis-Hastings accepts with
// min(1, exp(-dE/T) (1 - p)^(b' - b)) (a cluster move with a fixed link probability;
// Whitelam & Geissler's virtual-move Monte Carlo, J. Chem. Phys. 127, 154101 (2007), makes links
// depend on pair energies, which an elastic energy does not split into). With p < 1 aggregates
// meet and merge in one move, and the reverse move splits them. p = 1: S is the whole cluster and
// (1 - p)^(b' - b) forbids any new contact, so the move changes neither shape, bonds nor energy
// and needs no relaxation.
#pragma once

#include "box.hpp"
#include "montecarlo/linked_set.hpp"
#include "montecarlo/options.hpp"
#include "montecarlo/proposal.hpp"

#include <cstdint>

namespace pyfrustrate {

struct ClusterMove {
    static constexpr const char* kName = "cluster";
    struct Counters {
        std::int64_t attempted = 0, accepted = 0;
        std::int64_t rebonded = 0;  // accepted shifts that made or broke bonds (aggregates met or split)
        template <class F>
        void for_each(F&& f) {
            f("attempted", attempted, "cluster translations tried (counted in the chain's attempted too)");
            f("accepted", accepted, "cluster translations accepted (counted in the chain's accepted too)");
            f("rebonded", rebonded, "accepted translations that made or broke bonds (aggregates met or split)");
        }
    };
    static double probability(const MonteCarloOptions& o) { return o.cluster_moves; }

    ClusterWorkspace grown;

    template <class Chain>
    bool propose(Chain& c, Proposal& p, Counters& counters) {
        ++counters.attempted;
        const Box& box = c.box();
        if (static_cast<int>(grown.mark.size()) != box.n_sites()) grown.resize(box.n_sites());
        const int a = c.site_of(static_cast<int>(c.uniform_index(c.n())));
        const int L = box.L;
        const int di = static_cast<int>(c.uniform_index(L)), dj = static_cast<int>(c.uniform_index(L));  // a cell shift
        if (di == 0 && dj == 0) return false;
        // The set S (linked_set.hpp), shifted; targets must be empty or in S.
        const double link = c.options().cluster_link;
        grow_linked_set(c, grown, a, link, p.from);
        const auto shifted = [&](int s) {
            const Site x = box.coords(s);
            return box.index({x[0] + di, x[1] + dj, x[2]});
        };
        if (!place_linked_set(c, grown, link, true, p, shifted)) return false;
        p.carries_displacements = true;
        return true;
    }

    template <class Chain>
    void after_move(Chain&, Proposal&) {}

    void accepted(const Proposal& p, Counters& counters) {
        ++counters.accepted;
        counters.rebonded += !p.rigid;
    }
};

}  // namespace pyfrustrate
