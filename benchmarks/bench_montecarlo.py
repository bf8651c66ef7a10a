"""Benchmark of the Monte Carlo annealing (issue #5, main text "Monte-Carlo validation of the
phase diagram"): 200 particles in a 60 x 60 box at ell = 5, eps = 0.01, Gamma = 0.5, for
nu = 0.9 (fibres) and nu = 0.4 (disks).

For each parameter set:

1. one paper-size annealing run (``pyfrustrate.anneal`` with its former defaults, ``FORMER_DEFAULTS``:
   L-BFGS cluster energies at tol 1e-3 warm-started from the linear solve, particle moves only, cluster
   cache, delayed acceptance, linear schedule from T0 = g to 0): its time, final energy and
   clusters, cache hit rate and counters;
2. attempted moves per second from two states of the system, a mid-annealing one (a random
   placement quenched for 200 sweeps at T = 0.6 g: many small clusters) and the final annealed
   one (at T = 0.3 g: a few large aggregates), each from a cold cache, for:

   ``full``          delayed acceptance + cache + incremental clusters (the defaults)
   ``metropolis``    plain Metropolis + cache + incremental
   ``no cache``      plain Metropolis, incremental, every touched cluster re-minimised
   ``naive``         plain Metropolis, every cluster of the box re-minimised on every move
   and the same with ``method='lbfgs'`` (warm start from the linear solution or cold from the
   bulk reference);
3. the paper-size run again with cluster translations (``--cluster-moves``, default 0.02, the
   workflow's setting): time ratio, final energy and clusters against the particle-move run.

Ratios are printed from the same run. Rates use process CPU time (the kernel is single-threaded;
the machine may be shared), wall time is shown too.

``--exact``: only the exact (Newton) cluster energies of the workflow's runs, dense (300 particles
in 30 x 30, nu = 0.4) and sparse (200 in 60 x 60, nu = 0.9), ell = 5, eps = 0.01, Gamma = 0.5,
tol 1e-3, cluster_moves 0.02, seed 1 (config/paper.yaml): the warm-started path (``warm_start=True``,
anneal's default: each move's clusters relaxed from their parents' relaxed displacements) against
the cold one (``warm_start=False``: from the linear solution of the canonical representative),
alternately A B A B in the same run, each an annealing of ``--exact-sweeps`` sweeps (the whole
linear schedule, compressed): CPU time, minimisations, Newton factorisations and evaluations per
minimisation, time per minimisation, the time extrapolated to 10^4 sweeps (linearly; the true
10^4-sweep run coarsens further and relaxes larger clusters, so this is a lower bound), the
ratio, and the final energies of the two paths.

``--goals``: the issue's speed targets with the workflow's moves (cluster_moves 0.05, cluster_link
0.9): sparse paper-size runs of ``--sweeps`` sweeps at nu = 0.9 and 0.4 over Gamma from 0.1 to 1.3
against 30 s, the dense run of ``--exact-sweeps`` sweeps extrapolated to 10^4 against 2 minutes.

Usage: ``python benchmarks/bench_montecarlo.py [--sweeps 10000] [--quick]``,
``python benchmarks/bench_montecarlo.py --exact [--exact-sweeps 500] [--repeats 2]``,
``python benchmarks/bench_montecarlo.py --goals [--sweeps 10000] [--exact-sweeps 500]``
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _common  # noqa: E402  (pins BLAS threads before numpy is imported)

import numpy as np  # noqa: E402

pyfrustrate = _common.import_pyfrustrate()
from pyfrustrate import Hexagon, _kernel, continuum  # noqa: E402

BOX, N, ELL, EPS, GAMMA = 60, 200, 5.0, 0.01, 0.5

MODES = {
    # name: (method, delayed_acceptance, cache, warm_start, incremental)
    "full": ("linear", True, True, True, True),
    "metropolis": ("linear", False, True, True, True),
    "no cache": ("linear", False, False, True, True),
    "naive": ("linear", False, False, True, False),
    "lbfgs full": ("lbfgs", True, True, True, True),
    "lbfgs metropolis": ("lbfgs", False, True, True, True),
    "lbfgs no cache": ("lbfgs", False, False, True, True),
    "lbfgs no cache, cold": ("lbfgs", False, False, False, True),
    "lbfgs naive": ("lbfgs", False, False, True, False),
}


def make(particle, g, seed, method, delayed, cache, warm, incremental):
    return _kernel.MonteCarlo(particle._kernel_model, g, BOX, N, seed, method=method,
                              tol=1e-5, force_scale=particle.force_scale, cache=cache, warm_start=warm,
                              cluster_moves=0.0, bonded_moves=0.0, surface_moves=0.0,
                              incremental=incremental, delayed_acceptance=delayed,
                              bond_deformation=particle.bulk_energy_per_particle / 3)


def rate(particle, g, sites, T, mode, budget, min_moves, max_moves):
    """Attempted moves per CPU second from ``sites`` at temperature ``T`` (cold cache)."""
    mc = make(particle, g, 12345, *MODES[mode])
    mc.place(sites)
    c0 = mc.counters
    cpu, wall, moves, block = time.process_time(), time.perf_counter(), 0, 10
    while moves < max_moves:
        mc.run(np.array([T]), np.array([block]))
        moves += block
        spent = time.process_time() - cpu
        if moves >= min_moves and spent >= budget:
            break
        block = int(min(max(10, block * 2), max_moves - moves)) or 1
    spent, wall = time.process_time() - cpu, time.perf_counter() - wall
    c = mc.counters
    hits, misses = c["cache_hits"] - c0["cache_hits"], c["cache_misses"] - c0["cache_misses"]
    return dict(moves=moves, cpu=spent, wall=wall, rate=moves / spent,
                minimisations=(c["minimisations"] - c0["minimisations"]) / moves,
                hit_rate=hits / (hits + misses) if hits + misses else float("nan"))


EXACT_RUNS = {"dense": (300, 30, 0.4), "sparse": (200, 60, 0.9)}
# anneal's defaults until its defaults became the best measured settings (MonteCarloOptions):
# this benchmark's baseline run, and the moves the exact runs add theirs to.
FORMER_DEFAULTS = dict(method="lbfgs", cluster_moves=0.0, cluster_link=1.0, bonded_moves=0.0, surface_moves=0.0)


def exact_annealing(particle, g, box, n, sweeps, seed, **moves):
    """(CPU seconds, result) of one annealing with exact (Newton) cluster energies at tol 1e-3."""
    cpu = time.process_time()
    r = pyfrustrate.anneal(particle, g=g, box=box, n=n, steps=n * sweeps, seed=seed, tol=1e-3, progress=False,
                           **dict(FORMER_DEFAULTS, method="newton", **moves))
    return time.process_time() - cpu, r


def exact_energies(sweeps, repeats, seed):
    """Warm (parent) against cold starts of the Newton cluster energies, A B A B."""
    print(f"{_common.machine_line()}\n{_common.source_line()}")
    print(f"Exact (Newton) cluster energies, ell = {ELL}, eps = {EPS}, Gamma = {GAMMA}, tol 1e-3, cluster_moves 0.02, "
          f"seed {seed}: annealings of {sweeps} sweeps, warm (parent) and cold starts alternately, {repeats} each")
    for kind, (n, box, nu) in EXACT_RUNS.items():
        particle = Hexagon.from_continuum(ell=ELL, nu=nu, eps=EPS)
        g = float(continuum.particle_parameters(ELL, nu, GAMMA, eps=EPS).g)
        runs = {True: [], False: []}
        for _ in range(repeats):
            for warm in (True, False):
                runs[warm].append(exact_annealing(particle, g, box, n, sweeps, seed, cluster_moves=0.02,
                                                  warm_start=warm))
        print(f"\n=== {kind}: {n} particles in {box} x {box}, nu = {nu}, g = {g:.5g}")
        print(f"  {'start':6s} {'CPU s min/med/max':>20s} {'10^4 sweeps':>11s} {'minimis.':>9s} {'fact./min':>9s} "
              f"{'eval./min':>9s} {'ms/min':>7s} {'warm':>6s}  final energy")
        best = {}
        for warm, label in ((True, "warm"), (False, "cold")):
            times = sorted(t for t, _ in runs[warm])
            r = runs[warm][0][1]
            c = r.counters
            m = max(1, c["minimisations"])
            best[warm] = times[0]
            print(f"  {label:6s} {times[0]:6.2f} {times[len(times) // 2]:6.2f} {times[-1]:6.2f} "
                  f"{times[0] * 10_000 / sweeps:9.0f} s {c['minimisations']:9d} {c['factorizations'] / m:9.2f} "
                  f"{c['evaluations'] / m:9.2f} {1e3 * times[0] / m:7.2f} {c['warm_starts'] / m:6.2f}  {r.energy:.10g}")
        pairs = [a[0] / b[0] for a, b in zip(runs[False], runs[True])]
        w, cold = runs[True][0][1], runs[False][0][1]
        print(f"  cold/warm CPU time: {best[False] / best[True]:.2f} (pairs {', '.join(f'{x:.2f}' for x in pairs)}); "
              f"final energies differ by {abs(w.energy - cold.energy) / abs(cold.energy):.1e} relative, same final "
              f"sites: {sorted(map(tuple, w.sites.tolist())) == sorted(map(tuple, cold.sites.tolist()))}")


GOAL_GAMMAS = (0.1, 0.2, 0.35, 0.5, 0.8, 1.3)
WORKFLOW_MOVES = dict(cluster_moves=0.05, cluster_link=0.9)  # config/config.yaml's montecarlo


def speed_goals(sweeps, dense_sweeps, seed):
    """The speed targets of the Monte Carlo issue, exact (Newton) energies at tol 1e-3 with the
    workflow's moves: a sparse paper-size run (200 in 60 x 60, 10^4 sweeps) under 30 s, at
    nu = 0.9 and 0.4 over the diagram's range of Gamma; a dense one (300 in 30 x 30, 10^4
    sweeps) under 2 minutes, extrapolated from ``dense_sweeps`` (a lower bound, as above)."""
    print(f"{_common.machine_line()}\n{_common.source_line()}")
    print(f"Speed goals, exact (Newton) energies at tol 1e-3, moves {WORKFLOW_MOVES}, seed {seed}, CPU seconds")
    for nu in (0.9, 0.4):
        particle = Hexagon.from_continuum(ell=ELL, nu=nu, eps=EPS)
        for Gamma in GOAL_GAMMAS:
            g = float(continuum.particle_parameters(ELL, nu, Gamma, eps=EPS).g)
            cpu, r = exact_annealing(particle, g, BOX, N, sweeps, seed, **WORKFLOW_MOVES)
            print(f"  sparse nu = {nu}, Gamma = {Gamma:4}: {cpu:6.1f} s for {sweeps} sweeps, "
                  f"{cpu * 10_000 / sweeps / 30:.2f} x the 30 s goal; {r.counters['minimisations']:,} relaxations")
    n, box, nu = EXACT_RUNS["dense"]
    particle = Hexagon.from_continuum(ell=ELL, nu=nu, eps=EPS)
    g = float(continuum.particle_parameters(ELL, nu, GAMMA, eps=EPS).g)
    cpu, r = exact_annealing(particle, g, box, n, dense_sweeps, seed, **WORKFLOW_MOVES)
    c = r.counters
    print(f"  dense nu = {nu}, Gamma = {GAMMA}: {cpu:.1f} s for {dense_sweeps} sweeps, {cpu * 10_000 / dense_sweeps:.0f} s "
          f"per 10^4 (lower bound), {cpu * 10_000 / dense_sweeps / 120:.1f} x the 2 min goal; "
          f"{c['minimisations']:,} relaxations, {c['factorizations'] / max(1, c['minimisations']):.2f} factorisations "
          f"each, {1e3 * cpu / max(1, c['minimisations']):.2f} ms each; warm restarts {c['warm_restarts']}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sweeps", type=int, default=10_000, help="sweeps (n moves each) of the paper-size run")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--budget", type=float, default=2.0, help="CPU seconds per rate measurement")
    ap.add_argument("--quick", action="store_true", help="short run and measurements (smoke test)")
    ap.add_argument("--cluster-moves", type=float, default=0.02, help="cluster_moves of the comparison run")
    ap.add_argument("--exact", action="store_true",
                    help="only the exact-energy (Newton) runs, dense and sparse: warm against cold starts")
    ap.add_argument("--exact-sweeps", type=int, default=500, help="sweeps of each --exact annealing")
    ap.add_argument("--repeats", type=int, default=2, help="runs of each path with --exact")
    ap.add_argument("--goals", action="store_true",
                    help="only the issue's speed targets: sparse runs over Gamma (10^4 sweeps), the dense run extrapolated")
    args = ap.parse_args(argv)
    if args.goals:
        speed_goals(200 if args.quick else args.sweeps, 30 if args.quick else args.exact_sweeps, args.seed)
        return
    if args.exact:
        exact_energies(100 if args.quick else args.exact_sweeps, 1 if args.quick else args.repeats, args.seed)
        return
    if args.quick:
        args.sweeps, args.budget = 500, 0.3
    print(f"{_common.machine_line()}\n{_common.source_line()}")
    print(f"Monte Carlo benchmark: {N} particles in {BOX} x {BOX}, ell = {ELL}, eps = {EPS}, Gamma = {GAMMA}; "
          f"paper-size run of {args.sweeps} sweeps ({args.sweeps * N:,} attempted moves)")
    for nu in (0.9, 0.4):
        particle = Hexagon.from_continuum(ell=ELL, nu=nu, eps=EPS)
        g = float(continuum.particle_parameters(ELL, nu, GAMMA, eps=EPS).g)
        print(f"\n=== nu = {nu}, Gamma = {GAMMA}: g = {g:.5g}, bulk deformation per particle = "
              f"{particle.bulk_energy_per_particle:.4g}")
        cpu, wall = time.process_time(), time.perf_counter()
        res = pyfrustrate.anneal(particle, g=g, box=BOX, n=N, steps=args.sweeps * N, seed=args.seed, progress=False,
                                 **FORMER_DEFAULTS)
        cpu, wall = time.process_time() - cpu, time.perf_counter() - wall
        c = res.counters
        sizes = [len(x) for x in res.clusters()]
        print(f"paper-size run: {cpu:.1f} s CPU ({wall:.1f} s wall), {args.sweeps * N / cpu:,.0f} moves/s; "
              f"E = {res.energy:.5g}, {res.bonds} bonds; clusters {sizes[:8]}{' ...' if len(sizes) > 8 else ''}")
        print(f"  acceptance by tenth of the run {np.round(res.stage_acceptance, 3).tolist()}")
        print(f"  screened {c['screened'] / c['attempted']:.3f} of moves; cache hit rate {res.cache_hit_rate:.3f} "
              f"({c['cache_hits']:,} hits, {c['cache_misses']:,} misses); {c['minimisations']:,} minimisations "
              f"({c['minimisations'] / c['attempted']:.4f} per move)")

        # The same run with cluster translations (anneal's cluster_moves, the workflow's setting):
        # same Boltzmann distribution, aggregates meet instead of ripening by evaporation.
        cpu_cm = time.process_time()
        cm = pyfrustrate.anneal(particle, g=g, box=BOX, n=N, steps=args.sweeps * N, seed=args.seed, progress=False,
                                **dict(FORMER_DEFAULTS, cluster_moves=args.cluster_moves))
        cpu_cm = time.process_time() - cpu_cm
        sizes_cm = [len(x) for x in cm.clusters()]
        print(f"with cluster_moves = {args.cluster_moves:g}: {cpu_cm:.1f} s CPU ({cpu_cm / cpu:.2f}x the run above); E = {cm.energy:.5g} "
              f"(change {(cm.energy - res.energy) / particle.bulk_energy_per_particle:+.1f} bulk particle energies); "
              f"clusters {sizes_cm[:8]}{' ...' if len(sizes_cm) > 8 else ''}; "
              f"{cm.counters['cluster_accepted']:,} of {cm.counters['cluster_attempted']:,} translations accepted")

        mid = make(particle, g, args.seed + 1, *MODES["full"])
        mid.run(np.array([0.6 * g]), np.array([200 * N]))
        states = {"mid (T=0.6g)": (mid.particles, 0.6 * g), "final (T=0.3g)": (res.sites, 0.3 * g)}
        for label, (sites, T) in states.items():
            n_clusters = len(pyfrustrate.montecarlo.clusters(sites, BOX))
            print(f"\n  moves/s from the {label} state ({n_clusters} clusters, largest "
                  f"{len(pyfrustrate.montecarlo.clusters(sites, BOX)[0][0])}), cold cache:")
            print(f"  {'mode':22s} {'moves':>8s} {'CPU s':>7s} {'moves/s':>10s} {'min./move':>10s} {'hit rate':>8s}")
            rates = {}
            for mode in MODES:
                slow = MODES[mode][4] is False or (MODES[mode][2] is False and MODES[mode][0] == "lbfgs")
                r = rate(particle, g, sites, T, mode, args.budget, min_moves=20 if slow else 200,
                         max_moves=2_000 if slow else 400_000)
                rates[mode] = r["rate"]
                print(f"  {mode:22s} {r['moves']:8d} {r['cpu']:7.2f} {r['rate']:10.0f} {r['minimisations']:10.4f} "
                      f"{r['hit_rate']:8.3f}")
            print(f"  ratios: full/naive {rates['full'] / rates['naive']:.0f}x, full/no cache "
                  f"{rates['full'] / rates['no cache']:.0f}x, metropolis(cache)/no cache "
                  f"{rates['metropolis'] / rates['no cache']:.1f}x, delayed acceptance/metropolis "
                  f"{rates['full'] / rates['metropolis']:.1f}x, no cache/naive {rates['no cache'] / rates['naive']:.1f}x; "
                  f"lbfgs full/naive {rates['lbfgs full'] / rates['lbfgs naive']:.0f}x, lbfgs warm/cold "
                  f"{rates['lbfgs no cache'] / rates['lbfgs no cache, cold']:.1f}x")


if __name__ == "__main__":
    main()
