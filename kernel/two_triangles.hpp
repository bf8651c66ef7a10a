// What the particles built of a yellow and a red triangle of springs (hexagon.hpp, triangle.hpp)
// share: their parameters and checks, the rest areas of the two triangles, the reference edges
// of their springs, and the energy by kind of term.
#pragma once

#include "elements.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace pyfrustrate {

// k > 0, kc >= 0, k_area > -sqrt(3) k (the sheet's Poisson ratio reaches -1 there: below it the
// sheet buckles), 0 <= eps < 1, all finite; std::invalid_argument naming the first bad one.
inline void check_two_triangle_parameters(double k, double kc, double k_area, double eps) {
    if (!(k > 0) || !std::isfinite(k)) throw std::invalid_argument("k must be positive and finite");
    if (!(kc >= 0) || !std::isfinite(kc)) throw std::invalid_argument("kc must be non-negative and finite");
    if (!(k_area > -std::sqrt(3.0) * k) || !std::isfinite(k_area))
        throw std::invalid_argument("k_area must be finite and exceed -sqrt(3) k (unstable sheet otherwise), got " +
                                    std::to_string(k_area));
    if (!(eps >= 0 && eps < 1)) throw std::invalid_argument("eps must lie in [0, 1)");
}

// Rest areas of the yellow and red triangles, sides 1 +- eps: sqrt3/4 (1 +- eps)^2 as the
// reference (eps = 0) area plus what the mismatch adds, formed without cancellation.
struct TriangleRestAreas {
    double nominal = 0, yellow_delta = 0, red_delta = 0;
    explicit TriangleRestAreas(double eps)
        : nominal(std::sqrt(3.0) / 4.0), yellow_delta(nominal * eps * (2 + eps)), red_delta(nominal * eps * (eps - 2)) {}
};

// Reference edge (rest[to] - rest[from]) and length of every spring, from a rest shape.
template <int N, int S>
void reference_edges(const CornerArray<N>& rest, const int (&from)[S], const int (&to)[S], Eigen::Vector2d (&edge0)[S],
                     double (&length0)[S]) {
    for (int i = 0; i < S; ++i) {
        edge0[i] = rest.template segment<2>(2 * to[i]) - rest.template segment<2>(2 * from[i]);
        length0[i] = edge0[i].norm();
    }
}

// A particle's energy by kind of term: triangle sides, coupling springs, areas.
struct TwoTriangleTerms {
    double triangles = 0, connecting = 0, area = 0;
    double total() const { return triangles + connecting + area; }
};

}  // namespace pyfrustrate
