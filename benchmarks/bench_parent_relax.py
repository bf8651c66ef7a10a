"""Goal (a) of issue 32: one relaxation of an 817-particle aggregate after a one-particle change,
against a cold relaxation of the same aggregate (goal: ratio <= 0.2; the Monte Carlo measured
1.03 before the parent's factor was reused).

The aggregate is the compact disk of 817 particles (``topology.hexagon_sites(16)``), relaxed to
round-off with its factor kept (``relax(..., keep_factor=True)``; not timed: in the Monte Carlo
the parent was relaxed by the move before). Its children: one particle added at a site with two
occupied neighbours, one removed from the outline (keeping the aggregate connected), and one
moved from the outline to such a site (the surface move of the large box, 817 particles again).
Each child is relaxed, to the Monte Carlo's tolerance (largest force 1e-3 F), by

``cold``    ``pf.relax`` of the child alone (Newton from the linear solution: Hessian pattern,
            CHOLMOD analysis and factorisations made for it);
``warm``    today's Monte Carlo path before this change: Newton with exact steps from the
            parent's relaxed displacement (new corners by a rigid fit), with a fresh pattern,
            analysis and a factorisation per step (``_kernel.relax(start=...)``);
``parent``  ``pf.relax(..., parent=parent.factor)``: the same start, the parent's factor copied and
            modified (rows deleted and added, low-rank update and downdate; kernel/parent_factor.hpp),
            chord steps with it.

The three run round-robin, ``--repeats`` times; times are process CPU, min over the repeats.
Prints and writes (``--csv``) per case: particles, times, the ratios warm/cold and parent/cold
(the goal's), chord steps, whether the parent's factor served, and the relative energy
difference of each path from the cold one (all three stop at the same force tolerance).
``--baseline DIR`` also runs every nu with another build of the package (``DIR`` holding its
``pyfrustrate/``, e.g. ``pip install --no-deps --target DIR`` of an earlier commit), each build
in a child process, alternately (column ``build``: ``this`` or ``baseline``).

Usage: ``python benchmarks/bench_parent_relax.py [--radius 16] [--nu 0.9 0.4] [--repeats 5]
[--baseline DIR] [--csv benchmarks/results/parent_relax.csv] [--quick]``
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _common  # noqa: E402  (pins BLAS threads before numpy is imported)

import numpy as np  # noqa: E402

pyfrustrate = _common.import_pyfrustrate()
from pyfrustrate import Hexagon, _kernel  # noqa: E402
from pyfrustrate import topology as tp  # noqa: E402

from bench_parent_factor import child_start, children, connected, neighbours  # noqa: E402

ELL, EPS, TOL = 5.0, 0.01, 1e-3  # TOL: the Monte Carlo's, in units of the particle's force scale
GOAL = 0.2


class Tree:
    """The sites and topology of one aggregate, with the attributes child_start reads."""

    def __init__(self, sites):
        self.sites = sites
        self.full = tp.cluster(np.array(sites))
        self.topology = self.full.kernel


def moved(sites):
    """One particle moved from the outline to a site with two occupied neighbours elsewhere."""
    occupied = set(sites)
    edge = next(q for q in sites if sum(n in occupied for n in neighbours(q)) < 6
                and connected([s for s in sites if s != q]))
    rest = [s for s in sites if s != edge]
    left = set(rest)
    kink = next(s for q in reversed(rest) for s in neighbours(q)
                if s not in left and s != edge and sum(n in left for n in neighbours(s)) == 2)
    return "move", rest + [kink]


def cpu(fn):
    t0 = time.process_time()
    out = fn()
    return time.process_time() - t0, out


def case(radius, nu, repeats):
    particle = Hexagon.from_continuum(ell=ELL, nu=nu, eps=EPS)
    model = particle._kernel_model
    sites = [tuple(int(v) for v in s) for s in tp.hexagon_sites(radius)]
    parent = Tree(sites)
    relaxed = pyfrustrate.relax(particle, parent.full, tol=1e-10, keep_factor=True)
    rows = []
    for label, child_sites in list(children(sites)) + [moved(sites)]:
        child = Tree(child_sites)
        u0, _ = child_start(parent, child, relaxed.displacement)
        paths = {
            "cold": lambda: pyfrustrate.relax(particle, child.full, tol=TOL),
            "warm": lambda: _kernel.relax(model, child.topology, "newton", TOL * particle.force_scale, 500_000,
                                          start=u0),
            "parent": lambda: pyfrustrate.relax(particle, child.full, tol=TOL, parent=relaxed.factor),
        }
        times = {k: [] for k in paths}
        results = {}
        for _ in range(repeats):
            for k, fn in paths.items():
                t, results[k] = cpu(fn)
                times[k].append(t)
        energy = {k: (r["energy"] if isinstance(r, dict) else r.energy) for k, r in results.items()}
        best = {k: min(v) for k, v in times.items()}
        rows.append({
            "radius": radius, "nu": nu, "move": label, "particles": child.topology.n_particles,
            "cold_ms": 1e3 * best["cold"], "warm_ms": 1e3 * best["warm"], "parent_ms": 1e3 * best["parent"],
            "warm_over_cold": best["warm"] / best["cold"], "parent_over_cold": best["parent"] / best["cold"],
            "goal": GOAL, "from_parent": results["parent"].from_parent,
            "parent_steps": results["parent"].newton_steps, "parent_refactorizations": results["parent"].factorizations,
            "warm_factorizations": results["warm"]["factorizations"],
            "cold_factorizations": results["cold"].factorizations,
            "warm_rel_energy_diff": abs(energy["warm"] - energy["cold"]) / energy["cold"],
            "parent_rel_energy_diff": abs(energy["parent"] - energy["cold"]) / energy["cold"],
        })
    return rows


def case_in_child(package_dir, radius, nu, repeats):
    """case() in a child process whose pyfrustrate comes from package_dir (None: this one's)."""
    env = dict(os.environ)
    if package_dir is not None:
        env["PYTHONPATH"] = os.pathsep.join([str(Path(package_dir).resolve())] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    out = subprocess.run([sys.executable, __file__, "--child", str(radius), str(nu), str(repeats)],
                         env=env, check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main(argv=None):
    if argv is None and len(sys.argv) > 1 and sys.argv[1] == "--child":
        radius, nu, repeats = sys.argv[2:5]
        print(json.dumps(case(int(radius), float(nu), int(repeats))))
        return
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--radius", type=int, default=16, help="disk radius: 1 + 3R(R+1) particles (16: 817)")
    ap.add_argument("--nu", type=float, nargs="+", default=[0.9, 0.4])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--csv", type=Path, default=None, help="write the table here")
    ap.add_argument("--quick", action="store_true", help="a disk of R = 5, one nu, two repeats")
    ap.add_argument("--baseline", type=Path, default=None,
                    help="a directory holding another build's pyfrustrate/, run alternately with this one")
    args = ap.parse_args(argv)
    if args.baseline is not None and not (args.baseline / "pyfrustrate" / "__init__.py").is_file():
        ap.error(f"--baseline: {args.baseline} holds no pyfrustrate/ package")
    radius, nus, repeats = (5, [0.9], 2) if args.quick else (args.radius, args.nu, args.repeats)
    print(f"{_common.machine_line()}\n{_common.source_line()}")
    print(f"One relaxation after a one-particle change against a cold one, ell = {ELL}, eps = {EPS}, tol {TOL} F; "
          f"process CPU, min of {repeats} (goal: parent/cold <= {GOAL})")
    builds = {"this": None} if args.baseline is None else {"this": None, "baseline": args.baseline}
    rows = []
    for nu in nus:
        for build, package_dir in builds.items():
            measured = (case(radius, nu, repeats) if args.baseline is None
                        else case_in_child(package_dir, radius, nu, repeats))
            rows += [{"build": build, **row} for row in measured]
    print(_common.table(
        [(r["build"], r["radius"], r["nu"], r["move"], r["particles"], f"{r['cold_ms']:.2f}", f"{r['warm_ms']:.2f}",
          f"{r['parent_ms']:.2f}", f"{r['warm_over_cold']:.2f}", f"{r['parent_over_cold']:.3f}", r["from_parent"],
          r["parent_steps"], f"{r['parent_rel_energy_diff']:.1e}") for r in rows],
        ["build", "R", "nu", "move", "particles", "cold ms", "warm ms", "parent ms", "warm/cold", "parent/cold",
         "parent used", "chord steps", "dE/E parent"]))
    if args.csv:
        _common.write_csv(args.csv, rows, {"benchmark": "bench_parent_relax", "ell": ELL, "eps": EPS, "tol": TOL,
                                           "repeats": repeats,
                                           "baseline": str(args.baseline) if args.baseline else None})


if __name__ == "__main__":
    main()
