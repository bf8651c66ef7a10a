"""Fig. S3: (a) probability density of the boundary-layer length ell over all drawn matrices,
decaying fast at large ell (hence the large sample); (b) Poisson ratios of the particles
selected in each ell group for Fig. 6, near-uniform by construction."""
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to


def main(summary_path, selection_path, edges, outputs):
    s, sel = load_npz(summary_path), load_npz(selection_path)
    fig = plotting.figure(17.8, 6.5)
    ax = fig.add_subplot(1, 2, 1)
    e = s["ell_edges"]
    ax.stairs(s["ell_density"], e, color="k")
    ax.set_yscale("log")
    for edge in edges[1:-1]:
        ax.axvline(edge, color="0.6", lw=0.6, ls=":")
    ax.set_xlabel(r"boundary-layer length $\ell$")
    ax.set_ylabel("probability density")
    ax.set_title(f"{int(s['draws']):,} random matrices", fontsize=8)
    plotting.panel_label(ax, "a")
    ax = fig.add_subplot(1, 2, 2)
    colors = ["#1b9e77", "#d95f02", "#7570b3", "#e7298a"]
    bins = np.linspace(-1, 1, 21)
    for i in range(len(edges) - 1):
        nu = sel[f"group{i}_nu"]
        hi = "\\infty" if edges[i + 1] > 1e6 else f"{edges[i + 1]:g}"
        ax.hist(nu, bins, histtype="step", color=colors[i % 4], lw=1.2,
                label=rf"$\ell\in[{edges[i]:g},{hi})$: {len(nu)}")
    ax.set_xlabel(r"Poisson ratio $\nu$")
    ax.set_ylabel("particles selected")
    ax.legend(frameon=False, fontsize=7)
    plotting.panel_label(ax, "b")
    fig.tight_layout()
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.summary, snakemake.input.selection, snakemake.params.settings["ell_groups"],  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
