"""The heap's top pad (kernel/module.cpp, ``_kernel.allocator_top_pad``): what keeping 16 MiB at
the top of glibc's heap saves on the Monte Carlo's relaxations.

Each relaxation of a new cluster allocates and frees its factorisation's storage. With glibc's
default settings the top of the heap goes back to the system after such a free and comes back,
zeroed page by page, at the next allocation; the kernel sets a top pad at import to keep it.
The setting is per process, so each run is a child process: the shortened validation samples of
``bench_validation_samples.py`` (``--sweeps`` sweeps at ``--hold`` g, one at T = 0, warm starts,
the rule's options) with the kernel's pad (``pad``) and with ``PYFRUSTRATE_MALLOC_TOP_PAD=0``
(``glibc``: the C library's defaults), alternately, A B A B (``--repeats`` rounds). Per run: the
child's process CPU and its ratio to the ``glibc`` run of the same round; equal final energies
show that both took the same moves.

Usage: ``python benchmarks/bench_allocator.py [--cases disk:660 fibre:15] [--repeats 3]
[--csv benchmarks/results/allocator.csv]`` (the command that wrote the committed CSV is listed in
docs/conf.py, ``measured_sources``)
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import _common  # noqa: E402  (pins BLAS threads before numpy is imported)
from bench_validation_samples import add_sample_arguments  # noqa: E402

#: variant -> the environment's PYFRUSTRATE_MALLOC_TOP_PAD (None: unset, the kernel's pad).
VARIANTS = {"glibc": "0", "pad": None}

CHILD = """
import json, sys, types
sys.path.insert(0, {here!r})
import _common
from bench_validation_samples import one_run, scan_case
from pyfrustrate import _kernel
args = types.SimpleNamespace(**json.loads(sys.argv[1]))
_, _, _, _, particle, g, sites, box = scan_case(args.case, args)
r = one_run(particle, g, sites, box, args, "warm")
print(json.dumps(dict(r, top_pad=_kernel.allocator_top_pad)))
"""


def child_run(case, args, variant):
    env = dict(os.environ)
    env.pop("PYFRUSTRATE_MALLOC_TOP_PAD", None)
    if VARIANTS[variant] is not None:
        env["PYFRUSTRATE_MALLOC_TOP_PAD"] = VARIANTS[variant]
    child_args = dict(vars(args), case=case)
    # From the benchmarks' folder: the repository root's source tree would shadow the installed package.
    out = subprocess.run([sys.executable, "-c", CHILD.format(here=str(HERE)), json.dumps(child_args)], env=env,
                         cwd=HERE, capture_output=True, text=True)
    if out.returncode:
        sys.exit(f"the {variant} run of {case} failed:\n{out.stderr}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_sample_arguments(ap, cases=["disk:660", "fibre:15"], repeats=3)
    ap.add_argument("--csv")
    args = ap.parse_args()
    print(f"# {_common.machine_line()}\n# {_common.source_line()}")
    rows = []
    for case in args.cases:
        for repeat in range(args.repeats):
            base = None
            for variant in VARIANTS:
                r = child_run(case, args, variant)
                base = base or r
                rows.append(dict(case=case, variant=variant, repeat=repeat, top_pad=r["top_pad"], cpu_s=r["cpu_s"],
                                 cpu_ratio=r["cpu_s"] / base["cpu_s"], relaxations=r["relaxations"],
                                 energy_per_particle_over_g=r["energy_per_particle_over_g"]))
                print("  ".join(f"{v:.4g}" if isinstance(v, float) else str(v) for v in rows[-1].values()), flush=True)
    for case in args.cases:
        ratios = sorted(r["cpu_ratio"] for r in rows if r["case"] == case and r["variant"] == "pad")
        print(f"# {case}: pad / glibc CPU {ratios[len(ratios) // 2]:.3f} (median of {len(ratios)})")
    if args.csv:
        _common.write_csv(args.csv, rows, dict(benchmark="bench_allocator", **{
            k: v for k, v in vars(args).items() if k != "csv"}))


if __name__ == "__main__":
    main()
