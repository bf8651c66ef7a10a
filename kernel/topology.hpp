// Geometry and topology of aggregates: a tiling (tiling.hpp) and a set of occupied sites.
//
// Bound neighbours share the corners of their common edge (tiling.hpp says which), so a
// topology is just a set of sites; its corner graph, reference positions and bond count
// follow. The reference state is the bulk reference of the tiling (every particle at its rest
// shape without mismatch; main text Eq. 4 for the hexagon).
//
// Periodic cells model only what a scene needs: a fibre is one period of an infinite strip
// (one lattice period vector), a bulk is one cell of the plane (two). Positions of corners in
// neighbouring images are generated from the corners of the cell by the period map, whose
// parameters are degrees of freedom of the minimisation (the cell relaxes its length and,
// for a curved fibre, the angle between successive images).
#pragma once

#include "tiling.hpp"

#include <Eigen/Dense>
#include <array>
#include <vector>

namespace pyfrustrate {

enum class Periodicity { None = 0, Fiber = 1, Bulk = 2 };

struct Topology {
    TilingKind tiling_kind = TilingKind::Hexagon;
    Periodicity periodicity = Periodicity::None;
    bool curved = false;                      // fibre only: images rotated by a free angle
    std::array<LatticeVector, 2> periods{};   // lattice coordinates of the period vectors
    std::vector<Site> sites;                  // one representative per particle, in the cell
    std::vector<std::array<int, kMaxCorners>> corner;   // corner index of each slot
    std::vector<std::array<LatticeVector, kMaxCorners>> image;  // period image of each slot
    std::vector<Vec2> reference;              // bulk-reference position of each corner
    std::vector<int> corner_color;            // 1 yellow, 0 red
    int n_bonds = 0;                          // bound pairs of edges (per cell if periodic)
    // Curved fibre: images turn about the centroid of the cell's reference corners, and the
    // angle enters the state as bend = bend_scale * theta (a length, the cell's RMS radius),
    // so that its gradient is commensurate with the forces on corners.
    Vec2 pivot = Vec2::Zero();
    double bend_scale = 1.0;
    // Bulk-reference position of each corner slot relative to its particle's site centre, per
    // sublattice: the particle models' rest shape turned by the sublattice's frame (tests check
    // that they agree). The network evaluates particles from their corners' displacements
    // alone; these place them for drawing (network.hpp).
    std::array<std::array<Vec2, kMaxCorners>, kMaxSublattices> slot_offset{};
    int max_image = 0;                        // largest |image index| of any slot

    const Tiling& tiling() const { return tiling_of(tiling_kind); }
    int n_particles() const { return static_cast<int>(sites.size()); }
    int n_corners() const { return static_cast<int>(reference.size()); }
    // Number of period-map parameters: fibre (tx, ty[, bend]); bulk (t1x, t1y, t2x, t2y).
    int n_period_parameters() const;
    // Number of period vectors: 2 (bulk), 1 (fibre), 0.
    int n_period_vectors() const;
    // Whether any corner slot of particle p lies in a periodic image of the cell (inline: the
    // network asks it for every particle of every evaluation).
    bool has_image(int p) const {
        for (const auto& slot : image[p])
            if (slot[0] != 0 || slot[1] != 0) return true;
        return false;
    }
    // Reference values of the period-map parameters.
    Eigen::VectorXd reference_period_parameters() const;
    // Reference state of all degrees of freedom: corners (x0, y0, x1, y1, ...) then the
    // period-map parameters.
    Eigen::VectorXd reference_state() const;
};

// Builds the corner graph of a set of occupied sites of `tiling`. For a fibre, periods[0] is its axis;
// for a bulk, periods[0] and periods[1] span the cell. Sites are reduced into the cell; two
// sites equal modulo the periods, an empty set, or degenerate periods raise
// std::invalid_argument naming the offending parameter.
Topology make_topology(const Tiling& tiling, const std::vector<Site>& sites, Periodicity periodicity,
                       const std::array<LatticeVector, 2>& periods, bool curved);

}  // namespace pyfrustrate
