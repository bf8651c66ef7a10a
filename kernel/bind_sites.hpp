// Site arrays between numpy and the kernel: (n, 2) cells (i, j) for a tiling with one
// sublattice, (n, 3) (i, j, sublattice) otherwise. One definition for every binding.
#pragma once

#include "tiling.hpp"

#include <pybind11/numpy.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace pyfrustrate {

using SiteArray = pybind11::array_t<int, pybind11::array::c_style | pybind11::array::forcecast>;

inline int site_columns(const Tiling& t) { return t.sublattices > 1 ? 3 : 2; }

inline std::vector<Site> sites_from_array(const Tiling& t, const SiteArray& sites) {
    const int columns = site_columns(t);
    if (sites.ndim() != 2 || sites.shape(1) != columns)
        throw std::invalid_argument(std::string("sites must be an integer array of shape (n, ") +
                                    std::to_string(columns) + ") for the " + t.name + " tiling" +
                                    (columns == 3 ? " (i, j, sublattice: 0 up, 1 down)" : " (i, j)"));
    std::vector<Site> out(sites.shape(0));
    auto r = sites.unchecked<2>();
    for (pybind11::ssize_t k = 0; k < sites.shape(0); ++k) {
        out[k] = {r(k, 0), r(k, 1), columns == 3 ? r(k, 2) : 0};
        if (out[k][2] < 0 || out[k][2] >= t.sublattices)
            throw std::invalid_argument("sites: sublattice must be 0 or 1, got " + std::to_string(out[k][2]));
    }
    return out;
}

inline pybind11::array_t<int> sites_to_array(const Tiling& t, const std::vector<Site>& sites) {
    const int columns = site_columns(t);
    pybind11::array_t<int> a({static_cast<pybind11::ssize_t>(sites.size()), static_cast<pybind11::ssize_t>(columns)});
    auto w = a.mutable_unchecked<2>();
    for (std::size_t p = 0; p < sites.size(); ++p)
        for (int c = 0; c < columns; ++c) w(p, c) = sites[p][c];
    return a;
}

}  // namespace pyfrustrate
