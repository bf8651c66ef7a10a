"""One fixed-size Monte Carlo sample (issue 33, item 1): the seed of one size of a scan (a straight
fibre wrapping the box, or a compact disk), held at the point's reshaping-window temperature,
cooled and quenched at T = 0 with surface and bonded moves (montecarlo.fixed_size.sample); its
energy per particle including binding, how many particles ended outside its largest cluster, and
its wall time on one core."""
import json

from pyfrustrate.io import logging_to, save_json
from pyfrustrate.montecarlo import fixed_size
from pyfrustrate.particles import particle_class
from pyfrustrate.provenance import for_job

p = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
with logging_to(snakemake.log[0]):  # noqa: F821
    with open(snakemake.input.point) as f:  # noqa: F821
        point = json.load(f)
    size = point["sizes"][p.index]
    particle = particle_class("hexagon").from_continuum(point["ell"], point["nu"], eps=point["eps"])
    g = point["g"]
    options = fixed_size.fixed_size_options(p.bonded_moves, p.surface_moves, method=p.method, tol=p.tol)
    sites, box = fixed_size.scan_seed(point["scan"], size, fibre_length=p.fibre_length, disk_margin=p.disk_margin)
    schedule = fixed_size.sample_schedule(point["hold_temperature"], len(sites), hold_sweeps=p.hold_sweeps,
                                          cool_sweeps=p.cool_sweeps, quench_sweeps=p.quench_sweeps)
    s = fixed_size.sample(particle, sites, box, fixed_size.run_seed(p.seed, size, 1), g=g, schedule=schedule,
                          options=options)
    print(f"{point['scan']} size {size} seed {p.seed}: n={s.n} in {box}^2, e/g={s.energy_per_particle / g:.6f}, "
          f"{s.bonds} bonds, {s.outside} outside the largest cluster (wrapping {s.wraps}), {s.moves} moves in "
          f"{s.seconds:.1f} s")
    save_json(snakemake.output[0], dict(  # noqa: F821
        scan=point["scan"], nu=point["nu"], Gamma=point["Gamma"], size=size, seed=p.seed, n=s.n, box=box,
        energy=s.energy, energy_per_particle=s.energy_per_particle, bonds=s.bonds, outside=s.outside, wraps=s.wraps,
        seconds=s.seconds, moves=s.moves, schedule=schedule, counters=s.result.counters),
        provenance=for_job(snakemake))  # noqa: F821
