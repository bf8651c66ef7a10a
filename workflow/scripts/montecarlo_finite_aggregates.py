"""Finite-size prediction for a Monte Carlo box of n particles: the relaxed single aggregates of
exactly n particles, compact to elongated, round and faceted, solid and with holes up to
finite_hole_fraction of n (ansatz.finite_aggregates), and the best of them at
each line tension Gamma; and, on the hexagon tiling, the candidate ground states of the box
(ground_states.box_candidates: single aggregates, a fibre wrapping the box, several aggregates, the
gas), saved with the prefix candidate_. The triangle tiling (Fig. S6) gets the single aggregates
only."""
import numpy as np

from pyfrustrate import ansatz, ground_states
from pyfrustrate.io import logging_to, save_npz
from pyfrustrate.particles import particle_class
from pyfrustrate.provenance import for_job

s = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
n, nu, box = snakemake.params.n, snakemake.params.nu, snakemake.params.box  # noqa: F821
with logging_to(snakemake.log[0]):  # noqa: F821
    particle = particle_class(s["tiling"]).from_continuum(s["ell"], nu, eps=s["eps"])
    holes = ansatz.finite_hole_sizes(n, s["tiling"], fraction=s["finite_hole_fraction"])
    shapes = ansatz.finite_aggregates(particle, n, holes=holes)
    Gamma = np.linspace(0.0, s["finite_Gamma_max"], s["finite_Gamma_count"])
    g = ansatz.binding_energy_of(particle, s["ell"], nu, Gamma)
    best = shapes.best(g)
    print(f"n={n} nu={nu}: {len(shapes.segment)} shapes (holes {holes}), "
          f"all converged: {bool(shapes.converged.all())}; "
          f"best width {shapes.width[best].min():.1f}-{shapes.width[best].max():.1f} over Gamma in [0, {s['finite_Gamma_max']:g}]")
    box_states = {}
    if s["tiling"] == "hexagon":
        # The single aggregates just relaxed are the box's single candidates: not relaxed again.
        candidates = ground_states.box_candidates(particle, n, box, hole_fraction=s["finite_hole_fraction"],
                                                  single=shapes)
        families = sorted(set(candidates.best_family(g).tolist()))
        print(f"box {box}: {len(candidates.family)} candidate ground states; best over Gamma in [0, {s['finite_Gamma_max']:g}]: {families}")
        box_states = candidates.arrays()
    save_npz(snakemake.output[0], provenance=for_job(snakemake), nu=nu, ell=s["ell"], eps=s["eps"], Gamma=Gamma, g=g, best=best,  # noqa: F821
             bulk_energy_per_particle=particle.bulk_energy_per_particle, **shapes.arrays(), **box_states)
