// The compiled kernel of pyfrustrate. Each piece exports itself; this file calls them and sets the
// heap top pad (below).
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace py = pybind11;

namespace {

// Every relaxation of a new cluster allocates and frees its factorisation's storage (CHOLMOD's
// supernodal factor, the analysis, Eigen's vectors): megabytes for a cluster of a few hundred
// particles. glibc hands the top of its heap back to the system after each such free and takes
// it again, zeroed page by page, at the next: a fifth of a validation sample's time went to page
// faults and memset (perf, a 600-particle fibre). A top pad of 16 MiB keeps that memory in the
// heap (benchmarks/bench_allocator.py measures the gain against glibc's default, alternately).
// PYFRUSTRATE_MALLOC_TOP_PAD (bytes) sets another pad; 0 leaves glibc's default untouched.
constexpr long kDefaultTopPad = 16L << 20;

long set_allocator_top_pad() {
#if defined(__GLIBC__)
    long pad = kDefaultTopPad;
    if (const char* text = std::getenv("PYFRUSTRATE_MALLOC_TOP_PAD")) {
        char* end = nullptr;
        const long value = std::strtol(text, &end, 10);
        if (end == text || *end != '\0' || value < 0)
            throw std::invalid_argument(std::string("PYFRUSTRATE_MALLOC_TOP_PAD: expected a number of bytes >= 0, got '") +
                                        text + "'");
        pad = std::min(value, 1L << 30);  // mallopt takes an int
    }
    if (pad > 0 && mallopt(M_TOP_PAD, static_cast<int>(pad)) == 1) return pad;
#endif
    return 0;
}

}  // namespace

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
    // The heap's top pad set at import (bytes; 0: the C library's default), above.
    m.attr("allocator_top_pad") = set_allocator_top_pad();
    // SHA-256 of the kernel's sources and compiler (CMakeLists.txt): results record it.
    m.attr("build_hash") = PYFRUSTRATE_KERNEL_HASH;
}
