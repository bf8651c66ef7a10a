#include "network.hpp"
#include "relax.hpp"
#include "topology.hpp"
#include "shape_key.hpp"
#include "bind_sites.hpp"

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

namespace py = pybind11;
using namespace pyfrustrate;

namespace {

PointGroup point_group_named(const std::string& name) {
    if (name == "C3") return PointGroup::C3;
    if (name == "D3") return PointGroup::D3;
    throw std::invalid_argument("point_group must be 'C3' or 'D3', got '" + name + "'");
}

}  // namespace

void export_topology(py::module_& m) {
    m.def(
        "tiling",
        [](const std::string& name) {
            const Tiling& t = tiling_named(name);
            py::dict d;
            d["name"] = std::string(t.name);
            d["sublattices"] = t.sublattices;
            d["corners"] = t.corners;
            d["coordination"] = t.neighbours;
            d["bulk_bonds_per_particle"] = t.bulk_bonds_per_particle();
            py::list neighbours, offsets, frames, centres;
            for (int sub = 0; sub < t.sublattices; ++sub) {
                py::list nb, off;
                for (int k = 0; k < t.neighbours; ++k) {
                    const NeighbourSlot& n = t.neighbour[sub][k];
                    nb.append(py::make_tuple(n.di, n.dj, n.sublattice));
                }
                const Topology single = make_topology(t, {Site{0, 0, sub}}, Periodicity::None, {}, false);
                for (int k = 0; k < t.corners; ++k) off.append(single.slot_offset[sub][k]);
                neighbours.append(nb);
                offsets.append(off);
                frames.append(frame_matrix(t, sub));
                centres.append(cartesian3(t.site_offset3[sub]));
            }
            d["neighbours"] = neighbours;
            d["slot_offsets"] = offsets;
            d["frames"] = frames;
            d["site_offsets"] = centres;
            return d;
        },
        py::arg("name"),
        "Facts of a tiling (kernel/tiling.hpp): sublattices, corners per particle, coordination number, bonds per "
        "bulk particle, each sublattice's neighbours (di, dj, sublattice), corner offsets from the site centre, "
        "frame (rotation of the particle's rest shape) and site-centre offset within its cell.");
    m.def(
        "site_positions",
        [](const std::string& tiling, const SiteArray& sites) {
            const Tiling& t = tiling_named(tiling);
            const std::vector<Site> s = sites_from_array(t, sites);
            Eigen::MatrixXd out(s.size(), 2);
            for (std::size_t k = 0; k < s.size(); ++k) out.row(k) = site_position(t, s[k]).transpose();
            return out;
        },
        py::arg("tiling"), py::arg("sites"), "Cartesian centres (n, 2) of sites of a tiling.");
    m.def(
        "transform_sites",
        [](const std::string& tiling, int op, const SiteArray& sites) {
            const Tiling& t = tiling_named(tiling);
            std::vector<Site> s = sites_from_array(t, sites);
            for (auto& site : s) site = transform_site(t, op, site);
            return sites_to_array(t, s);
        },
        py::arg("tiling"), py::arg("op"), py::arg("sites"),
        "Sites sent by the lattice's point operation op (0-5: rotation by 60 op degrees; 6-11: the mirror x -> -x, "
        "then the rotation by 60 (op - 6) degrees) about the origin.");
    m.def(
        "point_group_operations", [](const std::string& name) { return point_group_operations(point_group_named(name)); },
        py::arg("point_group"), "The lattice point operations of a particle's point group ('C3' or 'D3'), in its own frame.");
    m.def("point_operation_matrix", &point_operation_matrix, py::arg("op"), "The point operation op on Cartesian vectors.");
    m.def(
        "shape_symmetries",
        [](const std::string& tiling, const std::string& point_group) {
            return shape_symmetries(tiling_named(tiling), point_group_named(point_group));
        },
        py::arg("tiling"), py::arg("point_group"),
        "Lattice operations under which cluster shapes of a particle with this point group share their energy.");
    m.def(
        "shape_key",
        [](const SiteArray& sites, const std::string& tiling, const std::string& point_group) {
            const Tiling& t = tiling_named(tiling);
            std::vector<Site> canonical;
            const ShapeKey key =
                finite_shape_key(t, shape_symmetries(t, point_group_named(point_group)), sites_from_array(t, sites), &canonical);
            return py::make_tuple(py::tuple(py::cast(key)), sites_to_array(t, canonical));
        },
        py::arg("sites"), py::arg("tiling") = "hexagon", py::arg("point_group") = "D3",
        "Canonical key of a finite cluster up to translations and the shape symmetries (tuple of ints) and its "
        "canonical sites.");
    py::class_<Topology>(m, "Topology",
                         "Corner graph of a set of occupied sites of a tiling "
                         "(finite, fibre-periodic or bulk-periodic).")
        .def(py::init([](const std::string& tiling, py::array_t<int, py::array::c_style | py::array::forcecast> sites,
                         int periodicity, const std::array<LatticeVector, 2>& periods, bool curved) {
                 const Tiling& t = tiling_named(tiling);
                 const std::vector<Site> s = sites_from_array(t, sites);
                 if (periodicity < 0 || periodicity > 2)
                     throw std::invalid_argument("periodicity must be 0 (none), 1 (fibre) or 2 (bulk)");
                 return make_topology(t, s, static_cast<Periodicity>(periodicity), periods, curved);
             }),
             py::arg("tiling"), py::arg("sites"), py::arg("periodicity"), py::arg("periods"), py::arg("curved"))
        .def_property_readonly("tiling", [](const Topology& t) { return std::string(t.tiling().name); })
        .def_property_readonly("periodicity", [](const Topology& t) { return static_cast<int>(t.periodicity); })
        .def_readonly("curved", &Topology::curved)
        .def_readonly("periods", &Topology::periods)
        .def_property_readonly("n_particles", &Topology::n_particles)
        .def_property_readonly("n_corners", &Topology::n_corners)
        .def_property_readonly("n_period_parameters", &Topology::n_period_parameters)
        .def_readonly("n_bonds", &Topology::n_bonds)
        .def_property_readonly("sites",
                               [](const Topology& t) { return sites_to_array(t.tiling(), t.sites); },
                               "(n_particles, 2) cells (i, j), or (n_particles, 3) (i, j, sublattice) for a tiling "
                               "with several sublattices")
        .def_property_readonly("corners",
                               [](const Topology& t) {
                                   const int nc = t.tiling().corners;
                                   py::array_t<int> a({t.n_particles(), nc});
                                   auto w = a.mutable_unchecked<2>();
                                   for (int p = 0; p < t.n_particles(); ++p)
                                       for (int s = 0; s < nc; ++s) w(p, s) = t.corner[p][s];
                                   return a;
                               },
                               "(n_particles, corners) corner index of each slot (the tiling's slot order)")
        .def_property_readonly("images",
                               [](const Topology& t) {
                                   const int nc = t.tiling().corners;
                                   py::array_t<int> a({t.n_particles(), nc, 2});
                                   auto w = a.mutable_unchecked<3>();
                                   for (int p = 0; p < t.n_particles(); ++p)
                                       for (int s = 0; s < nc; ++s)
                                           w(p, s, 0) = t.image[p][s][0], w(p, s, 1) = t.image[p][s][1];
                                   return a;
                               },
                               "(n_particles, corners, 2) period image of each slot")
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
                if (!state.allFinite()) throw std::invalid_argument("state contains non-finite values");
                if (!points.allFinite()) throw std::invalid_argument("points contain non-finite values");
                const Eigen::VectorXd period_displacement =
                    state.tail(t.n_period_parameters()) - t.reference_period_parameters();
                const PeriodMap map(t, period_displacement.data(), std::max(std::abs(n1), std::abs(n2)));
                const LatticeVector n{n1, n2};
                const Vec2 reference_shift = n1 * cell_position(t.periods[0]) + n2 * cell_position(t.periods[1]);
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
