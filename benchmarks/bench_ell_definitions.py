"""Boundary-layer length of random particles: how much the paper's statements depend on what
"ell" means (``pyfrustrate.boundary_layer``).

For each definition, on one sample of the paper's random matrices:

* ``P(ell>=1.5)``        the fraction of draws in the paper's largest-ell group (paper: 0.42 %);
* ``med pred/ell``       the median ell_pred / ell (paper: ell_pred "tends to overestimate" ell, > 1);
* ``P(pred>ell)``        the fraction with ell_pred > ell;
* per ell group (< 1, 1-1.5, >= 1.5): its share of the draws, its median nu, P(nu < -0.5);
* the time per particle of the definition, and its ratio to the exact slowest mode measured in
  the same run.

Definitions: (a) ``slowest`` mode of the half-plane (the package's default), (b)
``excited_share{s}`` the slowest mode carrying at least a share ``s`` of the edge displacement,
(c) ``finite_depth{D}_{reference}`` the paper's protocol literally: a slab of D rows relaxed
nonlinearly at eps = 0.01, the excess energy per particle relative to the slab's central row or
to the exact bulk, fitted log-linearly from the second row to the centre.

Usage: ``python benchmarks/bench_ell_definitions.py [--quick] [--n N] [--seed S] [--save FILE.npz]``
(default 100000 particles, about 5 min on one core; --quick: 2000).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import fmt_time, import_pyfrustrate, machine_line, source_line, table  # noqa: E402

import numpy as np  # noqa: E402

PAPER = {"P_above": 0.0042, "median_ratio": "> 1"}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="2000 particles instead of 100000")
    ap.add_argument("--n", type=int, default=None, help="number of particles")
    ap.add_argument("--seed", type=int, default=2025, help="sample seed (the workflow's random.seed)")
    ap.add_argument("--save", type=Path, default=None, help="write every particle's lengths here (.npz)")
    args = ap.parse_args(argv)
    import_pyfrustrate()
    from pyfrustrate import boundary_layer as bl
    from pyfrustrate import random_particles as rp

    n = args.n or (2000 if args.quick else 100_000)
    print(f"{machine_line()}\n{source_line()}\n{n} particles of sample {args.seed}")
    Ms = rp.elasticity_matrices(n, args.seed)
    t0 = time.perf_counter()
    study = bl.compare_definitions(Ms, progress=sys.stderr.isatty())
    total = time.perf_counter() - t0
    # Per-definition cost on a sub-sample (the study interleaves them).
    sub = Ms[: min(n, 300)]
    t_slowest = _per_particle(lambda: rp.boundary_layer_lengths(sub), len(sub))
    t_excited = _per_particle(lambda: [bl.excited_boundary_layer_length(M) for M in sub], len(sub))
    t_depth = {D: _per_particle(lambda D=D: [bl.finite_depth_boundary_layer_length(M, D) for M in sub], len(sub))
               for D in (10, 20, 40)}
    summary = bl.summarise(study)
    rows = []
    for name, row in summary.items():
        if name == "slowest":
            cost = t_slowest
        elif name.startswith("excited"):
            cost = t_excited
        else:
            cost = t_depth[int(name[len("finite_depth"):].split("_")[0])]
        rows.append((name, f"{100 * row['P_above']:.2f} %", f"{row['median_ratio']:.3f}",
                     f"{100 * row['above_one']:.1f} %",
                     " / ".join(f"{100 * row[f'group{g}_fraction']:.1f}" for g in range(3)),
                     " / ".join(f"{row[f'group{g}_median_nu']:.2f}" for g in range(3)),
                     " / ".join(f"{100 * row[f'group{g}_P_nu_below_-0.5']:.2f}" for g in range(3)),
                     f"{100 * row['not_decaying']:.2f} %", fmt_time(cost), f"{cost / t_slowest:.0f}"))
    print()
    print(table(rows, ["definition", "P(ell>=1.5)", "med pred/ell", "P(pred>ell)", "groups % of draws",
                       "median nu by group", "P(nu<-0.5) % by group", "no decay", "time/particle", "x slowest"]))
    print(f"\npaper: P(ell>=1.5) = {100 * PAPER['P_above']:.2f} %, median ell_pred/ell {PAPER['median_ratio']}; "
          f"study {total:.0f} s")
    if args.save:
        np.savez(args.save, **{k: np.asarray(v) for k, v in study.items()}, seed=args.seed)


def _per_particle(fn, count):
    t0 = time.perf_counter()
    fn()
    return (time.perf_counter() - t0) / count


if __name__ == "__main__":
    main()
