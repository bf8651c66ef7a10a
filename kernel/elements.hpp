// Elastic elements: stateless evaluators of one spring or one areal term. Each adds its energy
// to the return value and its gradient (and, on request, Hessian) into the caller's arrays of
// a particle's corner coordinates (corner c at entries 2c, 2c+1).
#pragma once

#include <Eigen/Dense>
#include <cmath>

namespace pyfrustrate {

template <int N>
using CornerArray = Eigen::Matrix<double, 2 * N, 1>;
template <int N>
using CornerMatrix = Eigen::Matrix<double, 2 * N, 2 * N>;

// Corners are given as reference + displacement (the particle's own frame: reference = the rest
// shape without mismatch, displacement small). Each term is formed from reference edges and
// displacement differences so that a deformation of 1e-8 keeps its digits; formed from positions
// of size 1 it would keep eight (tests/test_extremes.py relaxes eps = 1e-8 to tol 1e-12). The
// price: the scalar loop costs 111 instead of 65 ns per particle (network_simd.cpp hides it
// where AVX-512 is present).

// |d0 + dd| - |d0| for a reference edge d0 of length length0 and a small change dd, to full
// relative precision: length = fl(|d0 + dd|) is off by up to 1e-16 (d0 + dd and the root are
// rounded), which the Newton correction (q - (length^2 - length0^2)) / (2 length) removes, q =
// 2 d0.dd + dd.dd being exact to its own rounding. No division: inverse = 1 / length is shared
// with the force's direction.
inline double length_change(double d0x, double d0y, double ddx, double ddy, double length, double inverse,
                            double length0) {
    const double q = 2 * (d0x * ddx + d0y * ddy) + (ddx * ddx + ddy * ddy);
    const double change = length - length0;
    return change + 0.5 * (q - change * (length + length0)) * inverse;
}

// Harmonic spring between corners a and b: e = k/2 (|r_b - r_a| - L0)^2 with the rest length
// L0 = nominal + delta (nominal: the reference length, delta: what the mismatch adds), formed as
//   (|d0 + dd| - |d0|) + (|d0| - nominal) - delta
// for the reference edge d0 = ref_b - ref_a (of length length0, both computed once per model)
// and the displacement difference dd = disp_b - disp_a.
template <int N>
__attribute__((always_inline)) inline double spring(const CornerArray<N>& disp, int a, int b, const Eigen::Vector2d& d0, double length0, double k,
                     double nominal, double delta, CornerArray<N>* grad, CornerMatrix<N>* hess) {
    const Eigen::Vector2d dd = disp.template segment<2>(2 * b) - disp.template segment<2>(2 * a);
    const Eigen::Vector2d d = d0 + dd;
    const double length = std::sqrt(d.x() * d.x() + d.y() * d.y());
    // A spring of zero length has no direction; its force is then taken as zero. One reciprocal,
    // not two divisions: HexagonModel::energy_lanes does the same, to the bit.
    const double inverse = length > 0 ? 1.0 / length : 0.0;
    const double stretch =
        length_change(d0.x(), d0.y(), dd.x(), dd.y(), length, inverse, length0) + (length0 - nominal) - delta;
    if (grad || hess) {
        const Eigen::Vector2d u = d * inverse;
        if (grad) {
            const Eigen::Vector2d f = k * stretch * u;
            grad->template segment<2>(2 * b) += f;
            grad->template segment<2>(2 * a) -= f;
        }
        if (hess) {
            const Eigen::Matrix2d uu = u * u.transpose();
            const double tension = stretch * inverse;
            const Eigen::Matrix2d h = k * (uu + tension * (Eigen::Matrix2d::Identity() - uu));
            hess->template block<2, 2>(2 * a, 2 * a) += h;
            hess->template block<2, 2>(2 * b, 2 * b) += h;
            hess->template block<2, 2>(2 * a, 2 * b) -= h;
            hess->template block<2, 2>(2 * b, 2 * a) -= h;
        }
    }
    return 0.5 * k * stretch * stretch;
}

// Areal term of the triangle (a, b, c), counter-clockwise at rest (main text, after Eq. 1):
// e = k_area (A - A0)^2 / (2 A0), with A the signed area, so that inversion is penalised;
// A0 = nominal + delta (nominal: the reference triangle's area). A - A0 is formed as
//   A(ref) - nominal - delta + [cross(ab0, dac) + cross(dab, ac0) + cross(dab, dac)] / 2.
template <int N>
inline double triangle_area(const CornerArray<N>& ref, const CornerArray<N>& disp, int a, int b, int c, double k_area,
                            double nominal, double delta, CornerArray<N>* grad, CornerMatrix<N>* hess) {
    const int idx[3] = {a, b, c};
    auto cross = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q) { return p.x() * q.y() - p.y() * q.x(); };
    auto edge = [&](const CornerArray<N>& v, int from, int to) -> Eigen::Vector2d {
        return v.template segment<2>(2 * to) - v.template segment<2>(2 * from);
    };
    const Eigen::Vector2d ab0 = edge(ref, a, b), ac0 = edge(ref, a, c), dab = edge(disp, a, b), dac = edge(disp, a, c);
    const double rest_area = nominal + delta;
    const double excess =
        (0.5 * cross(ab0, ac0) - nominal) - delta + 0.5 * (cross(ab0, dac) + cross(dab, ac0) + cross(dab, dac));
    const double scale = k_area / rest_area;
    if (grad || hess) {
        Eigen::Matrix<double, 6, 1> dA;  // dA/d(xa, ya, xb, yb, xc, yc) = (y_b - y_c, x_c - x_b, ...) / 2
        for (int m = 0; m < 3; ++m) {
            const Eigen::Vector2d rq = edge(ref, idx[(m + 2) % 3], idx[(m + 1) % 3]) +
                                       edge(disp, idx[(m + 2) % 3], idx[(m + 1) % 3]);  // r_q - r_r
            dA(2 * m) = 0.5 * rq.y();
            dA(2 * m + 1) = -0.5 * rq.x();
        }
        if (grad)
            for (int m = 0; m < 3; ++m) grad->template segment<2>(2 * idx[m]) += scale * excess * dA.segment<2>(2 * m);
        if (hess) {
            for (int m = 0; m < 3; ++m)
                for (int n = 0; n < 3; ++n)
                    hess->template block<2, 2>(2 * idx[m], 2 * idx[n]) +=
                        scale * dA.segment<2>(2 * m) * dA.segment<2>(2 * n).transpose();
            // Second derivatives of the area: d2A/dx_m dy_{m+1} = 1/2, d2A/dx_m dy_{m+2} = -1/2.
            for (int m = 0; m < 3; ++m) {
                const int p = idx[m], q = idx[(m + 1) % 3], r = idx[(m + 2) % 3];
                (*hess)(2 * p, 2 * q + 1) += 0.5 * scale * excess;
                (*hess)(2 * q + 1, 2 * p) += 0.5 * scale * excess;
                (*hess)(2 * p, 2 * r + 1) -= 0.5 * scale * excess;
                (*hess)(2 * r + 1, 2 * p) -= 0.5 * scale * excess;
            }
        }
    }
    return 0.5 * scale * excess * excess;
}

}  // namespace pyfrustrate
