"""Shared figure style: the paper's colour code, particle drawing, atomic PDF + PNG output."""
from __future__ import annotations

import json
import warnings
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
# A Monte Carlo aggregate of disks fused by necks (montecarlo.analysis.compact_lobes) is drawn in
# the disk colour: it is the disk phase's, merged; a marker of its own tells it apart.
PHASE_COLORS["fused_disks"] = PHASE_COLORS["disk"]
# How a phase (the code's name) is written in legends.
PHASE_LABELS = {"bulk_with_holes": "bulk with holes", "disk": "disk", "fiber": "fibre", "bulk": "bulk",
                "gas": "single particles", "fused_disks": "fused disks"}
YELLOW, RED_CORNER, BLUE_SPRING = "#e6b800", "#d3002d", "#3b78c2"
# Colour of each corner slot (even slots red, odd yellow) and of each of the nine distances of
# a random particle (random_particles.DISTANCE_PAIRS: yellow sides, red sides, hexagon sides).
CORNER_COLORS = [RED_CORNER, YELLOW] * 3
DISTANCE_COLORS = [YELLOW] * 3 + [RED_CORNER] * 3 + [BLUE_SPRING] * 3

# The journal's print sizes (cm): one column, two columns, the tallest figure a page holds.
COLUMN_WIDTH_CM, PAGE_WIDTH_CM, MAX_HEIGHT_CM = 8.6, 17.8, 23.0
# Smallest type after placement (pt): every label, tick and legend; free annotations.
MIN_TEXT_PT, MIN_ANNOTATION_PT = 7.0, 6.0

# One style for every figure, drawn at its print size (no scaling afterwards): 7 pt type,
# 8 pt bold panel letters, thin lines.
STYLE: dict[str, Any] = {
    "font.size": 7, "axes.labelsize": 7, "axes.titlesize": 7, "legend.fontsize": 7,
    "xtick.labelsize": 7, "ytick.labelsize": 7, "figure.titlesize": 8,
    "figure.dpi": 150, "savefig.dpi": 300, "pdf.fonttype": 42, "ps.fonttype": 42,
    "axes.spines.top": False, "axes.spines.right": False, "axes.linewidth": 0.6,
    "axes.labelpad": 2.0, "axes.titlepad": 3.0,
    "xtick.major.width": 0.6, "ytick.major.width": 0.6, "xtick.minor.width": 0.4, "ytick.minor.width": 0.4,
    "xtick.major.size": 2.5, "ytick.major.size": 2.5, "xtick.minor.size": 1.5, "ytick.minor.size": 1.5,
    "xtick.major.pad": 2.0, "ytick.major.pad": 2.0,
    "lines.linewidth": 1.0, "lines.markersize": 3.5, "patch.linewidth": 0.6,
    "legend.frameon": False, "legend.handlelength": 1.6, "legend.borderaxespad": 0.3,
    "legend.labelspacing": 0.3, "legend.handletextpad": 0.5, "legend.columnspacing": 1.0,
    "mathtext.fontset": "dejavusans",
}
PANEL_LETTER_PT = 8.0

# One label per quantity, one unit per length (the particle lattice spacing, 1).
LENGTH_UNIT = "particle spacings"
LABELS = {
    "Gamma": r"line tension $\Gamma$",
    "nu": r"Poisson ratio $\nu$",
    "energy": r"deformation energy per particle / $e_{\rm bulk}$",
    "ell": r"boundary-layer length $\ell$",
    "W": r"$W^*/\ell$",
    "R": r"$R^*/\ell$",
}


# How the box structures of ground_states.FAMILIES (and "bulk") are written in figures.
STRUCTURE_LABELS = {"single": "one aggregate", "wrapping_fiber": "fibre around the box",
                    "aggregates": "several aggregates", "fused": "fused aggregates", "gas": "gas", "bulk": "bulk"}


def matching_prediction(run, predictions):
    """The finite-size prediction made for a Monte Carlo run's particle number and nu.

    Parameters
    ----------
    run : dict
        A Monte Carlo run's summary (``n``, ``nu``).
    predictions : iterable of dict
        Files of the montecarlo_finite_aggregates or triangle_finite_aggregates rule.

    Returns
    -------
    dict or None
        The matching prediction; None when there is none.
    """
    for f in predictions:
        if int(f["n"]) == int(run["n"]) and abs(float(f["nu"]) - float(run["nu"])) < 1e-9:
            return f
    return None


def gap_to_best_single(run, predictions):
    """A Monte Carlo run's final energy above the best single aggregate of as many particles.

    Parameters
    ----------
    run : dict
        A Monte Carlo run's summary (``n``, ``nu``, ``energy``, ``g``).
    predictions : iterable of dict
        Finite-size predictions (``matching_prediction``).

    Returns
    -------
    float or None
        The gap at the run's nu and g (``ansatz.energy_above_best_single``), in bulk particle
        energies; None when no prediction matches the run's particle number and nu.
    """
    from .ansatz import energy_above_best_single

    f = matching_prediction(run, predictions)
    return None if f is None else energy_above_best_single(run["energy"], run["g"], f)


def structure_label(structure: str) -> str:
    """A box structure in words.

    Parameters
    ----------
    structure : str
        A key of ``STRUCTURE_LABELS``, ``"aggregatesN"``: N separate aggregates, or ``"fusedN"``:
        N aggregates joined by necks, one cluster.

    Returns
    -------
    str
        The label.

    Examples
    --------
    >>> from pyfrustrate.plotting import structure_label
    >>> structure_label("wrapping_fiber"), structure_label("aggregates3"), structure_label("fused4")
    ('fibre around the box', '3 aggregates', '4 fused aggregates')
    """
    for family, words in (("aggregates", "aggregates"), ("fused", "fused aggregates")):
        if structure.startswith(family) and structure[len(family):].isdigit():
            return f"{structure[len(family):]} {words}"
    return STRUCTURE_LABELS.get(structure, structure.replace("_", " "))


def box_label(box: int) -> str:
    """A periodic box of ``box`` x ``box`` sites, written one way in every figure.

    Parameters
    ----------
    box : int
        Box side, in lattice cells.

    Returns
    -------
    str
        Mathtext label, e.g. ``60$\\times$60``.
    """
    return rf"{int(box)}$\times${int(box)}"


# Corner slots that outline a particle, in order (kernel slot order): the hexagon's six corners;
# the triangle's yellow nodes (its red ones coincide with them without mismatch).
OUTLINE_SLOTS = {"hexagon": [0, 1, 2, 3, 4, 5], "triangle": [0, 1, 2]}


def figure(width_cm: float = PAGE_WIDTH_CM, height_cm: float = 8.0, **kwargs):
    """A figure at its print size, in the figures' style (``STYLE``).

    The page is the figure (``save`` does not crop), so what is drawn here is what prints.

    Parameters
    ----------
    width_cm : float
        One column (8.6 cm, ``COLUMN_WIDTH_CM``) or two (17.8 cm, ``PAGE_WIDTH_CM``).
    height_cm : float
        Height in cm, in (0, 23].
    **kwargs
        Passed to ``matplotlib.pyplot.figure``.

    Returns
    -------
    matplotlib.figure.Figure
        The figure.

    Raises
    ------
    ValueError
        Another width, or a height out of range.

    Examples
    --------
    >>> from pyfrustrate import plotting
    >>> fig = plotting.figure(plotting.COLUMN_WIDTH_CM, 5.0)
    >>> [round(float(x) * 2.54, 2) for x in fig.get_size_inches()]
    [8.6, 5.0]
    """
    if width_cm not in (COLUMN_WIDTH_CM, PAGE_WIDTH_CM):
        raise ValueError(f"width_cm must be {COLUMN_WIDTH_CM} (one column) or {PAGE_WIDTH_CM} (two), got {width_cm}")
    if not 0 < height_cm <= MAX_HEIGHT_CM:
        raise ValueError(f"height_cm must be in (0, {MAX_HEIGHT_CM}], got {height_cm}")
    plt.rcParams.update(STYLE)  # type: ignore[arg-type]  # matplotlib types its keys as a Literal of every name
    return plt.figure(figsize=(width_cm / 2.54, height_cm / 2.54), **kwargs)


# PNG text chunk holding the figure check's findings (``check_figure``; "[]": none), so that a
# built figure can be checked without redrawing it (tests/test_figures.py).
CHECK_KEY = "figure-check"


def save(fig, outputs, provenance: dict | None = None) -> None:
    """Save ``fig`` to every path in ``outputs``, atomically, stamped with its provenance.

    At its drawn size (no cropping: the page is the print size). The findings of
    ``check_figure`` are warned about and stored in the PNG's ``CHECK_KEY`` chunk. The figure is
    closed.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    outputs : iterable of str or path-like
        Files to write, the format from the suffix (``.pdf``, ``.png``, ...).
    provenance : dict or None, optional
        The record stamped into each file (a PNG text chunk, or a PDF's Subject field); default
        ``provenance.describe()`` (package, commit, kernel build).
    """
    problems = check_figure(fig)
    for problem in problems:
        warnings.warn(f"figure check: {problem}", stacklevel=2)
    record = json.dumps(provenance if provenance is not None else describe(), sort_keys=True)
    for out in outputs:
        fmt = str(out).rsplit(".", 1)[-1]
        metadata = {"png": {PROVENANCE_KEY: record, CHECK_KEY: json.dumps(problems)},
                    "pdf": {"Subject": f"{PROVENANCE_KEY}: {record}"}}.get(fmt)
        with atomic_path(out) as tmp:
            fig.savefig(tmp, format=fmt, metadata=metadata)
    plt.close(fig)


def panel_label(ax, label: str, dx_pt: float = -6.0, dy_pt: float = 4.0, at_cm: tuple | None = None):
    """The panel letter "(a)", bold, in one place.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The panel.
    label : str
        The letter, without parentheses.
    dx_pt, dy_pt : float
        Offset in points from the axes' top-left corner (for a panel whose tick labels reach
        there); by default just above and left of it.
    at_cm : tuple of (float, float) or None
        For drawings whose equal aspect shrinks the axes: the letter's top-left corner, x and y
        in cm on the page, so that a row of drawings has its letters on one line.

    Returns
    -------
    matplotlib.text.Text
        The letter.
    """
    if at_cm is not None:
        fig = ax.figure
        width_cm, height_cm = (x * 2.54 for x in fig.get_size_inches())
        return fig.text(at_cm[0] / width_cm, at_cm[1] / height_cm, f"({label})", ha="left", va="top",
                        fontweight="bold", fontsize=PANEL_LETTER_PT)
    return ax.annotate(f"({label})", xy=(0, 1), xycoords="axes fraction", xytext=(dx_pt, dy_pt),
                       textcoords="offset points", ha="right", va="bottom", fontweight="bold",
                       fontsize=PANEL_LETTER_PT)


def draw_hexagons(ax, corners, values=None, cmap="viridis", norm=None, edgecolor="0.25", linewidth=0.3, **kwargs):
    """Draw particles as filled hexagons.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    corners : array_like, shape (n, 6, 2)
        Corner positions, Cartesian, in lattice spacings (``relaxation.particle_corners``).
    values : array_like, shape (n,), or None
        Colours the particles (e.g. ``relaxation.particle_energies``); None: uniform.
    cmap : str or matplotlib colormap
        Colormap of ``values``.
    norm : matplotlib.colors.Normalize or None
        Normalisation of ``values`` (default: their range).
    edgecolor : color
        Outline colour.
    linewidth : float
        Outline width, points.
    **kwargs
        Passed to ``matplotlib.collections.PolyCollection``.

    Returns
    -------
    matplotlib.collections.PolyCollection
        The hexagons (a mappable, for a colour bar).

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from pyfrustrate import Hexagon, relaxation, topology
    >>> from pyfrustrate.plotting import draw_hexagons
    >>> particle, aggregate = Hexagon.from_continuum(ell=2.0, nu=0.5), topology.disk(2)
    >>> result = relaxation.relax(particle, aggregate)
    >>> corners = relaxation.particle_corners(particle, aggregate, result.state)
    >>> fig, ax = plt.subplots()
    >>> hexagons = draw_hexagons(ax, corners, values=relaxation.particle_energies(particle, aggregate, result.state))
    >>> len(hexagons.get_paths()) == aggregate.n_particles
    True
    """
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
    """Particles with their three spring networks (Fig. 2).

    Yellow and red triangles, blue connecting sides, yellow and red corners.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    corners : array_like, shape (6, 2) or (n, 6, 2)
        Corner positions of one particle or of n, slots counter-clockwise from 30 degrees, odd
        slots yellow; lattice spacings.
    linewidth : float
        Spring width, points.
    markersize : float
        Corner marker area, points squared.
    """
    c = np.asarray(corners, float).reshape(-1, 6, 2)
    sides = [(p[s], p[(s + 1) % 6]) for p in c for s in range(6)]
    yellow = [(p[s], p[(s + 2) % 6]) for p in c for s in (1, 3, 5)]
    red = [(p[s], p[(s + 2) % 6]) for p in c for s in (0, 2, 4)]
    ax.add_collection(LineCollection(sides, colors=BLUE_SPRING, linewidths=linewidth, zorder=1))
    ax.add_collection(LineCollection(yellow, colors=YELLOW, linewidths=linewidth, zorder=2))
    ax.add_collection(LineCollection(red, colors=RED_CORNER, linewidths=linewidth, zorder=2))
    ax.scatter(*c[:, 1::2].reshape(-1, 2).T, s=markersize, color=YELLOW, edgecolor="k", linewidth=0.3, zorder=3)
    ax.scatter(*c[:, 0::2].reshape(-1, 2).T, s=markersize, color=RED_CORNER, edgecolor="k", linewidth=0.3, zorder=3)
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
    """The nine distances of a random particle on its six corners, labelled d1..d9.

    Each label starts at the midpoint of its own pair and moves outwards (away from the
    particle's centre) to the first place clear of every line, label and corner, with a thin grey
    leader back to a dot at the midpoint: in the star of the two triangles a label right at a
    midpoint would sit on the other triangle's sides.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    corners : array_like, shape (6, 2)
        The particle's corners, lattice spacings.
    pairs : sequence of (int, int)
        The corner slots each distance joins (``random_particles.DISTANCE_PAIRS``).
    colors : sequence of color or None
        One per distance (default ``DISTANCE_COLORS``).
    fontsize : float
        Label size, points.
    clearance : float
        Least distance from a label's centre to every line and other label, data units (about
        a label's half-diagonal).
    node_radius : float
        Added to ``clearance`` near corners, data units.
    linewidth : float
        Distance line width, points.
    markersize : float
        Corner marker area, points squared.
    """
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


def draw_size_points(ax, Gamma, sizes, keep, color, **kwargs):
    """Each random particle's best size at each line tension, as faint points (Figs. 5d, S2).

    The points of a Gamma column are spread over a third of the spacing to the next (drawing
    only, the same spread every time), so that the many particles of one column show as a band.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    Gamma : array_like, shape (m,)
        The line tensions of the columns.
    sizes : ndarray, shape (p, m)
        One row per particle.
    keep : ndarray of bool, shape (p, m)
        The points to draw.
    color : color
        Their colour.
    **kwargs
        Passed to ``ax.plot``.
    """
    Gamma = np.asarray(Gamma, float)
    x = np.broadcast_to(Gamma, sizes.shape)
    spread = np.random.default_rng(0).uniform(-0.3, 0.3, sizes.shape) * np.gradient(Gamma)[None, :]
    kwargs = dict(dict(ms=1.2, alpha=0.25, rasterized=True), **kwargs)
    ax.plot((x + spread)[keep], sizes[keep], ".", color=color, **kwargs)


def shaded_colormap(color, tint: float = 0.3):
    """A ramp from a light tint of ``color`` to ``color``, for sizes inside a phase's region.

    Parameters
    ----------
    color : color
        The phase's colour.
    tint : float
        Weight of the colour over white at the light end, so the smallest size still reads as
        its phase and not as the background.

    Returns
    -------
    matplotlib.colors.LinearSegmentedColormap
        The ramp.
    """
    from matplotlib.colors import LinearSegmentedColormap, to_rgb

    light = tuple(1 - tint * (1 - c) for c in to_rgb(color))
    return LinearSegmentedColormap.from_list("shade", [light, color])


# Monte Carlo snapshots: the largest cluster first, then the others, in colours that no phase
# uses (no red, teal, purple or black), isolated particles light grey (montecarlo.draw_snapshot).
CLUSTER_COLORS = ["#e08214", "#b8a000", "#8c6d31", "#7f9f3a", "#fdb863", "#66a61e", "#d9b365", "#bf812d"]


def cluster_colormap():
    """``CLUSTER_COLORS`` as a colormap, for ``montecarlo.draw_snapshot(cmap=...)``.

    Returns
    -------
    matplotlib.colors.ListedColormap
        The colormap.
    """
    from matplotlib.colors import ListedColormap

    return ListedColormap(CLUSTER_COLORS, name="clusters")


def draw_snapshot(sites, box, ax, **kwargs):
    """A Monte Carlo snapshot in the figures' colours, without the box's outline.

    The box's edges would cut through aggregates drawn across the periodic boundary.

    Parameters
    ----------
    sites : array_like, shape (n, 2) or (n, 3), int
        Occupied sites in lattice coordinates (``BoxState.sites``).
    box : int
        Box side, in lattice cells.
    ax : matplotlib.axes.Axes
        Where to draw.
    **kwargs
        Passed to ``montecarlo.draw_snapshot`` (``particle``, ``magnify``, ``tiling``, ...).

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.
    """
    from .montecarlo import draw_snapshot as _draw

    kwargs.setdefault("outline", False)
    kwargs.setdefault("cmap", cluster_colormap())
    return _draw(sites, box, ax=ax, **kwargs)


# The two phases each continuum line of ``continuum.critical_line_tensions`` separates.
CONTINUUM_LINE_PHASES = {"fiber_bulk": {"fiber", "bulk"}, "disk_bulk": {"disk", "bulk"},
                         "disk_fiber": {"disk", "fiber"}, "disk_fiber_upper": {"disk", "fiber"}}
SIZE_LABELS = {"fiber": LABELS["W"], "disk": LABELS["R"]}


def continuum_boundaries(lines: dict, flank: float = 1e-6) -> dict:
    """The continuum lines of Fig. 3a kept only where they are phase boundaries, nan elsewhere.

    ``critical_line_tensions`` gives each line wherever it is defined: ``fiber_bulk = 1`` at every
    nu, though below the triple point disks win on both sides of it, and ``disk_bulk = 1`` above,
    where fibres border the bulk. A point is kept where ``continuum.phase`` just left and right of
    it gives the two phases the line is named for; its neighbours are kept too, so that each
    drawn line runs to the last grid point before it stops being a boundary (the triple point,
    where the disk-bulk line reaches Gamma = 1).

    Parameters
    ----------
    lines : dict
        ``line_nu`` (m,) and the Gamma (m,) of each line of ``CONTINUUM_LINE_PHASES``, as in the
        continuum phase-diagram file (``continuum.critical_line_tensions``).
    flank : float
        How far left and right of a line (in Gamma) its phases are read.

    Returns
    -------
    dict of ndarray, each shape (m,)
        Each line's Gamma where it is a boundary (and at its neighbours), nan elsewhere.
    """
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
    """(Gamma, nu) where the disk-bulk boundary ends on the fibre-bulk one: the triple point.

    Parameters
    ----------
    boundaries : dict
        The kept lines (``continuum_boundaries``).
    line_nu : array_like, shape (m,)
        Their nu grid.

    Returns
    -------
    tuple of (float, float)
        Gamma and nu of the triple point.
    """
    line_nu = np.asarray(line_nu, float)
    top = np.nanargmax(np.where(np.isfinite(boundaries["disk_bulk"]), line_nu, np.nan))
    return float(boundaries["disk_bulk"][top]), float(line_nu[top])


def draw_continuum_boundaries(ax, lines: dict, dashed: bool = False) -> dict:
    """The continuum phase boundaries (``continuum_boundaries``) on ``ax``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw (Gamma on x, nu on y).
    lines : dict
        As ``continuum_boundaries`` takes.
    dashed : bool
        Dashed black on white (over the numerical diagrams) instead of solid black.

    Returns
    -------
    dict of ndarray
        The kept lines.
    """
    kept = continuum_boundaries(lines)
    for G in kept.values():
        if dashed:
            ax.plot(G, lines["line_nu"], "--", color="w", lw=1.6)
            ax.plot(G, lines["line_nu"], "--", color="k", lw=0.8)
        else:
            ax.plot(G, lines["line_nu"], "k-", lw=1.0)
    return kept


def size_norm():
    """One scale for W*/ell and R*/ell in every phase diagram.

    R*/ell stays below 8 (Fig. 4b); W*/ell diverges at the fibre-bulk boundary, so the bars
    extend beyond 10.

    Returns
    -------
    matplotlib.colors.LogNorm
        From 0.3 to 10.
    """
    from matplotlib.colors import LogNorm

    return LogNorm(0.3, 10.0)


SIZE_TICKS = (0.3, 1, 3, 10)


def size_colorbars(fig, mappables: dict, rect_cm: tuple, gap_cm: float = 1.25, width_cm: float = 0.25) -> list:
    """Colour bars of the fibre width W*/ell and the disk radius R*/ell, side by side.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    mappables : dict
        ``"fiber"`` and ``"disk"`` mappables (``draw_continuum_diagram``, ``shade_phases``).
    rect_cm : tuple of (float, float, float)
        (left, bottom, height) of the first bar, cm on the page.
    gap_cm : float
        From one bar's left edge to the next's, cm (room for the first bar's tick labels).
    width_cm : float
        Bar width, cm.

    Returns
    -------
    list of matplotlib.colorbar.Colorbar
        The two bars, each labelled once, above it.
    """
    page_w, page_h = (x * 2.54 for x in fig.get_size_inches())
    left, bottom, height = rect_cm
    bars = []
    for i, name in enumerate(("fiber", "disk")):
        cax = fig.add_axes([(left + i * gap_cm) / page_w, bottom / page_h, width_cm / page_w, height / page_h])
        bar = fig.colorbar(mappables[name], cax=cax, extend="both")
        bar.set_ticks(SIZE_TICKS, labels=[f"{t:g}" for t in SIZE_TICKS])
        bar.minorticks_off()
        cax.set_title(SIZE_LABELS[name], pad=4)
        bars.append(bar)
    return bars


SIZE_CONTOURS = (0.5, 1, 2, 4)


#: Where the size contours of Fig. 3a are labelled: a height nu at which each phase's contours are
#: spread out (fibre contours are vertical; disk ones fan out from nu = 1), clear of the
#: boundaries and of the phase names.
CONTOUR_LABEL_NU = {"fiber": 0.92, "disk": 0.3}


def contour_label_places(contours, nu: float, min_span: float = 0.1) -> list:
    """One point on each level of ``contours`` for ``clabel(manual=...)``.

    Parameters
    ----------
    contours : matplotlib.contour.QuadContourSet
        The contours (Gamma on x, nu on y).
    nu : float
        The height to label at: the vertex nearest to it (a level that does not reach it: its
        middle vertex).
    min_span : float
        Levels spanning less than this in nu (squeezed into a corner, where a label would cover
        the boundary) stay unlabelled: the colour bar reads them.

    Returns
    -------
    list of tuple of (float, float)
        The label positions.
    """
    places = []
    for segments in contours.allsegs:
        if not any(len(v) for v in segments):
            continue
        vertices = np.concatenate([v for v in segments if len(v)])
        if np.ptp(vertices[:, 1]) < min_span:
            continue
        nearest = int(np.argmin(np.abs(vertices[:, 1] - nu)))
        places.append(tuple(vertices[nearest] if abs(vertices[nearest, 1] - nu) < 0.05 else
                            vertices[len(vertices) // 2]))
    return places


def draw_continuum_diagram(ax, d: dict) -> dict:
    """The continuum phase diagram (Fig. 3a).

    Disk, fibre and bulk regions shaded by W*/ell and R*/ell (``size_norm``), contours at
    ``SIZE_CONTOURS`` (labelled where they are apart), the boundaries
    (``draw_continuum_boundaries``) and the triple point.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    d : dict
        The continuum phase-diagram file: ``nu`` (a,), ``Gamma`` (b,), ``phase``, ``width`` and
        ``radius`` (a, b; lengths in units of ell), and the lines of ``continuum_boundaries``.

    Returns
    -------
    dict
        The fibre and disk images, for ``size_colorbars``.
    """
    nu, G, phase = d["nu"], d["Gamma"], d["phase"]
    extent = (G[0], G[-1], nu[0], nu[-1])
    norm = size_norm()
    images = {}
    for name, size in (("fiber", d["width"]), ("disk", d["radius"])):
        field = np.where(phase == name, np.clip(size, norm.vmin, None), np.nan)
        images[name] = ax.imshow(field, origin="lower", extent=extent, aspect="auto", norm=norm,
                                 cmap=shaded_colormap(PHASE_COLORS[name]), interpolation="nearest")
    bulk = np.where(phase == "bulk", 1.0, np.nan)
    ax.imshow(bulk, origin="lower", extent=extent, aspect="auto", cmap=shaded_colormap(PHASE_COLORS["bulk"]),
              vmin=0, vmax=1, interpolation="nearest")
    for name, size, color in (("fiber", d["width"], "#003f4a"), ("disk", d["radius"], "#6b0016")):
        field = np.where(phase == name, size, np.nan)
        contours = ax.contour(G, nu, field, levels=SIZE_CONTOURS, colors=color, linewidths=0.5)
        ax.clabel(contours, fontsize=MIN_ANNOTATION_PT, fmt="%g", inline_spacing=2,
                  manual=contour_label_places(contours, CONTOUR_LABEL_NU[name]))
    boundaries = draw_continuum_boundaries(ax, d)
    triple = continuum_triple_point(boundaries, d["line_nu"])
    ax.plot(*triple, "o", ms=4, mfc="w", mec="k", zorder=5)
    ax.set_xlim(G[0], G[-1])
    ax.set_ylim(0, 1)
    ax.set_xlabel(LABELS["Gamma"])
    ax.set_ylabel(LABELS["nu"])
    ax.spines[["top", "right"]].set_visible(True)
    return images


def phase_legend(ax, phases, dashed_continuum: bool = False, **kwargs):
    """The legend of the phase colours (and of the dashed continuum lines), above ``ax``.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The diagram.
    phases : iterable of str
        Phases to list (keys of ``PHASE_COLORS``).
    dashed_continuum : bool
        Also list the dashed continuum lines.
    **kwargs
        Passed to ``ax.legend``, overriding the placement above the axes.

    Returns
    -------
    matplotlib.legend.Legend
        The legend.
    """
    from matplotlib.artist import Artist
    from matplotlib.patches import Patch

    handles: list[Artist] = [Patch(color=PHASE_COLORS[p], label=PHASE_LABELS[p]) for p in phases]
    if dashed_continuum:
        handles.append(plt.Line2D([], [], color="k", ls="--", lw=0.8, label=r"continuum ($\ell\to\infty$)"))
    kwargs = dict(dict(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=3, frameon=False), **kwargs)
    return ax.legend(handles=handles, **kwargs)


def shade_phases(ax, x_edges, y_edges, phase, length_over_ell, **kwargs) -> dict:
    """Cells of a diagram coloured by their phase, fibres and disks shaded by their size.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    x_edges : array_like, shape (b + 1,)
        Cell edges along x.
    y_edges : array_like, shape (a + 1,)
        Cell edges along y.
    phase : ndarray, shape (a, b), str
        Phase names of the cells.
    length_over_ell : ndarray, shape (a, b)
        W*/ell or R*/ell, shaded on ``size_norm``'s scale; the other phases are flat.
    **kwargs
        Passed to ``ax.pcolormesh``.

    Returns
    -------
    dict
        The fibre and disk meshes, for ``size_colorbars``.
    """
    norm = size_norm()
    meshes = {}
    for name in ("fiber", "disk"):
        field = np.ma.masked_where(phase != name, np.clip(length_over_ell, norm.vmin, None))
        meshes[name] = ax.pcolormesh(x_edges, y_edges, field, cmap=shaded_colormap(PHASE_COLORS[name]), norm=norm,
                                     **kwargs)
    for name in ("bulk", "bulk_with_holes", "gas"):
        field = np.ma.masked_where(phase != name, np.ones(phase.shape))
        ax.pcolormesh(x_edges, y_edges, field, cmap=shaded_colormap(PHASE_COLORS[name]), vmin=0, vmax=1, **kwargs)
    return meshes


def draw_ansatz_diagram(ax, diagram: dict, continuum: dict):
    """Numerical phase diagram (Figs. 3b, S1).

    Cells coloured by the winning aggregate (black bulk with holes, red disk, blue fibre, purple
    bulk), disks and fibres shaded by the winner's W*/ell and R*/ell (``size_norm``), with the
    continuum boundaries of Fig. 3a as dashed lines (only where they are boundaries:
    ``continuum_boundaries``).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    diagram : dict
        The catalogue's diagram: ``nu`` (a,), ``Gamma`` (b,), ``phase`` and ``length`` (a, b;
        W* or R* in lattice spacings) and ``ell``.
    continuum : dict
        The continuum phase-diagram file (its lines, ``continuum_boundaries``).

    Returns
    -------
    meshes : dict
        The fibre and disk meshes, for ``size_colorbars``.
    shown : list of str
        The phases drawn, for ``phase_legend``.
    """
    nu, G, phase, length = diagram["nu"], diagram["Gamma"], diagram["phase"], diagram["length"]
    ell = float(diagram["ell"])

    def edges(x):
        mid = 0.5 * (x[1:] + x[:-1])
        return np.concatenate([[x[0] - (mid[0] - x[0])], mid, [x[-1] + (x[-1] - mid[-1])]])

    nu_edges, G_edges = np.clip(edges(nu), 0, 1), np.clip(edges(G), 0, None)
    meshes = shade_phases(ax, G_edges, nu_edges, phase, length / ell)
    draw_continuum_boundaries(ax, continuum, dashed=True)
    ax.set_xlim(G_edges[0], G_edges[-1])
    ax.set_ylim(0, 1)
    ax.set_xlabel(LABELS["Gamma"])
    ax.set_ylabel(LABELS["nu"])
    shown = [p for p in ("bulk_with_holes", "disk", "fiber", "bulk", "gas") if np.any(phase == p)]
    return meshes, shown



def _drawn_texts(fig):
    """Every text the figure prints, with its kind: "text" (labels, ticks, titles, legends:
    at least ``MIN_TEXT_PT``) or "annotation" (free text placed in or beside an axes: at least
    ``MIN_ANNOTATION_PT``). Tick labels only of the ticks drawn (inside the view limits)."""
    from matplotlib.text import Text

    texts = []
    for ax in fig.axes:
        if not ax.get_visible():
            continue
        for axis in (ax.xaxis, ax.yaxis):
            if not (ax.axison and axis.get_visible()):  # ax.axis("off") hides the axes' axis artists
                continue
            for tick in axis._update_ticks():  # the ticks matplotlib draws (private, stable since 3.1)
                texts += [(label, "text") for label in (tick.label1, tick.label2) if label.get_visible()]
            texts.append((axis.label, "text"))
            texts.append((axis.get_offset_text(), "text"))
        texts += [(t, "text") for t in (ax.title, ax._left_title, ax._right_title)]
        legend = ax.get_legend()
        if legend is not None and legend.get_visible():
            texts += [(t, "text") for t in legend.get_texts()]
            texts.append((legend.get_title(), "text"))
        texts += [(t, "annotation") for t in ax.texts]
    for legend in fig.legends:
        texts += [(t, "text") for t in legend.get_texts()]
    texts += [(t, "annotation") for t in fig.texts]
    shown = []
    for t, kind in texts:
        if not (isinstance(t, Text) and t.get_visible() and t.get_text().strip()):
            continue
        if t.get_fontweight() == "bold" and t.get_text().startswith("("):
            kind = "text"  # panel letters
        shown.append((t, kind))
    return shown


# The gid of a text drawn over particles on purpose (a number labelling a line across a drawn
# bulk); any other text over drawn particles hides data (check_figure).
OVER_PARTICLES = "over-particles"


def _particle_centres(ax) -> np.ndarray:
    """Page positions (pixels) of the particles drawn in ``ax`` and visible in its view: the
    polygons of its PolyCollections with at most six corners (hexagons, triangles; filled areas
    such as ``fill_between`` have more)."""
    view = ax.get_window_extent()
    found: list[np.ndarray] = []
    for collection in ax.collections:
        if not (isinstance(collection, PolyCollection) and collection.get_visible()):
            continue
        transform = collection.get_transform()
        for path in collection.get_paths():
            corners = np.asarray(path.vertices, float)
            if len(corners) > 1 and np.allclose(corners[0], corners[-1]):
                corners = corners[:-1]  # a closed path repeats its first corner
            if 3 <= len(corners) <= 6:
                found.append(np.asarray(transform.transform(corners)).mean(axis=0))
    if not found:
        return np.empty((0, 2))
    centres = np.asarray(found)
    inside = ((centres[:, 0] >= view.x0) & (centres[:, 0] <= view.x1)
              & (centres[:, 1] >= view.y0) & (centres[:, 1] <= view.y1))
    return centres[inside]


def check_figure(fig, overlap_px: float = 0.0) -> list[str]:
    """What a machine can check of a figure drawn at print size.

    The page is at most 17.8 cm wide (one column 8.6 cm, two 17.8 cm) and 23 cm tall; every
    text is at least 7 pt (free annotations 6 pt); no two texts overlap and none leaves the
    page; no text covers drawn particles (the centre of a hexagon or triangle of a snapshot or
    an aggregate), unless it says so with the gid ``OVER_PARTICLES``; no visible axes is empty.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure (drawn here, as saved).
    overlap_px : float
        Overlap tolerated, pixels each way.

    Returns
    -------
    list of str
        The problems found (empty: none).

    Examples
    --------
    >>> from pyfrustrate import plotting
    >>> fig = plotting.figure(plotting.COLUMN_WIDTH_CM, 4.0)
    >>> ax = fig.add_subplot()
    >>> plotting.check_figure(fig)
    ['an empty axes at (...)']
    >>> _ = ax.plot([0, 1], [0, 1])
    >>> plotting.check_figure(fig)
    []
    """
    problems = []
    width_cm, height_cm = (x * 2.54 for x in fig.get_size_inches())
    if width_cm > PAGE_WIDTH_CM + 0.01:
        problems.append(f"page {width_cm:.1f} cm wide, wider than {PAGE_WIDTH_CM} cm")
    if height_cm > MAX_HEIGHT_CM + 0.01:
        problems.append(f"page {height_cm:.1f} cm tall, taller than {MAX_HEIGHT_CM} cm")
    renderer = fig.canvas.get_renderer()
    fig.draw(renderer)  # the layout as saved (constrained layout, label placement)
    page = fig.bbox
    boxes = []
    for t, kind in _drawn_texts(fig):
        least = MIN_TEXT_PT if kind == "text" else MIN_ANNOTATION_PT
        if t.get_fontsize() < least - 1e-6:
            problems.append(f"{kind} {t.get_text()!r} at {t.get_fontsize():g} pt, under {least:g} pt")
        box = t.get_window_extent(renderer)
        if box.width <= 0 or box.height <= 0:
            continue
        if (box.x0 < page.x0 - overlap_px or box.y0 < page.y0 - overlap_px
                or box.x1 > page.x1 + overlap_px or box.y1 > page.y1 + overlap_px):
            problems.append(f"text {t.get_text()!r} leaves the page")
        boxes.append((t, box))
    for i, (a, box_a) in enumerate(boxes):
        for b, box_b in boxes[i + 1:]:
            dx = min(box_a.x1, box_b.x1) - max(box_a.x0, box_b.x0)
            dy = min(box_a.y1, box_b.y1) - max(box_a.y0, box_b.y0)
            if dx > overlap_px and dy > overlap_px:
                problems.append(f"texts {a.get_text()!r} and {b.get_text()!r} overlap")
    per_axes = [_particle_centres(ax) for ax in fig.axes if ax.get_visible()]
    particles = np.concatenate(per_axes) if per_axes else np.empty((0, 2))
    for t, box in boxes:
        if t.get_gid() == OVER_PARTICLES or not len(particles):
            continue
        covered = ((particles[:, 0] > box.x0) & (particles[:, 0] < box.x1)
                   & (particles[:, 1] > box.y0) & (particles[:, 1] < box.y1))
        if covered.any():
            problems.append(f"text {t.get_text()!r} covers {int(covered.sum())} drawn particles")
    for ax in fig.axes:
        if ax.get_visible() and not (ax.has_data() or ax.images or ax.texts or ax.get_legend()):
            problems.append(f"an empty axes at {tuple(round(v, 2) for v in ax.get_position().bounds)}")
    return problems
