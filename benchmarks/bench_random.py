"""Boundary-layer length of random particles: three routes, speed against accuracy.

* ``strip fit``      the paper's protocol (Fig. 5b): relax a wide strip in linear response, fit the
                     edge energy profile (``fitted_boundary_layer_length``);
* ``companion``      the exact slowest mode of the half-plane, one 16 x 16 generalised eigenproblem
                     per particle (``boundary_layer_length``);
* ``batched``        the same roots for a whole sample through the palindromic scalar polynomial,
                     vectorised (``boundary_layer_lengths``): what makes the paper's 3e7 matrices a
                     matter of minutes.

Times are per particle; ratios are against the strip fit measured in the same run. Accuracy is
the deviation from the companion eigenproblem (exact up to round-off).

Usage: ``python benchmarks/bench_random.py [--quick]``.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import fmt_time, import_pyfrustrate, machine_line, source_line, table  # noqa: E402

import numpy as np  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    import_pyfrustrate()
    from pyfrustrate import random_particles as rp

    n_fit, n_exact, n_batch = (20, 200, 20_000) if args.quick else (100, 2000, 200_000)
    seed = 7
    print(f"{machine_line()}\n{source_line()}")
    M = rp.elasticity_matrices(n_batch, seed)

    t0 = time.perf_counter()
    batched = rp.boundary_layer_lengths(M)
    t_batch = (time.perf_counter() - t0) / n_batch
    t0 = time.perf_counter()
    exact = np.array([rp.boundary_layer_length(m) for m in M[:n_exact]])
    t_exact = (time.perf_counter() - t0) / n_exact
    fitted = np.full(n_fit, np.nan)
    t0 = time.perf_counter()
    for i in range(n_fit):
        try:
            fitted[i] = rp.fitted_boundary_layer_length(rp.RandomHexagon(M[i], eps=1e-4))
        except RuntimeError:
            pass
    t_fit = (time.perf_counter() - t0) / n_fit

    dev_batch = np.abs(batched[:n_exact] / exact - 1)
    dev_fit = np.abs(fitted / exact[:n_fit] - 1)
    rows = [
        ("strip fit (paper)", fmt_time(t_fit), "1", f"{np.nanmedian(dev_fit):.2e}", f"{np.nanmax(dev_fit):.2e}",
         f"{n_fit}"),
        ("companion (exact)", fmt_time(t_exact), f"{t_fit / t_exact:.0f}", "0 (reference)", "-", f"{n_exact}"),
        ("batched polynomial", fmt_time(t_batch), f"{t_fit / t_batch:.0f}", f"{np.median(dev_batch):.1e}",
         f"{dev_batch.max():.1e}", f"{n_batch}"),
    ]
    print()
    print(table(rows, ["route", "time/particle", "speed-up vs fit", "median |rel. dev|", "max |rel. dev|", "particles"]))
    print(f"\n3e7 matrices (the paper's sample) at this rate: batched {3e7 * t_batch / 60:.0f} min, "
          f"companion {3e7 * t_exact / 3600:.1f} h, strip fit {3e7 * t_fit / 86400:.1f} days (one core)")


if __name__ == "__main__":
    main()
