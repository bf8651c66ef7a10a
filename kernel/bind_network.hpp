// Network functions bound once per particle model (pybind11 dispatches on the model's type).
#pragma once

#include "bind_minimize.hpp"
#include "relax.hpp"

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace pyfrustrate {

template <class Model>
void check_state(const Network<Model>& net, const Vector& x) {
    if (x.size() != net.size())
        throw std::invalid_argument("x has " + std::to_string(x.size()) + " entries, the network has " +
                                    std::to_string(net.size()) + " degrees of freedom");
    if (!x.allFinite()) throw std::invalid_argument("x contains non-finite values");
}

template <class Model>
void export_network_functions(pybind11::module_& m) {
    namespace py = pybind11;
    m.def(
        "energy",
        [](const Model& model, const Topology& t, const Vector& x) {
            const Network<Model> net{model, t};
            check_state(net, x);
            Vector g;
            const double e = net.energy(x, &g);
            return py::make_tuple(e, g);
        },
        py::arg("model"), py::arg("topology"), py::arg("x"),
        "Energy of the network at state x and its gradient (same layout as x).");
    m.def(
        "particle_energies",
        [](const Model& model, const Topology& t, const Vector& x) {
            const Network<Model> net{model, t};
            check_state(net, x);
            Vector e(t.n_particles());
            for (int p = 0; p < t.n_particles(); ++p) e[p] = net.particle_energy(x, p);
            return e;
        },
        py::arg("model"), py::arg("topology"), py::arg("x"), "Deformation energy of each particle, shape (n_particles,).");
    m.def(
        "particle_corners",
        [](const Model& model, const Topology& t, const Vector& x) {
            const Network<Model> net{model, t};
            check_state(net, x);
            Eigen::MatrixXd out(t.n_particles(), 2 * Model::kCornerCount);
            for (int p = 0; p < t.n_particles(); ++p) out.row(p) = net.gather(x, p).transpose();
            return out;
        },
        py::arg("model"), py::arg("topology"), py::arg("x"),
        "Corner positions seen by each particle, shape (n_particles, 2 * corners): x0, y0, x1, y1, ...");
    m.def(
        "relax_lbfgs",
        [](const Model& model, const Topology& t, const Vector& x0, double tol, int max_iter, int memory) {
            MinimizeResult r;
            {
                py::gil_scoped_release release;
                r = relax_lbfgs(model, t, x0, make_options(tol, max_iter, memory, model.step_scale()));
            }
            return to_dict(r);
        },
        py::arg("model"), py::arg("topology"), py::arg("x0"), py::arg("tol"), py::arg("max_iter"), py::arg("memory") = 10,
        "NLopt L-BFGS from x0 until max |gradient| <= tol; returns a dict (x, energy, converged, iterations, "
        "gradient_norm, status).");
    m.def(
        "relax_newton",
        [](const Model& model, const Topology& t, double tol, int max_iter) {
            MinimizeResult r;
            {
                py::gil_scoped_release release;
                r = relax_newton(model, t, make_options(tol, max_iter, 10, model.step_scale()));
            }
            return to_dict(r);
        },
        py::arg("model"), py::arg("topology"), py::arg("tol"), py::arg("max_iter"),
        "Newton steps with the factorised reference stiffness from the linear solution, until max |gradient| <= "
        "tol (L-BFGS takes over if they stall); returns a dict like relax_lbfgs.");
    m.def(
        "relax_linear",
        [](const Model& model, const Topology& t) {
            MinimizeResult r;
            {
                py::gil_scoped_release release;
                r = relax_linear(model, t);
            }
            return to_dict(r);
        },
        py::arg("model"), py::arg("topology"),
        "Linearised solve about the bulk reference (sparse LDL^T), exact as eps -> 0.");
}

}  // namespace pyfrustrate
