"""Aggregate topologies on the triangular particle lattice (main text, "Two-dimensional particle
model"): which sites are occupied, and which periodic cell stands for an infinite scene.

Sites ``(i, j)`` sit at ``i a1 + j a2`` with ``a1 = (1, 0)``, ``a2 = (1/2, sqrt(3)/2)``
(lattice spacing 1, area ``sqrt(3)/2`` per particle). Model only what the scene requires: an
infinite fibre is one period of the strip, an infinite bulk one cell of the plane.

Fibre cuts (Fig. 4a has three kinds of fibres; the paper does not say which the third is:
this is our choice):

========  ====================  ====================================================
``cut``   axis (lattice)        edges
========  ====================  ====================================================
0         ``a1`` (0 degrees)    flat rows; yellow tips on one edge, red on the other:
                                left-right asymmetric, the fibre curves when free
1         ``-a1 + 2 a2`` (90)   zig-zag columns, mirror-symmetric: stays straight
2         ``2 a1 + a2`` (19.1)  stepped (kinked) edges, chiral: a cut between the two
========  ====================  ====================================================

``width`` counts the lattice lines parallel to the axis, i.e. the particles per period; the
continuum width is ``W = width * sqrt(3)/2 / |axis|`` (area per unit length).
The hexagonal aggregate ``disk(R)`` has ``1 + 3 R (R + 1)`` particles; its continuum radius is
that of the disk of equal area, ``sqrt(N sqrt(3) / (2 pi))``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from math import gcd

import numpy as np

from . import _kernel

SQRT3 = np.sqrt(3.0)
AREA_PER_PARTICLE = SQRT3 / 2
FIBER_AXES = {0: (1, 0), 1: (-1, 2), 2: (2, 1)}
NEIGHBOURS = np.array([(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)])
_PERIODICITY = {"none": 0, "fiber": 1, "bulk": 2}


def site_positions(sites) -> np.ndarray:
    """Cartesian positions of lattice sites, shape (n, 2)."""
    s = np.asarray(sites, dtype=float).reshape(-1, 2)
    return np.column_stack([s[:, 0] + 0.5 * s[:, 1], 0.5 * SQRT3 * s[:, 1]])


@dataclass(frozen=True)
class Topology:
    """An aggregate topology and its corner graph (built by the kernel).

    Attributes
    ----------
    kind : str
        ``'cluster'``, ``'disk'``, ``'fiber'``, ``'bulk'`` or ``'bulk_with_holes'``.
    sites : ndarray, shape (n_particles, 2)
        Occupied sites (one representative per particle of the cell).
    periodicity : str
        ``'none'``, ``'fiber'`` (one period vector) or ``'bulk'`` (two).
    periods : ndarray, shape (2, 2)
        Lattice period vectors (rows; unused rows are zero).
    curved : bool
        Fibre images are rotated by a free angle, so the fibre may bend.
    size : float
        Continuum size: ``W`` for a fibre, ``R`` for a disk (lattice units), ``inf`` for bulks,
        ``nan`` for clusters.
    label : str
        Short human-readable name.
    """

    kind: str
    sites: np.ndarray
    periodicity: str = "none"
    periods: np.ndarray = field(default_factory=lambda: np.zeros((2, 2), int))
    curved: bool = False
    size: float = float("nan")
    label: str = ""
    kernel: object = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        sites = np.asarray(self.sites)
        if sites.size == 0:
            raise ValueError("sites: the topology is empty")
        if sites.ndim != 2 or sites.shape[1] != 2:
            raise ValueError(f"sites must have shape (n, 2), got {sites.shape}")
        if not np.all(np.isfinite(sites)) or not np.all(np.equal(np.mod(sites, 1), 0)):
            raise ValueError("sites must be integer lattice coordinates (i, j): a site is off the lattice")
        sites = sites.astype(np.int64)
        if np.abs(sites).max() > 10**6:
            raise ValueError("sites: coordinates beyond 1e6 are not supported")
        object.__setattr__(self, "sites", sites.astype(np.int32))
        object.__setattr__(self, "periods", np.asarray(self.periods, dtype=np.int32).reshape(2, 2))
        kernel = _kernel.Topology(self.sites, _PERIODICITY[self.periodicity], self.periods.tolist(), bool(self.curved))
        object.__setattr__(self, "kernel", kernel)

    @property
    def n_particles(self) -> int:
        return self.kernel.n_particles

    @property
    def n_bonds(self) -> int:
        """Bound pairs of sides (per cell when periodic)."""
        return self.kernel.n_bonds

    @property
    def n_corners(self) -> int:
        return self.kernel.n_corners

    def reference_state(self) -> np.ndarray:
        """Bulk-reference degrees of freedom: corners ``(x0, y0, x1, ...)`` then period parameters."""
        return np.asarray(self.kernel.reference_state())


def cluster(sites, label: str = "cluster") -> Topology:
    """A finite aggregate: any set of distinct sites, shape (n, 2)."""
    sites = np.asarray(sites)
    if sites.size == 0:
        raise ValueError("sites: the topology is empty")
    if sites.ndim != 2 or sites.shape[1] != 2:
        raise ValueError(f"sites must have shape (n, 2) (lattice coordinates i, j), got {sites.shape}")
    return Topology("cluster", sites, label=label)


def hexagon_sites(R: int) -> np.ndarray:
    """Sites within hexagonal distance ``R`` of the origin: ``1 + 3 R (R + 1)`` of them."""
    r = np.arange(-R, R + 1)
    i, j = np.meshgrid(r, r, indexing="ij")
    keep = np.abs(i + j) <= R
    return np.column_stack([i[keep], j[keep]])


def disk(R: int) -> Topology:
    """Hexagonal aggregate of 'radius' ``R`` (``R = 0`` is a single particle)."""
    if int(R) != R or R < 0:
        raise ValueError(f"R must be a non-negative integer, got {R!r}")
    sites = hexagon_sites(int(R))
    return Topology("disk", sites, size=float(np.sqrt(len(sites) * AREA_PER_PARTICLE / np.pi)), label=f"disk R={R}")


def stadium_sites(n: int, segment: float = 0.0) -> np.ndarray:
    """The ``n`` sites nearest to a segment of length ``segment`` centred on the origin along
    ``a1``: a near-circular aggregate for ``segment = 0``, a rounded strip (a finite cut-0 fibre)
    of width about ``n sqrt(3) / (2 segment)`` for long segments. Ties in distance are broken
    by the distance to the origin, then by the angle, so the shape is unique and deterministic.

    Finite-size predictions use this one-parameter family of single aggregates of exactly ``n``
    particles (``ansatz.finite_aggregates``)."""
    if isinstance(n, bool) or int(n) != n or n < 1:
        raise ValueError(f"n must be a positive integer, got {n!r}")
    segment = float(segment)
    if not np.isfinite(segment) or segment < 0:
        raise ValueError(f"segment must be non-negative and finite, got {segment!r}")
    n = int(n)
    # Enough rows and columns to hold n sites around the segment.
    half = int(np.ceil(segment / 2 + np.sqrt(n))) + 2
    r = np.arange(-2 * half, 2 * half + 1)
    i, j = np.meshgrid(r, r, indexing="ij")
    sites = np.column_stack([i.ravel(), j.ravel()])
    xy = site_positions(sites)
    along = np.clip(xy[:, 0], -segment / 2, segment / 2)
    distance = np.round(np.hypot(xy[:, 0] - along, xy[:, 1]), 9)
    order = np.lexsort((np.arctan2(xy[:, 1], xy[:, 0]), np.round(np.hypot(*xy.T), 9), distance))
    return sites[order[:n]]


def gyration_dimensions(sites) -> tuple[float, float]:
    """Width and length of an aggregate from its gyration tensor: ``sqrt(12 lambda)`` for its two
    eigenvalues, which are exactly the sides of a uniform rectangle (a compact disk of radius
    ``R`` gives ``sqrt(3) R`` both ways). Orientation-free, so it measures Monte Carlo
    aggregates and pre-made ones alike."""
    xy = site_positions(sites)
    if len(xy) < 2:
        return 0.0, 0.0
    xy = xy - xy.mean(axis=0)
    eigen = np.clip(np.linalg.eigvalsh(xy.T @ xy / len(xy)), 0.0, None)
    return float(np.sqrt(12 * eigen[0])), float(np.sqrt(12 * eigen[1]))


def _line_representative(axis) -> np.ndarray:
    """A site s with cross(axis, s) = 1 (extended Euclid), so c * s lies on the c-th line."""
    p, q = axis
    if gcd(p, q) != 1:
        raise ValueError(f"fibre axis {axis} is not a primitive lattice vector")
    # Solve p v - q u = 1.
    for u in range(-abs(p) - abs(q) - 1, abs(p) + abs(q) + 2):
        for v in range(-abs(p) - abs(q) - 1, abs(p) + abs(q) + 2):
            if p * v - q * u == 1:
                return np.array([u, v])
    raise AssertionError("unreachable for a primitive axis")


def _strip_is_connected(sites: np.ndarray, axis) -> bool:
    """Whether the infinite strip generated by repeating ``sites`` along ``axis`` is connected:
    every site of the cell reaches its own next image through bonds."""
    axis = np.asarray(axis)
    copies = 4  # a band of consecutive lattice lines connects within neighbouring copies
    points = {tuple(s + m * axis): (i, m) for m in range(-copies, copies + 1) for i, s in enumerate(sites)}
    seen, frontier = {tuple(sites[0])}, [tuple(sites[0])]
    while frontier:
        here = np.array(frontier.pop())
        for d in NEIGHBOURS:
            there = tuple(here + d)
            if there in points and there not in seen:
                seen.add(there)
                frontier.append(there)
    return all(tuple(s) in seen and tuple(s + axis) in seen for s in sites)


def min_fiber_width(cut: int) -> int:
    """Narrowest connected fibre of a cut: 1 for cut 0, 2 for cut 1 (a single zig-zag column
    has its particles sqrt(3) apart), 3 for cut 2."""
    width = 1
    while not _strip_is_connected(np.outer(np.arange(width), _line_representative(FIBER_AXES[cut])), FIBER_AXES[cut]):
        width += 1
    return width


def fiber(width: int, cut: int = 0, curved: bool = True) -> Topology:
    """Infinite straight-cut fibre, as one periodic cell of ``width`` particles.

    ``cut`` selects the axis (module docstring). With ``curved=True`` (default) successive images
    are related by a rigid motion with a free angle, so an asymmetric fibre takes the constant
    curvature it prefers; ``curved=False`` keeps it straight (its length still relaxes).
    """
    if cut not in FIBER_AXES:
        raise ValueError(f"cut must be 0, 1 or 2, got {cut!r}")
    if int(width) != width or width < 1:
        raise ValueError(f"width must be a positive integer, got {width!r}")
    axis = FIBER_AXES[cut]
    step = _line_representative(axis)
    sites = np.outer(np.arange(int(width)), step)
    if not _strip_is_connected(sites, axis):
        raise ValueError(f"width {width} is too narrow for cut {cut}: the strip falls apart "
                         f"(the narrowest connected one has width {min_fiber_width(cut)})")
    length = np.linalg.norm(site_positions([axis])[0])
    return Topology("fiber", sites, "fiber", [axis, (0, 0)], curved=curved,
                    size=float(width * AREA_PER_PARTICLE / length),
                    label=f"fibre cut {cut} width {width}" + ("" if curved else " (straight)"))


def bulk() -> Topology:
    """The infinite bulk, as a one-particle periodic cell."""
    return Topology("bulk", [[0, 0]], "bulk", [(1, 0), (0, 1)], size=float("inf"), label="bulk")


# Hole patterns: (periods, occupied sites of the cell). 'honeycomb' removes one site in three
# (a sqrt(3) x sqrt(3) superlattice): no three particles share a corner, so every particle can
# keep its rest shape (zero deformation energy). 'kagome' removes one site in four, 'sqrt7'
# one in seven (isolated vacancies): more bonds, but particles must deform.
HOLE_PATTERNS = {
    "honeycomb": ([(1, 1), (-1, 2)], [(1, 0), (0, 1)]),
    "kagome": ([(2, 0), (0, 2)], [(1, 0), (0, 1), (1, 1)]),
    "sqrt7": ([(2, 1), (-1, 3)], [(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)]),
}


def bulk_with_holes(pattern: str = "honeycomb") -> Topology:
    """A periodic bulk with a regular pattern of holes (``HOLE_PATTERNS``)."""
    if pattern not in HOLE_PATTERNS:
        raise ValueError(f"pattern must be one of {sorted(HOLE_PATTERNS)}, got {pattern!r}")
    periods, sites = HOLE_PATTERNS[pattern]
    return Topology("bulk_with_holes", sites, "bulk", periods, size=float("inf"), label=f"bulk with holes ({pattern})")


def periodic(sites, periods, label: str = "periodic") -> Topology:
    """Any periodic bulk cell: ``sites`` of the cell spanned by the two lattice ``periods``."""
    return Topology("bulk_with_holes", np.asarray(sites).reshape(-1, 2), "bulk", periods, size=float("inf"), label=label)
