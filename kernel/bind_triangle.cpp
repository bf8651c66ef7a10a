#include "bind_montecarlo.hpp"
#include "bind_network.hpp"
#include "triangle.hpp"

namespace py = pybind11;
using namespace pyfrustrate;

void export_triangle(py::module_& m) {
    py::class_<TriangleModel> cls(m, "TriangleModel",
                                  "Triangular particle (supplement Fig. S6, reconstructed): yellow and red node "
                                  "triangles of springs k with rest sides 1 +- eps at each vertex, six coupling "
                                  "springs kc, areal stiffness k_area on each triangle.");
    cls.def(py::init<double, double, double, double>(), py::arg("k"), py::arg("kc"), py::arg("k_area"), py::arg("eps"))
        .def_readonly("k", &TriangleModel::k)
        .def_readonly("kc", &TriangleModel::kc)
        .def_readonly("k_area", &TriangleModel::k_area)
        .def_readonly("eps", &TriangleModel::eps);
    bind_evaluate_terms<TriangleModel>(cls, "Energy terms, gradient (12,) and Hessian (12, 12) of one particle from its nodes (x0, y0, ..., x5, y5): "
            "yellow at v0, v1, v2, then red at v0, v1, v2.");
    cls.def_property_readonly_static(
        "springs",
        [](py::object) {
            py::list out;
            for (int i = 0; i < TriangleModel::kSprings; ++i)
                out.append(py::make_tuple(TriangleModel::kFrom[i], TriangleModel::kTo[i],
                                          i < 3 ? "yellow" : i < 6 ? "red" : "coupling"));
            return out;
        },
        "The twelve springs as (slot, slot, kind), kind 'yellow', 'red' or 'coupling' (for drawing).");
    bind_particle_contract<TriangleModel>(cls);
    export_network_functions<TriangleModel>(m);
    export_montecarlo<TriangleModel>(m, "MonteCarloTriangle");
}
