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

// Removes the rigid-body part of a displacement from the reference state: the mean
// translation of the corners, and a linearised rotation (of corners about their centroid and of
// the period vectors). Which rotation is "zero" must not depend on how a scene is written down:
// for a periodic cell it is the one that keeps the first period vector's direction (the fibre
// axis), for a finite aggregate the least-squares rotation about the centroid. A linearised
// rotation left in the state would be stretched by the nonlinear energy (angle squared).
inline void remove_rigid_motion(const Topology& t, Vector& displacement) {
    const int nc = t.n_corners();
    const Vector x_ref = t.reference_state();
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero(), shift = Eigen::Vector2d::Zero();
    for (int c = 0; c < nc; ++c) {
        centroid += t.reference[c];
        shift += displacement.segment<2>(2 * c);
    }
    centroid /= nc;
    shift /= nc;
    for (int c = 0; c < nc; ++c) displacement.segment<2>(2 * c) -= shift;

    auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); };
    double angle = 0;
    if (t.periodicity == Periodicity::None) {
        double moment = 0;
        for (int c = 0; c < nc; ++c) {
            const Eigen::Vector2d r = t.reference[c] - centroid;
            angle += cross(r, displacement.segment<2>(2 * c));
            moment += r.squaredNorm();
        }
        angle /= moment;
    } else {
        const Eigen::Vector2d axis = x_ref.segment<2>(2 * nc);
        angle = cross(axis, displacement.segment<2>(2 * nc)) / axis.squaredNorm();
    }
    for (int c = 0; c < nc; ++c) {
        const Eigen::Vector2d r = t.reference[c] - centroid;
        displacement.segment<2>(2 * c) -= angle * Eigen::Vector2d(-r.y(), r.x());
    }
    const int n_vectors = t.periodicity == Periodicity::Bulk ? 2 : (t.periodicity == Periodicity::Fiber ? 1 : 0);
    for (int v = 0; v < n_vectors; ++v) {
        const Eigen::Vector2d p = x_ref.segment<2>(2 * nc + 2 * v);
        displacement.segment<2>(2 * nc + 2 * v) -= angle * Eigen::Vector2d(-p.y(), p.x());
    }
}

// The stiffness of the linearised (eps -> 0) theory: the Hessian of the particles without
// mismatch at the bulk reference, positive semi-definite, with the three rigid-body degrees of
// freedom pinned. Factorised once; every solve after that is two triangular sweeps.
class ReferenceStiffness {
   public:
    template <class Model>
    ReferenceStiffness(const Model& model, const Topology& topology) : size_(0) {
        const Model rest_model = model.without_mismatch();
        const Network<Model> rest{rest_model, topology};
        size_ = rest.size();
        const Eigen::SparseMatrix<double> H = rest.gauss_newton_hessian(topology.reference_state());
        const std::vector<int> pins = rigid_body_pins(topology);
        free_index_.assign(size_, -1);
        int n_free = 0;
        for (int i = 0; i < size_; ++i)
            if (std::find(pins.begin(), pins.end(), i) == pins.end()) free_index_[i] = n_free++;
        std::vector<Eigen::Triplet<double>> entries;
        for (int col = 0; col < H.outerSize(); ++col)
            for (Eigen::SparseMatrix<double>::InnerIterator it(H, col); it; ++it)
                if (free_index_[it.row()] >= 0 && free_index_[it.col()] >= 0)
                    entries.emplace_back(free_index_[it.row()], free_index_[it.col()], it.value());
        Eigen::SparseMatrix<double> K(n_free, n_free);
        K.setFromTriplets(entries.begin(), entries.end());
        solver_.compute(K);
        const double pivot_floor =
            1e-13 * (solver_.info() == Eigen::Success ? solver_.vectorD().cwiseAbs().maxCoeff() : 0.0);
        if (solver_.info() != Eigen::Success || (solver_.vectorD().array() <= pivot_floor).any())
            throw std::runtime_error(
                "linear solve: the stiffness matrix is not positive definite (the topology has a floppy mode "
                "or the parameters make the network unstable); use method='lbfgs'");
    }

    // K^-1 r on the free degrees of freedom (pinned ones get 0).
    Vector solve(const Vector& residual) const {
        Vector rhs(solver_.rows());
        for (int i = 0; i < size_; ++i)
            if (free_index_[i] >= 0) rhs[free_index_[i]] = residual[i];
        const Vector step = solver_.solve(rhs);
        if (!step.allFinite()) throw std::runtime_error("linear solve: sparse Cholesky back-substitution failed");
        Vector out = Vector::Zero(size_);
        for (int i = 0; i < size_; ++i)
            if (free_index_[i] >= 0) out[i] = step[free_index_[i]];
        return out;
    }

   private:
    int size_;
    std::vector<int> free_index_;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
};

// Linear response about the bulk reference: one Newton step with the reference stiffness,
// driven by the mismatch forces at the reference. The pins choose one of the solutions that
// differ by a rigid motion; remove_rigid_motion picks the one without a linearised rotation.
// The energy reported is the full nonlinear energy of that state, an
// upper bound on the minimum that is exact to O(eps^4).
template <class Model>
Vector linear_response(const Model& model, const Topology& topology, const ReferenceStiffness& stiffness) {
    const Network<Model> net{model, topology};
    const Vector x_ref = topology.reference_state();
    Vector gradient;
    net.energy(x_ref, &gradient);
    Vector displacement = -stiffness.solve(gradient);
    remove_rigid_motion(topology, displacement);
    return x_ref + displacement;
}

template <class Model>
MinimizeResult relax_linear(const Model& model, const Topology& topology) {
    const Network<Model> net{model, topology};
    MinimizeResult result;
    result.x = linear_response(model, topology, ReferenceStiffness(model, topology));
    Vector gradient;
    result.energy = net.energy(result.x, &gradient);
    result.gradient_norm = gradient.size() ? gradient.cwiseAbs().maxCoeff() : 0.0;
    result.converged = std::isfinite(result.energy);
    result.iterations = 1;
    result.status = "linear solve";
    return result;
}

// The nonlinear minimum by Newton steps with the reference stiffness, factorised once:
// x <- x - K^-1 grad E(x) from the linear response, halving a step that raises the energy.
// Each step costs one energy and two triangular sweeps, and the contraction is fast wherever
// the linearised theory is good (small eps); where it is not (progress per step slower than
// `stall`), L-BFGS takes over from the best state with the remaining evaluations.
template <class Model>
MinimizeResult relax_newton(const Model& model, const Topology& topology, const MinimizeOptions& options) {
    const Network<Model> net{model, topology};
    const ReferenceStiffness stiffness(model, topology);
    constexpr double stall = 0.5;  // required reduction of the largest force per step
    Vector x = linear_response(model, topology, stiffness);
    Vector gradient;
    double energy = net.energy(x, &gradient);
    double gnorm = gradient.cwiseAbs().maxCoeff();
    int evaluations = 1;
    while (gnorm > options.gradient_tolerance && evaluations < options.max_iterations) {
        const Vector step = stiffness.solve(gradient);
        double length = 1.0;
        Vector trial, trial_gradient;
        double trial_energy = 0;
        for (int halving = 0; halving < 4; ++halving, length *= 0.5) {
            trial = x - length * step;
            trial_energy = net.energy(trial, &trial_gradient);
            ++evaluations;
            if (trial_energy <= energy) break;
        }
        const double trial_gnorm = trial_gradient.cwiseAbs().maxCoeff();
        if (!(trial_energy <= energy) || !(trial_gnorm < stall * gnorm)) {
            if (trial_energy <= energy) x = trial;  // keep the progress made, then hand over
            MinimizeOptions rest = options;
            rest.max_iterations = std::max(1, options.max_iterations - evaluations);
            MinimizeResult result = relax_lbfgs(model, topology, x, rest);
            result.iterations += evaluations;
            result.status = "newton stalled, then L-BFGS: " + result.status;
            return result;
        }
        x = trial;
        energy = trial_energy;
        gradient = trial_gradient;
        gnorm = trial_gnorm;
    }
    MinimizeResult result;
    result.x = x;
    result.energy = energy;
    result.gradient_norm = gnorm;
    result.iterations = evaluations;
    result.converged = gnorm <= options.gradient_tolerance;
    result.status = result.converged ? "gradient tolerance reached (newton)" : "maximum number of iterations reached";
    return result;
}

}  // namespace pyfrustrate
