"""Summary of the random-particle sample (a plotted subsample, the distribution of ell) and the
selections of particles for the aggregation diagrams: a random set for the sizes (Figs. 5d, S2)
and, per ell group, a set with a near-uniform distribution of nu (Fig. 6; supplement S3)."""
import numpy as np

from pyfrustrate import random_particles as rp
from pyfrustrate.io import load_npz, logging_to, save_npz
from pyfrustrate.provenance import for_job

s = snakemake.params  # noqa: F821 (provided by snakemake; each value named in the rule)
FIELDS = ("index", "ell", "ell_pred", "ell_eigen", "nu")
with logging_to(snakemake.log[0]):  # noqa: F821
    batches = [load_npz(p) for p in snakemake.input]  # noqa: F821
    sample = {k: np.concatenate([b[k] for b in batches]) for k in FIELDS}
    finite = np.isfinite(sample["ell"]) & np.isfinite(sample["nu"])
    print(f"{len(finite)} matrices, {int((~finite).sum())} without a finite ell or nu (left out)")
    sample = {k: v[finite] for k, v in sample.items()}
    rng = np.random.default_rng([s["seed"], 1])
    plotted = np.sort(rng.choice(len(sample["ell"]), size=min(s["plotted"], len(sample["ell"])), replace=False))
    edges = np.linspace(0, 6, 121)
    hist, _ = np.histogram(sample["ell"], edges, density=True)
    above = float(np.mean(sample["ell"] >= edges[-1]))
    summary = {f"plotted_{k}": v[plotted] for k, v in sample.items()}
    summary.update(ell_edges=edges, ell_density=hist, ell_beyond=above, draws=len(finite))
    groups = np.asarray(s["ell_groups"], float)
    summary["nu_edges"] = np.linspace(-1, 1, 41)
    for i in range(len(groups) - 1):
        members = (sample["ell"] >= groups[i]) & (sample["ell"] < groups[i + 1])
        summary[f"group{i}_fraction"] = float(np.mean(members))
        # Each group's Poisson ratios before selection (Fig. S3b), as a density.
        summary[f"group{i}_nu_density"] = np.histogram(sample["nu"][members], summary["nu_edges"], density=True)[0]
        print(f"ell in [{groups[i]:g}, {groups[i + 1]:g}): fraction {summary[f'group{i}_fraction']:.4f}")
    save_npz(snakemake.output.summary, provenance=for_job(snakemake), **summary)  # noqa: F821

    selection = {}
    sizes = np.sort(rng.choice(len(sample["ell"]), size=min(s["size_particles"], len(sample["ell"])), replace=False))
    selection.update(sizes_index=sample["index"][sizes], sizes_ell=sample["ell"][sizes], sizes_nu=sample["nu"][sizes])
    nu_bins = np.linspace(-1, 1, s["nu_bins"] + 1)
    for i, count in enumerate(s["group_counts"]):
        members = np.flatnonzero((sample["ell"] >= groups[i]) & (sample["ell"] < groups[i + 1]))
        chosen = members[rp.select_uniform(sample["nu"][members], count, nu_bins, seed=s["seed"] + i)]
        print(f"group {i}: {len(members)} candidates, {len(chosen)} chosen")
        selection.update({f"group{i}_index": sample["index"][chosen], f"group{i}_ell": sample["ell"][chosen],
                          f"group{i}_nu": sample["nu"][chosen]})
    save_npz(snakemake.output.selection, provenance=for_job(snakemake), **selection)  # noqa: F821
