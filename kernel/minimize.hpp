// L-BFGS minimisation through NLopt, and the result record shared by every minimiser.
// The minimiser owns nothing of the system: it sees an objective (energy and gradient of a
// flat vector) and hands back a result value (x, energy, status, counters).
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <string>

namespace pyfrustrate {

using Vector = Eigen::VectorXd;

// Energy of x; writes the gradient into `gradient` (same size as x).
using Objective = std::function<double(const Vector& x, Vector& gradient)>;

struct MinimizeOptions {
    double gradient_tolerance = 1e-9;  // converged when max |dE/dx_i| <= this
    int max_iterations = 100000;       // cap on energy+gradient evaluations
    int memory = 10;                   // L-BFGS history length
    int restarts = 5;                  // fresh L-BFGS runs after a roundoff-limited stop
    // Typical displacement: NLopt works on x / step_scale. Its L-BFGS takes a first step of
    // unit length in its variables, which must be small on the scale of the problem (here the
    // mismatch eps): a long step can leave a merely local minimum.
    double step_scale = 1.0;
    // relax_lbfgs: finish with Newton steps when NLopt stops short of the tolerance.
    bool finish_with_newton = true;
    // relax_newton: exact Hessian from the first step (else the reference stiffness first).
    bool newton_exact_from_start = false;
    // relax_newton: steps with the reference stiffness go on while they are cheaper than exact
    // Newton (relax.hpp); one that divides the largest force by less than 1 / newton_switch_ratio
    // hands over to the exact Hessian whatever the costs.
    double newton_switch_ratio = 0.9;
    // relax_newton: largest displacement of a corner in one step (lattice units), a trust region.
    double newton_max_step = 0.25;
    // relax_newton: hand over to L-BFGS where damped Newton makes slow progress.
    bool newton_handover = true;
};

struct MinimizeResult {
    Vector x;
    double energy = 0.0;
    bool converged = false;
    int iterations = 0;       // energy+gradient evaluations
    double gradient_norm = 0; // max |dE/dx_i| at x
    std::string status;       // the minimisers' last word: which did the work and why it stopped
    // Set by the relaxations (relax.hpp): the displacement from the bulk reference (x holds
    // positions), Newton steps taken and exact Hessians factorised, L-BFGS's share of iterations.
    Vector displacement;
    int newton_steps = 0;
    int factorizations = 0;
    int lbfgs_evaluations = 0;
    bool handed_over = false;  // Newton gave the minimisation to L-BFGS (strongly nonlinear scene)
};

// NLopt's LD_LBFGS from x0; stops as soon as the gradient tolerance is met (NLopt itself has
// no gradient criterion, so the objective forces the stop), records NLopt's status instead of
// throwing on "roundoff limited", and restarts from the best point when it stops early.
MinimizeResult minimize_lbfgs(const Objective& objective, const Vector& x0,
                              const MinimizeOptions& options);

}  // namespace pyfrustrate
