// Outline moves: grand-canonical sampling of one connected aggregate. With probability
// options.outline_moves an attempted move exchanges a particle between the aggregate and a
// reservoir at chemical potential mu = options.chemical_potential (energy units, as g): with
// probability 1/2 an insertion on a uniformly chosen empty site next to the aggregate (e(C) of
// them), else a deletion of a uniformly chosen removable particle (d(C): those whose removal
// leaves the aggregate connected and non-empty, i.e. the non-articulation particles of at least
// two). The inserted particle is always removable in C' (removing it gives back C), and a deleted
// particle's site is an empty outline site of C' (it touched C', connected), so every move has its
// reverse, and Metropolis-Hastings accepts an insertion C -> C' with
//     min(1, e(C) / d(C') exp(-(dE - mu) / T)),
// a deletion with min(1, d(C) / e(C') exp(-(dE + mu) / T)): the ratio of the reverse proposal
// probability 1 / (2 d(C')) to the forward one 1 / (2 e(C)), and the Boltzmann factor of the
// grand potential E - mu n (the chain adds -mu dn to the energy change, montecarlo/chain.hpp).
// The chain then samples exp(-(E - mu n) / T) over the connected aggregates of the box; every
// other family's move that would leave the box disconnected is refused (a restriction of the state
// space, which keeps detailed balance: the refused states are never entered and never left).
// A box one particle short of full takes no insertion (a move needs an empty site).
#pragma once

#include "box.hpp"
#include "montecarlo/options.hpp"
#include "montecarlo/proposal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace pyfrustrate {

// The occupied sites of the chain's box as a graph (edges between neighbour sites): whether they
// form one connected aggregate, and which of them can leave it without disconnecting it.
class AggregateGraph {
public:
    // True iff the chain's particles form one cluster (a box with none counts as disconnected).
    template <class Chain>
    bool connected(const Chain& c) {
        if (c.n() < 1) return false;
        if (static_cast<int>(ws_.mark.size()) != c.box().n_sites()) ws_.resize(c.box().n_sites());
        ws_.new_round();
        return find_cluster(c.box(), c.occupancy(), c.site_of(0), ws_).size() == c.n();
    }

    // The sites of the particles whose removal leaves the aggregate connected and non-empty: for
    // a connected aggregate of at least two, those that are not articulation points (Hopcroft &
    // Tarjan's depth-first search, iterative); none for a single particle.
    template <class Chain>
    const std::vector<int>& removable(const Chain& c) {
        removable_.clear();
        const int N = c.n();
        if (N < 2) return removable_;
        const Box& box = c.box();
        const int D = box.neighbours();
        if (static_cast<int>(order_.size()) != box.n_sites()) order_.assign(box.n_sites(), -1), low_.assign(box.n_sites(), 0);
        for (int k = 0; k < N; ++k) order_[c.site_of(k)] = -1;
        cut_.assign(N, 0);  // by particle
        stack_.clear();
        int time = 0;
        const int root = c.site_of(0);
        order_[root] = low_[root] = time++;
        stack_.push_back({root, -1, 0});
        int root_children = 0;
        while (!stack_.empty()) {
            Frame& f = stack_.back();
            if (f.direction < D) {
                const int u = box.next(f.site, f.direction++);
                if (!c.occupied(u) || u == f.site || u == f.parent) continue;  // parallel edges to the parent change no cut
                if (order_[u] >= 0) {
                    low_[f.site] = std::min(low_[f.site], order_[u]);
                    continue;
                }
                order_[u] = low_[u] = time++;
                if (f.site == root) ++root_children;
                stack_.push_back({u, f.site, 0});
                continue;
            }
            const int s = f.site, parent = f.parent;
            stack_.pop_back();
            if (parent < 0) continue;
            low_[parent] = std::min(low_[parent], low_[s]);
            if (parent != root && low_[s] >= order_[parent]) cut_[c.occupancy()[parent]] = 1;
        }
        if (root_children > 1) cut_[0] = 1;
        for (int k = 0; k < N; ++k)
            if (!cut_[k]) removable_.push_back(c.site_of(k));
        return removable_;
    }

    // Empty sites with an occupied neighbour, each once.
    template <class Chain>
    const std::vector<int>& outline(const Chain& c) {
        const Box& box = c.box();
        if (static_cast<int>(ws_.mark.size()) != box.n_sites()) ws_.resize(box.n_sites());
        outline_.clear();
        ws_.new_round();
        for (int k = 0; k < c.n(); ++k)
            for (int d = 0; d < box.neighbours(); ++d) {
                const int u = box.next(c.site_of(k), d);
                if (c.occupied(u) || ws_.seen(u)) continue;
                ws_.mark[u] = ws_.stamp;
                outline_.push_back(u);
            }
        return outline_;
    }

private:
    struct Frame {
        int site, parent, direction;
    };
    ClusterWorkspace ws_;
    std::vector<int> order_, low_, removable_, outline_;
    std::vector<char> cut_;
    std::vector<Frame> stack_;
};

struct OutlineMove {
    static constexpr const char* kName = "outline";
    struct Counters {
        std::int64_t attempted = 0, accepted = 0;
        std::int64_t inserted = 0, removed = 0;  // accepted insertions and deletions
        template <class F>
        void for_each(F&& f) {
            f("attempted", attempted, "grand-canonical insertions and deletions tried");
            f("accepted", accepted, "grand-canonical moves accepted");
            f("inserted", inserted, "accepted insertions at the aggregate's outline");
            f("removed", removed, "accepted deletions at the aggregate's outline");
        }
    };
    static double probability(const MonteCarloOptions& o) { return o.outline_moves; }

    AggregateGraph graph;
    double forward_choices = 0;  // e(C) for an insertion, d(C) for a deletion

    template <class Chain>
    bool propose(Chain& c, Proposal& p, Counters& counters) {
        ++counters.attempted;
        if (c.uniform01() < 0.5) {
            if (c.n() + 1 >= c.box().n_sites()) return false;  // a full box: no move left
            const std::vector<int>& outline = graph.outline(c);
            if (outline.empty()) return false;
            forward_choices = static_cast<double>(outline.size());
            p.inserted = outline[c.uniform_index(outline.size())];
            return true;
        }
        const std::vector<int>& removable = graph.removable(c);
        if (removable.empty()) return false;  // a single particle stays
        forward_choices = static_cast<double>(removable.size());
        p.removed = removable[c.uniform_index(removable.size())];
        p.bond_change = -c.occupied_neighbours(p.removed);
        return true;
    }

    // On the moved occupancy: the bonds gained by an insertion, and the reverse move's choices.
    template <class Chain>
    void after_move(Chain& c, Proposal& p) {
        double reverse_choices;
        if (p.inserted >= 0) {
            p.bond_change = c.occupied_neighbours(p.inserted);
            reverse_choices = static_cast<double>(graph.removable(c).size());
        } else {
            reverse_choices = static_cast<double>(graph.outline(c).size());
        }
        p.log_hastings = std::log(forward_choices / reverse_choices);
    }

    void accepted(const Proposal& p, Counters& counters) {
        ++counters.accepted;
        counters.inserted += p.inserted >= 0;
        counters.removed += p.removed >= 0;
    }
};

}  // namespace pyfrustrate
