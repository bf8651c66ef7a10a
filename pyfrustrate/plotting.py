"""Shared figure style: the paper's colour code, particle drawing, atomic PDF + PNG output."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402

from .io import atomic_path  # noqa: E402

# Fig. 3 colour code: black bulk with holes, red disk, blue fibre, purple bulk.
PHASE_COLORS = {"bulk_with_holes": "#1a1a1a", "disk": "#d3002d", "fiber": "#007e94", "bulk": "#7b3294",
                "single": "#9e9e9e", "gas": "#b0b0b0"}
YELLOW, RED_CORNER, BLUE_SPRING = "#e6b800", "#d3002d", "#3b78c2"
# Colour of each corner slot (even slots red, odd yellow) and of each of the nine distances of
# a random particle (random_particles.DISTANCE_PAIRS: yellow sides, red sides, hexagon sides).
CORNER_COLORS = [RED_CORNER, YELLOW] * 3
DISTANCE_COLORS = [YELLOW] * 3 + [RED_CORNER] * 3 + [BLUE_SPRING] * 3

STYLE = {
    "font.size": 9, "axes.labelsize": 9, "axes.titlesize": 9, "legend.fontsize": 8,
    "xtick.labelsize": 8, "ytick.labelsize": 8, "figure.dpi": 150, "savefig.dpi": 200,
    "axes.spines.top": False, "axes.spines.right": False, "pdf.fonttype": 42,
}


# Corner slots that outline a particle, in order (kernel slot order): the hexagon's six corners;
# the triangle's yellow nodes (its red ones coincide with them without mismatch).
OUTLINE_SLOTS = {"hexagon": [0, 1, 2, 3, 4, 5], "triangle": [0, 1, 2]}


def figure(width_cm: float = 17.8, height_cm: float = 8.0, **kwargs):
    """A figure in the journal's column widths (8.6 cm single, 17.8 cm double)."""
    plt.rcParams.update(STYLE)
    return plt.figure(figsize=(width_cm / 2.54, height_cm / 2.54), **kwargs)


def save(fig, outputs) -> None:
    """Save ``fig`` to every path in ``outputs`` (format from the suffix), atomically."""
    for out in outputs:
        with atomic_path(out) as tmp:
            fig.savefig(tmp, format=str(out).rsplit(".", 1)[-1], bbox_inches="tight")
    plt.close(fig)


def panel_label(ax, label: str) -> None:
    ax.text(-0.02, 1.02, f"({label})", transform=ax.transAxes, ha="right", va="bottom", fontweight="bold")


def draw_hexagons(ax, corners, values=None, cmap="viridis", norm=None, edgecolor="0.25", linewidth=0.3, **kwargs):
    """Draw particles as filled hexagons. ``corners``: (n, 6, 2); ``values``: (n,) colours them."""
    polys = PolyCollection(np.asarray(corners), edgecolors=edgecolor, linewidths=linewidth, **kwargs)
    if values is not None:
        polys.set_array(np.asarray(values))
        polys.set_cmap(cmap)
        if norm is not None:
            polys.set_norm(norm)
    ax.add_collection(polys)
    ax.set_aspect("equal")
    ax.autoscale_view()
    return polys


def draw_particle_springs(ax, corners, linewidth: float = 1.2, markersize: float = 14) -> None:
    """One particle with its springs (Fig. 2a): yellow and red triangles, blue connecting sides.
    ``corners``: (6, 2), slots counter-clockwise from 30 degrees, odd slots yellow."""
    c = np.asarray(corners)
    sides = [(c[s], c[(s + 1) % 6]) for s in range(6)]
    yellow = [(c[s], c[(s + 2) % 6]) for s in (1, 3, 5)]
    red = [(c[s], c[(s + 2) % 6]) for s in (0, 2, 4)]
    ax.add_collection(LineCollection(sides, colors=BLUE_SPRING, linewidths=linewidth, zorder=1))
    ax.add_collection(LineCollection(yellow, colors=YELLOW, linewidths=linewidth, zorder=2))
    ax.add_collection(LineCollection(red, colors=RED_CORNER, linewidths=linewidth, zorder=2))
    ax.scatter(*c[1::2].T, s=markersize, color=YELLOW, edgecolor="k", linewidth=0.4, zorder=3)
    ax.scatter(*c[0::2].T, s=markersize, color=RED_CORNER, edgecolor="k", linewidth=0.4, zorder=3)
    ax.set_aspect("equal")
    ax.autoscale_view()


def shaded_colormap(color):
    """White-to-``color`` colormap, for sizes inside a region of a phase diagram."""
    from matplotlib.colors import LinearSegmentedColormap

    return LinearSegmentedColormap.from_list("shade", ["#ffffff", color])


def draw_ansatz_diagram(fig, ax, diagram: dict, continuum: dict, colorbar_axes=None):
    """Numerical phase diagram (Figs. 3b, S1): cells coloured by the winning aggregate (black bulk
    with holes, red disk, blue fibre, purple bulk), disks and fibres shaded by R/ell and W/ell,
    with the continuum boundaries of Fig. 3a as dashed lines."""
    from matplotlib.colors import LogNorm
    from matplotlib.patches import Patch

    nu, G, phase, length = diagram["nu"], diagram["Gamma"], diagram["phase"], diagram["length"]
    ell = float(diagram["ell"])

    def edges(x):
        mid = 0.5 * (x[1:] + x[:-1])
        return np.concatenate([[x[0] - (mid[0] - x[0])], mid, [x[-1] + (x[-1] - mid[-1])]])

    nu_edges, G_edges = np.clip(edges(nu), 0, 1), np.clip(edges(G), 0, None)
    norm = LogNorm(0.3, 30)
    meshes = {}
    for name in ("fiber", "disk"):
        field = np.ma.masked_where(phase != name, np.clip(length / ell, norm.vmin, norm.vmax))
        meshes[name] = ax.pcolormesh(G_edges, nu_edges, field, cmap=shaded_colormap(PHASE_COLORS[name]), norm=norm)
    for name in ("bulk", "bulk_with_holes", "gas"):
        field = np.ma.masked_where(phase != name, np.ones(phase.shape))
        ax.pcolormesh(G_edges, nu_edges, field, cmap=shaded_colormap(PHASE_COLORS[name]), vmin=0, vmax=1.05)
    line_nu = continuum["line_nu"]
    for key in ("fiber_bulk", "disk_bulk", "disk_fiber", "disk_fiber_upper"):
        ax.plot(continuum[key], line_nu, "--", color="w", lw=1.6)
        ax.plot(continuum[key], line_nu, "--", color="k", lw=0.8)
    ax.set_xlim(G_edges[0], G_edges[-1])
    ax.set_ylim(0, 1)
    ax.set_xlabel(r"line tension $\Gamma$")
    ax.set_ylabel(r"Poisson ratio $\nu$")
    shown = (("bulk_with_holes", "bulk with holes"), ("disk", "disk"), ("fiber", "fibre"), ("bulk", "bulk"))
    if np.any(phase == "gas"):
        shown += (("gas", "single particles"),)
    handles = [Patch(color=PHASE_COLORS[p], label=label) for p, label in shown]
    handles.append(plt.Line2D([], [], color="k", ls="--", lw=0.8, label=r"continuum ($\ell\to\infty$)"))
    ax.legend(handles=handles, loc="lower center", bbox_to_anchor=(0.5, 1.01), ncol=3, fontsize=7, frameon=False)
    if colorbar_axes is not None:
        fig.colorbar(meshes["fiber"], cax=colorbar_axes[0], label=r"$W/\ell$")
        fig.colorbar(meshes["disk"], cax=colorbar_axes[1], label=r"$R/\ell$")
    return meshes
