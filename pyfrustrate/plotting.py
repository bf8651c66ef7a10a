"""Shared figure style: the paper's colour code, particle drawing, atomic PDF + PNG output."""
from __future__ import annotations

import json
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402

from . import continuum as continuum_theory  # noqa: E402
from .io import PROVENANCE_KEY, atomic_path  # noqa: E402
from .provenance import describe  # noqa: E402

# Fig. 3 colour code: black bulk with holes, red disk, blue fibre, purple bulk.
PHASE_COLORS = {"bulk_with_holes": "#1a1a1a", "disk": "#d3002d", "fiber": "#007e94", "bulk": "#7b3294",
                "single": "#9e9e9e", "gas": "#b0b0b0"}
# How a phase (the code's name) is written in legends.
PHASE_LABELS = {"bulk_with_holes": "bulk with holes", "disk": "disk", "fiber": "fibre", "bulk": "bulk",
                "gas": "single particles"}
YELLOW, RED_CORNER, BLUE_SPRING = "#e6b800", "#d3002d", "#3b78c2"
# Colour of each corner slot (even slots red, odd yellow) and of each of the nine distances of
# a random particle (random_particles.DISTANCE_PAIRS: yellow sides, red sides, hexagon sides).
CORNER_COLORS = [RED_CORNER, YELLOW] * 3
DISTANCE_COLORS = [YELLOW] * 3 + [RED_CORNER] * 3 + [BLUE_SPRING] * 3

STYLE: dict[str, Any] = {
    "font.size": 9, "axes.labelsize": 9, "axes.titlesize": 9, "legend.fontsize": 8,
    "xtick.labelsize": 8, "ytick.labelsize": 8, "figure.dpi": 150, "savefig.dpi": 200,
    "axes.spines.top": False, "axes.spines.right": False, "pdf.fonttype": 42,
}


# Corner slots that outline a particle, in order (kernel slot order): the hexagon's six corners;
# the triangle's yellow nodes (its red ones coincide with them without mismatch).
OUTLINE_SLOTS = {"hexagon": [0, 1, 2, 3, 4, 5], "triangle": [0, 1, 2]}


def figure(width_cm: float = 17.8, height_cm: float = 8.0, **kwargs):
    """A figure in the journal's column widths (8.6 cm single, 17.8 cm double)."""
    plt.rcParams.update(STYLE)  # type: ignore[arg-type]  # matplotlib types its keys as a Literal of every name
    return plt.figure(figsize=(width_cm / 2.54, height_cm / 2.54), **kwargs)


def save(fig, outputs, provenance: dict | None = None) -> None:
    """Save ``fig`` to every path in ``outputs`` (format from the suffix), atomically, stamped
    with its provenance (by default ``provenance.describe()``: package, commit, kernel build): a
    PNG text chunk, or a PDF's Subject field."""
    record = json.dumps(provenance if provenance is not None else describe(), sort_keys=True)
    for out in outputs:
        fmt = str(out).rsplit(".", 1)[-1]
        metadata = {"png": {PROVENANCE_KEY: record}, "pdf": {"Subject": f"{PROVENANCE_KEY}: {record}"}}.get(fmt)
        with atomic_path(out) as tmp:
            fig.savefig(tmp, format=fmt, bbox_inches="tight", metadata=metadata)
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


def _distance_to_segments(point, segments) -> np.ndarray:
    """Distance from ``point`` (2,) to each segment of ``segments`` (n, 2, 2); a segment of zero
    length is a point."""
    a, b = segments[:, 0], segments[:, 1]
    ab = b - a
    length2 = np.einsum("ij,ij->i", ab, ab)
    t = np.clip(np.einsum("ij,ij->i", point - a, ab) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
    return np.linalg.norm(a + t[:, None] * ab - point, axis=1)


def draw_distance_definitions(ax, corners, pairs, colors=None, fontsize: float = 7, clearance: float = 0.13,
                              node_radius: float = 0.05, linewidth: float = 1.6, markersize: float = 22) -> None:
    """The nine distances of a random particle (``pairs``: random_particles.DISTANCE_PAIRS, the
    corner slots each joins) on its six ``corners`` (6, 2), each labelled d1..d9 at the
    midpoint of its own pair, moved outwards (away from the particle's centre) to the first
    place where the label's centre is ``clearance`` (data units; about a label's half-diagonal)
    from every line and other label, and ``clearance + node_radius`` from every corner, with a
    thin grey leader back to a dot at the midpoint: in the star of the two triangles a label
    right at a midpoint would sit on the other triangle's sides."""
    c = np.asarray(corners, float)
    colors = DISTANCE_COLORS if colors is None else colors
    outline = [(c[s], c[(s + 1) % 6]) for s in range(6)]
    segments = np.array([(c[a], c[b]) for a, b in pairs] + outline)
    ax.plot(*np.vstack([c, c[:1]]).T, color=BLUE_SPRING, lw=0.6, ls=":", zorder=0)
    centre = c.mean(axis=0)
    placed: list[np.ndarray] = []
    for i, ((a, b), color) in enumerate(zip(pairs, colors)):
        ax.plot(*c[[a, b]].T, color=color, lw=linewidth, zorder=1)
        mid = 0.5 * (c[a] + c[b])
        outward = (mid - centre) / np.linalg.norm(mid - centre)
        for step in np.arange(0.0, 1.5, 0.005):
            at = mid + step * outward
            if (_distance_to_segments(at, segments).min() >= clearance
                    and np.linalg.norm(c - at, axis=1).min() >= clearance + node_radius
                    and all(np.linalg.norm(at - p) >= 2 * clearance for p in placed)):
                break
        placed.append(at)
        ax.plot(*np.array([mid, at]).T, color="0.45", lw=0.4, zorder=0.5)
        ax.plot(*mid, "o", ms=2.4, color=color, mec="k", mew=0.3, zorder=2.5)
        ax.text(*at, rf"$d_{i + 1}$", ha="center", va="center", fontsize=fontsize, color="k", zorder=4,
                bbox=dict(boxstyle="round,pad=0.1", fc="w", ec=color, lw=0.8))
    ax.scatter(*c.T, c=CORNER_COLORS, s=markersize, edgecolors="k", linewidths=0.5, zorder=3)
    ax.set_aspect("equal")


def shaded_colormap(color):
    """White-to-``color`` colormap, for sizes inside a region of a phase diagram."""
    from matplotlib.colors import LinearSegmentedColormap

    return LinearSegmentedColormap.from_list("shade", ["#ffffff", color])


# The two phases each continuum line of ``continuum.critical_line_tensions`` separates.
CONTINUUM_LINE_PHASES = {"fiber_bulk": {"fiber", "bulk"}, "disk_bulk": {"disk", "bulk"},
                         "disk_fiber": {"disk", "fiber"}, "disk_fiber_upper": {"disk", "fiber"}}
SIZE_LABELS = {"fiber": r"$W^*/\ell$", "disk": r"$R^*/\ell$"}


def continuum_boundaries(lines: dict, flank: float = 1e-6) -> dict:
    """The continuum lines of Fig. 3a (``lines``: ``line_nu`` and the Gamma of each line, as in
    the continuum phase-diagram file) kept only where they are phase boundaries, nan elsewhere.

    ``critical_line_tensions`` gives each line wherever it is defined: ``fiber_bulk = 1`` at every
    nu, though below the triple point disks win on both sides of it, and ``disk_bulk = 1`` above,
    where fibres border the bulk. A point is kept where ``continuum.phase`` just left and right of
    it gives the two phases the line is named for; its neighbours are kept too, so that each
    drawn line runs to the last grid point before it stops being a boundary (the triple point,
    where the disk-bulk line reaches Gamma = 1)."""
    nu = np.asarray(lines["line_nu"], float)
    kept = {}
    for key, pair in CONTINUUM_LINE_PHASES.items():
        G = np.asarray(lines[key], float)
        defined = np.isfinite(G)
        boundary = np.zeros(G.shape, bool)
        if defined.any():
            left = continuum_theory.phase(nu[defined], np.maximum(G[defined] - flank, 0.0))
            right = continuum_theory.phase(nu[defined], G[defined] + flank)
            boundary[defined] = [{a, b} == pair for a, b in zip(np.atleast_1d(left), np.atleast_1d(right))]
        near = boundary.copy()
        near[1:] |= boundary[:-1]
        near[:-1] |= boundary[1:]
        kept[key] = np.where(near & defined, G, np.nan)
    return kept


def continuum_triple_point(boundaries: dict, line_nu) -> tuple[float, float]:
    """(Gamma, nu) where the disk-bulk boundary ends on the fibre-bulk one: the triple point."""
    line_nu = np.asarray(line_nu, float)
    top = np.nanargmax(np.where(np.isfinite(boundaries["disk_bulk"]), line_nu, np.nan))
    return float(boundaries["disk_bulk"][top]), float(line_nu[top])


def draw_continuum_boundaries(ax, lines: dict, dashed: bool = False) -> dict:
    """The continuum phase boundaries (``continuum_boundaries``) on ``ax``: solid black, or
    dashed black on white (over the numerical diagrams). Returns the kept lines."""
    kept = continuum_boundaries(lines)
    for G in kept.values():
        if dashed:
            ax.plot(G, lines["line_nu"], "--", color="w", lw=1.6)
            ax.plot(G, lines["line_nu"], "--", color="k", lw=0.8)
        else:
            ax.plot(G, lines["line_nu"], "k-", lw=1.0)
    return kept


def size_colorbars(fig, mappables: dict, left: float, bottom: float, height: float,
                   width: float = 0.022, step: float = 0.11, labelsize: float = 8,
                   label_on_top: bool = False) -> list:
    """Colour bars of the fibre width and disk radius, side by side from ``left`` (figure
    fraction), ``step`` apart: far enough that the first bar's label (on its right, or above it
    with ``label_on_top``, which needs less room) clears the second bar's ticks."""
    bars = []
    for i, name in enumerate(("fiber", "disk")):
        cax = fig.add_axes([left + i * step, bottom, width, height])
        bar = fig.colorbar(mappables[name], cax=cax)
        if label_on_top:
            cax.set_title(SIZE_LABELS[name], fontsize=labelsize, pad=3)
        else:
            bar.set_label(SIZE_LABELS[name], fontsize=labelsize, labelpad=2)
        cax.tick_params(labelsize=labelsize - 1)
        bars.append(bar)
    return bars


def draw_ansatz_diagram(fig, ax, diagram: dict, continuum: dict):
    """Numerical phase diagram (Figs. 3b, S1): cells coloured by the winning aggregate (black bulk
    with holes, red disk, blue fibre, purple bulk), disks and fibres shaded by the winner's
    W*/ell and R*/ell, with the continuum boundaries of Fig. 3a as dashed lines (only where they
    are boundaries: ``continuum_boundaries``). Returns the fibre and disk meshes, for
    ``size_colorbars``."""
    from matplotlib.colors import LogNorm
    from matplotlib.artist import Artist
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
    draw_continuum_boundaries(ax, continuum, dashed=True)
    ax.set_xlim(G_edges[0], G_edges[-1])
    ax.set_ylim(0, 1)
    ax.set_xlabel(r"line tension $\Gamma$")
    ax.set_ylabel(r"Poisson ratio $\nu$")
    shown = ["bulk_with_holes", "disk", "fiber", "bulk"] + (["gas"] if np.any(phase == "gas") else [])
    handles: list[Artist] = [Patch(color=PHASE_COLORS[p], label=PHASE_LABELS[p]) for p in shown]
    handles.append(plt.Line2D([], [], color="k", ls="--", lw=0.8, label=r"continuum ($\ell\to\infty$)"))
    ax.legend(handles=handles, loc="lower center", bbox_to_anchor=(0.5, 1.01), ncol=3, fontsize=7, frameon=False)
    return meshes
