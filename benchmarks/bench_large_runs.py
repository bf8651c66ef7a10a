"""The large box's runs (issue 33, item 3; rule ``montecarlo_large_run``): where their CPU goes, and
what the parent cluster's factor (``MonteCarloOptions.parent_factor``) saves on them.

The paper profile's large runs (800 hexagons in 120 x 120, 15 000 sweeps of ``window_schedule``,
then ``montecarlo.descend``) end in one aggregate of ~800 particles, which every move that
reaches it relaxes whole. This runs the same chain, the workflow's moves and schedule
(``MOVES``, ``WINDOW``: config/config.yaml's ``large_collective``, which config/paper.yaml keeps),
on a shortened schedule (``--sweeps``), in two modes:

``--profile``  one run stage by stage (each stage of the schedule, then each round of the
               descent, a call of ``anneal`` continuing the chain's state): per stage its
               temperature, sweeps, process CPU, attempted moves per CPU second, and the chain's
               counters over the stage (screened by the bond count, bounded, relaxed, cache hits,
               factorisations, runs on the parent's factor), the largest cluster at its end; a
               text table (``--out``) and a CSV (``--csv``).
``--compare``  the whole shortened run (schedule and descent) with each of ``--variants``
               alternately, A B A B (``--repeats`` rounds), in this process: ``workflow`` the rule's
               moves without the parent's factor, ``parentK`` the same with ``parent_factor=True,
               parent_factor_min_particles=K``; a suffix ``+screened`` puts rounds at
               ``descent_temperature`` g (``descend(temperature=)``, moves that break bonds screened
               out) before the descent at T = 0, as the rule does. Per run: process CPU of the
               schedule and of the descent (screened rounds included), their ratios to the first
               variant's run of the same round, relaxations and
               ms per relaxation, the final energy and bonds, the largest cluster, and the
               energy recomputed from scratch (``box_energy``: every cluster relaxed anew without
               the cache) against the chain's running sum. The chains with and without the
               parent's factor relax to the same tolerance but not to the same last bits, so at
               T = 0 a bond-neutral move may go either way: they need not stay identical (equal
               relaxation counts and energies show where they did), and their final energies are
               compared. A CSV (``--csv``) with provenance.

Usage: ``python benchmarks/bench_large_runs.py --profile [--sweeps 1500] [--out FILE]``,
``python benchmarks/bench_large_runs.py --compare [--sweeps 400] [--variants workflow parent64+screened]
[--repeats 2] [--descent-rounds 20] [--csv benchmarks/results/large_runs.csv]`` (the rule's options today:
``parent64+screened``; the commands that wrote the committed CSVs are listed in docs/conf.py, ``measured_sources``)
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
from pyfrustrate import Hexagon, anneal, continuum  # noqa: E402
from pyfrustrate.io import atomic_path  # noqa: E402
from pyfrustrate.montecarlo import MonteCarloOptions, descend, window_schedule  # noqa: E402
from pyfrustrate.montecarlo.annealing import AnnealState  # noqa: E402
from pyfrustrate.montecarlo.driver import new_chain  # noqa: E402

from bench_large_control import MOVES  # noqa: E402  (the workflow's moves of the large runs)

#: config/config.yaml's large_collective schedule (config/paper.yaml keeps it): the window in
#: units of g, the fractions of the sweeps in it and at T = 0, the descent's rounds.
WINDOW = dict(window=(0.15, 0.3), dwell=0.8, quench=0.005, descent_sweeps=20, descent_rounds=20,
              descent_temperature=0.01)
#: The counters a stage reports, as differences over the stage.
COUNTERS = ("attempted", "accepted", "screened", "bounded", "minimisations", "cache_hits", "cache_misses",
            "factorizations", "warm_starts", "warm_restarts", "parent_relaxations", "parent_fresh")


def variant_options(name: str) -> tuple[MonteCarloOptions, float]:
    """The chain's options and the temperature of the screened rounds before the descent (in units
    of g; 0: none) of a variant: ``workflow`` (the rule's moves, no parent factor) or ``parentK``
    (with the parent's factor, clusters of at least K particles keeping theirs), each optionally
    with ``+screened`` (rounds at ``WINDOW["descent_temperature"]`` before the descent at T = 0)."""
    options, _, suffix = name.partition("+")
    if suffix not in ("", "screened"):
        raise ValueError(f"variants: the only suffix is '+screened', got {name!r}")
    screened = WINDOW["descent_temperature"] if suffix else 0.0
    if options == "workflow":
        return MonteCarloOptions(**MOVES), screened
    if options.startswith("parent") and options[len("parent"):].isdigit():
        return (MonteCarloOptions(**MOVES, parent_factor=True, parent_factor_min_particles=int(options[len("parent"):])),
                screened)
    raise ValueError(f"variants: expected 'workflow' or 'parentK' (K an integer), optionally '+screened', got {name!r}")


def largest_cluster(result) -> int:
    return max(len(c) for c in result.clusters())


def continue_run(particle, g, args, options, stages, previous):
    """``anneal`` over ``stages`` from ``previous`` (an AnnealResult, or None: a new chain)."""
    state = None if previous is None else AnnealState(done=0, chain=previous.state.chain, energy_trace=np.zeros(0),
                                                      accepted=np.zeros(0, np.int64))
    return anneal(particle, g=g, box=args.box, n=args.n, seed=args.seed, schedule=stages, options=options, state=state,
                  progress=False)


def stage_row(label, T_over_g, sweeps, cpu, before, after, largest, energy, g):
    d = {k: after[k] - (before[k] if before else 0) for k in COUNTERS}
    relaxed = max(d["minimisations"], 1)
    return dict(stage=label, T_over_g=f"{T_over_g:.3f}", sweeps=sweeps, cpu_s=f"{cpu:.1f}",
                moves_per_s=f"{d['attempted'] / max(cpu, 1e-9):.0f}",
                screened=f"{d['screened'] / max(d['attempted'], 1):.3f}", bounded=d["bounded"],
                relaxations=d["minimisations"], relaxations_per_sweep=f"{d['minimisations'] / max(sweeps, 1e-9):.1f}",
                ms_per_relaxation=f"{1e3 * cpu / relaxed:.2f}", cache_hits=d["cache_hits"],
                factorizations_per_relaxation=f"{d['factorizations'] / relaxed:.2f}", parent=d["parent_relaxations"],
                parent_fresh=d["parent_fresh"],
                accepted=d["accepted"], largest=largest, energy_over_g=f"{energy / g:.1f}")


def schedule_for(args, g):
    low, high = WINDOW["window"]
    return window_schedule((low * g, high * g), args.n, sweeps=args.sweeps, T0=g, dwell=WINDOW["dwell"],
                           quench=WINDOW["quench"])


def profile(args, particle, g):
    options, screened = variant_options(args.variants[0])
    rows, result = [], None
    for k, (T, moves) in enumerate(schedule_for(args, g)):
        before = None if result is None else dict(result.counters)
        cpu = time.process_time()
        result = continue_run(particle, g, args, options, [(T, moves)], result)
        cpu = time.process_time() - cpu
        rows.append(stage_row(f"schedule {k}", T / g, moves / args.n, cpu, before, result.counters,
                              largest_cluster(result), result.energy, g))
        print(rows[-1], flush=True)
    for label, T_over_g in (("screened", screened), ("descent", 0.0)) if screened else (("descent", 0.0),):
        for k in range(args.descent_rounds):  # descend's rounds, one at a time
            before = dict(result.counters)
            cpu = time.process_time()
            result, _, still = descend(particle, result, options=options, sweeps_per_round=WINDOW["descent_sweeps"],
                                       max_rounds=1, temperature=T_over_g * g)
            cpu = time.process_time() - cpu
            rows.append(stage_row(f"{label} {k + 1}", T_over_g, WINDOW["descent_sweeps"], cpu, before, result.counters,
                                  largest_cluster(result), result.energy, g))
            print(rows[-1], flush=True)
            if still:
                break
    total = sum(float(r["cpu_s"]) for r in rows)
    descent = sum(float(r["cpu_s"]) for r in rows if not r["stage"].startswith("schedule"))
    header = (f"# Profile of one large run, stage by stage (benchmarks/bench_large_runs.py --profile): {args.n} hexagons"
              f" in {args.box} x {args.box}, ell = {args.ell}, eps = {args.eps}, nu = {args.nu}, Gamma = {args.Gamma}, "
              f"seed {args.seed}, {args.sweeps} sweeps of window_schedule {WINDOW} and at most {args.descent_rounds} rounds "
              f"of the descent, options "
              f"'{args.variants[0]}' ({options.signature()})\n# {_common.machine_line()}\n# {_common.source_line()}\n"
              f"# process CPU: {total:.0f} s in all, {descent:.0f} s ({100 * descent / max(total, 1e-9):.0f} %) in the "
              f"descent; screened = fraction of attempted moves rejected by the bond count alone; relaxations = "
              f"clusters relaxed (cache misses); largest = largest cluster at the stage's end\n")
    text = header + _common.table([tuple(r.values()) for r in rows], list(rows[0])) + "\n"
    print(text)
    if args.out:
        with atomic_path(args.out) as tmp:
            Path(tmp).write_text(text)
        print(f"wrote {args.out}")
    if args.csv:
        _common.write_csv(args.csv, rows, dict(benchmark="bench_large_runs --profile", **run_parameters(args)))


def one_run(args, particle, g, name):
    options, screened = variant_options(name)
    cpu = time.process_time()
    run = continue_run(particle, g, args, options, schedule_for(args, g), None)
    schedule_cpu = time.process_time() - cpu
    result, screened_rounds = run, 0
    if screened:  # as workflow/scripts/montecarlo_run.py: screened rounds, then the descent at T = 0
        result, screened_rounds, _ = descend(particle, run, options=options, sweeps_per_round=WINDOW["descent_sweeps"],
                                             max_rounds=args.descent_rounds, temperature=screened * g)
    result, rounds, converged = descend(particle, result, options=options, sweeps_per_round=WINDOW["descent_sweeps"],
                                        max_rounds=args.descent_rounds)
    descent_cpu = time.process_time() - cpu - schedule_cpu
    c = result.counters
    scratch = new_chain(particle, g, args.box, args.n, args.seed, options, state=result.state.chain).box_energy()
    return dict(variant=name, schedule_cpu_s=schedule_cpu, descent_cpu_s=descent_cpu,
                cpu_s=schedule_cpu + descent_cpu, screened_rounds=screened_rounds, descent_rounds=rounds,
                descent_converged=converged, relaxations=c["minimisations"],
                ms_per_relaxation=1e3 * (schedule_cpu + descent_cpu) / max(c["minimisations"], 1),
                parent_relaxations=c["parent_relaxations"], parent_fresh=c["parent_fresh"],
                factorizations=c["factorizations"], schedule_energy_over_g=run.energy / g,
                energy_over_g=result.energy / g, bonds=result.bonds, largest=largest_cluster(result),
                scratch_energy_over_g=scratch / g, running_minus_scratch_over_g=(result.energy - scratch) / g)


def compare(args, particle, g):
    rows = []
    for repeat in range(args.repeats):
        baseline = None
        for name in args.variants:
            row = dict(repeat=repeat, **one_run(args, particle, g, name))
            if name == args.variants[0]:
                baseline = row
            for part in ("schedule_cpu_s", "descent_cpu_s", "cpu_s"):
                row[f"{part[:-2]}_ratio"] = row[part] / baseline[part] if baseline else float("nan")
            rows.append(row)
            print({k: f"{v:.4g}" if isinstance(v, float) else v for k, v in row.items()}, flush=True)
    print(_common.table([tuple(f"{v:.4g}" if isinstance(v, float) else v for v in r.values()) for r in rows],
                        list(rows[0])))
    worst = max(abs(r["running_minus_scratch_over_g"]) for r in rows)
    print(f"largest |running - recomputed| energy: {worst:.2e} g")
    if args.csv:
        _common.write_csv(args.csv, rows, dict(benchmark="bench_large_runs --compare", repeats=args.repeats,
                                               **run_parameters(args)))


def run_parameters(args) -> dict:
    """What a CSV's provenance records of the runs."""
    return dict(n=args.n, box=args.box, ell=args.ell, eps=args.eps, nu=args.nu, Gamma=args.Gamma, seed=args.seed,
                sweeps=args.sweeps, moves=MOVES, window=WINDOW, descent_rounds=args.descent_rounds,
                variants=args.variants)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--profile", action="store_true")
    mode.add_argument("--compare", action="store_true")
    _common.add_box_arguments(ap, sweeps=1500)  # --sweeps: of the shortened window_schedule
    ap.set_defaults(n=800, box=120, Gamma=0.5)  # the paper profile's large box (config/paper.yaml)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--variants", nargs="+", default=["workflow", "parent64+screened"],
                    help="'workflow' or 'parentK'; the first is the baseline (--profile: the one profiled)")
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--descent-rounds", type=int, default=WINDOW["descent_rounds"],
                    help="most rounds of the descent (the workflow's by default; fewer to keep a profile short)")
    ap.add_argument("--out", type=Path, default=None, help="--profile: the table's text file")
    ap.add_argument("--csv", type=Path, default=None, help="the rows as CSV (--profile: one per stage; --compare: one per run)")
    args = ap.parse_args(argv)
    for name in args.variants:
        variant_options(name)  # a bad name fails before any run
    particle = Hexagon.from_continuum(args.ell, args.nu, eps=args.eps)
    g = float(continuum.particle_parameters(args.ell, args.nu, args.Gamma, eps=args.eps).g)
    print(f"{_common.machine_line()}\n{_common.source_line()}")
    (profile if args.profile else compare)(args, particle, g)


if __name__ == "__main__":
    main()
