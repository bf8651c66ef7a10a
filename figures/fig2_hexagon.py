"""Fig. 2: the 2D particle model. (a) One particle at rest with its springs (mismatch
exaggerated): yellow and red triangles, blue connecting sides. (b) A small relaxed aggregate,
mismatch exaggerated: regular (bulk-like) hexagons inside, particles near the edge relaxing
towards their ill-fitting rest shape. (c) A relaxed hexagonal disk and (d) a relaxed fibre,
several ell across, each particle coloured by its deformation energy over the bulk value:
bulk-like centres, a cheaper shallow-bulk layer about ell inside the edge, and edges back near
the bulk value (where the stretched connecting springs carry the energy)."""
from matplotlib.colors import Normalize

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to


def caption(ax, text):
    ax.text(0.5, -0.01, text, transform=ax.transAxes, ha="center", va="top", fontsize=7)


def main(data_path, outputs):
    d = load_npz(data_path)
    fig = plotting.figure(17.8, 6.6)
    norm = Normalize(0.3, 1.1)
    cmap = "magma"
    eps = float(d["drawing_eps"])

    ax = fig.add_axes([0.0, 0.15, 0.14, 0.7])
    plotting.draw_particle_springs(ax, d["rest_corners"])
    caption(ax, rf"particle at rest, $\epsilon={eps:g}$")
    ax.axis("off")
    plotting.panel_label(ax, "a")

    ax = fig.add_axes([0.15, 0.05, 0.22, 0.85])
    plotting.draw_hexagons(ax, d["small_corners"], facecolor="0.92", edgecolor=plotting.BLUE_SPRING, linewidth=0.8)
    corners = d["small_corners"]
    ax.scatter(*corners[:, 1::2].reshape(-1, 2).T, s=4, color=plotting.YELLOW, edgecolor="k", linewidth=0.2, zorder=3)
    ax.scatter(*corners[:, 0::2].reshape(-1, 2).T, s=4, color=plotting.RED_CORNER, edgecolor="k", linewidth=0.2, zorder=3)
    caption(ax, rf"relaxed, $\epsilon={eps:g}$, $\ell={float(d['drawing_ell']):g}$")
    ax.axis("off")
    plotting.panel_label(ax, "b")

    ax = fig.add_axes([0.39, 0.05, 0.26, 0.85])
    plotting.draw_hexagons(ax, d["disk_corners"], d["disk_energy"], cmap=cmap, norm=norm, linewidth=0.1)
    caption(ax, f"disk, mean {float(d['disk_mean']):.2f} of bulk")
    ax.axis("off")
    plotting.panel_label(ax, "c")

    ax = fig.add_axes([0.67, 0.05, 0.22, 0.85])
    polys = plotting.draw_hexagons(ax, d["fiber_corners"], d["fiber_energy"], cmap=cmap, norm=norm, linewidth=0.1)
    caption(ax, f"fibre (periodic cell repeated), mean {float(d['fiber_mean']):.2f}")
    ax.axis("off")
    plotting.panel_label(ax, "d")

    cax = fig.add_axes([0.91, 0.15, 0.012, 0.7])
    fig.colorbar(polys, cax=cax, label="particle energy / bulk value", extend="both")
    fig.text(0.39, -0.06, rf"(c, d): $\ell = {float(d['ell']):g}$, $\nu = {float(d['nu']):g}$, "
             rf"$\epsilon = {float(d['eps']):g}$", fontsize=7)
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input[0], [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
