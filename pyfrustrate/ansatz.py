"""Comparison of pre-made aggregate structures (main text "Comparison of pre-made discrete
aggregate structures", Figs. 3b, 4 and S1).

For one particle, every candidate topology of the catalogue (Fig. 4a) is relaxed once; its
deformation energy per particle and bonds per particle are all that the diagrams need, since the
total energy per particle, ``e_def - g * bonds / N`` (each bound pair of sides gives ``-g``), is
linear in the binding energy ``g``. For each line tension the lowest total energy wins.

Line tension convention (settled by measuring the discrete edge energy, see
``edge_line_tension``): ``gamma = g``, the binding cost per unit length of an edge along a lattice
vector (2 bonds broken per unit length, shared by two edges); ``Gamma`` then follows from
``continuum.mapping``.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from . import _checks, _kernel, continuum, topology
from .relaxation import relax

#: Aggregate kind of each candidate family, for the diagrams' colour code.
FAMILY_PHASE = {
    "single": "disk", "disk": "disk", "fiber_cut0": "fiber", "fiber_cut1": "fiber", "fiber_cut2": "fiber",
    "fiber_cut0_straight": "fiber", "bulk": "bulk", "holes_honeycomb": "bulk_with_holes",
    "holes_kagome": "bulk_with_holes", "holes_sqrt7": "bulk_with_holes",
}
PHASES = ("bulk_with_holes", "disk", "fiber", "bulk")


def winning_phase(family: str, g: float) -> str:
    """Phase of a winning candidate.

    ``FAMILY_PHASE``, except that a single particle winning at ``g > 0`` means no aggregate pays:
    a gas of monomers (triangles at very small Gamma, where a bound pair already costs
    deformation; at ``g = 0`` every candidate of zero deformation ties).

    Parameters
    ----------
    family : str
        A key of ``FAMILY_PHASE``.
    g : float
        Binding energy per bound pair of sides.

    Returns
    -------
    str
        One of ``PHASES``, or ``'gas'``.
    """
    return "gas" if family == "single" and g > 0 else FAMILY_PHASE[family]


@dataclass(frozen=True)
class Candidate:
    """One pre-made aggregate of the catalogue.

    Parameters
    ----------
    family : str
        Its family (a key of ``FAMILY_PHASE``).
    size : int
        Disk radius ``R`` or fibre width in **lattice lines** (``topology.fiber``); 0 otherwise.
        The continuum size is ``topology.size``.
    topology : Topology
        The aggregate.
    """

    family: str
    size: int
    topology: topology.Topology


def catalogue(max_radius: int = 25, max_width: int = 35, cuts=(0, 1, 2), straight_fibers: bool = False,
              hole_patterns=None, tiling: str = "hexagon") -> list[Candidate]:
    """The pre-made candidates of Fig. 4a (hexagons) or S6e (triangles).

    The single particle (a disk of one), compact disks ``R = 1..max_radius``, fibres of each cut
    from the narrowest connected one to ``max_width`` lattice lines (free to curve), optionally the
    straight cut-0 fibres, the bulk and bulks with holes.

    Parameters
    ----------
    max_radius : int, optional
        Largest disk radius, in lattice steps.
    max_width : int, optional
        Widest fibre, in lattice lines (``topology.fiber``; continuum ``W`` is the topology's
        ``size``).
    cuts : iterable of int, optional
        Fibre cuts to include.
    straight_fibers : bool, optional
        Add straight (``curved=False``) cut-0 fibres.
    hole_patterns : iterable of str, optional
        Bulks with holes to add (default: every pattern of the tiling, ``topology.hole_patterns``).
    tiling : {'hexagon', 'triangle'}, optional
        The tiling.

    Returns
    -------
    list of Candidate

    Raises
    ------
    ValueError
        For bad sizes, or sizes whose candidates would not fit in memory (the message says how
        much they would need).

    Examples
    --------
    >>> from pyfrustrate import ansatz
    >>> candidates = ansatz.catalogue(max_radius=4, max_width=8)
    >>> len(candidates), candidates[0].family, candidates[-1].family
    (30, 'single', 'holes_sqrt7')
    """
    max_radius = _checks.integer("max_radius", max_radius, 0)
    max_width = _checks.integer("max_width", max_width, 0)
    # Every candidate is kept. The disks' particles sum to (max_radius + 1)^3 on the hexagon
    # tiling (the centred hexagonal numbers 1 + 3 R (R + 1) sum to cubes), to
    # sum 6 R^2 = M (M + 1) (2 M + 1) on the triangle one; a fibre cell holds at most 2 width + 1.
    m = max_radius
    disks = (m + 1) ** 3 if tiling == "hexagon" else m * (m + 1) * (2 * m + 1)
    fibers = len(cuts) * (max_width + 1) ** 2
    _checks.affordable(f"catalogue(max_radius={max_radius}, max_width={max_width})",
                       (disks + fibers) * topology.TOPOLOGY_BYTES_PER_PARTICLE
                       + (2 * max_width + 1) * topology.FIBER_BYTES_PER_PARTICLE)
    if hole_patterns is None:
        hole_patterns = tuple(topology.hole_patterns(tiling))
    out = [Candidate("single", 0, topology.disk(0, tiling=tiling))]
    out += [Candidate("disk", R, topology.disk(R, tiling=tiling)) for R in range(1, max_radius + 1)]
    for cut in cuts:
        out += [Candidate(f"fiber_cut{cut}", w, topology.fiber(w, cut, tiling=tiling))
                for w in range(topology.min_fiber_width(cut, tiling), max_width + 1)]
    if straight_fibers:
        out += [Candidate("fiber_cut0_straight", w, topology.fiber(w, 0, curved=False, tiling=tiling))
                for w in range(1, max_width + 1)]
    out.append(Candidate("bulk", 0, topology.bulk(tiling)))
    out += [Candidate(f"holes_{p}", 0, topology.bulk_with_holes(p, tiling=tiling)) for p in hole_patterns]
    return out


@dataclass(frozen=True)
class CatalogueEnergies:
    """Relaxed energies of a catalogue for one particle (arrays of length n_candidates), from
    ``relax_catalogue``.

    Energies are **deformation** energies; the total at binding energy ``g`` per bound pair of
    sides is ``deformation - g * bonds`` per particle (``total``).

    Attributes
    ----------
    family : ndarray of str
        Candidate families.
    size : ndarray of int
        Disk radius or fibre width in lattice lines (0 otherwise).
    length : ndarray of float
        Continuum size: ``W`` or ``R`` in lattice spacings (``Topology.size``), inf for bulks.
    n_particles : ndarray of int
        Particles (per cell when periodic).
    deformation : ndarray of float
        Deformation energy per particle.
    bonds : ndarray of float
        Bound pairs of sides per particle.
    converged : ndarray of bool
        The minimiser's verdict per candidate.
    iterations : ndarray of int
        Energy and gradient evaluations per candidate.
    seconds : ndarray of float
        Wall time per candidate.
    """

    family: np.ndarray
    size: np.ndarray
    length: np.ndarray
    n_particles: np.ndarray
    deformation: np.ndarray
    bonds: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray
    seconds: np.ndarray

    def as_arrays(self) -> dict:
        """The fields as a dict of arrays (for ``io.save_npz``; inverse of ``from_arrays``).

        Returns
        -------
        dict
        """
        return {name: getattr(self, name) for name in self.__dataclass_fields__}

    @classmethod
    def from_arrays(cls, arrays: dict) -> "CatalogueEnergies":
        """Rebuild from a mapping with one entry per field (a saved ``.npz``).

        Parameters
        ----------
        arrays : mapping
            As written by ``as_arrays``.

        Returns
        -------
        CatalogueEnergies
        """
        return cls(**{name: np.asarray(arrays[name]) for name in cls.__dataclass_fields__})

    def total(self, g) -> np.ndarray:
        """Total energy per particle, ``deformation - g * bonds``.

        Parameters
        ----------
        g : array_like
            Binding energies per bound pair of sides.

        Returns
        -------
        ndarray, shape ``(n_candidates, *np.shape(g))``
        """
        g = np.asarray(g, float)
        return self.deformation.reshape((-1,) + (1,) * g.ndim) - np.multiply.outer(self.bonds, g)

    def winners(self, g, families=None) -> np.ndarray:
        """Index of the lowest total energy per particle at each binding energy ``g``.

        Ties go to the earlier candidate.

        Parameters
        ----------
        g : array_like
            Binding energies per bound pair of sides (``binding_energy_of`` from ``Gamma``).
        families : iterable of str, optional
            Compete among these families only (e.g. the fibres, for ``W*``).

        Returns
        -------
        ndarray of int, shape of ``g``

        Raises
        ------
        ValueError
            If none of ``families`` is in the catalogue.

        Examples
        --------
        ``W*`` at ``ell = 2, nu = 0.9, Gamma = 0.5`` from a small catalogue, against the continuum:

        >>> from pyfrustrate import Hexagon, ansatz, continuum
        >>> p = Hexagon.from_continuum(ell=2.0, nu=0.9)
        >>> energies = ansatz.relax_catalogue(p, ansatz.catalogue(max_radius=4, max_width=8))
        >>> best = energies.winners(ansatz.binding_energy_of(p, 2.0, 0.9, Gamma=0.5))
        >>> str(energies.family[best]), int(energies.size[best]), round(float(energies.length[best]) / 2.0, 2)
        ('fiber_cut0', 6, 2.6)
        >>> round(float(continuum.optimal_width(0.9, 0.5)), 2)  # W*/ell
        2.51
        """
        total = self.total(g)
        if families is not None:
            allowed = np.isin(self.family, list(families))
            if not allowed.any():
                raise ValueError(f"families: none of {families} is in the catalogue")
            total = np.where(allowed.reshape((-1,) + (1,) * np.ndim(g)), total, np.inf)
        return np.argmin(total, axis=0)


def relax_catalogue(particle, candidates, method: str = "auto", tol: float = 1e-5, progress: bool = False,
                    description: str = "catalogue") -> CatalogueEnergies:
    """Relax every candidate once.

    ``method='auto'`` (Newton) and ``'lbfgs'`` (started from the linear solution) are exact to the
    tolerance; ``'linear'`` keeps the linear solution (error O(eps^2) relative). On the
    paper-scale catalogue at ell = 5 Newton took a fifth of L-BFGS's time (benchmarks/README.md).

    Parameters
    ----------
    particle : Hexagon, Triangle or RandomHexagon
        The particle model.
    candidates : list of Candidate
        From ``catalogue``.
    method : {'auto', 'newton', 'lbfgs', 'linear'}, optional
        As for ``relax``.
    tol : float, optional
        As for ``relax``.
    progress : bool, optional
        Show a progress bar (tqdm).
    description : str, optional
        The progress bar's label.

    Returns
    -------
    CatalogueEnergies
        Deformation energies and bonds per particle; the binding enters through ``winners(g)``.

    Raises
    ------
    TypeError
        If ``particle`` is not a particle model.

    Examples
    --------
    >>> from pyfrustrate import Hexagon, ansatz
    >>> p = Hexagon.from_continuum(ell=2.0, nu=0.9)
    >>> energies = ansatz.relax_catalogue(p, ansatz.catalogue(max_radius=2, max_width=4))
    >>> bool(energies.converged.all()), energies.family[:3].tolist()
    (True, ['single', 'disk', 'disk'])
    """
    _checks.particle("particle", particle)
    rows = []
    iterator = candidates
    if progress:
        from tqdm.auto import tqdm

        iterator = tqdm(candidates, desc=description, unit="aggregate", mininterval=1.0)
    for c in iterator:
        start = time.perf_counter()
        kwargs: dict[str, Any] = {"x0": "linear"} if method == "lbfgs" else {}
        r = relax(particle, c.topology, method=method, tol=tol, **kwargs)
        rows.append((c.family, c.size, c.topology.size, r.n_particles, r.energy_per_particle,
                     r.n_bonds / r.n_particles, r.converged, r.iterations, time.perf_counter() - start))
    cols = list(zip(*rows))
    return CatalogueEnergies(np.array(cols[0]), np.array(cols[1]), np.array(cols[2], float), np.array(cols[3]),
                             np.array(cols[4], float), np.array(cols[5], float), np.array(cols[6], bool),
                             np.array(cols[7]), np.array(cols[8], float))


def binding_energy_of(particle, ell: float, nu: float, Gamma) -> np.ndarray:
    """Binding energy ``g`` per bound pair of sides for line tension ``Gamma``, at the particle's own
    ``(k, eps)`` and tiling, in the measured convention (``gamma = g``; ``continuum``).

    Parameters
    ----------
    particle : Hexagon or Triangle
        The particle model (its ``k``, ``eps`` and ``tiling`` are used).
    ell : float
        Boundary-layer length, in lattice spacings.
    nu : float
        2D Poisson ratio.
    Gamma : array_like
        Dimensionless line tension(s).

    Returns
    -------
    ndarray
        ``g``, shape of ``Gamma``.

    Raises
    ------
    TypeError
        If ``particle`` is not a particle model.
    ValueError
        For parameters out of range (named).
    """
    _checks.particle("particle", particle)
    return np.asarray(continuum.particle_parameters(ell, nu, Gamma, k=particle.k, eps=particle.eps,
                                                    tiling=particle.tiling).g, float)


def edge_line_tension(cut: int, tiling: str = "hexagon") -> float:
    """Binding cost per unit length of one straight edge of a cut-``cut`` fibre, in units of ``g``.

    Counted on the discrete lattice: bonds broken per period (the bulk's bonds per particle, from
    the kernel's tiling, times the particles, less the fibre's bonds), over the two edges and the
    period length. Hexagons: cut 0 (along a lattice vector) 1, cut 1 2/sqrt(3), cut 2 3/sqrt(7).
    Triangles: cut 0 1/2, cut 1 3/4 (the mean of its flat edge, 1/2, and sawtooth one, 1), cut 2
    1/sqrt(3).

    Parameters
    ----------
    cut : {0, 1, 2}
        The fibre cut.
    tiling : {'hexagon', 'triangle'}, optional
        The tiling.

    Returns
    -------
    float

    Examples
    --------
    >>> from pyfrustrate import ansatz
    >>> float(ansatz.edge_line_tension(0)), round(float(ansatz.edge_line_tension(1)), 4)  # 1 and 2/sqrt(3)
    (1.0, 1.1547)
    """
    width = 8
    t = topology.fiber(width, cut, curved=False, tiling=tiling)
    period = np.linalg.norm(topology.cell_positions([topology.fiber_axis(cut, tiling)])[0])
    bulk_bonds = topology.tiling_facts(tiling)["bulk_bonds_per_particle"] * t.n_particles
    return (bulk_bonds - t.n_bonds) / (2 * period)


#: Default segment lengths of ``finite_aggregates``, in units of sqrt(n): from a near-circular
#: aggregate (0) to a strip about ten times longer than wide (4).
FINITE_SEGMENTS = (0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0, 2.5, 3.0, 4.0)

#: Largest hole of ``finite_hole_sizes``, as a fraction of the aggregate's particles: the best
#: rings found held up to about 0.4 n (400 particles at ell = 2.5, nu = 0.9, Gamma = 0.4, whose rim
#: is a fibre of optimal width).
FINITE_HOLE_FRACTION = 0.5
#: Most holes of ``finite_hole_sizes`` besides none: every complete shape up to 800 particles,
#: evenly spaced radii beyond.
FINITE_HOLE_COUNT = 12


def finite_hole_sizes(n: int, tiling: str = "hexagon", fraction: float = FINITE_HOLE_FRACTION) -> tuple[int, ...]:
    """Default holes of ``finite_aggregates``: none, then complete compact shapes of the tiling up
    to ``fraction * n`` sites, at most ``FINITE_HOLE_COUNT`` of them (evenly spaced radii).

    The complete shapes (hexagons of ``1 + 3 r (r + 1)`` hexagons, of ``6 r^2`` triangles) leave
    the faceted compact aggregate a ring bounded by close-packed rows on both sides, the most
    bonds a hole of that size allows.

    Parameters
    ----------
    n : int
        Particles per aggregate, ``>= 1``.
    tiling : {'hexagon', 'triangle'}, optional
        The tiling.
    fraction : float, optional
        Largest hole over ``n``, in ``[0, 1]`` (0: solid shapes only, the cheapest prediction).

    Returns
    -------
    tuple of int
        Increasing, starting at 0.

    Examples
    --------
    >>> from pyfrustrate import ansatz
    >>> ansatz.finite_hole_sizes(200), ansatz.finite_hole_sizes(200, "triangle")
    ((0, 1, 7, 19, 37, 61, 91), (0, 6, 24, 54, 96))
    """
    n = _checks.integer("n", n, 1)
    largest = _checks.probability("fraction", fraction) * n
    if topology.tiling_facts(tiling)["sublattices"] > 1:
        def size(r):
            return 6 * r * r
        first, last = 1, int(np.sqrt(largest / 6)) + 1
    else:
        def size(r):
            return 1 + 3 * r * (r + 1)
        first, last = 0, int(np.sqrt(largest / 3)) + 1
    while last >= first and size(last) > largest:  # the square roots' rounding
        last -= 1
    if last < first:
        return (0,)
    radii = np.unique(np.round(np.linspace(first, last, min(FINITE_HOLE_COUNT, last - first + 1))).astype(int))
    return (0, *(size(int(r)) for r in radii))


class EnergiesLinearInG:
    """Candidates whose energies are ``deformation - g * bonds``: the lowest at each binding energy.

    Subclasses provide the arrays, one entry per candidate.

    Attributes
    ----------
    deformation : ndarray
        Deformation energy of each candidate.
    bonds : ndarray
        Bound pairs of sides of each candidate (energy ``-g`` each).
    """

    deformation: np.ndarray  # provided by the subclasses (dataclass fields there)
    bonds: np.ndarray

    def total(self, g) -> np.ndarray:
        """Total energy ``deformation - g * bonds`` of each candidate.

        Parameters
        ----------
        g : array_like
            Binding energies per bound pair of sides.

        Returns
        -------
        ndarray, shape ``(n, *np.shape(g))``
        """
        g = np.asarray(g, float)
        return self.deformation.reshape((-1,) + (1,) * g.ndim) - np.multiply.outer(self.bonds, g)

    def best(self, g) -> np.ndarray:
        """Index of the lowest-energy candidate at each binding energy ``g``.

        Parameters
        ----------
        g : array_like
            Binding energies per bound pair of sides.

        Returns
        -------
        ndarray of int, shape of ``g``
        """
        return np.argmin(self.total(g), axis=0)

    def best_energy(self, g) -> np.ndarray:
        """Total energy of the best candidate at each binding energy ``g``.

        Parameters
        ----------
        g : array_like
            Binding energies per bound pair of sides.

        Returns
        -------
        ndarray, shape of ``g``
        """
        return np.min(self.total(g), axis=0)


@dataclass(frozen=True)
class FiniteAggregates(EnergiesLinearInG):
    """Relaxed single aggregates of exactly ``n`` particles, from compact to elongated, round and
    faceted, solid and with a hole at their core (``topology.stadium_sites``): what a Monte Carlo
    box of ``n`` particles can form.

    The infinite-system catalogue says which structure wins per particle; at the particle numbers
    of a simulation a fibre of optimal width ``W*`` may not fit, and the best single aggregate is
    then more compact, or a ring: a hole relieves the stress frustration builds towards the
    centre, as a fibre's finite width does. Splitting into several aggregates is not considered
    (``ground_states.box_candidates`` does).

    Attributes
    ----------
    n : int
        Particles per aggregate.
    segment : ndarray
        Core segment length of each shape, lattice spacings.
    faceted : ndarray of bool
        Bounded by close-packed rows rather than round.
    hole : ndarray of int
        Sites left empty at the shape's core (0: solid).
    sites : tuple of ndarray
        Each shape's sites, shape (n, 2).
    deformation : ndarray
        Total relaxed deformation energy of each shape (not per particle).
    bonds : ndarray
        Bound pairs of sides of each shape.
    width, length : ndarray
        ``topology.gyration_dimensions``, lattice spacings.
    converged : ndarray of bool
        The minimiser's verdict.
    """

    n: int
    segment: np.ndarray
    faceted: np.ndarray
    hole: np.ndarray
    sites: tuple
    deformation: np.ndarray
    bonds: np.ndarray
    width: np.ndarray
    length: np.ndarray
    converged: np.ndarray

    _FIELDS = ("segment", "faceted", "hole", "deformation", "bonds", "width", "length", "converged")

    def best_aspect_ratio(self, g) -> np.ndarray:
        """Length over width of the best single aggregate at each ``g`` (1 for a round one).

        Parameters
        ----------
        g : array_like
            Binding energies per bound pair of sides.

        Returns
        -------
        ndarray, shape of ``g``
        """
        best = self.best(g)
        return self.length[best] / self.width[best]

    @classmethod
    def from_arrays(cls, arrays) -> "FiniteAggregates":
        """Rebuild from a mapping with one entry per field (a saved ``.npz``; ``sites`` stacked).

        Parameters
        ----------
        arrays : mapping
            As written by ``arrays``. Files written before the holes (without ``hole``) hold
            solid shapes only.

        Returns
        -------
        FiniteAggregates
        """
        fields = {k: np.asarray(arrays[k]) for k in cls._FIELDS if k != "hole"}
        fields["hole"] = np.asarray(arrays["hole"]) if "hole" in arrays else np.zeros(len(fields["segment"]), int)
        return cls(int(arrays["n"]), sites=tuple(np.asarray(arrays["sites"])), **fields)

    def arrays(self) -> dict:
        """The fields as arrays for ``io.save_npz`` (inverse of ``from_arrays``).

        Returns
        -------
        dict
        """
        return {"n": self.n, "sites": np.stack(self.sites), **{k: getattr(self, k) for k in self._FIELDS}}

    def __add__(self, other: "FiniteAggregates") -> "FiniteAggregates":
        """The shapes of both, ``self``'s first (aggregates of the same ``n``)."""
        if not isinstance(other, FiniteAggregates) or other.n != self.n:
            return NotImplemented
        return FiniteAggregates(self.n, sites=self.sites + other.sites,
                                **{k: np.concatenate([getattr(self, k), getattr(other, k)]) for k in self._FIELDS})


def energy_above_best_single(energy: float, g: float, prediction) -> float:
    """How far a Monte Carlo state lies above the best single aggregate of a saved finite-size
    prediction, in bulk particle energies.

    Parameters
    ----------
    energy : float
        Total energy of the state (deformation minus ``g`` times bonds).
    g : float
        Binding energy per bound pair of sides.
    prediction : mapping
        The arrays of ``FiniteAggregates`` plus ``bulk_energy_per_particle``.

    Returns
    -------
    float
        Negative: several aggregates beat one.
    """
    best = FiniteAggregates.from_arrays(prediction).best_energy(float(g))
    return (float(energy) - float(best)) / float(prediction["bulk_energy_per_particle"])


def finite_aggregates(particle, n: int, segments=None, holes=None, method: str = "lbfgs",
                      tol: float = 1e-5) -> FiniteAggregates:
    """Relax the two one-parameter families of single ``n``-particle aggregates, round and faceted,
    each solid and with each hole of ``holes``.

    The finite-size prediction for Monte Carlo: the best shape at binding energy ``g`` is
    ``best(g)``. The faceted shapes hold the most bonds; the round ones alone left the best
    aggregate of 200 particles 1-4 bulk particle energies too high (ell = 5, Gamma = 0.5 to 0.95),
    below which annealing with bonded moves went. Without holes, the disks of 800 particles at
    nu = 0.9 that Monte Carlo dug a hole into ended below the best solid shape.

    Parameters
    ----------
    particle : Hexagon, Triangle or RandomHexagon
        The particle model; the shapes are cut from its tiling (``topology.stadium_sites``).
    n : int
        Particles per aggregate.
    segments : array_like, optional
        Core segment lengths of the shapes (``topology.stadium_sites``), lattice spacings
        (default ``FINITE_SEGMENTS * sqrt(n)`` on the hexagon tiling, ``sqrt(n / 2)`` on the
        triangle one, whose particles cover half the area).
    holes : array_like of int, optional
        Sites left empty at each shape's core, 0 for solid (default ``finite_hole_sizes(n)``).
    method : {'auto', 'newton', 'lbfgs', 'linear'}, optional
        As for ``relax``.
    tol : float, optional
        As for ``relax``.

    Returns
    -------
    FiniteAggregates
        Round shapes first, then faceted ones, each in the order of ``segments`` and, per
        segment, of ``holes``; a shape that falls into pieces (a round triangle strip thinner
        than a row, a hole that cuts a strip) is left out.

    Raises
    ------
    TypeError
        If ``particle`` is not a particle model.
    ValueError
        For bad ``segments``, ``holes`` or ``n``, or ``n`` too large for memory.

    Examples
    --------
    >>> from pyfrustrate import Hexagon, ansatz
    >>> p = Hexagon.from_continuum(ell=2.0, nu=0.9)
    >>> shapes = ansatz.finite_aggregates(p, 19, segments=[0.0, 4.0], holes=[0, 1])
    >>> shapes.faceted.tolist(), shapes.hole.tolist(), shapes.bonds.tolist()
    ([False, False, False, False, True, True, True, True], [0, 1, 0, 1, 0, 1, 0, 1], [42, 38, 40, 36, 42, 38, 40, 36])
    >>> g = ansatz.binding_energy_of(p, 2.0, 0.9, Gamma=0.5)
    >>> int(shapes.best(g)), float(shapes.best_aspect_ratio(g))  # the compact hexagon of 19
    (4, 1.0)
    """
    tiling = _checks.particle("particle", particle).tiling
    if segments is None:
        # In units of the side of a square of the aggregate's area, counted in hexagons: the same
        # shapes on both tilings (a triangle covers half a hexagon's area).
        area = topology.area_per_particle(tiling) / topology.area_per_particle("hexagon")
        segments = np.asarray(FINITE_SEGMENTS) * np.sqrt(n * area)
    segments = np.atleast_1d(np.asarray(segments, float))
    if segments.ndim != 1 or segments.size == 0:
        raise ValueError(f"segments must be a non-empty 1D sequence, got shape {segments.shape}")
    holes = finite_hole_sizes(n, tiling) if holes is None else tuple(
        _checks.integer("holes", h, 0) for h in np.atleast_1d(np.asarray(holes)).tolist())
    if not holes:
        raise ValueError("holes must be a non-empty sequence (0: solid)")
    rows, shapes = [], []
    kwargs: dict[str, Any] = {"x0": "linear"} if method == "lbfgs" else {}
    for faceted in (False, True):
        for segment in segments:
            for hole in holes:
                sites = topology.stadium_sites(n, segment, faceted=faceted, tiling=tiling, hole=hole)
                cluster = topology.cluster(sites, tiling=tiling)
                if _kernel.rigid_pieces(cluster.kernel) > 1:
                    continue  # a strip thinner than a row of triangles, or cut by its slot: no single aggregate
                r = relax(particle, cluster, method=method, tol=tol, **kwargs)
                shapes.append(sites)
                rows.append((segment, faceted, hole, r.energy, r.n_bonds, *topology.gyration_dimensions(sites, tiling),
                             r.converged))
    # Each row holds the array fields in FiniteAggregates._FIELDS order.
    return FiniteAggregates(int(n), sites=tuple(shapes),
                            **{k: np.array(column) for k, column in zip(FiniteAggregates._FIELDS, zip(*rows))})
