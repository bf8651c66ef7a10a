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
#include "montecarlo/options.hpp"
#include "montecarlo/proposal.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

namespace pyfrustrate {

struct ClusterMove {
    static constexpr const char* kName = "cluster";
    struct Counters {
        std::int64_t attempted = 0, accepted = 0;
        std::int64_t rebonded = 0;  // accepted shifts that made or broke bonds (aggregates met or split)
        template <class F>
        void for_each(F&& f) {
            f("attempted", attempted), f("accepted", accepted), f("rebonded", rebonded);
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
        // The set S, by bond percolation from a: every bond from S to an occupied site outside it
        // is tested once (p = 1 draws no deviate: S is a's whole cluster).
        const double link = c.options().cluster_link;
        grown.new_round();
        std::vector<int>& set = p.from;
        set.push_back(a);
        grown.mark[a] = grown.stamp;
        for (std::size_t k = 0; k < set.size(); ++k)
            for (int d = 0; d < box.neighbours(); ++d) {
                const int u = box.next(set[k], d);
                if (!c.occupied(u) || grown.seen(u)) continue;
                if (link >= 1 || c.uniform01() < link) {
                    grown.mark[u] = grown.stamp;
                    set.push_back(u);
                }
            }
        // Bonds from S to the rest before (b) and after (b') the shift; targets must be empty or in S.
        int outer_before = 0, outer_after = 0;
        for (const int s : set) {
            const Site x = box.coords(s);
            const int t = box.index({x[0] + di, x[1] + dj, x[2]});
            if (c.occupied(t) && !grown.seen(t)) return false;
            p.to.push_back(t);
            for (int d = 0; d < box.neighbours(); ++d) {
                const int u = box.next(s, d), v = box.next(t, d);
                outer_before += c.occupied(u) && !grown.seen(u);
                outer_after += c.occupied(v) && !grown.seen(v);  // the rest does not move
            }
        }
        p.bond_change = outer_after - outer_before;
        if (link >= 1 && p.bond_change > 0) return false;  // (1 - p)^(b' - b) = 0
        p.log_hastings = p.bond_change == 0 ? 0.0 : p.bond_change * std::log1p(-link);
        p.carries_displacements = true;
        // S is a whole cluster and touches nothing where it lands: same shape, bonds and energy.
        p.rigid = outer_before == 0 && outer_after == 0;
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
