"""Fixed-size validation samples (issue 33, item 1; rule ``montecarlo_validation_sample``): what the
warm starts and the parent cluster's factor (``MonteCarloOptions.parent_factor``) save on them.

A sample is one aggregate of a few hundred to a few thousand particles (a straight fibre wrapping
an L x L box, or a compact disk), held at the reshaping window's temperature with surface and
bonded moves (``montecarlo.fixed_size``). Every accepted move relaxes the whole aggregate. With
the parent's factor a move that changes it by a few particles relaxes on the parent's modified
factor instead of factorising its own Hessian; a cluster that wraps the box has no parent factor
(the factor is for finite clusters), so fibre samples gain nothing from it. Warm starts (the
default) start each relaxation from the relaxed displacements of the clusters it came from,
wrapping ones included (with their strain, kernel/montecarlo/chain.hpp, kSiteRecord).

Each case runs a shortened sample (``--sweeps`` sweeps at ``--hold`` g, one at T = 0) with the
rule's options (``warm``), with the parent's factor (``parent64``: clusters of 64 particles or
more keep theirs) and without warm starts (``cold``: every cluster from the linear solution),
alternately, A B C A B C (``--repeats`` rounds), in this process, from the same seed. Per run:
process CPU, its ratio to the ``warm`` run of the same round, relaxations, runs on the parent's
factor, factorisations, and the final energy per particle and bonds (the chains relax to the
same tolerance; equal energies and counts show they took the same moves).

Usage: ``python benchmarks/bench_validation_samples.py [--cases fibre:15 disk:660] [--nu-fibre 0.9]
[--nu-disk 0.4] [--Gamma 0.5] [--sweeps 4] [--repeats 2] [--csv benchmarks/results/validation_samples.csv]``
(the command that wrote the committed CSV is listed in docs/conf.py, ``measured_sources``)
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import _common  # noqa: E402  (pins BLAS threads before numpy is imported)

pyfrustrate = _common.import_pyfrustrate()
from pyfrustrate.montecarlo import fixed_size  # noqa: E402
from pyfrustrate.montecarlo.options import binding  # noqa: E402
from pyfrustrate.particles import particle_class  # noqa: E402

#: config/config.yaml's validation options the rule passes to fixed_size_options.
RULE = dict(bonded_moves=0.9, surface_moves=0.9, method="newton", tol=1e-3)
VARIANTS = {"warm": {}, "parent64": dict(parent_factor=True, parent_factor_min_particles=64),
            "cold": dict(warm_start=False)}


def one_run(particle, g, sites, box, args, variant):
    options = fixed_size.fixed_size_options(**RULE, **VARIANTS[variant])
    schedule = [(args.hold * g, args.sweeps * len(sites)), (0.0, len(sites))]
    t0 = time.process_time()
    s = fixed_size.sample(particle, sites, box, args.seed, g=g, schedule=schedule, options=options)
    cpu = time.process_time() - t0
    c = s.result.counters
    return dict(cpu_s=cpu, relaxations=c["minimisations"], parent_relaxations=c["parent_relaxations"],
                factorizations=c["factorizations"], energy_per_particle_over_g=s.energy_per_particle / g,
                bonds=s.bonds)


def scan_case(case, args):
    """(scan, size, Gamma, nu, particle, g, sites, box) of a case ``scan:size[:Gamma]``."""
    scan, size, *rest = case.split(":")
    Gamma = float(rest[0]) if rest else args.Gamma
    nu = args.nu_fibre if scan == "fibre" else args.nu_disk
    particle = particle_class("hexagon").from_continuum(args.ell, nu, eps=args.eps)
    g = binding(particle, Gamma=Gamma)
    sites, box = fixed_size.scan_seed(scan, int(size), fibre_length=args.fibre_length, disk_margin=args.disk_margin)
    return scan, int(size), Gamma, nu, particle, g, sites, box


def add_sample_arguments(ap, cases, repeats):
    """The shortened samples' arguments (``one_run``, ``scan_case``), shared with bench_allocator.py."""
    ap.add_argument("--cases", nargs="+", default=cases,
                    help="scan:size[:Gamma]: rows of a fibre of --fibre-length or particles of a disk, at --Gamma "
                         "unless given")
    ap.add_argument("--nu-fibre", type=float, default=0.9)
    ap.add_argument("--nu-disk", type=float, default=0.4)
    ap.add_argument("--Gamma", type=float, default=0.5)
    ap.add_argument("--ell", type=float, default=5.0)
    ap.add_argument("--eps", type=float, default=0.01)
    ap.add_argument("--fibre-length", type=int, default=40)
    ap.add_argument("--disk-margin", type=int, default=4)
    ap.add_argument("--hold", type=float, default=0.3, help="hold temperature, units of g")
    ap.add_argument("--sweeps", type=int, default=4)
    ap.add_argument("--repeats", type=int, default=repeats)
    ap.add_argument("--seed", type=int, default=7)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_sample_arguments(ap, cases=["fibre:15", "disk:660"], repeats=2)
    ap.add_argument("--variants", nargs="+", choices=list(VARIANTS), default=list(VARIANTS),
                    help="which runs, in this order; ratios are against the first")
    ap.add_argument("--csv")
    args = ap.parse_args()
    print(f"# {_common.machine_line()}\n# {_common.source_line()}")
    rows = []
    for case in args.cases:
        scan, size, Gamma, nu, particle, g, sites, box = scan_case(case, args)
        for repeat in range(args.repeats):
            base = None
            for variant in args.variants:
                r = one_run(particle, g, sites, box, args, variant)
                base = base or r
                rows.append(dict(scan=scan, size=size, particles=len(sites), box=box, nu=nu, Gamma=Gamma,
                                 variant=variant, repeat=repeat, **r, cpu_ratio=r["cpu_s"] / base["cpu_s"]))
                print(_common.table([tuple(f"{v:.4g}" if isinstance(v, float) else v for v in rows[-1].values())],
                                    list(rows[-1])) if len(rows) == 1 else
                      "  ".join(f"{v:.4g}" if isinstance(v, float) else str(v) for v in rows[-1].values()), flush=True)
    if args.csv:
        _common.write_csv(args.csv, rows, dict(benchmark="bench_validation_samples", **{
            k: v for k, v in vars(args).items() if k != "csv"}))


if __name__ == "__main__":
    main()
