"""Where the exact Newton steps of Monte Carlo relaxations go (goal (b) of issue 32): a summary of
the per-relaxation trace that a kernel built with ``benchmarks/newton_trace.patch`` appends to the
file named by ``PF_NEWTON_LOG`` (one line per ``newton_from`` call: particles, whether the start
was warm, the start's largest force over the tolerance, then per step its kind (``E`` exact,
``R`` reference stiffness), whether it was damped, its energy evaluations and the largest force
after it over the tolerance, then the factorisations, the failed (indefinite) ones, evaluations,
steps and convergence).

Made by (a build of this commit with the patch applied in ``DIR``)::

    PF_NEWTON_LOG=trace.log PYTHONPATH=DIR python benchmarks/bench_mc_goals.py --child "b dense" warm 150 1 0
    python benchmarks/newton_trace_summary.py trace.log --out benchmarks/results/newton_trace_dense.txt

Prints, for warm starts and for starts from the linear solution apart: factorisations per
relaxation and their histogram, failed factorisations (Levenberg-Marquardt retries), steps,
line-search backtracks, the start's force, the force before the last step (a last exact step
taken from within a few times the tolerance is a factorisation spent on the last digits), the
contraction of the force per step, and factorisations by cluster size.
"""
from __future__ import annotations

import argparse
import collections
from pathlib import Path

import numpy as np


def read(path):
    rows = []
    for line in open(path):
        head, steps, tail = line.split("|")
        particles, warm, start = head.split()
        stats = {k: int(v) for k, v in (kv.split("=") for kv in tail.split())}
        parsed = [(s[0], s[1] == "1", int(s.split(":")[1]), float(s.split(":")[2])) for s in steps.split()]
        rows.append((int(particles), warm == "1", float(start), parsed, stats))
    return rows


def summary(rows):
    out = [f"{len(rows)} relaxations, {sum(r[4]['f'] for r in rows)} factorisations "
           f"({sum(r[4]['fail'] for r in rows)} of them failed: not positive definite)"]
    for warm in (True, False):
        group = [r for r in rows if r[1] == warm]
        if not group:
            continue
        f = np.array([r[4]["f"] for r in group])
        fail = np.array([r[4]["fail"] for r in group])
        steps = [s for r in group for s in r[3]]
        out.append(f"\n{'warm start' if warm else 'from the linear solution'}: {len(group)} relaxations")
        out.append(f"  factorisations per relaxation {f.mean():.2f}, of which failed {fail.mean():.2f}")
        out.append(f"  histogram of factorisations: {dict(sorted(collections.Counter(f.tolist()).items()))}")
        out.append(f"  histogram of failed factorisations: {dict(sorted(collections.Counter(fail.tolist()).items()))}")
        out.append(f"  first step damped (Hessian at the start indefinite): "
                   f"{np.mean([bool(r[3]) and r[3][0][1] for r in group]):.3f} of the relaxations")
        out.append(f"  steps per relaxation {len(steps) / len(group):.2f}, exact {sum(s[0] == 'E' for s in steps) / len(group):.2f}, "
                   f"damped {sum(s[1] for s in steps) / len(group):.2f}, with backtracking "
                   f"{sum(s[2] > 1 for s in steps) / len(group):.2f}, extra line-search evaluations "
                   f"{sum(s[2] - 1 for s in steps) / len(group):.2f}")
        start = np.array([r[2] for r in group])
        out.append(f"  largest force at the start / tolerance, quantiles 10 50 90 %: {np.percentile(start, [10, 50, 90]).round(1).tolist()}")
        before_last = np.array([([r[2]] + [s[3] for s in r[3]])[-2] for r in group if r[3]])
        out.append(f"  largest force before the last step / tolerance, quantiles 10 25 50 75 90 %: "
                   f"{np.percentile(before_last, [10, 25, 50, 75, 90]).round(2).tolist()}")
        out.append(f"  last step taken from below 3 / 10 / 30 x the tolerance: "
                   + " / ".join(f"{(before_last < k).mean():.3f}" for k in (3, 10, 30)))
        ratios = collections.defaultdict(list)
        for r in group:
            forces = [r[2]] + [s[3] for s in r[3]]
            for k in range(1, len(forces)):
                if forces[k] > 0:
                    ratios[min(k, 6)].append(forces[k] / forces[k - 1])
        out.append("  force after / before, median (90 %) by step: "
                   + ", ".join(f"{k}{'+' if k == 6 else ''}: {np.median(v):.3f} ({np.percentile(v, 90):.2f})"
                               for k, v in sorted(ratios.items())))
        size = np.array([r[0] for r in group])
        for lo, hi in ((1, 10), (10, 30), (30, 100), (100, None)):
            m = (size >= lo) & ((size < hi) if hi else True)
            if m.any():
                out.append(f"  clusters of {lo}{'-' + str(hi - 1) if hi else '+'} particles: {m.sum()} relaxations, "
                           f"{f[m].mean():.2f} factorisations each")
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("trace", type=Path)
    ap.add_argument("--out", type=Path, default=None, help="also write the summary here")
    ap.add_argument("--header", default="", help="a first line for the file (what ran)")
    args = ap.parse_args(argv)
    text = summary(read(args.trace))
    print(text)
    if args.out:
        from pyfrustrate.io import atomic_path
        with atomic_path(args.out) as tmp:
            tmp.write_text((f"# {args.header}\n" if args.header else "") + text + "\n")


if __name__ == "__main__":
    main()
