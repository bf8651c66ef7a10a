#include "chain.hpp"

#include <cmath>
#include <stdexcept>

namespace pyfrustrate {

void ChainParameters::validate() const {
    if (n < 1) throw std::invalid_argument("n must be at least 1");
    if (!(k > 0) || !std::isfinite(k)) throw std::invalid_argument("k must be positive and finite");
    if (!(kc >= 0) || !std::isfinite(kc)) throw std::invalid_argument("kc must be non-negative and finite");
    if (!(eps > 0 && eps < 1)) throw std::invalid_argument("eps must lie in (0, 1)");
}

double chain_energy(const ChainParameters& p, const Vector& x, Vector& gradient) {
    const int m = p.n + 1;
    const double* up = x.data();
    const double* down = x.data() + m;
    gradient.setZero(2 * m);
    double* gup = gradient.data();
    double* gdown = gradient.data() + m;
    double energy = 0.0;
    for (int i = 0; i < p.n; ++i) {
        const double top = up[i + 1] - up[i] - (1 + p.eps);
        const double bottom = down[i + 1] - down[i] - (1 - p.eps);
        const double right = up[i + 1] - down[i + 1] - p.eps;
        const double left = down[i] - up[i] - p.eps;
        energy += 0.5 * p.k * (top * top + bottom * bottom) + 0.25 * p.kc * (right * right + left * left);
        gup[i + 1] += p.k * top + 0.5 * p.kc * right;
        gup[i] += -p.k * top - 0.5 * p.kc * left;
        gdown[i + 1] += p.k * bottom - 0.5 * p.kc * right;
        gdown[i] += -p.k * bottom + 0.5 * p.kc * left;
    }
    return energy;
}

MinimizeResult chain_relax(const ChainParameters& p, const MinimizeOptions& options) {
    p.validate();
    const int m = p.n + 1;
    Vector x0(2 * m);
    // The bulk reference (every particle a unit rectangle), as in the continuum theory.
    for (int i = 0; i < m; ++i) x0[i] = x0[m + i] = i;
    const Objective objective = [&p](const Vector& x, Vector& g) { return chain_energy(p, x, g); };
    return minimize_lbfgs(objective, x0, options);
}

}  // namespace pyfrustrate
