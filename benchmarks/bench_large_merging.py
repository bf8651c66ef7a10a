"""The large box's runs before and after a change of their moves (issue 33, item 3): structure,
energy gap and CPU, run for run.

Each run is the workflow's (rule ``montecarlo_large_run``, quick profile: 400 hexagons in 85 x 85,
4000 sweeps): ``window_schedule`` with config/config.yaml's ``large_collective``, the screened
rounds at ``descent_temperature`` and the descent at T = 0 (``montecarlo.descend``), the chain's
relaxation with the parent's factor (``bench_large_runs.variant_options("parent64+screened")``),
judged by ``ground_states.structure_verdict`` against the box's candidates (read from the
workflow's finite-size prediction, ``--candidates``, when it exists, else built). A variant is
``workflow`` (the rule's moves as they were) or ``key=value[,key=value...]``, fields of
``MonteCarloOptions`` that replace the workflow's.

Runs go one at a time, in this process; each row is written to the CSV (``--csv``) as soon as
its run ends, and rows already in the file (same variant, nu, Gamma, seed) are kept and not
rerun, so an interrupted measurement resumes; a file written with other parameters (moves
included) is measured afresh.

Usage: ``python benchmarks/bench_large_merging.py --variants workflow hop_moves=0.05
[--points 0.4,0.5 0.4,0.8] [--seeds 1 2 3] [--csv benchmarks/results/large_merging.csv]``
"""
from __future__ import annotations

import argparse
import csv
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import import_pyfrustrate, machine_line, source_line, table, write_csv  # noqa: E402

from bench_large_control import MOVES, candidates_for  # noqa: E402  (the workflow moves; the box's candidate ground states)
from bench_large_runs import WINDOW, variant_options  # noqa: E402  (the workflow's schedule and chain)

DEFAULT_CSV = Path(__file__).resolve().parent / "results" / "large_merging.csv"
#: The quick profile's large runs: the disk scan at nu = 0.4 and the fibre scan at nu = 0.9, over
#: large_scan_Gamma (config/config.yaml).
QUICK_POINTS = ["0.4,0.2", "0.4,0.5", "0.4,0.8", "0.9,0.2", "0.9,0.5", "0.9,0.8"]


def options_of(variant: str):
    """The chain's options of a variant and the screened rounds' temperature (in units of g)."""
    import dataclasses

    options, screened = variant_options("parent64+screened")
    if variant == "workflow":
        return options, screened
    overrides = {}
    for item in variant.split(","):
        key, _, value = item.partition("=")
        field = next((f for f in dataclasses.fields(options) if f.name == key), None)
        if field is None or not value:
            raise ValueError(f"variants: {item!r} is not key=value of a MonteCarloOptions field")
        overrides[key] = type(getattr(options, key))(value)
    return dataclasses.replace(options, **overrides), screened


def large_run(args, variant, nu, Gamma, seed):
    """One run, as the workflow's: its row of the CSV."""
    import_pyfrustrate()
    from pyfrustrate import Hexagon, anneal, continuum
    from pyfrustrate.ground_states import structure_verdict
    from pyfrustrate.montecarlo import descend, window_schedule

    particle = Hexagon.from_continuum(args.ell, nu, eps=args.eps)
    g = float(continuum.particle_parameters(args.ell, nu, Gamma, eps=args.eps).g)
    candidates, bulk = candidates_for(args, particle, nu)
    options, screened = options_of(variant)
    low, high = WINDOW["window"]
    stages = window_schedule((low * g, high * g), args.n, sweeps=args.sweeps, T0=g, dwell=WINDOW["dwell"],
                             quench=WINDOW["quench"])
    cpu = time.process_time()
    run = anneal(particle, g=g, box=args.box, n=args.n, seed=seed, schedule=stages, options=options, progress=False)
    rounds = dict(sweeps_per_round=WINDOW["descent_sweeps"], max_rounds=WINDOW["descent_rounds"])
    near, _, _ = descend(particle, run, options=options, temperature=screened * g, **rounds)
    final, _, still = descend(particle, near, options=options, **rounds)
    cpu = time.process_time() - cpu
    verdict = structure_verdict(final.sites, args.box, candidates, g, final.energy, bulk)
    return dict(variant=variant, nu=nu, Gamma=Gamma, seed=seed, structure_match=verdict["structure_match"],
                kind=verdict["kind"], kind_predicted=verdict["kind_predicted"], count=verdict["count"],
                count_predicted=verdict["count_predicted"], gap=f"{verdict['gap']:.2f}",
                gap_gate=f"{verdict['gap_gate']:.2f}", gap_ok=verdict["gap_ok"], descent_converged=still,
                cpu_s=f"{cpu:.0f}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--variants", nargs="+", default=["workflow"])
    ap.add_argument("--points", nargs="+", default=QUICK_POINTS, help="nu,Gamma pairs (Gamma in the measured convention)")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1])
    ap.add_argument("--ell", type=float, default=5.0)
    ap.add_argument("--eps", type=float, default=0.01)
    ap.add_argument("--n", type=int, default=400)
    ap.add_argument("--box", type=int, default=85)
    ap.add_argument("--sweeps", type=int, default=4000)
    ap.add_argument("--candidates", default="results/montecarlo/finite/n{n}_nu{nu:g}.npz")
    ap.add_argument("--csv", type=Path, default=DEFAULT_CSV)
    args = ap.parse_args(argv)
    print(f"{machine_line()}\n{source_line()}")
    parameters = dict(ell=args.ell, eps=args.eps, n=args.n, box=args.box, sweeps=args.sweeps, window=WINDOW,
                      moves=MOVES)
    rows = []
    if args.csv.is_file():
        import_pyfrustrate()
        from pyfrustrate.io import read_provenance
        written = (read_provenance(args.csv) or {}).get("parameters")
        if written == json.loads(json.dumps(parameters)):
            with open(args.csv, newline="") as fh:
                rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
        else:
            print(f"{args.csv}: written with other parameters ({written}); measuring afresh")
    done = {(r["variant"], float(r["nu"]), float(r["Gamma"]), int(r["seed"])) for r in rows}
    for seed in args.seeds:
        for point in args.points:
            nu, Gamma = (float(x) for x in point.split(","))
            for variant in args.variants:
                if (variant, nu, Gamma, seed) in done:
                    continue
                rows.append(large_run(args, variant, nu, Gamma, seed))
                print(", ".join(f"{k} {v}" for k, v in rows[-1].items()), flush=True)
                write_csv(args.csv, rows, parameters=parameters)
    print(table([tuple(str(v) for v in row.values()) for row in rows], list(rows[0])))


if __name__ == "__main__":
    main()
