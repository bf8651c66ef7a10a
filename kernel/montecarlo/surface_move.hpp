// Surface moves: with probability options.surface_moves (among moves other than cluster moves),
// a random particle among those with an empty neighbour (n_s of them) goes to a random empty
// site among those with an occupied neighbour (n_p). The reverse move exists iff the site left
// keeps an occupied neighbour and the site reached has an empty one; Metropolis-Hastings then
// takes the ratio n_s n_p / (n_s' n_p') of the counts before and after (a move kernel of its
// own, mixed with the others at a fixed probability, so each keeps detailed balance alone).
// Where bonded moves propose a given kink-to-kink jump of a 200-particle aggregate with
// probability ~ w c / (D N^2), this proposes it with ~ 1 / (n_s n_p): the bond-neutral
// rearrangements that take an aggregate's outline to the one with the most bonds are tried some
// 50 times as often. Below 1, or a gas particle could never leave its spot.
#pragma once

#include "box.hpp"
#include "montecarlo/options.hpp"
#include "montecarlo/proposal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace pyfrustrate {

// The sites whose neighbour counts a jump of one particle from a to b can change: a, b and their
// neighbours, each once (surface and vacancy moves count their candidates over these before and
// after the move instead of over the box).
inline void jump_neighbourhood(const Box& box, int a, int b, std::vector<int>& around) {
    around.assign({a, b});
    for (const int s : {a, b})
        for (int d = 0; d < box.neighbours(); ++d) around.push_back(box.next(s, d));
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
}

struct SurfaceMove {
    static constexpr const char* kName = "surface";
    struct Counters {
        std::int64_t attempted = 0, accepted = 0;
        template <class F>
        void for_each(F&& f) {
            f("attempted", attempted, "surface moves tried (within the chain's attempted)");
            f("accepted", accepted, "surface moves accepted (within the chain's accepted)");
        }
    };
    static double probability(const MonteCarloOptions& o) { return o.surface_moves; }

    std::vector<int> surface, perimeter, around;  // candidates, and the sites whose status a move can change
    ClusterWorkspace marks;
    std::pair<int, int> before{0, 0};
    int lost = 0;

    // Particles with an empty neighbour and empty sites with an occupied neighbour, among `sites`.
    template <class Chain>
    static std::pair<int, int> exposed_counts(const Chain& c, const std::vector<int>& sites) {
        int exposed = 0, next_to = 0;
        for (const int s : sites) {
            const int k = c.occupied_neighbours(s);
            if (c.occupied(s)) exposed += k < c.box().neighbours();
            else next_to += k > 0;
        }
        return {exposed, next_to};
    }

    template <class Chain>
    bool propose(Chain& c, Proposal& p, Counters& counters) {
        ++counters.attempted;
        // The candidates, listed afresh (O(N D), small beside a relaxation), each once.
        const Box& box = c.box();
        if (static_cast<int>(marks.mark.size()) != box.n_sites()) marks.resize(box.n_sites());
        surface.clear(), perimeter.clear();
        marks.new_round();
        for (int k = 0; k < c.n(); ++k) {
            const int s = c.site_of(k);
            bool is_exposed = false;
            for (int d = 0; d < box.neighbours(); ++d) {
                const int u = box.next(s, d);
                if (c.occupied(u)) continue;
                is_exposed = true;
                if (!marks.seen(u)) {
                    marks.mark[u] = marks.stamp;
                    perimeter.push_back(u);
                }
            }
            if (is_exposed) surface.push_back(s);
        }
        if (surface.empty() || perimeter.empty()) return false;  // a full box
        const int a = surface[c.uniform_index(surface.size())];
        const int b = perimeter[c.uniform_index(perimeter.size())];
        // Only a, b and their neighbours can change status: the counts after the move are those
        // before plus the change over these sites.
        jump_neighbourhood(box, a, b, around);
        before = exposed_counts(c, around);
        p.from.push_back(a);
        p.to.push_back(b);
        lost = c.occupied_neighbours(a);
        return true;
    }

    template <class Chain>
    void after_move(Chain& c, Proposal& p) {
        const int a = p.from[0], b = p.to[0];
        p.bond_change = c.occupied_neighbours(b) - lost;
        if (c.occupied_neighbours(a) == 0 || c.occupied_neighbours(b) == c.box().neighbours()) {
            p.log_hastings = Proposal::kImpossible;  // no reverse proposal
            return;
        }
        const std::pair<int, int> after = exposed_counts(c, around);
        const double n_surface = static_cast<double>(surface.size()), n_perimeter = static_cast<double>(perimeter.size());
        const double surface_after = n_surface + after.first - before.first,
                     perimeter_after = n_perimeter + after.second - before.second;
        p.log_hastings = std::log(n_surface * n_perimeter / (surface_after * perimeter_after));
    }

    void accepted(const Proposal&, Counters& counters) { ++counters.accepted; }
};

}  // namespace pyfrustrate
