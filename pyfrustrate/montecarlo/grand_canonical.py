"""Grand-canonical sampling of one fibre: its width at a chemical potential, and the optimal width
``W*`` at a temperature from a scan of the chemical potential.

A fibre wrapping a periodic box of side ``L`` holds ``n / L`` rows whatever its optimal width, so a
canonical box cannot measure ``W*`` (``fixed_size`` therefore samples each width on its own).
Here the fibre exchanges particles with a reservoir at chemical potential ``mu`` instead: outline
moves (``kernel/montecarlo/outline_move.hpp``) insert a particle on an empty site next to the
aggregate or delete one whose removal leaves it connected, with the Hastings ratio of the counts
of those choices, and the chain samples ``exp(-(E - mu n) / T)`` over the connected aggregates of
the box (every other move that would disconnect it is refused). Surface and bonded particle moves
reshape the outline meanwhile (``grand_options``).

What the scan shows. With ``e(W)`` the energy per particle of a straight fibre of ``W`` rows,
binding included (``fixed_size.best_straight_fibre``), the grand potential of a wrapping fibre is
``Omega(W) = L W (e(W) - mu)``. Its width follows ``mu`` continuously, where the energy of one more
row equals ``mu``: ``d(W e) / dW = e + W e' = mu``; at ``mu = e(W*) = min_W e(W)`` that width is
``W*`` (``e' = 0``), and ``Omega`` changes sign there: below it the fibre is only metastable
against no aggregate at all (it shrinks, and once thin enough breaks and dissolves), above it the
fibre is stable and widens. At ``T > 0`` the measured energy per particle ``<E> / <n>`` takes the
place of ``e``: the threshold of the scan is the ``mu`` where ``<E> / <n> = mu``, i.e. where
``<E> - mu <n>`` crosses 0, and the width there estimates ``W*`` at that temperature
(``threshold_width``; entropy is neglected against the energy, as in the reshaping window).
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .._checks import integer, non_negative
from .analysis import clusters
from .fixed_size import _seeded_chain, fibre_seed
from .options import MonteCarloOptions

__all__ = ["grand_options", "hold_fibre", "GrandSample", "threshold_width"]


def grand_options(mu: float, outline_moves: float = 0.3, surface_moves: float = 0.9, bonded_moves: float = 0.9,
                  **fields) -> MonteCarloOptions:
    """The chain's options for grand-canonical sampling of one aggregate (module docstring).

    Parameters
    ----------
    mu : float
        The reservoir's chemical potential, in spring units (as ``g``), finite.
    outline_moves : float, optional
        Probability of an outline move (insertion or deletion), in (0, 1].
    surface_moves, bonded_moves : float, optional
        As in ``fixed_size.fixed_size_options``: the other moves reshape the outline.
    **fields
        Other fields of ``MonteCarloOptions`` (``method``, ``tol``, ...).

    Returns
    -------
    MonteCarloOptions
        No cluster moves (a translation of the whole aggregate changes nothing, a partial one
        would disconnect it).

    Raises
    ------
    ValueError
        ``mu`` not finite (named ``chemical_potential``), ``outline_moves`` 0, or another field out
        of range, named.

    Examples
    --------
    >>> from pyfrustrate.montecarlo.grand_canonical import grand_options
    >>> o = grand_options(-0.02)
    >>> o.chemical_potential, o.outline_moves, o.cluster_moves
    (-0.02, 0.3, 0.0)
    """
    options = MonteCarloOptions(cluster_moves=0.0, bonded_moves=bonded_moves, surface_moves=surface_moves,
                                outline_moves=outline_moves, chemical_potential=mu, **fields)
    if options.outline_moves == 0:
        raise ValueError("outline_moves must be positive for grand-canonical sampling, got 0")
    return options


@dataclass(frozen=True)
class GrandSample:
    """One fibre held at a chemical potential.

    Attributes
    ----------
    mu, T : float
        Chemical potential and temperature, spring units.
    length : int
        The box side and the fibre's period, lattice spacings.
    n : ndarray of int, shape (B,)
        Particles after each record block.
    energy : ndarray, shape (B,)
        Energy ``-g * bonds + deformation`` after each block.
    n_mean, n_std : float
        Mean and standard deviation of ``n`` over the blocks after ``equilibration``.
    W_mean, W_std : float
        The same for the width ``W = n / length``, rows.
    energy_per_particle : float
        ``<E> / <n>`` over those blocks (the ``e`` of the threshold, ``threshold_width``).
    wraps : int
        How many directions the aggregate wraps at the end (1: still a fibre).
    seconds : float
        Wall time.
    counters : dict
        The chain's counters at the end (``outline_inserted``, ``outline_removed``, ...).
    """

    mu: float
    T: float
    length: int
    n: np.ndarray
    energy: np.ndarray
    n_mean: float
    n_std: float
    W_mean: float
    W_std: float
    energy_per_particle: float
    wraps: int
    seconds: float
    counters: dict


def hold_fibre(particle, length: int, width: int, seed: int, *, g: float, mu: float, T: float, sweeps: int,
               equilibration: float = 0.5, blocks_per_sweep: int = 1, options: MonteCarloOptions | None = None
               ) -> GrandSample:
    """Seed a straight fibre of ``width`` rows wrapping a ``length x length`` box and hold it at
    temperature ``T`` and chemical potential ``mu``, recording its size.

    Parameters
    ----------
    particle : Hexagon or RandomHexagon
        The particle model (hexagon tiling).
    length, width : int
        As for ``fixed_size.fibre_seed``.
    seed : int
        Seed of the chain's generator, in [0, 2**64).
    g : float, keyword only
        Binding energy per bound pair of sides, spring units.
    mu : float, keyword only
        Chemical potential, spring units.
    T : float, keyword only
        Temperature, spring units, >= 0.
    sweeps : int, keyword only
        Sweeps held, a sweep being as many attempted moves as the seed has particles (>= 2).
    equilibration : float, keyword only
        Fraction of the sweeps left out of the means, in [0, 1).
    blocks_per_sweep : int, keyword only
        Records per sweep (>= 1).
    options : MonteCarloOptions or None, keyword only
        The chain's options; None: ``grand_options(mu)``. Their ``chemical_potential`` must be
        ``mu``.

    Returns
    -------
    GrandSample

    Raises
    ------
    ValueError
        A bad value, named (``mu`` not finite as ``chemical_potential``), or options whose
        chemical potential is not ``mu`` or without outline moves.
    """
    start = time.perf_counter()
    options = grand_options(mu) if options is None else options
    if not isinstance(options, MonteCarloOptions):
        raise TypeError(f"options must be a MonteCarloOptions, got {type(options).__name__}")
    if options.chemical_potential != float(mu) or options.outline_moves == 0:
        raise ValueError(f"options must have outline moves and chemical_potential = mu = {mu!r}, got "
                         f"outline_moves={options.outline_moves}, chemical_potential={options.chemical_potential}")
    T = non_negative("T", T)
    sweeps = integer("sweeps", sweeps, 2)
    blocks_per_sweep = integer("blocks_per_sweep", blocks_per_sweep, 1)
    equilibration = float(equilibration)
    if not 0 <= equilibration < 1:
        raise ValueError(f"equilibration must be in [0, 1), got {equilibration!r}")
    sites = fibre_seed(length, width)
    chain = _seeded_chain(particle, sites, length, seed, g, options)
    blocks = sweeps * blocks_per_sweep
    steps = max(1, len(sites) // blocks_per_sweep)
    out = chain.run(np.full(blocks, T), np.full(blocks, steps, dtype=np.int64))
    n, energy = np.asarray(out["n"], np.int64), np.asarray(out["energy"], float)
    late = slice(int(equilibration * blocks), blocks)
    W = n[late] / length
    wraps = clusters(np.asarray(chain.particles), length, particle.tiling)[0][1]
    return GrandSample(mu=float(mu), T=T, length=int(length), n=n, energy=energy, n_mean=float(n[late].mean()),
                       n_std=float(n[late].std()), W_mean=float(W.mean()), W_std=float(W.std()),
                       energy_per_particle=float(energy[late].mean() / n[late].mean()), wraps=int(wraps),
                       seconds=time.perf_counter() - start, counters=dict(chain.counters))


def threshold_width(mu, W_mean, energy_per_particle) -> tuple[float, float]:
    """The width and chemical potential where a scan crosses its threshold ``<E>/<n> = mu``
    (module docstring): ``W*`` at the scan's temperature.

    The crossing of ``energy_per_particle - mu`` through 0 between two consecutive ``mu`` of the
    scan, linearly interpolated (the first crossing from below).

    Parameters
    ----------
    mu : array_like, shape (k,)
        The scan's chemical potentials, increasing, k >= 2.
    W_mean : array_like, shape (k,)
        The mean width at each (``GrandSample.W_mean``).
    energy_per_particle : array_like, shape (k,)
        ``<E> / <n>`` at each (``GrandSample.energy_per_particle``).

    Returns
    -------
    W : float
        The width at the threshold, rows; nan when the scan does not cross it.
    mu_threshold : float
        The threshold's chemical potential; nan likewise.

    Raises
    ------
    ValueError
        Arrays of different lengths, fewer than two values, ``mu`` not increasing, or values not
        finite.

    Examples
    --------
    >>> from pyfrustrate.montecarlo.grand_canonical import threshold_width
    >>> threshold_width([-3.0, -2.0, -1.0], [10.0, 12.0, 16.0], [-2.5, -2.5, -2.5])
    (11.0, -2.5)
    """
    mu, W, e = (np.asarray(x, float) for x in (mu, W_mean, energy_per_particle))
    if not (mu.ndim == 1 and mu.shape == W.shape == e.shape and mu.size >= 2):
        raise ValueError(f"mu, W_mean and energy_per_particle must be 1D of one length >= 2, got shapes {mu.shape}, "
                         f"{W.shape}, {e.shape}")
    if not (np.all(np.isfinite(mu)) and np.all(np.isfinite(W)) and np.all(np.isfinite(e))):
        raise ValueError("mu, W_mean and energy_per_particle must be finite")
    if np.any(np.diff(mu) <= 0):
        raise ValueError(f"mu must be increasing, got {mu.tolist()}")
    gap = e - mu  # > 0 below the threshold (Omega > 0), < 0 above
    for k in range(mu.size - 1):
        if gap[k] >= 0 > gap[k + 1] or gap[k] == 0:
            t = gap[k] / (gap[k] - gap[k + 1]) if gap[k] != gap[k + 1] else 0.0
            return float(W[k] + t * (W[k + 1] - W[k])), float(mu[k] + t * (mu[k + 1] - mu[k]))
    return float("nan"), float("nan")
