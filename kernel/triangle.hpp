// The triangular particle (supplement, "Triangular particles", Fig. S6). The supplement fixes two
// triangles of hard springs k, six softer coupling springs kc, the same continuum theory as the
// hexagon, a bound pair that already costs elastic energy, and bulk edges where the two
// triangles must match; its panel (a), the design, is lost. This is our reconstruction, which
// meets every one of those statements (docs/topics/triangle.md):
//
// every vertex of the particle carries a yellow node (slots 0-2 at vertices v0, v1, v2) and a
// red node (slots 3-5); the yellow triangle has springs k of rest length 1 + eps, the red one
// springs k of rest length 1 - eps, both with areal stiffness k_area as the hexagon's. Each
// edge (a, b) carries two coupling springs kc, Y_a-R_b and Y_b-R_a, at rest when both triangles
// are at rest, concentric and equally oriented: length sqrt(1 + eps^2 / 3). Bound neighbours
// share the yellow and the red node of each vertex of their common edge (tiling.hpp, triangle
// tiling). Without mismatch both nodes of a vertex coincide: the rest shape is the unit
// triangle, up, centred on its centroid.
#pragma once

#include "two_triangles.hpp"
#include "tiling.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pyfrustrate {

struct TriangleModel {
    static constexpr TilingKind kTiling = TilingKind::Triangle;
    static constexpr PointGroup kPointGroup = PointGroup::D3;
    static constexpr int kCornerCount = 6;
    using Corners = CornerArray<6>;
    using Hessian = CornerMatrix<6>;

    double k = 1.0, kc = 0.01, k_area = 0.0, eps = 0.01;

    TriangleModel(double k_, double kc_, double k_area_, double eps_)
        : k(k_), kc(kc_), k_area(k_area_), eps(eps_), areas_(eps_) {
        check_two_triangle_parameters(k, kc, k_area, eps);
        // Coupling rest length sqrt(1 + eps^2/3) = 1 + (eps^2/3) / (sqrt(1 + eps^2/3) + 1), formed
        // without cancellation; areas sqrt3/4 (1 +- eps)^2.
        coupling_delta_ = eps * eps / 3.0 / (std::sqrt(1 + eps * eps / 3.0) + 1);
        rest_ = rest_corners();
        reference_edges<6>(rest_, kFrom, kTo, edge0_, length0_);
    }

    // Springs: yellow sides, red sides, then the couplings Y_a-R_b, Y_b-R_a of each edge.
    static constexpr int kSprings = 12;
    static constexpr int kFrom[kSprings] = {0, 1, 2, 3, 4, 5, 0, 1, 1, 2, 2, 0};
    static constexpr int kTo[kSprings] = {1, 2, 0, 4, 5, 3, 4, 3, 5, 4, 3, 5};

    // Corners at rest without mismatch, in the particle's own frame: the unit up triangle about
    // its centroid, v0 (-1/2, -1/(2 sqrt3)), v1 (1/2, -1/(2 sqrt3)), v2 (0, 1/sqrt3); yellow and
    // red nodes of a vertex coincide.
    static Corners rest_corners() {
        Corners c;
        const double low = -0.5 / std::sqrt(3.0), top = 1 / std::sqrt(3.0);
        const double x[3] = {-0.5, 0.5, 0.0}, y[3] = {low, low, top};
        for (int colour = 0; colour < 2; ++colour)
            for (int v = 0; v < 3; ++v) c[2 * (3 * colour + v)] = x[v], c[2 * (3 * colour + v) + 1] = y[v];
        return c;
    }

    double step_scale() const { return std::max(eps, 1e-3); }
    TriangleModel without_mismatch() const { return TriangleModel(k, kc, k_area, 0.0); }

    using Terms = TwoTriangleTerms;

    Terms terms_of_displacement(const Corners& disp, Corners* grad = nullptr, Hessian* hess = nullptr) const {
        Terms t;
        for (int i = 0; i < 6; ++i)
            t.triangles += spring<6>(disp, kFrom[i], kTo[i], edge0_[i], length0_[i], k, 1.0, i < 3 ? eps : -eps, grad, hess);
        for (int i = 6; i < kSprings; ++i)
            t.connecting += spring<6>(disp, kFrom[i], kTo[i], edge0_[i], length0_[i], kc, 1.0, coupling_delta_, grad, hess);
        if (k_area != 0) {
            t.area += triangle_area<6>(rest_, disp, 0, 1, 2, k_area, areas_.nominal, areas_.yellow_delta, grad, hess);
            t.area += triangle_area<6>(rest_, disp, 3, 4, 5, k_area, areas_.nominal, areas_.red_delta, grad, hess);
        }
        return t;
    }
    Terms terms(const Corners& x, Corners* grad = nullptr, Hessian* hess = nullptr) const {
        return terms_of_displacement(Corners(x - rest_), grad, hess);
    }
    double energy_of_displacement(const Corners& disp, Corners* grad, Hessian* hess = nullptr) const {
        return terms_of_displacement(disp, grad, hess).total();
    }
    double energy(const Corners& x, Corners* grad, Hessian* hess = nullptr) const { return terms(x, grad, hess).total(); }

   private:
    double coupling_delta_ = 0;
    TriangleRestAreas areas_;
    Corners rest_ = Corners::Zero();
    Eigen::Vector2d edge0_[kSprings];
    double length0_[kSprings] = {};
};

}  // namespace pyfrustrate
