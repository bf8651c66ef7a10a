"""Relaxed energies of every candidate aggregate (Fig. 4a catalogue, Fig. S6e for triangles) for
one particle (ell, nu) of a tiling."""
import numpy as np

from pyfrustrate import ansatz
from pyfrustrate.io import logging_to, save_npz
from pyfrustrate.provenance import for_job
from pyfrustrate.particles import particle_class

s = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
ell, nu, tiling = snakemake.params.ell, snakemake.params.nu, snakemake.params.tiling  # noqa: F821
with logging_to(snakemake.log[0]):  # noqa: F821
    particle = particle_class(tiling).from_continuum(ell, nu, eps=s["eps"])
    max_radius = max(s["min_radius"], int(np.ceil(s["radius_per_ell"] * ell)))
    max_width = max(s["min_width"], int(np.ceil(s["width_per_ell"] * ell)))
    candidates = ansatz.catalogue(max_radius=max_radius, max_width=max_width, straight_fibers=True, tiling=tiling)
    print(f"ell={ell} nu={nu}: {particle}; {len(candidates)} candidates, R <= {max_radius}, width <= {max_width}")
    table = ansatz.relax_catalogue(particle, candidates, method=s["method"], tol=s["tol"], progress=True,
                                   description=f"ell={ell:g} nu={nu:g}")
    print(f"not converged: {int((~table.converged).sum())}; total time {table.seconds.sum():.1f} s")
    save_npz(snakemake.output[0], provenance=for_job(snakemake), ell=ell, nu=nu, eps=s["eps"], k=particle.k, kc=particle.kc, tiling=tiling,  # noqa: F821
             k_area=particle.k_area, method=s["method"], bulk_reference=particle.bulk_energy_per_particle,
             **table.as_arrays())
