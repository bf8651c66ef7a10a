"""Fig. 4b: optimal fibre width W* (nu = 0.95) and disk radius R* (nu = 0.2) against Gamma for
several ell. Left: in lattice units (numbers of particles), strongly ell-dependent. Right:
divided by ell, against the continuum prediction (dashed red); each ell's legend entry gives
its median W*/W*_continuum (R*/R*_continuum) over the Gamma grid, with the quartiles; a file
beside the figure (the rule's summary output) gives the ell range over which the median is
within COLLAPSE_TOLERANCE of 1.

The medians themselves are not written here: they are measured at each build and printed in
the legend and the summary file (on the quick profile the fibres at ell = 1, one to four lattice
spacings wide, are the ones that sit above the continuum)."""
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to, save_json
from pyfrustrate.provenance import for_job

COLLAPSE_TOLERANCE = 0.10  # |median ratio - 1| within which we call the sizes collapsed


def size_ratios(d, kind):
    """Per ell: the sizes over ell divided by the continuum's, where both are defined and the
    size is not the catalogue's largest member (a lower bound only); nan elsewhere."""
    theory = d[f"{kind}_theory"]
    ratios = []
    for ell, length, at_cap in zip(d["ells"], d[f"{kind}_length"], d[f"{kind}_at_cap"]):
        with np.errstate(divide="ignore", invalid="ignore"):
            r = length / ell / theory
        ratios.append(np.where(~at_cap & np.isfinite(r) & (theory > 0), r, np.nan))
    return np.array(ratios)


def collapse_range(ells, medians) -> str:
    """The smallest ell from which every larger ell's median ratio is within tolerance."""
    ok = np.abs(np.asarray(medians) - 1) <= COLLAPSE_TOLERANCE
    if not ok[-1]:
        return "no ell"
    first = len(ok) - np.argmin(ok[::-1]) if not ok.all() else 0
    return f"ℓ ≥ {ells[first]:g}"


def main(data_path, outputs, provenance=None, summary_path=None):
    d = load_npz(data_path)
    G, ells = d["Gamma"], d["ells"]
    fig = plotting.figure(plotting.PAGE_WIDTH_CM, 10.2)
    colors = ["#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02"]
    summary = []
    grid = fig.add_gridspec(2, 3, width_ratios=[1, 1, 0.5])
    for row, (kind, symbol) in enumerate((("fiber", "W"), ("disk", "R"))):
        nu = float(d[f"{kind}_nu"])
        ratios = size_ratios(d, kind)
        medians = np.nanmedian(ratios, axis=1)
        quartiles = np.nanpercentile(ratios, [25, 75], axis=1).T
        for ell, med, (q1, q3) in zip(ells, medians, quartiles):
            print(f"{kind} ell = {ell:g}: median {symbol}*/{symbol}*_continuum = {med:.3f} "
                  f"(quartiles {q1:.3f}-{q3:.3f})")
        summary.append(f"{symbol}*/{symbol}*_continuum within {100 * COLLAPSE_TOLERANCE:.0f} % (median) for "
                       f"{collapse_range(ells, medians)}")
        for col in range(2):
            ax = fig.add_subplot(grid[row, col])
            for ell, length, at_cap, med, (q1, q3), c in zip(ells, d[f"{kind}_length"], d[f"{kind}_at_cap"],
                                                          medians, quartiles, colors):
                y = length if col == 0 else length / ell
                y = np.where(at_cap, np.nan, y)  # the catalogue's largest member: a lower bound only
                label = rf"$\ell = {ell:g}$"
                if col == 1:
                    label += f": {med:.2f} ({q1:.2f}-{q3:.2f})"
                ax.step(G, y, where="mid", color=c, lw=1.0, label=label)
            if col == 1:
                ax.plot(G, d[f"{kind}_theory"], "--", color="#d3002d", lw=1.4, label="continuum")
                ax.set_ylabel(rf"${symbol}^*/\ell$")
                # Beside the panel: inside, it would cover the curves.
                legend_ax = fig.add_subplot(grid[row, 2])
                legend_ax.axis("off")
                legend_ax.legend(*ax.get_legend_handles_labels(), loc="center left",
                                 title=rf"median ${symbol}^*/{symbol}^*_\mathrm{{continuum}}$" "\n(quartiles) over the "
                                 r"$\Gamma$ grid", alignment="left")
            else:
                ax.set_ylabel(rf"${symbol}^*$ ({plotting.LENGTH_UNIT})")
            ax.set_xlabel(plotting.LABELS["Gamma"])
            ax.set_title(rf"best {'fibre' if kind == 'fiber' else 'disk'}, $\nu$ = {nu:g}")
            if row == 0 and col == 0:
                plotting.panel_label(ax, "b", dx_pt=-22)
            ax.set_xlim(0, G[-1])
            ax.set_ylim(0, None)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    plotting.save(fig, outputs, provenance)
    # The conclusion goes beside the figure, not into it (the gallery shows it with the caption).
    text = "Collapse onto the continuum: " + "; ".join(summary) + "."
    print(text)
    if summary_path is not None:
        save_json(summary_path, {"summary": text}, provenance=provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input[0], [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake), summary_path=snakemake.output.summary)  # noqa: F821
