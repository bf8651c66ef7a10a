#include "bind_montecarlo.hpp"
#include "bind_network.hpp"
#include "random_hexagon.hpp"

namespace py = pybind11;
using namespace pyfrustrate;

void export_random_hexagon(py::module_& m) {
    py::class_<RandomHexagonModel> cls(m, "RandomHexagonModel",
                                   "Random-elasticity hexagon (main text Eq. 14): e = 1/2 (d - d0)^T M (d - d0) over "
                                   "nine corner distances (yellow sides, red sides, alternate hexagon sides).");
    cls
        .def(py::init<const RandomHexagonModel::Matrix9&, double>(), py::arg("M"), py::arg("eps"))
        .def_readonly("M", &RandomHexagonModel::M)
        .def_readonly("eps", &RandomHexagonModel::eps)
        .def_property_readonly_static("distance_pairs",
                                      [](py::object) {
                                          py::list out;
                                          for (const auto& p : RandomHexagonModel::kPairs) out.append(py::make_tuple(p[0], p[1]));
                                          return out;
                                      })
        .def("rest_distances", &RandomHexagonModel::rest_distances)
        .def(
            "evaluate",
            [](const RandomHexagonModel& model, const RandomHexagonModel::Corners& corners) {
                check_finite("corners", corners);
                RandomHexagonModel::Corners g = RandomHexagonModel::Corners::Zero();
                RandomHexagonModel::Hessian h = RandomHexagonModel::Hessian::Zero();
                const double e = model.energy(corners, &g, &h);
                py::dict d;
                d["energy"] = e;
                d["distances"] = model.distances(corners);
                d["gradient"] = g;
                d["hessian"] = h;
                return d;
            },
            py::arg("corners"),
            "Energy, the nine distances, gradient (12,) and Hessian (12, 12) of one particle from its corners "
            "(x0, y0, ..., x5, y5), slots at 30, 90, ..., 330 degrees, even slots red.");
    bind_particle_contract<RandomHexagonModel>(cls);
    export_network_functions<RandomHexagonModel>(m);
    export_montecarlo<RandomHexagonModel>(m, "MonteCarloRandomHexagon");
}
