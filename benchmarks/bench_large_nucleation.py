"""When the large box's aggregates nucleate and when they fuse (issue 33, item 3).

The large runs at nu = 0.4 (rule ``montecarlo_large_run``) end in one aggregate of disks fused by
necks, where one disk is predicted. This reruns one such run, the workflow's chain (moves
``MOVES``, schedule ``window_schedule`` with config/config.yaml's ``large_collective``), block by
block, and every ``--every`` sweeps records the clusters: how many hold at least ``--nucleus``
particles (nuclei), the sizes of the four largest, the free particles (clusters of one), the
compact lobes of the largest (``analysis.compact_lobes``: disks joined by necks fall apart into one
each), with the block's temperature (in units of g) and energy. It then prints, from that trace,
the temperature where the first nucleus appears, the most nuclei seen at once, and when the
last two became one.

Writes a CSV per run (``--csv``, the trace; ``{nu}``, ``{Gamma}``, ``{seed}`` and ``{schedule}``
filled in) and prints the summary.

Usage: ``python benchmarks/bench_large_nucleation.py --nu 0.4 --Gamma 0.5 [--seed 1] [--sweeps 4000]
[--every 10] [--csv PATH]``
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import import_pyfrustrate, machine_line, source_line, write_csv  # noqa: E402

import numpy as np  # noqa: E402  (after _common, which pins BLAS to one thread)

from bench_large_control import MOVES  # noqa: E402  (the workflow's moves of the large runs)
from bench_large_runs import WINDOW  # noqa: E402  (the workflow's schedule of the large runs)

DEFAULT_CSV = Path(__file__).resolve().parent / "results" / "large_nucleation_nu{nu:g}_G{Gamma:g}_seed{seed}_{schedule}.csv"


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


def stages_for(args, g):
    """The schedule's stages: the workflow's window schedule (``--schedule window``), or
    ``--stages`` (``T:sweeps`` pairs, T in units of g; ``--schedule stages``)."""
    from pyfrustrate.montecarlo import window_schedule

    if args.schedule == "stages":
        pairs = [stage.split(":") for stage in args.stages]
        return [(float(t) * g, int(m) * args.n) for t, m in pairs]
    low, high = WINDOW["window"]
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
    options = MonteCarloOptions(**MOVES)
    stages = stages_for(args, g)
    temps = np.concatenate([np.full(-(-m // args.n), t) for t, m in stages])
    block_steps = np.concatenate([np.diff(np.r_[0:m:args.n, m]) for _, m in stages])
    mc = new_chain(particle, g, args.box, args.n, args.seed, options)
    rows, cpu, sweep = [], time.process_time(), 0
    for lo in range(0, len(temps), args.every):
        hi = min(len(temps), lo + args.every)
        out = mc.run(temps[lo:hi], block_steps[lo:hi], True)
        sweep = hi
        rows.append(dict(sweep=sweep, T_over_g=f"{temps[hi - 1] / g:.4f}", energy_over_g=f"{out['energy'][-1] / g:.2f}",
                         **cluster_row(out["sites"][-1], args.box, args.nucleus)))
    return rows, time.process_time() - cpu


def summary(rows, nucleus):
    """The first nucleus (sweep, T/g), the most nuclei at once, the last sweep with two or more."""
    first = next((r for r in rows if r["nuclei"] >= 1), None)
    most = max(rows, key=lambda r: r["nuclei"])
    several = [r for r in rows if r["nuclei"] >= 2]
    lines = [f"nuclei: clusters of at least {nucleus} particles"]
    if first is None:
        return "\n".join(lines + ["no nucleus formed"])
    lines.append(f"first nucleus at sweep {first['sweep']} (T = {first['T_over_g']} g), "
                 f"largest cluster {first['size1']}")
    lines.append(f"most nuclei at once: {most['nuclei']} at sweep {most['sweep']} (T = {most['T_over_g']} g), "
                 f"sizes {most['size1']}, {most['size2']}, {most['size3']}, {most['size4']}")
    if several:
        last = several[-1]
        lines.append(f"last sweep with two or more nuclei: {last['sweep']} (T = {last['T_over_g']} g)")
    end = rows[-1]
    lines.append(f"end: {end['nuclei']} nuclei, largest {end['size1']}, {end['lobes']} compact lobes, "
                 f"{end['free']} free particles")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--nu", type=float, default=0.4)
    ap.add_argument("--Gamma", type=float, default=0.5, help="measured convention")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--ell", type=float, default=5.0)
    ap.add_argument("--eps", type=float, default=0.01)
    ap.add_argument("--n", type=int, default=400)
    ap.add_argument("--box", type=int, default=85)
    ap.add_argument("--sweeps", type=int, default=4000)
    ap.add_argument("--schedule", choices=("window", "stages"), default="window")
    ap.add_argument("--stages", nargs="+", default=[], help="T:sweeps pairs, T in units of g (--schedule stages)")
    ap.add_argument("--every", type=int, default=10, help="sweeps between records")
    ap.add_argument("--nucleus", type=int, default=10, help="particles that make a cluster a nucleus")
    ap.add_argument("--csv", default=str(DEFAULT_CSV))
    args = ap.parse_args(argv)
    print(f"{machine_line()}\n{source_line()}")
    rows, cpu = trace(args)
    text = summary(rows, args.nucleus)
    print(text + f"\nCPU {cpu:.0f} s")
    path = Path(args.csv.format(nu=args.nu, Gamma=args.Gamma, seed=args.seed, schedule=args.schedule))
    write_csv(path, rows, parameters=dict(nu=args.nu, Gamma=args.Gamma, seed=args.seed, ell=args.ell, eps=args.eps,
                                          n=args.n, box=args.box, sweeps=args.sweeps, schedule=args.schedule,
                                          window=WINDOW, stages=args.stages, every=args.every, nucleus=args.nucleus, moves=MOVES,
                                          cpu_s=round(cpu)))


if __name__ == "__main__":
    main()
