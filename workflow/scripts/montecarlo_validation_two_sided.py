"""A two-sided check of the fixed-size validation (issue 33, item 4): the ansatz's predicted state
at a point (its better single aggregate, montecarlo.fixed_size.predicted_kind) and its nearest
competitor (two disks against a disk; the other kind, fibre or disk, of as many particles near the
fibre-disk line or at a fibre point), the same particles in the same box, both held at the point's
reshaping-window temperature, cooled and quenched with the samples' schedule and moves
(montecarlo.fixed_size.two_sided_seeds, sample). The predicted state should persist
(fixed_size.persists) and the competitor should not end below it."""
import json

from pyfrustrate.io import logging_to, save_json
from pyfrustrate.montecarlo import clusters, fixed_size
from pyfrustrate.particles import particle_class
from pyfrustrate.provenance import for_job

p = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
with logging_to(snakemake.log[0]):  # noqa: F821
    with open(snakemake.input.point) as f:  # noqa: F821
        point = json.load(f)
    g = point["g"]
    particle = particle_class("hexagon").from_continuum(point["ell"], point["nu"], eps=point["eps"])
    options = fixed_size.fixed_size_options(p.bonded_moves, p.surface_moves, method=p.method, tol=p.tol)
    seeds = fixed_size.two_sided_seeds(point, p.competitor, fibre_length=p.fibre_length, margin=p.disk_margin)
    n, box = seeds["n"], seeds["box"]
    schedule = fixed_size.sample_schedule(point["hold_temperature"], n, hold_sweeps=p.hold_sweeps,
                                          cool_sweeps=p.cool_sweeps, quench_sweeps=p.quench_sweeps)
    runs = {}
    for role, name in enumerate(("predicted", "competitor"), start=2):
        s = fixed_size.sample(particle, seeds[name], box, fixed_size.run_seed(p.seed, n, role), g=g,
                              schedule=schedule, options=options)
        sizes = [len(c) for c, _ in clusters(s.result.sites, box)]
        runs[name] = dict(energy_over_g=s.energy / g, bonds=s.bonds, cluster_sizes=sizes, outside=s.outside,
                          wraps=s.wraps, seconds=s.seconds, moves=s.moves)
        print(f"{name} ({seeds[f'{name}_state']}): {n} particles in {box}^2 ended in clusters {sizes[:4]} "
              f"(largest wrapping {s.wraps}), E/g = {s.energy / g:.3f}, {s.bonds} bonds, {s.seconds:.1f} s")
    runs["predicted"]["persists"] = fixed_size.persists(seeds["predicted_kind"], runs["predicted"]["outside"],
                                                        runs["predicted"]["wraps"])
    save_json(snakemake.output[0], dict(  # noqa: F821
        scan=point["scan"], nu=point["nu"], Gamma=point["Gamma"], seed=p.seed, n=n, box=box,
        competitor_rule=p.competitor, predicted_kind=seeds["predicted_kind"],
        predicted_state=seeds["predicted_state"], competitor_state=seeds["competitor_state"],
        ansatz_margin_per_particle_over_g=fixed_size.ansatz_margin(point) / g,
        schedule=schedule, **runs),
        provenance=for_job(snakemake))  # noqa: F821
