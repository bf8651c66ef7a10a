"""Fig. S5: the softest-mode predictor ell_eigen = 1/sqrt(min eigenvalue of M) against the
boundary-layer length ell: no correlation (right: a close-up), unlike ell_pred (Fig. 5c). Grey
levels: particles per hexagonal bin (log scale, colour bars)."""
import matplotlib.pyplot as plt
import numpy as np

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to


def count_colorbar(fig, bins, ax):
    bar = fig.colorbar(bins, ax=ax, pad=0.02, fraction=0.05)
    bar.set_label("particles per bin", fontsize=7)
    bar.ax.tick_params(labelsize=6)


def main(summary_path, outputs):
    s = load_npz(summary_path)
    ell, eig = s["plotted_ell"].astype(float), s["plotted_ell_eigen"].astype(float)
    ok = np.isfinite(eig) & (ell > 0)
    fig = plotting.figure(17.8, 7.0)
    ax = fig.add_subplot(1, 2, 1)
    bins = ax.hexbin(eig[ok], ell[ok], xscale="log", yscale="log", gridsize=45, bins="log", cmap="Greys", mincnt=1,
                     linewidths=0)
    count_colorbar(fig, bins, ax)
    r = np.corrcoef(np.log(eig[ok]), np.log(ell[ok]))[0, 1]
    ax.text(0.96, 0.96, f"{ok.sum()} particles\ncorr(log) = {r:.2f}", transform=ax.transAxes, va="top", ha="right",
            fontsize=7)
    box = (0.5, 6.0, 0.2, 3.0)
    ax.add_patch(plt.Rectangle((box[0], box[2]), box[1] - box[0], box[3] - box[2], fill=False, color="#d3002d", lw=0.8))
    ax.set_xlabel(r"$\ell^\mathrm{eigen} = 1/\sqrt{\min_i \lambda_i}$")
    ax.set_ylabel(r"$\ell$ (transfer problem)")
    ax = fig.add_subplot(1, 2, 2)
    inside = ok & (eig > box[0]) & (eig < box[1]) & (ell > box[2]) & (ell < box[3])
    bins = ax.hexbin(eig[inside], ell[inside], gridsize=35, bins="log", cmap="Greys", mincnt=1, linewidths=0,
                     extent=box)
    count_colorbar(fig, bins, ax)
    ax.set_xlim(*box[:2])
    ax.set_ylim(*box[2:])
    ax.set_xlabel(r"$\ell^\mathrm{eigen}$")
    ax.set_ylabel(r"$\ell$")
    ax.set_title("close-up (red box)", fontsize=8)
    fig.tight_layout()
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.summary, [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
