// The hexagonal particle of the paper (main text, "Two-dimensional particle model", Fig. 2a):
// a yellow and a red triangle of springs k with rest sides 1 + eps and 1 - eps, six connecting
// springs kc along the hexagon's sides, at rest when both triangles are at rest and centred,
// and an areal stiffness k_area on each triangle. A stateless evaluator of one particle's
// energy from its six corners (slots as in topology.hpp: even slots red, odd slots yellow).
#pragma once

#include "two_triangles.hpp"
#include "tiling.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pyfrustrate {

struct Topology;

struct HexagonModel {
    static constexpr TilingKind kTiling = TilingKind::Hexagon;
    static constexpr PointGroup kPointGroup = PointGroup::D3;
    static constexpr int kCornerCount = 6;
    using Corners = CornerArray<6>;
    using Hessian = CornerMatrix<6>;

    double k = 1.0, kc = 0.01, k_area = 0.0, eps = 0.01;

    HexagonModel(double k_, double kc_, double k_area_, double eps_)
        : k(k_), kc(kc_), k_area(k_area_), eps(eps_), areas_(eps_) {
        check_two_triangle_parameters(k, kc, k_area, eps);
        // Rest lengths and areas as the reference (eps = 0) value plus what the mismatch adds,
        // each addition formed without cancellation (elements.hpp). Triangle sides 1 +- eps; the
        // hexagon side, corners at radii (1 +- eps)/sqrt3 60 degrees apart, is
        // sqrt((1 + 3 eps^2) / 3) = 1/sqrt3 + eps^2 / (side + 1/sqrt3); areas sqrt3/4 (1 +- eps)^2.
        side_nominal_ = 1 / std::sqrt(3.0);
        side_delta_ = side_delta(eps);
        rest_ = rest_corners();
        reference_edges<6>(rest_, kFrom, kTo, edge0_, length0_);
    }

    // The twelve springs in the order terms() sums them: yellow and red triangle sides
    // alternately, then the six hexagon sides (slot s to s + 1).
    static constexpr int kSprings = 12;
    static constexpr int kFrom[kSprings] = {1, 0, 3, 2, 5, 4, 0, 1, 2, 3, 4, 5};
    static constexpr int kTo[kSprings] = {3, 2, 5, 4, 1, 0, 1, 2, 3, 4, 5, 0};

    // What the mismatch adds to the hexagon's side, without cancellation:
    // sqrt((1 + 3 eps^2) / 3) - 1/sqrt3 = eps^2 / (sqrt((1 + 3 eps^2) / 3) + 1/sqrt3).
    static double side_delta(double eps) {
        return eps * eps / (std::sqrt((1 + 3 * eps * eps) / 3.0) + 1 / std::sqrt(3.0));
    }

    // Corners of the particle at rest without mismatch, in its own frame (slots as in
    // topology.hpp: radius 1/sqrt3, 30 + 60 s degrees): the reference of energy(x).
    static Corners rest_corners() {
        Corners c;
        for (int s = 0; s < 6; ++s) {
            const double angle = M_PI / 6 + s * M_PI / 3;
            c[2 * s] = std::cos(angle) / std::sqrt(3.0);
            c[2 * s + 1] = std::sin(angle) / std::sqrt(3.0);
        }
        return c;
    }

    // Typical corner displacement of a relaxation: the mismatch (at least a small floor).
    double step_scale() const { return std::max(eps, 1e-3); }

    // The same particle without mismatch: its Hessian at the bulk reference is the stiffness
    // matrix of the linearised (eps -> 0) theory.
    HexagonModel without_mismatch() const { return HexagonModel(k, kc, k_area, 0.0); }

    using Terms = TwoTriangleTerms;

    // The energy by terms of the particle whose corners are displaced by disp from rest_corners()
    // (its own frame), with gradient and Hessian on request (elements.hpp).
    Terms terms_of_displacement(const Corners& disp, Corners* grad = nullptr, Hessian* hess = nullptr) const {
        Terms t;
        for (int i = 0; i < 6; ++i)
            t.triangles += spring<6>(disp, kFrom[i], kTo[i], edge0_[i], length0_[i], k, 1.0, i % 2 == 0 ? eps : -eps,
                                     grad, hess);
        for (int i = 6; i < kSprings; ++i)
            t.connecting += spring<6>(disp, kFrom[i], kTo[i], edge0_[i], length0_[i], kc, side_nominal_, side_delta_,
                                      grad, hess);
        if (k_area != 0) {
            t.area += triangle_area<6>(rest_, disp, 1, 3, 5, k_area, areas_.nominal, areas_.yellow_delta, grad, hess);
            t.area += triangle_area<6>(rest_, disp, 0, 2, 4, k_area, areas_.nominal, areas_.red_delta, grad, hess);
        }
        return t;
    }

    // The same from absolute corners x (any frame).
    Terms terms(const Corners& x, Corners* grad = nullptr, Hessian* hess = nullptr) const {
        return terms_of_displacement(Corners(x - rest_), grad, hess);
    }

    double energy_of_displacement(const Corners& disp, Corners* grad, Hessian* hess = nullptr) const {
        return terms_of_displacement(disp, grad, hess).total();
    }
    double energy(const Corners& x, Corners* grad, Hessian* hess = nullptr) const {
        return terms(x, grad, hess).total();
    }

    // energy_of_displacement() with gradient on kLanes particles at once, their displacements in
    // structure-of-arrays layout (x[c][l]: coordinate c = x0, y0, ..., y5 of particle l), so that a vector unit evaluates one term
    // for kLanes particles per instruction (network_simd.cpp). Every operation mirrors terms()
    // in kind and order (no fused multiply-add there), so the sums are equal to the last bit:
    // tests/test_relaxation_engine.py checks it.
    template <int kLanes>
    void energy_lanes(const double (&x)[12][kLanes], double (&g)[12][kLanes], double (&e)[kLanes]) const {
        double triangles[kLanes] = {}, connecting[kLanes] = {}, area[kLanes] = {};
        for (int c = 0; c < 12; ++c)
            for (int l = 0; l < kLanes; ++l) g[c][l] = 0.0;
        for (int i = 0; i < kSprings; ++i) {
            const bool triangle = i < 6;
            const double stiffness = triangle ? k : kc, nominal = triangle ? 1.0 : side_nominal_;
            const double delta = triangle ? (i % 2 == 0 ? eps : -eps) : side_delta_;
            const int a = kFrom[i], b = kTo[i];
            const double d0x = edge0_[i].x(), d0y = edge0_[i].y(), length0 = length0_[i];
            const double offset = length0 - nominal;
            double* sum = triangle ? triangles : connecting;
            for (int l = 0; l < kLanes; ++l) {
                const double ddx = x[2 * b][l] - x[2 * a][l], ddy = x[2 * b + 1][l] - x[2 * a + 1][l];
                const double dx = d0x + ddx, dy = d0y + ddy;
                const double length = std::sqrt(dx * dx + dy * dy);
                const double inverse = length > 0 ? 1.0 / length : 0.0;
                const double stretch = length_change(d0x, d0y, ddx, ddy, length, inverse, length0) + offset - delta;
                const double ux = dx * inverse, uy = dy * inverse;
                const double f = stiffness * stretch;
                g[2 * b][l] += f * ux, g[2 * b + 1][l] += f * uy;
                g[2 * a][l] -= f * ux, g[2 * a + 1][l] -= f * uy;
                sum[l] += 0.5 * stiffness * stretch * stretch;
            }
        }
        if (k_area != 0) {
            const int corners[2][3] = {{1, 3, 5}, {0, 2, 4}};
            const double area_delta[2] = {areas_.yellow_delta, areas_.red_delta};
            const Corners& ref = rest_;
            for (int t = 0; t < 2; ++t) {
                const int* idx = corners[t];
                const double scale = k_area / (areas_.nominal + area_delta[t]);
                const double ab0x = ref[2 * idx[1]] - ref[2 * idx[0]], ab0y = ref[2 * idx[1] + 1] - ref[2 * idx[0] + 1];
                const double ac0x = ref[2 * idx[2]] - ref[2 * idx[0]], ac0y = ref[2 * idx[2] + 1] - ref[2 * idx[0] + 1];
                const double offset = 0.5 * (ab0x * ac0y - ab0y * ac0x) - areas_.nominal;
                for (int l = 0; l < kLanes; ++l) {
                    const double dabx = x[2 * idx[1]][l] - x[2 * idx[0]][l], daby = x[2 * idx[1] + 1][l] - x[2 * idx[0] + 1][l];
                    const double dacx = x[2 * idx[2]][l] - x[2 * idx[0]][l], dacy = x[2 * idx[2] + 1][l] - x[2 * idx[0] + 1][l];
                    const double excess = offset - area_delta[t] +
                                          0.5 * ((ab0x * dacy - ab0y * dacx) + (dabx * ac0y - daby * ac0x) +
                                                 (dabx * dacy - daby * dacx));
                    const double force = scale * excess;
                    for (int m = 0; m < 3; ++m) {
                        const int q = idx[(m + 1) % 3], r = idx[(m + 2) % 3];
                        const double rqx = (ref[2 * q] - ref[2 * r]) + (x[2 * q][l] - x[2 * r][l]);
                        const double rqy = (ref[2 * q + 1] - ref[2 * r + 1]) + (x[2 * q + 1][l] - x[2 * r + 1][l]);
                        g[2 * idx[m]][l] += force * (0.5 * rqy);
                        g[2 * idx[m] + 1][l] += force * (-0.5 * rqx);
                    }
                    area[l] += 0.5 * scale * excess * excess;
                }
            }
        }
        for (int l = 0; l < kLanes; ++l) e[l] = triangles[l] + connecting[l] + area[l];
    }

   private:
    // Rest lengths and areas as nominal (eps = 0) value + delta, and the reference shape's
    // corners, spring edges and lengths: computed once per model.
    double side_nominal_ = 0, side_delta_ = 0;
    TriangleRestAreas areas_;
    Corners rest_ = Corners::Zero();
    Eigen::Vector2d edge0_[kSprings];
    double length0_[kSprings] = {};
};

// Energy and gradient of a finite network of hexagons, eight particles per instruction where the
// processor has AVX-512 (network_simd.cpp; network.hpp calls it through
// vectorised_finite_energy). Returns false where it does not apply: the scalar loop then runs.
bool vectorised_finite_energy(const HexagonModel& model, const Topology& topology, const double* u, double* gradient,
                              double& total);
// Whether this processor runs it (AVX-512).
bool vectorised_evaluation_available();

}  // namespace pyfrustrate
