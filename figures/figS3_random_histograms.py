"""Fig. S3: (a) probability density of the boundary-layer length ell over all drawn matrices,
decaying fast at large ell (hence the large sample); (b) Poisson ratios in each ell group: the
whole drawn population (shaded, density) and the particles selected for Fig. 6 (black, density),
one panel per group,
near-uniform by construction where the population allows: particles with both large ell and
small nu are scarce."""
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job


def main(summary_path, selection_path, edges, outputs, provenance=None):
    s, sel = load_npz(summary_path), load_npz(selection_path)
    width_cm, height_cm = plotting.PAGE_WIDTH_CM, 6.5
    fig = plotting.figure(width_cm, height_cm)

    def rect(left, bottom, w, h):
        return [left / width_cm, bottom / height_cm, w / width_cm, h / height_cm]

    ax = fig.add_axes(rect(1.3, 1.1, 4.4, 4.2))
    e = s["ell_edges"]
    ax.stairs(s["ell_density"], e, color="k")
    ax.set_yscale("log")
    for edge in edges[1:-1]:
        ax.axvline(edge, color="0.6", lw=0.6, ls=":")
    ax.set_xlabel(r"boundary-layer length $\ell$")
    ax.set_ylabel("probability density")
    # The density stops at the last bin edge; the title says how much of the sample lies beyond.
    ax.set_title(f"{int(s['draws']):,} random matrices\n"
                 rf"{100 * float(s['ell_beyond']):.2g} % with $\ell$ > {e[-1]:g} (not drawn)")
    plotting.panel_label(ax, "a", at_cm=(0.15, height_cm - 0.1))
    # (b) one panel per ell group, on one density scale: the whole drawn population of the group
    # (shaded) and the particles selected from it for Fig. 6 (black), near-uniform where the
    # population allows.
    drawn = "0.55"  # one neutral shade: each panel is one group, and colours mean phases elsewhere
    bins = np.linspace(-1, 1, 21)
    groups = len(edges) - 1
    left, gap = 7.0, 0.45
    panel_w = (width_cm - 0.4 - left - gap * (groups - 1)) / groups
    top = max(max(float(np.max(s[f"group{i}_nu_density"])) for i in range(groups)),
              max(float(np.max(np.histogram(sel[f"group{i}_nu"], bins, density=True)[0])) for i in range(groups)))
    for i in range(groups):
        ax = fig.add_axes(rect(left + i * (panel_w + gap), 1.1, panel_w, 4.2))
        nu = sel[f"group{i}_nu"]
        hi = "\\infty" if edges[i + 1] > 1e6 else f"{edges[i + 1]:g}"
        ax.stairs(s[f"group{i}_nu_density"], s["nu_edges"], color=drawn, lw=0.8, fill=True, alpha=0.35,
                  label="all drawn")
        ax.stairs(s[f"group{i}_nu_density"], s["nu_edges"], color=drawn, lw=0.8)
        ax.stairs(np.histogram(nu, bins, density=True)[0], bins, color="k", lw=1.2, label="selected")
        ax.set_ylim(0, 1.3 * top)
        ax.set_xlim(-1, 1)
        ax.set_xticks([-1, 0, 1])
        ax.set_xlabel(r"Poisson ratio $\nu$")
        ax.set_title(rf"$\ell\in[{edges[i]:g},{hi})$" "\n"
                     f"{100 * float(s[f'group{i}_fraction']):.2g} % of draws\n{len(nu)} selected")
        if i == 0:
            ax.set_ylabel("probability density")
            ax.legend(loc="upper left")
            plotting.panel_label(ax, "b", at_cm=(left - 1.0, height_cm - 0.1))
        else:
            ax.tick_params(labelleft=False)
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.summary, snakemake.input.selection, snakemake.params.ell_groups,  # noqa: F821
             [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
