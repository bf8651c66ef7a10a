#include "minimize.hpp"

#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pyfrustrate {
namespace {

struct CallbackState {
    const Objective* objective;
    const MinimizeOptions* options;
    Vector x, gradient;
    Vector best_x;
    double best_energy = std::numeric_limits<double>::infinity();
    double best_gradient_norm = std::numeric_limits<double>::infinity();
    int evaluations = 0;
    bool reached_tolerance = false;
    bool non_finite = false;
    bool stopped = false;
    // NLopt's L-BFGS (Luksan) ends a run by itself once its gradient falls below an internal
    // absolute threshold near 1e-8. A run that starts there (a restart close to the minimum)
    // sees the objective scaled up so that only our criterion decides; the first run is not
    // scaled, since its first step is as long as the scaled gradient and a long step can
    // escape from a merely local minimum (k_area < 0 makes the energy unbounded below).
    double scale = 1.0;
};

double nlopt_callback(unsigned n, const double* x, double* grad, void* data) {
    auto& s = *static_cast<CallbackState*>(data);
    // NLopt may call again after a forced stop before it notices: those calls change nothing.
    if (s.stopped) throw nlopt::forced_stop();
    s.x = s.options->step_scale * Eigen::Map<const Vector>(x, n);
    const double energy = (*s.objective)(s.x, s.gradient);
    ++s.evaluations;
    if (!std::isfinite(energy) || !s.gradient.allFinite()) {
        s.non_finite = s.stopped = true;
        throw nlopt::forced_stop();
    }
    if (grad) Eigen::Map<Vector>(grad, n) = (s.scale * s.options->step_scale) * s.gradient;
    const double gnorm = s.gradient.size() ? s.gradient.cwiseAbs().maxCoeff() : 0.0;
    if (energy <= s.best_energy || gnorm <= s.options->gradient_tolerance) {
        s.best_energy = energy;
        s.best_x = s.x;
        s.best_gradient_norm = gnorm;
    }
    if (gnorm <= s.options->gradient_tolerance) s.reached_tolerance = s.stopped = true;
    if (s.evaluations >= s.options->max_iterations) s.stopped = true;
    if (s.stopped) throw nlopt::forced_stop();
    return s.scale * energy;
}

const char* describe(nlopt::result r) {
    switch (r) {
        case nlopt::SUCCESS: return "success";
        case nlopt::STOPVAL_REACHED: return "stopval reached";
        case nlopt::FTOL_REACHED: return "ftol reached";
        case nlopt::XTOL_REACHED: return "xtol reached";
        case nlopt::MAXEVAL_REACHED: return "maxeval reached";
        case nlopt::MAXTIME_REACHED: return "maxtime reached";
        case nlopt::ROUNDOFF_LIMITED: return "roundoff limited";
        case nlopt::FORCED_STOP: return "forced stop";
        default: return "failure";
    }
}

}  // namespace

MinimizeResult minimize_lbfgs(const Objective& objective, const Vector& x0,
                              const MinimizeOptions& options) {
    if (!(options.gradient_tolerance > 0)) throw std::invalid_argument("tol must be positive");
    if (options.max_iterations < 1) throw std::invalid_argument("max_iter must be at least 1");
    if (!x0.allFinite()) throw std::invalid_argument("x0 contains non-finite values");
    if (!(options.step_scale > 0)) throw std::invalid_argument("step_scale must be positive");

    CallbackState state;
    state.objective = &objective;
    state.options = &options;
    state.gradient.resize(x0.size());
    state.best_x = x0;
    std::string status = "not started";

    Vector x = x0;
    for (int run = 0; run <= options.restarts; ++run) {
        if (run > 0 && std::isfinite(state.best_gradient_norm) && state.best_gradient_norm > 0)
            state.scale = std::max(1.0, 1e-4 / (options.step_scale * state.best_gradient_norm));
        nlopt::opt opt(nlopt::LD_LBFGS, static_cast<unsigned>(x.size()));
        opt.set_min_objective(nlopt_callback, &state);
        opt.set_vector_storage(static_cast<unsigned>(options.memory));
        // Tolerances are explicit: only the gradient criterion (enforced in the callback) or
        // NLopt's own roundoff detection ends a run.
        opt.set_ftol_rel(0.0);
        opt.set_ftol_abs(0.0);
        opt.set_xtol_rel(0.0);
        opt.set_maxeval(std::max(1, options.max_iterations - state.evaluations));
        const Vector y = x / options.step_scale;
        std::vector<double> xv(y.data(), y.data() + y.size());
        double fmin = 0;
        nlopt::result r;
        try {
            r = opt.optimize(xv, fmin);
        } catch (const nlopt::roundoff_limited&) {
            r = nlopt::ROUNDOFF_LIMITED;
        } catch (const nlopt::forced_stop&) {
            r = nlopt::FORCED_STOP;
        } catch (const std::runtime_error&) {
            r = nlopt::FAILURE;
        }
        status = describe(r);
        if (state.non_finite) {
            status = "non-finite energy or gradient";
            break;
        }
        if (state.reached_tolerance || state.evaluations >= options.max_iterations) break;
        x = state.best_x;  // restart with a fresh history from the best point found
    }

    MinimizeResult result;
    result.x = state.best_x;
    result.energy = state.best_energy;
    result.iterations = state.evaluations;
    result.gradient_norm = state.best_gradient_norm;
    result.converged = state.reached_tolerance;
    if (!state.reached_tolerance && state.evaluations >= options.max_iterations)
        status = "maximum number of iterations reached";
    result.status = state.reached_tolerance ? "gradient tolerance reached" : status;
    return result;
}

}  // namespace pyfrustrate
