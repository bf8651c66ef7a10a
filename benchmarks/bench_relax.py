"""Kernel vs numpy/scipy: one energy+gradient evaluation and a full relaxation of a hexagonal disk.

Particle: ``Hexagon.from_continuum(ell=5, nu=0.5, eps=0.01)``; topology ``disk(R)`` from the
bulk reference state. Every L-BFGS stops on the same criterion, ``max|grad| <= 1e-5 * F`` with
``F = particle.force_scale = eps * max(k, |k_area|, kc)`` (= k * eps = 0.01 for this particle;
the kernel's ``tol=1e-5``; scipy's ``gtol``, the max-norm of the projected gradient, which is
the gradient here since there are no bounds; ``ftol=0`` so that only the gradient stops it).

Paths timed (wall clock of the Python call, repeated round-robin so that load changes on a
shared machine hit every path alike; min and median reported):

* ``kernel lbfgs``        ``relax(..., 'lbfgs')`` from the bulk reference (cold start);
* ``kernel linear``       ``relax(..., 'linear')``: one sparse LDL^T solve (not converged to the
                          gradient tolerance: its energy error is O(eps^2), see bench_tradeoff);
* ``kernel lbfgs warm``   ``relax(..., 'lbfgs', x0='linear')``: the linear solve then L-BFGS;
* ``kernel newton``       ``relax(..., 'newton')``: Newton steps reusing the factorised reference
                          stiffness from the linear solution, to the same tolerance;
* ``scipy L-BFGS-B``      ``scipy.optimize.minimize(method='L-BFGS-B', jac=True)`` on the numpy
                          energy of ``numpy_hexagon.py`` (same memory, 10 pairs): the baseline;
* ``scipy + naive numpy`` the same on ``NaiveNumpyHexagon`` (particle-major arrays, np.add.at),
                          for scale only: what a first numpy version would cost.

Start-up checks the numpy energy and gradient against the kernel (random and relaxed states) and
stops with an AssertionError if they disagree.

    python benchmarks/bench_relax.py [--quick] [--radii 10 25] [--repeats 5] [--csv PATH]
"""
from __future__ import annotations

import argparse
import math
import statistics
import sys
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import fmt_time, import_pyfrustrate, machine_line, per_call, table, timed, write_csv  # noqa: E402

import numpy as np  # noqa: E402
from scipy.optimize import minimize  # noqa: E402

from numpy_hexagon import NaiveNumpyHexagon, NumpyHexagon, check_against_kernel  # noqa: E402

pf = import_pyfrustrate()
try:  # the module was renamed relax -> relaxation
    from pyfrustrate.relaxation import energy as kernel_energy  # noqa: E402
except ImportError:  # pragma: no cover
    from pyfrustrate.relax import energy as kernel_energy  # noqa: E402

ELL, NU, EPS = 5.0, 0.5, 0.01
TOL = 1e-5  # relative: max|grad| <= TOL * force_scale


def force_scale(p):
    """The kernel's unit of the gradient tolerance (k * eps before force_scale existed)."""
    return getattr(p, "force_scale", p.k * p.eps)


def particle():
    return pf.Hexagon.from_continuum(ELL, NU, EPS)


def startup_check(p, topo, seed=0):
    """Numpy vs kernel on the reference, a random and a relaxed state (raises on mismatch)."""
    x0 = topo.reference_state()
    rng = np.random.default_rng(seed)
    states = {"reference": x0, "random": x0 + 0.05 * rng.standard_normal(x0.size),
              "relaxed": pf.relax(p, topo, tol=TOL).state}
    return check_against_kernel(p, topo, states)


def run_paths(p, topo, repeats):
    """Times and results of every relaxation path, interleaved over ``repeats`` rounds."""
    x0 = topo.reference_state()
    model = NumpyHexagon(p, topo)
    naive = NaiveNumpyHexagon(p, topo)
    gtol = TOL * force_scale(p)

    def kernel(method, **kw):
        def run():
            r = pf.relax(p, topo, method, tol=TOL, **kw)
            return dict(energy=r.energy, evals=r.iterations, gmax=r.gradient_norm, converged=r.converged)
        return run

    def scipy_run(fun):
        def run():
            res = minimize(fun, x0, jac=True, method="L-BFGS-B",
                           options=dict(gtol=gtol, ftol=0.0, maxiter=10**6, maxfun=10**6, maxcor=10))
            return dict(energy=float(res.fun), evals=int(res.nfev), gmax=float(np.abs(res.jac).max()),
                        converged=bool(res.success) and np.abs(res.jac).max() <= gtol)
        return run

    paths = {"kernel lbfgs": kernel("lbfgs"), "kernel linear": kernel("linear"),
             "kernel lbfgs warm": kernel("lbfgs", x0="linear"), "kernel newton": kernel("newton"),
             "scipy L-BFGS-B": scipy_run(model),
             "scipy + naive numpy": scipy_run(naive)}
    times = {k: [] for k in paths}
    results = {}
    for _ in range(repeats):
        for name, fn in paths.items():
            t, results[name] = timed(fn)
            times[name].append(t)
    return times, results


def linear_profile(p, radii, repeats):
    """Linear-solve time vs size, with the cost of its two energy evaluations subtracted: what
    remains is Hessian assembly + LDL^T factorisation + solve."""
    rows = []
    for R in radii:
        topo = pf.topology.disk(R)
        x0 = topo.reference_state()
        t_lin = min(timed(pf.relax, p, topo, "linear")[0] for _ in range(repeats))
        t_eval = per_call(lambda: kernel_energy(p, topo, x0), repeats=repeats)[0]
        rows.append(dict(R=R, n_dof=x0.size, t_linear=t_lin, t_eval=t_eval,
                         t_solve=max(t_lin - 2 * t_eval, 0.0)))
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="small sizes, few repeats (smoke run)")
    ap.add_argument("--radii", type=int, nargs="+", default=None)
    ap.add_argument("--repeats", type=int, default=None)
    ap.add_argument("--csv", type=Path, default=None, help="write the relaxation table here")
    args = ap.parse_args(argv)
    radii = args.radii or ([5, 10] if args.quick else [10, 25])
    repeats = args.repeats or (2 if args.quick else 5)
    scaling_radii = [5, 10, 15] if args.quick else [5, 10, 20, 30, 40]

    p = particle()
    print(f"bench_relax: Hexagon.from_continuum(ell={ELL}, nu={NU}, eps={EPS}) = {p}")
    print(f"  stop: max|grad| <= {TOL:g} * force_scale = {TOL * force_scale(p):.1e}; {machine_line()}")
    print("  timings are wall-clock min (median) over", repeats, "interleaved repeats\n")

    csv_rows, summary = [], []
    for R in radii:
        topo = pf.topology.disk(R)
        x0 = topo.reference_state()
        de, dg = startup_check(p, topo)
        print(f"disk R={R}: {topo.n_particles} particles, {x0.size} dof. numpy vs kernel: energy "
              f"{de:.1e} relative, gradient {dg:.1e} k*eps (checked, < 1e-12 and 1e-12*max|x|)")

        # (a) one energy + gradient evaluation
        model, naive = NumpyHexagon(p, topo), NaiveNumpyHexagon(p, topo)
        e_n, g_n = model(x0 + 0.01)
        e_v, g_v = naive(x0 + 0.01)
        assert abs(e_v - e_n) <= 1e-12 * e_n and np.abs(g_v - g_n).max() <= 1e-12, "naive numpy disagrees"
        k_min, k_med = per_call(lambda: kernel_energy(p, topo, x0), repeats=repeats + 2)
        n_min, n_med = per_call(lambda: model(x0), repeats=repeats + 2)
        v_min, v_med = per_call(lambda: naive(x0), repeats=max(3, repeats // 2))
        print(f"  (a) energy+gradient: kernel {fmt_time(k_min)} ({fmt_time(k_med)}), numpy "
              f"{fmt_time(n_min)} ({fmt_time(n_med)}): numpy/kernel = {n_min / k_min:.1f}x "
              f"(median {n_med / k_med:.1f}x)\n      [naive numpy, (P, 6, 2) + np.add.at: "
              f"{fmt_time(v_min)} = {v_min / k_min:.0f}x the kernel]")

        # (b) full relaxations
        with warnings.catch_warnings():
            warnings.simplefilter("error", pf.ConvergenceWarning)
            times, results = run_paths(p, topo, repeats)
        best = min(r["energy"] for r in results.values())
        base_min = min(times["scipy L-BFGS-B"])
        base_med = statistics.median(times["scipy L-BFGS-B"])
        rows = []
        for name, r in results.items():
            t_min, t_med = min(times[name]), statistics.median(times[name])
            one_eval = k_min if name.startswith("kernel") else (n_min if name == "scipy L-BFGS-B" else v_min)
            eval_cost = one_eval * r["evals"]
            in_energy = "-" if name == "kernel linear" else f"{min(eval_cost / t_min, 1.0):.0%}"
            rel = (r["energy"] - best) / best
            rows.append((name, fmt_time(t_min), fmt_time(t_med), r["evals"], f"{r['energy']:.12g}",
                         f"{rel:.1e}", f"{r['gmax'] / force_scale(p):.1e}",
                         f"{base_min / t_min:.1f}x", f"{base_med / t_med:.1f}x", in_energy))
            csv_rows.append(dict(R=R, n_dof=x0.size, path=name, t_min=t_min, t_median=t_med,
                                 evals=r["evals"], energy=r["energy"], rel_energy_diff=rel,
                                 gmax_over_force_scale=r["gmax"] / force_scale(p), converged=r["converged"],
                                 speedup_min=base_min / t_min, speedup_median=base_med / t_med,
                                 eval_kernel=k_min, eval_numpy=n_min))
            summary.append((R, name, base_min / t_min, base_med / t_med))
        print("  (b) full relaxation")
        print("      " + table(rows, ["path", "time min", "median", "evals", "energy", "dE/E_best",
                                      "max|g|/F", "speed-up", "(median)", "in energy"]).replace(
            "\n", "\n      "))
        print("      speed-up = scipy time / path time, same run; 'in energy' = evals x one "
              "evaluation / total: the rest is the optimiser's own work\n")

    prof = linear_profile(p, scaling_radii, max(2, repeats - 2))
    rows = [(r["R"], r["n_dof"], fmt_time(r["t_linear"]), fmt_time(2 * r["t_eval"]),
             fmt_time(r["t_solve"]), f"{r['t_solve'] / r['n_dof'] * 1e6:.2f} us") for r in prof]
    print("linear solve vs size (assembly + LDL^T + solve = total - 2 energy evaluations)")
    print("  " + table(rows, ["R", "dof", "linear total", "2 evals", "assembly+LDL^T",
                              "per dof"]).replace("\n", "\n  "))
    if len(prof) >= 2:
        a, b = prof[-2], prof[-1]
        slope = math.log(b["t_solve"] / a["t_solve"]) / math.log(b["n_dof"] / a["n_dof"])
        print(f"  growth between the two largest: time ~ dof^{slope:.2f} (assembly alone is linear "
              "in dof;\n  see profile_kernel.py for the phase split)")

    print("\nsummary: speed-up over scipy L-BFGS-B + numpy (min-based, median-based)")
    print("  " + table([(R, n, f"{a:.1f}x", f"{m:.1f}x") for R, n, a, m in summary],
                       ["R", "path", "min", "median"]).replace("\n", "\n  "))
    if args.csv:
        write_csv(args.csv, csv_rows)
    return summary


if __name__ == "__main__":
    main()
