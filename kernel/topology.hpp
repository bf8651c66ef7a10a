// Geometry and topology of aggregates on the triangular particle lattice.
//
// Sites (i, j) sit at i*a1 + j*a2 with a1 = (1, 0), a2 = (1/2, sqrt(3)/2): lattice spacing 1,
// area sqrt(3)/2 per particle. A particle is a hexagon whose corners, in the bulk reference
// state (all hexagons regular, main text Eq. 4), sit at 1/sqrt(3) from its site at angles
// 30, 90, ..., 330 degrees. Corners alternate red (30, 150, 270) and yellow (90, 210, 330); the
// yellow corners form a triangular lattice Y(i, j) = site(i, j) + (0, 1/sqrt 3), the red ones
// R(i, j) = site(i, j) - (0, 1/sqrt 3). Bound neighbours share the two corners of their common
// side, yellow on yellow and red on red (Fig. 2b), so a topology is just a set of sites.
//
// Periodic cells model only what a scene needs: a fibre is one period of an infinite strip
// (one lattice period vector), a bulk is one cell of the plane (two). Positions of corners in
// neighbouring images are generated from the corners of the cell by the period map, whose
// parameters are degrees of freedom of the minimisation (the cell relaxes its length and,
// for a curved fibre, the angle between successive images).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

namespace pyfrustrate {

using Vec2 = Eigen::Vector2d;
using LatticeVector = std::array<int, 2>;

enum class Periodicity { None = 0, Fiber = 1, Bulk = 2 };

// Corner slots of a particle in counter-clockwise order, starting at 30 degrees.
// Even slots are red (withdrawn corners), odd slots yellow (protruding corners).
constexpr int kCorners = 6;

struct Topology {
    Periodicity periodicity = Periodicity::None;
    bool curved = false;                      // fibre only: images rotated by a free angle
    std::array<LatticeVector, 2> periods{};   // lattice coordinates of the period vectors
    std::vector<LatticeVector> sites;         // one representative per particle, in the cell
    std::vector<std::array<int, kCorners>> corner;   // corner index of each slot
    std::vector<std::array<LatticeVector, kCorners>> image;  // period image of each slot
    std::vector<Vec2> reference;              // bulk-reference position of each corner
    std::vector<int> corner_color;            // 1 yellow, 0 red
    int n_bonds = 0;                          // bound pairs of sides (per cell if periodic)
    // Curved fibre: images turn about the centroid of the cell's reference corners, and the
    // angle enters the state as bend = bend_scale * theta (a length, the cell's RMS radius),
    // so that its gradient is commensurate with the forces on corners.
    Vec2 pivot = Vec2::Zero();
    double bend_scale = 1.0;
    // Bulk-reference position of each corner slot relative to its particle's site, the same
    // for every particle: the regular hexagon that the particle models take as their rest shape
    // (HexagonModel::rest_corners; tests check that they agree). The network evaluates particles
    // from their corners' displacements alone; these place them for drawing (network.hpp).
    std::array<Vec2, kCorners> slot_offset{};
    int max_image = 0;                        // largest |image index| of any slot

    int n_particles() const { return static_cast<int>(sites.size()); }
    int n_corners() const { return static_cast<int>(reference.size()); }
    // Number of period-map parameters: fibre (tx, ty[, bend]); bulk (t1x, t1y, t2x, t2y).
    int n_period_parameters() const;
    // Reference values of the period-map parameters.
    Eigen::VectorXd reference_period_parameters() const;
    // Reference state of all degrees of freedom: corners (x0, y0, x1, y1, ...) then the
    // period-map parameters.
    Eigen::VectorXd reference_state() const;
};

// Builds the corner graph of a set of occupied sites. For a fibre, periods[0] is its axis;
// for a bulk, periods[0] and periods[1] span the cell. Sites are reduced into the cell; two
// sites equal modulo the periods, an empty set, or degenerate periods raise
// std::invalid_argument naming the offending parameter.
Topology make_topology(const std::vector<LatticeVector>& sites, Periodicity periodicity,
                       const std::array<LatticeVector, 2>& periods, bool curved);

Vec2 site_position(const LatticeVector& site);

}  // namespace pyfrustrate
