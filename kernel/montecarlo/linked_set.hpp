// The linked set of the collective moves (montecarlo/cluster_move.hpp, isometry_move.hpp): grown
// from a seed particle by bond percolation, then carried by a map of the box's sites that keeps
// its internal bonds (a lattice isometry).
//
// Growth: every bond from the set S to an occupied site outside it is followed once with
// probability p = link (p = 1 draws no deviate: S is the seed's whole cluster). The probability
// of growing exactly S is F(S) (1 - p)^b, F depending only on the bonds inside S and b counting
// the bonds from S to the rest (and, S being the percolation cluster of each of its members, not
// on which member seeded it). A map that keeps S's internal bonds keeps F, so a move and its
// reverse (same seed particle, inverse map drawn with the same probability) differ only by
// (1 - p)^(b' - b), b' the bonds from the moved set to the rest: place_linked_set writes that
// factor as the proposal's log Hastings ratio.
#pragma once

#include "box.hpp"
#include "montecarlo/proposal.hpp"

#include <cmath>
#include <vector>

namespace pyfrustrate {

// S grown from site `seed` into `set` (seed first), its members marked in the current round of
// `ws` (sized to the box).
template <class Chain>
void grow_linked_set(Chain& c, ClusterWorkspace& ws, int seed, double link, std::vector<int>& set) {
    const Box& box = c.box();
    ws.new_round();
    set.push_back(seed);
    ws.mark[seed] = ws.stamp;
    for (std::size_t k = 0; k < set.size(); ++k)
        for (int d = 0; d < box.neighbours(); ++d) {
            const int u = box.next(set[k], d);
            if (!c.occupied(u) || ws.seen(u)) continue;
            if (link >= 1 || c.uniform01() < link) {
                ws.mark[u] = ws.stamp;
                set.push_back(u);
            }
        }
}

// The set p.from (grown by grow_linked_set into `ws`) sent to image(s) for each member s: p.to,
// the bond change and the Hastings factor (1 - link)^(b' - b). False if a target is occupied
// outside the set, or if link = 1 and the move would make a bond ((1 - p)^(b' - b) = 0).
// `translation`: the map is a translation, so a whole cluster landing untouched keeps its shape
// (and energy) exactly and is marked rigid.
template <class Chain, class Image>
bool place_linked_set(const Chain& c, const ClusterWorkspace& ws, double link, bool translation, Proposal& p,
                      Image&& image) {
    const Box& box = c.box();
    int outer_before = 0, outer_after = 0;
    for (const int s : p.from) {
        const int t = image(s);
        if (c.occupied(t) && !ws.seen(t)) return false;
        p.to.push_back(t);
    }
    // Bonds from the set to the rest before (b) and after (b') the move; the rest does not move,
    // and a target's neighbour in the set is a bond inside the set after the move too.
    for (std::size_t k = 0; k < p.from.size(); ++k)
        for (int d = 0; d < box.neighbours(); ++d) {
            const int u = box.next(p.from[k], d), v = box.next(p.to[k], d);
            outer_before += c.occupied(u) && !ws.seen(u);
            outer_after += c.occupied(v) && !ws.seen(v);
        }
    p.bond_change = outer_after - outer_before;
    if (link >= 1 && p.bond_change > 0) return false;  // (1 - p)^(b' - b) = 0
    p.log_hastings = p.bond_change == 0 ? 0.0 : p.bond_change * std::log1p(-link);
    p.rigid = translation && outer_before == 0 && outer_after == 0;
    return true;
}

}  // namespace pyfrustrate
