"""Kernel vs numpy/scipy: relaxations of disks and periodic fibres at the same final accuracy.

Particle: ``Hexagon.from_continuum(ell=5, nu=0.5, eps=0.01)``. Scenes: disks R = 10, 25, 50, 100
and straight periodic fibre cells (cut 0) of width 30 and 300 (``--quick``: R = 5, 10 and width
30). Same final accuracy: every exact path runs at the loosest tolerance of 1e-3, 1e-4, 1e-5,
1e-6 (stop at ``max|grad| <= tol * F``, ``F = particle.force_scale``; scipy's ``gtol``, the
max-norm of the gradient here, with ``ftol=0``) whose relative energy error against a Newton
reference at 1e-12 is below 1e-8, found by a calibration run per rung; the error is printed.

Paths timed (wall clock of the Python call, repeated round-robin, short ones up to 30 times; min
and median):

* ``scipy L-BFGS-B``  ``scipy.optimize.minimize(method='L-BFGS-B', jac=True)`` on the vectorised
                      numpy energy of ``numpy_hexagon.py`` (10 pairs of memory): the baseline;
* ``kernel lbfgs``    NLopt L-BFGS from the bulk reference (Newton finishes if NLopt stops short);
* ``newton cold``     ``relax(method='newton')`` from nothing: the Hessian pattern, CHOLMOD's
                      symbolic analysis and the reference factorisation are part of the time;
* ``newton cached``   the same with a ``StiffnessCache`` made by an earlier call on the topology
                      (what a parameter scan or a Monte Carlo cache pays per relaxation);
* ``linear cold``, ``linear cached``  one solve with the eps = 0 stiffness (energy error O(eps^2),
                      listed for its speed).

Also: one energy+gradient evaluation, kernel vs numpy, per particle; time per degree of freedom
of the Newton paths as the disk grows. Start-up checks the numpy energy and gradient against the
kernel and stops with an AssertionError if they disagree.

    python benchmarks/bench_relax.py [--quick] [--repeats 3] [--csv PATH]
"""
from __future__ import annotations

import argparse
import statistics
import sys
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import fmt_time, import_pyfrustrate, machine_line, per_call, table, timed, write_csv  # noqa: E402

import numpy as np  # noqa: E402
from scipy.optimize import minimize  # noqa: E402

from numpy_hexagon import NumpyHexagon, check_against_kernel  # noqa: E402

pf = import_pyfrustrate()
from pyfrustrate.relaxation import energy as kernel_energy  # noqa: E402

ELL, NU, EPS = 5.0, 0.5, 0.01
TOL = 1e-5  # relative: max|grad| <= TOL * force_scale (the linear paths: unused)
ACCURACY = 1e-8  # the relative energy error every exact path must reach
LADDER = (1e-3, 1e-4, 1e-5, 1e-6)  # tolerances tried, loosest first, to reach it


def particle():
    return pf.Hexagon.from_continuum(ELL, NU, EPS)


def scenes(quick):
    if quick:
        return [("disk", 5), ("disk", 10), ("fibre", 30)]
    return [("disk", 10), ("disk", 25), ("disk", 50), ("disk", 100), ("fibre", 30), ("fibre", 300)]


def make_topology(kind, size):
    return pf.topology.disk(size) if kind == "disk" else pf.topology.fiber(size, 0, curved=False)


def startup_check(p, topo, seed=0):
    x0 = topo.reference_state()
    rng = np.random.default_rng(seed)
    return check_against_kernel(p, topo, {"reference": x0, "random": x0 + 0.02 * rng.standard_normal(x0.size)})


def run_paths(p, topo, repeats, scipy_repeats, reference):
    """Times and results of every path; each exact path at the loosest tolerance of LADDER that
    reaches the ACCURACY (found by one calibration run per rung, loosest first)."""
    x0 = topo.reference_state()
    model = NumpyHexagon(p, topo)
    cache = pf.StiffnessCache(topo)
    pf.relax(p, topo, method="linear", cache=cache)  # the cached paths start with a made cache

    def kernel(method, with_cache=False):
        def run(tol):
            r = pf.relax(p, topo, method, tol=tol, cache=cache if with_cache else None)
            return dict(energy=r.energy, evals=r.iterations, factorizations=r.factorizations,
                        gmax=r.gradient_norm, converged=r.converged)
        return run

    def scipy_run(tol):
        gtol = tol * p.force_scale
        res = minimize(model, x0, jac=True, method="L-BFGS-B",
                       options=dict(gtol=gtol, ftol=0.0, maxiter=10**6, maxfun=10**6, maxcor=10))
        return dict(energy=float(res.fun), evals=int(res.nfev), factorizations=0, gmax=float(np.abs(res.jac).max()),
                    converged=bool(np.abs(res.jac).max() <= gtol))

    paths = {"scipy L-BFGS-B": scipy_run, "kernel lbfgs": kernel("lbfgs"), "newton cold": kernel("newton"),
             "newton cached": kernel("newton", True), "linear cold": kernel("linear"),
             "linear cached": kernel("linear", True)}
    tols, rounds = {}, {}
    for name, fn in paths.items():
        for tol in (TOL,) if name.startswith("linear") else LADDER:  # linear: one solve, whatever tol
            t, r = timed(fn, tol)
            if name.startswith("linear") or abs(r["energy"] - reference) < ACCURACY * reference:
                tols[name] = tol
                break
        else:
            raise AssertionError(f"{topo.label} {name}: no tolerance of {LADDER} reaches {ACCURACY:g}")
        # Short paths get more rounds (at least 0.3 s of them, up to 30): on a shared machine the
        # minimum of a few millisecond-long runs is noisy.
        rounds[name] = scipy_repeats if name.startswith("scipy") else max(repeats, min(30, int(0.3 / t)))
    times = {k: [] for k in paths}
    results = {}
    for round_ in range(max(rounds.values())):
        for name, fn in paths.items():
            if round_ < rounds[name]:
                t, results[name] = timed(fn, tols[name])
                times[name].append(t)
    return times, results, tols


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="small sizes, few repeats (smoke run)")
    ap.add_argument("--repeats", type=int, default=None)
    ap.add_argument("--csv", type=Path, default=None, help="write the relaxation table here")
    args = ap.parse_args(argv)
    repeats = args.repeats or (2 if args.quick else 3)

    p = particle()
    print(f"bench_relax: Hexagon.from_continuum(ell={ELL}, nu={NU}, eps={EPS}) = {p}")
    print(f"  stop: max|grad| <= {TOL:g} * force_scale = {TOL * p.force_scale:.1e}; relative energy error "
          f"against Newton at 1e-12 must be < {ACCURACY:g}; {machine_line()}")
    print("  timings are wall-clock min (median) over interleaved repeats\n")

    csv_rows, summary, per_dof = [], [], []
    for kind, size in scenes(args.quick):
        topo = make_topology(kind, size)
        x0 = topo.reference_state()
        label = f"{kind} {'R' if kind == 'disk' else 'W'}={size}"
        de, dg = startup_check(p, topo)
        print(f"{label}: {topo.n_particles} particles, {x0.size} dof (numpy vs kernel: energy {de:.0e}, "
              f"gradient {dg:.0e} F)")
        model = NumpyHexagon(p, topo)
        k_min, _ = per_call(lambda: kernel_energy(p, topo, x0), repeats=5)
        n_min, _ = per_call(lambda: model(x0), repeats=5)
        print(f"  one energy+gradient: kernel {fmt_time(k_min)} ({k_min / topo.n_particles * 1e9:.0f} ns/particle), "
              f"numpy {fmt_time(n_min)}: {n_min / k_min:.1f}x")
        with warnings.catch_warnings():
            # The reference may stop at the forces' round-off (1.4e-12 F at R = 100): its energy
            # is then exact to ~1e-25 relative, which is all a reference needs.
            warnings.simplefilter("ignore", pf.ConvergenceWarning)
            reference = pf.relax(p, topo, method="newton", tol=1e-12).energy
        with warnings.catch_warnings():
            warnings.simplefilter("error", pf.ConvergenceWarning)
            big = x0.size > 50_000
            times, results, tols = run_paths(p, topo, 2 if big else repeats, 1 if big else repeats, reference)
        base_min = min(times["scipy L-BFGS-B"])
        base_med = statistics.median(times["scipy L-BFGS-B"])
        rows = []
        for name, r in results.items():
            t_min, t_med = min(times[name]), statistics.median(times[name])
            err = (r["energy"] - reference) / reference
            exact = not name.startswith("linear")
            if exact and abs(err) >= ACCURACY:
                raise AssertionError(f"{label} {name}: relative energy error {err:.1e} >= {ACCURACY:g}")
            rows.append((name, f"{tols[name]:g}" if exact else "-", fmt_time(t_min), fmt_time(t_med), r["evals"],
                         r["factorizations"], f"{err:.1e}",
                         f"{base_min / t_min:.1f}x", f"{base_med / t_med:.1f}x"))
            csv_rows.append(dict(scene=label, kind=kind, size=size, n_dof=x0.size, path=name, tol=tols[name], t_min=t_min,
                                 t_median=t_med, evals=r["evals"], factorizations=r["factorizations"],
                                 rel_energy_error=err, converged=r["converged"], speedup_min=base_min / t_min,
                                 speedup_median=base_med / t_med, eval_kernel=k_min, eval_numpy=n_min))
            summary.append((label, name, base_min / t_min))
            if kind == "disk" and name.startswith("newton"):
                per_dof.append((name, size, x0.size, t_min / x0.size))
        print("  " + table(rows, ["path", "tol", "time min", "median", "evals", "factorisations", "dE/E",
                                  "speed-up", "(median)"]).replace("\n", "\n  ") + "\n")

    print("time per degree of freedom, Newton on disks (min)")
    for name in ("newton cold", "newton cached"):
        pts = [(R, n, t) for nm, R, n, t in per_dof if nm == name]
        if pts:
            first = pts[0][2]
            print(f"  {name:14s} " + "  ".join(f"R={R}: {t * 1e9:.0f} ns ({t / first:.2f}x)" for R, n, t in pts))
    print("\nsummary: speed-up over scipy L-BFGS-B + numpy (same run, min-based)")
    labels = list(dict.fromkeys(s[0] for s in summary))
    names = list(dict.fromkeys(s[1] for s in summary if s[1] != "scipy L-BFGS-B"))
    lookup = {(s[0], s[1]): s[2] for s in summary}
    print("  " + table([[lab] + [f"{lookup[(lab, n)]:.1f}x" for n in names] for lab in labels],
                       ["scene"] + names).replace("\n", "\n  "))
    if args.csv:
        write_csv(args.csv, csv_rows)
    return summary


if __name__ == "__main__":
    main()
