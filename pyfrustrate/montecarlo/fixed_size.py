"""Single aggregates sampled at fixed size: the Monte Carlo's own optimal fibre width and disk size.

A box annealed from a gas cannot measure the optimal fibre width ``W*``: a fibre that wraps a
periodic box of side ``L`` holds ``n / L`` rows whatever ``W*`` is, and low-temperature reshaping
of a faceted aggregate is nucleation-limited. Self-limiting assembly is instead validated by the
free energy against size (Hagan & Grason, Rev. Mod. Phys. 93, 025008, 2021). Here each size is
sampled on its own:

* **fibres**: ``W`` full rows along ``a1`` wrapping a periodic ``L x L`` box (``n = L W``,
  ``fibre_seed``), which the chain relaxes as a straight periodic fibre with a free period;
* **disks**: one compact seed of ``n`` particles (the faceted, bond-maximal shape of
  ``topology.stadium_sites``, ``disk_seed``) in a box that leaves it ``margin`` empty rows on
  every side (``disk_box``).

Each seed is held at a temperature of the reshaping window, where the outline moves but the
aggregate neither melts nor evaporates (``reshaping_temperature`` picks it from the energy trace
of a heating ladder, ``heating_ladder``), then cooled and quenched at ``T = 0``
(``sample_schedule``). The energy per particle including binding, ``e = (-g bonds + deformation)
/ n``, of the quenched states against ``W`` or ``n`` gives ``W*_MC`` and ``n*_MC`` per seed
(``size_of_lowest_energy``), to compare with the ansatz's best straight fibre and best hexagonal
disk (``best_straight_fibre``, ``best_disk``) and with the continuum's optima.

Moves (``fixed_size_options``): surface moves and bonded particle moves, with probabilities close
to 1, and no cluster moves. Each family keeps detailed balance on its own (its Hastings ratio,
``anneal``; every one is checked against exact enumeration in ``tests/test_montecarlo.py``) and a
fixed mixture of them keeps it too, so the chain samples the Boltzmann distribution of the box.
Both families take a particle to a site next to an occupied one, so they move particles along the
outline rather than into the gas. The kernel keeps the plain particle move (to any empty site)
with probability ``(1 - surface_moves)(1 - bonded_moves)`` (a move that cannot leave an aggregate
would break ergodicity, so the options refuse probability 1): with the defaults, 1 % of the moves.
Evaporation is then not forbidden but rare, as the Boltzmann weight of a lone particle at a
window temperature is; each sample records how many particles end outside its largest cluster
(``FixedSizeSample.outside``). Cluster translations are left out: a whole-aggregate translation
changes nothing here, and a partial one splits the aggregate.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .. import continuum, topology
from .._checks import integer, non_negative, probability
from ..relaxation import relax
from .analysis import clusters
from .annealing import AnnealState, anneal
from .driver import ChainState, new_chain
from .options import MonteCarloOptions, check_particle

__all__ = ["SCANS", "COMPETITORS", "fibre_seed", "disk_seed", "two_disks_seed", "fibre_and_disk_seeds",
           "disk_and_fibre_seeds", "ansatz_margin", "predicted_kind", "two_sided_seeds", "persists", "disk_box", "fixed_size_options", "seeded_state",
           "heating_ladder", "reshaping_temperature", "reshaping_window", "sample_schedule", "sample", "FixedSizeSample",
           "size_of_lowest_energy", "fitted_optimum", "best_straight_fibre", "best_disk", "continuum_optima"]

#: The two kinds of fixed-size samples.
SCANS = ("fibre", "disk")
#: The competitors of a two-sided check: two disks of half the predicted disk's size, or the other
#: kind (a fibre against a predicted disk, a disk against a predicted fibre) of as many particles.
COMPETITORS = ("two_disks", "other_kind")


def fibre_seed(length: int, width: int) -> np.ndarray:
    """The sites of a straight fibre of ``width`` rows along ``a1`` that wraps a box of side ``length``.

    Rows ``j = 0 .. width - 1``, each of ``length`` sites ``i = 0 .. length - 1``: the cut-0 fibre
    (``topology.fiber(width, 0)``) repeated ``length`` times, ``n = length * width`` particles.

    Parameters
    ----------
    length : int
        The box side and the fibre's period, in lattice spacings (>= 3).
    width : int
        Rows, in [1, length - 2]: at least two empty rows keep the fibre's two edges from binding
        across the box.

    Returns
    -------
    ndarray of int, shape (length * width, 2)
        Lattice coordinates ``(i, j)``, row by row.

    Raises
    ------
    ValueError
        ``length`` or ``width`` out of range, named.

    Examples
    --------
    >>> from pyfrustrate.montecarlo.fixed_size import fibre_seed
    >>> fibre_seed(4, 2).tolist()
    [[0, 0], [1, 0], [2, 0], [3, 0], [0, 1], [1, 1], [2, 1], [3, 1]]
    """
    length = integer("length", length, 3)
    width = integer("width", width, 1, length - 2)
    j, i = np.divmod(np.arange(length * width), length)
    return np.column_stack([i, j]).astype(np.int64)


def disk_seed(n: int, box: int) -> np.ndarray:
    """A compact aggregate of ``n`` particles (the faceted shape with the most bonds,
    ``topology.stadium_sites(n, 0, faceted=True)``) centred in a ``box x box`` cell.

    Parameters
    ----------
    n : int
        Particles, >= 1.
    box : int
        Box side; the aggregate must not touch its periodic images (``disk_box(n)`` is the
        smallest box with a margin).

    Returns
    -------
    ndarray of int, shape (n, 2)
        Sites in ``[0, box)``.

    Raises
    ------
    ValueError
        Bad ``n`` or ``box``, or a box too small for the aggregate and one empty row around it.
    """
    n = integer("n", n, 1)
    box = integer("box", box, 2)
    sites = topology.stadium_sites(n, 0.0, faceted=True)
    span = _span(sites)
    if span + 2 > box:
        raise ValueError(f"box must exceed the disk's span {span} by at least one empty row on each side, got "
                         f"box={box} for n={n} (disk_box(n) gives a box that fits)")
    return sites + box // 2


def two_disks_seed(n: int, margin: int = 4) -> tuple[np.ndarray, np.ndarray, int]:
    """One compact disk of ``n`` particles and, in the same box, two of ``n // 2`` and
    ``n - n // 2`` side by side: the seeds of a two-sided check (one aggregate against two).

    The box is two ``disk_box(n - n // 2, margin)`` side by side along ``a1`` (square), so the
    two disks sit ``2 margin`` empty rows apart, and from their periodic images; the single disk
    is centred in the same box.

    Parameters
    ----------
    n : int
        Particles, >= 2.
    margin : int, optional
        As for ``disk_box``.

    Returns
    -------
    one : ndarray of int, shape (n, 2)
        The single disk.
    two : ndarray of int, shape (n, 2)
        The two disks.
    box : int
        The box side.

    Raises
    ------
    ValueError
        Bad ``n`` or ``margin``.

    Examples
    --------
    >>> from pyfrustrate.montecarlo.fixed_size import two_disks_seed
    >>> one, two, box = two_disks_seed(14, margin=2)
    >>> one.shape, two.shape, box
    ((14, 2), (14, 2), 14)
    """
    n = integer("n", n, 2)
    half = disk_box(n - n // 2, margin)
    box = 2 * half
    small = topology.stadium_sites(n // 2, 0.0, faceted=True)
    large = topology.stadium_sites(n - n // 2, 0.0, faceted=True)
    two = np.concatenate([small + (half // 2, box // 2), large + (half + half // 2, box // 2)])
    return disk_seed(n, box), two, box


def fibre_and_disk_seeds(width: int, length: int, margin: int = 4) -> tuple[np.ndarray, np.ndarray, int]:
    """A straight fibre of ``width`` rows wrapping a box and a compact disk of as many particles in
    the same box: the seeds of a two-sided check at a fibre point (a fibre against a disk).

    The box side is the smallest ``L >= length`` whose ``L * width`` particles fit as a disk with
    ``margin`` empty rows around it (``disk_box``); the fibre has ``L * width`` particles.

    Parameters
    ----------
    width : int
        The fibre's rows, >= 1.
    length : int
        The shortest box side, >= 3.
    margin : int, optional
        As for ``disk_box``.

    Returns
    -------
    fibre, disk : ndarray of int, shape (n, 2)
    box : int

    Raises
    ------
    ValueError
        Bad ``width``, ``length`` or ``margin``, named.

    Examples
    --------
    >>> from pyfrustrate.montecarlo.fixed_size import fibre_and_disk_seeds
    >>> fibre, disk, box = fibre_and_disk_seeds(3, 6, margin=2)
    >>> len(fibre) == len(disk) == 3 * box, box
    (True, 11)
    """
    width = integer("width", width, 1)
    box = integer("length", length, 3)
    margin = integer("margin", margin, 1)
    while disk_box(box * width, margin) > box:
        box += 1
    return fibre_seed(box, width), disk_seed(box * width, box), box


def disk_and_fibre_seeds(n: int, margin: int = 4) -> tuple[np.ndarray, np.ndarray, int]:
    """A compact disk of ``n`` particles and a straight fibre of as many wrapping the same box: the
    seeds of a two-sided check at a disk point near the fibre-disk line (a disk against a fibre).

    The box is ``disk_box(n, margin)``; the fibre fills its rows one after the other
    (``fibre_seed``'s order), the last one partly when the box side does not divide ``n``.

    Parameters
    ----------
    n : int
        Particles, >= 1.
    margin : int, optional
        As for ``disk_box``.

    Returns
    -------
    disk, fibre : ndarray of int, shape (n, 2)
    box : int

    Raises
    ------
    ValueError
        Bad ``n`` or ``margin``, or a fibre too wide for the box (two empty rows must separate its
        edges across the box).

    Examples
    --------
    >>> from pyfrustrate.montecarlo.fixed_size import disk_and_fibre_seeds
    >>> disk, fibre, box = disk_and_fibre_seeds(19, margin=2)
    >>> box, len(disk), len(fibre), sorted(set(fibre[:, 1].tolist()))
    (9, 19, 19, [0, 1, 2])
    """
    n = integer("n", n, 1)
    box = disk_box(n, margin)
    rows = -(-n // box)
    if rows > box - 2:
        raise ValueError(f"a fibre of n={n} particles needs {rows} rows of the box side {box}, more than box - 2")
    return disk_seed(n, box), fibre_seed(box, rows)[:n], box


def ansatz_margin(point) -> float:
    """The ansatz's best disk minus its best straight fibre, in energy per particle including
    binding (spring units): positive where the fibre is the better single aggregate.

    Parameters
    ----------
    point : mapping
        A point record with ``fibre_energy_per_particle`` and ``disk_energy_per_particle`` (the
        ansatz's per width and per radius, as ``best_straight_fibre`` and ``best_disk`` give them).

    Returns
    -------
    float
    """
    fibre = np.min(np.asarray(point["fibre_energy_per_particle"], float))
    disk = np.min(np.asarray(point["disk_energy_per_particle"], float))
    return float(disk - fibre)


def predicted_kind(point) -> str:
    """The ansatz's better single aggregate at a validation point: ``"fibre"`` where its best
    straight fibre has the lower energy per particle (``ansatz_margin`` > 0), else ``"disk"``.

    Parameters
    ----------
    point : mapping
        As for ``ansatz_margin``.

    Returns
    -------
    str
    """
    return "fibre" if ansatz_margin(point) > 0 else "disk"


def two_sided_seeds(point, competitor: str, *, fibre_length: int, margin: int = 4):
    """The seeds of a two-sided check (issue 33, item 4): the ansatz's predicted state at ``point``
    (``predicted_kind``) and its competitor, with the same particles in the same box.

    Parameters
    ----------
    point : mapping
        A validation point record (``W_ansatz``, ``n_ansatz`` and the ansatz's energies).
    competitor : {"two_disks", "other_kind"}
        ``"two_disks"``: a predicted disk of ``n_ansatz`` against two of half of it
        (``two_disks_seed``). ``"other_kind"``: a predicted fibre of ``W_ansatz`` rows against a
        disk (``fibre_and_disk_seeds``), or a predicted disk of ``n_ansatz`` against a fibre
        (``disk_and_fibre_seeds``).
    fibre_length : int, keyword only
        The shortest box side of a predicted fibre.
    margin : int, optional
        As for ``disk_box``.

    Returns
    -------
    dict
        ``predicted_state``, ``competitor_state`` (words), ``predicted_kind`` (``"fibre"`` or
        ``"disk"``), ``predicted`` and ``competitor`` (sites), ``box``, ``n``.

    Raises
    ------
    ValueError
        An unknown competitor, or two disks against a predicted fibre.
    """
    if competitor not in COMPETITORS:
        raise ValueError(f"competitor must be one of {COMPETITORS}, got {competitor!r}")
    kind = predicted_kind(point)
    if competitor == "two_disks":
        if kind != "disk":
            raise ValueError("competitor='two_disks' needs a point where the ansatz predicts a disk, but at "
                             f"nu={point['nu']}, Gamma={point['Gamma']} it predicts a fibre")
        predicted, other, box = two_disks_seed(int(point["n_ansatz"]), margin)
        words = ("one disk", "two disks")
    elif kind == "fibre":
        predicted, other, box = fibre_and_disk_seeds(int(point["W_ansatz"]), fibre_length, margin)
        words = ("a fibre wrapping the box", "one disk")
    else:
        predicted, other, box = disk_and_fibre_seeds(int(point["n_ansatz"]), margin)
        words = ("one disk", "a fibre wrapping the box")
    return dict(predicted_state=words[0], competitor_state=words[1], predicted_kind=kind, predicted=predicted,
                competitor=other, box=box, n=len(predicted))


def persists(kind: str, outside: int, wraps: int) -> bool:
    """Whether a run seeded as ``kind`` ended in that kind: every particle in one aggregate, which
    wraps the box in one direction for a fibre and in none for a disk.

    Parameters
    ----------
    kind : {"fibre", "disk"}
    outside : int
        Particles outside the largest cluster at the end (``FixedSizeSample.outside``).
    wraps : int
        Directions the largest cluster wraps (``FixedSizeSample.wraps``).

    Returns
    -------
    bool
    """
    if kind not in SCANS:
        raise ValueError(f"kind must be one of {SCANS}, got {kind!r}")
    return outside == 0 and wraps == (1 if kind == "fibre" else 0)


def _span(sites) -> int:
    """The largest extent of sites along the three lattice directions, in lattice steps (plus one)."""
    i, j = np.asarray(sites).T
    return int(max(np.ptp(i), np.ptp(j), np.ptp(i + j))) + 1


def disk_box(n: int, margin: int = 4) -> int:
    """The smallest box that holds ``disk_seed(n)`` with ``margin`` empty rows on every side.

    The margin lets the outline reshape without touching its periodic images.

    Parameters
    ----------
    n : int
        Particles, >= 1.
    margin : int, optional
        Empty rows between the aggregate and its images, >= 1.

    Returns
    -------
    int

    Raises
    ------
    ValueError
        Bad ``n`` or ``margin``.
    """
    n = integer("n", n, 1)
    margin = integer("margin", margin, 1)
    return _span(topology.stadium_sites(n, 0.0, faceted=True)) + 2 * margin


def fixed_size_options(bonded_moves: float = 0.9, surface_moves: float = 0.9, **fields) -> MonteCarloOptions:
    """The chain's options for fixed-size sampling (module docstring): surface and bonded moves,
    no cluster moves.

    Parameters
    ----------
    bonded_moves, surface_moves : float, optional
        Their probabilities, in [0, 1) (``MonteCarloOptions``).
    **fields
        Other fields of ``MonteCarloOptions`` (``method``, ``tol``, ...).

    Returns
    -------
    MonteCarloOptions

    Raises
    ------
    ValueError
        A field out of range, named.
    """
    return MonteCarloOptions(cluster_moves=0.0, bonded_moves=bonded_moves, surface_moves=surface_moves, **fields)


def seeded_state(particle, sites, box: int, seed: int, *, g: float, options: MonteCarloOptions) -> AnnealState:
    """An ``AnnealState`` with the particles on ``sites``, to start ``anneal(..., state=)`` from.

    The chain's generator is seeded by ``seed`` (the kernel's ``std::mt19937_64``, as a chain of
    one particle in the box draws it) and its energy is computed from scratch for ``sites``.

    Parameters
    ----------
    particle : Hexagon, RandomHexagon or Triangle
        The particle model.
    sites : array_like of int, shape (n, 2)
        The occupied sites (as ``fibre_seed``, ``disk_seed``).
    box : int
        Box side.
    seed : int
        Seed of the chain's generator, in [0, 2**64).
    g : float, keyword only
        Binding energy per bound pair of sides (spring units).
    options : MonteCarloOptions, keyword only
        The chain's options (those the run will use).

    Returns
    -------
    AnnealState
        No block done; ``state.chain`` holds the sites, the generator and the relaxed energy.

    Raises
    ------
    ValueError
        Sites held twice or too many for the box, or a bad ``seed``, named.
    """
    chain = _seeded_chain(particle, sites, box, seed, g, options)
    return AnnealState(done=0, chain=chain.state, energy_trace=np.zeros(0), accepted=np.zeros(0, np.int64))


def _seeded_chain(particle, sites, box, seed, g, options):
    """The kernel chain of ``seeded_state``, its energy computed for ``sites``."""
    check_particle(particle)
    seed = integer("seed", seed, 0, 2**64 - 1)
    sites = np.ascontiguousarray(sites, dtype=np.int32)
    if sites.ndim != 2 or len(sites) < 1:
        raise ValueError(f"sites must be an (n, 2) array of lattice sites, n >= 1, got shape {sites.shape}")
    generator = new_chain(particle, g, box, 1, seed, options).state.rng_state
    empty = ChainState(particle.tiling, box, sites, generator, 0.0, {}, np.zeros(0), np.zeros(0, np.uint8))
    try:
        chain = new_chain(particle, g, box, len(sites), seed, options, state=empty)
        chain.place(sites)  # energy from scratch (the state above carries none)
    except ValueError as e:
        raise ValueError(f"sites: {str(e).removeprefix('sites: ').removeprefix('state: ')}") from None
    return chain


def heating_ladder(particle, sites, box: int, seed: int, *, g: float, temperatures, sweeps: int,
                   options: MonteCarloOptions) -> tuple[object, float]:
    """Run a seeded aggregate through rising temperatures: the energy trace that
    ``reshaping_temperature`` reads.

    Parameters
    ----------
    particle : Hexagon, RandomHexagon or Triangle
        The particle model.
    sites : array_like of int, shape (n, 2)
        The seed.
    box, seed : int
        Box side and the chain's seed.
    g : float, keyword only
        Binding energy per bound pair of sides.
    temperatures : sequence of float, keyword only
        The ladder, increasing, in spring units (the chain continues from one to the next).
    sweeps : int, keyword only
        Sweeps (``n`` attempted moves) per temperature.
    options : MonteCarloOptions, keyword only
        The chain's options.

    Returns
    -------
    result : AnnealResult
        One record block per sweep (``temperature``, ``energy_trace``, ``accepted``).
    seed_energy : float
        The seed's energy ``-g * bonds + deformation``, before any move (the reference of
        ``reshaping_temperature``).

    Raises
    ------
    ValueError
        Temperatures not increasing or negative, or other bad values, named.
    """
    temperatures = np.asarray(temperatures, float)
    if temperatures.ndim != 1 or temperatures.size < 2 or not np.all(np.isfinite(temperatures)):
        raise ValueError(f"temperatures must be at least two finite values, got {temperatures!r}")
    if temperatures[0] < 0 or np.any(np.diff(temperatures) <= 0):
        raise ValueError(f"temperatures must be non-negative and increasing, got {temperatures.tolist()}")
    sweeps = integer("sweeps", sweeps, 2)
    chain = _seeded_chain(particle, sites, box, seed, g, options)
    state = AnnealState(done=0, chain=chain.state, energy_trace=np.zeros(0), accepted=np.zeros(0, np.int64))
    n = len(sites)
    result = anneal(particle, g=g, box=box, n=n, seed=seed, schedule=[(T, sweeps * n) for T in temperatures],
                    options=options, state=state, progress=False)
    return result, float(chain.energy)


def reshaping_temperature(temperature, energy, accepted, *, n: int, g: float, reference_energy: float,
                          max_excess: float = 0.05, min_acceptance: float = 0.01):
    """The hold temperature of fixed-size sampling, from a heating ladder's energy trace.

    The ladder's temperatures (one per record block, rising by stages) are judged stage by stage
    on the second half of each stage's blocks, the first half being its equilibration:

    * the aggregate **holds** while its mean energy lies less than ``max_excess * n * g`` above
      ``reference_energy`` (the seed's: ``max_excess`` bonds broken per particle, on average);
      above that it melts, roughens into a loose network or evaporates;
    * it **reshapes** where at least ``min_acceptance`` of the attempted moves are accepted
      (its outline moves).

    The reshaping window is the range of temperatures that reshape, up to the first that does
    not hold; the hold temperature is its top, where reshaping is fastest.

    Parameters
    ----------
    temperature, energy : array_like, shape (B,)
        Temperature and energy after each record block (``AnnealResult.temperature``,
        ``energy_trace``), stages of equal temperature in increasing order.
    accepted : array_like, shape (B,)
        Accepted moves per block (``AnnealResult.accepted``), blocks of ``n`` moves.
    n : int, keyword only
        Particles.
    g : float, keyword only
        Binding energy per bound pair of sides (> 0).
    reference_energy : float, keyword only
        The seed's energy.
    max_excess : float, keyword only
        Broken bonds per particle, on average, beyond which the aggregate no longer holds.
    min_acceptance : float, keyword only
        Fraction of accepted moves from which the aggregate reshapes.

    Returns
    -------
    temperature : float
        The hold temperature.
    stages : list of dict
        Per stage: ``T``, ``excess`` (mean energy above the reference over ``n g``),
        ``acceptance``, ``holds``, ``reshapes``.

    Raises
    ------
    ValueError
        Arrays of different lengths or not in stages of rising temperature, bad ``n``, ``g`` or
        thresholds, or no stage that both holds and reshapes (the message lists the stages, so
        the ladder can be moved).

    Examples
    --------
    A ladder at g = 1 for 10 particles: the aggregate holds up to T = 0.2 and reshapes from 0.1.

    >>> from pyfrustrate.montecarlo.fixed_size import reshaping_temperature
    >>> T = [0.05] * 4 + [0.1] * 4 + [0.2] * 4 + [0.3] * 4
    >>> E = [-20] * 4 + [-20, -20, -19.9, -19.9] + [-20, -19.8, -19.7, -19.7] + [-20, -18, -15, -14]
    >>> acc = [0] * 4 + [1] * 4 + [3] * 4 + [5] * 4
    >>> reshaping_temperature(T, E, acc, n=10, g=1.0, reference_energy=-20.0)[0]
    0.2
    """
    T = np.asarray(temperature, float)
    E = np.asarray(energy, float)
    A = np.asarray(accepted, float)
    if not (T.ndim == E.ndim == A.ndim == 1 and T.size == E.size == A.size) or T.size == 0:
        raise ValueError(f"temperature, energy and accepted must be 1D arrays of one length, got shapes "
                         f"{T.shape}, {E.shape}, {A.shape}")
    if not (np.all(np.isfinite(T)) and np.all(np.isfinite(E)) and np.all(np.isfinite(A))):
        raise ValueError("temperature, energy and accepted must be finite")
    n = integer("n", n, 1)
    g = non_negative("g", g)
    if g == 0:
        raise ValueError("g must be positive: the excess energy is counted in bonds")
    reference_energy = float(reference_energy)
    if not np.isfinite(reference_energy):
        raise ValueError(f"reference_energy must be finite, got {reference_energy!r}")
    max_excess = non_negative("max_excess", max_excess)
    min_acceptance = probability("min_acceptance", min_acceptance)
    starts = np.flatnonzero(np.r_[True, np.diff(T) != 0])
    if np.any(np.diff(T[starts]) <= 0):
        raise ValueError(f"temperature must rise stage by stage, got stages at {T[starts].tolist()}")
    stages = []
    for lo, hi in zip(starts, np.r_[starts[1:], T.size]):
        late = slice(lo + (hi - lo) // 2, hi)
        excess = float((E[late].mean() - reference_energy) / (n * g))
        acceptance = float(A[late].mean() / n)
        stages.append(dict(T=float(T[lo]), excess=excess, acceptance=acceptance, holds=excess <= max_excess,
                           reshapes=acceptance >= min_acceptance))
    window = _window_temperatures(stages)
    if not window:
        table = ", ".join(f"T={s['T']:.3g}: excess {s['excess']:.3g}, acceptance {s['acceptance']:.3g}" for s in stages)
        raise ValueError(f"no stage of the ladder both holds (excess <= {max_excess:g} bonds per particle) and "
                         f"reshapes (acceptance >= {min_acceptance:g}): {table}")
    return window[-1], stages


def _window_temperatures(stages) -> list[float]:
    """The temperatures of the stages that reshape, below the first that does not hold."""
    window = []
    for stage in stages:
        if not stage["holds"]:
            break
        if stage["reshapes"]:
            window.append(stage["T"])
    return window


def reshaping_window(stages) -> tuple[float, float]:
    """The reshaping window's lowest and highest temperatures, from ``reshaping_temperature``'s
    stages (the input of ``annealing.window_schedule``).

    Parameters
    ----------
    stages : list of dict
        ``reshaping_temperature(...)[1]``: per stage ``T``, ``holds``, ``reshapes``, by rising
        ``T``.

    Returns
    -------
    (float, float)
        The lowest and the highest temperature that reshape below the first stage that does not
        hold (equal if one stage does).

    Raises
    ------
    ValueError
        ``stages`` is not such a list, or no stage both holds and reshapes.

    Examples
    --------
    >>> from pyfrustrate.montecarlo.fixed_size import reshaping_window
    >>> reshaping_window([dict(T=0.05, holds=True, reshapes=False), dict(T=0.1, holds=True, reshapes=True),
    ...                   dict(T=0.2, holds=True, reshapes=True), dict(T=0.3, holds=False, reshapes=True)])
    (0.1, 0.2)
    """
    try:
        window = _window_temperatures(stages)
    except (TypeError, KeyError) as error:
        raise ValueError(f"stages must be reshaping_temperature's list of dicts with T, holds and reshapes, "
                         f"got {stages!r}") from error
    if not window:
        raise ValueError("stages: no stage both holds and reshapes")
    return float(min(window)), float(max(window))


def sample_schedule(hold_temperature: float, n: int, *, hold_sweeps: int, cool_sweeps: int, quench_sweeps: int,
                    cool_stages: int = 4) -> list[tuple[float, int]]:
    """The stages of one fixed-size sample: hold, cool linearly, quench at ``T = 0``.

    Parameters
    ----------
    hold_temperature : float
        The reshaping window's temperature (``reshaping_temperature``), spring units.
    n : int
        Particles (a sweep is ``n`` attempted moves).
    hold_sweeps, cool_sweeps, quench_sweeps : int, keyword only
        Sweeps held at ``hold_temperature``, spent cooling (in ``cool_stages`` equal stages at
        ``hold_temperature * k / (cool_stages + 1)``, ``k = cool_stages .. 1``; the remainder of
        ``cool_sweeps / cool_stages`` is dropped), and at ``T = 0`` (a descent: every move that
        lowers the energy is taken).
    cool_stages : int, keyword only
        Temperatures between the hold and 0.

    Returns
    -------
    list of (float, int)
        ``(T, attempted moves)`` stages for ``anneal(schedule=)``.

    Raises
    ------
    ValueError
        A bad value, named.

    Examples
    --------
    >>> from pyfrustrate.montecarlo.fixed_size import sample_schedule
    >>> sample_schedule(0.3, 10, hold_sweeps=5, cool_sweeps=4, quench_sweeps=2, cool_stages=2)
    [(0.3, 50), (0.2, 20), (0.1, 20), (0.0, 20)]
    """
    hold_temperature = non_negative("hold_temperature", hold_temperature)
    n = integer("n", n, 1)
    hold_sweeps = integer("hold_sweeps", hold_sweeps, 1)
    quench_sweeps = integer("quench_sweeps", quench_sweeps, 1)
    cool_stages = integer("cool_stages", cool_stages, 1)
    cool_sweeps = integer("cool_sweeps", cool_sweeps, cool_stages)
    per_stage = cool_sweeps // cool_stages
    stages = [(hold_temperature, hold_sweeps * n)]
    stages += [(round(hold_temperature * k / (cool_stages + 1), 12), per_stage * n) for k in range(cool_stages, 0, -1)]
    return stages + [(0.0, quench_sweeps * n)]


@dataclass(frozen=True)
class FixedSizeSample:
    """One quenched fixed-size sample.

    Attributes
    ----------
    n : int
        Particles.
    energy : float
        Final energy ``-g * bonds + deformation``, spring units.
    energy_per_particle : float
        ``energy / n``: the ``e(W)`` or ``e(n)`` of the scans.
    bonds : int
        Bound pairs of sides at the end.
    outside : int
        Particles outside the largest cluster at the end (0: one aggregate).
    wraps : int
        How many directions the largest cluster wraps (0 finite, 1 a fibre, 2 a bulk).
    seconds : float
        Wall time of the run (seeding included).
    moves : int
        Attempted moves.
    result : AnnealResult
        The run.
    """

    n: int
    energy: float
    energy_per_particle: float
    bonds: int
    outside: int
    wraps: int
    seconds: float
    moves: int
    result: object


def sample(particle, sites, box: int, seed: int, *, g: float, schedule, options: MonteCarloOptions) -> FixedSizeSample:
    """Hold, cool and quench one seeded aggregate (``sample_schedule``).

    Parameters
    ----------
    particle : Hexagon, RandomHexagon or Triangle
        The particle model.
    sites : array_like of int, shape (n, 2)
        The seed (``fibre_seed``, ``disk_seed``).
    box, seed : int
        Box side and the chain's seed.
    g : float, keyword only
        Binding energy per bound pair of sides.
    schedule : sequence of (T, steps), keyword only
        The stages (``sample_schedule``); the last should be at ``T = 0``.
    options : MonteCarloOptions, keyword only
        The chain's options (``fixed_size_options``).

    Returns
    -------
    FixedSizeSample

    Raises
    ------
    ValueError
        Bad sites, schedule or options, named.
    """
    start = time.perf_counter()
    state = seeded_state(particle, sites, box, seed, g=g, options=options)
    n = len(sites)
    result = anneal(particle, g=g, box=box, n=n, seed=seed, schedule=schedule, options=options, state=state,
                    progress=False)
    parts = clusters(result.sites, box, particle.tiling)
    largest, wraps = parts[0]
    return FixedSizeSample(n=n, energy=result.energy, energy_per_particle=result.energy / n, bonds=result.bonds,
                           outside=n - len(largest), wraps=int(wraps), seconds=time.perf_counter() - start,
                           moves=int(result.steps[-1]), result=result)


def size_of_lowest_energy(sizes, energy_per_particle) -> tuple[float, bool]:
    """The size of lowest energy per particle on a scan, and whether the scan brackets it.

    Parameters
    ----------
    sizes : array_like, shape (k,)
        Distinct sizes (rows ``W`` or particles ``n``), k >= 3, in any order.
    energy_per_particle : array_like, shape (k,)
        The energy per particle including binding at each size.

    Returns
    -------
    size : float
        The size of the lowest energy (the first, on ties).
    bracketed : bool
        False when it is the smallest or largest size scanned: the optimum may lie beyond.

    Raises
    ------
    ValueError
        Arrays of different lengths, fewer than three sizes, repeated sizes or non-finite values.

    Examples
    --------
    >>> from pyfrustrate.montecarlo.fixed_size import size_of_lowest_energy
    >>> size_of_lowest_energy([8, 10, 12, 14], [-1.0, -1.3, -1.2, -1.1])
    (10.0, True)
    >>> size_of_lowest_energy([8, 10, 12], [-1.0, -1.1, -1.2])
    (12.0, False)
    """
    sizes = np.asarray(sizes, float)
    e = np.asarray(energy_per_particle, float)
    if sizes.ndim != 1 or e.shape != sizes.shape:
        raise ValueError(f"sizes and energy_per_particle must be 1D of one length, got shapes {sizes.shape} and "
                         f"{e.shape}")
    if sizes.size < 3:
        raise ValueError(f"sizes: at least three are needed to bracket a minimum, got {sizes.size}")
    if not (np.all(np.isfinite(sizes)) and np.all(np.isfinite(e))):
        raise ValueError("sizes and energy_per_particle must be finite")
    if np.unique(sizes).size != sizes.size:
        raise ValueError(f"sizes must be distinct, got {sizes.tolist()}")
    order = np.argsort(sizes, kind="stable")
    k = int(np.argmin(e[order]))
    return float(sizes[order][k]), 0 < k < sizes.size - 1


def fitted_optimum(sizes, energy_per_particle) -> float:
    """The optimum of the least-squares parabola through ``e`` against ``log(size)``: an optimum
    that averages the samples' noise over the whole scan, where ``size_of_lowest_energy`` takes
    one sample's word.

    Near its optimum ``e`` is flat (a row or a hexagon shell is worth a fraction of a bond in a
    whole sample), so one outline defect more in one sample moves the lowest sample; a fit over
    ``W* +- 6`` or ``n*/2 .. 2 n*`` uses the curvature the scan spans. In ``log(size)`` because
    ``e`` rises faster below its optimum than above it (the outline's share falls as
    ``1/sqrt(n)`` or ``1/W``): on the relaxed hexagons of ell = 5, nu = 0.4, Gamma = 0.5 a parabola
    in ``n`` puts the optimum 10 % too high, one in ``log n`` within 4 %.

    Parameters
    ----------
    sizes, energy_per_particle : array_like, shape (k,)
        As for ``size_of_lowest_energy`` (k >= 3, distinct sizes, finite), sizes positive.

    Returns
    -------
    float
        ``exp`` of the parabola's vertex; nan when it opens downwards or is flat (no minimum).

    Raises
    ------
    ValueError
        As ``size_of_lowest_energy``, or a size that is not positive.

    Examples
    --------
    >>> import numpy as np
    >>> from pyfrustrate.montecarlo.fixed_size import fitted_optimum
    >>> sizes = np.array([10, 12, 14, 16])
    >>> round(fitted_optimum(sizes, np.log(sizes / 12.5) ** 2), 6)
    12.5
    """
    size_of_lowest_energy(sizes, energy_per_particle)  # the same checks
    x = np.asarray(sizes, float)
    if np.any(x <= 0):
        raise ValueError(f"sizes must be positive, got {x.tolist()}")
    x = np.log(x)
    centre, scale = x.mean(), np.ptp(x)  # conditioned: energies of 1e-3 against logarithms
    a, b, _ = np.polyfit((x - centre) / scale, np.asarray(energy_per_particle, float), 2)
    return float(np.exp(centre - scale * b / (2 * a))) if a > 0 else float("nan")


def best_straight_fibre(particle, g: float, max_width: int = 35, tol: float = 1e-5) -> tuple[int, np.ndarray]:
    """The ansatz's best straight cut-0 fibre: the width, in rows, of lowest energy per particle.

    The fibres of ``fibre_seed`` as the box relaxes them: straight (``topology.fiber(W, 0,
    curved=False)``), cut 0, with a free period length.

    Parameters
    ----------
    particle : Hexagon or RandomHexagon
        The particle model (hexagon tiling).
    g : float
        Binding energy per bound pair of sides.
    max_width : int, optional
        The widest fibre relaxed, rows (>= 1).
    tol : float, optional
        As for ``relax``.

    Returns
    -------
    width : int
        Rows of the best one.
    energy_per_particle : ndarray, shape (max_width,)
        ``deformation - g * bonds`` per particle of widths ``1 .. max_width``.

    Raises
    ------
    TypeError
        ``particle`` is not a particle model.
    ValueError
        Bad ``g`` or ``max_width``.
    """
    check_particle(particle)
    g = non_negative("g", g)
    max_width = integer("max_width", max_width, 1)
    e = np.empty(max_width)
    for w in range(1, max_width + 1):
        r = relax(particle, topology.fiber(w, 0, curved=False, tiling=particle.tiling), tol=tol)
        e[w - 1] = (r.energy - g * r.n_bonds) / r.n_particles
    return int(np.argmin(e)) + 1, e


def best_disk(particle, g: float, max_radius: int = 25, tol: float = 1e-5,
              stop_after: int = 3) -> tuple[int, int, np.ndarray]:
    """The ansatz's best single disk: the hexagon (``topology.disk(R)``) of lowest energy per particle.

    Disks are relaxed in order of radius up to ``max_radius``, stopping ``stop_after`` radii
    past the lowest so far (the energy per particle has one minimum in ``R``).

    Parameters
    ----------
    particle : Hexagon or RandomHexagon
        The particle model.
    g : float
        Binding energy per bound pair of sides.
    max_radius : int, optional
        The largest radius, lattice steps (>= 1).
    tol : float, optional
        As for ``relax``.
    stop_after : int, optional
        Radii relaxed past the lowest one before stopping (>= 1).

    Returns
    -------
    n : int
        Particles of the best disk, ``1 + 3 R (R + 1)``.
    radius : int
        Its radius ``R``.
    energy_per_particle : ndarray
        ``deformation - g * bonds`` per particle of radii ``1 ..`` (as far as relaxed).

    Raises
    ------
    TypeError
        ``particle`` is not a particle model.
    ValueError
        Bad ``g``, ``max_radius`` or ``stop_after``.
    """
    check_particle(particle)
    g = non_negative("g", g)
    max_radius = integer("max_radius", max_radius, 1)
    stop_after = integer("stop_after", stop_after, 1)
    e = []
    for R in range(1, max_radius + 1):
        r = relax(particle, topology.disk(R, tiling=particle.tiling), tol=tol)
        e.append((r.energy - g * r.n_bonds) / r.n_particles)
        if R - (int(np.argmin(e)) + 1) >= stop_after:
            break
    R = int(np.argmin(e)) + 1
    return 1 + 3 * R * (R + 1), R, np.array(e)


def continuum_optima(ell: float, nu: float, Gamma: float) -> dict:
    """The continuum theory's optimal fibre width and disk size, in the units of the scans.

    ``continuum.optimal_width`` and ``optimal_radius`` (in units of ``ell``) as rows (``W ell``
    over the row spacing ``sqrt(3)/2``) and as particles (``pi (R ell)^2`` over the area per
    particle ``sqrt(3)/2``); nan where that aggregate has no optimum.

    Parameters
    ----------
    ell : float
        Boundary-layer length, lattice spacings.
    nu : float
        Poisson ratio.
    Gamma : float
        Dimensionless line tension.

    Returns
    -------
    dict
        ``W_rows`` and ``n_disk``.
    """
    ell = non_negative("ell", ell)
    width = float(continuum.optimal_width(nu, Gamma)) * ell
    radius = float(continuum.optimal_radius(nu, Gamma)) * ell
    return dict(W_rows=width / topology.ROW_SPACING, n_disk=np.pi * radius**2 / topology.area_per_particle("hexagon"))



def run_seed(seed: int, *keys: int) -> int:
    """The kernel seed of one run of a scan: ``SeedSequence([seed, *keys])``'s first 64-bit word.

    Distinct ``keys`` (a size, a role: 0 for the heating ladder, 1 for a sample) give independent
    streams from one configured seed.

    Parameters
    ----------
    seed : int
        The configured seed, >= 0.
    *keys : int
        Non-negative integers naming the run.

    Returns
    -------
    int
        In [0, 2**64).

    Raises
    ------
    ValueError
        A negative or non-integer ``seed`` or key.

    Examples
    --------
    >>> from pyfrustrate.montecarlo.fixed_size import run_seed
    >>> run_seed(1, 15, 1) == run_seed(1, 15, 1) != run_seed(1, 16, 1)
    True
    """
    words = [integer("seed", seed, 0)] + [integer("keys", k, 0) for k in keys]
    return int(np.random.SeedSequence(words).generate_state(1, np.uint64)[0])


def scan_sizes(scan: str, optimum: int, steps) -> list[int]:
    """The sizes of a scan around the ansatz's optimum.

    Parameters
    ----------
    scan : {"fibre", "disk"}
        Fibres: ``steps`` are rows added to the best width ``optimum``. Disks: ``steps`` are
        factors on the best disk's ``optimum`` particles (rounded).
    optimum : int
        The ansatz's best width (rows) or disk (particles), >= 1.
    steps : sequence of int or float
        Offsets (fibres) or factors (disks), at least three, distinct sizes.

    Returns
    -------
    list of int
        The sizes, in the order of ``steps``.

    Raises
    ------
    ValueError
        An unknown scan, a size below 1, repeated sizes or fewer than three.

    Examples
    --------
    >>> from pyfrustrate.montecarlo.fixed_size import scan_sizes
    >>> scan_sizes("fibre", 15, [-1, 0, 1]), scan_sizes("disk", 331, [0.5, 1.0, 2.0])
    ([14, 15, 16], [166, 331, 662])
    """
    if scan not in SCANS:
        raise ValueError(f"scan must be one of {SCANS}, got {scan!r}")
    optimum = integer("optimum", optimum, 1)
    steps = list(steps)
    if scan == "fibre":
        sizes = [optimum + integer("steps", s, -optimum) for s in steps]
    else:
        sizes = [int(round(non_negative("steps", s) * optimum)) for s in steps]
    if len(sizes) < 3 or len(set(sizes)) != len(sizes) or min(sizes) < 1:
        raise ValueError(f"steps must give at least three distinct sizes >= 1, got {sizes} from {steps}")
    return sizes


def scan_seed(scan: str, size: int, *, fibre_length: int, disk_margin: int) -> tuple[np.ndarray, int]:
    """The seed of one size of a scan and its box.

    Parameters
    ----------
    scan : {"fibre", "disk"}
        Fibres: ``fibre_seed(fibre_length, size)`` in a box of side ``fibre_length``. Disks:
        ``disk_seed(size, disk_box(size, disk_margin))``.
    size : int
        Rows (fibres) or particles (disks).
    fibre_length, disk_margin : int, keyword only
        As for ``fibre_seed`` and ``disk_box``.

    Returns
    -------
    sites : ndarray of int, shape (n, 2)
    box : int

    Raises
    ------
    ValueError
        An unknown scan or a bad size, named.
    """
    if scan not in SCANS:
        raise ValueError(f"scan must be one of {SCANS}, got {scan!r}")
    if scan == "fibre":
        return fibre_seed(fibre_length, size), integer("fibre_length", fibre_length, 3)
    box = disk_box(size, disk_margin)
    return disk_seed(size, box), box
