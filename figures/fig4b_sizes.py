"""Fig. 4b: optimal fibre width W* (nu = 0.95) and disk radius R* (nu = 0.2) against Gamma for
several ell. Left: in lattice units (numbers of particles), strongly ell-dependent. Right:
divided by ell, collapsing onto the continuum prediction (dashed red) down to ell ~ 1."""
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to


def main(data_path, outputs):
    d = load_npz(data_path)
    G, ells = d["Gamma"], d["ells"]
    fig = plotting.figure(17.8, 11.0)
    colors = ["#1b9e77", "#d95f02", "#7570b3", "#e7298a", "#66a61e", "#e6ab02"]
    for row, (kind, symbol) in enumerate((("fiber", "W"), ("disk", "R"))):
        nu = float(d[f"{kind}_nu"])
        for col in range(2):
            ax = fig.add_subplot(2, 2, 2 * row + col + 1)
            for ell, length, at_cap, c in zip(ells, d[f"{kind}_length"], d[f"{kind}_at_cap"], colors):
                y = length if col == 0 else length / ell
                y = np.where(at_cap, np.nan, y)  # the catalogue's largest member: a lower bound only
                ax.step(G, y, where="mid", color=c, lw=1.0, label=rf"$\ell = {ell:g}$")
            if col == 1:
                ax.plot(G, d[f"{kind}_theory"], "--", color="#d3002d", lw=1.4, label="continuum")
                ax.set_ylabel(rf"${symbol}^*/\ell$")
            else:
                ax.set_ylabel(rf"${symbol}^*$ (particle spacings)")
            ax.set_xlabel(r"$\Gamma$")
            ax.set_title(rf"best {'fibre' if kind == 'fiber' else 'disk'}, $\nu = {nu:g}$", fontsize=8)
            ax.set_xlim(0, G[-1])
            ax.set_ylim(0, None)
            if row == 0 and col == 1:
                ax.legend(frameon=False, fontsize=7)
    fig.tight_layout()
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input[0], [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
