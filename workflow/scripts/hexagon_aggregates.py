"""The discrete hexagon model (Fig. 2): a particle at rest, a small relaxed aggregate with an
exaggerated mismatch (shapes), and large relaxed aggregates (a disk and a fibre, several ell
across) with the deformation energy of each particle in units of the bulk value."""

from pyfrustrate import Hexagon, relax, topology
from pyfrustrate.io import logging_to, save_npz
from pyfrustrate.provenance import for_job
from pyfrustrate.relaxation import particle_corners, relaxed_drawing

s = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
with logging_to(snakemake.log[0]):  # noqa: F821
    particle = Hexagon.from_continuum(s["ell"], s["nu"], eps=s["eps"])
    bulk_value = relax(particle, topology.bulk()).energy_per_particle

    drawn = Hexagon.from_continuum(s["drawing_ell"], s["nu"], eps=s["drawing_eps"])
    single = topology.disk(0)
    rest = particle_corners(drawn, single, relax(drawn, single).state)[0]
    small = topology.disk(s["drawing_radius"])
    small_state = relax(drawn, small, x0="linear").state
    small_corners = particle_corners(drawn, small, small_state)

    results = {}
    for name, topo in [("disk", topology.disk(s["disk_radius"])),
                       ("fiber", topology.fiber(s["fiber_width"], s["fiber_cut"]))]:
        corners, energies, r = relaxed_drawing(particle, topo, range(-6, 7), x0="linear")
        print(f"{topo.label}: E/N = {r.energy_per_particle / bulk_value:.4f} bulk, converged={r.converged}, "
              f"{r.iterations} evaluations")
        results[f"{name}_corners"] = corners
        results[f"{name}_energy"] = energies / bulk_value
        results[f"{name}_mean"] = r.energy_per_particle / bulk_value
    save_npz(snakemake.output[0], provenance=for_job(snakemake), rest_corners=rest, small_corners=small_corners, ell=s["ell"], nu=s["nu"],  # noqa: F821
             eps=s["eps"], drawing_eps=s["drawing_eps"], drawing_ell=s["drawing_ell"], **results)
