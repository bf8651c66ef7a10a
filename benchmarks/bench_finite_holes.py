"""The finite-size prediction with and without rings (``finite_hole_fraction``): what the holes cost
and what they find.

``ground_states.box_candidates(particle, n, box, hole_fraction=f)`` for ``f = 0`` (the solid
shapes only) and the default ``f`` (every shape with each complete hexagonal hole up to ``f n``
sites as the single aggregate, the compact shapes with holes as the parts of several),
alternately, A B (``--repeats`` rounds), at each case ``n:box:ell:nu``: the quick profile's box,
and 400 particles at ell = 2.5, where a strip of them is only about ten W* long. Per run: the
process CPU and its ratio to the solid run of the same round, the number of candidates, and at
each ``--Gamma`` how far the best candidate lies below the best solid one, in bulk particle
energies (0: the holes change nothing there), its family and the empty sites it encloses.

Usage: ``python benchmarks/bench_finite_holes.py [--cases 200:60:5:0.9 400:85:2.5:0.9]
[--repeats 2] [--csv benchmarks/results/finite_holes.csv]`` (the command that wrote the committed
CSV is listed in docs/conf.py, ``measured_sources``)
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import _common  # noqa: E402  (pins BLAS threads before numpy is imported)

_common.import_pyfrustrate()
import numpy as np  # noqa: E402

from pyfrustrate import Hexagon, ansatz, continuum  # noqa: E402
from pyfrustrate.ground_states import box_candidates  # noqa: E402


def parse_case(text):
    n, box, ell, nu = text.split(":")
    return int(n), int(box), float(ell), float(nu)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", nargs="+", default=["200:60:5:0.9", "400:85:2.5:0.9"])
    ap.add_argument("--Gamma", type=float, nargs="+", default=[0.2, 0.3, 0.5, 0.8])
    ap.add_argument("--hole-fraction", type=float, default=ansatz.FINITE_HOLE_FRACTION)
    ap.add_argument("--eps", type=float, default=0.01)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--csv")
    args = ap.parse_args()
    print(f"# {_common.machine_line()}\n# {_common.source_line()}")
    rows = []
    for case in args.cases:
        n, box, ell, nu = parse_case(case)
        particle = Hexagon.from_continuum(ell, nu, eps=args.eps)
        e_bulk = particle.bulk_energy_per_particle
        g = np.array([float(continuum.particle_parameters(ell, nu, G, eps=args.eps).g) for G in args.Gamma])
        for repeat in range(args.repeats):
            runs, cpu = {}, {}
            for variant, fraction in (("solid", 0.0), ("holes", args.hole_fraction)):
                t0 = time.process_time()
                runs[variant] = box_candidates(particle, n, box, hole_fraction=fraction)
                cpu[variant] = time.process_time() - t0
            for variant, fraction in (("solid", 0.0), ("holes", args.hole_fraction)):
                candidates = runs[variant]
                for G, gk in zip(args.Gamma, g):
                    best = candidates.best(gk)
                    rows.append(dict(case=case, n=n, box=box, ell=ell, nu=nu, variant=variant, repeat=repeat,
                                     hole_fraction=fraction, cpu_s=cpu[variant], cpu_ratio=cpu[variant] / cpu["solid"],
                                     candidates=len(candidates.family), Gamma=G,
                                     gain_over_solid=float(runs["solid"].best_energy(gk) - candidates.best_energy(gk))
                                     / e_bulk, best_family=str(candidates.family[best]),
                                     enclosed_sites=enclosed_sites(candidates.sites[best], box)))
                    print("  ".join(f"{v:.4g}" if isinstance(v, float) else str(v) for v in rows[-1].values()),
                          flush=True)
    for case in args.cases:
        per_round = {r["repeat"]: r["cpu_ratio"] for r in rows if r["case"] == case and r["variant"] == "holes"}
        ratios = sorted(per_round.values())
        gains = {r["Gamma"]: r["gain_over_solid"] for r in rows if r["case"] == case and r["variant"] == "holes"}
        print(f"# {case}: holes / solid CPU {ratios[len(ratios) // 2]:.3f} (median of {len(ratios)}); gain in bulk "
              f"energies by Gamma {', '.join(f'{G:g}: {x:.2f}' for G, x in gains.items())}")
    if args.csv:
        _common.write_csv(args.csv, rows, dict(benchmark="bench_finite_holes", **{
            k: v for k, v in vars(args).items() if k != "csv"}))


def enclosed_sites(sites, box):
    """Empty sites of the periodic box that the largest empty region does not reach: the holes the
    candidate's aggregates enclose (edge-neighbour steps)."""
    empty = np.ones((box, box), bool)
    empty[sites[:, 0] % box, sites[:, 1] % box] = False
    label = -np.ones((box, box), int)
    sizes = []
    for start in map(tuple, np.argwhere(empty)):
        if label[start] >= 0:
            continue
        label[start] = len(sizes)
        queue = [start]
        for i, j in queue:
            for di, dj in ((1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)):
                v = ((i + di) % box, (j + dj) % box)
                if empty[v] and label[v] < 0:
                    label[v] = len(sizes)
                    queue.append(v)
        sizes.append(len(queue))
    return int(sum(sizes) - max(sizes, default=0))


if __name__ == "__main__":
    main()
