"""When the large box's aggregates nucleate and whether they fuse (issue 33, item 3).

The large runs at nu = 0.4 (rule ``montecarlo_large_run``) end in one aggregate of disks fused by
necks, where one disk is predicted. This reruns such a run, the workflow's chain (moves
``MOVES``, with ``--moves key=value`` overrides), block by block, and every ``--every`` sweeps
records the clusters: how many hold at least ``--nucleus`` particles (nuclei), the sizes of the
four largest, the free particles (clusters of one), the compact lobes of the largest
(``analysis.compact_lobes``: disks joined by necks fall apart into one each), with the block's
temperature (in units of g) and energy (over g). The schedule is the workflow's
(``--schedule window``: ``window_schedule`` with config/config.yaml's ``large_collective``) or
given stages (``--schedule stages --stages T:sweeps ...``, T in units of g), started from the gas
or, with ``--seeded``, from the box's predicted ground state (its candidates from the workflow's
finite-size prediction, ``--candidates``).

Writes the trace as a CSV (``--csv``) and, with ``--label``, one row summing it up into
``--summary`` (default ``benchmarks/results/large_nucleation.csv``; the row of that label
replaced): the first nucleus (sweep, T), the most nuclei at once, the last sweep with two or
more, the second half of the last stage (its temperature, the mean, least and most nuclei, the
mean energy and free particles) and the end (nuclei, largest cluster, its lobes), the CPU seconds.

Usage: ``python benchmarks/bench_large_nucleation.py --nu 0.4 --Gamma 0.5 [--seed 1] [--schedule stages
--stages 1:50 0.6:1500] [--seeded] [--moves cluster_moves=0] [--every 20] [--csv PATH] [--label NAME]``;
the commands behind the committed files: ``measured_sources`` in docs/conf.py.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import add_box_arguments, import_pyfrustrate, machine_line, source_line, write_csv  # noqa: E402

import numpy as np  # noqa: E402  (after _common, which pins BLAS to one thread)

from bench_large_control import MOVES, candidates_for  # noqa: E402  (the workflow's moves of the large runs)
from bench_large_runs import WINDOW  # noqa: E402  (the workflow's schedule of the large runs)

DEFAULT_CSV = Path(__file__).resolve().parent / "results" / "large_nucleation" / "trace_nu{nu:g}_G{Gamma:g}_seed{seed}.csv"
DEFAULT_SUMMARY = Path(__file__).resolve().parent / "results" / "large_nucleation.csv"


def cluster_row(sites_index, box, nucleus):
    """Nuclei, the four largest sizes, free particles and the largest's lobes of one configuration
    given as the kernel's site indices (``i + box j``)."""
    from pyfrustrate.montecarlo.analysis import clusters, compact_lobes

    s = np.asarray(sites_index)
    coords = np.column_stack([s % box, s // box])
    found = clusters(coords, box)
    sizes = [len(c) for c, _ in found]
    largest, rank = found[0]
    lobes = len(compact_lobes(largest)) if rank == 0 else 0
    top = (sizes + [0] * 4)[:4]
    return dict(nuclei=sum(k >= nucleus for k in sizes), size1=top[0], size2=top[1], size3=top[2], size4=top[3],
                free=sum(k == 1 for k in sizes), lobes=lobes)


def moves_for(args):
    """The workflow's moves (``MOVES``) with ``--moves key=value`` overrides."""
    overrides = dict(item.split("=") for item in args.moves)
    return {**MOVES, **{key: type(MOVES.get(key, 0.0))(value) for key, value in overrides.items()}}


def stages_for(args, g):
    """The schedule's stages: the workflow's window schedule (``--schedule window``), or
    ``--stages`` (``T:sweeps`` pairs, T in units of g; ``--schedule stages``)."""
    from pyfrustrate.montecarlo import window_schedule

    if args.schedule == "stages":
        pairs = [stage.split(":") for stage in args.stages]
        return [(float(t) * g, int(m) * args.n) for t, m in pairs]
    low, high = args.window or WINDOW["window"]
    return window_schedule((low * g, high * g), args.n, sweeps=args.sweeps, T0=g, dwell=WINDOW["dwell"],
                           quench=WINDOW["quench"])


def trace(args):
    """The run, recorded: rows of the CSV, and the process CPU seconds."""
    import_pyfrustrate()
    from pyfrustrate import Hexagon, continuum
    from pyfrustrate.montecarlo import MonteCarloOptions
    from pyfrustrate.montecarlo.driver import new_chain

    particle = Hexagon.from_continuum(args.ell, args.nu, eps=args.eps)
    g = float(continuum.particle_parameters(args.ell, args.nu, args.Gamma, eps=args.eps).g)
    options = MonteCarloOptions(**moves_for(args))
    stages = stages_for(args, g)
    temps = np.concatenate([np.full(-(-m // args.n), t) for t, m in stages])
    block_steps = np.concatenate([np.diff(np.r_[0:m:args.n, m]) for _, m in stages])
    state = None
    if args.seeded or args.sites_from:  # the box's predicted ground state, or a run's end, instead of the gas
        from pyfrustrate.montecarlo.fixed_size import seeded_state

        if args.sites_from:
            with np.load(args.sites_from, allow_pickle=False) as f:
                sites = f["sites"]
        else:
            candidates, _ = candidates_for(args, particle, args.nu)
            sites = candidates.sites[int(candidates.best(g))]
        state = seeded_state(particle, sites, args.box, args.seed, g=g, options=options).chain
    mc = new_chain(particle, g, args.box, args.n, args.seed, options, state=state)
    rows, cpu, sweep = [], time.process_time(), 0
    for lo in range(0, len(temps), args.every):
        hi = min(len(temps), lo + args.every)
        out = mc.run(temps[lo:hi], block_steps[lo:hi], True)
        sweep = hi
        rows.append(dict(sweep=sweep, T_over_g=f"{temps[hi - 1] / g:.4f}", energy_over_g=f"{out['energy'][-1] / g:.2f}",
                         **cluster_row(out["sites"][-1], args.box, args.nucleus)))
    return rows, time.process_time() - cpu


def summary(rows):
    """The trace in one row: the first nucleus (sweep, T/g), the most nuclei at once, the last
    sweep with two or more, the second half of the last stage (its temperature; mean, least and
    most nuclei; mean energy and free particles) and the end (nuclei, largest, compact lobes)."""
    first = next((r for r in rows if r["nuclei"] >= 1), rows[-1])
    most = max(rows, key=lambda r: r["nuclei"])
    several = [r for r in rows if r["nuclei"] >= 2]
    last_stage = [r for r in rows if r["T_over_g"] == rows[-1]["T_over_g"]]
    tail = last_stage[len(last_stage) // 2:]
    nuclei = [r["nuclei"] for r in tail]
    end = rows[-1]
    return dict(first_nucleus_sweep=first["sweep"], first_nucleus_T_over_g=first["T_over_g"], nuclei_most=most["nuclei"],
                nuclei_most_T_over_g=most["T_over_g"], last_several_sweep=several[-1]["sweep"] if several else 0,
                last_T_over_g=end["T_over_g"], last_nuclei_mean=f"{np.mean(nuclei):.1f}", last_nuclei_least=min(nuclei),
                last_nuclei_most=max(nuclei), last_energy_over_g=f"{np.mean([float(r['energy_over_g']) for r in tail]):.1f}",
                last_free_mean=f"{np.mean([r['free'] for r in tail]):.1f}", end_nuclei=end["nuclei"],
                end_largest=end["size1"], end_lobes=end["lobes"])


def update_summary(path, label, row, parameters):
    """Put ``row`` (with its ``label``) into the summary CSV at ``path``, replacing that label's."""
    import csv

    rows = []
    if path.is_file():
        with open(path, newline="") as fh:
            rows = [r for r in csv.DictReader(line for line in fh if not line.startswith("#")) if r["label"] != label]
    rows.append(dict(label=label, **row))
    write_csv(path, rows, parameters=parameters)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_box_arguments(ap)  # the quick profile's large box; Gamma in the measured convention
    ap.set_defaults(nu=0.4, Gamma=0.5)  # the failing large run, not the equilibration case
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--schedule", choices=("window", "stages"), default="window")
    ap.add_argument("--window", type=float, nargs=2, default=None,
                    help="the window schedule's window, in units of g (default: the workflow's)")
    ap.add_argument("--stages", nargs="+", default=[], help="T:sweeps pairs, T in units of g (--schedule stages)")
    ap.add_argument("--moves", nargs="+", default=[], help="key=value overrides of the workflow's moves")
    ap.add_argument("--seeded", action="store_true", help="start from the box's predicted ground state")
    ap.add_argument("--sites-from", default="", help="start from the sites of this run file (npz, 'sites')")
    ap.add_argument("--candidates", default="results/montecarlo/finite/n{n}_nu{nu:g}.npz",
                    help="the box's candidates (the workflow's finite-size prediction), for --seeded")
    ap.add_argument("--every", type=int, default=10, help="sweeps between records")
    ap.add_argument("--nucleus", type=int, default=10, help="particles that make a cluster a nucleus")
    ap.add_argument("--csv", default=str(DEFAULT_CSV))
    ap.add_argument("--label", default="", help="this run's row in --summary (none: no summary row)")
    ap.add_argument("--summary", default=str(DEFAULT_SUMMARY))
    args = ap.parse_args(argv)
    print(f"{machine_line()}\n{source_line()}")
    rows, cpu = trace(args)
    row = dict(nu=args.nu, Gamma=args.Gamma, seed=args.seed, start="seeded" if args.seeded else (Path(args.sites_from).name or "gas"),
               schedule=(f"window {' '.join(f'{t:g}' for t in args.window or WINDOW['window'])}" if args.schedule == "window"
                         else " ".join(args.stages)),
               moves=" ".join(args.moves) or "workflow", **summary(rows), cpu_s=f"{cpu:.0f}")
    print("\n".join(f"{key}: {value}" for key, value in row.items()))
    path = Path(args.csv.format(nu=args.nu, Gamma=args.Gamma, seed=args.seed))
    write_csv(path, rows, parameters=dict(nu=args.nu, Gamma=args.Gamma, seed=args.seed, ell=args.ell, eps=args.eps,
                                          n=args.n, box=args.box, sweeps=args.sweeps, schedule=args.schedule,
                                          window=WINDOW, window_override=args.window, stages=args.stages, seeded=args.seeded,
                                          sites_from=args.sites_from, every=args.every, nucleus=args.nucleus, moves=moves_for(args),
                                          cpu_s=round(cpu)))
    if args.label:
        update_summary(Path(args.summary), args.label, row, parameters=dict(ell=args.ell, eps=args.eps, n=args.n, box=args.box,
                                                                            every=args.every, nucleus=args.nucleus))


if __name__ == "__main__":
    main()
