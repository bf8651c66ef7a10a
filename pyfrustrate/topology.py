"""Aggregate topologies (main text, "Two-dimensional particle model"): which sites of a tiling are
occupied, and which periodic cell stands for an infinite scene.

Every builder takes the tiling through one keyword, ``tiling="hexagon"`` (default, the paper's
particle) or ``"triangle"`` (supplement, Fig. S6). The kernel owns each tiling's geometry
(``tiling_facts``): cells ``(i, j)`` at ``i a1 + j a2`` with ``a1 = (1, 0)``,
``a2 = (1/2, sqrt(3)/2)``; a hexagon tiling has one site per cell (sites ``(i, j)``, area
``sqrt(3)/2`` per particle, six neighbours), a triangle tiling two (sites ``(i, j, s)``, ``s = 0``
the up triangle ``(i, j), (i+1, j), (i, j+1)``, ``s = 1`` the down one; area ``sqrt(3)/4`` per
particle, three neighbours). Model only what the scene requires: an infinite fibre is one period
of the strip, an infinite bulk one cell of the plane.

Hexagon fibre cuts (Fig. 4a has three kinds of fibres; the paper does not say which the third
is: this is our choice):

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

Triangle fibre cuts (supplement, Fig. S6e; a reconstruction, the panel's design being lost):

========  ====================  ====================================================
``cut``   axis (lattice)        edges; ``width``
========  ====================  ====================================================
0         ``a1`` (0 degrees)    flat on both sides; ``width`` whole rows (2 width particles
                                per period)
1         ``a1`` (0 degrees)    one flat, one sawtooth edge: ``width`` rows and the up
                                triangles of the next (2 width + 1 per period)
2         ``-a1 + 2 a2`` (90)   zig-zag; ``width`` columns of triangles (2 width per period)
========  ====================  ====================================================

The triangle ``disk(R)`` is the hexagon of side ``R`` around a vertex (``6 R^2`` particles;
``disk(0)`` is a single particle); its continuum radius that of the disk of equal area.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from math import gcd, isqrt

import numpy as np

from . import _kernel
from ._checks import affordable, integer, non_negative

SQRT3 = np.sqrt(3.0)
ROW_SPACING = SQRT3 / 2  # distance between the lattice's rows parallel to a1, lattice spacings

# Memory estimates: upper bounds, with some headroom, on the peak memory per particle or grid
# cell (tests/test_api.py checks each against what building a topology really takes). A size
# whose estimate exceeds the allowed share of memory is refused up front (``_checks.affordable``)
# instead of dying in numpy's allocator or swapping the machine.
#: Bytes per particle of a ``Topology`` (the kernel's corner graph).
TOPOLOGY_BYTES_PER_PARTICLE = 400
#: Bytes per lattice cell of the numpy grids each site builder scans (coordinates, masks, sorts).
GRID_BYTES_PER_CELL = {"hexagon_sites": 48, "triangle_hexagon_sites": 104, "stadium_sites": 120,
                       "triangle_fiber": 160}
#: Bytes per particle of a fibre's connectivity check (Python sets of nine images), topology
#: included.
FIBER_BYTES_PER_PARTICLE = 3600
TILINGS = ("hexagon", "triangle")
_PERIODICITY = {"none": 0, "fiber": 1, "bulk": 2}


@lru_cache(maxsize=None)
def tiling_facts(tiling: str = "hexagon") -> dict:
    """What the kernel knows of a tiling (``kernel/tiling.hpp``), asked for rather than copied.

    Parameters
    ----------
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    dict
        ``sublattices`` (sites per lattice cell), ``corners`` per particle, ``coordination`` (edge
        neighbours per site), ``bulk_bonds_per_particle``, ``neighbours`` (per sublattice, tuples
        ``(di, dj, sublattice)`` in lattice coordinates), ``slot_offsets`` (corner positions from
        the site centre, per sublattice), ``frames`` (rotation of each sublattice's particles) and
        ``site_offsets``.

    Raises
    ------
    ValueError
        If ``tiling`` is not one of ``TILINGS``.

    Examples
    --------
    >>> from pyfrustrate import topology
    >>> facts = topology.tiling_facts("hexagon")
    >>> facts["sublattices"], facts["coordination"], facts["bulk_bonds_per_particle"]
    (1, 6, 3.0)
    """
    if tiling not in TILINGS:
        raise ValueError(f"tiling must be one of {TILINGS}, got {tiling!r}")
    return _kernel.tiling(tiling)


def site_columns(tiling: str = "hexagon") -> int:
    """Columns of a site array: 2 (``i, j``) on the hexagon tiling, 3 (``i, j, sublattice``) on the
    triangle one.

    Parameters
    ----------
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    int
    """
    return 3 if tiling_facts(tiling)["sublattices"] > 1 else 2


def area_per_particle(tiling: str = "hexagon") -> float:
    """Area of one site, in squared lattice spacings: ``sqrt(3)/2`` per cell, shared by its sites.

    Parameters
    ----------
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    float
        ``sqrt(3)/2`` (hexagons) or ``sqrt(3)/4`` (triangles).
    """
    return float(SQRT3 / 2 / tiling_facts(tiling)["sublattices"])


AREA_PER_PARTICLE = SQRT3 / 2  # hexagon tiling
FIBER_AXES = {0: (1, 0), 1: (-1, 2), 2: (2, 1)}  # hexagon tiling
TRIANGLE_FIBER_AXES = {0: (1, 0), 1: (1, 0), 2: (-1, 2)}


def _whole(name: str, value, lo: int) -> int:
    """``value`` as an int ``>= lo`` if it is a whole number (an integral float too), else
    ValueError naming ``name``: ``int()`` alone raises OverflowError for inf and a message
    without the parameter for NaN or text."""
    try:
        ok = not isinstance(value, bool) and float(value) == int(float(value)) and value >= lo
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        bound = "positive" if lo == 1 else "non-negative" if lo == 0 else f">= {lo}"
        raise ValueError(f"{name} must be a {bound} integer, got {value!r}")
    return int(value)


def fiber_axis(cut: int, tiling: str = "hexagon") -> tuple[int, int]:
    """Axis of a fibre cut, as a lattice vector (module docstring).

    The axis is in **lattice coordinates** ``(i, j)``, i.e. ``i a1 + j a2`` with ``a1 = (1, 0)``
    and ``a2 = (1/2, sqrt(3)/2)`` (60-degree axes), not in Cartesian ones: its length is
    ``|i a1 + j a2|`` (``cell_positions``), e.g. ``sqrt(3)`` for cut 1, not ``sqrt(5)``.

    Parameters
    ----------
    cut : {0, 1, 2}
        The cut (module docstring).
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    tuple of int
        ``(i, j)``.

    Raises
    ------
    ValueError
        For an unknown cut or tiling.

    Examples
    --------
    >>> from pyfrustrate import topology
    >>> topology.fiber_axis(1)
    (-1, 2)
    >>> topology.cell_positions([topology.fiber_axis(1)]).round(4)  # Cartesian: the 90-degree axis
    array([[0.    , 1.7321]])
    """
    tiling_facts(tiling)  # an unknown tiling is refused, not given the triangle's axes
    axes = FIBER_AXES if tiling == "hexagon" else TRIANGLE_FIBER_AXES
    if cut not in axes:
        raise ValueError(f"cut must be 0, 1 or 2, got {cut!r}")
    return axes[cut]


def cell_positions(cells) -> np.ndarray:
    """Cartesian positions of lattice cells.

    Parameters
    ----------
    cells : array_like, shape (n, 2)
        Lattice coordinates ``(i, j)`` (any real values), meaning ``i a1 + j a2`` with
        ``a1 = (1, 0)``, ``a2 = (1/2, sqrt(3)/2)``.

    Returns
    -------
    ndarray, shape (n, 2)
        ``(x, y)`` in lattice spacings.
    """
    s = np.asarray(cells, dtype=float).reshape(-1, 2)
    return np.column_stack([s[:, 0] + 0.5 * s[:, 1], 0.5 * SQRT3 * s[:, 1]])


def site_positions(sites, tiling: str = "hexagon") -> np.ndarray:
    """Cartesian centres of sites.

    Parameters
    ----------
    sites : array_like, shape (n, 2) or (n, 3)
        Sites in lattice coordinates, ``(i, j)`` (hexagons) or ``(i, j, sublattice)`` (triangles).
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    ndarray, shape (n, 2)
        ``(x, y)`` in lattice spacings.
    """
    if tiling == "hexagon":
        return cell_positions(sites)
    sites = np.asarray(sites, dtype=np.int32).reshape(-1, site_columns(tiling))
    return np.asarray(_kernel.site_positions(tiling, sites))


def neighbour_sites(site, tiling: str = "hexagon") -> list[tuple]:
    """The edge neighbours of one site (the kernel's table).

    Parameters
    ----------
    site : sequence of int
        ``(i, j)`` or ``(i, j, sublattice)``, in lattice coordinates.
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    list of tuple
        The neighbouring sites, in the same form.

    Examples
    --------
    >>> from pyfrustrate import topology
    >>> topology.neighbour_sites((0, 0))
    [(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)]
    """
    site = tuple(int(v) for v in site)
    sub = site[2] if len(site) == 3 else 0
    out = []
    for di, dj, s in tiling_facts(tiling)["neighbours"][sub]:
        out.append((site[0] + di, site[1] + dj, s) if len(site) == 3 else (site[0] + di, site[1] + dj))
    return out


@dataclass(frozen=True)
class Topology:
    """An aggregate topology and its corner graph (built by the kernel).

    Built by ``cluster``, ``disk``, ``fiber``, ``bulk``, ``bulk_with_holes`` or ``periodic``
    rather than directly. Immutable.

    Parameters
    ----------
    kind : str
        ``'cluster'``, ``'disk'``, ``'fiber'``, ``'bulk'`` or ``'bulk_with_holes'``.
    sites : array_like of int, shape (n_particles, 2) or (n_particles, 3)
        Occupied sites in lattice coordinates (one representative per particle of a periodic cell).
    periodicity : {'none', 'fiber', 'bulk'}
        No period, one period vector or two.
    periods : array_like of int, shape (2, 2)
        Lattice period vectors (rows, in lattice coordinates; unused rows are zero).
    curved : bool
        Fibre images are rotated by a free angle, so the fibre may bend.
    size : float
        Continuum size in lattice spacings: ``W`` for a fibre (area per unit length), ``R`` for a
        disk (radius of the disk of equal area), ``inf`` for bulks, ``nan`` for clusters.
    label : str
        Short human-readable name.
    tiling : {'hexagon', 'triangle'}
        The tiling of the sites.

    Attributes
    ----------
    kernel : pyfrustrate._kernel.Topology
        The kernel's corner graph.
    n_particles, n_bonds, n_corners : int
        Particles, bound pairs of sides and distinct corners (per cell when periodic).

    Raises
    ------
    ValueError
        For an empty or malformed site array, sites off the lattice or beyond 1e6, duplicate
        sites (the kernel), or a size too large for memory.
    """

    kind: str
    sites: np.ndarray
    periodicity: str = "none"
    periods: np.ndarray = field(default_factory=lambda: np.zeros((2, 2), int))
    curved: bool = False
    size: float = float("nan")
    label: str = ""
    tiling: str = "hexagon"
    kernel: _kernel.Topology = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        sites = np.asarray(self.sites)
        if sites.size == 0:
            raise ValueError("sites: the topology is empty")
        columns = site_columns(self.tiling)
        if sites.ndim != 2 or sites.shape[1] != columns:
            raise ValueError(f"sites must have shape (n, {columns}) for the {self.tiling} tiling, got {sites.shape}")
        if not np.all(np.isfinite(sites)) or not np.all(np.equal(np.mod(sites, 1), 0)):
            raise ValueError("sites must be integer lattice coordinates (i, j): a site is off the lattice")
        affordable(f"a topology of {len(sites)} particles", len(sites) * TOPOLOGY_BYTES_PER_PARTICLE)
        sites = sites.astype(np.int64)
        if np.abs(sites).max() > 10**6:
            raise ValueError("sites: coordinates beyond 1e6 are not supported")
        object.__setattr__(self, "sites", sites.astype(np.int32))
        object.__setattr__(self, "periods", np.asarray(self.periods, dtype=np.int32).reshape(2, 2))
        kernel = _kernel.Topology(self.tiling, self.sites, _PERIODICITY[self.periodicity], self.periods.tolist(),
                                  bool(self.curved))
        object.__setattr__(self, "kernel", kernel)

    @property
    def n_particles(self) -> int:
        """Particles (per cell when periodic)."""
        return self.kernel.n_particles

    @property
    def n_bonds(self) -> int:
        """Bound pairs of sides (per cell when periodic)."""
        return self.kernel.n_bonds

    @property
    def n_corners(self) -> int:
        """Distinct corners: the degrees of freedom are their ``2 n_corners`` coordinates."""
        return self.kernel.n_corners

    def reference_state(self) -> np.ndarray:
        """The bulk-reference degrees of freedom: corners at the rest positions of the lattice.

        Returns
        -------
        ndarray, shape (2 n_corners + n_period_parameters,)
            Corner coordinates ``(x0, y0, x1, y1, ...)`` in lattice spacings, then the period
            parameters (fibre: the period vector ``tx, ty`` and, when curved, the bend angle's
            parameter; bulk: the two period vectors ``t1x, t1y, t2x, t2y``).
        """
        return np.asarray(self.kernel.reference_state())


NEIGHBOURS = np.array([(di, dj) for di, dj, _ in tiling_facts("hexagon")["neighbours"][0]])  # hexagon tiling


def _site_array(sites, tiling: str) -> np.ndarray:
    sites = np.asarray(sites)
    columns = site_columns(tiling)
    if sites.size == 0:
        raise ValueError("sites: the topology is empty")
    if sites.ndim != 2 or sites.shape[1] != columns:
        names = "i, j, sublattice" if columns == 3 else "i, j"
        raise ValueError(f"sites must have shape (n, {columns}) ({names}) for the {tiling} tiling, got {sites.shape}")
    return sites


def cluster(sites, label: str = "cluster", tiling: str = "hexagon") -> Topology:
    """A finite aggregate of any set of distinct sites.

    Parameters
    ----------
    sites : array_like of int, shape (n, 2) or (n, 3)
        Sites in lattice coordinates, ``(i, j)`` (hexagons) or ``(i, j, sublattice)`` (triangles).
    label : str, optional
        Short name.
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    Topology

    Raises
    ------
    ValueError
        For an empty or malformed site array.

    Examples
    --------
    >>> from pyfrustrate import topology
    >>> t = topology.cluster([[0, 0], [1, 0], [0, 1]])  # three mutually bound hexagons
    >>> t.n_particles, t.n_bonds
    (3, 3)
    """
    tiling_facts(tiling)
    return Topology("cluster", _site_array(sites, tiling), label=label, tiling=tiling)


def hexagon_sites(R: int) -> np.ndarray:
    """Sites within hexagonal distance ``R`` of the origin.

    Parameters
    ----------
    R : int
        Radius in lattice steps, ``>= 0``.

    Returns
    -------
    ndarray of int, shape (1 + 3 R (R + 1), 2)
        Lattice coordinates ``(i, j)``.

    Raises
    ------
    ValueError
        If ``R`` is not a non-negative integer, or too large for memory.
    """
    R = _whole("R", R, 0)
    affordable(f"hexagon_sites(R={R})", (2 * R + 1) ** 2 * GRID_BYTES_PER_CELL["hexagon_sites"])
    r = np.arange(-R, R + 1)
    i, j = np.meshgrid(r, r, indexing="ij")
    keep = np.abs(i + j) <= R
    return np.column_stack([i[keep], j[keep]])


def triangle_hexagon_sites(R: int) -> np.ndarray:
    """Triangles inside the hexagon of side ``R`` around the vertex (0, 0): those whose three
    vertices lie within hexagonal distance ``R`` of it.

    Parameters
    ----------
    R : int
        Side in lattice steps, ``>= 0``.

    Returns
    -------
    ndarray of int, shape (6 R^2, 3)
        Sites ``(i, j, sublattice)``.

    Raises
    ------
    ValueError
        If ``R`` is not a non-negative integer, or too large for memory.
    """
    R = _whole("R", R, 0)
    affordable(f"triangle_hexagon_sites(R={R})", (2 * R + 2) ** 2 * GRID_BYTES_PER_CELL["triangle_hexagon_sites"])
    r = np.arange(-R - 1, R + 1)
    i, j = (a.ravel() for a in np.meshgrid(r, r, indexing="ij"))

    def inside(a, b):
        return np.maximum(np.maximum(np.abs(a), np.abs(b)), np.abs(a + b)) <= R

    up = inside(i, j) & inside(i + 1, j) & inside(i, j + 1)
    down = inside(i + 1, j + 1) & inside(i, j + 1) & inside(i + 1, j)
    return np.concatenate([np.column_stack([i[up], j[up], np.zeros(up.sum(), int)]),
                           np.column_stack([i[down], j[down], np.ones(down.sum(), int)])])


def disk(R: int, tiling: str = "hexagon") -> Topology:
    """Compact aggregate of radius ``R``: the hexagon of radius ``R`` around a site (hexagon tiling,
    ``1 + 3 R (R + 1)`` particles) or of side ``R`` around a vertex (triangle tiling, ``6 R^2``).

    Parameters
    ----------
    R : int
        Radius in lattice steps; ``R = 0`` is a single particle.
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    Topology
        ``size`` is the continuum radius, that of the disk of equal area,
        ``sqrt(N * area_per_particle / pi)`` in lattice spacings. To compare with the continuum
        theory divide it by the particle's ``ell``: ``continuum.disk_energy(size / ell, ...)``.

    Raises
    ------
    ValueError
        If ``R`` is not a non-negative integer, or the disk is too large for memory (the message
        says how much it would need).

    Examples
    --------
    >>> from pyfrustrate import topology
    >>> d = topology.disk(2)
    >>> d.n_particles, d.n_bonds, round(d.size, 4)
    (19, 42, 2.2886)
    >>> topology.disk(1, tiling="triangle").n_particles
    6
    """
    R = _whole("R", R, 0)
    facts = tiling_facts(tiling)
    if facts["sublattices"] == 1:
        n_particles, grid = 1 + 3 * R * (R + 1), (2 * R + 1) ** 2 * GRID_BYTES_PER_CELL["hexagon_sites"]
    else:
        n_particles, grid = max(1, 6 * R * R), (2 * R + 2) ** 2 * GRID_BYTES_PER_CELL["triangle_hexagon_sites"]
    affordable(f"disk(R={R})", grid + n_particles * TOPOLOGY_BYTES_PER_PARTICLE)
    if facts["sublattices"] == 1:
        sites = hexagon_sites(int(R))
    else:
        sites = triangle_hexagon_sites(int(R)) if R > 0 else np.array([[0, 0, 0]])
    return Topology("disk", sites, size=float(np.sqrt(len(sites) * area_per_particle(tiling) / np.pi)),
                    label=f"disk R={R}", tiling=tiling)


def stadium_sites(n: int, segment: float = 0.0, faceted: bool = False, tiling: str = "hexagon",
                  hole: int = 0) -> np.ndarray:
    """The ``n`` sites nearest to a segment of length ``segment`` centred on the origin along ``a1``,
    after the ``hole`` nearest ones.

    A near-circular aggregate for ``segment = 0``, a rounded strip (a finite cut-0 fibre) of width
    about ``n sqrt(3) / (2 segment)`` for long segments. Ties in distance are broken by the
    distance to the origin, then by the angle, so the shape is unique and deterministic.

    ``faceted``: nearest in the lattice's own (hexagonal) distance instead of the Euclidean one,
    so the shape is bounded by close-packed rows: a hexagon for ``segment = 0``, a strip with
    faceted ends for long segments. An unfinished outer shell is filled in order of angle about
    the origin, from just past the corner on ``a1``, so it grows side by side like a spiral; at
    ``segment = 0`` this gives every ``n`` the largest number of bonds any ``n`` sites of the
    lattice can have, ``3 n - ceil(sqrt(12 n - 3))`` (Harary and Harborth, 1976). A Euclidean disk
    of 200 particles has two bonds fewer: at strong binding the faceted shapes win.

    ``hole``: the same order with its first ``hole`` sites left empty, an aggregate with a hole
    at its core: a hexagonal ring for ``faceted``, ``segment = 0`` and ``hole`` a hexagonal number
    ``1 + 3 r (r + 1)``; a slot along the segment of a long one. Frustrated particles build up
    stress towards an aggregate's centre, which a hole relieves at the cost of its rim's bonds.

    Finite-size predictions use both one-parameter families of single aggregates of exactly
    ``n`` particles, solid and with holes (``ansatz.finite_aggregates``).

    On the triangle tiling the distances are those of the triangles' centres from a segment
    centred on the vertex (0, 0): a faceted shape of ``6 R^2`` triangles at ``segment = 0`` is
    the hexagon of side ``R``, ``triangle_hexagon_sites(R)``.

    Parameters
    ----------
    n : int
        Number of sites, ``>= 1``.
    segment : float, optional
        Length of the core segment, in lattice spacings, ``>= 0``.
    faceted : bool, optional
        Hexagonal rather than Euclidean distance.
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).
    hole : int, optional
        Sites left empty nearest to the segment, ``>= 0`` (default 0: a solid aggregate).

    Returns
    -------
    ndarray of int, shape (n, 2) or (n, 3)
        Sites ``(i, j)``, or ``(i, j, sublattice)`` on the triangle tiling.

    Raises
    ------
    ValueError
        For a bad ``n``, ``segment`` or ``hole``, or a request too large for memory.

    Examples
    --------
    >>> from pyfrustrate import topology
    >>> sites = topology.stadium_sites(7, faceted=True)  # a particle and its ring
    >>> len(sites), topology.cluster(sites).n_bonds == topology.most_bonds(7)
    (7, True)
    >>> ring = topology.stadium_sites(6, faceted=True, hole=1)  # the ring without its centre
    >>> topology.cluster(ring).n_bonds
    6
    """
    n = integer("n", n, 1)
    segment = non_negative("segment", segment)
    hole = integer("hole", hole, 0)
    # Enough rows and columns to hold the hole and n sites around the segment.
    half = int(np.ceil(segment / 2 + np.sqrt(n + hole))) + 2
    sublattices = tiling_facts(tiling)["sublattices"]
    affordable(f"stadium_sites(n={n}, segment={segment:g}, hole={hole})",
               sublattices * (4 * half + 1) ** 2 * GRID_BYTES_PER_CELL["stadium_sites"])
    r = np.arange(-2 * half, 2 * half + 1)
    # One column per lattice coordinate, and the sublattice on tilings with several (triangles).
    axes = [r, r] + ([np.arange(sublattices)] if sublattices > 1 else [])
    sites = np.column_stack([a.ravel() for a in np.meshgrid(*axes, indexing="ij")])
    xy = site_positions(sites, tiling)
    across, along = np.abs(xy[:, 1]), np.abs(xy[:, 0] - np.clip(xy[:, 0], -segment / 2, segment / 2))
    if faceted:
        # The hexagonal distance from the segment: the number of nearest-neighbour steps to it
        # (its level sets are hexagons with corners on the lattice directions a1, a2 - a1, ...).
        distance = np.round(np.maximum(along + across / np.sqrt(3), 2 * across / np.sqrt(3)), 9)
        # Angle in (0, 2 pi], the corner on a1 last: a shell is filled from just past that corner.
        angle = np.round(2 * np.pi - np.mod(-np.arctan2(xy[:, 1], xy[:, 0]), 2 * np.pi), 9)
        order = np.lexsort((xy[:, 0], angle, distance))
    else:
        distance = np.round(np.hypot(along, across), 9)
        order = np.lexsort((np.arctan2(xy[:, 1], xy[:, 0]), np.round(np.hypot(*xy.T), 9), distance))
    return sites[order[hole:hole + n]]


def most_bonds(n: int) -> int:
    """The most nearest-neighbour pairs ``n`` sites of the triangular lattice can share,
    ``3 n - ceil(sqrt(12 n - 3))`` (Harary and Harborth, 1976), in integer arithmetic.

    Parameters
    ----------
    n : int
        Number of sites, ``>= 1``.

    Returns
    -------
    int

    Examples
    --------
    >>> from pyfrustrate import topology
    >>> topology.most_bonds(7), topology.most_bonds(200)
    (12, 551)
    """
    n = integer("n", n, 1)
    root = isqrt(12 * n - 3)
    return 3 * n - (root if root * root == 12 * n - 3 else root + 1)


def complete_hexagon_sides(n: int) -> tuple[int, int, int] | None:
    """Sides of the complete hexagon of ``n`` sites, or None when ``n`` is no such number.

    The sides ``(a, b, c)``, in sites and differing by at most one, run a, b, c, a, b, c around
    the hexagon, ``n = ab + bc + ca - a - b - c + 1``: ``n`` is one of 3k^2 - 3k + 1, 3k^2 - k,
    3k^2 + k (200 = sides 8, 9, 9). One more site adds at most two bonds to ``most_bonds`` at these
    ``n`` (they are the largest with their minimal perimeter), and the complete hexagon is the only
    outline, up to the lattice's rotations and reflections, that holds ``most_bonds(n)`` bonds
    (tests/test_topology.py enumerates every shape of 7 and 10 sites); outlines with one bond fewer
    are many. A Monte Carlo run whose ground state is this hexagon must find that one shape.

    Parameters
    ----------
    n : int
        Number of sites, ``>= 1``.

    Returns
    -------
    tuple of int or None

    Examples
    --------
    >>> from pyfrustrate import topology
    >>> topology.complete_hexagon_sides(200), topology.complete_hexagon_sides(8)
    ((8, 9, 9), None)
    """
    n = integer("n", n, 1)
    k = max(1, round(np.sqrt(n / 3)))
    for a in (k - 1, k, k + 1):
        for b, c in ((a, a), (a, a + 1), (a + 1, a + 1)):
            if a >= 1 and a * b + b * c + c * a - a - b - c + 1 == n:
                return a, b, c
    return None


def gyration_dimensions(sites, tiling: str = "hexagon") -> tuple[float, float]:
    """Width and length of an aggregate from its gyration tensor.

    ``sqrt(12 lambda)`` for its two eigenvalues, which are exactly the sides of a uniform
    rectangle (a compact disk of radius ``R`` gives ``sqrt(3) R`` both ways). Orientation-free, so
    it measures Monte Carlo aggregates and pre-made ones alike.

    Parameters
    ----------
    sites : array_like of int, shape (n, 2) or (n, 3)
        The aggregate's sites, in lattice coordinates.
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    width : float
        The smaller side, in lattice spacings (0 for a single site).
    length : float
        The larger side, in lattice spacings (0 for a single site).
    """
    xy = site_positions(sites, tiling)
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


def _strip_is_connected(sites: np.ndarray, axis, tiling: str = "hexagon") -> bool:
    """Whether the infinite strip generated by repeating ``sites`` along ``axis`` is connected:
    every site of the cell reaches its own next image through bonds."""
    axis = np.asarray(axis)
    shift = np.zeros(sites.shape[1], int)
    shift[:2] = axis
    copies = 4  # a band of consecutive lattice lines connects within neighbouring copies
    points = {tuple(s + m * shift) for m in range(-copies, copies + 1) for s in sites}
    seen, frontier = {tuple(sites[0])}, [tuple(sites[0])]
    while frontier:
        for there in neighbour_sites(frontier.pop(), tiling):
            if there in points and there not in seen:
                seen.add(there)
                frontier.append(there)
    return all(tuple(s) in seen and tuple(s + shift) in seen for s in sites)


def _triangle_fiber_sites(width: int, cut: int) -> np.ndarray:
    """One period of a triangle fibre (module docstring): rows along a1 (cuts 0, 1), columns
    along -a1 + 2 a2 (cut 2)."""
    if cut in (0, 1):
        rows = [(0, j, s) for j in range(width) for s in (0, 1)]
        return np.array(rows + ([(0, width, 0)] if cut == 1 else []))
    # Column c holds the triangles whose centres have x = (c + 1) / 2, one up and one down per
    # period (0, sqrt 3): the sites of centre x in [1/2, (width + 1)/2) and y in [0, sqrt 3).
    r = np.arange(-2 * width - 4, 2 * width + 5)
    i, j = (a.ravel() for a in np.meshgrid(r, r, indexing="ij"))
    sites = np.concatenate([np.column_stack([i, j, np.zeros_like(i)]), np.column_stack([i, j, np.ones_like(i)])])
    xy = site_positions(sites, "triangle")
    keep = (xy[:, 0] > 0.25) & (xy[:, 0] < (width + 1) / 2 - 0.25) & (xy[:, 1] > -1e-9) & (xy[:, 1] < SQRT3 - 1e-9)
    return sites[keep]


def min_fiber_width(cut: int, tiling: str = "hexagon") -> int:
    """Narrowest connected fibre of a cut, in lattice lines.

    Hexagons: 1 for cut 0, 2 for cut 1 (a single zig-zag column has its particles sqrt(3)
    apart), 3 for cut 2. Triangles: 1, 1, 2 (a single column of triangles touches only at
    corners).

    Parameters
    ----------
    cut : {0, 1, 2}
        The cut (module docstring).
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    int
    """
    width = 1
    while not _strip_is_connected(_fiber_cell(width, cut, tiling), fiber_axis(cut, tiling), tiling):
        width += 1
    return width


def _fiber_cell(width: int, cut: int, tiling: str) -> np.ndarray:
    if tiling == "hexagon":
        return np.outer(np.arange(width), _line_representative(fiber_axis(cut, tiling)))
    return _triangle_fiber_sites(width, cut)


def fiber(width: int, cut: int = 0, curved: bool = True, tiling: str = "hexagon") -> Topology:
    """Infinite straight-cut fibre, as one periodic cell of ``width`` lattice lines.

    ``width`` counts **lattice lines** parallel to the axis (the particles per period on the
    hexagon tiling), not a length: the continuum width is the area per unit length,
    ``W = width * sqrt(3)/2 / |axis|`` in lattice spacings for hexagons (``width * sqrt(3)/2``
    for cut 0, ``width / 2`` for cut 1), returned as ``size``. Compare with the continuum theory
    through ``size / ell``, never ``width / ell``.

    Parameters
    ----------
    width : int
        Lattice lines per period, at least ``min_fiber_width(cut, tiling)``.
    cut : {0, 1, 2}, optional
        Axis and edges (module docstring): 0 flat rows, 1 zig-zag, 2 stepped.
    curved : bool, optional
        True (default): successive images are related by a rigid motion with a free angle, so an
        asymmetric fibre takes the constant curvature it prefers. False keeps it straight (its
        length still relaxes).
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    Topology
        ``periods[0]`` is the axis (lattice coordinates), ``size`` the continuum width ``W``.

    Raises
    ------
    ValueError
        For a bad cut, a width that is not a positive integer or too narrow for the cut to hold
        together, or a width too large for memory.

    Examples
    --------
    >>> from pyfrustrate import topology
    >>> f = topology.fiber(4)
    >>> f.n_particles, f.n_bonds, round(f.size, 4)  # W = 4 sqrt(3)/2
    (4, 10, 3.4641)
    >>> round(topology.fiber(4, cut=1).size, 4)  # the zig-zag axis has length sqrt(3)
    2.0
    """
    tiling_facts(tiling)
    axis = fiber_axis(cut, tiling)
    width = _whole("width", width, 1)
    grid = (4 * width + 9) ** 2 * GRID_BYTES_PER_CELL["triangle_fiber"] if tiling == "triangle" and cut == 2 else 0
    affordable(f"fiber(width={width})", grid + 2 * width * FIBER_BYTES_PER_PARTICLE)
    sites = _fiber_cell(int(width), cut, tiling)
    if not _strip_is_connected(sites, axis, tiling):
        raise ValueError(f"width {width} is too narrow for cut {cut}: the strip falls apart "
                         f"(the narrowest connected one has width {min_fiber_width(cut, tiling)})")
    length = np.linalg.norm(cell_positions([axis])[0])
    return Topology("fiber", sites, "fiber", np.array([axis, (0, 0)]), curved=curved,
                    size=float(len(sites) * area_per_particle(tiling) / length),
                    label=f"fibre cut {cut} width {width}" + ("" if curved else " (straight)"), tiling=tiling)


def bulk(tiling: str = "hexagon") -> Topology:
    """The infinite bulk, as a one-cell periodic cell (one hexagon, or an up and a down triangle).

    Parameters
    ----------
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    Topology

    Examples
    --------
    >>> from pyfrustrate import topology
    >>> b = topology.bulk()
    >>> b.n_particles, b.n_bonds, b.size
    (1, 3, inf)
    """
    sites = [[0, 0]] if site_columns(tiling) == 2 else [[0, 0, 0], [0, 0, 1]]
    return Topology("bulk", np.array(sites), "bulk", np.array([(1, 0), (0, 1)]), size=float("inf"), label="bulk",
                    tiling=tiling)


# Hole patterns: (periods, occupied sites of the cell), per tiling. Hexagons: 'honeycomb'
# removes one site in three (a sqrt(3) x sqrt(3) superlattice): no three particles share a
# corner, so every particle can keep its rest shape (zero deformation energy). 'kagome' removes
# one site in four, 'sqrt7' one in seven (isolated vacancies): more bonds, but particles must
# deform. Triangles (for completeness: no bulk with holes can win there, as any bound pair
# already costs energy): 'vacancy3' removes one triangle in six, 'vacancy4' one in eight,
# 'hexagonal' the six triangles around one vertex in eighteen.
HOLE_PATTERNS = {
    "honeycomb": ([(1, 1), (-1, 2)], [(1, 0), (0, 1)]),
    "kagome": ([(2, 0), (0, 2)], [(1, 0), (0, 1), (1, 1)]),
    "sqrt7": ([(2, 1), (-1, 3)], [(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)]),
}


def _triangle_cell(periods, removed) -> tuple:
    (a, b), (c, d) = periods
    n_cells = abs(a * d - b * c)
    sites, seen = [], set()
    span = range(-abs(a) - abs(c) - 1, abs(a) + abs(c) + 2)
    for i in span:
        for j in range(-abs(b) - abs(d) - 1, abs(b) + abs(d) + 2):
            # reduce cell (i, j) into the cell spanned by the periods (fractional coordinates)
            det = a * d - b * c
            s = (i * d - j * c) / det
            t = (a * j - b * i) / det
            if 0 <= s < 1 and 0 <= t < 1 and (i, j) not in seen:
                seen.add((i, j))
                sites += [(i, j, 0), (i, j, 1)]
    assert len(seen) == n_cells
    return periods, [x for x in sites if x not in set(removed)]


TRIANGLE_HOLE_PATTERNS = {
    "vacancy3": _triangle_cell([(1, 1), (-1, 2)], [(0, 0, 0)]),
    "vacancy4": _triangle_cell([(2, 0), (0, 2)], [(0, 0, 0)]),
    "hexagonal": _triangle_cell([(3, 0), (0, 3)], [(1, 1, 0), (0, 1, 0), (1, 0, 0), (0, 0, 1), (1, 0, 1), (0, 1, 1)]),
}


def hole_patterns(tiling: str = "hexagon") -> dict:
    """The hole patterns of a tiling.

    Parameters
    ----------
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    dict
        ``HOLE_PATTERNS`` or ``TRIANGLE_HOLE_PATTERNS``: name to ``(periods, sites of the cell)``.
    """
    tiling_facts(tiling)
    return HOLE_PATTERNS if tiling == "hexagon" else TRIANGLE_HOLE_PATTERNS


def bulk_with_holes(pattern: str = "honeycomb", tiling: str = "hexagon") -> Topology:
    """A periodic bulk with a regular pattern of holes.

    Parameters
    ----------
    pattern : str, optional
        A name of ``hole_patterns(tiling)`` (hexagons: ``'honeycomb'``, ``'kagome'``, ``'sqrt7'``).
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    Topology

    Raises
    ------
    ValueError
        For an unknown pattern or tiling.

    Examples
    --------
    >>> from pyfrustrate import topology
    >>> h = topology.bulk_with_holes("honeycomb")
    >>> h.n_particles, h.n_bonds  # one site in three removed: no corner shared by three
    (2, 3)
    """
    patterns = hole_patterns(tiling)
    if pattern not in patterns:
        raise ValueError(f"pattern must be one of {sorted(patterns)} for the {tiling} tiling, got {pattern!r}")
    periods, sites = patterns[pattern]
    return Topology("bulk_with_holes", sites, "bulk", periods, size=float("inf"), label=f"bulk with holes ({pattern})",
                    tiling=tiling)


def periodic(sites, periods, label: str = "periodic", tiling: str = "hexagon") -> Topology:
    """Any periodic bulk cell.

    Parameters
    ----------
    sites : array_like of int, shape (n, 2) or (n, 3)
        Sites of the cell, in lattice coordinates.
    periods : array_like of int, shape (2, 2)
        The two lattice period vectors (rows, lattice coordinates).
    label : str, optional
        Short name.
    tiling : {'hexagon', 'triangle'}, optional
        The tiling (default ``'hexagon'``, the paper's particle).

    Returns
    -------
    Topology
    """
    sites = np.asarray(sites).reshape(-1, site_columns(tiling))
    return Topology("bulk_with_holes", sites, "bulk", periods, size=float("inf"), label=label, tiling=tiling)
