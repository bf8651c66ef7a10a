// The hexagonal particle of the paper (main text, "Two-dimensional particle model", Fig. 2a):
// a yellow and a red triangle of springs k with rest sides 1 + eps and 1 - eps, six connecting
// springs kc along the hexagon's sides, at rest when both triangles are at rest and centred,
// and an areal stiffness k_area on each triangle. A stateless evaluator of one particle's
// energy from its six corners (slots as in topology.hpp: even slots red, odd slots yellow).
#pragma once

#include "elements.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pyfrustrate {

struct HexagonModel {
    static constexpr int kCornerCount = 6;
    using Corners = CornerArray<6>;
    using Hessian = CornerMatrix<6>;

    double k = 1.0, kc = 0.01, k_area = 0.0, eps = 0.01;

    HexagonModel(double k_, double kc_, double k_area_, double eps_) : k(k_), kc(kc_), k_area(k_area_), eps(eps_) {
        if (!(k > 0) || !std::isfinite(k)) throw std::invalid_argument("k must be positive and finite");
        if (!(kc >= 0) || !std::isfinite(kc)) throw std::invalid_argument("kc must be non-negative and finite");
        // The sheet's Poisson ratio is -1 at k_area = -sqrt(3) k: below it the sheet buckles.
        if (!(k_area > -std::sqrt(3.0) * k) || !std::isfinite(k_area))
            throw std::invalid_argument("k_area must be finite and exceed -sqrt(3) k (unstable sheet otherwise), got " +
                                        std::to_string(k_area));
        if (!(eps >= 0 && eps < 1)) throw std::invalid_argument("eps must lie in [0, 1)");
        yellow_ = 1 + eps;
        red_ = 1 - eps;
        // Hexagon side at rest: corners at radii yellow/sqrt3 and red/sqrt3, 60 degrees apart.
        side_ = std::sqrt((yellow_ * yellow_ + red_ * red_ - yellow_ * red_) / 3.0);
        yellow_area_ = std::sqrt(3.0) / 4.0 * yellow_ * yellow_;
        red_area_ = std::sqrt(3.0) / 4.0 * red_ * red_;
    }

    // Typical corner displacement of a relaxation: the mismatch (at least a small floor).
    double step_scale() const { return std::max(eps, 1e-3); }

    // The same particle without mismatch: its Hessian at the bulk reference is the stiffness
    // matrix of the linearised (eps -> 0) theory.
    HexagonModel without_mismatch() const { return HexagonModel(k, kc, k_area, 0.0); }

    struct Terms {
        double triangles = 0, connecting = 0, area = 0;
        double total() const { return triangles + connecting + area; }
    };

    // The energy by terms, with gradient and Hessian on request (elements.hpp).
    Terms terms(const Corners& x, Corners* grad = nullptr, Hessian* hess = nullptr) const {
        Terms t;
        for (int m = 0; m < 3; ++m) {
            t.triangles += spring<6>(x, 2 * m + 1, (2 * m + 3) % 6, k, yellow_, grad, hess);
            t.triangles += spring<6>(x, 2 * m, (2 * m + 2) % 6, k, red_, grad, hess);
        }
        for (int s = 0; s < 6; ++s) t.connecting += spring<6>(x, s, (s + 1) % 6, kc, side_, grad, hess);
        if (k_area != 0) {
            t.area += triangle_area<6>(x, 1, 3, 5, k_area, yellow_area_, grad, hess);
            t.area += triangle_area<6>(x, 0, 2, 4, k_area, red_area_, grad, hess);
        }
        return t;
    }

    double energy(const Corners& x, Corners* grad, Hessian* hess = nullptr) const {
        return terms(x, grad, hess).total();
    }

   private:
    // Rest shape, computed once per particle model rather than once per evaluation.
    double yellow_ = 1, red_ = 1, side_ = 1, yellow_area_ = 0, red_area_ = 0;
};

}  // namespace pyfrustrate
