"""Candidate ground states of a periodic Monte Carlo box: what ``n`` particles in a ``box x box``
lattice can form at best, to judge whether a run has equilibrated (issue: the finite-size
prediction as the real ground state of the box).

Families, each a set of real configurations of the box (their sites are returned and checked to
fit without touching their periodic images):

``single``
    one aggregate of all ``n`` particles, compact to elongated, round and faceted, solid or with a
    hole at its core (``ansatz.finite_aggregates``: ``topology.stadium_sites``);
``wrapping_fiber``
    full rows along ``a1`` that wrap the box (a straight fibre periodic with the box, ``n // box``
    rows) plus the remaining particles as a partial row on one edge; with ``n`` near ``box**2`` it
    is a slab;
``aggregates{m}``
    ``m`` separate aggregates of ``n / m`` particles each (the remainder in the last), all of the
    same shape (the solid shapes, and the compact ones with holes: ``_part_shapes``); ``m`` runs
    over ``aggregate_counts(n)``: every count to 16, then counts 1.25x
    apart while the aggregates keep at least 7 particles, since at low line tension the best
    aggregate is small and a large box holds many of them (800 particles at ell = 5, nu = 0.4, Gamma
    = 0.2: seven aggregates; the best of at most four lay 2-12 bulk energies above where annealing
    runs ended);
``fused{m}``
    the parts of ``aggregates{m}`` not apart but touching at necks, relaxed as one cluster
    (``fused_copies``): neighbouring copies shifted along a lattice direction by the smallest shift
    that neither overlaps nor leaves them apart (``neck_shift``), either on the ``m`` points of
    that super-lattice nearest the first copy (2 in a pair, 3 in a triangle, 4 in a rhombus, 7 in a
    hexagon) or in a chain along the direction of the narrowest neck. A neck of one bond adds that
    bond at almost no elastic cost, since it is compliant; a closed ring of necks, or a contact
    along a flat side, strains the parts (tests/test_ground_states.py). A box at ell = 5, nu = 0.4,
    Gamma = 0.2 seeded in separate disks ended below them, in one cluster of disks joined by necks
    (``benchmarks/bench_large_control.py``). Only the part shapes that are the best
    ``n / m``-particle aggregate at some binding energy (``ever_best``) are fused;
``gas``
    every particle alone (energy 0), when the box can hold ``n`` particles none of which touch.

Each candidate's energy is ``deformation - g * bonds`` with its relaxed deformation energy, so the
best at a binding energy ``g`` is the lowest of linear functions of ``g``.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from . import _checks, ansatz, topology
from ._checks import integer
from .relaxation import relax

FAMILIES = ("single", "wrapping_fiber", "aggregates", "fused", "gas")
#: Final energy above the box's predicted ground state, in bulk particle energies, beyond which a
#: Monte Carlo run counts as not equilibrated (the criterion of 5). A relative criterion would be
#: too loose: 18.9 bulk energies is 1 % of the energy of 400 particles, yet another structure.
#: The prediction is itself an upper bound (its shapes are a finite family).
EQUILIBRATED_GAP = 5.0
#: The energy gate of a large run judged by structure (``structure_verdict``): its final energy lies
#: within max(EQUILIBRATED_GAP bulk energies, GATE_BONDS bonds) of the box's ground state. At
#: Gamma >= 0.5 one bond is worth 2-4 bulk energies, and the bond-maximal outline that 5 bulk
#: energies asks for is entropically suppressed wherever the aggregate still moves (issue 33).
GATE_BONDS = 2
#: A fibre's width agrees with the prediction within this many rows.
WIDTH_TOLERANCE_ROWS = 1
#: A run counts as below the prediction (``structure_verdict``'s ``below_prediction``) when its
#: energy is lower by more than this many bulk energies: far above the differences that relaxing
#: the same shape to the runs' and the candidates' tolerances leaves.
BELOW_PREDICTION_MARGIN = 0.1
#: The fields of ``structure_verdict`` that the workflow stores per run (all but the gap itself).
VERDICT_FIELDS = ("count", "count_predicted", "kind", "kind_predicted", "width", "width_predicted", "lobes",
                  "lobes_predicted", "gap_gate", "count_ok", "kind_ok", "width_ok", "lobes_ok", "gap_ok",
                  "structure_match", "candidates_within_gate", "structure_within_gate", "below_prediction")
_NEIGHBOURS = tuple(tuple(int(x) for x in d) for d in topology.neighbour_sites((0, 0)))  # the six edge neighbours
#: The lattice directions along which ``fused_copies`` places neighbouring copies: a1, a2 (the
#: super-lattice's basis) and a2 - a1.
LATTICE_DIRECTIONS = ((1, 0), (0, 1), (-1, 1))


@dataclass(frozen=True)
class BoxCandidates(ansatz.EnergiesLinearInG):
    """Candidate ground states of ``n`` particles in a periodic ``box``, from ``box_candidates``.

    Energies are linear in the binding: candidate ``i`` has total energy
    ``deformation[i] - g * bonds[i]`` (``total``, ``best``, ``best_energy``).

    Attributes
    ----------
    n, box : int
        Particles and box side (lattice steps).
    family : ndarray of str
        ``single``, ``wrapping_fiber``, ``aggregates{m}``, ``fused{m}`` or ``gas`` (module
        docstring).
    deformation : ndarray
        Relaxed deformation energy of each candidate (whole box).
    bonds : ndarray of int
        Bound pairs of sides of each candidate.
    sites : tuple of ndarray
        Each candidate's sites, shape (n, 2), box cells ``0 <= i, j < box``.
    converged : ndarray of bool
        The minimiser's verdict.
    """

    n: int
    box: int
    family: np.ndarray
    deformation: np.ndarray
    bonds: np.ndarray
    sites: tuple
    converged: np.ndarray

    def best_family(self, g):
        """Family of the best candidate at each binding energy ``g``.

        Parameters
        ----------
        g : array_like
            Binding energies per bound pair of sides.

        Returns
        -------
        ndarray of str
            ``FAMILIES``, ``aggregates`` and ``fused`` with their count.
        """
        return self.family[self.best(g)]

    @classmethod
    def from_arrays(cls, arrays) -> "BoxCandidates":
        """Rebuild from a mapping with one entry per field (a saved ``.npz``, ``sites`` stacked, keys
        prefixed ``candidate_``).

        Parameters
        ----------
        arrays : mapping
            As written by ``arrays``.

        Returns
        -------
        BoxCandidates
        """
        return cls(int(arrays["candidate_n"]), int(arrays["candidate_box"]), np.asarray(arrays["candidate_family"]),
                   np.asarray(arrays["candidate_deformation"], float), np.asarray(arrays["candidate_bonds"]),
                   tuple(np.asarray(arrays["candidate_sites"])), np.asarray(arrays["candidate_converged"], bool))

    def arrays(self) -> dict:
        """The fields as arrays for ``io.save_npz`` (inverse of ``from_arrays``).

        Returns
        -------
        dict
        """
        return {"candidate_n": self.n, "candidate_box": self.box, "candidate_family": self.family.astype(str),
                "candidate_deformation": self.deformation, "candidate_bonds": self.bonds,
                "candidate_sites": np.stack(self.sites), "candidate_converged": self.converged}


def _in_box(sites, box) -> np.ndarray:
    return np.mod(np.asarray(sites, int), box)


def _touches_itself(sites, box) -> bool:
    """Whether a finite aggregate placed in the periodic box overlaps or touches one of its own
    images (then it is not the aggregate it was relaxed as)."""
    from .montecarlo import clusters
    wrapped = _in_box(sites, box)
    if len({tuple(s) for s in wrapped.tolist()}) < len(wrapped):
        return True
    parts = clusters(wrapped, box)
    return len(parts) != 1 or parts[0][1] != 0


def _pack(shapes, box):
    """Place finite aggregates (each an array of sites) in the box, apart: each is shifted to the
    first cell of a coarse grid where neither it nor its neighbours meet an occupied site. Returns
    the sites (all, box cells) or None when they do not fit."""
    occupied = np.zeros((box, box), bool)
    placed = []
    step = 2
    offsets = [(i, j) for j in range(0, box, step) for i in range(0, box, step)]
    for shape in shapes:
        shape = np.asarray(shape, int) - np.asarray(shape, int).min(axis=0)
        for di, dj in offsets:
            cells = _in_box(shape + (di, dj), box)
            halo = _in_box(np.concatenate([cells] + [cells + d for d in _NEIGHBOURS]), box)
            if not occupied[halo[:, 0], halo[:, 1]].any():
                occupied[cells[:, 0], cells[:, 1]] = True
                placed.append(cells)
                break
        else:
            return None
    return np.concatenate(placed)


def _gas_sites(n, box):
    """``n`` sites none of which touch (a sqrt(3) x sqrt(3) pattern, thinned at the seam when the
    box is not a multiple of 3), or None when the box holds fewer."""
    chosen, taken = [], np.zeros((box, box), bool)
    for j in range(box):
        for i in range(box):
            if (i - j) % 3 or taken[i, j]:
                continue
            if any(taken[(i + a) % box, (j + b) % box] for a, b in _NEIGHBOURS):
                continue
            taken[i, j] = True
            chosen.append((i, j))
            if len(chosen) == n:
                return np.array(chosen)
    return None


def ever_best(candidates: ansatz.EnergiesLinearInG) -> list[int]:
    """The candidates that are the lowest at some binding energy ``g >= 0``: the lower envelope of
    the lines ``deformation - g * bonds``, in order of increasing ``g`` (ties: the most bonds).

    Parameters
    ----------
    candidates : EnergiesLinearInG
        E.g. ``ansatz.finite_aggregates``.

    Returns
    -------
    list of int
        Indices into the candidates.

    Examples
    --------
    >>> import numpy as np
    >>> from pyfrustrate.ground_states import ever_best
    >>> class Lines:  # best at g = 0: index 1; then 0 from g = 1 (1 - 4 g = 0 - 3 g); 2 never
    ...     deformation, bonds = np.array([1.0, 0.0, 5.0]), np.array([4, 3, 4])
    >>> ever_best(Lines())
    [1, 0]
    """
    deformation, bonds = np.asarray(candidates.deformation, float), np.asarray(candidates.bonds, int)
    order = np.lexsort((-bonds, deformation))  # lowest at g = 0, the most bonds among equals
    chosen, g = [int(order[0])], 0.0
    while True:
        now = chosen[-1]
        more = np.flatnonzero(bonds > bonds[now])  # only a line with more bonds can cross below it
        if not len(more):
            return chosen
        crossing = (deformation[more] - deformation[now]) / (bonds[more] - bonds[now])
        crossing = np.maximum(crossing, g)
        first = more[np.lexsort((-bonds[more], crossing))[0]]
        chosen.append(int(first))
        g = float(max(crossing.min(), g))


def contact_bonds(a, b) -> int:
    """Bound pairs of sides between two sets of sites (unwrapped, edge neighbours).

    Parameters
    ----------
    a, b : array_like of int, shape (k, 2)
        Sites of two aggregates.

    Returns
    -------
    int
    """
    other = {tuple(s) for s in np.asarray(b, int).tolist()}
    return sum((i + x, j + y) in other for i, j in np.asarray(a, int).tolist() for x, y in _NEIGHBOURS)


def neck_shift(shape, direction) -> np.ndarray | None:
    """The smallest shift of an aggregate along a lattice ``direction`` at which its copy does not
    overlap it and touches it (at least one bond): where two copies meet at a neck.

    Parameters
    ----------
    shape : array_like of int, shape (k, 2)
        The aggregate's sites.
    direction : sequence of int
        A lattice direction, e.g. one of ``LATTICE_DIRECTIONS``.

    Returns
    -------
    ndarray of int, shape (2,), or None
        The shift, or None when the first shift without overlap leaves a gap (a shape with a notch
        along ``direction``).
    """
    shape, direction = np.asarray(shape, int), np.asarray(direction, int)
    own = {tuple(s) for s in shape.tolist()}
    reach = int(np.ptp(shape, axis=0).sum()) + 2  # beyond this shift no copy can overlap
    for step in range(1, reach + 1):
        copy = shape + step * direction
        if any(tuple(s) in own for s in copy.tolist()):
            continue
        return step * direction if contact_bonds(shape, copy) else None
    return None


#: How ``fused_copies`` arranges the copies: on the neck super-lattice as compactly as possible, or
#: in a straight chain along one neck direction (a tree of necks: no closed loop).
ARRANGEMENTS = ("compact", "chain")


def fused_copies(part, m: int, last=None, arrangement: str = "compact") -> list[np.ndarray] | None:
    """``m`` copies of an aggregate joined by necks: the ``fused{m}`` family's placements.

    ``"compact"``: copies on the super-lattice spanned by the neck shifts along a1 and a2
    (``neck_shift``; for a shape with the hexagon's symmetry, copies shifted by their difference
    meet at the neck along a2 - a1 too), at the ``m`` points of it nearest to the first copy (ties
    by angle from a1): a pair, a triangle, a rhombus, ..., a hexagon with its centre at 7.
    ``"chain"``: copies in a row along the lattice direction whose neck holds the fewest bonds
    (ties: the first of ``LATTICE_DIRECTIONS``), each touching only its neighbours. The two differ
    in their loops: a closed ring of necks (three copies in a triangle) ties the copies' corners to
    a triangle of fixed sides, which strains them, where a chain's necks, each free to bend, cost
    almost nothing.

    ``last`` replaces the last copy (the ``aggregates{m}`` family's remainder): it is centred on
    its point, then moved outwards along the lattice direction nearest to that point's until it
    overlaps no copy; it must touch one.

    Parameters
    ----------
    part : array_like of int, shape (k, 2)
        The aggregate's sites.
    m : int
        Copies, ``>= 1``.
    last : array_like of int, shape (k', 2), optional
        Another aggregate in place of the last copy.
    arrangement : {'compact', 'chain'}, optional
        ``ARRANGEMENTS``.

    Returns
    -------
    list of ndarray, or None
        Each copy's sites (unwrapped lattice coordinates), or None when a neck cannot be made (see
        ``neck_shift``), copies overlap, or ``last`` touches none.

    Raises
    ------
    ValueError
        For a bad ``m`` or ``arrangement``.

    Examples
    --------
    Three hexagonal disks of radius 2 meet pairwise at necks of one bond, or in a row:

    >>> from pyfrustrate import topology
    >>> from pyfrustrate.ground_states import contact_bonds, fused_copies
    >>> a, b, c = fused_copies(topology.hexagon_sites(2), 3)
    >>> contact_bonds(a, b), contact_bonds(b, c), contact_bonds(a, c)
    (1, 1, 1)
    >>> a, b, c = fused_copies(topology.hexagon_sites(2), 3, arrangement="chain")
    >>> contact_bonds(a, b), contact_bonds(b, c), contact_bonds(a, c)
    (1, 1, 0)
    """
    m = integer("m", m, 1)
    if arrangement not in ARRANGEMENTS:
        raise ValueError(f"arrangement must be one of {ARRANGEMENTS}, got {arrangement!r}")
    part = np.asarray(part, int)
    shifts = [neck_shift(part, d) for d in LATTICE_DIRECTIONS]
    if arrangement == "chain":
        usable = [t for t in shifts if t is not None]
        if not usable:
            return None
        step = min(usable, key=lambda t: contact_bonds(part, part + t))  # the first of the narrowest necks
        points = np.arange(m)[:, None] * step
    else:
        if shifts[0] is None or shifts[1] is None:
            return None
        # Super-lattice points by distance from the first copy, then angle from a1 (counter-clockwise).
        span = range(-m, m + 1)
        grid = np.array([(i, j) for i in span for j in span]) @ np.array(shifts[:2])
        xy = topology.site_positions(grid)
        angle = np.mod(np.arctan2(xy[:, 1], xy[:, 0]), 2 * np.pi)
        points = grid[np.lexsort((np.round(angle, 9), np.round(np.hypot(*xy.T), 9)))[:m]]
    copies = [part + p for p in points]
    if last is not None and m >= 2:
        copies[-1] = _placed_outwards(np.asarray(last, int), part, points[-1], copies[:-1])
        if copies[-1] is None:
            return None
    sites = np.concatenate(copies)
    if len({tuple(s) for s in sites.tolist()}) < len(sites):
        return None
    return copies


def _placed_outwards(shape, part, point, others) -> np.ndarray | None:
    """``shape`` centred where ``part + point`` is, moved outwards (along the lattice direction
    nearest to ``point``'s) to the first position overlapping none of ``others``; None unless it
    then touches one of them."""
    centre = np.rint(part.mean(axis=0) - shape.mean(axis=0)).astype(int) + point
    directions = np.array(LATTICE_DIRECTIONS + tuple((-a, -b) for a, b in LATTICE_DIRECTIONS))
    outwards = directions[np.argmax(topology.site_positions(directions) @ topology.site_positions([point])[0])]
    taken = {tuple(s) for o in others for s in o.tolist()}
    for step in range(int(np.ptp(shape, axis=0).sum()) + 2):
        placed = shape + centre + step * outwards
        if not any(tuple(s) in taken for s in placed.tolist()):
            return placed if any(contact_bonds(placed, o) for o in others) else None
    return None


def aggregate_counts(n: int, max_aggregates: int | None = None) -> list[int]:
    """The numbers ``m`` of separate aggregates ``box_candidates`` tries for ``n`` particles.

    Every ``m`` from 2 to ``max_aggregates`` if given, else every ``m`` to 16 and then counts
    1.25x apart up to ``n // 7`` (aggregates of at least seven particles, one ring around a
    particle).

    Parameters
    ----------
    n : int
        Particles.
    max_aggregates : int, optional
        Largest count.

    Returns
    -------
    list of int

    Raises
    ------
    ValueError
        For a bad ``max_aggregates``.

    Examples
    --------
    >>> from pyfrustrate import ground_states
    >>> ground_states.aggregate_counts(40), ground_states.aggregate_counts(40, max_aggregates=3)
    ([2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16], [2, 3])
    """
    if max_aggregates is not None:
        return list(range(2, integer("max_aggregates", max_aggregates, 1) + 1))
    counts, m = list(range(2, min(16, n // 2) + 1)), 16.0
    while round(m * 1.25) <= n // 7:
        m *= 1.25
        if round(m) > counts[-1]:
            counts.append(round(m))
    return counts


def box_candidates(particle, n: int, box: int, max_aggregates: int | None = None,
                   hole_fraction: float = ansatz.FINITE_HOLE_FRACTION, method: str = "lbfgs",
                   tol: float = 1e-5, single: ansatz.FiniteAggregates | None = None) -> BoxCandidates:
    """Candidate ground states of ``n`` particles in a periodic ``box x box`` lattice (module
    docstring), relaxed with ``method`` to ``tol``. Hexagon tiling.

    Parameters
    ----------
    particle : Hexagon or RandomHexagon
        A particle of the hexagon tiling.
    n : int
        Particles, ``>= 1`` and fewer than ``box**2``.
    box : int
        Box side, lattice steps, ``>= 2``.
    max_aggregates : int, optional
        Limit the separate and the fused aggregates to counts 2 .. max_aggregates (default:
        ``aggregate_counts(n)``).
    hole_fraction : float, optional
        Largest hole of the single aggregates and of the parts, over their particles
        (``ansatz.finite_hole_sizes``; 0: solid shapes only). The single aggregate has every shape
        with every hole; the parts have holes in their compact shapes only.
    method : {'auto', 'newton', 'lbfgs', 'linear'}, optional
        As for ``relax``.
    tol : float, optional
        As for ``relax``.
    single : FiniteAggregates, optional
        The single aggregates of ``n`` particles, already relaxed (a finite-size prediction's
        own ``ansatz.finite_aggregates``): used as they are instead of being relaxed again, so
        ``hole_fraction`` then applies to the parts only.

    Returns
    -------
    BoxCandidates

    Raises
    ------
    TypeError
        If ``particle`` is not a particle model.
    ValueError
        For a triangle-tiling particle, bad ``n`` or ``box``, a box too large for memory, or
        ``single`` of another ``n``.

    Examples
    --------
    >>> from pyfrustrate import Hexagon, ansatz, ground_states
    >>> p = Hexagon.from_continuum(ell=2.0, nu=0.9)
    >>> c = ground_states.box_candidates(p, 12, 8, max_aggregates=2)
    >>> g = ansatz.binding_energy_of(p, 2.0, 0.9, Gamma=0.5)
    >>> str(c.best_family(g)), bool(c.converged.all())
    ('single', True)
    """
    if _checks.particle("particle", particle).tiling != "hexagon":
        raise ValueError("particle: box ground states are built for hexagon tilings only")
    n, box = integer("n", n, 1), integer("box", box, 2)
    # Occupancy grids and placement offsets per box cell (a list of tuples, the largest), the
    # topologies of n particles and the grids their shapes are cut from.
    _checks.affordable(f"box_candidates(n={n}, box={box})", box * box * 64 + n * (
        topology.TOPOLOGY_BYTES_PER_PARTICLE + 16 * topology.GRID_BYTES_PER_CELL["stadium_sites"]))
    if n >= box * box:
        raise ValueError(f"n must be smaller than the box's {box * box} sites, got {n}")
    counts = aggregate_counts(n, max_aggregates)  # checks max_aggregates before any relaxation
    rows = []  # (family, deformation, bonds, sites, converged)
    kwargs: dict[str, Any] = {"x0": "linear"} if method == "lbfgs" else {}

    if single is None:
        single = ansatz.finite_aggregates(particle, n, holes=ansatz.finite_hole_sizes(n, fraction=hole_fraction),
                                          method=method, tol=tol)
    elif single.n != n:
        raise ValueError(f"single: aggregates of {single.n} particles, not n = {n}")
    for k, sites in enumerate(single.sites):
        if not _touches_itself(sites, box):
            rows.append(("single", single.deformation[k], single.bonds[k], _in_box(sites, box), single.converged[k]))

    full, rest = divmod(n, box)
    if full >= 1:
        sites = [(i, j) for j in range(full) for i in range(box)] + [(i, full) for i in range(rest)]
        sites = np.array(sites)
        if full + (rest > 0) < box:  # a slab that fills the box would wrap both ways
            fibre = topology.Topology("fiber", sites, "fiber", np.array([(box, 0), (0, 0)]), curved=False,
                                      label=f"wrapping fibre of {n} in {box}")
            r = relax(particle, fibre, method=method, tol=tol, **kwargs)
            rows.append(("wrapping_fiber", r.energy, r.n_bonds, sites, r.converged))

    for m in counts:
        q = n // m
        if q < 2:
            break
        # The last part (q plus the remainder) has the same holes as the others, so that each shape
        # of q has its counterpart (_same_shape).
        holes = ansatz.finite_hole_sizes(q, fraction=hole_fraction)
        parts = {q: _part_shapes(particle, q, holes, method, tol)}
        last = q + n - m * q
        parts[last] = parts[q] if last == q else _part_shapes(particle, last, holes, method, tol)
        counterpart = _same_shape(parts[q], parts[last])
        for k, j in counterpart.items():
            shapes = [parts[q].sites[k]] * (m - 1) + [parts[last].sites[j]]
            if any(_touches_itself(shape, box) for shape in shapes[-2:]):
                continue
            sites = _pack(shapes, box)
            if sites is None:
                continue
            rows.append((f"aggregates{m}", (m - 1) * parts[q].deformation[k] + parts[last].deformation[j],
                         (m - 1) * parts[q].bonds[k] + parts[last].bonds[j], sites,
                         parts[q].converged[k] and parts[last].converged[j]))
        # The same parts joined by necks, relaxed as one cluster: the necks' strain is the whole's,
        # not a sum over the parts.
        placed = set()
        for k in ever_best(parts[q]):
            if k not in counterpart:
                continue
            for arrangement in ARRANGEMENTS:
                copies = fused_copies(parts[q].sites[k], m, last=parts[last].sites[counterpart[k]],
                                      arrangement=arrangement)
                if copies is None:
                    continue
                sites = np.concatenate(copies)
                key = frozenset(map(tuple, sites.tolist()))  # a chain of two is the compact pair
                if key in placed or _touches_itself(sites, box):
                    continue
                placed.add(key)
                r = relax(particle, topology.cluster(sites, label=f"{m} fused aggregates of {q}, {arrangement}"),
                          method=method, tol=tol, **kwargs)
                rows.append((f"fused{m}", r.energy, r.n_bonds, _in_box(sites, box), r.converged))

    gas = _gas_sites(n, box)
    if gas is not None:
        rows.append(("gas", 0.0, 0, gas, True))

    family, deformation, bonds, sites, converged = zip(*rows)
    return BoxCandidates(n, box, np.array(family), np.array(deformation, float), np.array(bonds, int),
                         tuple(np.asarray(s, int) for s in sites), np.array(converged, bool))


def _part_shapes(particle, q: int, holes, method: str, tol: float) -> ansatz.FiniteAggregates:
    """The shapes of one of several aggregates of ``q`` particles: every solid shape of
    ``ansatz.finite_aggregates``, and the compact ones (segment 0) with each hole of ``holes``.

    Rings are compact: every ring that beat the solid shapes of 400 and 800 particles at nu = 0.9
    was a hexagonal one. Holes in every elongated shape would multiply the parts' relaxations,
    most of the box's cost, by the number of holes.
    """
    solid = ansatz.finite_aggregates(particle, q, holes=(0,), method=method, tol=tol)
    if len(holes) == 1:
        return solid
    return solid + ansatz.finite_aggregates(particle, q, segments=[0.0], holes=holes[1:], method=method, tol=tol)


def _same_shape(parts, other) -> dict:
    """Index in ``other`` of each shape of ``parts`` cut the same way (round or faceted, segment
    in units of sqrt(n), hole): a shape that fell into pieces in one of them has none."""
    def keys(shapes):
        return [(bool(f), round(float(s) / np.sqrt(shapes.n), 9), int(h))
                for f, s, h in zip(shapes.faceted, shapes.segment, shapes.hole)]
    index = {key: j for j, key in enumerate(keys(other))}
    return {k: index[key] for k, key in enumerate(keys(parts)) if key in index}


def box_bonds(sites, box) -> int:
    """Bound pairs of sides among particles on ``sites`` of the periodic ``box``.

    Edge neighbours, each pair once: what a run's energy counts ``-g`` for, to compare with a
    candidate's.

    Parameters
    ----------
    sites : array_like of int, shape (n, 2)
        Occupied sites (wrapped into the box).
    box : int
        Box side.

    Returns
    -------
    int
    """
    occupied = {tuple(s) for s in _in_box(sites, box).tolist()}
    return sum(((i + a) % box, (j + b) % box) in occupied for i, j in occupied for a, b in _NEIGHBOURS) // 2


def structure(sites, box, major: float = 0.1) -> str:
    """The structure of a box configuration in the terms of ``box_candidates``' families.

    From its clusters alone (no anisotropy threshold): ``"gas"`` (no cluster of 3 or more),
    ``"bulk"`` (a cluster wraps the box both ways), ``"wrapping_fiber"`` (one way), ``"single"``
    (one cluster holds all but ``major`` of the particles), else ``"aggregates{m}"`` with ``m``
    the clusters of at least 3 particles and at least ``major`` times the largest one's
    (``"aggregates1"``: one such cluster and much smaller ones). Relative to the largest cluster,
    not to ``n``, since a large box's ground state can hold more than 1 / ``major`` aggregates.

    Parameters
    ----------
    sites : array_like of int, shape (n, 2)
        Occupied sites.
    box : int
        Box side.
    major : float, optional
        Fraction of the largest cluster below which a cluster does not count.

    Returns
    -------
    str
    """
    from .montecarlo import clusters
    parts = clusters(np.asarray(sites, int), int(box))
    n = sum(len(c) for c, _ in parts)
    sizes = np.array([len(c) for c, _ in parts])
    ranks = np.array([rank for _, rank in parts])
    if sizes.max() < 3:
        return "gas"
    if (ranks == 2).any():
        return "bulk"
    if (ranks == 1).any():
        return "wrapping_fiber"
    if sizes.max() >= (1 - major) * n:
        return "single"
    return f"aggregates{int((sizes >= max(3, major * sizes.max())).sum())}"


def aggregate_count(found: str) -> int:
    """Aggregates of a ``structure`` (or family) name: 0 for ``gas``, ``m`` for ``aggregates{m}``,
    1 otherwise (``single``, ``wrapping_fiber``, ``bulk``, and ``fused{m}``: its ``m`` parts are
    one cluster, whose ``structure`` is ``single``).

    Parameters
    ----------
    found : str
        As ``structure`` returns it, or a ``BoxCandidates.family``.

    Returns
    -------
    int

    Examples
    --------
    >>> from pyfrustrate.ground_states import aggregate_count
    >>> aggregate_count("aggregates4"), aggregate_count("fused4"), aggregate_count("single"), aggregate_count("gas")
    (4, 1, 1, 0)
    """
    if found == "gas":
        return 0
    if found.startswith("aggregates"):
        return int(found[len("aggregates"):])
    return 1


def family_structure(family: str) -> str:
    """The ``structure`` a candidate of ``family`` reads as from its clusters: ``single`` for
    ``fused{m}`` (its parts are one cluster), the family itself otherwise.

    Parameters
    ----------
    family : str
        A ``BoxCandidates.family``.

    Returns
    -------
    str

    Examples
    --------
    >>> from pyfrustrate.ground_states import family_structure
    >>> family_structure("fused4"), family_structure("aggregates4")
    ('single', 'aggregates4')
    """
    family = str(family)
    return "single" if family.startswith("fused") else family


def width_in_rows(sites, box) -> float:
    """Width of the largest cluster of a box configuration, in lattice rows: that of the strip with
    as many particles ``n`` and as many exposed sides ``E = 6 n - 2 b`` (``b`` bonds).

    A straight strip of ``W`` rows of ``L`` particles has ``E = 4 (L + W) - 2``, and one that wraps
    the box ``E = 4 L`` (no ends), so ``W`` is the smaller root of ``x^2 - (E + 2) x / 4 + n = 0``
    for a finite cluster and ``4 n / E`` for a wrapping one. Exact for straight strips; a fibre
    bent by 60 or 120 degrees keeps its arms' width to a quarter of a row, where the extent across
    the principal axis reads the bend's span (twice to seven times the width). Kinks and holes
    expose more sides, so a rough fibre reads a little narrower. A cluster too compact for any
    strip (a disk) reads as the square strip, ``(E + 2) / 8``.

    Parameters
    ----------
    sites : array_like of int, shape (n, 2)
        Occupied sites.
    box : int
        Box side.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        The largest cluster wraps the box both ways (bulk): it has no width.

    Examples
    --------
    >>> from pyfrustrate.ground_states import width_in_rows
    >>> round(width_in_rows([(i, j) for i in range(12) for j in range(3)], 12), 6)
    3.0
    >>> round(width_in_rows([(i, j) for i in range(20) for j in range(3)], 40), 6)
    3.0
    """
    from .montecarlo import clusters
    coords, rank = clusters(np.asarray(sites, int), int(box))[0]
    if rank == 2:
        raise ValueError("width_in_rows: the largest cluster wraps the box both ways (bulk); it has no width")
    n = len(coords)
    exposed = 6 * n - 2 * box_bonds(coords[:, :2], int(box))
    if rank == 1:
        return float(4 * n / exposed)
    half_sum = (exposed + 2) / 8  # (L + W) / 2
    return float(half_sum - np.sqrt(max(half_sum ** 2 - n, 0.0)))


def aggregate_kind(sites, box) -> str:
    """Kind of the largest cluster of a box configuration: ``"gas"`` (fewer than 3 particles),
    ``"bulk"`` (wraps the box both ways), ``"fused_disks"`` (finite, compact disks joined by
    necks: ``montecarlo.analysis.compact_lobes``), ``"fiber"`` (wraps one way, or finite and
    elongated: ``montecarlo.analysis.elongated``) or ``"disk"``: ``montecarlo.classify_aggregate`` without
    its open-network reading, so that a thin fibre (one or two rows, under two thirds of the bulk's
    bonds per particle) stays a fibre.

    Parameters
    ----------
    sites : array_like of int, shape (n, 2)
        Occupied sites.
    box : int
        Box side.

    Returns
    -------
    str

    Examples
    --------
    >>> from pyfrustrate.ground_states import aggregate_kind
    >>> aggregate_kind([(i, 0) for i in range(8)], 20), aggregate_kind([(0, 0), (1, 0), (0, 1)], 20)
    ('fiber', 'disk')
    """
    from .montecarlo.analysis import classify_aggregate
    return classify_aggregate(sites, box, open_networks=False)[0]


def structure_verdict(sites, box, candidates: BoxCandidates, g: float, energy: float, bulk_energy: float) -> dict:
    """A large run judged by structure against its box's predicted ground state (issue 33, item 3).

    The run and the prediction (the best of ``candidates`` at ``g``) are read by the same
    functions: the aggregate count (``aggregate_count`` of ``structure``), the kind of the
    largest aggregate (``aggregate_kind``: ``fiber`` or ``disk``, or another kind)
    and, for a fibre, its width in rows (``width_in_rows``), for disks fused by necks, the number
    of disks they join (``montecarlo.analysis.compact_lobes``). The run's **structure matches**
    when the count is exact, the kind the same and, for fibres, the width within
    ``WIDTH_TOLERANCE_ROWS``, for fused disks, the number of disks the same. The energy gap (bulk
    energies above the prediction) is reported and gated at
    ``max(EQUILIBRATED_GAP, GATE_BONDS * g / bulk_energy)``.

    The gate can be wider than the energy between candidates of different structure (one disk
    more or fewer than predicted, an elongated aggregate beside a predicted disk), which no
    energy criterion then tells apart; so the run's structure is also compared with every
    candidate within the gate of the prediction: ``structure_within_gate`` when it is one of
    theirs (by the same rule as ``structure_match``, which implies it).

    Parameters
    ----------
    sites : array_like of int, shape (n, 2)
        The run's final sites.
    box : int
        Box side (the candidates' box).
    candidates : BoxCandidates
        The box's candidate ground states.
    g : float
        Binding energy per bound pair of sides.
    energy : float
        The run's final energy.
    bulk_energy : float
        The bulk deformation energy per particle (> 0), the gap's unit.

    Returns
    -------
    dict
        ``count``, ``count_predicted``, ``kind``, ``kind_predicted``, ``width``,
        ``width_predicted`` (rows, where that side is a fibre, else None), ``lobes``,
        ``lobes_predicted`` (disks joined, where that side is fused disks, else None; sizes are
        judged only where both sides are of that kind), ``gap`` and ``gap_gate`` (bulk
        energies), ``count_ok``, ``kind_ok``, ``width_ok``, ``lobes_ok``, ``gap_ok``,
        ``structure_match``,
        ``candidates_within_gate`` (how many candidates lie within the gate of the prediction,
        the prediction included), ``structure_within_gate`` and ``below_prediction`` (the run's
        energy is below the prediction's by more than ``BELOW_PREDICTION_MARGIN`` bulk energies:
        the candidates, a finite family, miss a better state).

    Raises
    ------
    ValueError
        A box other than the candidates', or a non-positive ``bulk_energy``.
    """
    box = integer("box", box, 2)
    if box != candidates.box:
        raise ValueError(f"box: {box}, but the candidates were built for box {candidates.box}")
    bulk_energy = float(bulk_energy)
    if not bulk_energy > 0:
        raise ValueError(f"bulk_energy must be positive, got {bulk_energy!r}")
    best = int(candidates.best(g))
    own, predicted = aggregate_structure(sites, box), aggregate_structure(candidates.sites[best], box)
    (count, kind, size), (count_predicted, kind_predicted, size_predicted) = own, predicted
    fibres = kind == kind_predicted == "fiber"
    fused = kind == kind_predicted == "fused_disks"
    # Each side's size is reported for its own kind (a fibre's rows, fused disks' count), and
    # judged only where both are of that kind.
    width = size if kind == "fiber" else None
    width_predicted = size_predicted if kind_predicted == "fiber" else None
    lobes = size if kind == "fused_disks" else None
    lobes_predicted = size_predicted if kind_predicted == "fused_disks" else None
    gap = (float(energy) - float(candidates.best_energy(g))) / bulk_energy
    gate = max(EQUILIBRATED_GAP, GATE_BONDS * float(g) / bulk_energy)
    verdict = dict(count=count, count_predicted=count_predicted, kind=str(kind), kind_predicted=str(kind_predicted),
                   width=width, width_predicted=width_predicted, lobes=lobes, lobes_predicted=lobes_predicted,
                   gap=gap, gap_gate=gate, count_ok=count == count_predicted, kind_ok=kind == kind_predicted,
                   width_ok=not fibres or _same_width(width, width_predicted),
                   lobes_ok=not fused or lobes == lobes_predicted,
                   gap_ok=gap <= gate)
    verdict["structure_match"] = all(verdict[f"{part}_ok"] for part in ("count", "kind", "width", "lobes"))
    # The candidates the gate cannot tell from the prediction (the prediction among them): is the
    # run's structure one of theirs?
    excess = (candidates.total(g) - candidates.best_energy(g)) / bulk_energy
    within = np.flatnonzero(excess <= gate + 1e-12)
    verdict["candidates_within_gate"] = int(len(within))
    verdict["structure_within_gate"] = any(_same_structure(own, aggregate_structure(candidates.sites[k], box))
                                           for k in within)
    # Below every candidate: the run found a state the prediction's finite family misses, and
    # then the prediction, not the run, is what fails the structure.
    verdict["below_prediction"] = gap < -BELOW_PREDICTION_MARGIN
    return verdict


def aggregate_structure(sites, box) -> tuple[int, str, float | int | None]:
    """What ``structure_verdict`` compares, for one box configuration: how many aggregates, the
    kind of the largest and its size.

    Parameters
    ----------
    sites : array_like of int, shape (n, 2)
        Occupied sites.
    box : int
        Box side.

    Returns
    -------
    count : int
        Aggregates (``aggregate_count`` of ``structure``).
    kind : str
        Kind of the largest cluster (``aggregate_kind``).
    size : float, int or None
        For a fibre its width in rows (``width_in_rows``); for disks fused by necks the number of
        disks they join (``montecarlo.analysis.compact_lobes``); else None.

    Examples
    --------
    >>> from pyfrustrate.ground_states import aggregate_structure
    >>> strip = [(i, r) for r in range(3) for i in range(30)]  # 3 rows wrapping a 30-box
    >>> count, kind, rows = aggregate_structure(strip, 30)
    >>> count, kind, round(rows, 6)
    (1, 'fiber', 3.0)
    """
    from .montecarlo.analysis import clusters, compact_lobes
    kind = str(aggregate_kind(sites, box))
    size = None
    if kind == "fiber":
        size = width_in_rows(sites, box)
    elif kind == "fused_disks":
        size = len(compact_lobes(clusters(np.asarray(sites, int), int(box))[0][0]))
    return aggregate_count(structure(sites, box)), kind, size


def _same_width(width, other) -> bool:
    return abs(width - other) <= WIDTH_TOLERANCE_ROWS + 1e-9


def _same_structure(a, b) -> bool:
    """Same count and kind and, for fibres, widths within ``WIDTH_TOLERANCE_ROWS``, for fused
    disks, as many disks."""
    return a[:2] == b[:2] and (_same_width(a[2], b[2]) if a[1] == "fiber" else a[1] != "fused_disks" or a[2] == b[2])
