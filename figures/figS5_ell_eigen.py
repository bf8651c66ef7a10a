"""Fig. S5: the softest-mode predictor ell_eigen = 1/sqrt(min eigenvalue of M) against the
boundary-layer length ell: no correlation, unlike ell_pred (Fig. 5c). Centre: all particles on
logarithmic axes with the line ell = ell_eigen; left and right: close-ups of the two regions
framed in black (the dense core, and the tail of soft modes). Grey levels: particles per
hexagonal bin, one logarithmic scale for the three panels."""
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import LogNorm

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job

WIDTH_CM, HEIGHT_CM = plotting.PAGE_WIDTH_CM, 6.8
# (ell_eigen range, ell range) of the two close-ups, and where each is drawn (left cm).
CLOSE_UPS = (((0.5, 6.0), (0.2, 3.0), 1.2), ((6.0, 60.0), (0.2, 3.0), 13.3))


def main(summary_path, outputs, provenance=None):
    s = load_npz(summary_path)
    ell, eig = s["plotted_ell"].astype(float), s["plotted_ell_eigen"].astype(float)
    ok = np.isfinite(eig) & (ell > 0) & (eig > 0)
    fig = plotting.figure(WIDTH_CM, HEIGHT_CM)

    def rect(left, w):
        return [left / WIDTH_CM, 1.0 / HEIGHT_CM, w / WIDTH_CM, 5.0 / HEIGHT_CM]

    ax = fig.add_axes(rect(6.9, 5.0))
    bins = ax.hexbin(eig[ok], ell[ok], xscale="log", yscale="log", gridsize=40, bins="log", cmap="Greys", mincnt=1,
                     linewidths=0)
    norm = LogNorm(1, bins.get_array().max())
    bins.set_norm(norm)
    lo, hi = 0.1, max(eig[ok].max(), ell[ok].max()) * 1.5
    ax.plot([lo, hi], [lo, hi], color="#d3002d", lw=1.0, label=r"$\ell = \ell^\mathrm{eigen}$")
    ax.set_xlim(0.3, hi)
    ax.set_ylim(0.1, 10)
    r = np.corrcoef(np.log(eig[ok]), np.log(ell[ok]))[0, 1]
    ax.text(0.96, 0.04, f"{ok.sum()} particles\ncorrelation of logs {r:.2f}", transform=ax.transAxes, va="bottom",
            ha="right")
    ax.legend(loc="upper left")
    ax.set_xlabel(r"$\ell^\mathrm{eigen} = 1/\sqrt{\min_i \lambda_i}$")
    ax.set_ylabel(r"$\ell$ (transfer problem)")
    bar = fig.colorbar(bins, cax=ax.inset_axes([0.5, 0.9, 0.45, 0.04]), orientation="horizontal")
    bar.ax.set_title("particles per bin", pad=2)
    plotting.panel_label(ax, "b")
    for label, ((x0, x1), (y0, y1), left) in zip("ac", CLOSE_UPS):
        ax.add_patch(plt.Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, color="k", lw=0.8))
        # Which close-up each frame is, at the frame's top corner (above it, off the data).
        ax.annotate(label, (x0, y1), xytext=(1, 1), textcoords="offset points", ha="left", va="bottom",
                    fontweight="bold")
        sub = fig.add_axes(rect(left, 4.2))
        inside = ok & (eig > x0) & (eig < x1) & (ell > y0) & (ell < y1)
        sub.hexbin(eig[inside], ell[inside], gridsize=30, bins="log", cmap="Greys", mincnt=1, linewidths=0,
                   extent=(x0, x1, y0, y1), norm=norm)
        sub.plot([x0, x1], [x0, x1], color="#d3002d", lw=1.0)
        sub.set_xlim(x0, x1)
        sub.set_ylim(y0, y1)
        sub.set_xlabel(r"$\ell^\mathrm{eigen}$")
        sub.set_ylabel(r"$\ell$")
        for spine in ("top", "right"):
            sub.spines[spine].set_visible(True)
        plotting.panel_label(sub, label)
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input.summary, [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
