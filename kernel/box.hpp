// The periodic box of the Monte Carlo and the clusters of occupied sites in it.
//
// An L x L box of cells of a tiling (tiling.hpp), cell (i, j) with i and j modulo L, each cell
// holding the tiling's sublattices: L^2 sites for hexagons, 2 L^2 (up and down triangles) for
// triangles. Site index s = sublattice + S (i + L j) for S sublattices. Connectivity is through
// the tiling's edge neighbours, periodic.
//
// Clusters that wrap around the box are periodic aggregates: the wrap vectors met during the
// breadth-first search span a sublattice of cells; rank 1 is a straight fibre along the wrap
// vector, rank 2 a bulk cell.
#pragma once

#include "tiling.hpp"
#include "topology.hpp"

#include <algorithm>
#include <vector>

namespace pyfrustrate {

struct Box {
    const Tiling* tiling = nullptr;
    int L = 0;
    std::vector<int> neighbour;  // tiling->neighbours per site, in the tiling's order

    Box(const Tiling& tiling_, int L_);
    int n_sites() const { return tiling->sublattices * L * L; }
    int neighbours() const { return tiling->neighbours; }
    int index(const Site& s) const;  // any cell, reduced modulo L
    Site coords(int s) const {
        const int S = tiling->sublattices, cell = s / S;
        return {cell % L, cell / L, s % S};
    }
    int next(int s, int d) const { return neighbour[neighbours() * s + d]; }
};

// A connected cluster of occupied sites found by breadth-first search on the torus.
struct Cluster {
    std::vector<int> members;      // site indices, in BFS order from the start site
    std::vector<Site> unwrapped;   // plane sites of the members (same order)
    // Lattice of wrap vectors (differences of unwrapped cells of the same site), in Hermite
    // normal form: basis (a, b), (0, c) with a, c >= 0 and 0 <= b < c when c > 0.
    int a = 0, b = 0, c = 0;
    int rank() const { return (a != 0) + (c != 0); }
    int size() const { return static_cast<int>(members.size()); }
};

// Scratch space of the searches: visit marks (stamped, never cleared) and unwrapped sites.
struct ClusterWorkspace {
    std::vector<unsigned> mark;
    std::vector<Site> position;
    unsigned stamp = 0;
    std::vector<int> queue;
    void resize(int n_sites);
    void new_round() { if (++stamp == 0) { std::fill(mark.begin(), mark.end(), 0u); stamp = 1; } }
    bool seen(int s) const { return mark[s] == stamp; }
};

// Cluster of `start` among the sites with occupied[s] >= 0. Marks its members as seen in the
// current round of `ws` (call ws.new_round() to forget earlier searches).
Cluster find_cluster(const Box& box, const std::vector<int>& occupied, int start, ClusterWorkspace& ws);

// A cluster as a topology: finite clusters from `sites` (plane sites); wrapped ones as a
// straight fibre along (a, b) or (0, c) (rank 1) or as a bulk cell spanned by (a, b), (0, c)
// (rank 2), `sites` being unwrapped sites consistent with those periods.
Topology cluster_topology(const Tiling& tiling, const std::vector<Site>& sites, const Cluster& wrap);

}  // namespace pyfrustrate
