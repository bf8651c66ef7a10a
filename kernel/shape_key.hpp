// Canonical keys of cluster shapes, for the Monte Carlo's cache of relaxed energies: two
// clusters with the same key have the same relaxed deformation energy.
//
// A finite cluster's energy is invariant under translations by lattice vectors and under the
// operations of the lattice's point group (tiling.hpp) that map every particle onto the particle
// of the site it lands on: op g is a symmetry of the shapes iff, for every sublattice s (frame
// F_s) sent to sublattice s', F_s'^-1 G F_s belongs to the particle's own point group. Hexagons
// (D3) keep the rotations by 120 degrees and the colour-preserving mirrors, not the 60-degree
// rotations, which swap yellow and red corners; random particles (C3) keep the rotations only;
// triangles (D3, with the down triangles turned by 180 degrees) keep all twelve.
#pragma once

#include "box.hpp"
#include "tiling.hpp"

#include <cstdint>
#include <vector>

namespace pyfrustrate {

// The lattice operations that are symmetries of cluster shapes of `particle` on `tiling` (above).
std::vector<int> shape_symmetries(const Tiling& tiling, PointGroup particle);

using ShapeKey = std::vector<std::int64_t>;
struct ShapeKeyHash {
    std::size_t operator()(const ShapeKey& key) const;
};

// Canonical key of a finite cluster given by its plane sites: over the operations `symmetries`,
// transform, translate the cell of the lexicographically smallest site to the origin, sort;
// keep the lexicographically smallest list. If `canonical_sites` is given, it receives the sites
// of that representative (sorted), from which the energy of the shape is computed.
ShapeKey finite_shape_key(const Tiling& tiling, const std::vector<int>& symmetries, const std::vector<Site>& sites,
                          std::vector<Site>* canonical_sites = nullptr);
// The sites of a finite key's representative.
std::vector<Site> key_sites(const ShapeKey& key);

// Key of a wrapped cluster: (-rank, L, a, b, c, sorted member site indices). No symmetry
// reduction.
ShapeKey wrapped_shape_key(const Cluster& cluster, int L);

}  // namespace pyfrustrate
