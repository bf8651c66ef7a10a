"""Where the kernel's time goes: phase split of the linear solve and of L-BFGS, measured in C++.

Builds ``profile_kernel.cpp`` against the kernel sources (``kernel/*.hpp``, ``topology.cpp``,
``minimize.cpp``; g++ -O3 like the extension, NLopt from the system) into a cache directory, then
prints:

* linear solve: reference forces, Gauss-Newton Hessian assembly as the kernel does it (dense
  per-particle Jacobian product), the same Hessian scattered directly from the particle
  Hessians, reduction to the free dof, AMD analysis, LDL^T factorisation, solve, final energy;
  nnz of K and L; preconditioned CG on the same K for comparison; fixed-stiffness Newton
  iterations from the linear solution reusing the factorisation (a candidate fast path);
* L-BFGS: total time, evaluations, the share spent inside the energy, hence NLopt's own cost
  per iteration, against an Eigen two-loop recursion (m = 10) of the same size;
* L-BFGS at nu = 0.2 (k_area < 0, energy unbounded below) next to nu = 0.5; when
  ``minimize.cpp`` still multiplies the objective by ``1e-4 / gradient_tolerance`` (the version
  benchmarked first), the same runs with a patched copy that scales only as far as NLopt's
  internal 1e-8 gradient threshold requires.

Needs g++, Eigen 3 and NLopt headers (the build dependencies of the package).

    python benchmarks/profile_kernel.py [--quick] [--radii 10 25] [--repeats 5]
"""
from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import fmt_time, machine_line, table  # noqa: E402

HERE = Path(__file__).resolve().parent
KERNEL = HERE.parent / "kernel"
SCALE_LINE = "state.scale = 1e-4 / options.gradient_tolerance;"
SCALE_PATCH = "state.scale = std::max(1.0, 1e-7 / options.gradient_tolerance);"


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


def _optional_solvers():
    """Compiler flags and libraries for the optional comparisons: METIS ordering and CHOLMOD's
    supernodal Cholesky (Debian: libmetis-dev, libsuitesparse-dev; not needed by the package)."""
    flags, libs = [], []
    if Path("/usr/include/metis.h").exists():
        flags.append("-DHAVE_METIS")
        libs.append("-lmetis")
    if Path("/usr/include/suitesparse/cholmod.h").exists():
        flags += ["-DHAVE_CHOLMOD", "-I/usr/include/suitesparse"]
        libs.append("-lcholmod")
    return flags, libs


def build(variant="kernel"):
    """Path of the profiler binary for ``variant`` ('kernel' or 'scale'), built if stale;
    None if the scale patch does not apply."""
    if shutil.which("g++") is None:
        raise RuntimeError("g++ not found")
    minimize_src = (KERNEL / "minimize.cpp").read_text()
    if variant == "scale":
        if SCALE_LINE not in minimize_src:
            return None
        minimize_src = minimize_src.replace(SCALE_LINE, SCALE_PATCH)
        if "#include <algorithm>" not in minimize_src:
            minimize_src = "#include <algorithm>\n" + minimize_src
    sources = [HERE / "profile_kernel.cpp", KERNEL / "topology.cpp"] + sorted(KERNEL.glob("*.hpp"))
    digest = hashlib.sha256(minimize_src.encode() + b"".join(p.read_bytes() for p in sources)
                            + repr(_optional_solvers()).encode()).hexdigest()[:16]
    cache = _cache_dir()
    exe = cache / f"profile_kernel-{variant}-{digest}"
    if exe.exists():
        return exe
    minimize_path = cache / f"minimize-{variant}-{digest}.cpp"
    minimize_path.write_text(minimize_src)
    extra, libs = _optional_solvers() if variant == "kernel" else ([], [])
    cmd = ["g++", "-O3", "-std=c++17", "-DNDEBUG", f"-I{KERNEL}", "-I/usr/include/eigen3", *extra,
           str(HERE / "profile_kernel.cpp"), str(KERNEL / "topology.cpp"), str(minimize_path),
           f"-l{_nlopt_lib()}", *libs, "-o", str(exe)]
    print(f"  building {exe.name} (once) ...", flush=True)
    subprocess.run(cmd, check=True)
    return exe


def run(exe, *args):
    out = subprocess.run([str(exe), *map(str, args)], check=True, capture_output=True, text=True).stdout
    return [json.loads(line) for line in out.splitlines() if line.startswith("{")]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--radii", type=int, nargs="+", default=None)
    ap.add_argument("--repeats", type=int, default=None)
    args = ap.parse_args(argv)
    radii = args.radii or ([10] if args.quick else [10, 25, 40])
    repeats = args.repeats or (2 if args.quick else 5)

    print(f"profile_kernel: disks, ell=5, nu=0.5, eps=0.01, tol=1e-5; min of {repeats}; {machine_line()}")
    try:
        exe = build("kernel")
    except (RuntimeError, subprocess.CalledProcessError) as exc:
        print(f"  skipped: cannot build the C++ profiler ({exc})")
        return None
    recs = run(exe, "--repeats", repeats, *radii)
    lin = [r for r in recs if r["phase"] == "linear"]
    lb = [r for r in recs if r["phase"] == "lbfgs"]

    print("\nlinear solve, phase by phase")
    rows = []
    for r in lin:
        total = (r["t_force"] + r["t_gauss_newton"] + r["t_reduce"] + r["t_analyze"] + r["t_factorize"]
                 + r["t_solve"] + r["t_final_energy"])
        pct = lambda key: f"{fmt_time(r[key])} ({r[key] / total:.0%})"  # noqa: E731
        rows.append((r["R"], r["dof"], fmt_time(total), pct("t_gauss_newton"), fmt_time(r["t_direct_assembly"]),
                     pct("t_reduce"), pct("t_analyze"), pct("t_factorize"), pct("t_solve"),
                     fmt_time(r["t_force"] + r["t_final_energy"]), r["nnz_K"], r["nnz_L"]))
    print("  " + table(rows, ["R", "dof", "total", "GN assembly", "direct asm", "reduce", "AMD analyse",
                              "LDLT factorise", "solve", "2 evals", "nnz K", "nnz L"]).replace("\n", "\n  "))
    print("  GN assembly = kernel's gauss_newton_hessian (dense 12x(12+np) Jacobian per particle);"
          "\n  direct asm = the same matrix scattered straight from the 12x12 particle Hessians "
          f"(identical: max rel diff {max(r['assembly_rel_diff'] for r in lin):.0e})")
    rows = [(r["R"], fmt_time(r["t_factorize"] + r["t_analyze"] + r["t_solve"]),
             f"{fmt_time(r['t_cg_ichol'])} / {r['cg_ichol_iterations']} it",
             f"{fmt_time(r['t_cg_diag'])} / {r['cg_diag_iterations']} it") for r in lin]
    headers = ["R", "LDLT AMD (kernel)", "CG + incomplete Cholesky", "CG + diagonal"]
    if lin[0]["t_ldlt_metis"] >= 0:
        headers.append("LDLT METIS")
        rows = [row + (f"{fmt_time(r['t_ldlt_metis'])} (nnz L {r['nnz_L_metis']})",) for row, r in zip(rows, lin)]
    if lin[0]["t_cholmod_factorize"] >= 0:
        headers.append("CHOLMOD supernodal")
        rows = [row + (fmt_time(r["t_cholmod_analyze"] + r["t_cholmod_factorize"] + r["t_cholmod_solve"])
                       + f" (factorise {fmt_time(r['t_cholmod_factorize'])})",) for row, r in zip(rows, lin)]
    print("  direct and iterative alternatives on the same K (analyse + factorise + solve; CG to a"
          "\n  1e-10 residual; METIS/CHOLMOD only if libmetis-dev/libsuitesparse-dev are installed):"
          + "\n  " + table(rows, headers).replace("\n", "\n  "))

    print("\nfixed-stiffness Newton: from the linear solution, x <- x - K^-1 grad(x) with the LDL^T of"
          "\n  the eps = 0 stiffness already factorised, to the L-BFGS tolerance max|grad| <= 1e-5 k eps")
    rows = [(r["R"], r["newton_steps"], fmt_time(r["t_newton"]),
             fmt_time(r["t_newton"] / max(r["newton_steps"], 1)), f"{r['newton_gmax'] / 0.01:.1e}",
             f"{r['newton_energy']:.12g}") for r in lin]
    print("  " + table(rows, ["R", "steps", "time (after factorising)", "per step", "max|g|/k eps",
                              "energy"]).replace("\n", "\n  "))
    print("  (each step = one energy evaluation + one back-substitution; compare the L-BFGS totals below)")

    print("\nL-BFGS (cold start), where the time goes")
    rows = []
    for r in lb:
        other = r["t_total"] - r["t_in_energy"]
        rows.append((r["R"], r["dof"], fmt_time(r["t_total"]), r["evaluations"], fmt_time(r["t_eval"]),
                     f"{r['t_in_energy'] / r['t_total']:.0%}", f"{other / r['t_total']:.0%}",
                     fmt_time(other / r["evaluations"]), fmt_time(r["t_eigen_twoloop"])))
    print("  " + table(rows, ["R", "dof", "total", "evals", "1 eval", "in energy", "in NLopt",
                              "NLopt / eval", "Eigen two-loop"]).replace("\n", "\n  "))

    scaled = build("scale")
    exp_radii = [radii[0]] if args.quick else [10, 25]
    variants = [("kernel", exe)] + ([("patched", scaled)] if scaled is not None else [])
    if scaled is None:
        print("\nL-BFGS at nu = 0.5 and at nu = 0.2 (k_area < 0, energy unbounded below), current kernel"
              "\n  (the scale experiment is skipped: minimize.cpp no longer scales by 1e-4/tol)")
    else:
        print("\nexperiment: NLopt objective scale  1e-4/tol (kernel)  vs  max(1, 1e-7/tol) (patched copy)")
    rows = []
    for nu, Rs in ((0.5, exp_radii), (0.2, [15])):
        for name, binary in variants:
            for r in run(binary, "--repeats", max(1, repeats - 2), "--nu", nu, "--lbfgs-only",
                         "--max-evals", 5000, *Rs):
                rows.append((nu, r["R"], name, fmt_time(r["t_total"]), r["evaluations"],
                             f"{r['energy']:.10g}", r["converged"]))
    print("  " + table(rows, ["nu", "R", "build", "time", "evals", "energy", "converged"]).replace("\n", "\n  "))
    print("  (nu = 0.2 has k_area < 0: the energy is unbounded below and a long first step can run"
          "\n  away to E ~ -1e80; runs are capped at 5000 evaluations here)")
    return recs


if __name__ == "__main__":
    main()
