"""Drawing a Monte Carlo configuration, one colour per cluster.

Every particle is a polygon at its lattice site, each cluster unwrapped across the periodic
boundary (relaxed shapes on request).
"""
from __future__ import annotations

import numpy as np

from ..topology import site_positions, tiling_facts
from .analysis import clusters, placed

__all__ = ["draw_snapshot"]


def _reference_outlines(coords, tiling):
    """Outline polygons (n, m, 2) of particles at rest without mismatch.

    Their site centres plus the kernel's corner offsets, for the outline slots
    (``plotting.OUTLINE_SLOTS``)."""
    from ..plotting import OUTLINE_SLOTS

    facts = tiling_facts(tiling)
    offsets = np.asarray(facts["slot_offsets"])[:, OUTLINE_SLOTS[tiling]]  # (sublattices, m, 2)
    sub = coords[:, 2] if coords.shape[1] == 3 else np.zeros(len(coords), int)
    return site_positions(coords, tiling)[:, None, :] + offsets[sub]


def draw_snapshot(sites, box, ax=None, particle=None, *, magnify=1.0, cmap="tab10", outline=True, tiling=None):
    """Draw particles as polygons at their lattice positions, one colour per cluster.

    Isolated particles are grey; each cluster is unwrapped (so a cluster across the periodic
    boundary looks connected) and placed with its centre inside the box, whose outline is drawn.

    Parameters
    ----------
    sites : array_like, shape (n, 2) or (n, 3), int
        Occupied sites in lattice coordinates (``BoxState.sites``).
    box : int
        Box side, in lattice cells.
    ax : matplotlib.axes.Axes or None, optional
        Where to draw (None: a new figure).
    particle : Hexagon, RandomHexagon, Triangle or None, optional
        With a particle, finite clusters are drawn in their relaxed shapes (linear solve);
        wrapped clusters stay regular.
    magnify : float, keyword only
        Factor on the displacements from the regular reference (with ``particle``).
    cmap : str or matplotlib colormap, keyword only
        Colours of the clusters.
    outline : bool, keyword only
        Draw the box's outline (dotted, beneath the particles).
    tiling : {"hexagon", "triangle"} or None, keyword only
        The tiling; defaults to the particle's, else the hexagon's.

    Returns
    -------
    matplotlib.axes.Axes
        The axes drawn on.

    Raises
    ------
    ValueError
        Bad ``sites`` or ``box`` (``clusters``), named.

    Examples
    --------
    >>> from pyfrustrate.montecarlo import draw_snapshot
    >>> ax = draw_snapshot([(0, 0), (1, 0), (3, 3)], box=6)
    >>> len(ax.collections[0].get_paths())  # one polygon per particle
    3
    """
    import matplotlib.pyplot as plt
    from ..plotting import OUTLINE_SLOTS
    from matplotlib.collections import PolyCollection

    if ax is None:
        _, ax = plt.subplots(figsize=(5, 5 * np.sqrt(3) / 2 / 1.5))
    colours = plt.get_cmap(cmap)
    polys, faces = [], []
    multi = 0
    if tiling is None:
        tiling = particle.tiling if particle is not None else "hexagon"
    for coords, rank in clusters(sites, box, tiling):
        coords = placed(coords, box)
        corners = _reference_outlines(coords, tiling)
        if particle is not None and rank == 0 and len(coords) > 1:
            from .. import relaxation as _relax
            from ..topology import cluster as _cluster

            top = _cluster(coords, tiling=tiling)
            r = _relax.relax(particle, top, method="linear")
            relaxed = _relax.particle_corners(particle, top, r.state)[:, OUTLINE_SLOTS[tiling]]
            corners = corners + magnify * (relaxed - corners)
        if len(coords) == 1:
            colour = (0.75, 0.75, 0.75, 1.0)
        else:
            colour = colours(multi % colours.N)
            multi += 1
        polys.extend(corners)
        faces.extend([colour] * len(coords))
    ax.add_collection(PolyCollection(polys, facecolors=faces, edgecolors="k", linewidths=0.2))
    if outline:
        # The box's cells: a rhombus, drawn around the sites' centres (a cell's sites lie within it).
        corner = site_positions([(0.5, 0.5)]) if tiling == "hexagon" else np.zeros((1, 2))
        rhombus = site_positions([(0, 0), (box, 0), (box, box), (0, box), (0, 0)]) - corner
        # Dotted and beneath the particles: a cropped view shows only part of the box, whose
        # edges must not read as cracks through an aggregate.
        ax.plot(rhombus[:, 0], rhombus[:, 1], color="0.55", lw=0.6, ls=":", zorder=0.5)
    allc = np.concatenate(polys) if polys else np.zeros((1, 2))
    pad = 1.0
    ax.set_xlim(min(allc[:, 0].min(), -1) - pad, max(allc[:, 0].max(), 1.5 * box) + pad)
    ax.set_ylim(min(allc[:, 1].min(), -1) - pad, max(allc[:, 1].max(), np.sqrt(3) / 2 * box) + pad)
    ax.set_aspect("equal")
    ax.set_axis_off()
    return ax
