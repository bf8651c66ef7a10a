"""What ``pyfrustrate.anneal`` reaches with its own defaults (issue 32, item 2): the issue's bar case.

A user calling ``anneal(particle, Gamma=..., box=..., n=..., seed=...)`` gets the package defaults
(``MonteCarloOptions()``, ``annealing.DEFAULT_SWEEPS``, the linear schedule). This runs the issue's
case -- 400 hexagons in 60 x 60, ell = 5, eps = 0.01, nu = 0.9, Gamma = 0.3, seed 1 -- with those
defaults and, in the same run as the baseline, with the defaults ``anneal`` had before the engine's
redesign (L-BFGS, no cluster, bonded or surface moves, 10 000 sweeps). Each run's final energy is
compared with the best single aggregate of the n particles (``ansatz.finite_aggregates``, Newton to
the runs' tolerance), in bulk particle energies ``e_b``, and its CPU time is measured.

Writes a CSV (``--csv``, default ``benchmarks/results/anneal_defaults.csv``) that the ``anneal``
documentation quotes.

Usage: ``python benchmarks/bench_anneal_defaults.py [--quick] [--no-baseline] [--seed 1] [--csv PATH]``
"""
from __future__ import annotations

import argparse
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import add_box_arguments, import_pyfrustrate, machine_line, source_line, table, write_csv  # noqa: E402

#: ``anneal``'s defaults before the redesign of issue 32 (commit 4e30625): L-BFGS relaxations,
#: particle moves only, 10 000 sweeps; the schedule (linear from T0 = g) is unchanged.
FORMER_DEFAULTS = dict(method="lbfgs", cluster_moves=0.0, cluster_link=1.0, bonded_moves=0.0, surface_moves=0.0)
FORMER_SWEEPS = 10_000

DEFAULT_CSV = Path(__file__).resolve().parent / "results" / "anneal_defaults.csv"


def _run(args, fields, sweeps):
    """One anneal from ``fields`` over the defaults: (energy, g, largest cluster, CPU seconds, sweeps)."""
    pf = import_pyfrustrate()
    from pyfrustrate import Hexagon
    from pyfrustrate.montecarlo import annealing

    particle = Hexagon.from_continuum(args.ell, args.nu, args.eps)
    steps = None if sweeps is None else sweeps * args.n
    cpu = time.process_time()
    r = pf.anneal(particle, Gamma=args.Gamma, box=args.box, n=args.n, seed=args.seed, steps=steps, progress=False,
                  **fields)
    cpu = time.process_time() - cpu
    return r.energy, r.g, max(len(c) for c in r.clusters()), cpu, (steps or annealing.DEFAULT_SWEEPS * args.n) // args.n


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="100 particles in 30 x 30, 1000 sweeps (a smoke run)")
    add_box_arguments(ap)
    ap.set_defaults(box=60)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--no-baseline", action="store_true", help="skip the run with the former defaults")
    ap.add_argument("--jobs", type=int, default=2, help="runs side by side (processes)")
    ap.add_argument("--csv", type=Path, default=DEFAULT_CSV)
    args = ap.parse_args(argv)
    import_pyfrustrate()
    from pyfrustrate import Hexagon, ansatz
    from pyfrustrate.montecarlo import MonteCarloOptions, annealing, binding

    sweeps = {"package defaults": None, "former defaults": FORMER_SWEEPS}
    if args.quick:
        args.n, args.box = 100, 30
        sweeps = {"package defaults": 1000, "former defaults": 1000}
    settings = {"package defaults": {}} if args.no_baseline else {"package defaults": {}, "former defaults": FORMER_DEFAULTS}
    particle = Hexagon.from_continuum(args.ell, args.nu, args.eps)
    print(f"{machine_line()}\n{source_line()}")
    print(f"{args.n} particles in {args.box} x {args.box}, ell = {args.ell:g}, eps = {args.eps:g}, nu = {args.nu:g}, "
          f"Gamma = {args.Gamma:g}, seed {args.seed}; package defaults: {MonteCarloOptions()}, "
          f"{annealing.DEFAULT_SWEEPS} sweeps")
    # The prediction to beat, relaxed as the runs relax their clusters (Newton, tol 1e-3).
    g = binding(particle, Gamma=args.Gamma)
    best_single = float(ansatz.finite_aggregates(particle, args.n, method="newton", tol=1e-3).best_energy(g))
    e_bulk = particle.bulk_energy_per_particle
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        futures = {label: pool.submit(_run, args, fields, sweeps[label]) for label, fields in settings.items()}
        results = {label: f.result() for label, f in futures.items()}
    base_cpu = results[list(settings)[-1]][3]
    rows = []
    for label, (energy, run_g, largest, cpu, n_sweeps) in results.items():
        assert run_g == g, (run_g, g)
        rows.append(dict(setting=label, n=args.n, box=args.box, nu=args.nu, Gamma=args.Gamma, seed=args.seed,
                         sweeps=n_sweeps, energy=f"{energy:.6g}", best_single_aggregate=f"{best_single:.6g}",
                         gap_bulk_energies=f"{(energy - best_single) / e_bulk:.1f}", cpu_s=f"{cpu:.0f}",
                         cpu_ratio_to_former=f"{cpu / base_cpu:.2f}", largest_cluster=largest))
    print(table([tuple(str(v) for v in row.values()) for row in rows], list(rows[0])))
    if not args.quick:
        write_csv(args.csv, rows, parameters=dict(n=args.n, box=args.box, ell=args.ell, eps=args.eps, nu=args.nu,
                                                  Gamma=args.Gamma, seed=args.seed))


if __name__ == "__main__":
    main()
