"""Aggregation lines (winner at each Gamma, best fibre width and disk radius, Gamma_max) of one
batch of selected random particles (Figs. 5d, 6, S2)."""
import warnings

import numpy as np
from tqdm.auto import tqdm

from pyfrustrate import random_particles as rp
from pyfrustrate.io import load_npz, logging_to, save_npz
from pyfrustrate.provenance import for_job

s = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
name, batch = snakemake.wildcards.set, snakemake.params.batch  # noqa: F821
with logging_to(snakemake.log[0]):  # noqa: F821
    selection = load_npz(snakemake.input[0])  # noqa: F821
    part = slice(batch * s["diagram_batch"], (batch + 1) * s["diagram_batch"])
    index, ell, nu = (selection[f"{name}_{k}"][part].astype(float) for k in ("index", "ell", "nu"))
    Gamma = rp.line_tension_grid(s["Gamma_max"], s["Gamma_count"])
    n, m = len(index), len(Gamma)
    phase = np.zeros((n, m), np.int8)
    width, radius = np.zeros((n, m), np.float32), np.zeros((n, m), np.float32)
    Gamma_max = np.zeros(n)
    relative = np.linspace(0, 1, s["Gamma_count"])  # Gamma / Gamma_max (Fig. S2), for the sizes set only
    width_rel, radius_rel = np.zeros((n, m), np.float32), np.zeros((n, m), np.float32)
    capped = {key: np.zeros((n, m), bool) for key in ("width", "radius", "width_relative", "radius_relative")}
    for k in tqdm(range(n), desc=f"{name} batch {batch}", unit="particle", mininterval=2):
        particle = rp.RandomHexagon.draw(s["seed"], int(index[k]), eps=s["eps"])
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # a failed relaxation must not pass silently
            line = rp.aggregation_line(particle, Gamma, ell[k], nu[k])
        phase[k], width[k], radius[k], Gamma_max[k] = line["phase"], line["width"], line["radius"], line["Gamma_max"]
        capped["width"][k], capped["radius"][k] = line["width_capped"], line["radius_capped"]
        if name == "sizes":
            rel = rp.aggregation_line(particle, relative, ell[k], nu[k], relative=True)
            width_rel[k], radius_rel[k] = rel["width"], rel["radius"]
            capped["width_relative"][k], capped["radius_relative"][k] = rel["width_capped"], rel["radius_capped"]
    print(f"{n} particles")
    save_npz(snakemake.output[0], provenance=for_job(snakemake), index=index.astype(np.int64), ell=ell, nu=nu, Gamma=Gamma, phase=phase,  # noqa: F821
             width=width, radius=radius, Gamma_max=Gamma_max, phases=np.array(rp.PHASE_CODES),
             Gamma_relative=relative, width_relative=width_rel, radius_relative=radius_rel,
             **{f"{key}_capped": value for key, value in capped.items()})
