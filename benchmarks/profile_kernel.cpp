// Phase profile of the kernel's relaxation paths, built against kernel/ sources by
// profile_kernel.py (same -O3, no -march). Prints one JSON object per line.
//
//   linear   : reference forces | Gauss-Newton Hessian assembly (kernel) | the same Hessian
//              assembled directly from the particle Hessians (no dense per-particle Jacobian,
//              finite clusters only) | reduction to free dof | AMD analysis | LDL^T
//              factorisation | solve | final energy; nnz of K and of L. Alternatives on the same
//              K: conjugate gradient with incomplete-Cholesky and with diagonal preconditioner;
//              fixed-stiffness Newton iterations from the linear solution reusing the LDL^T.
//   lbfgs    : total time, evaluations, time inside the energy, and hence NLopt's own share;
//              the cost of one m=10 two-loop recursion written with Eigen, for comparison.
//   eval     : one energy + gradient evaluation.
//
// usage: profile_kernel [--repeats N] [--nu NU] [--lbfgs-only] [--max-evals N] R [R ...]
//        (hexagonal disks, ell=5, nu=0.5 unless given, eps=0.01, tol=1e-5)
#include "hexagon.hpp"
#include "relax.hpp"

#include <Eigen/IterativeLinearSolvers>
#ifdef HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif
#ifdef HAVE_METIS
#include <iostream>  // Eigen/MetisSupport uses std::cerr without including it
#include <Eigen/MetisSupport>
#endif
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace pyfrustrate;
using Clock = std::chrono::steady_clock;

static double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Minimum over `repeats` runs of f() (seconds).
template <class F>
static double best_of(int repeats, F&& f) {
    double best = 1e300;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = Clock::now();
        f();
        best = std::min(best, seconds_since(t0));
    }
    return best;
}

// The kernel's L-BFGS runs in variables scaled by the model's step_scale() where the kernel has
// one (relax_lbfgs passes it); these overloads keep the profiler building on either version.
template <class O>
static auto set_step_scale(O& o, double s, int) -> decltype(o.step_scale = s, void()) { o.step_scale = s; }
template <class O>
static void set_step_scale(O&, double, long) {}
template <class M>
static auto model_step_scale(const M& m, int) -> decltype(m.step_scale()) { return m.step_scale(); }
template <class M>
static double model_step_scale(const M&, long) { return 1.0; }

static Topology disk(int R) {
    std::vector<LatticeVector> sites;
    for (int i = -R; i <= R; ++i)
        for (int j = -R; j <= R; ++j)
            if (std::abs(i + j) <= R) sites.push_back({i, j});
    return make_topology(sites, Periodicity::None, {LatticeVector{0, 0}, LatticeVector{0, 0}}, false);
}

// Hessian of a finite cluster, scattered straight from each particle's 12x12 Hessian.
static Eigen::SparseMatrix<double> direct_hessian(const HexagonModel& model, const Topology& t,
                                                  const Eigen::VectorXd& x) {
    const int C = HexagonModel::kCornerCount;
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(static_cast<size_t>(t.n_particles()) * 4 * C * C);
    for (int p = 0; p < t.n_particles(); ++p) {
        HexagonModel::Corners c;
        for (int s = 0; s < C; ++s) c.segment<2>(2 * s) = x.segment<2>(2 * t.corner[p][s]);
        HexagonModel::Hessian h = HexagonModel::Hessian::Zero();
        model.energy(c, nullptr, &h);
        for (int a = 0; a < 2 * C; ++a) {
            const int ga = 2 * t.corner[p][a / 2] + a % 2;
            for (int b = 0; b < 2 * C; ++b)
                entries.emplace_back(ga, 2 * t.corner[p][b / 2] + b % 2, h(a, b));
        }
    }
    Eigen::SparseMatrix<double> H(2 * t.n_corners(), 2 * t.n_corners());
    H.setFromTriplets(entries.begin(), entries.end());
    return H;
}

static void profile_linear(const Network<HexagonModel>& net, const Network<HexagonModel>& rest,
                           const HexagonModel& rest_model, const Topology& topo, const Vector& x_ref, int R,
                           int repeats, double gtol) {
    const int n = net.size();
    Vector g;
    Vector force;
    const double t_force = best_of(repeats, [&] { net.energy(x_ref, &force); });
    force = -force;
    Eigen::SparseMatrix<double> H;
    const double t_gn = best_of(repeats, [&] { H = rest.gauss_newton_hessian(x_ref); });
    Eigen::SparseMatrix<double> H2;
    const double t_direct = best_of(repeats, [&] { H2 = direct_hessian(rest_model, topo, x_ref); });
    const double assembly_diff = (H - H2).norm() / H.norm();

    std::vector<int> pins = rigid_body_pins(topo);
    std::vector<int> free_index(n, -1);
    int n_free = 0;
    for (int i = 0; i < n; ++i)
        if (std::find(pins.begin(), pins.end(), i) == pins.end()) free_index[i] = n_free++;
    Eigen::SparseMatrix<double> K(n_free, n_free);
    const double t_reduce = best_of(repeats, [&] {
        std::vector<Eigen::Triplet<double>> entries;
        for (int col = 0; col < H.outerSize(); ++col)
            for (Eigen::SparseMatrix<double>::InnerIterator it(H, col); it; ++it)
                if (free_index[it.row()] >= 0 && free_index[it.col()] >= 0)
                    entries.emplace_back(free_index[it.row()], free_index[it.col()], it.value());
        K.setFromTriplets(entries.begin(), entries.end());
    });
    Vector rhs(n_free);
    for (int i = 0; i < n; ++i)
        if (free_index[i] >= 0) rhs[free_index[i]] = force[i];

    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
    const double t_analyze = best_of(repeats, [&] { ldlt.analyzePattern(K); });
    const double t_factor = best_of(repeats, [&] { ldlt.factorize(K); });
    Vector step;
    const double t_solve = best_of(repeats, [&] { step = ldlt.solve(rhs); });
    const long nnz_L = ldlt.matrixL().nestedExpression().nonZeros();
    Vector x = x_ref;
    for (int i = 0; i < n; ++i)
        if (free_index[i] >= 0) x[i] += step[free_index[i]];
    const double t_final = best_of(repeats, [&] { net.energy(x, &g); });

    // Alternatives on the same K: preconditioned conjugate gradient to a residual of 1e-10.
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper, Eigen::IncompleteCholesky<double>> cg_ic;
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg_diag;
    cg_ic.setTolerance(1e-10);
    cg_diag.setTolerance(1e-10);
    cg_diag.setMaxIterations(20 * n_free);
    Vector s_ic, s_diag;
    const double t_cg_ic = best_of(repeats, [&] { cg_ic.compute(K); s_ic = cg_ic.solve(rhs); });
    const double t_cg_diag = best_of(repeats, [&] { cg_diag.compute(K); s_diag = cg_diag.solve(rhs); });
    const double err_ic = (s_ic - step).norm() / step.norm(), err_diag = (s_diag - step).norm() / step.norm();

    // Fixed-stiffness Newton from the linear solution: x <- x - K^-1 grad(x) on the free dof,
    // reusing the factorisation of the eps = 0 stiffness, until max|grad| <= gtol.
    int newton_steps = 0;
    double newton_energy = 0, newton_gmax = 0;
    Vector g_free(n_free);
    const double t_newton = best_of(repeats, [&] {
        Vector xn = x;
        newton_steps = 0;
        for (;;) {
            newton_energy = net.energy(xn, &g);
            newton_gmax = g.cwiseAbs().maxCoeff();
            if (newton_gmax <= gtol || newton_steps >= 200) break;
            for (int i = 0; i < n; ++i)
                if (free_index[i] >= 0) g_free[free_index[i]] = g[i];
            const Vector d = ldlt.solve(g_free);
            for (int i = 0; i < n; ++i)
                if (free_index[i] >= 0) xn[i] -= d[free_index[i]];
            ++newton_steps;
        }
    });

    // Optional: other orderings / supernodal factorisation, when the libraries are installed.
    double t_metis = -1, t_cholmod_analyze = -1, t_cholmod_factor = -1, t_cholmod_solve = -1, err_cholmod = -1;
    long nnz_L_metis = -1;
#ifdef HAVE_METIS
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::MetisOrdering<int>> ldlt_metis;
    t_metis = best_of(repeats, [&] { ldlt_metis.compute(K); });
    nnz_L_metis = ldlt_metis.matrixL().nestedExpression().nonZeros();
#endif
#ifdef HAVE_CHOLMOD
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> chol;
    t_cholmod_analyze = best_of(repeats, [&] { chol.analyzePattern(K); });
    t_cholmod_factor = best_of(repeats, [&] { chol.factorize(K); });
    Vector s_chol;
    t_cholmod_solve = best_of(repeats, [&] { s_chol = chol.solve(rhs); });
    err_cholmod = (s_chol - step).norm() / step.norm();
#endif
    std::printf("{\"phase\": \"linear\", \"R\": %d, \"dof\": %d, \"t_force\": %.6g, \"t_gauss_newton\": %.6g, "
                "\"t_direct_assembly\": %.6g, \"assembly_rel_diff\": %.3g, \"t_reduce\": %.6g, \"t_analyze\": %.6g, "
                "\"t_factorize\": %.6g, \"t_solve\": %.6g, \"t_final_energy\": %.6g, \"nnz_K\": %ld, \"nnz_L\": %ld, "
                "\"t_cg_ichol\": %.6g, \"cg_ichol_iterations\": %ld, \"cg_ichol_rel_err\": %.3g, "
                "\"t_cg_diag\": %.6g, \"cg_diag_iterations\": %ld, \"cg_diag_rel_err\": %.3g, "
                "\"t_ldlt_metis\": %.6g, \"nnz_L_metis\": %ld, \"t_cholmod_analyze\": %.6g, "
                "\"t_cholmod_factorize\": %.6g, \"t_cholmod_solve\": %.6g, \"cholmod_rel_err\": %.3g, "
                "\"t_newton\": %.6g, \"newton_steps\": %d, \"newton_energy\": %.15g, \"newton_gmax\": %.3g}\n",
                R, n, t_force, t_gn, t_direct, assembly_diff, t_reduce, t_analyze, t_factor, t_solve, t_final,
                static_cast<long>(K.nonZeros()), nnz_L, t_cg_ic, static_cast<long>(cg_ic.iterations()), err_ic,
                t_cg_diag, static_cast<long>(cg_diag.iterations()), err_diag, t_metis, nnz_L_metis,
                t_cholmod_analyze, t_cholmod_factor, t_cholmod_solve, err_cholmod, t_newton, newton_steps,
                newton_energy, newton_gmax);

}

static void profile(int R, int repeats, double nu, bool lbfgs_only, int max_evals) {
    const double ell = 5, eps = 0.01, k = 1;
    const HexagonModel model(k, k / (8 * (1 - nu) * ell * ell), std::sqrt(3.0) * k * (3 * nu - 1) / (2 * (1 - nu)), eps);
    const Topology topo = disk(R);
    const Network<HexagonModel> net{model, topo};
    const HexagonModel rest_model = model.without_mismatch();
    const Network<HexagonModel> rest{rest_model, topo};
    const Vector x_ref = topo.reference_state();
    const int n = net.size();

    // --- one evaluation
    Vector g;
    volatile double sink = 0;
    const int batch = std::max(1, 200000 / n);
    const double t_eval = best_of(repeats, [&] { for (int i = 0; i < batch; ++i) sink = sink + net.energy(x_ref, &g); }) / batch;

    if (!lbfgs_only) profile_linear(net, rest, rest_model, topo, x_ref, R, repeats, 1e-5 * k * eps);

    // --- L-BFGS: total, evaluations, time inside the energy
    MinimizeOptions options;
    options.gradient_tolerance = 1e-5 * k * eps;
    options.max_iterations = max_evals;
    options.memory = 10;
    options.restarts = 5;
    set_step_scale(options, model_step_scale(model, 0), 0);
    double t_in_energy = 0;
    int evals = 0;
    const Objective objective = [&](const Vector& xx, Vector& gg) {
        const auto t0 = Clock::now();
        const double e = net.energy(xx, &gg);
        t_in_energy += seconds_since(t0);
        ++evals;
        return e;
    };
    MinimizeResult res;
    double t_lbfgs = 1e300, t_lbfgs_energy = 0;
    for (int r = 0; r < repeats; ++r) {
        t_in_energy = 0;
        evals = 0;
        const auto t0 = Clock::now();
        res = minimize_lbfgs(objective, x_ref, options);
        const double t = seconds_since(t0);
        if (t < t_lbfgs) t_lbfgs = t, t_lbfgs_energy = t_in_energy;
    }
    // Cost of one L-BFGS direction (two-loop recursion, m = 10) plus the x/g updates, with Eigen.
    const int m = 10;
    std::vector<Vector> S(m, Vector::Random(n)), Y(m, Vector::Random(n));
    std::vector<double> rho(m, 1.0), alpha(m);
    Vector q = Vector::Random(n), xx = Vector::Random(n);
    const double t_twoloop = best_of(repeats, [&] {
        for (int rep = 0; rep < 20; ++rep) {
            for (int i = m - 1; i >= 0; --i) { alpha[i] = rho[i] * S[i].dot(q); q -= alpha[i] * Y[i]; }
            q *= 0.5;
            for (int i = 0; i < m; ++i) { const double b = rho[i] * Y[i].dot(q); q += (alpha[i] - b) * S[i]; }
            xx += 1e-9 * q;
            S[rep % m] = xx - q;  // the two history copies of an iteration
            Y[rep % m] = q - xx;
        }
    }) / 20;
    std::printf("{\"phase\": \"lbfgs\", \"nu\": %g, \"R\": %d, \"dof\": %d, \"t_total\": %.6g, \"evaluations\": %d, "
                "\"t_in_energy\": %.6g, \"energy\": %.15g, \"converged\": %s, \"t_eval\": %.6g, "
                "\"t_eigen_twoloop\": %.6g}\n",
                nu, R, n, t_lbfgs, res.iterations, t_lbfgs_energy, res.energy, res.converged ? "true" : "false",
                t_eval, t_twoloop);
    (void)sink;
}

int main(int argc, char** argv) {
    int repeats = 5;
    double nu = 0.5;
    bool lbfgs_only = false;
    int max_evals = 500000;
    std::vector<int> radii;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--repeats" && i + 1 < argc) repeats = std::atoi(argv[++i]);
        else if (a == "--nu" && i + 1 < argc) nu = std::atof(argv[++i]);
        else if (a == "--lbfgs-only") lbfgs_only = true;
        else if (a == "--max-evals" && i + 1 < argc) max_evals = std::atoi(argv[++i]);
        else radii.push_back(std::atoi(a.c_str()));
    }
    if (radii.empty()) radii = {10, 25};
    for (int R : radii) profile(R, repeats, nu, lbfgs_only, max_evals);
    return 0;
}
