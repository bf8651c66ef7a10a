#include "bind_montecarlo.hpp"
#include "bind_network.hpp"
#include "hexagon.hpp"

namespace py = pybind11;
using namespace pyfrustrate;

void export_hexagon(py::module_& m) {
    py::class_<HexagonModel> cls(m, "HexagonModel",
                             "Hexagonal particle (main text Fig. 2a): yellow/red triangles of springs k with rest "
                             "sides 1 +- eps, six connecting springs kc, areal stiffness k_area on each triangle.");
    cls
        .def(py::init<double, double, double, double>(), py::arg("k"), py::arg("kc"), py::arg("k_area"), py::arg("eps"))
        .def_readonly("k", &HexagonModel::k)
        .def_readonly("kc", &HexagonModel::kc)
        .def_readonly("k_area", &HexagonModel::k_area)
        .def_readonly("eps", &HexagonModel::eps);
    bind_evaluate_terms<HexagonModel>(cls, "Energy terms, gradient (12,) and Hessian (12, 12) of one particle from its corners "
            "(x0, y0, ..., x5, y5), slots at 30, 90, ..., 330 degrees, even slots red.");
    bind_particle_contract<HexagonModel>(cls);
    export_network_functions<HexagonModel>(m);
    export_montecarlo<HexagonModel>(m, "MonteCarloHexagon");
    m.def("vectorised_evaluation_available", &vectorised_evaluation_available,
          "Whether finite networks of hexagons are evaluated eight particles at a time (AVX-512 present).");
}
