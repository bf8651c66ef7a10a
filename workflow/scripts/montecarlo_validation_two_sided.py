"""A two-sided check at a disk point of the fixed-size validation (issue 33, item 4: one aggregate
against two): the same particles seeded as the predicted state (one compact disk of the ansatz's
best size) and as its nearest competitor (two disks of half that size, apart in the same box), both
held at the point's reshaping-window temperature, cooled and quenched with the samples' schedule and
moves (montecarlo.fixed_size.two_disks_seed, sample). The predicted state should persist (one
aggregate) and the competitor should not end below it."""
import json

from pyfrustrate.io import logging_to, save_json
from pyfrustrate.montecarlo import clusters, fixed_size
from pyfrustrate.particles import particle_class
from pyfrustrate.provenance import for_job

p = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
with logging_to(snakemake.log[0]):  # noqa: F821
    with open(snakemake.input.point) as f:  # noqa: F821
        point = json.load(f)
    n, g = point["n_ansatz"], point["g"]
    particle = particle_class("hexagon").from_continuum(point["ell"], point["nu"], eps=point["eps"])
    options = fixed_size.fixed_size_options(p.bonded_moves, p.surface_moves, method=p.method, tol=p.tol)
    schedule = fixed_size.sample_schedule(point["hold_temperature"], n, hold_sweeps=p.hold_sweeps,
                                          cool_sweeps=p.cool_sweeps, quench_sweeps=p.quench_sweeps)
    one, two, box = fixed_size.two_disks_seed(n, p.disk_margin)
    runs = {}
    for role, (name, sites) in enumerate((("predicted", one), ("competitor", two)), start=2):
        s = fixed_size.sample(particle, sites, box, fixed_size.run_seed(p.seed, n, role), g=g, schedule=schedule,
                              options=options)
        sizes = [len(c) for c, _ in clusters(s.result.sites, box)]
        runs[name] = dict(energy_over_g=s.energy / g, bonds=s.bonds, cluster_sizes=sizes, seconds=s.seconds,
                          moves=s.moves)
        print(f"{name}: {n} particles in {box}^2 ended in clusters {sizes[:4]}, E/g = {s.energy / g:.3f}, "
              f"{s.bonds} bonds, {s.seconds:.1f} s")
    save_json(snakemake.output[0], dict(  # noqa: F821
        scan=point["scan"], nu=point["nu"], Gamma=point["Gamma"], seed=p.seed, n=n, box=box,
        predicted_state="one disk", competitor_state="two disks", schedule=schedule, **runs),
        provenance=for_job(snakemake))  # noqa: F821
