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

// Harmonic spring between corners a and b: e = k/2 (|r_b - r_a| - L0)^2.
template <int N>
inline double spring(const CornerArray<N>& x, int a, int b, double k, double rest, CornerArray<N>* grad,
                     CornerMatrix<N>* hess) {
    const Eigen::Vector2d d = x.template segment<2>(2 * b) - x.template segment<2>(2 * a);
    const double length = d.norm();
    const double stretch = length - rest;
    if (grad || hess) {
        // A spring of zero length has no direction; its force is then taken as zero. One
        // reciprocal, not two divisions: HexagonModel::energy_lanes does the same, to the bit.
        const double inverse = length > 0 ? 1.0 / length : 0.0;
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
// e = k_area (A - A0)^2 / (2 A0), with A the signed area, so that inversion is penalised.
template <int N>
inline double triangle_area(const CornerArray<N>& x, int a, int b, int c, double k_area, double rest_area,
                            CornerArray<N>* grad, CornerMatrix<N>* hess) {
    const int idx[3] = {a, b, c};
    // From edge vectors, not absolute coordinates: far from the origin the products of
    // coordinates would cancel to the area with a loss of digits that stalls the minimiser.
    const Eigen::Vector2d ab = x.template segment<2>(2 * b) - x.template segment<2>(2 * a);
    const Eigen::Vector2d ac = x.template segment<2>(2 * c) - x.template segment<2>(2 * a);
    const double area = 0.5 * (ab.x() * ac.y() - ab.y() * ac.x());
    Eigen::Matrix<double, 6, 1> dA;  // dA/d(xa, ya, xb, yb, xc, yc)
    for (int m = 0; m < 3; ++m) {
        const Eigen::Vector2d q = x.template segment<2>(2 * idx[(m + 1) % 3]);
        const Eigen::Vector2d r = x.template segment<2>(2 * idx[(m + 2) % 3]);
        dA(2 * m) = 0.5 * (q.y() - r.y());
        dA(2 * m + 1) = 0.5 * (r.x() - q.x());
    }
    const double excess = area - rest_area;
    const double scale = k_area / rest_area;
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
    return 0.5 * scale * excess * excess;
}

}  // namespace pyfrustrate
