#include "box.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace pyfrustrate {
namespace {

int floor_mod(int a, int m) {
    const int r = a % m;
    return r < 0 ? r + m : r;
}

int gcd(int a, int b) {
    a = std::abs(a), b = std::abs(b);
    while (b) {
        const int t = a % b;
        a = b, b = t;
    }
    return a;
}

// p a + q b = g = gcd(a, b) >= 0.
void extended_gcd(long a, long b, long& g, long& p, long& q) {
    long r0 = a, r1 = b, s0 = 1, s1 = 0, t0 = 0, t1 = 1;
    while (r1 != 0) {
        const long k = r0 / r1;
        long tmp = r0 - k * r1; r0 = r1; r1 = tmp;
        tmp = s0 - k * s1; s0 = s1; s1 = tmp;
        tmp = t0 - k * t1; t0 = t1; t1 = tmp;
    }
    if (r0 < 0) r0 = -r0, s0 = -s0, t0 = -t0;
    g = r0, p = s0, q = t0;
}

// Adds the wrap vector (x, y) to the lattice (a, b), (0, c) of the cluster, keeping the
// Hermite normal form: the new first row is the gcd combination of (a, b) and (x, y), the
// remainder (x/g)(a, b) - (a/g)(x, y) = (0, r) merges into c (a unimodular change of basis).
void add_wrap(Cluster& cl, int x, int y) {
    if (x == 0 && cl.a == 0) {
        cl.c = gcd(cl.c, y);
    } else {
        long g, p, q;
        extended_gcd(cl.a, x, g, p, q);
        const long b = p * cl.b + q * y;
        const long r = (x / g) * static_cast<long>(cl.b) - (cl.a / g) * static_cast<long>(y);
        cl.a = static_cast<int>(g);
        cl.b = static_cast<int>(b);
        cl.c = gcd(cl.c, static_cast<int>(r));
    }
    if (cl.c > 0) cl.b = floor_mod(cl.b, cl.c);
}

}  // namespace

Box::Box(const Tiling& tiling_, int L_) : tiling(&tiling_), L(L_) {
    // A box of one cell is a valid torus (each site its own image); the chain needs two (montecarlo/chain.hpp).
    if (L < 1) throw std::invalid_argument("box must be at least 1, got " + std::to_string(L));
    if (L > 30000) throw std::invalid_argument("box must be at most 30000, got " + std::to_string(L));
    const int D = neighbours();
    neighbour.resize(static_cast<std::size_t>(D) * n_sites());
    for (int s = 0; s < n_sites(); ++s)
        for (int d = 0; d < D; ++d) neighbour[D * s + d] = index(neighbour_of(*tiling, coords(s), d));
}

int Box::index(const Site& s) const { return s[2] + tiling->sublattices * (floor_mod(s[0], L) + L * floor_mod(s[1], L)); }

void ClusterWorkspace::resize(int n_sites) {
    mark.assign(n_sites, 0u);
    position.assign(n_sites, Site{0, 0, 0});
    stamp = 1;
}

Cluster find_cluster(const Box& box, const std::vector<int>& occupied, int start, ClusterWorkspace& ws) {
    Cluster cl;
    ws.queue.clear();
    ws.queue.push_back(start);
    ws.mark[start] = ws.stamp;
    ws.position[start] = box.coords(start);
    const int D = box.neighbours();
    for (std::size_t head = 0; head < ws.queue.size(); ++head) {
        const int s = ws.queue[head];
        const Site u = ws.position[s];
        cl.members.push_back(s);
        cl.unwrapped.push_back(u);
        for (int d = 0; d < D; ++d) {
            const int t = box.next(s, d);
            if (occupied[t] < 0) continue;
            const Site v = neighbour_of(*box.tiling, u, d);
            if (ws.mark[t] != ws.stamp) {
                ws.mark[t] = ws.stamp;
                ws.position[t] = v;
                ws.queue.push_back(t);
            } else if (ws.position[t] != v) {
                // Reached again by another path: the cluster wraps around the box.
                add_wrap(cl, v[0] - ws.position[t][0], v[1] - ws.position[t][1]);
            }
        }
    }
    return cl;
}

Topology cluster_topology(const Tiling& tiling, const std::vector<Site>& sites, const Cluster& wrap) {
    switch (wrap.rank()) {
        case 0: return make_topology(tiling, sites, Periodicity::None, {}, false);
        case 1: {
            const LatticeVector axis = wrap.a ? LatticeVector{wrap.a, wrap.b} : LatticeVector{0, wrap.c};
            return make_topology(tiling, sites, Periodicity::Fiber, {axis, LatticeVector{0, 0}}, false);
        }
        default:
            return make_topology(tiling, sites, Periodicity::Bulk, {LatticeVector{wrap.a, wrap.b}, LatticeVector{0, wrap.c}},
                                 false);
    }
}

}  // namespace pyfrustrate
