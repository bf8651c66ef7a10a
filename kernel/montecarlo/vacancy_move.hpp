// Vacancy moves: with probability options.vacancy_moves (among the moves that are not cluster,
// isometry or outline moves), a hole inside an aggregate is filled, or one is dug. With
// probability 1/2 a random particle with an empty neighbour (n_s of them) goes to a random hole,
// an empty site whose neighbours are all occupied (n_h); else a random particle whose neighbours
// are all occupied (n_i) goes to a random empty site with both an occupied and an empty neighbour
// (n_p). Each kind is the other's reverse, so Metropolis-Hastings takes the ratio
// n_s n_h / (n_i' n_p') for a fill and n_i n_p / (n_s' n_h') for a dig (counts before over counts
// after), and a fill whose reverse could not be proposed (the particle left from next to the
// hole, or leaves a site with no occupied neighbour) is refused.
// Why: a surface move never fills a hole (the particle would end with no empty neighbour, so its
// reverse could not be proposed), and a bonded move proposes a given jump into one with
// probability ~ 1 / N^2, so a hole left inside an aggregate as it cools stays to the end of a run.
#pragma once

#include "box.hpp"
#include "montecarlo/options.hpp"
#include "montecarlo/proposal.hpp"
#include "montecarlo/surface_move.hpp"  // jump_neighbourhood

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace pyfrustrate {

struct VacancyMove {
    static constexpr const char* kName = "vacancy";
    struct Counters {
        std::int64_t attempted = 0, accepted = 0, filled = 0;
        template <class F>
        void for_each(F&& f) {
            f("attempted", attempted, "vacancy moves tried (within the chain's attempted)");
            f("accepted", accepted, "vacancy moves accepted (within the chain's accepted)");
            f("filled", filled, "accepted vacancy moves that filled a hole (the others dug one)");
        }
    };
    static double probability(const MonteCarloOptions& o) { return o.vacancy_moves; }

    // The four kinds of sites a move can change: particles with an empty neighbour (surface) and
    // without (interior); empty sites with every neighbour occupied (holes) and with some
    // (perimeter).
    enum Kind { kSurface, kInterior, kHole, kPerimeter };
    using Counts = std::array<int, 4>;

    std::vector<int> sites[4], around;
    ClusterWorkspace marks;
    Counts before{};
    bool fill = false;
    int lost = 0;

    // The kind of site s, or -1 (an empty site with no occupied neighbour).
    template <class Chain>
    static int kind_of(const Chain& c, int s) {
        const int k = c.occupied_neighbours(s), d = c.box().neighbours();
        if (c.occupied(s)) return k < d ? kSurface : kInterior;
        return k == d ? kHole : (k > 0 ? kPerimeter : -1);
    }

    template <class Chain>
    static Counts counts(const Chain& c, const std::vector<int>& among) {
        Counts n{};
        for (const int s : among) {
            const int k = kind_of(c, s);
            if (k >= 0) ++n[k];
        }
        return n;
    }

    template <class Chain>
    bool propose(Chain& c, Proposal& p, Counters& counters) {
        ++counters.attempted;
        // The candidates, listed afresh (O(N D), small beside a relaxation), each once.
        const Box& box = c.box();
        if (static_cast<int>(marks.mark.size()) != box.n_sites()) marks.resize(box.n_sites());
        for (auto& list : sites) list.clear();
        marks.new_round();
        for (int k = 0; k < c.n(); ++k) {
            const int s = c.site_of(k);
            sites[kind_of(c, s)].push_back(s);
            for (int d = 0; d < box.neighbours(); ++d) {
                const int u = box.next(s, d);
                if (c.occupied(u) || marks.seen(u)) continue;
                marks.mark[u] = marks.stamp;
                sites[kind_of(c, u)].push_back(u);  // a neighbour of a particle: a hole or perimeter
            }
        }
        fill = c.uniform_index(2) == 0;
        const std::vector<int>& from = sites[fill ? kSurface : kInterior];
        const std::vector<int>& to = sites[fill ? kHole : kPerimeter];
        if (from.empty() || to.empty()) return false;
        const int a = from[c.uniform_index(from.size())];
        const int b = to[c.uniform_index(to.size())];
        // Only a, b and their neighbours can change kind.
        jump_neighbourhood(box, a, b, around);
        before = counts(c, around);
        p.from.push_back(a);
        p.to.push_back(b);
        lost = c.occupied_neighbours(a);
        return true;
    }

    template <class Chain>
    void after_move(Chain& c, Proposal& p) {
        const int a = p.from[0], b = p.to[0];
        p.bond_change = c.occupied_neighbours(b) - lost;
        // The reverse takes the particle on b back to a: b must be of the kind the reverse draws
        // from, and a of the kind it draws into.
        if (kind_of(c, b) != (fill ? kInterior : kSurface) || kind_of(c, a) != (fill ? kPerimeter : kHole)) {
            p.log_hastings = Proposal::kImpossible;
            return;
        }
        const Counts after = counts(c, around);
        const auto total = [&](int k) { return static_cast<double>(sites[k].size()) + after[k] - before[k]; };
        p.log_hastings = fill ? std::log(sites[kSurface].size() * static_cast<double>(sites[kHole].size()) /
                                         (total(kInterior) * total(kPerimeter)))
                              : std::log(sites[kInterior].size() * static_cast<double>(sites[kPerimeter].size()) /
                                         (total(kSurface) * total(kHole)));
    }

    void accepted(const Proposal&, Counters& counters) {
        ++counters.accepted;
        counters.filled += fill;
    }
};

}  // namespace pyfrustrate
