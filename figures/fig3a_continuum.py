"""Fig. 3a: continuum phase diagram in the (Gamma, nu) plane. Regions: disk (red), fibre (blue),
bulk (purple); shading and contours give the optimal fibre width W*/ell and disk radius R*/ell.
Fibre widths diverge at the fibre-bulk boundary Gamma = 1; the disk radius jumps at the
disk-bulk boundary; the three phases meet at (Gamma, nu) = (1, 1/2). Each line is drawn only
where it is a phase boundary (plotting.continuum_boundaries): Gamma = 1 from nu = 1 down to the
triple point, the disk-bulk line below it."""
import numpy as np
from matplotlib.colors import LinearSegmentedColormap, LogNorm

from pyfrustrate import plotting
from pyfrustrate.io import load_npz, logging_to


def shaded(color):
    return LinearSegmentedColormap.from_list("shade", ["#ffffff", color])


def main(data_path, outputs):
    d = load_npz(data_path)
    nu, G, phase = d["nu"], d["Gamma"], d["phase"]
    fig = plotting.figure(12.0, 9.0)
    ax = fig.add_axes([0.1, 0.12, 0.6, 0.8])
    extent = (G[0], G[-1], nu[0], nu[-1])
    norm = LogNorm(0.3, 30)
    images = {}
    for name, size in (("fiber", d["width"]), ("disk", d["radius"])):
        field = np.where(phase == name, np.clip(size, norm.vmin, norm.vmax), np.nan)
        images[name] = ax.imshow(field, origin="lower", extent=extent, aspect="auto", norm=norm,
                                 cmap=shaded(plotting.PHASE_COLORS[name]), interpolation="nearest")
    bulk = np.where(phase == "bulk", 1.0, np.nan)
    ax.imshow(bulk, origin="lower", extent=extent, aspect="auto", cmap=shaded(plotting.PHASE_COLORS["bulk"]),
              vmin=0, vmax=1.6, interpolation="nearest")

    levels = [0.5, 1, 2, 4, 8]
    for name, size, color in (("fiber", d["width"], "#003f4a"), ("disk", d["radius"], "#6b0016")):
        field = np.where(phase == name, size, np.nan)
        cs = ax.contour(G, nu, field, levels=levels, colors=color, linewidths=0.5)
        ax.clabel(cs, fontsize=6, fmt="%g")

    boundaries = plotting.draw_continuum_boundaries(ax, d)
    triple = plotting.continuum_triple_point(boundaries, d["line_nu"])
    ax.plot(*triple, "o", ms=4, mfc="w", mec="k", zorder=5)
    ax.annotate(rf"triple point $({triple[0]:.2g}, {triple[1]:.2g})$", triple, xytext=(1.08, 0.38), fontsize=7,
                arrowprops=dict(arrowstyle="-", lw=0.5))
    for text, xy, color in (("fiber", (0.6, 0.88), "k"), ("disk", (0.35, 0.15), "k"), ("bulk", (1.3, 0.6), "w")):
        ax.text(*xy, text, color=color, fontsize=10, ha="center", fontweight="bold")
    ax.set_xlim(G[0], G[-1])
    ax.set_ylim(0, 1)
    ax.set_xlabel(r"line tension $\Gamma$")
    ax.set_ylabel(r"Poisson ratio $\nu$")
    ax.spines[["top", "right"]].set_visible(True)

    plotting.size_colorbars(fig, images, left=0.74, bottom=0.12, height=0.8)
    plotting.save(fig, outputs)


if "snakemake" in globals():
    with logging_to(snakemake.log[0]):  # noqa: F821
        main(snakemake.input[0], [snakemake.output.pdf, snakemake.output.png])  # noqa: F821
