"""Fig. 1: the 1D toy model. (a) A relaxed chain of trapezoids (mismatch exaggerated);
(b) the corner shift delta_i from the kernel's L-BFGS against the exact sinh form;
(c) the fitted boundary-layer length against main text Eq. (3)."""
import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.patches import Polygon

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to


def draw_chain(ax, x_up, x_down):
    for i in range(len(x_up) - 1):
        quad = [(x_down[i], 0), (x_down[i + 1], 0), (x_up[i + 1], 1), (x_up[i], 1)]
        ax.add_patch(Polygon(quad, closed=True, facecolor="0.93", edgecolor="none"))
    top = [((x_up[i], 1), (x_up[i + 1], 1)) for i in range(len(x_up) - 1)]
    bottom = [((x_down[i], 0), (x_down[i + 1], 0)) for i in range(len(x_down) - 1)]
    sides = [((x_down[i], 0), (x_up[i], 1)) for i in range(len(x_up))]
    ax.add_collection(LineCollection(sides, colors=plotting.BLUE_SPRING, linewidths=1.0))
    ax.add_collection(LineCollection(top, colors=plotting.YELLOW, linewidths=2.0))
    ax.add_collection(LineCollection(bottom, colors=plotting.RED_CORNER, linewidths=2.0))
    ax.set_xlim(min(x_up.min(), x_down.min()) - 0.3, max(x_up.max(), x_down.max()) + 0.3)
    ax.set_ylim(-0.4, 1.4)
    ax.set_aspect("equal")
    ax.axis("off")


def main(data_path, outputs):
    d = load_npz(data_path)
    fig = plotting.figure(17.8, 9.5)
    grid = fig.add_gridspec(2, 2, height_ratios=[0.75, 1.6], hspace=0.45, wspace=0.3)

    ax = fig.add_subplot(grid[0, :])
    draw_chain(ax, d["drawing_x_up"], d["drawing_x_down"])
    ax.text(0.5, 1.0, f"relaxed chain, $k_c/k = {float(d['drawing_kc_over_k']):g}$, "
            f"$\\epsilon = {float(d['drawing_eps']):g}$ (exaggerated): yellow faces rest at $1+\\epsilon$, "
            "red at $1-\\epsilon$, blue connecting springs", transform=ax.transAxes, ha="center", fontsize=8)
    plotting.panel_label(ax, "a")

    ax = fig.add_subplot(grid[1, 0])
    n = int(d["n"])
    i = np.arange(n + 1)
    colors = ["#1b9e77", "#d95f02", "#7570b3", "#e7298a"]
    for ratio, num, exact, c in zip(d["profile_kc_over_k"], d["profiles"], d["exact"], colors):
        ax.plot(i, exact / d["eps"], "-", color=c, lw=1.0, label=f"exact, $k_c/k={ratio:g}$")
        ax.plot(i[::2], num[::2] / d["eps"], "o", ms=2.5, mfc="none", color=c)
    ax.plot([], [], "o", ms=2.5, mfc="none", color="0.3", label="kernel L-BFGS")
    ax.axhline(0, color="0.7", lw=0.5)
    ax.set_xlabel("corner index $i$")
    ax.set_ylabel(r"shift $\delta_i/\epsilon = (x_i^\uparrow - x_i^\downarrow)/\epsilon$")
    ax.legend(frameon=False, loc="upper left")
    plotting.panel_label(ax, "b")

    ax = fig.add_subplot(grid[1, 1])
    x = d["scan_kc_over_k"]
    ax.loglog(x, d["scan_ell_theory"], "-", color="k", lw=1.0, label=r"Eq. (3): $1/\ln[1+x+\sqrt{2x+x^2}]$")
    ax.loglog(x, np.sqrt(1 / (2 * x)), "--", color="0.5", lw=0.8, label=r"$\sqrt{k/2k_c}$")
    ax.loglog(x, d["scan_ell_fit"], "o", ms=3.5, mfc="none", color="#d95f02", label="fit to relaxed chains")
    ax.set_xlabel(r"$x = k_c/k$")
    ax.set_ylabel(r"boundary-layer length $\ell$")
    ax.legend(frameon=False)
    plotting.panel_label(ax, "c")
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input[0], [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
