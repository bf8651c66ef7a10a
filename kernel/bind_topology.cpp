#include "network.hpp"
#include "relax.hpp"
#include "topology.hpp"

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;
using namespace pyfrustrate;

void export_topology(py::module_& m) {
    py::class_<Topology>(m, "Topology",
                         "Corner graph of a set of occupied sites of the triangular particle lattice "
                         "(finite, fibre-periodic or bulk-periodic).")
        .def(py::init([](py::array_t<int, py::array::c_style | py::array::forcecast> sites, int periodicity,
                         const std::array<LatticeVector, 2>& periods, bool curved) {
                 if (sites.ndim() != 2 || sites.shape(1) != 2)
                     throw std::invalid_argument("sites must be an integer array of shape (n, 2)");
                 if (periodicity < 0 || periodicity > 2)
                     throw std::invalid_argument("periodicity must be 0 (none), 1 (fibre) or 2 (bulk)");
                 std::vector<LatticeVector> s(sites.shape(0));
                 auto r = sites.unchecked<2>();
                 for (py::ssize_t i = 0; i < sites.shape(0); ++i) s[i] = {r(i, 0), r(i, 1)};
                 return make_topology(s, static_cast<Periodicity>(periodicity), periods, curved);
             }),
             py::arg("sites"), py::arg("periodicity"), py::arg("periods"), py::arg("curved"))
        .def_property_readonly("periodicity", [](const Topology& t) { return static_cast<int>(t.periodicity); })
        .def_readonly("curved", &Topology::curved)
        .def_readonly("periods", &Topology::periods)
        .def_property_readonly("n_particles", &Topology::n_particles)
        .def_property_readonly("n_corners", &Topology::n_corners)
        .def_property_readonly("n_period_parameters", &Topology::n_period_parameters)
        .def_readonly("n_bonds", &Topology::n_bonds)
        .def_property_readonly("sites",
                               [](const Topology& t) {
                                   py::array_t<int> a({t.n_particles(), 2});
                                   auto w = a.mutable_unchecked<2>();
                                   for (int p = 0; p < t.n_particles(); ++p) w(p, 0) = t.sites[p][0], w(p, 1) = t.sites[p][1];
                                   return a;
                               })
        .def_property_readonly("corners",
                               [](const Topology& t) {
                                   py::array_t<int> a({t.n_particles(), kCorners});
                                   auto w = a.mutable_unchecked<2>();
                                   for (int p = 0; p < t.n_particles(); ++p)
                                       for (int s = 0; s < kCorners; ++s) w(p, s) = t.corner[p][s];
                                   return a;
                               },
                               "(n_particles, 6) corner index of each slot (30, 90, ..., 330 degrees)")
        .def_property_readonly("images",
                               [](const Topology& t) {
                                   py::array_t<int> a({t.n_particles(), kCorners, 2});
                                   auto w = a.mutable_unchecked<3>();
                                   for (int p = 0; p < t.n_particles(); ++p)
                                       for (int s = 0; s < kCorners; ++s)
                                           w(p, s, 0) = t.image[p][s][0], w(p, s, 1) = t.image[p][s][1];
                                   return a;
                               },
                               "(n_particles, 6, 2) period image of each slot")
        .def_property_readonly("reference",
                               [](const Topology& t) {
                                   Eigen::MatrixXd r(t.n_corners(), 2);
                                   for (int c = 0; c < t.n_corners(); ++c) r.row(c) = t.reference[c].transpose();
                                   return r;
                               },
                               "(n_corners, 2) bulk-reference positions")
        .def_readonly("corner_color", &Topology::corner_color)
        .def_property_readonly("pivot", [](const Topology& t) { return Eigen::Vector2d(t.pivot); },
                               "curved fibre: the point its images turn about")
        .def_readonly("bend_scale", &Topology::bend_scale,
                      "curved fibre: the state's bend parameter is bend_scale * (angle between images)")
        .def(
            "image_points",
            [](const Topology& t, const Eigen::VectorXd& state, const Eigen::MatrixXd& points, int n1, int n2) {
                const int expected = 2 * t.n_corners() + t.n_period_parameters();
                if (state.size() != expected)
                    throw std::invalid_argument("state has " + std::to_string(state.size()) + " entries, expected " +
                                                std::to_string(expected));
                if (points.cols() != 2) throw std::invalid_argument("points must have shape (m, 2)");
                const Eigen::VectorXd period_displacement =
                    state.tail(t.n_period_parameters()) - t.reference_period_parameters();
                const PeriodMap map(t, period_displacement.data(), std::max(std::abs(n1), std::abs(n2)));
                const LatticeVector n{n1, n2};
                const Vec2 reference_shift = n1 * site_position(t.periods[0]) + n2 * site_position(t.periods[1]);
                Eigen::MatrixXd out(points.rows(), 2);
                for (Eigen::Index k = 0; k < points.rows(); ++k) {
                    const Vec2 r = points.row(k).transpose();
                    out.row(k) = (r + reference_shift + map.displacement(n, r, Vec2::Zero())).transpose();
                }
                return out;
            },
            py::arg("state"), py::arg("points"), py::arg("n1"), py::arg("n2") = 0,
            "Points (m, 2) sent by the period map of the relaxed state to image (n1, n2): the same map the "
            "energy uses (kernel/network.hpp).")
        .def("reference_state", &Topology::reference_state,
             "Flat reference state: corners (x0, y0, x1, ...) then period-map parameters.");

    py::class_<StiffnessCache>(m, "StiffnessCache",
                               "What every solve on one topology reuses: the Hessian's sparsity pattern, CHOLMOD's "
                               "symbolic analysis, and the factorised eps = 0 stiffness of the last particle "
                               "stiffness it served (refactorised, numerically only, when that changes).")
        .def(py::init<const Topology&>(), py::arg("topology"), py::keep_alive<1, 2>())
        .def_property_readonly("reference_factorizations", &StiffnessCache::reference_factorizations,
                               "How many times the reference stiffness was factorised.")
        .def_property_readonly("factor_nonzeros", [](const StiffnessCache& c) { return c.analysis() ? c.analysis()->factor_nonzeros() : -1L; },
                               "Nonzeros of the Cholesky factor (-1 before the first solve).")
        .def_property_readonly("supernodal", [](const StiffnessCache& c) { return c.analysis() && c.analysis()->supernodal(); },
                               "Whether CHOLMOD chose its supernodal factorisation.");
}
