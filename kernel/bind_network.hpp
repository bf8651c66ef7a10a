// Network functions bound once per particle model (pybind11 dispatches on the model's type).
#pragma once

#include "bind_minimize.hpp"
#include "relax.hpp"

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/typing.h>

namespace pyfrustrate {

// The optional StiffnessCache of the relaxations. Typed `StiffnessCache | None` (a raw pointer
// defaulting to nullptr would be written `StiffnessCache = None` in the signature, which type
// checkers reject as an implicit Optional); anything else is a TypeError naming the parameter.
using OptionalCache = pybind11::typing::Optional<StiffnessCache>;

inline StiffnessCache* cache_pointer(const OptionalCache& cache) {
    if (cache.is_none()) return nullptr;
    if (!pybind11::isinstance<StiffnessCache>(cache))
        throw pybind11::type_error("cache must be a StiffnessCache or None, got " +
                                   std::string(pybind11::str(pybind11::type::of(cache).attr("__name__"))));
    return cache.cast<StiffnessCache*>();
}

// A NaN or inf argument would come back as a NaN energy, silently: refused, naming the argument.
template <class Vec>
void check_finite(const char* name, const Vec& v) {
    if (!v.allFinite()) throw std::invalid_argument(std::string(name) + " contains non-finite values");
}

template <class Model>
void check_state(const Network<Model>& net, const Vector& x) {
    if (x.size() != net.size())
        throw std::invalid_argument("x has " + std::to_string(x.size()) + " entries, the network has " +
                                    std::to_string(net.size()) + " degrees of freedom");
    if (!x.allFinite()) throw std::invalid_argument("x contains non-finite values");
}

// (energy, gradient) of the network at displacement u, for Python.
template <class Model>
pybind11::tuple energy_and_gradient(const Model& model, const Topology& t, const Vector& u, bool vectorised) {
    const Network<Model> net{model, t};
    Vector g;
    const double e = net.energy(u, &g, vectorised);
    return pybind11::make_tuple(e, g);
}

// The particle contract (network.hpp) as attributes of the bound model class, the same for every
// model: tiling, corner count, point group, rest shape, energy with gradient and Hessian of a
// displacement from it, the model without mismatch, the typical step.
template <class Model, class Class>
void bind_particle_contract(Class& cls) {
    namespace py = pybind11;
    cls.def_property_readonly_static("tiling", [](py::object) { return std::string(tiling_of(Model::kTiling).name); })
        .def_property_readonly_static("corner_count", [](py::object) { return Model::kCornerCount; })
        .def_property_readonly_static("point_group",
                                      [](py::object) { return Model::kPointGroup == PointGroup::C3 ? "C3" : "D3"; })
        .def_static("rest_corners", &Model::rest_corners,
                    "Corners (x0, y0, x1, ...) of the rest shape without mismatch, in the particle's own frame.")
        .def(
            "energy_of_displacement",
            [](const Model& model, const typename Model::Corners& disp) {
                check_finite("displacement", disp);
                typename Model::Corners g = Model::Corners::Zero();
                typename Model::Hessian h = Model::Hessian::Zero();
                const double e = model.energy_of_displacement(disp, &g, &h);
                return py::make_tuple(e, g, h);
            },
            py::arg("displacement"),
            "(energy, gradient, Hessian) of one particle whose corners are displaced by `displacement` from "
            "rest_corners().")
        .def("without_mismatch", &Model::without_mismatch)
        .def_property_readonly("step_scale", &Model::step_scale);
}

// Model::terms (energy by kind of term, gradient, Hessian of absolute corners) as `evaluate`,
// for models that sum springs and areas by kind.
template <class Model, class Class>
void bind_evaluate_terms(Class& cls, const char* doc) {
    namespace py = pybind11;
    cls.def(
        "evaluate",
        [](const Model& model, const typename Model::Corners& corners) {
            check_finite("corners", corners);
            typename Model::Corners g = Model::Corners::Zero();
            typename Model::Hessian h = Model::Hessian::Zero();
            const auto terms = model.terms(corners, &g, &h);
            py::dict d;
            d["triangles"] = terms.triangles;
            d["connecting"] = terms.connecting;
            d["area"] = terms.area;
            d["energy"] = terms.total();
            d["gradient"] = g;
            d["hessian"] = h;
            return d;
        },
        py::arg("corners"), doc);
}

// The relaxation policy's binding (bind_relax.hpp, included at the end of this file).
template <class Model>
void export_relax_policy(pybind11::module_& m);

template <class Model>
void export_network_functions(pybind11::module_& m) {
    export_relax_policy<Model>(m);
    namespace py = pybind11;
    m.def(
        "energy",
        [](const Model& model, const Topology& t, const Vector& x) {
            check_state(Network<Model>{model, t}, x);
            return energy_and_gradient(model, t, displacement_of(t, x), true);
        },
        py::arg("model"), py::arg("topology"), py::arg("x"),
        "Energy of the network at state x and its gradient (same layout as x).");
    m.def(
        "energy_of_displacement",
        [](const Model& model, const Topology& t, const Vector& u, bool vectorised) {
            check_state(Network<Model>{model, t}, u);
            return energy_and_gradient(model, t, u, vectorised);
        },
        py::arg("model"), py::arg("topology"), py::arg("u"), py::arg("vectorised") = true,
        "Energy and gradient at the displacement u = x - reference_state (exact to round-off of the forces); "
        "vectorised=False keeps to the scalar loop.");
    m.def(
        "hessian",
        [](const Model& model, const Topology& t, const Vector& u, bool exact) {
            const Network<Model> net{model, t};
            check_state(net, u);
            const HessianPattern pat = net.hessian_pattern({});
            const std::vector<double> values = net.hessian(u, pat, exact);
            std::vector<Eigen::Triplet<double>> entries;
            for (int j = 0; j < pat.n_free; ++j)
                for (int k = pat.column_start[j]; k < pat.column_start[j + 1]; ++k) {
                    entries.emplace_back(pat.row[k], j, values[k]);
                    if (pat.row[k] != j) entries.emplace_back(j, pat.row[k], values[k]);
                }
            Eigen::SparseMatrix<double> H(net.size(), net.size());
            H.setFromTriplets(entries.begin(), entries.end());
            return H;
        },
        py::arg("model"), py::arg("topology"), py::arg("u"), py::arg("exact") = true,
        "Hessian of the energy at displacement u (scipy sparse): exact (with the curvature of the period map) "
        "or its Gauss-Newton part.");
    m.def(
        "particle_energies",
        [](const Model& model, const Topology& t, const Vector& x) {
            const Network<Model> net{model, t};
            check_state(net, x);
            const Vector u = displacement_of(t, x);
            const PeriodMap map = net.period_map(u);
            Vector e(t.n_particles());
            for (int p = 0; p < t.n_particles(); ++p) e[p] = net.particle_energy(u, map, p);
            return e;
        },
        py::arg("model"), py::arg("topology"), py::arg("x"), "Deformation energy of each particle, shape (n_particles,).");
    m.def(
        "particle_corners",
        [](const Model& model, const Topology& t, const Vector& x) {
            const Network<Model> net{model, t};
            check_state(net, x);
            const Vector u = displacement_of(t, x);
            const PeriodMap map = net.period_map(u);
            Eigen::MatrixXd out(t.n_particles(), 2 * Model::kCornerCount);
            for (int p = 0; p < t.n_particles(); ++p) {
                auto c = net.local_corners(u, map, p);
                const Vec2 site = site_position(t.tiling(), t.sites[p]);
                for (int s = 0; s < Model::kCornerCount; ++s) c.template segment<2>(2 * s) += site;
                out.row(p) = c.transpose();
            }
            return out;
        },
        py::arg("model"), py::arg("topology"), py::arg("x"),
        "Corner positions seen by each particle, shape (n_particles, 2 * corners): x0, y0, x1, y1, ...");
    m.def(
        "relax_lbfgs",
        [](const Model& model, const Topology& t, const Vector& x0, double tol, int max_iter, int memory,
           const OptionalCache& cache_arg) {
            StiffnessCache* cache = cache_pointer(cache_arg);
            MinimizeResult r;
            {
                py::gil_scoped_release release;
                r = relax_lbfgs(model, t, x0, make_options(tol, max_iter, memory, model.step_scale()), cache);
            }
            return to_dict(r);
        },
        py::arg("model"), py::arg("topology"), py::arg("x0"), py::arg("tol"), py::arg("max_iter"), py::arg("memory") = 10,
        py::arg("cache") = py::none(),
        "NLopt L-BFGS from x0 until max |gradient| <= tol, finished by Newton steps if NLopt stops short; returns a "
        "dict (x, displacement, energy, converged, iterations, gradient_norm, status, newton_steps, ...).");
    m.def(
        "relax_newton",
        [](const Model& model, const Topology& t, double tol, int max_iter, const OptionalCache& cache_arg, bool exact,
           double switch_ratio) {
            StiffnessCache* cache = cache_pointer(cache_arg);
            MinimizeResult r;
            {
                py::gil_scoped_release release;
                MinimizeOptions o = make_options(tol, max_iter, 10, model.step_scale());
                o.newton_exact_from_start = exact;
                if (!(switch_ratio > 0 && switch_ratio <= 1)) throw std::invalid_argument("switch_ratio must lie in (0, 1]");
                o.newton_switch_ratio = switch_ratio;
                r = relax_newton(model, t, o, cache);
            }
            return to_dict(r);
        },
        py::arg("model"), py::arg("topology"), py::arg("tol"), py::arg("max_iter"), py::arg("cache") = py::none(),
        py::arg("exact") = false, py::arg("switch_ratio") = 0.9,
        "Newton steps from the linear solution until max |gradient| <= tol: reference stiffness while that is "
        "cheaper, then the exact Hessian (exact=True: from the start; switch_ratio: the slowest contraction of "
        "the force per reference step tolerated whatever the costs); returns a dict like relax_lbfgs.");
    m.def(
        "relax_linear",
        [](const Model& model, const Topology& t, const OptionalCache& cache_arg) {
            StiffnessCache* cache = cache_pointer(cache_arg);
            MinimizeResult r;
            {
                py::gil_scoped_release release;
                r = relax_linear(model, t, cache);
            }
            return to_dict(r);
        },
        py::arg("model"), py::arg("topology"), py::arg("cache") = py::none(),
        "Linearised solve about the bulk reference (sparse Cholesky), exact as eps -> 0.");
}

}  // namespace pyfrustrate

#include "bind_relax.hpp"
