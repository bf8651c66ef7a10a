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

// Corner key: colour (which corner lattice) and cell of the corner (tiling.hpp).
struct CornerKey {
    int color;
    int i, j;
    bool operator<(const CornerKey& o) const { return std::tie(color, i, j) < std::tie(o.color, o.i, o.j); }
};

CornerKey corner_of(const Tiling& tiling, const Site& site, int slot) {
    const CornerSlot& c = tiling.slot[site[2]][slot];
    return {c.color, site[0] + c.di, site[1] + c.dj};
}

// Three times the lattice coordinates of a corner: exact integer arithmetic for the reduction.
LatticeVector thrice(const Tiling& tiling, const CornerKey& c) {
    return {3 * c.i + tiling.corner_offset3[c.color][0], 3 * c.j + tiling.corner_offset3[c.color][1]};
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

int Topology::n_period_parameters() const {
    switch (periodicity) {
        case Periodicity::Fiber: return curved ? 3 : 2;
        case Periodicity::Bulk: return 4;
        default: return 0;
    }
}

int Topology::n_period_vectors() const {
    switch (periodicity) {
        case Periodicity::Fiber: return 1;
        case Periodicity::Bulk: return 2;
        default: return 0;
    }
}

Eigen::VectorXd Topology::reference_period_parameters() const {
    Eigen::VectorXd p = Eigen::VectorXd::Zero(n_period_parameters());
    if (periodicity == Periodicity::None) return p;
    p.head<2>() = cell_position(periods[0]);
    if (periodicity == Periodicity::Bulk) p.segment<2>(2) = cell_position(periods[1]);
    return p;  // a curved fibre starts straight (theta = 0)
}

Eigen::VectorXd Topology::reference_state() const {
    Eigen::VectorXd x(2 * n_corners() + n_period_parameters());
    for (int c = 0; c < n_corners(); ++c) x.segment<2>(2 * c) = reference[c];
    x.tail(n_period_parameters()) = reference_period_parameters();
    return x;
}

Topology make_topology(const Tiling& tiling, const std::vector<Site>& input_sites, Periodicity periodicity,
                       const std::array<LatticeVector, 2>& periods, bool curved) {
    if (input_sites.empty()) throw std::invalid_argument("sites: the topology is empty");
    if (curved && periodicity != Periodicity::Fiber)
        throw std::invalid_argument("curved: only a fibre can be curved");
    if (periodicity == Periodicity::Fiber && periods[0][0] == 0 && periods[0][1] == 0)
        throw std::invalid_argument("period: a fibre needs a non-zero period vector");
    if (periodicity == Periodicity::Bulk && cross(periods[0], periods[1]) == 0)
        throw std::invalid_argument("periods: the two bulk period vectors are parallel or zero");

    Topology t;
    t.tiling_kind = tiling.kind;
    t.periodicity = periodicity;
    t.curved = curved;
    t.periods = periods;

    // A site is reduced into the cell by the image of its centre.
    auto reduce = [&](const Site& s) {
        const LatticeVector cell = shift({s[0], s[1]}, image_of(site_centre3(tiling, s), periodicity, periods), periods);
        return Site{cell[0], cell[1], s[2]};
    };
    std::set<Site> occupied;
    for (const auto& s : input_sites) {
        if (s[2] < 0 || s[2] >= tiling.sublattices)
            throw std::invalid_argument("sites: sublattice " + std::to_string(s[2]) + " does not exist in the " +
                                        tiling.name + " tiling");
        const Site reduced = reduce(s);
        if (!occupied.insert(reduced).second)
            throw std::invalid_argument("sites: site (" + std::to_string(s[0]) + ", " + std::to_string(s[1]) +
                                        (tiling.sublattices > 1 ? ", " + std::to_string(s[2]) : std::string()) +
                                        ") is occupied twice (modulo the periods)");
        t.sites.push_back(reduced);
    }

    std::map<CornerKey, int> index;
    for (const auto& s : t.sites) {
        std::array<int, kMaxCorners> ids{};
        std::array<LatticeVector, kMaxCorners> images{};
        for (int slot = 0; slot < tiling.corners; ++slot) {
            CornerKey key = corner_of(tiling, s, slot);
            const LatticeVector n = image_of(thrice(tiling, key), periodicity, periods);
            const LatticeVector ij = shift({key.i, key.j}, n, periods);
            key.i = ij[0];
            key.j = ij[1];
            auto [it, inserted] = index.emplace(key, static_cast<int>(t.reference.size()));
            if (inserted) {
                t.reference.push_back(cartesian3(thrice(tiling, key)));
                t.corner_color.push_back(key.color);
            }
            ids[slot] = it->second;
            images[slot] = n;
        }
        t.corner.push_back(ids);
        t.image.push_back(images);
    }

    for (int sub = 0; sub < tiling.sublattices; ++sub)
        for (int slot = 0; slot < tiling.corners; ++slot) {
            const Site origin{0, 0, sub};
            t.slot_offset[sub][slot] =
                cartesian3(thrice(tiling, corner_of(tiling, origin, slot))) - site_position(tiling, origin);
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
        for (int d = 0; d < tiling.neighbours; ++d) directed_bonds += occupied.count(reduce(neighbour_of(tiling, s, d)));
    t.n_bonds = directed_bonds / 2;
    return t;
}

}  // namespace pyfrustrate
