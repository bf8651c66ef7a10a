// Tilings: the lattice of sites particles occupy, the corners neighbours share, and the
// symmetries of the lattice. Topology, network, the Monte Carlo box and the shape keys read
// everything lattice-specific from here; a new lattice is one more instance below.
//
// Every tiling lives on the triangular Bravais lattice a1 = (1, 0), a2 = (1/2, sqrt(3)/2): a site
// is (i, j, sublattice), its cell (i, j) at i a1 + j a2. Points are handled as three times their
// lattice coordinates (integers for every site centre and corner of both tilings), so periodic
// reduction and symmetry operations are exact integer arithmetic.
//
// Hexagon tiling (main text, Fig. 2b): one site per cell, a hexagon centred on i a1 + j a2.
//   Corners alternate red (slots 0, 2, 4 at 30, 150, 270 degrees) and yellow (1, 3, 5); the
//   yellow corners form the lattice Y(i, j) = (i - 1/3, j + 2/3), the red ones R(i, j) =
//   (i + 1/3, j - 2/3) (lattice coordinates). Six edge neighbours; bound neighbours share the two
//   corners of their common side.
// Triangle tiling (supplement, Fig. S6): two sites per cell, the up triangle (i, j), (i+1, j),
//   (i, j+1) and the down triangle (i+1, j+1), (i, j+1), (i+1, j). Every vertex carries a yellow
//   and a red node, both at the vertex in the reference state; slots 0-2 are the yellow nodes of
//   the particle's vertices v0, v1, v2, slots 3-5 the red ones. The down triangle lists its
//   vertices so that it is the up one turned by 180 degrees slot by slot: that is its frame.
//   Three edge neighbours (the sites form a honeycomb graph); bound neighbours share the yellow
//   and red nodes of their common edge's two vertices.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <string>
#include <vector>

namespace pyfrustrate {

using Vec2 = Eigen::Vector2d;
using LatticeVector = std::array<int, 2>;
using Site = std::array<int, 3>;  // cell (i, j) and sublattice

enum class TilingKind { Hexagon = 0, Triangle = 1 };

constexpr int kMaxCorners = 6;
constexpr int kMaxNeighbours = 6;
constexpr int kMaxSublattices = 2;
constexpr int kPointGroupOrder = 12;  // D6 about the origin: the lattice's point group
constexpr double kSqrt3 = 1.7320508075688772;  // correctly rounded, as std::sqrt(3.0)

struct CornerSlot {
    int color;   // which corner lattice (node colour): 0 red, 1 yellow
    int di, dj;  // the corner's cell relative to the site's cell
};

struct NeighbourSlot {
    int di, dj, sublattice;  // the neighbour's cell relative to the site's, and its sublattice
};

struct Tiling {
    TilingKind kind;
    const char* name;
    int sublattices;
    int corners;     // per particle
    int neighbours;  // edge neighbours per site: the coordination number
    // Three times the lattice coordinates of each sublattice's site centre, and of each
    // corner lattice's point in cell (0, 0).
    std::array<LatticeVector, kMaxSublattices> site_offset3;
    std::array<LatticeVector, 2> corner_offset3;
    std::array<std::array<CornerSlot, kMaxCorners>, kMaxSublattices> slot;
    std::array<std::array<NeighbourSlot, kMaxNeighbours>, kMaxSublattices> neighbour;
    // Orientation of each sublattice's particles: cos and sin of the angle by which the
    // particle's own frame (the model's rest shape) is turned.
    std::array<std::array<double, 2>, kMaxSublattices> frame;

    // Bonds per particle of the infinite bulk: each particle binds all its edge neighbours.
    double bulk_bonds_per_particle() const { return 0.5 * neighbours; }
};

constexpr Tiling kHexagonTiling{
    TilingKind::Hexagon,
    "hexagon",
    1,
    6,
    6,
    {{{0, 0}, {0, 0}}},
    {{{1, -2}, {-1, 2}}},
    {{{{{0, 0, 1}, {1, 0, 0}, {0, -1, 1}, {1, 0, -1}, {0, 0, 0}, {1, 1, -1}}}, {}}},
    {{{{{1, 0, 0}, {0, 1, 0}, {-1, 1, 0}, {-1, 0, 0}, {0, -1, 0}, {1, -1, 0}}}, {}}},
    {{{1.0, 0.0}, {1.0, 0.0}}},
};

constexpr Tiling kTriangleTiling{
    TilingKind::Triangle,
    "triangle",
    2,
    6,
    3,
    {{{1, 1}, {2, 2}}},
    {{{0, 0}, {0, 0}}},
    {{{{{1, 0, 0}, {1, 1, 0}, {1, 0, 1}, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}}},
      {{{1, 1, 1}, {1, 0, 1}, {1, 1, 0}, {0, 1, 1}, {0, 0, 1}, {0, 1, 0}}}}},
    {{{{{0, 0, 1}, {-1, 0, 1}, {0, -1, 1}, {}, {}, {}}}, {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {}, {}, {}}}}},
    {{{1.0, 0.0}, {-1.0, 0.0}}},
};

constexpr const Tiling& tiling_of(TilingKind kind) {
    return kind == TilingKind::Hexagon ? kHexagonTiling : kTriangleTiling;
}

// The tiling named `name` ("hexagon" or "triangle"); std::invalid_argument otherwise.
const Tiling& tiling_named(const std::string& name);

// Cartesian point of three times lattice coordinates v3.
inline Vec2 cartesian3(const LatticeVector& v3) {
    return {(v3[0] + 0.5 * v3[1]) / 3.0, 0.5 * kSqrt3 * v3[1] / 3.0};
}
// Cartesian point of cell (i, j).
inline Vec2 cell_position(const LatticeVector& cell) { return {cell[0] + 0.5 * cell[1], 0.5 * kSqrt3 * cell[1]}; }

// Three times the lattice coordinates of a site's centre.
inline LatticeVector site_centre3(const Tiling& t, const Site& s) {
    return {3 * s[0] + t.site_offset3[s[2]][0], 3 * s[1] + t.site_offset3[s[2]][1]};
}
inline Vec2 site_position(const Tiling& t, const Site& s) { return cartesian3(site_centre3(t, s)); }

// The site whose centre is at v3 (three times lattice coordinates); std::invalid_argument if none.
Site site_at(const Tiling& t, const LatticeVector& v3);

inline Site neighbour_of(const Tiling& t, const Site& s, int d) {
    const NeighbourSlot& n = t.neighbour[s[2]][d];
    return {s[0] + n.di, s[1] + n.dj, n.sublattice};
}

// The lattice's point group D6 about the origin (a site of the hexagon tiling, a vertex of the
// triangle tiling), acting on lattice coordinates: op k < 6 is the rotation by 60 k degrees,
// op 6 + k that rotation after the mirror x -> -x. The rotation by 60 degrees sends (i, j) to
// (-j, i + j); the mirror sends (i, j) to (-i - j, j).
LatticeVector point_operation(int op, const LatticeVector& v);
Eigen::Matrix2d point_operation_matrix(int op);  // the same op on Cartesian vectors
inline Site transform_site(const Tiling& t, int op, const Site& s) {
    return site_at(t, point_operation(op, site_centre3(t, s)));
}

// A particle's point group in its own frame, as a set of the lattice's point operations above
// (the particle model declares it as kPointGroup):
//   C3: the rotations by 0, 120, 240 degrees;
//   D3: those and the mirrors whose axes point at 90, 210 and 330 degrees.
enum class PointGroup { C3 = 0, D3 = 1 };
std::vector<int> point_group_operations(PointGroup group);

inline Eigen::Matrix2d frame_matrix(const Tiling& t, int sublattice) {
    const auto& f = t.frame[sublattice];
    Eigen::Matrix2d r;
    r << f[0], -f[1], f[1], f[0];
    return r;
}

}  // namespace pyfrustrate
