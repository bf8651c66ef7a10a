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

struct Topology;

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

    // energy() with gradient on kLanes particles at once, in structure-of-arrays layout (x[c][l]:
    // coordinate c = x0, y0, ..., y5 of particle l), so that a vector unit evaluates one term
    // for kLanes particles per instruction (network_simd.cpp). Every operation mirrors terms()
    // in kind and order (no fused multiply-add there), so the sums are equal to the last bit:
    // tests/test_relaxation_engine.py checks it.
    template <int kLanes>
    void energy_lanes(const double (&x)[12][kLanes], double (&g)[12][kLanes], double (&e)[kLanes]) const {
        constexpr int from[12] = {1, 0, 3, 2, 5, 4, 0, 1, 2, 3, 4, 5};  // the order of terms()
        constexpr int to[12] = {3, 2, 5, 4, 1, 0, 1, 2, 3, 4, 5, 0};
        const double rest[12] = {yellow_, red_, yellow_, red_, yellow_, red_, side_, side_, side_, side_, side_, side_};
        double triangles[kLanes] = {}, connecting[kLanes] = {}, area[kLanes] = {};
        for (int c = 0; c < 12; ++c)
            for (int l = 0; l < kLanes; ++l) g[c][l] = 0.0;
        for (int i = 0; i < 12; ++i) {
            const double stiffness = i < 6 ? k : kc;
            const int a = from[i], b = to[i];
            double* sum = i < 6 ? triangles : connecting;
            for (int l = 0; l < kLanes; ++l) {
                const double dx = x[2 * b][l] - x[2 * a][l], dy = x[2 * b + 1][l] - x[2 * a + 1][l];
                const double length = std::sqrt(dx * dx + dy * dy);
                const double stretch = length - rest[i];
                const double inverse = length > 0 ? 1.0 / length : 0.0;
                const double ux = dx * inverse, uy = dy * inverse;
                const double f = stiffness * stretch;
                g[2 * b][l] += f * ux, g[2 * b + 1][l] += f * uy;
                g[2 * a][l] -= f * ux, g[2 * a + 1][l] -= f * uy;
                sum[l] += 0.5 * stiffness * stretch * stretch;
            }
        }
        if (k_area != 0) {
            const int corners[2][3] = {{1, 3, 5}, {0, 2, 4}};
            const double rest_area[2] = {yellow_area_, red_area_};
            for (int t = 0; t < 2; ++t) {
                const double scale = k_area / rest_area[t];
                const int* idx = corners[t];
                for (int l = 0; l < kLanes; ++l) {
                    const double abx = x[2 * idx[1]][l] - x[2 * idx[0]][l], aby = x[2 * idx[1] + 1][l] - x[2 * idx[0] + 1][l];
                    const double acx = x[2 * idx[2]][l] - x[2 * idx[0]][l], acy = x[2 * idx[2] + 1][l] - x[2 * idx[0] + 1][l];
                    const double excess = 0.5 * (abx * acy - aby * acx) - rest_area[t];
                    const double force = scale * excess;
                    for (int m = 0; m < 3; ++m) {
                        const int q = idx[(m + 1) % 3], r = idx[(m + 2) % 3];
                        g[2 * idx[m]][l] += force * (0.5 * (x[2 * q + 1][l] - x[2 * r + 1][l]));
                        g[2 * idx[m] + 1][l] += force * (0.5 * (x[2 * r][l] - x[2 * q][l]));
                    }
                    area[l] += 0.5 * scale * excess * excess;
                }
            }
        }
        for (int l = 0; l < kLanes; ++l) e[l] = triangles[l] + connecting[l] + area[l];
    }

   private:
    // Rest shape, computed once per particle model rather than once per evaluation.
    double yellow_ = 1, red_ = 1, side_ = 1, yellow_area_ = 0, red_area_ = 0;
};

// Energy and gradient of a finite network of hexagons, eight particles per instruction where the
// processor has AVX-512 (network_simd.cpp; network.hpp calls it through
// vectorised_finite_energy). Returns false where it does not apply: the scalar loop then runs.
bool vectorised_finite_energy(const HexagonModel& model, const Topology& topology, const double* u, double* gradient,
                              double& total);
// Whether this processor runs it (AVX-512).
bool vectorised_evaluation_available();

}  // namespace pyfrustrate
