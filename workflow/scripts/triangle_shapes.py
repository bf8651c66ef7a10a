"""Relaxed triangle aggregates for Fig. S6 (a, b, c, e): every node (yellow and red) of each
particle, mismatch exaggerated so that deformations show. Periodic cells are repeated."""
import numpy as np

from pyfrustrate import Triangle, relax, topology
from pyfrustrate.io import logging_to, save_npz
from pyfrustrate.provenance import for_job
from pyfrustrate.relaxation import relaxed_drawing

p = snakemake.params  # noqa: F821
TILING = "triangle"
with logging_to(snakemake.log[0]):  # noqa: F821
    particle = Triangle.from_continuum(p.ell, p.nu, eps=p.eps)
    bulk_pp = relax(particle, topology.bulk(TILING)).energy_per_particle
    items = {
        "single": (topology.disk(0, tiling=TILING), None),
        "pair": (topology.cluster([(0, 0, 0), (0, 0, 1)], tiling=TILING), None),
        "disk_R1": (topology.disk(1, tiling=TILING), None),
        "disk_R3": (topology.disk(3, tiling=TILING), None),
        "fiber_cut0": (topology.fiber(3, 0, tiling=TILING), range(-8, 9)),
        "fiber_cut1": (topology.fiber(3, 1, tiling=TILING), range(-8, 9)),
        "fiber_cut2": (topology.fiber(3, 2, tiling=TILING), range(-4, 5)),
        "bulk": (topology.bulk(TILING), range(-3, 4)),
        **{f"holes_{name}": (topology.bulk_with_holes(name, tiling=TILING), range(-1, 2))
           for name in topology.hole_patterns(TILING)},
    }
    out = {}
    for name, (topo, images) in items.items():
        corners, energy, r = relaxed_drawing(particle, topo, images)
        out[f"{name}_corners"], out[f"{name}_energy"] = corners, energy / bulk_pp
        out[f"{name}_per_particle"] = r.energy_per_particle / bulk_pp
        print(f"{name}: E/N = {r.energy_per_particle / bulk_pp:.4f} bulk, bonds/N = {topo.n_bonds / topo.n_particles:.3f}, "
              f"converged={r.converged}")
    save_npz(snakemake.output[0], provenance=for_job(snakemake), ell=p.ell, nu=p.nu, eps=p.eps, names=np.array(list(items)),  # noqa: F821
             springs=np.array([(a, b) for a, b, _ in particle._kernel_model.springs]),
             spring_kinds=np.array([kind for _, _, kind in particle._kernel_model.springs]), **out)
