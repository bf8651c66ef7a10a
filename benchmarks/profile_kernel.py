"""Where the relaxation engine's time goes, measured in C++ (``profile_kernel.cpp``).

Builds ``profile_kernel.cpp`` against the kernel sources (``kernel/*.hpp``, ``topology.cpp``,
``minimize.cpp``, ``cholesky.cpp``, ``network_simd.cpp``; g++ -O3 like the extension, NLopt and CHOLMOD from the system)
into a cache directory, runs it on disks and prints, per radius: one energy + gradient (per
particle), the one-off work of a topology (Hessian pattern, CHOLMOD's symbolic analysis), the
work of a particle stiffness (assembly and numeric factorisation), one solve, and the cached
linear and Newton relaxations next to NLopt's L-BFGS.

Needs g++, Eigen 3, NLopt and SuiteSparse headers (the build dependencies of the package).

    python benchmarks/profile_kernel.py [--quick] [--radii 10 25 50] [--repeats 5]
"""
from __future__ import annotations

import argparse
import hashlib
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import fmt_time, machine_line, table  # noqa: E402

HERE = Path(__file__).resolve().parent
KERNEL = HERE.parent / "kernel"


def _cache_dir():
    base = Path(os.environ.get("XDG_CACHE_HOME", Path(tempfile.gettempdir()) / f"pyfrustrate-bench-{os.getuid()}"))
    d = base / "profile_kernel"
    d.mkdir(parents=True, exist_ok=True)
    return d


def _nlopt_lib():
    for lib in ("nlopt_cxx", "nlopt"):
        if subprocess.run(["g++", f"-l{lib}", "-shared", "-o", os.devnull], capture_output=True).returncode == 0:
            return lib
    return "nlopt"


def build():
    """Compile (once per source state) and return the executable's path."""
    sources = [HERE / "profile_kernel.cpp", KERNEL / "topology.cpp", KERNEL / "minimize.cpp", KERNEL / "cholesky.cpp",
               KERNEL / "network_simd.cpp"]
    digest = hashlib.sha256(b"".join(p.read_bytes() for p in sorted(KERNEL.glob("*.hpp")) + sources)).hexdigest()[:16]
    exe = _cache_dir() / f"profile_kernel-{digest}"
    if not exe.exists():
        # The extension's flags (CMakeLists.txt); -ffp-contract=off, which it gives network_simd.cpp
        # alone, changes nothing elsewhere (the baseline x86-64 has no fused multiply-add).
        cmd = ["g++", "-O3", "-std=c++17", "-fno-math-errno", "-ffp-contract=off", "-fopenmp",
               "-DPYFRUSTRATE_HAVE_OPENMP", f"-I{KERNEL}",
               "-I/usr/include/eigen3", "-I/usr/include/suitesparse", *map(str, sources),
               f"-l{_nlopt_lib()}", "-lcholmod", "-o", str(exe)]
        print("compiling:", " ".join(cmd[:3]), "...", flush=True)
        subprocess.run(cmd, check=True)
    return exe


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--radii", type=int, nargs="+", default=None)
    ap.add_argument("--repeats", type=int, default=None)
    args = ap.parse_args(argv)
    radii = args.radii or ([5, 10] if args.quick else [10, 25, 50])
    repeats = args.repeats or (2 if args.quick else 5)
    exe = build()
    out = subprocess.run([str(exe), "--repeats", str(repeats), *map(str, radii)], check=True, capture_output=True,
                         text=True, env={**os.environ, "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"})
    recs = [json.loads(line) for line in out.stdout.splitlines() if line.startswith("{")]
    print(f"profile_kernel: disks, ell = 5, nu = 0.5, eps = 0.01; min of {repeats}; {machine_line()}\n")
    rows = [(r["R"], r["dof"], fmt_time(r["t_eval"]), f"{r['t_eval'] / r['particles'] * 1e9:.0f} ns",
             fmt_time(r["t_pattern"]), fmt_time(r["t_analysis"]), f"{r['nnz_L'] / 1e3:.0f}k",
             f"{r['flops'] / 1e6:.0f}M", "yes" if r["supernodal"] else "no") for r in recs]
    print("per topology (once) and per evaluation")
    print("  " + table(rows, ["R", "dof", "energy+grad", "per particle", "pattern", "analysis", "nnz L",
                              "flops", "supernodal"]).replace("\n", "\n  "))
    rows = [(r["R"], fmt_time(r["t_reference_assembly"]), fmt_time(r["t_exact_assembly"]), fmt_time(r["t_factorize"]),
             f"{r['flops'] / r['t_factorize'] / 1e9:.1f}", fmt_time(r["t_solve"]),
             f"{8 * 2 * r['nnz_L'] / r['t_solve'] / 1e9:.1f}") for r in recs]
    print("\nper particle stiffness (numeric) and per step")
    print("  " + table(rows, ["R", "reference assembly", "exact assembly", "factorise", "GFlop/s", "solve",
                              "GB/s of L read"]).replace("\n", "\n  "))
    rows = [(r["R"], fmt_time(r["t_linear_cached"]), fmt_time(r["t_newton_cached"]), r["newton_steps"],
             r["newton_evaluations"], fmt_time(r["t_newton_cached_1e-10"]), r["newton_steps_1e-10"],
             fmt_time(r["t_lbfgs"]), r["lbfgs_evaluations"], f"{r['t_eval'] * r['lbfgs_evaluations'] / r['t_lbfgs']:.0%}")
            for r in recs]
    print("\nrelaxations with a made StiffnessCache, and L-BFGS (tol 1e-4 unless said)")
    print("  " + table(rows, ["R", "linear", "newton", "steps", "evals", "newton 1e-10", "steps", "L-BFGS", "evals",
                              "L-BFGS in energy"]).replace("\n", "\n  "))
    return recs


if __name__ == "__main__":
    main()
