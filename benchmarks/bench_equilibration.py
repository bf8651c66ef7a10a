"""Does annealing reach the ground state of its box? Cluster-move settings at equal sweeps (issue 15).

For each system, seed and setting (``cluster_moves``, ``cluster_link``, ``bonded_moves``,
``surface_moves``), ``pyfrustrate.anneal``
runs ``sweeps`` sweeps (Newton, tol 1e-3, linear schedule from T0 = g) and the final energy is
compared with the box's predicted ground state (``ground_states.box_candidates``: single
aggregates, a wrapping fibre, several aggregates, the gas), in bulk particle energies ``e_b``.
The issue's criterion is a gap below 5. The first setting is the baseline: ratios of gap and
CPU time are against it, for the same seed, measured in the same run.

Default system: 400 particles in 85 x 85 at ell = 5, eps = 0.01, nu = 0.9, Gamma = 0.3 (the case
of ``bench_replica_exchange.py``), settings ``0.02:1`` (the former workflow: whole clusters,
rejected on contact), ``0.02:0.8``, ``0.1:0.8`` and ``0.05:0.9:0.5``
(``cluster_moves:cluster_link[:bonded_moves[:surface_moves]]``).

Usage: ``python benchmarks/bench_equilibration.py [--quick] [--n 400 --box 85 --nu 0.9
--Gamma 0.3 --sweeps 4000 --settings 0.02:1 0.1:0.8 --seeds 1 2 3 --jobs 2]``
"""
from __future__ import annotations

import argparse
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import add_box_arguments, import_pyfrustrate, machine_line, source_line, table  # noqa: E402


def _setting(text):
    try:
        values = [float(x) for x in text.split(":")]
        if len(values) not in (2, 3, 4):
            raise ValueError
    except ValueError:
        raise argparse.ArgumentTypeError("a setting is cluster_moves:cluster_link[:bonded_moves[:surface_moves]], "
                                         f"got {text!r}") from None
    return tuple(values) + (0.0,) * (4 - len(values))


def _label(setting):
    """cluster_moves:cluster_link:bonded_moves:surface_moves, as given on the command line."""
    return ":".join(f"{x:g}" for x in setting)


def _run(args, seed, moves, link, bonded, surface):
    """One annealing run: (energy, largest cluster, structure, CPU seconds, counters)."""
    import_pyfrustrate()
    from pyfrustrate import Hexagon, anneal, continuum
    from pyfrustrate.ground_states import structure

    particle = Hexagon.from_continuum(args.ell, args.nu, args.eps)
    g = float(continuum.particle_parameters(args.ell, args.nu, args.Gamma, eps=args.eps).g)
    cpu = time.process_time()
    r = anneal(particle, g=g, box=args.box, n=args.n, steps=args.sweeps * args.n, seed=seed, method="newton",
               tol=1e-3, cluster_moves=moves, cluster_link=link, bonded_moves=bonded,
               surface_moves=surface, progress=False)
    cpu = time.process_time() - cpu
    return r.energy, max(len(c) for c in r.clusters()), structure(r.sites, args.box), cpu, r.counters


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="100 particles in 40 x 40, 1000 sweeps, one seed")
    add_box_arguments(ap)
    ap.add_argument("--settings", type=_setting, nargs="+",
                    default=[(0.02, 1.0, 0.0), (0.02, 0.8, 0.0), (0.1, 0.8, 0.0), (0.05, 0.9, 0.5)],
                    help="cluster_moves:cluster_link[:bonded_moves[:surface_moves]] (default 0); the first is the baseline")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--jobs", type=int, default=2, help="runs side by side (processes)")
    args = ap.parse_args(argv)
    if args.quick:
        args.n, args.box, args.sweeps, args.seeds = 100, 40, 1000, [1]
    import_pyfrustrate()
    from pyfrustrate import Hexagon, continuum
    from pyfrustrate.ground_states import box_candidates

    particle = Hexagon.from_continuum(args.ell, args.nu, args.eps)
    g = float(continuum.particle_parameters(args.ell, args.nu, args.Gamma, eps=args.eps).g)
    e_bulk = particle.bulk_energy_per_particle
    candidates = box_candidates(particle, args.n, args.box, method="newton", tol=1e-3)
    ground = float(candidates.best_energy(g))
    print(f"{machine_line()}\n{source_line()}")
    print(f"{args.n} particles in {args.box} x {args.box}, ell = {args.ell:g}, nu = {args.nu:g}, Gamma = {args.Gamma:g} "
          f"(g = {g:.4g}); predicted ground state: {candidates.best_family(g)}, {ground / e_bulk:.1f} e_b; "
          f"{args.sweeps} sweeps per run, {args.jobs} side by side")
    jobs = [(seed, *setting) for seed in args.seeds for setting in args.settings]
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        futures = {job: pool.submit(_run, args, *job) for job in jobs}
        results = {job: f.result() for job, f in futures.items()}
    rows, gaps = [], {}
    for seed, *setting in jobs:
        energy, largest, found, cpu, counters = results[(seed, *setting)]
        gap = (energy - ground) / e_bulk
        base_energy, _, _, base_cpu, _ = results[(seed, *args.settings[0])]
        base_gap = (base_energy - ground) / e_bulk
        gaps.setdefault(tuple(setting), []).append(gap)
        rows.append((seed, _label(setting), f"{gap:.1f}", f"{gap / base_gap:.2f}" if base_gap > 0 else "-",
                     found, largest, counters["cluster_rebonded"], f"{cpu:.0f} s", f"{cpu / base_cpu:.2f}"))
    print(table(rows, ["seed", "moves:link:bonded:surface", "gap (e_b)", "gap / baseline", "structure", "largest", "merges+splits",
                       "CPU", "CPU / baseline"]))
    print()
    print(table([(_label(setting), f"{sum(v) / len(v):.1f}", f"{sum(x < 5 for x in v)}/{len(v)}")
                 for setting, v in gaps.items()], ["moves:link:bonded:surface", "mean gap (e_b)", "within 5 e_b"]))


if __name__ == "__main__":
    main()
