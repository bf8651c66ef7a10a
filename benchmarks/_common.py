"""Shared helpers of the benchmarks: environment, timing, table printing, CSV output.

Import this module before numpy: it pins BLAS/OpenMP to one thread. The kernel is single-threaded;
a multi-threaded BLAS on a shared 2-core machine makes scipy's L-BFGS-B up to 10x slower in
thread contention, which would flatter the kernel.
"""
from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import platform  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402


def import_pyfrustrate():
    """The installed package, with a clear error if the compiled kernel is missing (e.g. when
    run from the repository root, where the source tree shadows the installed package)."""
    try:
        import pyfrustrate
        from pyfrustrate import _kernel  # noqa: F401
    except ImportError as exc:  # pragma: no cover - environment problem
        sys.exit(f"cannot import pyfrustrate with its compiled _kernel ({exc}); install the package "
                 "(pip install .) and run the scripts by path (python benchmarks/run.py), without "
                 "PYTHONPATH pointing at the source tree")
    return pyfrustrate


def add_box_arguments(ap, sweeps=4000):
    """The Monte Carlo benchmarks' system: n particles in a box x box cell at (ell, nu, Gamma, eps),
    annealed for ``sweeps`` sweeps (defaults: the equilibration benchmark case of issue 15)."""
    ap.add_argument("--n", type=int, default=400)
    ap.add_argument("--box", type=int, default=85)
    ap.add_argument("--nu", type=float, default=0.9)
    ap.add_argument("--Gamma", type=float, default=0.3)
    ap.add_argument("--ell", type=float, default=5.0)
    ap.add_argument("--eps", type=float, default=0.01)
    ap.add_argument("--sweeps", type=int, default=sweeps)


def timed(fn, *args, **kwargs):
    """(seconds, result) of one call."""
    t0 = time.perf_counter()
    out = fn(*args, **kwargs)
    return time.perf_counter() - t0, out


def per_call(fn, repeats=7, min_batch_time=0.02):
    """Per-call time of ``fn()``: batches long enough to beat the timer, ``repeats`` batches;
    returns (min, median) seconds per call."""
    t, _ = timed(fn)
    number = max(1, int(min_batch_time / max(t, 1e-7)))
    samples = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(number):
            fn()
        samples.append((time.perf_counter() - t0) / number)
    return min(samples), statistics.median(samples)


def fmt_time(seconds):
    if seconds != seconds:  # nan
        return "-"
    if seconds < 1e-3:
        return f"{seconds * 1e6:.0f} us"
    if seconds < 1:
        return f"{seconds * 1e3:.1f} ms"
    return f"{seconds:.2f} s"


def table(rows, headers, align=None):
    """Plain-text table (list of row tuples of strings)."""
    rows = [[str(c) for c in r] for r in rows]
    widths = [max(len(h), *(len(r[i]) for r in rows)) if rows else len(h) for i, h in enumerate(headers)]
    align = align or ["<"] + [">"] * (len(headers) - 1)
    line = "  ".join(f"{h:{a}{w}}" for h, a, w in zip(headers, align, widths))
    out = [line, "  ".join("-" * w for w in widths)]
    out += ["  ".join(f"{c:{a}{w}}" for c, a, w in zip(r, align, widths)) for r in rows]
    return "\n".join(out)


def source_line():
    """Which kernel was measured: the repository's commit, and whether kernel/ had local edits
    (several people edit the tree at once), with a short digest of the kernel sources."""
    import hashlib
    import subprocess
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    digest = hashlib.sha256(b"".join(p.read_bytes() for p in sorted((root / "kernel").glob("*.[ch]pp"))))
    try:
        head = subprocess.run(["git", "-C", str(root), "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(root), "status", "--porcelain", "--", "kernel"],
                               capture_output=True, text=True, check=True).stdout.strip()
        return f"repository {head}{' + local kernel edits' if dirty else ''}, kernel sources {digest.hexdigest()[:8]}"
    except (OSError, subprocess.CalledProcessError):
        return f"kernel sources {digest.hexdigest()[:8]}"


def machine_line():
    try:
        load = os.getloadavg()
        load_s = f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}"
    except OSError:
        load_s = "load average n/a"
    return (f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores, {load_s}, "
            f"python {platform.python_version()}")


def write_csv(path, rows, parameters=None):
    """Write ``rows`` (dicts with the same keys) as CSV, atomically (``pyfrustrate.io.atomic_path``:
    the trade-off table is a workflow output), its first line a comment with the provenance of
    the run and its ``parameters``, and say so."""
    import csv

    from pyfrustrate.io import atomic_path, provenance_line
    from pyfrustrate.provenance import describe

    # Described before the temporary file exists: inside the repository it would mark the tree dirty.
    header = provenance_line(describe(parameters))
    with atomic_path(path) as tmp, open(tmp, "w", newline="") as fh:
        fh.write(header)
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"\nwrote {path}")
