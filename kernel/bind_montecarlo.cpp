// Bindings shared by every model's Monte Carlo class (bind_montecarlo.hpp): the clusters of a
// set of occupied sites in the periodic box (box.hpp), the one cluster analysis pyfrustrate has
// (Python's montecarlo.analysis calls it), and MonteCarloState, a chain's state as a value.
#include "bind_montecarlo.hpp"
#include "bind_sites.hpp"
#include "box.hpp"

#include <pybind11/numpy.h>
#include <sstream>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace py = pybind11;
using namespace pyfrustrate;

void export_montecarlo_common(py::module_& m) {
    m.def("monte_carlo_option_fields", &option_fields,
          "The Monte Carlo options' table (kernel/montecarlo/options.hpp), one dict per field in order: name, kind "
          "('flag', 'real', 'integer', 'method'), scope ('run': a run's options, pyfrustrate's MonteCarloOptions; "
          "'particle': set from the particle; 'benchmark': baselines), default, range (as errors say it), doc.");
    m.def(
        "check_monte_carlo_options", [](const py::kwargs& options) { return options_dict(options_from_keywords(options)); },
        "Every option, the given keywords read and checked against the table (ValueError naming a field out of its "
        "range, TypeError a keyword that is no field), the others at their defaults: the one check of the options.");
    m.def(
        "box_clusters",
        [](const std::string& tiling_name, int L, const SiteArray& sites) {
            const Tiling& tiling = tiling_named(tiling_name);
            const Box box(tiling, L);
            const std::vector<Site> given = sites_from_array(tiling, sites);
            std::vector<int> occupant(box.n_sites(), -1);
            for (std::size_t p = 0; p < given.size(); ++p) {
                const int s = box.index(given[p]);
                if (occupant[s] >= 0)
                    throw std::invalid_argument("sites: site (" + std::to_string(given[p][0]) + ", " +
                                                std::to_string(given[p][1]) + ") is occupied twice (modulo the box)");
                occupant[s] = static_cast<int>(p);
            }
            ClusterWorkspace ws;
            ws.resize(box.n_sites());
            ws.new_round();
            std::vector<Cluster> found;
            for (const Site& site : given) {
                const int s = box.index(site);
                if (!ws.seen(s)) found.push_back(find_cluster(box, occupant, s, ws));
            }
            std::stable_sort(found.begin(), found.end(), [](const Cluster& a, const Cluster& b) { return a.size() > b.size(); });
            py::list out;
            for (const Cluster& cl : found) out.append(py::make_tuple(sites_to_array(tiling, cl.unwrapped), cl.rank()));
            return out;
        },
        py::arg("tiling"), py::arg("box"), py::arg("sites"),
        "Connected clusters of the occupied sites (edge neighbours of the tiling) in the periodic box of box x box "
        "cells, largest first: (unwrapped sites, rank) pairs, rank 0 finite, 1 wrapping one way, 2 both ways "
        "(box.hpp, the search the Monte Carlo uses).");
    py::class_<BoundState>(m, "MonteCarloState",
                           "A Monte Carlo chain's state, a value (kernel/montecarlo/state.hpp): the particles' sites, "
                           "the std::mt19937_64 generator, the running deformation energy, the warm-start store of "
                           "relaxed displacements and the counters. Read from a chain (MonteCarlo.state), passed "
                           "into one (MonteCarlo(..., state=)).")
        .def(py::init([](const std::string& tiling_name, int L, const SiteArray& particles, const std::string& rng_state,
                         double deformation, const py::dict& counters, py::array_t<double, py::array::c_style | py::array::forcecast> displacement,
                         py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast> known) {
                 const Tiling& tiling = tiling_named(tiling_name);
                 const Box box(tiling, L);
                 BoundState b{ChainState{}, &tiling, L};
                 for (const Site& s : sites_from_array(tiling, particles)) b.state.particles.push_back(box.index(s));
                 std::istringstream in(rng_state);
                 in >> b.state.rng;
                 if (in.fail()) throw std::invalid_argument("rng_state: not a std::mt19937_64 state");
                 if (!std::isfinite(deformation)) throw std::invalid_argument("deformation must be finite");
                 b.state.deformation = deformation;
                 for_each_counter(b.state, [&](const std::string& name, std::int64_t& v, const char*) {
                     v = counters.contains(name.c_str()) ? counters[name.c_str()].cast<std::int64_t>() : 0;
                 });
                 if ((known.size() == 0) != (displacement.size() == 0) || (known.size() > 0 && displacement.size() % known.size() != 0))
                     throw std::invalid_argument("displacement and known must describe the same sites");
                 b.state.displacement.assign(displacement.data(), displacement.data() + displacement.size());
                 b.state.known.assign(known.data(), known.data() + known.size());
                 return b;
             }),
             py::arg("tiling"), py::arg("box"), py::arg("particles"), py::arg("rng_state"), py::arg("deformation"),
             py::arg("counters"), py::arg("displacement"), py::arg("known"),
             "A state from its parts (as the properties give them); the chain it is passed to counts the bonds and "
             "labels the clusters again.")
        .def_property_readonly("tiling", [](const BoundState& b) { return std::string(b.tiling->name); })
        .def_property_readonly("box", [](const BoundState& b) { return b.L; })
        .def_property_readonly(
            "particles",
            [](const BoundState& b) {
                const Box box(*b.tiling, b.L);
                std::vector<Site> sites;
                for (const int s : b.state.particles) sites.push_back(box.coords(s));
                return sites_to_array(*b.tiling, sites);
            },
            "Sites of the particles, in particle order, as MonteCarlo.particles.")
        .def_property_readonly("rng_state",
                               [](const BoundState& b) {
                                   std::ostringstream out;
                                   out << b.state.rng;
                                   return out.str();
                               },
                               "The std::mt19937_64 as its stream representation.")
        .def_property_readonly("deformation", [](const BoundState& b) { return b.state.deformation; })
        .def_property_readonly("counters", [](BoundState& b) { return counters_dict(b.state); })
        .def_property_readonly("displacement",
                               [](const BoundState& b) {
                                   return py::array_t<double>(static_cast<py::ssize_t>(b.state.displacement.size()),
                                                              b.state.displacement.data());
                               },
                               "Relaxed corner displacements of every site (warm starts; one record per site, a wrapping cluster's strain kept apart), empty without them.")
        .def_property_readonly("known",
                               [](const BoundState& b) {
                                   return py::array_t<std::uint8_t>(static_cast<py::ssize_t>(b.state.known.size()),
                                                                    reinterpret_cast<const std::uint8_t*>(b.state.known.data()));
                               },
                               "Whether each site's displacement is known (1) or not (0).")
        .def("__copy__", [](const BoundState& b) { return b; })
        .def("__deepcopy__", [](const BoundState& b, const py::dict&) { return b; }, py::arg("memo"));
}
