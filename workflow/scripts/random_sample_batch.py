"""One batch of the random-particle sample: exact boundary-layer length (transfer problem),
the supplement's predictors and Poisson ratio of matrices start .. start + count - 1."""
import numpy as np
from tqdm.auto import tqdm

from pyfrustrate import random_particles as rp
from pyfrustrate.io import logging_to, save_npz
from pyfrustrate.provenance import for_job

s = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
start, count = snakemake.params.start, snakemake.params.size  # noqa: F821
STEP = 20_000
with logging_to(snakemake.log[0]):  # noqa: F821
    parts = []
    for offset in tqdm(range(0, count, STEP), desc=f"matrices {start}..{start + count - 1}", unit="chunk", mininterval=2):
        parts.append(rp.sample_properties(min(STEP, count - offset), s["seed"], start + offset))
    out = {k: np.concatenate([p[k] for p in parts]) for k in ("index", "ell", "ell_pred", "ell_eigen", "nu")}
    bad = ~np.isfinite(out["ell"])
    print(f"{count} matrices; non-finite ell: {int(bad.sum())}; ell > 1.5: {np.mean(out['ell'] > 1.5):.4f}")
    save_npz(snakemake.output[0], provenance=for_job(snakemake), seed=s["seed"], index=out["index"].astype(np.int64),  # noqa: F821
             **{k: out[k].astype(np.float32) for k in ("ell", "ell_pred", "ell_eigen", "nu")})
