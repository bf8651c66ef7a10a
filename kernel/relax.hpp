// Minimising a network's energy at fixed topology (main text Eq. 7, the inner minimisation):
// NLopt L-BFGS on the full nonlinear energy, or the linearised solve, exact as eps -> 0.
#pragma once

#include "minimize.hpp"
#include "network.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <string>
#include <stdexcept>

namespace pyfrustrate {

template <class Model>
MinimizeResult relax_lbfgs(const Model& model, const Topology& topology, const Vector& x0,
                           const MinimizeOptions& options) {
    const Network<Model> net{model, topology};
    if (x0.size() != net.size())
        throw std::invalid_argument("x0 has " + std::to_string(x0.size()) + " entries, the network has " +
                                    std::to_string(net.size()) + " degrees of freedom");
    const Objective objective = [&net](const Vector& x, Vector& g) { return net.energy(x, &g); };
    return minimize_lbfgs(objective, x0, options);
}

// Degrees of freedom held fixed to remove the three rigid-body zero modes (two translations
// and a rotation, which also turns the period vectors): corner 0, and the coordinate of the
// corner farthest from it that a rotation about corner 0 moves most.
inline std::vector<int> rigid_body_pins(const Topology& t) {
    int far = 0;
    double best = -1;
    for (int c = 1; c < t.n_corners(); ++c) {
        const double d = (t.reference[c] - t.reference[0]).squaredNorm();
        if (d > best) best = d, far = c;
    }
    const Eigen::Vector2d d = t.reference[far] - t.reference[0];
    return {0, 1, 2 * far + (std::abs(d.x()) >= std::abs(d.y()) ? 1 : 0)};
}

// The three rigid-body modes at the reference state, orthonormalised: translations of every
// corner, and the rotation about the corners' centroid, which also turns the period vectors
// (a curved fibre's bend is unchanged by a rotation of everything).
inline Eigen::MatrixXd rigid_body_modes(const Topology& t) {
    const int nc = t.n_corners();
    const Vector x_ref = t.reference_state();
    Eigen::MatrixXd P = Eigen::MatrixXd::Zero(x_ref.size(), 3);
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    for (int c = 0; c < nc; ++c) centroid += t.reference[c];
    centroid /= nc;
    for (int c = 0; c < nc; ++c) {
        P(2 * c, 0) = 1.0;
        P(2 * c + 1, 1) = 1.0;
        const Eigen::Vector2d r = t.reference[c] - centroid;
        P(2 * c, 2) = -r.y();
        P(2 * c + 1, 2) = r.x();
    }
    const int n_vectors = t.periodicity == Periodicity::Bulk ? 2 : (t.periodicity == Periodicity::Fiber ? 1 : 0);
    for (int v = 0; v < n_vectors; ++v) {
        const int i = 2 * nc + 2 * v;
        P(i, 2) = -x_ref[i + 1];
        P(i + 1, 2) = x_ref[i];
    }
    return Eigen::HouseholderQR<Eigen::MatrixXd>(P).householderQ() * Eigen::MatrixXd::Identity(x_ref.size(), 3);
}

// Linear response about the bulk reference: one Newton step whose stiffness matrix is that of
// the particles without mismatch (positive semi-definite, exact at eps -> 0), driven by the
// mismatch forces at the reference. The energy reported is the full nonlinear energy of the
// resulting state, an upper bound on the minimum that is exact to O(eps^4).
template <class Model>
MinimizeResult relax_linear(const Model& model, const Topology& topology) {
    const Network<Model> net{model, topology};
    const Model rest_model = model.without_mismatch();
    const Network<Model> rest{rest_model, topology};
    const Vector x_ref = topology.reference_state();
    Vector force;
    net.energy(x_ref, &force);
    force = -force;

    const Eigen::SparseMatrix<double> H = rest.gauss_newton_hessian(x_ref);
    std::vector<int> pins = rigid_body_pins(topology);
    std::vector<int> free_index(net.size(), -1);
    int n_free = 0;
    for (int i = 0; i < net.size(); ++i)
        if (std::find(pins.begin(), pins.end(), i) == pins.end()) free_index[i] = n_free++;
    std::vector<Eigen::Triplet<double>> entries;
    for (int col = 0; col < H.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator it(H, col); it; ++it)
            if (free_index[it.row()] >= 0 && free_index[it.col()] >= 0)
                entries.emplace_back(free_index[it.row()], free_index[it.col()], it.value());
    Eigen::SparseMatrix<double> K(n_free, n_free);
    K.setFromTriplets(entries.begin(), entries.end());
    Vector rhs(n_free);
    for (int i = 0; i < net.size(); ++i)
        if (free_index[i] >= 0) rhs[free_index[i]] = force[i];

    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(K);
    const double pivot_floor = 1e-13 * (solver.info() == Eigen::Success ? solver.vectorD().cwiseAbs().maxCoeff() : 0.0);
    if (solver.info() != Eigen::Success || (solver.vectorD().array() <= pivot_floor).any())
        throw std::runtime_error(
            "linear solve: the stiffness matrix is not positive definite (the topology has a floppy mode "
            "or the parameters make the network unstable); use method='lbfgs'");
    const Vector step = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !step.allFinite())
        throw std::runtime_error("linear solve: sparse Cholesky back-substitution failed");

    // The pins choose one of the solutions that differ by a rigid motion; the one orthogonal
    // to the rigid modes carries no linearised rotation, whose nonlinear energy (stretching
    // by the angle squared) would depend on the aggregate's orientation.
    Vector displacement = Vector::Zero(net.size());
    for (int i = 0; i < net.size(); ++i)
        if (free_index[i] >= 0) displacement[i] = step[free_index[i]];
    const Eigen::MatrixXd modes = rigid_body_modes(topology);
    displacement -= modes * (modes.transpose() * displacement);

    MinimizeResult result;
    result.x = x_ref + displacement;
    Vector gradient;
    result.energy = net.energy(result.x, &gradient);
    result.gradient_norm = gradient.size() ? gradient.cwiseAbs().maxCoeff() : 0.0;
    result.converged = std::isfinite(result.energy);
    result.iterations = 1;
    result.status = "linear solve";
    return result;
}

}  // namespace pyfrustrate
