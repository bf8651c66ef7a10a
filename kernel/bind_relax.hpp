// pf.relax's entry into the kernel: the one relaxation policy (relax_policy.hpp), and the
// relaxed cluster a relaxation hands on to the clusters made from it (parent_factor.hpp).
#pragma once

#include "bind_network.hpp"
#include "relax_policy.hpp"

#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/typing.h>

namespace pyfrustrate {

inline void export_relaxed_cluster(pybind11::module_& m) {
    namespace py = pybind11;
    if (py::detail::get_type_info(typeid(RelaxedCluster))) return;  // bound by the first model already
    py::class_<RelaxedCluster, std::shared_ptr<RelaxedCluster>>(
        m, "RelaxedCluster",
        "A relaxed finite aggregate with its Hessian factor, ready to serve the aggregates made from it by adding "
        "or removing a few particles (relax(..., parent=...)).")
        .def_property_readonly("modifications", [](const RelaxedCluster& c) { return c.modifications; },
                               "Particles added or removed since the factor was last made from scratch.")
        .def_property_readonly("factor_nonzeros", [](const RelaxedCluster& c) { return c.factor->nonzeros(); },
                               "Nonzeros of the factor L.")
        .def_property_readonly("fresh_nonzeros", [](const RelaxedCluster& c) { return c.fresh_nonzeros; },
                               "Nonzeros of L when it was last made from scratch.");
    m.def(
        "_sparse_ldl_solve",
        [](int n, const std::vector<int>& column_start, const std::vector<int>& row, const std::vector<double>& values,
           const std::vector<int>& node_of, const Vector& rhs) -> py::tuple {
            if (rhs.size() != n) throw std::invalid_argument("rhs must have n entries");
            if (values.size() != row.size()) throw std::invalid_argument("values must have one entry per row index");
            auto analysis = std::make_shared<CholeskyAnalysis>(n, column_start, row, /*own_ldl=*/true,
                                                               node_of.empty() ? nullptr : &node_of);
            CholeskyFactor factor(analysis);
            const py::object x = factor.factorize(values) ? py::cast(Vector(factor.solve(rhs))) : py::none();
            return py::make_tuple(x, analysis->own_ldl(), analysis->cholmod_analysed(), analysis->paired_rows());
        },
        py::arg("n"), py::arg("column_start"), py::arg("row"), py::arg("values"), py::arg("node_of"), py::arg("rhs"),
        "Testing hook: the solution of A x = rhs by the kernel's sparse LDL^T (A: upper triangle in compressed "
        "columns; node_of: a node per column, empty for CHOLMOD's ordering), None if A is not positive definite; "
        "with whether the own LDL^T ran, whether CHOLMOD analysed, and how many pairs of rows it factorised "
        "together.");
    m.def("rigid_pieces", &rigid_pieces, py::arg("topology"),
          "How many rigidly joined pieces (particles sharing a side) a finite topology falls into; 1 for a "
          "periodic cell.");
}

template <class Model>
void export_relax_policy(pybind11::module_& m) {
    namespace py = pybind11;
    export_relaxed_cluster(m);
    m.def(
        "relax",
        [](const Model& model, const Topology& t, const std::string& method, double tol, int max_iter, int memory,
           const pybind11::typing::Optional<Vector>& start_arg, bool lbfgs_from_linear, const OptionalCache& cache_arg,
           const pybind11::typing::Optional<RelaxedCluster>& parent_arg, bool keep_factor) {
            RelaxRequest request;
            if (method == "auto") request.method = RelaxMethod::Auto;
            else if (method == "newton") request.method = RelaxMethod::Newton;
            else if (method == "lbfgs") request.method = RelaxMethod::Lbfgs;
            else if (method == "linear") request.method = RelaxMethod::Linear;
            else throw std::invalid_argument("method must be 'auto', 'newton', 'lbfgs' or 'linear', got '" + method + "'");
            request.minimize = make_options(tol, max_iter, memory, model.step_scale());
            Vector start;
            if (!start_arg.is_none()) {
                start = start_arg.cast<Vector>();
                const Network<Model> net{model, t};
                if (start.size() != net.size())
                    throw std::invalid_argument("start has " + std::to_string(start.size()) + " entries, the network has " +
                                                std::to_string(net.size()) + " degrees of freedom");
                if (!start.allFinite()) throw std::invalid_argument("start contains non-finite values");
                request.start = &start;
            }
            std::shared_ptr<RelaxedCluster> parent;
            if (!parent_arg.is_none()) {
                if (!py::isinstance<RelaxedCluster>(parent_arg))
                    throw py::type_error("parent must be a RelaxedCluster or None");
                parent = parent_arg.cast<std::shared_ptr<RelaxedCluster>>();
                request.parent = parent.get();
            }
            request.lbfgs_from_linear = lbfgs_from_linear;
            request.keep_factor = keep_factor;
            request.rigid_pieces = rigid_pieces(t);
            if (request.rigid_pieces > 1 &&
                (request.method == RelaxMethod::Newton || request.method == RelaxMethod::Linear))
                throw std::invalid_argument(
                    "topology: it falls into " + std::to_string(request.rigid_pieces) + " pieces joined by no side, which "
                    "method='" + method + "' cannot pin (each moves rigidly on its own): use method='lbfgs' or 'auto', "
                    "or relax each piece");
            StiffnessCache* cache = cache_pointer(cache_arg);
            RelaxCounters counters;
            RelaxExtras extras;
            MinimizeResult r;
            {
                py::gil_scoped_release release;
                r = relax_by_policy(model, t, request, counters, cache, &extras);
            }
            py::dict d = to_dict(r);
            static const char* names[] = {"linear", "lbfgs", "newton", "auto"};
            d["method"] = std::string(names[static_cast<int>(extras.method)]);
            d["factor"] = extras.factor ? py::cast(extras.factor) : py::none();
            d["from_parent"] = extras.parent.from_parent;
            d["chord_steps"] = extras.parent.chord_steps;
            d["refactorizations"] = extras.parent.refactorizations;
            d["fresh_reason"] = extras.parent.fresh_reason;
            return d;
        },
        py::arg("model"), py::arg("topology"), py::arg("method"), py::arg("tol"), py::arg("max_iter"),
        py::arg("memory") = 10, py::arg("start") = py::none(), py::arg("lbfgs_from_linear") = false,
        py::arg("cache") = py::none(), py::arg("parent") = py::none(), py::arg("keep_factor") = false,
        "The one relaxation policy (relax_policy.hpp): method 'auto' (Newton, or L-BFGS given a start or a topology "
        "in several pieces), 'newton', 'lbfgs' or 'linear'; start: a displacement to start from; parent: the "
        "RelaxedCluster this topology differs from by a few particles (its factor is modified, not remade); "
        "keep_factor: return this relaxation's RelaxedCluster as 'factor'. Returns a dict like relax_lbfgs with "
        "'method', 'factor', 'from_parent', 'chord_steps', 'refactorizations', 'fresh_reason'.");
}

}  // namespace pyfrustrate
