// Conversion of minimiser results and options for the bindings.
#pragma once

#include "minimize.hpp"

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

namespace pyfrustrate {

inline pybind11::dict to_dict(const MinimizeResult& r) {
    pybind11::dict d;
    d["x"] = r.x;
    d["energy"] = r.energy;
    d["converged"] = r.converged;
    d["iterations"] = r.iterations;
    d["gradient_norm"] = r.gradient_norm;
    d["status"] = r.status;
    d["displacement"] = r.displacement;
    d["newton_steps"] = r.newton_steps;
    d["factorizations"] = r.factorizations;
    d["lbfgs_evaluations"] = r.lbfgs_evaluations;
    return d;
}

inline MinimizeOptions make_options(double tol, int max_iter, int memory, double step_scale) {
    MinimizeOptions o;
    o.gradient_tolerance = tol;
    o.max_iterations = max_iter;
    o.memory = memory;
    o.step_scale = step_scale;
    return o;
}

}  // namespace pyfrustrate
