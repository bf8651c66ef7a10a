// The compiled kernel of pyfrustrate. Each piece exports itself; this file only calls them.
#include <pybind11/pybind11.h>

namespace py = pybind11;

void export_montecarlo_common(py::module_& m);
void export_chain(py::module_& m);
void export_topology(py::module_& m);
void export_hexagon(py::module_& m);
void export_random_hexagon(py::module_& m);
void export_triangle(py::module_& m);

PYBIND11_MODULE(_kernel, m) {
    m.doc() = "pyfrustrate's C++ kernel (Eigen, NLopt, CHOLMOD): energies, gradients, Hessians, L-BFGS, Newton and linear solves";
    export_montecarlo_common(m);
    export_chain(m);
    export_topology(m);
    export_hexagon(m);
    export_random_hexagon(m);
    export_triangle(m);
    // SHA-256 of the kernel's sources and compiler (CMakeLists.txt): results record it.
    m.attr("build_hash") = PYFRUSTRATE_KERNEL_HASH;
}
