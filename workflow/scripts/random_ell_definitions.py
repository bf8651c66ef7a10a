"""Definitions of the boundary-layer length compared on the first particles of the random sample
(pyfrustrate.boundary_layer): every particle's ell under each definition, and the numbers the
paper states for each (P(ell >= 1.5), median ell_pred/ell, nu per ell group)."""
import numpy as np

from pyfrustrate import boundary_layer as bl
from pyfrustrate import random_particles as rp
from pyfrustrate.io import logging_to, save_json, save_npz
from pyfrustrate.provenance import for_job

p = snakemake.params  # noqa: F821
with logging_to(snakemake.log[0]):  # noqa: F821
    Ms = rp.elasticity_matrices(p.particles, p.seed)
    study = bl.compare_definitions(Ms, depths=p.depths, eps=p.eps, min_shares=p.min_shares, progress=True)
    groups = [float(g) for g in p.ell_groups]
    table = bl.summarise(study, ell_groups=groups)
    for name, row in table.items():
        print(f"{name:24s} P(ell>=1.5) {row['P_above']:.4f}  median ell_pred/ell {row['median_ratio']:.3f}  "
              f"P(ell_pred>ell) {row['above_one']:.3f}  no decay {row['not_decaying']:.4f}")
    columns = {k: np.asarray(v) for k, v in study.items()}
    save_npz(snakemake.output.study, provenance=for_job(snakemake), **columns, index=np.arange(p.particles))  # noqa: F821
    save_json(snakemake.output.table, provenance=for_job(snakemake), obj={"particles": p.particles, "seed": p.seed, "ell_groups": groups,  # noqa: F821
                                       "definitions": table})
