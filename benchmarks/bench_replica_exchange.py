"""Replica exchange against simulated annealing at the same number of attempted moves (issue 15):
does the Monte Carlo reach the finite-size ground state?

System (default): 400 particles in an 85 x 85 box at ell = 5, eps = 0.01, nu = 0.9, Gamma = 0.3,
where the workflow's annealing (4000 sweeps, linear schedule from T0 = g, linked cluster moves)
ends tens of bulk particle energies above the best single aggregate of 400 particles (+28.0 at
seed 1, measured with bench_equilibration.py; docs/results_log.md). For each seed:

* ``anneal``            ``pyfrustrate.anneal`` with ``sweeps`` sweeps (the workflow's moves: Newton at tol
                        1e-3, cluster_moves 0.05, cluster_link 0.9, bonded_moves 0, surface_moves 0,
                        or as given);
* ``replica exchange``  ``pyfrustrate.replica_exchange`` on a geometric ladder of ``K``
                        temperatures from ``T_min`` to ``T_max`` (in units of g), ``sweeps / K``
                        rounds of one sweep per replica (the same attempted moves in all), then
                        a T = 0 descent of the coldest configuration.

Printed per run: the final energy above the best single aggregate (``ansatz.finite_aggregates``)
in bulk particle energies (the issue's criterion: within 5), the largest cluster, CPU and wall
time, and for replica exchange the swap acceptance and round trips. Ratios are against the
annealing run of the same seed.

Usage: ``python benchmarks/bench_replica_exchange.py [--quick] [--n 400 --box 85 --nu 0.9
--Gamma 0.3 --sweeps 4000 --replicas 8 --T-min 0.05 --T-max 0.5 --cluster-moves 0.05 --cluster-link 0.9
--bonded-moves 0 --surface-moves 0 --method newton --seeds 1 2]``
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import add_box_arguments, import_pyfrustrate, machine_line, source_line, table  # noqa: E402

import numpy as np  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="100 particles in 40 x 40, 400 sweeps")
    add_box_arguments(ap)
    ap.add_argument("--replicas", type=int, default=8)
    ap.add_argument("--T-min", type=float, default=0.05, help="coldest temperature, in units of g")
    ap.add_argument("--T-max", type=float, default=0.5, help="hottest temperature, in units of g")
    ap.add_argument("--cluster-moves", type=float, default=0.05)
    ap.add_argument("--cluster-link", type=float, default=0.9)
    ap.add_argument("--bonded-moves", type=float, default=0.0)
    ap.add_argument("--surface-moves", type=float, default=0.0)
    ap.add_argument("--method", default="newton")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1])
    args = ap.parse_args(argv)
    if args.quick:
        args.n, args.box, args.sweeps = 100, 40, 400
    import_pyfrustrate()
    from pyfrustrate import Hexagon, ansatz, anneal, continuum, replica_exchange
    from pyfrustrate.montecarlo import geometric_temperatures

    particle = Hexagon.from_continuum(args.ell, args.nu, args.eps)
    g = float(continuum.particle_parameters(args.ell, args.nu, args.Gamma, eps=args.eps).g)
    e_bulk = particle.bulk_energy_per_particle
    best = float(ansatz.finite_aggregates(particle, args.n).best_energy(g))
    ladder = geometric_temperatures(args.T_min * g, args.T_max * g, args.replicas)
    rounds = max(1, args.sweeps // args.replicas)
    moves = dict(method=args.method, tol=1e-3, cluster_moves=args.cluster_moves, cluster_link=args.cluster_link,
                 bonded_moves=args.bonded_moves, surface_moves=args.surface_moves)
    print(f"{machine_line()}\n{source_line()}")
    print(f"{args.n} particles in {args.box} x {args.box}, ell = {args.ell:g}, nu = {args.nu:g}, "
          f"Gamma = {args.Gamma:g} "
          f"(g = {g:.4g}); best single aggregate {best / e_bulk:.1f} bulk energies; {args.sweeps} sweeps per run; "
          f"ladder {args.T_min:g}..{args.T_max:g} g, {args.replicas} replicas x {rounds} rounds; {moves}")
    rows = []
    for seed in args.seeds:
        runs = {}
        cpu, wall = time.process_time(), time.perf_counter()
        a = anneal(particle, g=g, box=args.box, n=args.n, steps=args.sweeps * args.n, seed=seed, progress=False, **moves)
        runs["anneal"] = (a, time.process_time() - cpu, time.perf_counter() - wall, "")
        cpu, wall = time.process_time(), time.perf_counter()
        r = replica_exchange(particle, ladder, g=g, box=args.box, n=args.n, rounds=rounds, seed=seed, threads=args.threads,
                             progress=False, **moves)
        swaps = f"swaps {np.nanmin(r.swap_acceptance):.2f}-{np.nanmax(r.swap_acceptance):.2f}, {r.round_trips} trips"
        runs["replica exchange"] = (r, time.process_time() - cpu, time.perf_counter() - wall, swaps)
        base = runs["anneal"]
        for name, (res, cpu_s, wall_s, note) in runs.items():
            largest = max(len(c) for c in res.clusters())
            rows.append((seed, name, f"{(res.energy - best) / e_bulk:.1f}", f"{largest}", f"{cpu_s:.0f} s",
                         f"{wall_s:.0f} s", f"{cpu_s / base[1]:.2f}", note))
            print(rows[-1], flush=True)
    print()
    print(table(rows, ["seed", "run", "E - E_best (bulk energies)", "largest cluster", "CPU", "wall",
                       "CPU / anneal", "replica exchange"]))


if __name__ == "__main__":
    main()
