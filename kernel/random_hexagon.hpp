// The random-elasticity particle (main text "Extension to random particles", Eq. 14): the same
// hexagon at rest and the same binding rules as HexagonModel, with deformation energy an
// arbitrary positive semi-definite quadratic form of nine corner distances,
//   e_d = 1/2 (d - d0)^T M (d - d0).
// d1..d3 are the yellow triangle's sides, d4..d6 the red triangle's, d7..d9 three alternate sides
// of the hexagon, one every 120 degrees (the reading under which the supplement's pseudo-modulus
// vectors make sense; docs/topics/corrections.md). Each triple is listed in the order a rotation by
// 120 degrees permutes it (slot s -> s + 2), the permutation of supplement S4.
// Nine distances fix the twelve corner coordinates up to a rigid motion.
#pragma once

#include "elements.hpp"
#include "hexagon.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pyfrustrate {

struct RandomHexagonModel {
    static constexpr TilingKind kTiling = TilingKind::Hexagon;
    static constexpr PointGroup kPointGroup = PointGroup::C3;  // M is not mirror-symmetric in general
    static constexpr int kCornerCount = 6;
    static constexpr int kDistances = 9;
    using Corners = CornerArray<6>;
    using Hessian = CornerMatrix<6>;
    using Matrix9 = Eigen::Matrix<double, 9, 9>;
    using Vector9 = Eigen::Matrix<double, 9, 1>;

    // Corner slots (topology.hpp: even slots red, odd yellow) joined by each distance.
    static constexpr int kPairs[9][2] = {{1, 3}, {3, 5}, {5, 1}, {0, 2}, {2, 4}, {4, 0}, {0, 1}, {2, 3}, {4, 5}};

    Matrix9 M;
    double eps = 0.01;

    RandomHexagonModel(const Matrix9& M_, double eps_) : M(M_), eps(eps_) {
        if (!M.allFinite()) throw std::invalid_argument("M must be finite");
        const double scale = M.cwiseAbs().maxCoeff();
        if (!(scale > 0)) throw std::invalid_argument("M must not vanish");
        if ((M - M.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale)
            throw std::invalid_argument("M must be symmetric");
        const double lowest = Eigen::SelfAdjointEigenSolver<Matrix9>(M, Eigen::EigenvaluesOnly).eigenvalues()(0);
        if (lowest < -1e-12 * scale)
            throw std::invalid_argument("M must be positive semi-definite (lowest eigenvalue " + std::to_string(lowest) +
                                        "): the particle's rest state would be unstable");
        if (!(eps >= 0 && eps < 1)) throw std::invalid_argument("eps must lie in [0, 1)");
        const Reference& r = reference();
        for (int i = 0; i < 9; ++i)
            mismatch_[i] = r.hexagon_side[i] ? HexagonModel::side_delta(eps) : eps * r.eps_coefficient[i];
    }

    double step_scale() const { return std::max(eps, 1e-3); }

    // The nine distances of the rest shape without mismatch (HexagonModel::rest_corners()): edges
    // and lengths computed once; rest distances as nominal + what eps adds (mismatch_: +eps, -eps,
    // or for the hexagon sides HexagonModel::side_delta).
    struct Reference {
        Eigen::Vector2d edge[9];
        double length[9], nominal[9], eps_coefficient[9];
        bool hexagon_side[9];
    };
    static const Reference& reference() {
        static const Reference r = [] {
            Reference out;
            const Corners rest = HexagonModel::rest_corners();
            for (int i = 0; i < 9; ++i) {
                out.edge[i] = rest.segment<2>(2 * kPairs[i][1]) - rest.segment<2>(2 * kPairs[i][0]);
                out.length[i] = out.edge[i].norm();
                out.hexagon_side[i] = i >= 6;
                out.nominal[i] = i >= 6 ? 1 / std::sqrt(3.0) : 1.0;
                out.eps_coefficient[i] = i < 3 ? 1.0 : (i < 6 ? -1.0 : 0.0);
            }
            return out;
        }();
        return r;
    }

    static Corners rest_corners() { return HexagonModel::rest_corners(); }
    RandomHexagonModel without_mismatch() const { return RandomHexagonModel(M, 0.0); }

    // d0: triangle sides 1 + eps (yellow) and 1 - eps (red); hexagon sides as in HexagonModel.
    Vector9 rest_distances() const {
        const double yellow = 1 + eps, red = 1 - eps;
        const double side = std::sqrt((yellow * yellow + red * red - yellow * red) / 3.0);
        Vector9 d0;
        d0 << yellow, yellow, yellow, red, red, red, side, side, side;
        return d0;
    }

    Vector9 distances(const Corners& x) const {
        Vector9 d;
        for (int i = 0; i < 9; ++i)
            d(i) = (x.segment<2>(2 * kPairs[i][1]) - x.segment<2>(2 * kPairs[i][0])).norm();
        return d;
    }

    // The energy from absolute corners x (any frame): the same hexagon at rest as HexagonModel.
    double energy(const Corners& x, Corners* grad, Hessian* hess = nullptr) const {
        return energy_of_displacement(Corners(x - HexagonModel::rest_corners()), grad, hess);
    }

    // The energy of the particle displaced by disp from HexagonModel::rest_corners() (its own
    // frame). Each distance's departure from its rest value is formed as in elements.hpp's
    // spring, from the reference edge and the displacement difference: exact at small eps.
    double energy_of_displacement(const Corners& disp, Corners* grad, Hessian* hess = nullptr) const {
        Vector9 stretch;
        Eigen::Vector2d unit[9];
        double length[9];
        const Reference& r = reference();
        for (int i = 0; i < 9; ++i) {
            const int a = kPairs[i][0], b = kPairs[i][1];
            const Eigen::Vector2d& d0 = r.edge[i];
            const Eigen::Vector2d dd = disp.segment<2>(2 * b) - disp.segment<2>(2 * a);
            const Eigen::Vector2d v = d0 + dd;
            length[i] = v.norm();
            // A distance of zero has no direction; its derivative is then taken as zero.
            const double inverse = length[i] > 0 ? 1.0 / length[i] : 0.0;
            unit[i] = v * inverse;
            stretch(i) = length_change(d0.x(), d0.y(), dd.x(), dd.y(), length[i], inverse, r.length[i]) +
                         (r.length[i] - r.nominal[i]) - mismatch_[i];
        }
        const Vector9 force = M * stretch;  // dE/dd
        if (grad)
            for (int i = 0; i < 9; ++i) {
                grad->segment<2>(2 * kPairs[i][1]) += force(i) * unit[i];
                grad->segment<2>(2 * kPairs[i][0]) -= force(i) * unit[i];
            }
        if (hess) {
            // J^T M J (J = dd/dx), plus the curvature of each distance weighted by its force.
            Eigen::Matrix<double, 9, 12> J = Eigen::Matrix<double, 9, 12>::Zero();
            for (int i = 0; i < 9; ++i) {
                J.block<1, 2>(i, 2 * kPairs[i][1]) = unit[i].transpose();
                J.block<1, 2>(i, 2 * kPairs[i][0]) = -unit[i].transpose();
            }
            *hess += J.transpose() * M * J;
            for (int i = 0; i < 9; ++i) {
                if (!(length[i] > 0)) continue;
                const Eigen::Matrix2d h =
                    force(i) / length[i] * (Eigen::Matrix2d::Identity() - unit[i] * unit[i].transpose());
                const int a = kPairs[i][0], b = kPairs[i][1];
                hess->block<2, 2>(2 * a, 2 * a) += h;
                hess->block<2, 2>(2 * b, 2 * b) += h;
                hess->block<2, 2>(2 * a, 2 * b) -= h;
                hess->block<2, 2>(2 * b, 2 * a) -= h;
            }
        }
        return 0.5 * stretch.dot(force);
    }

   private:
    // What eps adds to each rest distance (+-eps, or HexagonModel::side_delta for hexagon sides).
    double mismatch_[9] = {};
};

}  // namespace pyfrustrate
