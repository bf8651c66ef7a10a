"""Goals (b) and (c) of issue 32: Monte Carlo annealings with exact (Newton, tol 1e-3) cluster
energies and the workflow's moves (cluster_moves 0.05, cluster_link 0.9), seed 1:

(b) dense box: 300 hexagons in 30 x 30, ell = 5, nu = 0.4, Gamma = 0.5, 10^4 sweeps, goal 2 min
    of CPU;
(c) sparse box: 200 in 60 x 60, 10^4 sweeps, goal 10 s, at (nu, Gamma) = (0.4, 0.1), the
    slowest case measured, and (0.9, 0.5).

Each run is made up to three times in the same process, alternately (``--starts``): with the
parent clusters' factors modified (``parent``: ``warm_start=True, parent_factor=True``, clusters
of at least ``--parent-min-particles`` keeping theirs), with the Monte Carlo's warm starts from
the parent clusters alone (``warm``: ``warm_start=True``, anneal's default, the parent path's
baseline) and cold (``warm_start=False``, each cluster from the linear solution), so that the
table carries its own baselines. ``--baseline DIR`` also runs each configuration with another
build of the package (``DIR`` holding its ``pyfrustrate/``, e.g. ``pip install --no-deps
--target DIR`` of an earlier commit), in a child process, alternately with this one (column
``build``: ``this`` or ``baseline``); this build then runs in a child process too, so both pay
the same start-up. Times are process
CPU. Per run: sweeps, CPU seconds, seconds per 10^4 sweeps (measured, or scaled linearly when
``--sweeps`` is below 10^4, which the table says), the goal and the ratio to it, relaxations,
factorisations and milliseconds per relaxation, and the final energy.

Usage: ``python benchmarks/bench_mc_goals.py [--dense-sweeps 10000] [--sparse-sweeps 10000]
[--starts parent warm cold] [--parent-min-particles 0] [--baseline DIR] [--csv benchmarks/results/mc_goals.csv]
[--quick]``
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _common  # noqa: E402  (pins BLAS threads before numpy is imported)

pyfrustrate = _common.import_pyfrustrate()
from pyfrustrate import Hexagon, continuum  # noqa: E402

from bench_montecarlo import ELL, EPS, WORKFLOW_MOVES, exact_annealing  # noqa: E402

# start: the options it passes to anneal
STARTS = {
    "parent": dict(warm_start=True, parent_factor=True),
    "warm": dict(warm_start=True),
    "cold": dict(warm_start=False),
}

# name: (n, box, nu, Gamma, goal in CPU seconds per 10^4 sweeps)
RUNS = {
    "b dense": (300, 30, 0.4, 0.5, 120.0),
    "c sparse nu=0.4 Gamma=0.1": (200, 60, 0.4, 0.1, 10.0),
    "c sparse nu=0.9 Gamma=0.5": (200, 60, 0.9, 0.5, 10.0),
}


def one_run(name, start, sweeps, seed, parent_min_particles):
    """(CPU seconds, energy, counters) of one annealing of RUNS[name] with STARTS[start]."""
    n, box, nu, Gamma, _ = RUNS[name]
    particle = Hexagon.from_continuum(ell=ELL, nu=nu, eps=EPS)
    g = float(continuum.particle_parameters(ELL, nu, Gamma, eps=EPS).g)
    extra = dict(parent_factor_min_particles=parent_min_particles) if start == "parent" else {}
    cpu, r = exact_annealing(particle, g, box, n, sweeps, seed, **STARTS[start], **extra, **WORKFLOW_MOVES)
    return cpu, float(r.energy), dict(r.counters)


def run_in_child(package_dir, name, start, sweeps, seed, parent_min_particles):
    """one_run in a child process whose pyfrustrate comes from package_dir (None: this one's)."""
    env = dict(os.environ)
    if package_dir is not None:
        env["PYTHONPATH"] = os.pathsep.join([str(Path(package_dir).resolve())] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    out = subprocess.run([sys.executable, __file__, "--child", name, start, str(sweeps), str(seed), str(parent_min_particles)],
                         env=env, check=True, capture_output=True, text=True).stdout
    cpu, energy, counters = json.loads(out.strip().splitlines()[-1])
    return cpu, energy, counters


def main(argv=None):
    if argv is None and len(sys.argv) > 1 and sys.argv[1] == "--child":
        name, start, sweeps, seed, parent_min_particles = sys.argv[2:7]
        print(json.dumps(one_run(name, start, int(sweeps), int(seed), int(parent_min_particles))))
        return
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dense-sweeps", type=int, default=10_000)
    ap.add_argument("--sparse-sweeps", type=int, default=10_000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--only", choices=sorted(RUNS), nargs="+", default=sorted(RUNS))
    ap.add_argument("--csv", type=Path, default=None)
    ap.add_argument("--quick", action="store_true", help="20 sweeps each")
    ap.add_argument("--starts", choices=sorted(STARTS), nargs="+", default=["parent", "warm", "cold"])
    ap.add_argument("--parent-min-particles", type=int, default=0,
                    help="parent: clusters smaller than this relax without their parent's factor")
    ap.add_argument("--baseline", type=Path, default=None,
                    help="a directory holding another build's pyfrustrate/, run alternately with this one")
    args = ap.parse_args(argv)
    if args.baseline is not None and not (args.baseline / "pyfrustrate" / "__init__.py").is_file():
        ap.error(f"--baseline: {args.baseline} holds no pyfrustrate/ package")
    print(f"{_common.machine_line()}\n{_common.source_line()}")
    print(f"Exact (Newton) cluster energies at tol 1e-3, moves {WORKFLOW_MOVES}, seed {args.seed}; process CPU")
    builds = {"this": None} if args.baseline is None else {"this": None, "baseline": args.baseline}
    rows = []
    for name in args.only:
        n, box, nu, Gamma, goal = RUNS[name]
        sweeps = 20 if args.quick else (args.dense_sweeps if name.startswith("b") else args.sparse_sweeps)
        for start in args.starts:
            for build, package_dir in builds.items():
                if args.baseline is None:
                    cpu, energy, c = one_run(name, start, sweeps, args.seed, args.parent_min_particles)
                else:
                    cpu, energy, c = run_in_child(package_dir, name, start, sweeps, args.seed, args.parent_min_particles)
                m = max(1, c["minimisations"])
                per = cpu * 10_000 / sweeps
                rows.append({
                    "run": name, "start": start, "build": build,
                    "parent_min_particles": args.parent_min_particles if start == "parent" else "", "n": n, "box": box,
                    "nu": nu, "Gamma": Gamma, "sweeps": sweeps, "cpu_s": cpu, "cpu_s_per_1e4_sweeps": per,
                    "scaled": sweeps != 10_000, "goal_s": goal, "over_goal": per / goal,
                    "attempted": c["attempted"], "screened": c["screened"], "accepted": c["accepted"],
                    "relaxations": c["minimisations"], "bounded": c.get("bounded", 0),
                    "factorizations_per_relaxation": c["factorizations"] / m,
                    "evaluations_per_relaxation": c["evaluations"] / m,
                    "ms_per_relaxation": 1e3 * cpu / m, "warm_restarts": c["warm_restarts"],
                    "parent_relaxations": c["parent_relaxations"], "parent_fresh": c["parent_fresh"],
                    "parent_chord_steps": c["parent_chord_steps"], "parent_refactorizations": c["parent_refactorizations"],
                    "unconverged": c["unconverged"], "energy": energy,
                })
                print(f"  {name:28s} {start:6s} {build:8s}: {cpu:7.1f} s for {sweeps} sweeps -> {per:7.1f} s per 10^4"
                      f"{' (scaled)' if sweeps != 10_000 else ''}, {per / goal:5.2f} x the {goal:g} s goal; "
                      f"{c['minimisations']:,} relaxations ({rows[-1]['bounded']:,} moves bounded), "
                      f"{c['factorizations'] / m:.2f} factorisations and {1e3 * cpu / m:.2f} ms each", flush=True)
    if args.csv:
        _common.write_csv(args.csv, rows, {"benchmark": "bench_mc_goals", "seed": args.seed,
                                           "baseline": str(args.baseline) if args.baseline else None})


if __name__ == "__main__":
    main()
