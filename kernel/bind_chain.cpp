#include "bind_minimize.hpp"
#include "chain.hpp"

namespace py = pybind11;
using namespace pyfrustrate;

void export_chain(py::module_& m) {
    m.def(
        "chain_energy",
        [](int n, double k, double kc, double eps, const Vector& x) {
            ChainParameters p{n, k, kc, eps};
            p.validate();
            if (x.size() != 2 * (n + 1)) throw std::invalid_argument("x must have 2 (n + 1) entries");
            if (!x.allFinite()) throw std::invalid_argument("x contains non-finite values");
            Vector g;
            const double e = chain_energy(p, x, g);
            return py::make_tuple(e, g);
        },
        py::arg("n"), py::arg("k"), py::arg("kc"), py::arg("eps"), py::arg("x"),
        "Energy of main text Eq. (1) summed over n particles and its gradient; x = (x_up[0..n], x_down[0..n]).");
    m.def(
        "chain_relax",
        [](int n, double k, double kc, double eps, double tol, int max_iter) {
            const ChainParameters p{n, k, kc, eps};
            MinimizeResult r;
            {
                py::gil_scoped_release release;
                r = chain_relax(p, make_options(tol, max_iter, 10, eps));
            }
            return to_dict(r);
        },
        py::arg("n"), py::arg("k"), py::arg("kc"), py::arg("eps"), py::arg("tol"), py::arg("max_iter"),
        "L-BFGS relaxation of the 1D chain from the bulk reference; returns a dict (x, energy, converged, ...).");
}
