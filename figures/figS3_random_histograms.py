"""Fig. S3: (a) probability density of the boundary-layer length ell over all drawn matrices,
decaying fast at large ell (hence the large sample); (b) Poisson ratios in each ell group: the
whole drawn population (lines, density) and the particles selected for Fig. 6 (steps, density),
near-uniform by construction where the population allows: particles with both large ell and
small nu are scarce."""
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job


def main(summary_path, selection_path, edges, outputs, provenance=None):
    s, sel = load_npz(summary_path), load_npz(selection_path)
    fig = plotting.figure(plotting.PAGE_WIDTH_CM, 6.5)
    ax = fig.add_subplot(1, 2, 1)
    e = s["ell_edges"]
    ax.stairs(s["ell_density"], e, color="k")
    ax.set_yscale("log")
    for edge in edges[1:-1]:
        ax.axvline(edge, color="0.6", lw=0.6, ls=":")
    ax.set_xlabel(r"boundary-layer length $\ell$")
    ax.set_ylabel("probability density")
    ax.set_title(f"{int(s['draws']):,} random matrices")
    plotting.panel_label(ax, "a")
    ax = fig.add_subplot(1, 2, 2)
    colors = ["#1b9e77", "#d95f02", "#7570b3", "#e7298a"]
    bins = np.linspace(-1, 1, 21)
    for i in range(len(edges) - 1):
        nu = sel[f"group{i}_nu"]
        hi = "\\infty" if edges[i + 1] > 1e6 else f"{edges[i + 1]:g}"
        ax.stairs(s[f"group{i}_nu_density"], s["nu_edges"], color=colors[i % 4], lw=0.8, alpha=0.8,
                  label=rf"$\ell\in[{edges[i]:g},{hi})$: all, {100 * float(s[f'group{i}_fraction']):.2g} % of draws")
        ax.hist(nu, bins, density=True, histtype="step", color=colors[i % 4], lw=1.4, ls="--",
                label=f"    selected: {len(nu)} particles")
    ax.set_xlabel(r"Poisson ratio $\nu$")
    ax.set_ylabel("probability density")
    ax.legend(ncol=1, loc="upper left", bbox_to_anchor=(1.02, 1.0))
    plotting.panel_label(ax, "b")
    fig.subplots_adjust(left=0.07, right=0.66, bottom=0.17, top=0.9, wspace=0.3)
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.summary, snakemake.input.selection, snakemake.params.ell_groups,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
