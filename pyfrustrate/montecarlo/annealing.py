"""Monte Carlo annealing of aggregate topologies.

Main text, "Monte-Carlo validation of the phase diagram"; the snapshots of Fig. 3b.

``n`` particles occupy distinct sites of a periodic ``box x box`` patch of cells of the particle's
tiling (cell ``(i, j)`` at ``i a1 + j a2``, ``i, j`` modulo ``box``): ``box**2`` sites for hexagons,
``2 box**2`` (an up and a down triangle per cell) for triangles. A move takes a random particle
to a random empty site; the energy of a configuration is a sum over its connected clusters::

    E = sum over clusters of [ -g * bonds + relaxed deformation energy ],

the deformation energy being minimised at fixed topology before the Metropolis test, so the
temperature acts on the topology only. Simulated annealing lowers ``T`` to zero.

By default each move is first screened with the bond count alone (delayed acceptance,
Christen & Fox 2005: surrogate energy ``-(g - e_b/b) * bonds``, ``b`` the bonds per bulk
particle: 3 for hexagons, 3/2 for triangles), and clusters are relaxed only
for the moves that pass; the second stage accepts with the ratio of the true to the surrogate
Boltzmann factors. The chain samples exactly ``exp(-E/T)`` at every temperature, like plain
Metropolis (``delayed_acceptance=False``), with most relaxations skipped at low ``T``. At
``T = 0`` the run is a descent: every move that lowers the energy is taken.

The kernel (``kernel/montecarlo/``) recomputes only the clusters a move leaves and joins and
caches relaxed energies by shape up to translations and the symmetries the particle shares with
its tiling (hexagons: D3, the colour-preserving rotations by 120 degrees and mirrors, not the
60-degree rotations, which swap the yellow and red corners; random hexagons: C3, their ``M``
having no mirror symmetry; triangles: all twelve operations of the lattice). Each shape's energy
is computed from its canonical representative, so results do not depend on the cache. Clusters
that wrap around the box are relaxed as periodic aggregates (a straight fibre if they wrap in one
direction, a bulk cell if in two) with free period vectors: the box stands for an infinite
system.

Units: energies (``g``, temperatures, traces) are those of the particle's springs (``k``, lengths
in lattice spacings). ``continuum.particle_parameters(ell, nu, Gamma, eps=...)`` gives the ``g``
of a dimensionless line tension ``Gamma``.

Schedules (``schedule=``), temperatures in energy units:

``"linear"``
    ``T = T0 (1 - x)``, ``x`` the fraction of the run (0 on the first record block, 1 on the
    last), so the run ends at ``T = 0``.
``"geometric"``
    ``T = T0 (T_end / T0)**y`` from ``T0`` on the first block to ``T_end`` on the last but one
    (``y`` from 0 to 1), and ``T = 0`` on the last block.
a callable
    ``T = schedule(x)``, evaluated once per record block.
a sequence of stages
    ``(T, n_steps)`` pairs, run in order (``steps`` is then their sum). ``window_schedule``
    builds stages that dwell in an aggregate's reshaping window.

``T0`` defaults to ``g`` (the energy of one bond), or to the particle's bulk deformation energy per
particle when ``g = 0``. A record block is ``record_every`` attempted moves (default one sweep,
``n`` moves): the temperature is constant over a block and the energy is recorded after it.
"""
from __future__ import annotations

import hashlib
import os
import secrets
import time
from dataclasses import dataclass, field

import numpy as np

from .._checks import integer, non_negative
from .analysis import BoxState
from .checkpoints import read_checkpoint_file
from .driver import ChainState, box_run, chain_states_from_disk, drive, new_chain, particle_signature, save
from .options import chain_options
from .trajectory import Trajectory

__all__ = ["anneal", "AnnealResult", "AnnealState", "read_checkpoint", "SCHEDULES", "DEFAULT_SWEEPS",
           "window_schedule", "descend"]

SCHEDULES = ("linear", "geometric")
_CONTINUOUS_STAGES = 10  # acceptance is reported over tenths of a run without explicit stages
# Default length of a run, in sweeps of n attempted moves: the paper profile's sparse box
# (config/paper.yaml, montecarlo.sweeps), with the default moves (options.DEFAULTS_MEASURED).
DEFAULT_SWEEPS = 15_000


@dataclass
class AnnealState:
    """Where an annealing run stands: a value, what a checkpoint holds on disk.

    Pass it to ``anneal(..., state=)`` (with the run's parameters) to continue the run.

    Attributes
    ----------
    done : int
        Record blocks completed.
    chain : ChainState
        The kernel chain's state (sites, the ``std::mt19937_64`` state, the run's only random
        stream seeded by ``seed``, the running deformation energy, the counters).
    energy_trace : ndarray, shape (done,)
        Energy after each completed block, in the particle's spring units.
    accepted : ndarray, shape (done,), int
        Accepted moves in each completed block.
    elapsed : float
        Seconds spent so far.
    """

    done: int
    chain: ChainState = field(repr=False)  # type: ignore[valid-type]
    energy_trace: np.ndarray = field(repr=False)
    accepted: np.ndarray = field(repr=False)
    elapsed: float = 0.0

    @property
    def particles(self) -> np.ndarray:
        """Occupied sites, shape (n, 2) (or (n, 3) with a sublattice), in lattice coordinates."""
        return self.chain.particles

    @property
    def rng_state(self) -> str:
        """The chain's ``std::mt19937_64`` state, as text."""
        return self.chain.rng_state


@dataclass
class AnnealResult(BoxState):
    """Outcome of ``anneal``.

    Attributes
    ----------
    sites : ndarray, shape (n, 2), int
        Final lattice coordinates ``0 <= i, j < box`` of each particle (particle order), on the
        60-degree axes ``a1 = (1, 0)``, ``a2 = (1/2, sqrt(3)/2)``; shape (n, 3) for triangles (the
        third column the sublattice, 0 up, 1 down).
    box : int
        Box side, in lattice cells.
    n : int
        Number of particles.
    g : float
        Binding energy per bound pair of sides, in the particle's spring units (what ``Gamma=``
        was converted to).
    energy : float
        Final energy ``-g * bonds + deformation`` (running sum of the accepted moves), spring
        units.
    bonds : int
        Bound pairs of sides at the end.
    deformation : float
        Sum of the relaxed deformation energies of the final clusters.
    steps : ndarray, shape (B,), int
        Attempted moves done at the end of each record block.
    temperature : ndarray, shape (B,)
        Temperature of each record block.
    energy_trace : ndarray, shape (B,)
        Energy after each record block.
    accepted : ndarray, shape (B,), int
        Accepted moves in each record block.
    stage_acceptance : ndarray, shape (S,)
        Acceptance rate of each stage (the given stages, or tenths of the run).
    acceptance : float
        Overall acceptance rate.
    counters : dict
        Kernel counters: ``attempted, accepted, screened`` (identical on resumption) and ``bounded``
        (rejected at the second stage by a lower bound, without relaxing), ``cache_hits,
        cache_misses, cache_clears, minimisations, evaluations, fallbacks, unconverged`` (these
        depend on the cache, which a checkpoint does not save).
    seed : int
        The seed the run used (drawn when none was given).
    params : dict
        Everything that defines the run (particle, g, box, n, method, tol, schedule, ...).
    elapsed : float
        Wall time of this call, seconds.
    resumed : bool
        Whether the run started from a checkpoint or a given state.
    state : AnnealState
        Where the run stands at the end (to continue it: ``anneal(..., state=result.state)``).
    tiling : str
        The particle's tiling.
    """

    steps: np.ndarray = field(repr=False)
    temperature: np.ndarray = field(repr=False)
    energy_trace: np.ndarray = field(repr=False)
    accepted: np.ndarray = field(repr=False)
    stage_acceptance: np.ndarray = field(repr=False)
    acceptance: float
    counters: dict
    seed: int
    params: dict = field(repr=False)
    elapsed: float = 0.0
    resumed: bool = False
    tiling: str = "hexagon"
    state: AnnealState | None = field(default=None, repr=False)

    @property
    def cache_hit_rate(self) -> float:
        """Fraction of cluster energies taken from the cache (isolated particles excluded).

        Nan when no cluster was relaxed.
        """
        c = self.counters
        total = c["cache_hits"] + c["cache_misses"]
        return c["cache_hits"] / total if total else float("nan")


# ---------------------------------------------------------------------------------------------
# Schedule
# ---------------------------------------------------------------------------------------------

def _plan(steps, schedule, T0, T_end, record_every):
    """Record blocks: temperatures (B,), attempted moves (B,), stage index (B,), stage count."""
    if isinstance(schedule, str) or callable(schedule):
        if steps is None:
            raise ValueError("steps must be given with a continuous schedule")
        steps = integer("steps", steps, 1)
        n_blocks = -(-steps // record_every)
        block_steps = np.full(n_blocks, record_every, dtype=np.int64)
        block_steps[-1] = steps - record_every * (n_blocks - 1)
        x = np.arange(n_blocks) / (n_blocks - 1) if n_blocks > 1 else np.ones(1)
        if isinstance(schedule, str):
            if schedule == "linear":
                temps = T0 * (1.0 - x)
            elif schedule == "geometric":
                if T_end is None:
                    T_end = 1e-3 * T0
                T_end = non_negative("T_end", T_end)
                if not (0 < T_end <= T0):
                    raise ValueError(f"T_end must lie in (0, T0] for a geometric schedule, got {T_end!r}")
                xg = np.arange(n_blocks) / max(n_blocks - 2, 1)
                temps = T0 * (T_end / T0) ** xg if T0 > 0 else np.zeros(n_blocks)
                temps[-1] = 0.0
            else:
                raise ValueError(f"schedule must be one of {SCHEDULES}, a callable or a sequence of (T, steps) "
                                 f"stages, got {schedule!r}")
        else:
            temps = np.array([non_negative("schedule(x)", schedule(float(xi))) for xi in x])
        stage = np.minimum(_CONTINUOUS_STAGES * np.arange(n_blocks) // max(n_blocks, 1), _CONTINUOUS_STAGES - 1)
        return temps.astype(float), block_steps, stage, _CONTINUOUS_STAGES
    try:
        stages = [(s[0], s[1]) for s in schedule]
    except (TypeError, IndexError, KeyError):
        raise ValueError("schedule must be 'linear', 'geometric', a callable or a sequence of (T, steps) "
                         f"stages, got {schedule!r}") from None
    if not stages:
        raise ValueError("schedule: the sequence of stages is empty")
    temps, block_steps, stage_index = [], [], []
    for k, (t, m) in enumerate(stages):
        t = non_negative(f"schedule: temperature of stage {k}", t)
        m = integer(f"schedule: steps of stage {k}", m, 1)
        full, rest = divmod(m, record_every)
        chunks = [record_every] * full + ([rest] if rest else [])
        temps += [t] * len(chunks)
        block_steps += chunks
        stage_index += [k] * len(chunks)
    total = int(sum(block_steps))
    if steps is not None and integer("steps", steps, 1) != total:
        raise ValueError(f"steps ({steps}) disagrees with the stages of schedule (total {total}); leave steps=None")
    return np.array(temps, float), np.array(block_steps, np.int64), np.array(stage_index), len(stages)


def window_schedule(window, n: int, *, sweeps: int, T0: float, dwell: float = 0.8, quench: float = 0.05,
                    dwell_stages: int = 6, entry_stages: int = 4) -> list[tuple[float, int]]:
    """Stages for ``anneal(schedule=)`` that spend most of a run in the reshaping window.

    A linear schedule from ``g`` spends most of its sweeps above ~0.2 g, where aggregates melt,
    and a tenth in the window below it where they still reshape (their outline moves while they
    hold together; ``fixed_size.reshaping_temperature`` measures it from a heating ladder, and
    ``fixed_size.reshaping_window`` gives its ends). These stages instead:

    1. **enter**: ``entry_stages`` equal steps from ``T0`` down to the window's top (the gas
       condenses), with the fraction ``1 - dwell - quench`` of the sweeps;
    2. **dwell**: ``dwell_stages`` temperatures from the window's top to its bottom, geometric,
       with the fraction ``dwell``;
    3. **quench**: ``T = 0`` (a descent) with the fraction ``quench``.

    Each stage of a part gets an equal share of its sweeps (whole moves; the remainder goes to
    the part's last stage).

    Parameters
    ----------
    window : (float, float)
        The reshaping window's lowest and highest temperature, ``0 < low <= high``, in the
        particle's spring units (``fixed_size.reshaping_window``).
    n : int
        Particles: a sweep is ``n`` attempted moves.
    sweeps : int, keyword only
        Sweeps of the whole schedule.
    T0 : float, keyword only
        The first temperature, at least the window's top (``anneal``'s default is ``g``).
    dwell, quench : float, keyword only
        Fractions of the sweeps in the window and at ``T = 0``, positive, with ``dwell + quench
        <= 1`` (at 1 the entry is skipped: the run starts in the window).
    dwell_stages, entry_stages : int, keyword only
        Temperatures in the window (>= 1) and on the way down to it (>= 1).

    Returns
    -------
    list of (float, int)
        ``(T, attempted moves)`` stages, temperatures not increasing, ending with ``T = 0``.

    Raises
    ------
    ValueError
        A bad value, named; or a part too short to give each of its stages one move.

    Examples
    --------
    >>> from pyfrustrate.montecarlo.annealing import window_schedule
    >>> window_schedule((0.1, 0.2), 10, sweeps=100, T0=1.0, dwell=0.8, quench=0.1, dwell_stages=2,
    ...                 entry_stages=2)
    [(1.0, 50), (0.6, 50), (0.2, 400), (0.1, 400), (0.0, 100)]
    """
    try:
        low, high = (float(t) for t in window)
    except (TypeError, ValueError):
        raise ValueError(f"window must be a (lowest, highest) pair of temperatures, got {window!r}") from None
    if not (np.isfinite(low) and np.isfinite(high) and 0 < low <= high):
        raise ValueError(f"window must satisfy 0 < lowest <= highest (finite), got {window!r}")
    n = integer("n", n, 1)
    sweeps = integer("sweeps", sweeps, 1)
    T0 = non_negative("T0", T0)
    if T0 < high:
        raise ValueError(f"T0 ({T0!r}) must be at least the window's top ({high!r})")
    dwell_stages = integer("dwell_stages", dwell_stages, 1)
    entry_stages = integer("entry_stages", entry_stages, 1)
    fractions = {}
    for name, value in (("dwell", dwell), ("quench", quench)):
        value = non_negative(name, value)
        if not 0 < value <= 1:
            raise ValueError(f"{name} must lie in (0, 1], got {value!r}")
        fractions[name] = value
    if fractions["dwell"] + fractions["quench"] > 1 + 1e-12:
        raise ValueError(f"dwell + quench must be at most 1, got {dwell!r} + {quench!r}")
    total = sweeps * n
    moves = {part: int(round(fractions[part] * total)) for part in ("dwell", "quench")}
    moves["entry"] = total - moves["dwell"] - moves["quench"]
    temperatures = {
        # From T0 towards the window's top, which the dwell starts at.
        "entry": [T0 + (high - T0) * k / entry_stages for k in range(entry_stages)] if moves["entry"] > 0 else [],
        "dwell": list(np.geomspace(high, low, dwell_stages)) if dwell_stages > 1 else [high],
        "quench": [0.0],
    }
    stages = []
    for part in ("entry", "dwell", "quench"):
        temps = temperatures[part]
        if not temps:
            continue
        share, rest = divmod(moves[part], len(temps))
        if share < 1:
            raise ValueError(f"sweeps ({sweeps}) too few: the {part} part's {moves[part]} moves do not give each of "
                             f"its {len(temps)} stages one")
        stages += [(round(float(t), 12), share + (rest if k == len(temps) - 1 else 0)) for k, t in enumerate(temps)]
    return stages


def descend(particle, result: AnnealResult, *, options, sweeps_per_round: int = 20, max_rounds: int = 50,
            min_gain: float = 0.01, temperature: float = 0.0) -> tuple[AnnealResult, int, bool]:
    """Continue a run at ``T = 0`` until it stands in a local minimum of its moves.

    A schedule's last stage at ``T = 0`` is a descent (every move that does not raise the energy
    is taken) of a fixed length, which may end while moves that lower the energy remain, and then
    the energy reported is that of a state still on its way down. This continues the chain from
    ``result`` in rounds of ``sweeps_per_round`` sweeps at ``T = 0`` until a round lowers the
    energy by less than ``min_gain`` bonds' worth (``min_gain * g``; relaxation to the run's
    tolerance leaves energies uncertain well below that), or ``max_rounds`` rounds have run.

    At ``T = 0`` no move is screened by its bond count (delayed acceptance needs ``T > 0``), so
    every move that breaks bonds relaxes the clusters it changes before it is refused: in a box
    holding one large aggregate each such round costs as much as hundreds of rounds at a small
    positive temperature, where those moves are screened out (``exp(-g / T)`` per bond lost)
    while the bond-neutral and bond-making ones still run. ``temperature > 0`` runs the rounds
    there (the same stopping rule); a second call at ``T = 0`` then certifies the minimum, in
    fewer rounds than a descent at ``T = 0`` alone needs (``benchmarks/bench_large_runs.py``).

    Parameters
    ----------
    particle : Hexagon, RandomHexagon or Triangle
        The run's particle.
    result : AnnealResult
        The run to continue (its ``state``, ``g``, ``box``, ``n`` and ``seed``).
    options : MonteCarloOptions, keyword only
        The moves of the descent (the run's, or others: the chain's state does not depend on them).
    sweeps_per_round : int, keyword only
        Sweeps (``n`` attempted moves each) per round, >= 1.
    max_rounds : int, keyword only
        Most rounds, >= 1.
    min_gain : float, keyword only
        The least energy drop of a round, in units of ``g``, that starts another (>= 0).
    temperature : float, keyword only
        The rounds' temperature (>= 0, energy units): 0 (default) a descent, where every move
        that lowers the energy is taken; small and positive, a screened walk near the minimum.

    Returns
    -------
    (AnnealResult, int, bool)
        The last round's result (its ``energy``, ``sites``, ``state``), the rounds run, and
        whether the last one gained less than ``min_gain * g`` (a local minimum) rather than
        the rounds running out.

    Raises
    ------
    ValueError
        A bad value, named; a ``result`` without a state.

    Examples
    --------
    >>> from pyfrustrate import Hexagon
    >>> from pyfrustrate.montecarlo import MonteCarloOptions, anneal, descend
    >>> particle = Hexagon.from_continuum(ell=5.0, nu=0.9)
    >>> options = MonteCarloOptions(method="linear")
    >>> run = anneal(particle, Gamma=0.5, box=8, n=12, steps=120, seed=1, options=options, progress=False)
    >>> final, rounds, still = descend(particle, run, options=options, sweeps_per_round=5)
    >>> bool(final.energy <= run.energy and still)
    True
    """
    if not isinstance(result, AnnealResult) or result.state is None:
        raise ValueError("result must be an AnnealResult with its state (anneal's return value)")
    sweeps_per_round = integer("sweeps_per_round", sweeps_per_round, 1)
    max_rounds = integer("max_rounds", max_rounds, 1)
    min_gain = non_negative("min_gain", min_gain)
    temperature = non_negative("temperature", temperature)
    current, chain = result, result.state.chain
    for rounds in range(1, max_rounds + 1):
        start = AnnealState(done=0, chain=chain, energy_trace=np.zeros(0), accepted=np.zeros(0, np.int64))
        following = anneal(particle, g=result.g, box=result.box, n=result.n, seed=result.seed,
                           schedule=[(temperature, sweeps_per_round * result.n)], options=options, state=start,
                           progress=False)
        assert following.state is not None  # anneal always returns the state it ended in
        gain = current.energy - following.energy
        current, chain = following, following.state.chain
        if gain < min_gain * result.g:
            return current, rounds, True
    return current, max_rounds, False


def _schedule_description(schedule):
    if isinstance(schedule, str):
        return schedule
    if callable(schedule):
        return getattr(schedule, "__name__", "callable")
    return [(float(t), int(m)) for t, m in schedule]


# ---------------------------------------------------------------------------------------------
# Checkpoints
# ---------------------------------------------------------------------------------------------

def read_checkpoint(path, signature=None) -> AnnealState:
    """The ``AnnealState`` an ``anneal`` checkpoint holds.

    Parameters
    ----------
    path : str or path-like
        The checkpoint file (``anneal(..., checkpoint=path)``).
    signature : dict or None, optional
        A run's defining parameters (``result.params`` holds them); the file is refused when it
        was written by a run with other ones. None accepts any ``anneal`` checkpoint.

    Returns
    -------
    AnnealState
        The state to pass to ``anneal(..., state=)``.

    Raises
    ------
    FileNotFoundError
        No file at ``path``.
    ValueError
        The file is not a checkpoint of an ``anneal`` run (empty, truncated, another format or
        version, another kind of run) or, with ``signature``, of this run; the message names it
        (``checkpoints``).
    """
    metadata, arrays = read_checkpoint_file(path, "anneal", signature)
    chain, = chain_states_from_disk(path, metadata, arrays)
    try:
        return AnnealState(done=int(metadata["done"]), chain=chain, energy_trace=np.asarray(arrays["energy_trace"], float),
                           accepted=np.asarray(arrays["accepted"], np.int64), elapsed=float(metadata["elapsed"]))
    except (KeyError, TypeError, ValueError) as e:
        raise ValueError(f"checkpoint: {path!r} holds an incomplete anneal state ({type(e).__name__}: {e}); delete it "
                         "or pass another checkpoint path to start the run afresh") from None


def _save(path, signature, params, state: AnnealState) -> None:
    save(path, "anneal", signature, [state.chain], dict(done=state.done, elapsed=state.elapsed, params=params),
         dict(energy_trace=state.energy_trace, accepted=state.accepted))


# ---------------------------------------------------------------------------------------------
# The annealing
# ---------------------------------------------------------------------------------------------

def anneal(particle, *, g=None, Gamma=None, convention="measured", box=60, n=200, steps=None, schedule="linear",
           seed=None, options=None, checkpoint=None, progress=True, T0=None, T_end=None, record_every=None,
           checkpoint_interval=60.0, callback=None, state=None, trajectory=None, trajectory_every=None,
           **option_fields) -> AnnealResult:
    """Simulated annealing of the topology of ``n`` particles in a periodic ``box x box`` lattice.

    The defaults are the best settings measured for the paper's sparse box (moves, schedule,
    method; ``options.DEFAULTS_MEASURED`` names where): Newton cluster energies (``method="auto"``,
    as ``relax``) warm-started from the parents' relaxed state, the linear schedule from
    ``T0 = g``, and the mix of cluster, bonded and surface moves whose values ``MonteCarloOptions``
    lists (its defaults are the kernel's, read from its option table).
    What they reach on the issue's bar case (400 hexagons in 60 x 60, nu = 0.9, Gamma = 0.3,
    seed 1) against the best single aggregate, and at what CPU cost, beside the former defaults
    (L-BFGS, particle moves only): ``benchmarks/bench_anneal_defaults.py`` writes
    ``benchmarks/results/anneal_defaults.csv``, which the Monte Carlo topic page of the
    documentation quotes.

    Parameters
    ----------
    particle : Hexagon, RandomHexagon or Triangle (any ``particles.Particle``)
        Anything else raises ``TypeError``.
    g : float, keyword only
        Binding energy per bound pair of sides (>= 0), in the units of the particle's springs
        (``k = 1`` for ``Hexagon.from_continuum``): the energy ``-g`` of each pair of touching
        sides. Not the dimensionless ``Gamma``: at ell = 5, nu = 0.9, eps = 0.01 the paper's
        ``Gamma = 0.5`` is ``g = 0.0078`` (``continuum.particle_parameters``), so a ``Gamma``
        passed as ``g`` binds 64 times too strongly.
    Gamma : float, keyword only
        Or the dimensionless line tension (spring particles ``Hexagon`` and ``Triangle``),
        converted to ``g`` (``options.binding``) in ``convention``. Exactly one of ``g`` and
        ``Gamma``, by keyword.
    convention : {"measured", "supplement"}, keyword only
        How ``Gamma`` maps to ``g`` (``continuum.BINDING_CONVENTIONS``, the ``continuum`` module
        docstring): ``"measured"`` (default, every figure) line tension ``gamma = g`` on hexagons
        (``g / 2`` on triangles); ``"supplement"`` the printed ``gamma = 4 g / sqrt(3)`` (hexagons
        only), so the same ``Gamma`` binds ``sqrt(3)/4 = 0.433`` times as strongly. Ignored with
        ``g``.
    box : int
        Box side in lattice cells (>= 2). The paper: 60 (200 particles) and 30 (300 particles).
    n : int
        Number of particles, fewer than the box's sites (``box**2`` cells times the tiling's
        sublattices).
    steps : int
        Attempted moves in all (with a continuous schedule). Default ``DEFAULT_SWEEPS * n``.
    schedule : "linear", "geometric", callable or sequence of (T, steps)
        Temperature schedule (module docstring).
    seed : int or None
        Seed of the kernel's ``std::mt19937_64`` (``0 <= seed < 2**64``); None draws one, which the
        result records.
    options : MonteCarloOptions or None
        The chain's moves and relaxation, checked once (``MonteCarloOptions``); its fields may
        also be given as keywords (``method="lbfgs"``, ``cluster_moves=0``, ...), which replace
        those of ``options``. The fields:

        ``method`` {"auto", "newton", "lbfgs", "linear"}: cluster relaxation. ``"auto"``
        (default) runs ``relaxation.AUTO_METHOD``, Newton: the relaxed energy to ``tol`` by
        Newton steps from the linear solution (faster than L-BFGS in sparse and dense boxes:
        benchmarks/bench_montecarlo.py measures both); ``"lbfgs"``: the same minimum by L-BFGS
        warm-started from the linear solution (``warm_start=False``: from the bulk reference);
        ``"linear"``: the linearised solve alone, faster than Newton in a dense box but biased
        upwards for loosely bound clusters (the bias is measured by benchmarks/bench_tradeoff.py,
        ``figX_speed_accuracy``): an approximation.

        ``tol``: relaxation tolerance, relative as in ``relax``: max gradient <=
        ``tol * particle.force_scale``. The default leaves relative energy errors far below what
        changes a Metropolis decision (benchmarks/bench_tradeoff.py measures them).

        ``warm_start``: with Newton, relax the clusters a move makes from the relaxed
        displacements of the clusters they came from (the moved particle rigidly attached;
        exact Hessian from the first step) where every other particle's is known, instead of
        from the linear solution of the canonical representative; with L-BFGS, start from the
        linear solution. Energies then agree with the cold start's to the tolerance, not to the
        last bit: they depend on the path and on the cache at that level, so a run resumed from
        a checkpoint (empty cache, no stored displacements) follows the uninterrupted one within
        the tolerance rather than bit for bit. ``warm_start=False`` (or ``method="lbfgs"``) makes
        resumption exact.

        ``parent_factor`` (with Newton and ``warm_start``): a cluster a move changes by a few
        particles relaxes by chord steps on its parent cluster's Hessian factor, modified for the
        particles that came and went, instead of factorising its own; clusters of at least
        ``parent_factor_min_particles`` particles keep their factor for their children (one
        factor per cluster of the box). Energies stay exact to the tolerance.

        ``delayed_acceptance``: screen each move first with the surrogate energy
        ``-(g - e_b/b) * bonds`` (``e_b`` the bulk deformation energy per particle, ``b`` the
        bonds per bulk particle), relaxing clusters only for moves that pass, then accept with
        the ratio of the true to the surrogate Boltzmann factors (Christen & Fox 2005): the same
        Boltzmann distribution as plain Metropolis (``False``), most relaxations skipped at low T.

        ``cluster_moves`` in [0, 1]: the probability that a move shifts a set of bonded particles
        by a uniformly random lattice vector, the set grown from a random particle by following
        each bond with probability ``cluster_link`` in [0, 1], accepted with
        ``min(1, exp(-dE/T) (1 - cluster_link)**(b' - b))`` (b, b' the bonds between the set and
        the rest before and after): aggregates diffuse, and below link 1 merge in one move (the
        reverse move splits them). Link 1 moves whole clusters, rejected on any new contact.

        ``bonded_moves`` in [0, 1): the probability that a particle move takes the particle next
        to a random other particle instead of to a random empty site (aggregation-volume-bias,
        Chen & Siepmann 2000), with the ratio of reverse to forward proposal probabilities.

        ``surface_moves`` in [0, 1): the probability that a move (other than a cluster move)
        takes a random particle with an empty neighbour to a random empty site with an occupied
        neighbour, with the ratio ``n_s n_p / (n_s' n_p')`` of those counts before and after
        (refused when the reverse move could not be proposed): the bond-neutral jumps between the
        kinks of an aggregate's outline, proposed far more often than by the other moves.

        ``shift_moves``, ``rotation_moves``, ``reflection_moves`` in [0, 1] (0 by default): the
        probabilities of the collective isometry moves, a set grown from a random seed particle
        (each bond followed with probability ``isometry_link``) shifted to a neighbouring site,
        turned by +-60 degrees about the seed's site or mirrored about an axis through it,
        accepted with ``min(1, exp(-dE/T) (1 - isometry_link)**(b' - b))``: they straighten and
        compact aggregates in place. Hexagon tiling only for turns and mirrors (a ``ValueError``
        from the run otherwise).

        ``carry_moves`` in [0, 1] (0 by default): the probability of a carry, a set grown with
        ``cluster_link`` (a whole disk, or a lobe of a raft) translated by a cell vector of at most
        three neighbour steps, each of the 36 equally likely, accepted with ``min(1, exp(-dE/T)
        (1 - cluster_link)**(b' - b))``: meant to slide disks that touch at a corner into contact
        along a facet (at nu = 0.4 it did not make the large box's disks fuse: the Monte Carlo
        topic page of the documentation).

        ``max_iter``: cap on energy evaluations per L-BFGS relaxation; ``cache``: the cache of
        relaxed energies by shape (speed only).
    checkpoint : path or None
        File to resume from if it exists (same parameters required) and to save to every
        ``checkpoint_interval`` seconds, on interruption (KeyboardInterrupt or any exception, the
        last completed chunk is saved) and at the end: a data-only archive (``checkpoints``),
        written atomically. A file that is not a checkpoint of this run is refused with a
        ``ValueError`` naming it. The cluster cache is not saved: it only affects speed. A
        finished checkpoint is returned as is.
    progress : bool
        Show a tqdm progress bar.
    T0, T_end : float
        Start temperature (default ``g``, or the bulk energy per particle when ``g = 0``) and the
        geometric schedule's last non-zero one (default ``T0 / 1000``), in energy units (the
        particle's springs, as ``g``).
    record_every : int
        Attempted moves per record block (default ``n``, one sweep).
    checkpoint_interval : float
        Seconds between checkpoint saves (with ``checkpoint``).
    callback : callable or None
        Called after every chunk of blocks as ``callback(steps_done, total_steps, energy)``; an
        exception raised there stops the run after saving the checkpoint.
    state : AnnealState or None
        Continue from this state (a run's ``result.state``, or ``read_checkpoint``), with the
        same parameters; it is not modified. Takes precedence over an existing checkpoint file.
    trajectory : path or None
        Write snapshots to this GSD file (HOOMD-blue's format, read by OVITO and freud;
        ``trajectory.Trajectory``): every ``trajectory_every`` record blocks (default: about 100
        frames over the run) the occupied sites' positions, type, the box, the step and the
        energy. A resumed run continues the file from its state.
    trajectory_every : int or None
        Record blocks between trajectory frames (default: about 100 frames over the run).
    **option_fields
        Fields of ``MonteCarloOptions`` (see ``options``), replacing those of ``options``.

    Returns
    -------
    AnnealResult
        The final configuration (``sites``, ``energy``, ``bonds``, ``deformation``), the traces
        per record block, acceptance rates, kernel counters, the ``params`` and ``seed`` that
        define the run, and the ``state`` to continue it.

    Raises
    ------
    TypeError
        ``particle`` is not a particle model, or an unknown keyword.
    ValueError
        Any other bad input, naming the parameter (``g`` and ``Gamma`` both or neither, a
        checkpoint of another run, too many particles for the box, ...).

    See Also
    --------
    replica_exchange : Sampling at fixed temperatures, from the same chain.
    read_checkpoint : The state an ``anneal`` checkpoint holds.

    Examples
    --------
    Ten hexagons at the paper's point (ell = 5, nu = 0.9, Gamma = 0.5, in the measured convention)
    in a 6 x 6 box, 20 sweeps of a linear schedule, with a fixed seed:

    >>> from pyfrustrate import Hexagon
    >>> from pyfrustrate.montecarlo import anneal
    >>> particle = Hexagon.from_continuum(ell=5.0, nu=0.9)
    >>> result = anneal(particle, Gamma=0.5, box=6, n=10, steps=200, seed=1, progress=False)
    >>> round(result.g, 8)  # Gamma=0.5 as a binding energy per bond, spring units
    0.00781588
    >>> result.sites.shape, len(result.energy_trace), int(result.steps[-1])
    ((10, 2), 20, 200)
    >>> bool(abs(result.energy - (-result.g * result.bonds + result.deformation)) < 1e-12)
    True

    The same binding given as ``g``, with the same seed, is the same run:

    >>> again = anneal(particle, g=result.g, box=6, n=10, steps=200, seed=1, progress=False)
    >>> bool(again.bonds == result.bonds and (again.sites == result.sites).all())
    True
    """
    g, box, n = box_run(particle, Gamma, g, convention, box, n)
    opts = chain_options(options, option_fields)
    if seed is None:
        seed = secrets.randbits(63)
    seed = integer("seed", seed, 0, 2**64 - 1)
    record_every = n if record_every is None else integer("record_every", record_every, 1)
    if T0 is None:
        T0 = g if g > 0 else particle.bulk_energy_per_particle
    T0 = non_negative("T0", T0)
    if steps is None and (isinstance(schedule, str) or callable(schedule)):
        steps = DEFAULT_SWEEPS * n
    temps, block_steps, stage_of_block, n_stages = _plan(steps, schedule, T0, T_end, record_every)
    total_steps = int(block_steps.sum())
    cum_steps = np.cumsum(block_steps)
    writer = Trajectory.for_run(trajectory, trajectory_every, particle, box, len(temps))

    plan_digest = hashlib.sha256(temps.tobytes() + block_steps.tobytes()).hexdigest()
    signature = dict(particle=particle_signature(particle), g=g, box=box, n=n, seed=seed, **opts.signature(),
                     plan=plan_digest)
    params = dict(signature, particle_type=type(particle).__name__, schedule=_schedule_description(schedule),
                  T0=T0, T_end=T_end, steps=total_steps, record_every=record_every, cache=opts.cache,
                  bond_deformation=opts.kernel_arguments(particle)["bond_deformation"])

    energies, accepted = [], []
    done, elapsed_before, resumed = 0, 0.0, False
    if state is None and checkpoint is not None and os.path.exists(checkpoint):
        state = read_checkpoint(checkpoint, signature)
    if state is not None:
        if not isinstance(state, AnnealState):
            raise ValueError(f"state must be an AnnealState, got {type(state).__name__}")
        if not 0 <= state.done <= len(temps) or len(state.energy_trace) != state.done:
            raise ValueError(f"state: {state.done} blocks done does not fit this run's {len(temps)} blocks")
        energies, accepted = list(state.energy_trace), list(state.accepted)
        done, elapsed_before, resumed = int(state.done), float(state.elapsed), True
    mc = new_chain(particle, g, box, n, seed, opts, state=state.chain if state is not None else None)

    start = time.perf_counter()

    def snapshot(blocks_done):
        return AnnealState(done=blocks_done, chain=mc.state, energy_trace=np.asarray(energies[:blocks_done], float),
                           accepted=np.asarray(accepted[:blocks_done], np.int64),
                           elapsed=elapsed_before + time.perf_counter() - start)

    last = snapshot(done)
    chunk = 1
    if writer is not None:
        writer.open(int(cum_steps[done - 1]) if done else 0)

    def advance(done):
        nonlocal last, chunk
        lo, hi = done, min(len(temps), done + chunk)
        t = time.perf_counter()
        out = mc.run(temps[lo:hi], block_steps[lo:hi], writer is not None)
        dt = time.perf_counter() - t
        energies.extend(out["energy"].tolist())
        accepted.extend(out["accepted"].tolist())
        if writer is not None:
            writer.write_blocks(out["sites"], cum_steps[lo:hi], out["energy"], temps[lo:hi], first_block=lo)
        last = snapshot(hi)
        moves = int(block_steps[lo:hi].sum())
        rate = float(np.sum(out["accepted"])) / max(1, moves)
        # Chunks of about half a second and at most 1% of the run: prompt progress and
        # interruption. (Chunking does not change the chain.)
        chunk = int(min(max(1, chunk * 0.5 / max(dt, 1e-3)), 2 * chunk + 1, max(1, len(temps) // 100)))
        if callback is not None:
            callback(int(cum_steps[hi - 1]), total_steps, energies[-1])
        return hi, dict(T=f"{temps[hi - 1]:.3g}", E=f"{energies[-1]:.5g}", acc=f"{rate:.3f}")

    try:
        drive(done, len(temps), advance, lambda: _save(checkpoint, signature, params, last), checkpoint=checkpoint,
              checkpoint_interval=checkpoint_interval, progress=progress, desc=f"anneal n={n} box={box}", unit="move",
              position=lambda d: int(cum_steps[d - 1]) if d else 0, scale=total_steps)
    finally:
        if writer is not None:
            writer.close()

    energy_trace, accepted_per_block = np.asarray(energies, float), np.asarray(accepted, np.int64)
    stage_attempted = np.bincount(stage_of_block, weights=block_steps, minlength=n_stages)
    stage_accepted = np.bincount(stage_of_block, weights=accepted_per_block, minlength=n_stages)
    with np.errstate(invalid="ignore", divide="ignore"):
        stage_acceptance = stage_accepted / stage_attempted
    return AnnealResult(sites=np.asarray(mc.particles), box=box, n=n, g=g, energy=float(mc.energy),
                        bonds=int(mc.bonds), deformation=float(mc.deformation), steps=cum_steps.copy(),
                        temperature=temps, energy_trace=energy_trace, accepted=accepted_per_block,
                        stage_acceptance=stage_acceptance,
                        acceptance=float(accepted_per_block.sum() / max(1, total_steps)), counters=mc.counters,
                        seed=seed, params=params, elapsed=time.perf_counter() - start, resumed=resumed,
                        tiling=particle.tiling, state=last)
