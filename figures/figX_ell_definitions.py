"""Beyond the paper: what "the boundary-layer length" means, and whether any meaning reproduces
the paper's statements about random particles (pyfrustrate.boundary_layer).

(a) P(ell >= x) under each definition: the exact slowest mode of the half-plane (the package's
default), the slowest mode the edge excites (a share of at least 10 % or 50 % of the edge
displacement), and the paper's protocol read literally (a slab of D rows relaxed nonlinearly,
the excess energy fitted from the second row to the centre, relative to the central row or to
the exact bulk). The star is the paper's ell >= 1.5 batch (1.25e5 of 3e7 draws, 0.42 %).
(b) The median of ell_pred / ell (dot) and the fraction of particles with ell_pred > ell (bar);
the paper says ell_pred tends to overestimate ell.
(c) The fraction of auxetic particles (nu < 0) in each ell group under each definition: the paper
says particles with both large ell and small nu are scarce, so the fraction should fall steeply
with ell."""
import json

import numpy as np

from pyfrustrate import plotting
from pyfrustrate.boundary_layer import definition_names
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job

PAPER_THRESHOLD, PAPER_FRACTION = 1.5, 1.25e5 / 3e7


def style(name):
    """Colour, line style and legend label of a definition."""
    if name == "slowest":
        return "k", "-", "slowest mode (default)"
    if name.startswith("excited_share"):
        share = float(name[len("excited_share"):])
        return ("#7b3294", "--", f"excited mode, share $\\geq$ {share:g}") if share < 0.3 else \
            ("#c2a5cf", "-.", f"excited mode, share $\\geq$ {share:g}")
    depth, reference = name[len("finite_depth"):].split("_")
    shade = {"10": 0.35, "20": 0.6, "40": 0.85}.get(depth, 0.6)
    cmap = plotting.plt.get_cmap("Blues" if reference == "centre" else "Oranges")
    return cmap(shade), "-" if reference == "centre" else ":", f"slab fit, depth {depth}, vs {reference}"


def main(study_path, table_path, ell_groups, outputs, provenance=None):
    study, table = load_npz(study_path), json.load(open(table_path))
    names = definition_names(study)
    n = len(study["slowest"])
    fig = plotting.figure(17.8, 7.2)
    ax = fig.add_axes([0.065, 0.17, 0.245, 0.73])
    x = np.linspace(0.2, 6, 300)
    for name in names:
        ell = np.asarray(study[name])
        ell = ell[np.isfinite(ell)]
        color, ls, _ = style(name)
        ax.plot(x, [np.mean(ell >= v) for v in x], color=color, ls=ls, lw=1.1)
    ax.plot([PAPER_THRESHOLD], [PAPER_FRACTION], marker="*", ms=11, color="#d3002d", ls="none",
            label="paper: 0.42 % with $\\ell \\geq 1.5$", zorder=5)
    ax.axvline(PAPER_THRESHOLD, color="0.7", lw=0.6, ls=":")
    ax.set_yscale("log")
    ax.set_ylim(max(0.3 / n, 1e-5), 1.05)
    ax.set_xlim(x[0], x[-1])
    ax.set_xlabel(rf"boundary-layer length $x$ ({plotting.LENGTH_UNIT})")
    ax.set_ylabel(r"$P(\ell \geq x)$")
    ax.set_title(f"{n:,} random particles")
    ax.legend(loc="lower left")
    plotting.panel_label(ax, "a")

    ax = fig.add_axes([0.545, 0.17, 0.2, 0.73])
    rows = np.arange(len(names))[::-1]
    for row, name in zip(rows, names):
        color, _, _ = style(name)
        entry = table["definitions"][name]
        ax.barh(row, entry["above_one"], color=color, alpha=0.35, height=0.7)
        ax.plot(entry["median_ratio"], row, "o", color=color, ms=4)
        ax.plot([1.12, 1.38], [row, row], color=color, ls=style(name)[1], lw=1.2)  # the key of (a) and (c)
    ax.axvline(1.0, color="#d3002d", lw=1.0)
    ax.text(0.98, rows[0] + 0.55, "paper: > 1", color="#d3002d", va="bottom", ha="right")
    ax.set_yticks(rows, [style(nm)[2] for nm in names])
    ax.set_xticks([0, 0.5, 1.0])
    ax.set_xlim(0, 1.42)
    ax.set_ylim(-0.7, len(names) - 0.1)
    ax.set_xlabel(r"median $\ell^{\rm pred}/\ell$ (dots)" "\n" r"$P(\ell^{\rm pred} > \ell)$ (bars)")
    plotting.panel_label(ax, "b")

    ax = fig.add_axes([0.81, 0.2, 0.16, 0.7])
    labels = []
    for g in range(len(ell_groups) - 1):
        hi = "\\infty" if ell_groups[g + 1] > 1e6 else f"{ell_groups[g + 1]:g}"
        labels.append(rf"$[{ell_groups[g]:g}, {hi})$")
    for name in names:
        color, ls, _ = style(name)
        entry = table["definitions"][name]
        ax.plot(range(len(labels)), [entry[f"group{g}_P_nu_below_0"] for g in range(len(labels))], color=color, ls=ls,
                marker="o", ms=3, lw=1.0)
    ax.set_xticks(range(len(labels)), labels)
    ax.set_xlabel(r"$\ell$ group")
    ax.set_ylabel(r"$P(\nu < 0)$ in the group")
    ax.set_ylim(0, None)
    plotting.panel_label(ax, "c")
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        groups = [float(g) for g in snakemake.params.ell_groups]  # noqa: F821
        outputs = [snakemake.output.pdf, snakemake.output.png]  # noqa: F821
        main(snakemake.input.study, snakemake.input.table, groups, outputs, provenance=for_job(snakemake))  # noqa: F821
