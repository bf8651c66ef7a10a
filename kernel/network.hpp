// A network: a topology with one particle model on every site. Its energy is the sum of the
// particle energies of the corners each particle sees (main text Eq. 15 for the aggregate
// energy at fixed topology); the loop over particles and the period map are written once here
// for every particle model.
//
// Degrees of freedom: x = (corner 0 (x, y), corner 1 (x, y), ..., period-map parameters).
// The period map sends a corner of the cell to its image n:
//   fibre, straight:  r + n t
//   fibre, curved:    g^n(r) with g(r) = R(theta) (r - c) + c + t (a rigid motion about the
//                     cell's centroid c, so the fibre bends with constant curvature; theta is free)
//   bulk:             r + n1 t1 + n2 t2
#pragma once

#include "topology.hpp"

#include <Eigen/Sparse>
#include <cmath>

namespace pyfrustrate {

namespace detail {

inline Eigen::Matrix2d rotation(double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    Eigen::Matrix2d r;
    r << c, -s, s, c;
    return r;
}

// Position of image n of corner r, with the Jacobians d(pos)/dr (2x2) and d(pos)/dp (2 x np)
// with respect to the period parameters p.
struct ImagePoint {
    Eigen::Vector2d position;
    Eigen::Matrix2d d_corner;
    Eigen::Matrix<double, 2, Eigen::Dynamic> d_period;
};

inline ImagePoint image_point(const Topology& t, const Eigen::Vector2d& r, const LatticeVector& n,
                              const double* period) {
    ImagePoint out;
    const int np = t.n_period_parameters();
    out.d_period.setZero(2, np);
    out.d_corner.setIdentity();
    out.position = r;
    if (n[0] == 0 && n[1] == 0) return out;
    if (t.periodicity == Periodicity::Bulk) {
        out.position += n[0] * Eigen::Vector2d(period[0], period[1]) + n[1] * Eigen::Vector2d(period[2], period[3]);
        out.d_period.block<2, 2>(0, 0) = n[0] * Eigen::Matrix2d::Identity();
        out.d_period.block<2, 2>(0, 2) = n[1] * Eigen::Matrix2d::Identity();
        return out;
    }
    const Eigen::Vector2d tr(period[0], period[1]);
    if (!t.curved) {
        out.position += n[0] * tr;
        out.d_period.block<2, 2>(0, 0) = n[0] * Eigen::Matrix2d::Identity();
        return out;
    }
    // g(r) = R(theta) (r - c) + c + t about the pivot c, so g^n(r) = R(n theta)(r - c) + c + s_n
    // with s_n = sum_{m=0}^{n-1} R(m theta) t for n > 0 and s_n = -sum_{m=1}^{|n|} R(-m theta) t
    // for n < 0. The state holds bend = bend_scale * theta.
    const double theta = period[2] / t.bend_scale;
    const Eigen::Matrix2d quarter = rotation(M_PI / 2);  // dR(a)/da = R(a) * quarter
    const int steps = n[0];
    const Eigen::Matrix2d rn = rotation(steps * theta);
    out.d_corner = rn;
    out.position = rn * (r - t.pivot) + t.pivot;
    Eigen::Matrix2d d_shift = Eigen::Matrix2d::Zero();
    Eigen::Vector2d d_theta = steps * rn * quarter * (r - t.pivot);
    if (steps > 0) {
        for (int m = 0; m < steps; ++m) {
            const Eigen::Matrix2d rm = rotation(m * theta);
            out.position += rm * tr;
            d_shift += rm;
            d_theta += m * rm * quarter * tr;
        }
    } else {
        for (int m = 1; m <= -steps; ++m) {
            const Eigen::Matrix2d rm = rotation(-m * theta);
            out.position -= rm * tr;
            d_shift -= rm;
            d_theta += m * rm * quarter * tr;
        }
    }
    out.d_period.block<2, 2>(0, 0) = d_shift;
    out.d_period.col(2) = d_theta / t.bend_scale;
    return out;
}

}  // namespace detail

template <class Model>
struct Network {
    static constexpr int C = Model::kCornerCount;
    using Corners = typename Model::Corners;

    const Model& model;
    const Topology& topology;

    int size() const { return 2 * topology.n_corners() + topology.n_period_parameters(); }

    // Corner coordinates seen by particle p, and the image Jacobians.
    Corners gather(const Eigen::VectorXd& x, int p, detail::ImagePoint* jac = nullptr) const {
        const double* period = x.data() + 2 * topology.n_corners();
        Corners c;
        for (int s = 0; s < C; ++s) {
            const int id = topology.corner[p][s];
            const Eigen::Vector2d r = x.template segment<2>(2 * id);
            const auto& n = topology.image[p][s];
            if (n[0] == 0 && n[1] == 0 && !jac) {
                c.template segment<2>(2 * s) = r;
                continue;
            }
            detail::ImagePoint ip = detail::image_point(topology, r, n, period);
            c.template segment<2>(2 * s) = ip.position;
            if (jac) jac[s] = ip;
        }
        return c;
    }

    double particle_energy(const Eigen::VectorXd& x, int p) const {
        return model.energy(gather(x, p), nullptr);
    }

    // Total energy; adds dE/dx into `gradient` when given (resized and zeroed here).
    double energy(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const {
        const int nc = topology.n_corners();
        const bool periodic_images = topology.periodicity != Periodicity::None;
        if (gradient) gradient->setZero(size());
        double total = 0.0;
        detail::ImagePoint jac[C];
        Corners g;
        for (int p = 0; p < topology.n_particles(); ++p) {
            const Corners c = gather(x, p, periodic_images && gradient ? jac : nullptr);
            if (!gradient) {
                total += model.energy(c, nullptr);
                continue;
            }
            g.setZero();
            total += model.energy(c, &g);
            for (int s = 0; s < C; ++s) {
                const int id = topology.corner[p][s];
                const Eigen::Vector2d gs = g.template segment<2>(2 * s);
                if (!periodic_images) {
                    gradient->template segment<2>(2 * id) += gs;
                    continue;
                }
                gradient->template segment<2>(2 * id) += jac[s].d_corner.transpose() * gs;
                gradient->segment(2 * nc, topology.n_period_parameters()) += jac[s].d_period.transpose() * gs;
            }
        }
        return total;
    }

    // Sparse Hessian J^T H_p J of the particle energies, ignoring the curvature of the period
    // map (exact where the particle gradients vanish, as at the rest state of the eps = 0 model
    // used by the linear solve).
    Eigen::SparseMatrix<double> gauss_newton_hessian(const Eigen::VectorXd& x) const {
        const int nc = topology.n_corners(), np = topology.n_period_parameters();
        std::vector<Eigen::Triplet<double>> entries;
        entries.reserve(static_cast<size_t>(topology.n_particles()) * 4 * C * C);
        detail::ImagePoint jac[C];
        for (int p = 0; p < topology.n_particles(); ++p) {
            const Corners c = gather(x, p, jac);
            typename Model::Hessian h = Model::Hessian::Zero();
            model.energy(c, nullptr, &h);
            // Full Jacobian of this particle's corners: 2C rows, columns = its corners + period.
            Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2 * C, 2 * C + np);
            for (int s = 0; s < C; ++s) {
                J.block<2, 2>(2 * s, 2 * s) = jac[s].d_corner;
                if (np) J.block(2 * s, 2 * C, 2, np) = jac[s].d_period;
            }
            const Eigen::MatrixXd local = J.transpose() * h * J;
            auto global = [&](int a) { return a < 2 * C ? 2 * topology.corner[p][a / 2] + a % 2 : 2 * nc + (a - 2 * C); };
            for (int a = 0; a < 2 * C + np; ++a)
                for (int b = 0; b < 2 * C + np; ++b)
                    if (local(a, b) != 0.0) entries.emplace_back(global(a), global(b), local(a, b));
        }
        Eigen::SparseMatrix<double> H(size(), size());
        H.setFromTriplets(entries.begin(), entries.end());
        return H;
    }
};

}  // namespace pyfrustrate
