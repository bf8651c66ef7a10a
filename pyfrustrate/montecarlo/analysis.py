"""What a Monte Carlo configuration holds: its clusters, the kind of its largest aggregate.

Clusters are found by the kernel's search, the one the chain itself uses
(``_kernel.box_clusters``, kernel/box.hpp); the kind of the largest aggregate feeds phase
diagrams; ``BoxState`` is the final configuration every run returns.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import _kernel
from .._checks import integer
from ..topology import neighbour_sites, site_columns, site_positions, tiling_facts

__all__ = ["BoxState", "clusters", "classify_aggregate", "compact_lobes", "largest_cluster_extent", "ELONGATION_THRESHOLD",
           "OPEN_NETWORK_BONDS"]

#: Gyration anisotropy sqrt(l1 / l2) above which a finite aggregate counts as elongated.
ELONGATION_THRESHOLD = 1.6
#: Bonds per particle, as a fraction of the bulk's, below which a large aggregate counts as an
#: open network (hexagons: 1.5 of 3 in the honeycomb pattern, about 2.5 in a compact disk of 100).
OPEN_NETWORK_BONDS = 2.0 / 3.0


def box_sites(sites, box: int, tiling: str) -> np.ndarray:
    """Return the sites of a box state as an (n, columns) integer array.

    Parameters
    ----------
    sites : array_like, shape (n, columns)
        Lattice coordinates (integers, or floats holding integers).
    box : int
        Box side, in lattice cells.
    tiling : {"hexagon", "triangle"}
        The tiling (``columns``: 2 for hexagons, 3 for triangles).

    Returns
    -------
    ndarray, shape (n, columns), int64
        The sites.

    Raises
    ------
    ValueError
        ``sites`` of another shape or not integer, named (reshaping any array into columns would
        make sites of garbage).
    """
    columns = site_columns(tiling)
    a = np.asarray(sites)
    if a.size == 0:
        return np.zeros((0, columns), np.int32)
    if a.ndim != 2 or a.shape[1] != columns:
        raise ValueError(f"sites must have shape (n, {columns}) for the {tiling} tiling, got {a.shape}")
    if a.dtype.kind not in "iu" and not (a.dtype.kind == "f" and np.all(np.isfinite(a)) and np.all(a == np.round(a))):
        raise ValueError("sites must be integer lattice coordinates")
    return a.astype(np.int64)


def clusters(sites, box, tiling="hexagon") -> list[tuple[np.ndarray, int]]:
    """Connected clusters of occupied sites in the periodic ``box`` (edge neighbours of the tiling).

    The kernel's search (the one the Monte Carlo chain uses).

    Parameters
    ----------
    sites : array_like, shape (n, 2) or (n, 3), int
        Occupied sites in lattice coordinates (60-degree axes ``a1 = (1, 0)``,
        ``a2 = (1/2, sqrt(3)/2)``; triangles: a third column, the sublattice), taken modulo
        ``box``.
    box : int
        Box side, in lattice cells, in [1, 30000].
    tiling : {"hexagon", "triangle"}, optional
        The tiling.

    Returns
    -------
    list of (ndarray, int)
        ``(coords, rank)`` pairs, largest cluster first (ties in the order of their first site in
        ``sites``): ``coords`` (k, 2) or (k, 3) are unwrapped sites (a breadth-first search from
        the cluster's first site, so neighbours are one lattice step apart), ``rank`` is 0 for a
        finite cluster, 1 if it wraps around the box in one direction, 2 in two.

    Raises
    ------
    ValueError
        A site held twice (modulo the box), or bad ``sites`` or ``box``, named.

    Examples
    --------
    Two hexagons side by side and one apart, in a 6 x 6 box; a row of six wraps around it:

    >>> from pyfrustrate.montecarlo import clusters
    >>> [(len(c), rank) for c, rank in clusters([(0, 0), (1, 0), (3, 3)], box=6)]
    [(2, 0), (1, 0)]
    >>> [(len(c), rank) for c, rank in clusters([(i, 2) for i in range(6)], box=6)]
    [(6, 1)]
    """
    box = integer("box", box, 1, 30000)
    a = box_sites(sites, box, tiling)
    a[:, :2] %= box
    if len(a) == 0:
        return []
    return [(np.asarray(coords, np.int64), int(rank))
            for coords, rank in _kernel.box_clusters(tiling, box, a.astype(np.int32))]


def classify_aggregate(sites, box, tiling="hexagon", *, open_networks=True) -> tuple[str, int]:
    """Kind of the largest aggregate of a Monte Carlo state, for phase diagrams.

    A heuristic with the limits of a finite box: an aggregate narrower than the optimal fibre
    width but too short to show it (few particles) reads as a disk.

    Parameters
    ----------
    sites : array_like, shape (n, 2) or (n, 3), int
        Occupied sites in lattice coordinates (as ``clusters``).
    box : int
        Box side, in lattice cells.
    tiling : {"hexagon", "triangle"}, optional
        The tiling.
    open_networks : bool, keyword only
        Whether a finite cluster with few bonds per particle is ``'bulk_with_holes'`` (the
        phase diagrams' reading); False judges it by its shape alone, so that a fibre of one or
        two rows stays a fibre (``ground_states.structure_verdict``).

    Returns
    -------
    kind : str
        ``'bulk'`` (wraps the box both ways), ``'fiber'`` (wraps one way, or finite and
        elongated: gyration anisotropy above ``ELONGATION_THRESHOLD``), ``'fused_disks'``
        (finite, compact disks joined by necks, elongated or not: ``compact_lobes``; checked
        first),
        ``'bulk_with_holes'``
        (with ``open_networks``: fewer than ``OPEN_NETWORK_BONDS`` times the bulk's bonds per
        particle), ``'disk'`` (compact), or ``'gas'`` (largest cluster of fewer than 3 particles).
    size : int
        Particles in the largest cluster.

    Raises
    ------
    ValueError
        No particle, or bad ``sites`` or ``box``.

    Examples
    --------
    >>> from pyfrustrate.montecarlo import classify_aggregate
    >>> classify_aggregate([(i, 2) for i in range(6)], box=6)
    ('fiber', 6)
    >>> classify_aggregate([(0, 0), (3, 3)], box=6)
    ('gas', 1)
    """
    found = clusters(sites, box, tiling)
    if not found:
        raise ValueError("sites: no particle to classify")
    coords, rank = found[0]
    size = len(coords)
    if size < 3:
        return "gas", size
    if rank == 2:
        return "bulk", size
    if rank == 1:
        return "fiber", size
    if open_networks:
        members = {tuple(c) for c in coords.tolist()}
        bonds = sum(v in members for c in coords.tolist() for v in neighbour_sites(c, tiling)) / 2
        if bonds / size < OPEN_NETWORK_BONDS * tiling_facts(tiling)["bulk_bonds_per_particle"]:
            return "bulk_with_holes", size
    if len(compact_lobes(coords, tiling)) >= 2:
        return "fused_disks", size
    return ("fiber" if elongated(coords, tiling) else "disk"), size


def _interior(members: set, tiling: str) -> set:
    """The members all of whose edge neighbours are members (one erosion of the surface)."""
    return {c for c in members if all(v in members for v in neighbour_sites(c, tiling))}


def compact_lobes(coords, tiling="hexagon") -> list[set]:
    """The compact lobes of a finite cluster: the connected pieces left when its surface is
    eroded (every particle with an empty edge neighbour removed) that still hold a particle
    whose edge neighbours all lie in the piece, i.e. pieces at least three rows thick somewhere.

    A compact disk or a straight fibre of any width keeps one piece (or none, if it is at most
    two rows thick); compact disks joined by necks of one or two rows fall apart into one
    lobe each. So a cluster with two or more lobes is disks fused by necks, neither one disk nor a
    fibre, however elongated (``classify_aggregate``). A fibre of three or four rows with a notch splits into
    strips too thin to hold a lobe, and stays a fibre.

    Parameters
    ----------
    coords : array_like, shape (k, 2) or (k, 3), int
        The cluster's unwrapped sites (``clusters``; a finite cluster, rank 0).
    tiling : {"hexagon", "triangle"}, optional
        The tiling.

    Returns
    -------
    list of set of tuple
        The lobes' sites (of the eroded cluster), largest first.

    Examples
    --------
    Two hexagonal disks of radius 2 touching at one pair of particles, and one disk:

    >>> import numpy as np
    >>> from pyfrustrate import topology
    >>> from pyfrustrate.montecarlo.analysis import compact_lobes
    >>> disk = topology.hexagon_sites(2)
    >>> [len(lobe) for lobe in compact_lobes(np.vstack([disk, disk + (5, 0)]))]
    [7, 7]
    >>> [len(lobe) for lobe in compact_lobes(disk)]
    [7]
    """
    members = {tuple(c) for c in np.asarray(coords, np.int64).tolist()}
    core = _interior(members, tiling)
    lobes, seen = [], set()
    for start in core:
        if start in seen:
            continue
        piece, frontier = {start}, [start]
        while frontier:
            for v in neighbour_sites(frontier.pop(), tiling):
                if v in core and v not in piece:
                    piece.add(v)
                    frontier.append(v)
        seen |= piece
        if _interior(piece, tiling):
            lobes.append(piece)
    return sorted(lobes, key=len, reverse=True)


def elongated(coords, tiling="hexagon") -> bool:
    """Whether a finite cluster reads as a fibre: gyration anisotropy (the square root of the
    ratio of the principal variances of its site centres) above ``ELONGATION_THRESHOLD``.

    Parameters
    ----------
    coords : array_like, shape (k, 2) or (k, 3), int
        The cluster's unwrapped sites (``clusters``).
    tiling : {"hexagon", "triangle"}, optional
        The tiling.

    Returns
    -------
    bool
    """
    xy = site_positions(coords, tiling)
    eigen = np.linalg.eigvalsh(np.cov(xy.T))
    return bool(np.sqrt(eigen[1] / max(eigen[0], 1e-12)) > ELONGATION_THRESHOLD)


def placed(coords, box):
    """Unwrapped cluster sites shifted by whole boxes so that their centre lies in the box.

    Parameters
    ----------
    coords : ndarray, shape (k, 2) or (k, 3), int
        A cluster's unwrapped sites (``clusters``).
    box : int
        Box side, in lattice cells.

    Returns
    -------
    ndarray, shape (k, 2) or (k, 3), int
        The sites where ``draw_snapshot`` draws them.
    """
    coords = coords.copy()
    coords[:, :2] -= np.floor(coords[:, :2].mean(axis=0) / box).astype(int) * box
    return coords


def largest_cluster_extent(sites, box, tiling="hexagon") -> tuple[np.ndarray, np.ndarray]:
    """The window to centre a snapshot panel on: the largest cluster as ``draw_snapshot`` places it.

    Parameters
    ----------
    sites : array_like, shape (n, 2) or (n, 3), int
        Occupied sites in lattice coordinates.
    box : int
        Box side, in lattice cells.
    tiling : {"hexagon", "triangle"}, optional
        The tiling.

    Returns
    -------
    lower : ndarray, shape (2,)
        Lower-left corner of its site centres, Cartesian, in lattice spacings.
    upper : ndarray, shape (2,)
        Upper-right corner.

    Raises
    ------
    ValueError
        Bad ``sites`` or ``box`` (``clusters``), named, or no particle (``sites`` empty).
    """
    found = clusters(sites, box, tiling)
    if not found:
        raise ValueError("largest_cluster_extent: sites is empty; a snapshot needs at least one particle")
    coords, _ = found[0]
    xy = site_positions(placed(coords, box), tiling)
    return xy.min(axis=0), xy.max(axis=0)


@dataclass
class BoxState:
    """A final configuration of the periodic box, shared by ``AnnealResult`` and ``ReplicaExchangeResult``.

    Attributes
    ----------
    sites : ndarray, shape (n, 2) (or (n, 3) for triangles), int
        Occupied sites in lattice coordinates (60-degree axes; the third column the sublattice).
    box : int
        Box side, in lattice cells.
    n : int
        Number of particles.
    g : float
        Binding energy per bound pair of sides, spring units.
    energy : float
        ``-g * bonds + deformation``, spring units.
    bonds : int
        Bound pairs of sides.
    deformation : float
        Sum of the relaxed deformation energies of the clusters, spring units.
    """

    sites: np.ndarray = field(repr=False)
    box: int
    n: int
    g: float
    energy: float
    bonds: int
    deformation: float

    def clusters(self) -> list[np.ndarray]:
        """Final clusters, largest first.

        Returns
        -------
        list of ndarray
            Unwrapped sites of each cluster, shape (k, 2) (or (k, 3) for tilings with several
            sublattices).
        """
        return [c for c, _ in clusters(self.sites, self.box, getattr(self, "tiling", "hexagon"))]
