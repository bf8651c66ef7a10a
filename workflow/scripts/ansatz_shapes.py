"""Relaxed shapes of the catalogue's members (Fig. 4a), mismatch exaggerated so that the
deformations and the curvature of the asymmetric fibre are visible."""
import numpy as np

from pyfrustrate import Hexagon, relax, topology
from pyfrustrate.io import logging_to, save_npz
from pyfrustrate.provenance import for_job
from pyfrustrate.relaxation import relaxed_drawing

ELL, NU, EPS = (snakemake.params[key] for key in ("drawing_ell", "drawing_nu", "drawing_eps"))  # noqa: F821
with logging_to(snakemake.log[0]):  # noqa: F821
    particle = Hexagon.from_continuum(ELL, NU, eps=EPS)
    bulk_pp = relax(particle, topology.bulk()).energy_per_particle
    items = {
        "single": (topology.disk(0), None), "disk_R1": (topology.disk(1), None), "disk_R3": (topology.disk(3), None),
        "fiber_cut0": (topology.fiber(3, 0), range(-14, 15)), "fiber_cut1": (topology.fiber(6, 1), range(-8, 9)),
        "fiber_cut2": (topology.fiber(4, 2), range(-6, 7)), "bulk": (topology.bulk(), range(-3, 4)),
        "holes_honeycomb": (topology.bulk_with_holes("honeycomb"), range(-2, 3)),
        "holes_kagome": (topology.bulk_with_holes("kagome"), range(-2, 2)),
        "holes_sqrt7": (topology.bulk_with_holes("sqrt7"), range(-1, 2)),
    }
    out = {}
    for name, (topo, images) in items.items():
        corners, energy, r = relaxed_drawing(particle, topo, images, x0="linear")
        out[f"{name}_corners"], out[f"{name}_energy"] = corners, energy / bulk_pp
        print(f"{name}: E/N = {r.energy_per_particle / bulk_pp:.4f} bulk, bonds/N = {topo.n_bonds / topo.n_particles:.3f}, "
              f"converged={r.converged}")
    save_npz(snakemake.output[0], provenance=for_job(snakemake), ell=ELL, nu=NU, eps=EPS, names=np.array(list(items)), **out)  # noqa: F821
