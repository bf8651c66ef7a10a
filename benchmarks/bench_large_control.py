"""The control of the large box's runs (issue 33, item 3): a run seeded in its box's predicted
ground state, put through only the window dwell and the quench of the workflow's schedule, then
the descent at T = 0 (``montecarlo.descend``).

The workflow's large runs (rule ``montecarlo_large_run``) start from a gas. Where they end outside
the energy gate, or in another structure, either the search failed (the ground state is never
reached) or the gate asks for more than the dwell and quench can keep (the predicted outline,
bond-maximal, is entropically suppressed wherever the aggregate still moves, and a quench leaves
the state it finds). This control tells them apart: if even the predicted state, put through the
same dwell, quench and descent, ends outside the gate or in another structure, the verdict
measures the dwell's entropy, not the search. Its runs are diagnostics, never the verdict's.

Defaults: the quick profile's large box (400 particles in 85 x 85, 4000 sweeps, the window
0.15-0.3 g, dwell 0.8, quench 0.005 of the sweeps, the moves of ``large_collective``) at the
points where its runs missed. The box's candidates are read from the workflow's finite-size
prediction (``--candidates``, the rule ``montecarlo_finite_aggregates``' file) when it exists,
else built (``ground_states.box_candidates``).

Writes a CSV (``--csv``, default ``benchmarks/results/large_control.csv``), one row per point.

Usage: ``python benchmarks/bench_large_control.py [--points 0.4,0.5 0.9,0.5] [--csv PATH]``
"""
from __future__ import annotations

import argparse
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import import_pyfrustrate, machine_line, source_line, table, write_csv  # noqa: E402

import numpy as np  # noqa: E402  (after _common, which pins BLAS to one thread)

DEFAULT_CSV = Path(__file__).resolve().parent / "results" / "large_control.csv"
#: The moves of config/config.yaml's large runs (montecarlo: cluster_*, large_*_moves, large_collective).
MOVES = dict(method="newton", tol=1e-3, cluster_moves=0.05, cluster_link=0.9, bonded_moves=0.3, surface_moves=0.3,
             shift_moves=0.05, rotation_moves=0.05, reflection_moves=0.05, isometry_link=0.3, vacancy_moves=0.05)


def candidates_for(args, particle, nu):
    """The box's candidate ground states and the bulk energy per particle."""
    from pyfrustrate.ground_states import BoxCandidates, box_candidates
    path = Path(args.candidates.format(n=args.n, nu=nu))
    if path.is_file():
        with np.load(path, allow_pickle=False) as f:
            return BoxCandidates.from_arrays(f), float(f["bulk_energy_per_particle"])
    return box_candidates(particle, args.n, args.box, method="newton", tol=1e-3), particle.bulk_energy_per_particle


def control(args, nu, Gamma):
    """One point: its row of the CSV."""
    import_pyfrustrate()
    from pyfrustrate import Hexagon, anneal, continuum
    from pyfrustrate.ground_states import structure_verdict
    from pyfrustrate.montecarlo import MonteCarloOptions, descend, window_schedule
    from pyfrustrate.montecarlo.fixed_size import seeded_state

    particle = Hexagon.from_continuum(args.ell, nu, eps=args.eps)
    g = float(continuum.particle_parameters(args.ell, nu, Gamma, eps=args.eps).g)
    candidates, bulk = candidates_for(args, particle, nu)
    best = int(candidates.best(g))
    predicted = candidates.sites[best]
    options = MonteCarloOptions(**MOVES)
    low, high = args.window
    # The run's dwell and quench alone: the same moves as the run's window_schedule gives them
    # (dwell + quench = 1 skips the entry), starting at the window's top.
    part = args.dwell + args.quench
    stages = window_schedule((low * g, high * g), args.n, sweeps=round(args.sweeps * part), T0=high * g,
                             dwell=args.dwell / part, quench=args.quench / part)
    cpu = time.process_time()
    state = seeded_state(particle, predicted, args.box, args.seed, g=g, options=options)
    run = anneal(particle, g=g, box=args.box, n=args.n, seed=args.seed, schedule=stages, options=options, state=state,
                 progress=False)
    final, rounds, still = descend(particle, run, options=options, sweeps_per_round=args.descent_sweeps,
                                   max_rounds=args.descent_rounds)
    cpu = time.process_time() - cpu
    quench_blocks = -(-stages[-1][1] // args.n)
    end_of_dwell = float(run.energy_trace[-quench_blocks - 1])
    verdict = structure_verdict(final.sites, args.box, candidates, g, final.energy, bulk)

    def gap(energy):  # above the prediction, bulk energies
        return f"{(energy - float(candidates.best_energy(g))) / bulk:.2f}"

    return dict(nu=nu, Gamma=Gamma, seed=args.seed, n=args.n, box=args.box,
                dwell_sweeps=sum(m for _, m in stages[:-1]) // args.n, gap_end_of_dwell=gap(end_of_dwell),
                gap_after_quench=gap(run.energy), gap_after_descent=gap(final.energy),
                gap_gate=f"{verdict['gap_gate']:.2f}", gap_ok=verdict["gap_ok"], descent_rounds=rounds,
                descent_converged=still, bonds=final.bonds, bonds_predicted=int(candidates.bonds[best]),
                count=verdict["count"], count_predicted=verdict["count_predicted"], kind=verdict["kind"],
                kind_predicted=verdict["kind_predicted"], structure_match=verdict["structure_match"],
                structure_within_gate=verdict["structure_within_gate"],
                below_prediction=verdict["below_prediction"], cpu_s=f"{cpu:.0f}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--points", nargs="+", default=["0.4,0.2", "0.4,0.5", "0.9,0.5", "0.9,0.8"],
                    help="nu,Gamma pairs (Gamma in the measured convention)")
    ap.add_argument("--ell", type=float, default=5.0)
    ap.add_argument("--eps", type=float, default=0.01)
    ap.add_argument("--n", type=int, default=400)
    ap.add_argument("--box", type=int, default=85)
    ap.add_argument("--sweeps", type=int, default=4000,
                    help="the run's whole schedule; the control runs its dwell and quench")
    ap.add_argument("--window", type=float, nargs=2, default=(0.15, 0.3), help="in units of g")
    ap.add_argument("--dwell", type=float, default=0.8)
    ap.add_argument("--quench", type=float, default=0.005)
    ap.add_argument("--descent-sweeps", type=int, default=20)
    ap.add_argument("--descent-rounds", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--candidates", default="results/montecarlo/finite/n{n}_nu{nu:g}.npz")
    ap.add_argument("--jobs", type=int, default=1, help="points side by side (processes)")
    ap.add_argument("--csv", type=Path, default=DEFAULT_CSV)
    args = ap.parse_args(argv)
    print(f"{machine_line()}\n{source_line()}")
    points = [tuple(float(x) for x in point.split(",")) for point in args.points]
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        rows = list(pool.map(control, [args] * len(points), *zip(*points)))
    print(table([tuple(str(v) for v in row.values()) for row in rows], list(rows[0])))
    write_csv(args.csv, rows, parameters=dict(ell=args.ell, eps=args.eps, n=args.n, box=args.box, sweeps=args.sweeps,
                                              window=list(args.window), dwell=args.dwell, quench=args.quench,
                                              descent_sweeps=args.descent_sweeps,
                                              descent_rounds=args.descent_rounds, moves=MOVES))


if __name__ == "__main__":
    main()
