// Bindings of the periodic box (box.hpp): the clusters of a set of occupied sites, the one
// cluster analysis pyfrustrate has (Python's montecarlo.analysis calls it).
#include "bind_sites.hpp"
#include "box.hpp"

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace py = pybind11;
using namespace pyfrustrate;

void export_box(py::module_& m) {
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
}
