"""Fig. 1: the 1D toy model. (a) A relaxed chain of trapezoids (mismatch exaggerated): yellow
faces rest at 1 + eps, red at 1 - eps, blue connecting springs; (b) the corner shift delta_i
from the kernel's L-BFGS against the exact sinh form; (c) the fitted boundary-layer length
against main text Eq. (3)."""
import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.patches import Polygon

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to
from pyfrustrate.provenance import for_job


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


WIDTH_CM, HEIGHT_CM = plotting.PAGE_WIDTH_CM, 8.6


def main(data_path, outputs, provenance=None):
    d = load_npz(data_path)
    fig = plotting.figure(WIDTH_CM, HEIGHT_CM)

    def rect(left, bottom, w, h):
        return [left / WIDTH_CM, bottom / HEIGHT_CM, w / WIDTH_CM, h / HEIGHT_CM]

    ax = fig.add_axes(rect(0.6, 6.3, 16.6, 1.8))
    draw_chain(ax, d["drawing_x_up"], d["drawing_x_down"])
    # The drawing's equal aspect shrinks its axes: the letter goes where (b)'s stands, 6 pt left
    # of that panel's axes at 1.4 cm (its right edge; "(b)" is about 0.5 cm wide).
    plotting.panel_label(ax, "a", at_cm=(1.4 - 6 / 72 * 2.54 - 0.5, HEIGHT_CM - 0.1))

    ax = fig.add_axes(rect(1.4, 0.9, 6.9, 4.6))
    n = int(d["n"])
    i = np.arange(n + 1)
    colors = ["#1b9e77", "#d95f02", "#7570b3", "#e7298a"]
    for ratio, num, exact, c in zip(d["profile_kc_over_k"], d["profiles"], d["exact"], colors):
        ax.plot(i, exact / d["eps"], "-", color=c, lw=1.0, label=f"$k_c/k$ = {ratio:g}")
        ax.plot(i[::2], num[::2] / d["eps"], "o", ms=2.5, mfc="none", color=c, mew=0.6)
    ax.plot([], [], "k-", lw=1.0, label="exact (sinh)")
    ax.plot([], [], "o", ms=2.5, mfc="none", color="k", mew=0.6, label="relaxed numerically")
    ax.axhline(0, color="0.7", lw=0.5)
    ax.set_xlabel("corner index $i$")
    ax.set_ylabel(r"shift $\delta_i/\epsilon$")
    ax.legend(loc="upper center", ncol=2)
    ax.set_ylim(top=ax.get_ylim()[1] * 1.45)
    plotting.panel_label(ax, "b")

    ax = fig.add_axes(rect(10.3, 0.9, 6.9, 4.6))
    x = d["scan_kc_over_k"]
    # The lines over the circles, and circles small and thin enough that a dense scan (the paper
    # profile's 41 points over four decades) does not hide them.
    ax.loglog(x, d["scan_ell_theory"], "-", color="k", lw=0.8, label="Eq. (3)", zorder=3)
    ax.loglog(x, np.sqrt(1 / (2 * x)), "--", color="0.5", lw=0.8, label=r"$\sqrt{k/2k_c}$", zorder=3)
    ax.loglog(x, d["scan_ell_fit"], "o", ms=3.0, mew=0.6, mfc="none", color="#d95f02", label="fit to relaxed chains",
              zorder=2)
    ax.set_xlabel(r"coupling stiffness $k_c/k$")
    ax.set_ylabel(plotting.LABELS["ell"])
    ax.legend(loc="upper right")
    plotting.panel_label(ax, "c")
    plotting.save(fig, outputs, provenance)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input[0], [snakemake.output.pdf, snakemake.output.png],  # noqa: F821
             provenance=for_job(snakemake))  # noqa: F821
