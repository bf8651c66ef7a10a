// Phase profile of the relaxation engine, built against kernel/ sources by profile_kernel.py
// (same -O3 as the extension). Prints one JSON object per line, one per disk radius:
//
//   evaluation   one energy + gradient (and per particle)
//   pattern      the Hessian's sparsity pattern on the free dof (once per topology)
//   analysis     CHOLMOD's symbolic analysis (once per topology): nnz(L), flops, supernodal
//   assembly     the reference (Gauss-Newton at rest) and exact Hessian values
//   factorize    one numeric factorisation (reference or exact)
//   solve        one pair of triangular sweeps
//   linear/newton cached   relax_linear and relax_newton (tol 1e-4 and 1e-10) with a made cache
//   lbfgs        NLopt L-BFGS from the bulk reference (tol 1e-4): total, evaluations, share in the energy
//
// usage: profile_kernel [--repeats N] R [R ...]   (hexagonal disks, ell = 5, nu = 0.5, eps = 0.01)
#include "hexagon.hpp"
#include "relax.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace pyfrustrate;
using Clock = std::chrono::steady_clock;

template <class F>
static double best_of(int repeats, F&& f) {
    double best = 1e300;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = Clock::now();
        f();
        best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
    }
    return best;
}

static Topology disk(int R) {
    std::vector<LatticeVector> sites;
    for (int i = -R; i <= R; ++i)
        for (int j = -R; j <= R; ++j)
            if (std::abs(i + j) <= R) sites.push_back({i, j});
    return make_topology(sites, Periodicity::None, {}, false);
}

int main(int argc, char** argv) {
    int repeats = 5;
    std::vector<int> radii;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--repeats" && i + 1 < argc) repeats = std::atoi(argv[++i]);
        else radii.push_back(std::atoi(argv[i]));
    }
    if (radii.empty()) radii = {10, 25};
    // Hexagon.from_continuum(ell=5, nu=0.5, eps=0.01): kc = k / (8 (1 - nu) ell^2), k_area = sqrt3 k (3 nu - 1) / (2 (1 - nu)).
    const double k = 1, kc = 1.0 / (8 * 0.5 * 25), k_area = std::sqrt(3.0) * 0.5 / 1.0;
    const HexagonModel model(k, kc, k_area, 0.01);
    const double force_scale = 0.01 * std::max({k, kc, std::abs(k_area)});
    for (int R : radii) {
        const Topology t = disk(R);
        const Network<HexagonModel> net{model, t};
        const Vector u0 = Vector::Zero(net.size());
        Vector g;
        const double t_eval = best_of(repeats * 4, [&] { net.energy(u0, &g); });
        HessianPattern pat;
        const double t_pattern = best_of(repeats, [&] { pat = net.hessian_pattern(rigid_body_pins(t)); });
        std::shared_ptr<CholeskyAnalysis> analysis;
        const double t_analysis =
            best_of(repeats, [&] { analysis = std::make_shared<CholeskyAnalysis>(pat.n_free, pat.column_start, pat.row); });
        const HexagonModel rest = model.without_mismatch();
        const Network<HexagonModel> rest_net{rest, t};
        std::vector<double> values;
        const double t_reference_assembly = best_of(repeats, [&] { values = rest_net.hessian(u0, pat, false); });
        CholeskyFactor factor(analysis);
        const double t_factorize = best_of(repeats, [&] { factor.factorize(values); });
        const Vector b = Vector::Ones(pat.n_free);
        const double t_solve = best_of(repeats * 4, [&] { factor.solve(b); });
        StiffnessCache cache(t);
        const Vector u_lin = relax_linear(model, t, &cache).displacement;
        std::vector<double> exact;
        const double t_exact_assembly = best_of(repeats, [&] { exact = net.hessian(u_lin, pat, true); });
        const double t_linear = best_of(repeats * 2, [&] { relax_linear(model, t, &cache); });
        MinimizeOptions o;
        o.gradient_tolerance = 1e-4 * force_scale;
        MinimizeResult newton;
        const double t_newton = best_of(repeats * 2, [&] { newton = relax_newton(model, t, o, &cache); });
        MinimizeOptions tight = o;
        tight.gradient_tolerance = 1e-10 * force_scale;
        MinimizeResult newton_tight;
        const double t_newton_tight = best_of(repeats, [&] { newton_tight = relax_newton(model, t, tight, &cache); });
        o.step_scale = model.step_scale();
        MinimizeResult lbfgs;
        const double t_lbfgs = best_of(std::max(1, repeats / 2), [&] { lbfgs = relax_lbfgs(model, t, t.reference_state(), o, &cache); });
        std::printf(
            "{\"R\": %d, \"dof\": %d, \"particles\": %d, \"t_eval\": %.6g, \"t_pattern\": %.6g, \"t_analysis\": %.6g, "
            "\"nnz_L\": %ld, \"flops\": %.6g, \"supernodal\": %d, \"t_reference_assembly\": %.6g, "
            "\"t_exact_assembly\": %.6g, \"t_factorize\": %.6g, \"t_solve\": %.6g, \"t_linear_cached\": %.6g, "
            "\"t_newton_cached\": %.6g, \"newton_steps\": %d, \"newton_evaluations\": %d, \"t_newton_cached_1e-10\": %.6g, "
            "\"newton_steps_1e-10\": %d, \"t_lbfgs\": %.6g, \"lbfgs_evaluations\": %d}\n",
            R, net.size(), t.n_particles(), t_eval, t_pattern, t_analysis, analysis->factor_nonzeros(),
            analysis->factor_flops(), analysis->supernodal() ? 1 : 0, t_reference_assembly, t_exact_assembly, t_factorize,
            t_solve, t_linear, t_newton, newton.newton_steps, newton.iterations, t_newton_tight, newton_tight.newton_steps,
            t_lbfgs, lbfgs.iterations);
        std::fflush(stdout);
    }
}
