"""Run the benchmarks: ``python benchmarks/run.py [--quick] [--csv-dir DIR] [--no-profile] [--with-others]``.

* ``bench_relax``     kernel vs numpy/scipy at the same accuracy: one evaluation and full
                      relaxations of disks R = 10-100 and fibres of width 30 and 300;
* ``profile_kernel``  where the engine's time goes (C++; the first run compiles one binary,
                      ~40 s; skipped with --quick unless --profile);
* ``bench_tradeoff``  relative energy error vs time for each method and tolerance.

``--with-others`` also runs the other ``bench_*.py`` scripts of this directory (Monte Carlo,
phase diagram: written separately, with their own run times). ``--quick`` is a smoke run (smaller sizes, fewer repeats, < 30 s). Needs the package installed
(``pip install .``); run the script by path (``python benchmarks/run.py``), not with ``-m``, so
that the installed ``pyfrustrate`` with its compiled ``_kernel`` is imported.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _common  # noqa: E402,F401  (pins BLAS threads before numpy is imported)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="smoke run: small sizes, few repeats")
    ap.add_argument("--csv-dir", type=Path, default=None, help="write relax.csv and tradeoff.csv here")
    ap.add_argument("--no-profile", action="store_true", help="skip the C++ phase profile")
    ap.add_argument("--profile", action="store_true", help="run the C++ profile even with --quick")
    ap.add_argument("--with-others", action="store_true",
                    help="also run the other benchmarks/bench_*.py scripts (not timed into the budget)")
    args = ap.parse_args(argv)

    import bench_relax
    import bench_tradeoff
    import profile_kernel

    quick = ["--quick"] if args.quick else []
    csv = (lambda name: ["--csv", str(args.csv_dir / name)]) if args.csv_dir else (lambda name: [])
    if args.csv_dir:
        args.csv_dir.mkdir(parents=True, exist_ok=True)
    steps = [("bench_relax", lambda: bench_relax.main(quick + csv("relax.csv")))]
    if not args.no_profile and (args.profile or not args.quick):
        steps.append(("profile_kernel", lambda: profile_kernel.main(quick)))
    steps.append(("bench_tradeoff", lambda: bench_tradeoff.main(quick + csv("tradeoff.csv"))))

    print(f"{_common.machine_line()}\n{_common.source_line()} (the installed _kernel should match it)")
    if args.with_others:
        import subprocess

        here = Path(__file__).resolve().parent
        mine = {"bench_relax.py", "bench_tradeoff.py"}
        for script in sorted(here.glob("bench_*.py")):
            if script.name not in mine:
                steps.append((script.stem, lambda s=script: subprocess.run(
                    [sys.executable, str(s)] + quick, check=True)))

    t_start = time.perf_counter()
    for name, fn in steps:
        print(f"\n{'=' * 100}\n{name}\n{'=' * 100}", flush=True)
        t0 = time.perf_counter()
        fn()
        print(f"[{name}: {time.perf_counter() - t0:.1f} s]", flush=True)
    print(f"\nall benchmarks: {time.perf_counter() - t_start:.1f} s")


if __name__ == "__main__":
    main()
