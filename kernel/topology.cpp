#include "topology.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>

namespace pyfrustrate {
namespace {

const double kSqrt3 = std::sqrt(3.0);

// Neighbour directions of the triangular lattice, in lattice coordinates.
constexpr std::array<LatticeVector, 6> kNeighbours{{{1, 0}, {0, 1}, {-1, 1}, {-1, 0}, {0, -1}, {1, -1}}};

// Corner key: colour and lattice index of the yellow/red corner lattices (see topology.hpp).
struct CornerKey {
    int color;  // 1 yellow, 0 red
    int i, j;
    bool operator<(const CornerKey& o) const { return std::tie(color, i, j) < std::tie(o.color, o.i, o.j); }
};

// Slot s of the particle at (i, j): 30 R(i, j+1), 90 Y(i, j), 150 R(i-1, j+1), 210 Y(i, j-1),
// 270 R(i, j), 330 Y(i+1, j-1).
CornerKey corner_of(const LatticeVector& site, int slot) {
    const int i = site[0], j = site[1];
    switch (slot) {
        case 0: return {0, i, j + 1};
        case 1: return {1, i, j};
        case 2: return {0, i - 1, j + 1};
        case 3: return {1, i, j - 1};
        case 4: return {0, i, j};
        default: return {1, i + 1, j - 1};
    }
}

// Three times the lattice coordinates of a corner: exact integer arithmetic for the reduction.
// Y(i, j) = (i - 1/3, j + 2/3), R(i, j) = (i + 1/3, j - 2/3) in the basis (a1, a2).
LatticeVector thrice(const CornerKey& c) {
    return c.color ? LatticeVector{3 * c.i - 1, 3 * c.j + 2} : LatticeVector{3 * c.i + 1, 3 * c.j - 2};
}

long floor_div(long a, long b) {
    long q = a / b;
    if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
    return q;
}

long cross(const LatticeVector& a, const LatticeVector& b) {
    return static_cast<long>(a[0]) * b[1] - static_cast<long>(a[1]) * b[0];
}

// Twice the Euclidean dot product of two lattice vectors (metric [[2, 1], [1, 2]] / 2).
long dot2(const LatticeVector& a, const LatticeVector& b) {
    return 2L * a[0] * b[0] + static_cast<long>(a[0]) * b[1] + static_cast<long>(a[1]) * b[0] + 2L * a[1] * b[1];
}

// Image index of a point given by three times its lattice coordinates: the cell is
// [0, 1) along each period (fibre: along the axis only, by orthogonal projection).
LatticeVector image_of(const LatticeVector& v3, Periodicity periodicity,
                       const std::array<LatticeVector, 2>& P) {
    if (periodicity == Periodicity::None) return {0, 0};
    if (periodicity == Periodicity::Fiber)
        return {static_cast<int>(floor_div(dot2(v3, P[0]), 3 * dot2(P[0], P[0]))), 0};
    const long det = cross(P[0], P[1]);
    // v = s P0 + t P1 with s = cross(v, P1) / det, t = cross(P0, v) / det.
    return {static_cast<int>(floor_div(cross(v3, P[1]), 3 * det)),
            static_cast<int>(floor_div(cross(P[0], v3), 3 * det))};
}

LatticeVector shift(const LatticeVector& v, const LatticeVector& n, const std::array<LatticeVector, 2>& P) {
    return {v[0] - n[0] * P[0][0] - n[1] * P[1][0], v[1] - n[0] * P[0][1] - n[1] * P[1][1]};
}

}  // namespace

Vec2 site_position(const LatticeVector& s) { return {s[0] + 0.5 * s[1], 0.5 * kSqrt3 * s[1]}; }

int Topology::n_period_parameters() const {
    switch (periodicity) {
        case Periodicity::Fiber: return curved ? 3 : 2;
        case Periodicity::Bulk: return 4;
        default: return 0;
    }
}

Eigen::VectorXd Topology::reference_period_parameters() const {
    Eigen::VectorXd p = Eigen::VectorXd::Zero(n_period_parameters());
    if (periodicity == Periodicity::None) return p;
    p.head<2>() = site_position(periods[0]);
    if (periodicity == Periodicity::Bulk) p.segment<2>(2) = site_position(periods[1]);
    return p;  // a curved fibre starts straight (theta = 0)
}

Eigen::VectorXd Topology::reference_state() const {
    Eigen::VectorXd x(2 * n_corners() + n_period_parameters());
    for (int c = 0; c < n_corners(); ++c) x.segment<2>(2 * c) = reference[c];
    x.tail(n_period_parameters()) = reference_period_parameters();
    return x;
}

Topology make_topology(const std::vector<LatticeVector>& input_sites, Periodicity periodicity,
                       const std::array<LatticeVector, 2>& periods, bool curved) {
    if (input_sites.empty()) throw std::invalid_argument("sites: the topology is empty");
    if (curved && periodicity != Periodicity::Fiber)
        throw std::invalid_argument("curved: only a fibre can be curved");
    if (periodicity == Periodicity::Fiber && periods[0][0] == 0 && periods[0][1] == 0)
        throw std::invalid_argument("period: a fibre needs a non-zero period vector");
    if (periodicity == Periodicity::Bulk && cross(periods[0], periods[1]) == 0)
        throw std::invalid_argument("periods: the two bulk period vectors are parallel or zero");

    Topology t;
    t.periodicity = periodicity;
    t.curved = curved;
    t.periods = periods;

    std::set<LatticeVector> occupied;
    for (const auto& s : input_sites) {
        const LatticeVector s3{3 * s[0], 3 * s[1]};
        const LatticeVector reduced = shift(s, image_of(s3, periodicity, periods), periods);
        if (!occupied.insert(reduced).second)
            throw std::invalid_argument("sites: site (" + std::to_string(s[0]) + ", " + std::to_string(s[1]) +
                                        ") is occupied twice (modulo the periods)");
        t.sites.push_back(reduced);
    }

    std::map<CornerKey, int> index;
    for (const auto& s : t.sites) {
        std::array<int, kCorners> ids{};
        std::array<LatticeVector, kCorners> images{};
        for (int slot = 0; slot < kCorners; ++slot) {
            CornerKey key = corner_of(s, slot);
            const LatticeVector n = image_of(thrice(key), periodicity, periods);
            const LatticeVector ij = shift({key.i, key.j}, n, periods);
            key.i = ij[0];
            key.j = ij[1];
            auto [it, inserted] = index.emplace(key, static_cast<int>(t.reference.size()));
            if (inserted) {
                const Vec2 offset(0.0, (key.color ? 1.0 : -1.0) / kSqrt3);
                t.reference.push_back(site_position({key.i, key.j}) + offset);
                t.corner_color.push_back(key.color);
            }
            ids[slot] = it->second;
            images[slot] = n;
        }
        t.corner.push_back(ids);
        t.image.push_back(images);
    }

    for (int slot = 0; slot < kCorners; ++slot) {
        const CornerKey key = corner_of({0, 0}, slot);
        t.slot_offset[slot] = site_position({key.i, key.j}) + Vec2(0.0, (key.color ? 1.0 : -1.0) / kSqrt3);
    }
    for (const auto& images : t.image)
        for (const auto& n : images) t.max_image = std::max({t.max_image, std::abs(n[0]), std::abs(n[1])});

    if (curved) {
        for (const auto& r : t.reference) t.pivot += r;
        t.pivot /= t.n_corners();
        double spread = 0;
        for (const auto& r : t.reference) spread += (r - t.pivot).squaredNorm();
        t.bend_scale = std::max(1.0, std::sqrt(spread / t.n_corners()));
    }

    int directed_bonds = 0;
    for (const auto& s : t.sites)
        for (const auto& d : kNeighbours) {
            const LatticeVector nb{s[0] + d[0], s[1] + d[1]};
            const LatticeVector nb3{3 * nb[0], 3 * nb[1]};
            if (occupied.count(shift(nb, image_of(nb3, periodicity, periods), periods))) ++directed_bonds;
        }
    t.n_bonds = directed_bonds / 2;
    return t;
}

}  // namespace pyfrustrate
