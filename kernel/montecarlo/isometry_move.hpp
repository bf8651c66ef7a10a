// Collective isometry moves: a linked set S grown from a random seed particle by bond percolation
// (linked_set.hpp, link probability options.isometry_link, as the cluster move grows it) is moved
// by a lattice isometry that keeps its internal bonds. Three families, each with its own
// probability (options.shift_moves, rotation_moves, reflection_moves):
//   shift:      S translated by one of the six shortest cell vectors (to a neighbouring site);
//   rotation:   S turned by +60 or -60 degrees about its seed particle's site;
//   reflection: S mirrored about one of the six mirror axes through its seed's site;
//   carry:      S, grown with options.cluster_link instead (a disk, a lobe), translated by one of
//               the kCarryVectors: every cell vector of at most kCarryRadius neighbour steps.
// Where the cluster move jumps sets across the box, these straighten and compact an aggregate
// in place: a kinked branch turned back into line, a side arm folded against the body. A carry
// moves a whole disk or a lobe a few sites, so that two disks that touch at a corner may slide
// into contact along a facet, which the cluster move's jumps across the box seldom land them in
// (it did not make the large box's disks at nu = 0.4 fuse: docs/topics/montecarlo.md, "Why the
// runs at nu = 0.4 end in rafts").
//
// Detailed balance. The forward proposal of S and map G has probability (1/N) F(S) (1 - p)^b
// P(G), the seed drawn among N particles. Its reverse takes the same particle as seed (G keeps a
// rotation's or reflection's seed in place; a shift carries it along), grows G(S) with F(G(S)) =
// F(S) (G keeps the bonds inside S) times (1 - p)^b', and draws G's inverse: -e for a shift e,
// -60 for +60 degrees, the same mirror for a mirror, each drawn with the same probability as G
// (uniform over the six vectors, the carry's vectors, the two senses, the six axes: each set is
// closed under negation). So the proposal is symmetric up
// to (1 - p)^(b' - b), which Metropolis-Hastings takes as in the cluster move. b' counts the
// bonds from the moved set to the particles that stay, not to the set's old sites: a turned or
// mirrored set always overlaps its image at the seed, and counting its old sites as occupied is
// wrong (tests/test_montecarlo_rules.py shows the exact-enumeration statistic rejecting that rule,
// and the factor dropped). An uneven choice of sense (+60 more often than -60) breaks detailed
// balance too, but the enumerable boxes hardly show it: a set's six turns about its seed
// alternate between two energies (the particle keeps its shape under turns by 120 degrees), where
// a biased cycle still keeps the Boltzmann weights, so only collisions with the rest reveal it.
//
// The maps are exact integer operations on three times lattice coordinates (tiling.hpp). On the
// torus they are well defined because each isometry sends the box's periods (L, 0) and (0, L) to
// periods ((L, 0) -> (0, L) and (0, L) -> (-L, L) for +60 degrees), and they move particles
// because they send the tiling to itself: every site centre to a site centre, the particle's
// outline (its corner points) onto the outline of the image site, neighbours to neighbours. Both
// are checked once per box (check_tiling_symmetry); the hexagon tiling passes, the triangle
// tiling fails for rotations and reflections (a 60-degree turn about a triangle's centre does not
// map triangles onto triangles), and such a chain refuses the move with std::invalid_argument.
//
// A rotated or reflected set is in general a new shape (a 60-degree turn exchanges the hexagon's
// red and yellow corners): its clusters are relaxed on the chain's one path, and the moved
// particles carry no relaxed displacements. A shift of a whole cluster that touches nothing is
// rigid (same shape, bonds and energy), as in the cluster move.
#pragma once

#include "box.hpp"
#include "montecarlo/linked_set.hpp"
#include "montecarlo/options.hpp"
#include "montecarlo/proposal.hpp"
#include "tiling.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace pyfrustrate {

enum class IsometryKind { Shift, Rotation, Reflection, Carry };

// The six shortest cell vectors: the hexagon's neighbour directions.
constexpr std::array<LatticeVector, 6> kShortestCellVectors{{{1, 0}, {0, 1}, {-1, 1}, {-1, 0}, {0, -1}, {1, -1}}};

// The carry's displacements: every non-zero cell vector (i, j) of at most kCarryRadius neighbour
// steps (hexagonal distance max(|i|, |j|, |i + j|)), 3 R (R + 1) of them, closed under negation.
constexpr int kCarryRadius = 3;
constexpr std::size_t kCarryCount = 3 * kCarryRadius * (kCarryRadius + 1);
constexpr std::array<LatticeVector, kCarryCount> carry_vectors() {
    std::array<LatticeVector, kCarryCount> out{};
    std::size_t k = 0;
    for (int i = -kCarryRadius; i <= kCarryRadius; ++i)
        for (int j = -kCarryRadius; j <= kCarryRadius; ++j) {
            const int steps = std::max({i < 0 ? -i : i, j < 0 ? -j : j, i + j < 0 ? -(i + j) : i + j});
            if (steps >= 1 && steps <= kCarryRadius) out[k++] = {i, j};
        }
    return out;
}
constexpr std::array<LatticeVector, kCarryCount> kCarryVectors = carry_vectors();
// Point operations (tiling.hpp numbering): rotations by +60 and -60 degrees; the six mirrors.
constexpr std::array<int, 2> kTurns{1, 5};
constexpr std::array<int, 6> kMirrors{6, 7, 8, 9, 10, 11};

// Three times the lattice coordinates of every corner point of site s's particle, sorted.
inline std::vector<LatticeVector> corner_points3(const Tiling& t, const Site& s) {
    std::vector<LatticeVector> points;
    for (int k = 0; k < t.corners; ++k) {
        const CornerSlot& c = t.slot[s[2]][k];
        points.push_back({3 * (s[0] + c.di) + t.corner_offset3[c.color][0], 3 * (s[1] + c.dj) + t.corner_offset3[c.color][1]});
    }
    std::sort(points.begin(), points.end());
    points.erase(std::unique(points.begin(), points.end()), points.end());
    return points;
}

// The point `v3` under point operation `op` about the point `centre3` (three times lattice coordinates).
inline LatticeVector about(int op, const LatticeVector& centre3, const LatticeVector& v3) {
    const LatticeVector w = point_operation(op, {v3[0] - centre3[0], v3[1] - centre3[1]});
    return {centre3[0] + w[0], centre3[1] + w[1]};
}

// Whether point operation `op` about any site of the tiling maps the tiling to itself (site
// centres to site centres, each particle's corner points onto its image's, neighbours to
// neighbours) and the L x L box's periods to periods; the reason if not, empty if so. The map
// being affine, the sites of cell (0, 0) and their neighbours decide it for every cell.
inline std::string tiling_symmetry_failure(const Tiling& t, int L, int op) {
    for (const LatticeVector& period : {LatticeVector{L, 0}, LatticeVector{0, L}}) {
        const LatticeVector w = point_operation(op, period);
        if (w[0] % L != 0 || w[1] % L != 0) return "it does not map the periodic box to itself";
    }
    const auto image = [&](const LatticeVector& centre3, const Site& s, Site& out) {
        try {
            out = site_at(t, about(op, centre3, site_centre3(t, s)));
            return true;
        } catch (const std::invalid_argument&) {
            return false;
        }
    };
    for (int seed = 0; seed < t.sublattices; ++seed) {
        const LatticeVector centre3 = site_centre3(t, {0, 0, seed});
        for (int q = 0; q < t.sublattices; ++q) {
            const Site s{0, 0, q};
            Site gs;
            if (!image(centre3, s, gs)) return "it does not map site centres onto site centres";
            std::vector<LatticeVector> turned;
            for (const LatticeVector& x : corner_points3(t, s)) turned.push_back(about(op, centre3, x));
            std::sort(turned.begin(), turned.end());
            if (turned != corner_points3(t, gs)) return "it does not map a particle's outline onto a site's";
            for (int d = 0; d < t.neighbours; ++d) {
                Site gn;
                if (!image(centre3, neighbour_of(t, s, d), gn)) return "it does not map site centres onto site centres";
                bool adjacent = false;
                for (int e = 0; e < t.neighbours; ++e) adjacent = adjacent || neighbour_of(t, gs, e) == gn;
                if (!adjacent) return "it does not map neighbours to neighbours";
            }
        }
    }
    return "";
}

template <IsometryKind Kind>
struct IsometryMove {
    static constexpr const char* kName = Kind == IsometryKind::Shift      ? "shift"
                                         : Kind == IsometryKind::Rotation ? "rotation"
                                         : Kind == IsometryKind::Carry    ? "carry"
                                                                          : "reflection";
    // A translation: the set keeps its shape, and a whole cluster landing untouched its energy.
    static constexpr bool kTranslation = Kind == IsometryKind::Shift || Kind == IsometryKind::Carry;
    struct Counters {
        std::int64_t attempted = 0, accepted = 0;
        std::int64_t rebonded = 0;  // accepted moves that changed the number of bonds
        template <class F>
        void for_each(F&& f) {
            f("attempted", attempted, "isometries of a linked set tried");
            f("accepted", accepted, "isometries accepted");
            f("rebonded", rebonded, "accepted isometries that changed the number of bonds");
        }
    };
    static double probability(const MonteCarloOptions& o) {
        return Kind == IsometryKind::Shift      ? o.shift_moves
               : Kind == IsometryKind::Rotation ? o.rotation_moves
               : Kind == IsometryKind::Carry    ? o.carry_moves
                                                : o.reflection_moves;
    }
    // The carry moves disks and lobes, grown as the cluster move grows its sets; the others move
    // local pieces (options.hpp: isometry_link).
    static double link(const MonteCarloOptions& o) { return Kind == IsometryKind::Carry ? o.cluster_link : o.isometry_link; }

    ClusterWorkspace grown;
    int checked_box = 0;  // the box size whose symmetry was checked (0: none yet)

    // The point operations this family draws from (none for translations).
    static std::vector<int> operations() {
        if (Kind == IsometryKind::Rotation) return {kTurns.begin(), kTurns.end()};
        if (Kind == IsometryKind::Reflection) return {kMirrors.begin(), kMirrors.end()};
        return {};
    }

    void check_symmetry(const Box& box) {
        if (checked_box == box.L) return;
        for (const int op : operations()) {
            const std::string failure = tiling_symmetry_failure(*box.tiling, box.L, op);
            if (!failure.empty())
                throw std::invalid_argument(std::string(kName) + "_moves need a tiling that a " +
                                            (Kind == IsometryKind::Rotation ? "60-degree rotation" : "mirror") +
                                            " about a site maps to itself; on the " + box.tiling->name + " tiling " +
                                            failure + " (set " + kName + "_moves=0)");
        }
        checked_box = box.L;
    }

    template <class Chain>
    bool propose(Chain& c, Proposal& p, Counters& counters) {
        ++counters.attempted;
        const Box& box = c.box();
        check_symmetry(box);
        if (static_cast<int>(grown.mark.size()) != box.n_sites()) grown.resize(box.n_sites());
        const int seed = c.site_of(static_cast<int>(c.uniform_index(c.n())));
        const Tiling& t = *box.tiling;
        const LatticeVector centre3 = site_centre3(t, box.coords(seed));
        LatticeVector step{0, 0};
        int op = 0;
        if (Kind == IsometryKind::Shift) step = kShortestCellVectors[c.uniform_index(kShortestCellVectors.size())];
        if (Kind == IsometryKind::Carry) step = kCarryVectors[c.uniform_index(kCarryVectors.size())];
        if (Kind == IsometryKind::Rotation) op = kTurns[c.uniform_index(kTurns.size())];
        if (Kind == IsometryKind::Reflection) op = kMirrors[c.uniform_index(kMirrors.size())];
        const double link = IsometryMove::link(c.options());
        grow_linked_set(c, grown, seed, link, p.from);
        const auto image = [&](int s) {
            const Site x = box.coords(s);
            if (kTranslation) return box.index({x[0] + step[0], x[1] + step[1], x[2]});
            return box.index(site_at(t, about(op, centre3, site_centre3(t, x))));
        };
        if (!place_linked_set(c, grown, link, kTranslation, p, image)) return false;
        // A set the map sends onto itself (a symmetric set turned or mirrored, a fibre shifted
        // along itself) leaves the occupancy as it was: nothing to relax, the chain stays.
        if (std::all_of(p.to.begin(), p.to.end(), [&](int s) { return grown.seen(s); })) return false;
        p.carries_displacements = kTranslation;
        return true;
    }

    template <class Chain>
    void after_move(Chain&, Proposal&) {}

    void accepted(const Proposal& p, Counters& counters) {
        ++counters.accepted;
        counters.rebonded += p.bond_change != 0;
    }
};

using ShiftMove = IsometryMove<IsometryKind::Shift>;
using RotationMove = IsometryMove<IsometryKind::Rotation>;
using ReflectionMove = IsometryMove<IsometryKind::Reflection>;
using CarryMove = IsometryMove<IsometryKind::Carry>;

}  // namespace pyfrustrate
