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
                "single": "#9e9e9e"}
YELLOW, RED_CORNER, BLUE_SPRING = "#e6b800", "#d3002d", "#3b78c2"

STYLE = {
    "font.size": 9, "axes.labelsize": 9, "axes.titlesize": 9, "legend.fontsize": 8,
    "xtick.labelsize": 8, "ytick.labelsize": 8, "figure.dpi": 150, "savefig.dpi": 200,
    "axes.spines.top": False, "axes.spines.right": False, "pdf.fonttype": 42,
}


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
