"""Replica exchange (parallel tempering) over temperature for the aggregation Monte Carlo.

``K`` copies of the box (replicas) run the same chain as ``anneal`` (the same ``MonteCarloOptions``), each at one temperature of a ladder
``T_1 < ... < T_K``. After every round of ``exchange_every`` attempted moves per replica,
neighbouring temperatures offer to swap their configurations, accepted with probability::

    min(1, exp[(1/T_s - 1/T_{s+1}) (E_s - E_{s+1})])

(even pairs on even rounds, odd pairs on odd ones). Each replica's moves keep ``exp(-E/T)`` at its
temperature and the swaps keep the product of these, so every slot samples its own Boltzmann
distribution exactly (tested against exact enumeration) while configurations travel up the ladder,
where aggregates melt and re-form, and back down: the hot end does the coarsening that a cooling
schedule leaves undone. A swap exchanges the temperatures of two replicas (each replica keeps its
configuration, cache and random stream), so the kernel chains never copy a box.

Replicas run in threads (the kernel releases the GIL): on 2 cores, two replicas at a time.

Random streams (all from ``seed``, ``numpy.random.SeedSequence``): child ``k`` of the sequence
seeds replica ``k``'s kernel ``std::mt19937_64``; child ``K`` drives the swap decisions.

The state is a value (``ReplicaState``): replicas' occupancies, random states, deformation
energies and counters, which temperature each holds, the swap stream and the traces. A run
resumes from one passed in (``state=``) or from a checkpoint file holding one.
"""
from __future__ import annotations

import copy
import hashlib
import math
import os
import secrets
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from .._checks import integer
from .analysis import BoxState
from .checkpoints import read_checkpoint_file
from .driver import box_run, chain_states_from_disk, drive, new_chain, particle_signature, save
from .options import chain_options
from .trajectory import Trajectory

__all__ = ["replica_exchange", "geometric_temperatures", "ReplicaState", "ReplicaExchangeResult", "read_checkpoint"]


def geometric_temperatures(T_min: float, T_max: float, count: int) -> np.ndarray:
    """``count`` temperatures from ``T_min`` to ``T_max`` in geometric progression.

    The usual ladder when the heat capacity varies slowly (equal swap rates between neighbours).

    Parameters
    ----------
    T_min, T_max : float
        The coldest and the hottest temperature, ``0 < T_min < T_max``, finite, in energy units
        (the particle's springs, as ``g``).
    count : int
        Number of temperatures, at least 2.

    Returns
    -------
    ndarray, shape (count,)
        The increasing ladder, from ``T_min`` to ``T_max`` inclusive.

    Raises
    ------
    ValueError
        Temperatures not positive, finite and increasing, or ``count`` below 2.

    Examples
    --------
    >>> from pyfrustrate.montecarlo import geometric_temperatures
    >>> geometric_temperatures(0.001, 0.1, 3).round(6).tolist()
    [0.001, 0.01, 0.1]
    """
    if not (math.isfinite(T_min) and math.isfinite(T_max) and 0 < T_min < T_max):
        raise ValueError(f"temperatures: need 0 < T_min < T_max, finite, got T_min={T_min!r}, T_max={T_max!r}")
    count = integer("count", count, 2)
    return np.geomspace(T_min, T_max, count)




@dataclass
class ReplicaState:
    """Everything a replica-exchange run needs to continue: a value.

    Pass it to ``replica_exchange(..., state=)`` (with the run's parameters) to continue the run.

    Attributes
    ----------
    replicas : list of ChainState
        Each replica's kernel chain state (``driver``), K of them.
    slot_of_replica : ndarray, shape (K,), int
        The temperature index replica ``k`` holds.
    swap_rng : dict
        The bit-generator state of the swap stream.
    rounds : int
        Rounds done.
    energy : list of ndarray, each shape (K,)
        The energy at each temperature after each round (spring units).
    swaps_attempted, swaps_accepted : ndarray, shape (K - 1,), int
        Swap offers and acceptances per neighbouring pair of temperatures.
    best_energy : float
        The lowest energy seen at the coldest temperature after a round.
    best_sites : ndarray, shape (n, 2) (or (n, 3)), or None
        Its sites, in lattice coordinates.
    round_trips : int
        How many times a replica came back to the coldest temperature after reaching the hottest.
    last_end : ndarray, shape (K,), int
        The end of the ladder each replica last visited (0 coldest, K - 1 hottest, -1 neither yet).
    """

    replicas: list
    slot_of_replica: np.ndarray
    swap_rng: dict
    rounds: int = 0
    energy: list = field(default_factory=list)
    swaps_attempted: np.ndarray | None = None
    swaps_accepted: np.ndarray | None = None
    best_energy: float = math.inf
    best_sites: np.ndarray | None = None
    round_trips: int = 0
    last_end: np.ndarray | None = None


@dataclass
class ReplicaExchangeResult(BoxState):
    """Outcome of ``replica_exchange``.

    Attributes
    ----------
    sites : ndarray, shape (n, 2) (or (n, 3) for triangles), int
        The coldest temperature's configuration after the final zero-temperature descent, in
        lattice coordinates (60-degree axes ``a1``, ``a2``; the third column the sublattice).
    box : int
        Box side, in lattice cells.
    n : int
        Number of particles.
    g : float
        Binding energy per bound pair of sides, spring units.
    energy : float
        ``-g * bonds + deformation`` of ``sites``, spring units.
    bonds : int
        Bound pairs of sides of ``sites``.
    deformation : float
        Relaxed deformation energy of ``sites``' clusters, spring units.
    temperatures : ndarray, shape (K,)
        The ladder.
    energy_trace : ndarray, shape (rounds, K)
        The energy at each temperature after each round.
    swap_acceptance : ndarray, shape (K - 1,)
        Swap acceptance of each neighbouring pair (nan for a pair never offered a swap).
    round_trips : int
        Replicas that went from the coldest to the hottest temperature and back.
    best_energy : float
        The lowest energy seen at the coldest temperature after a round.
    best_sites : ndarray, shape (n, 2) (or (n, 3))
        Its sites.
    state : ReplicaState
        The final state (to continue the run), before the descent.
    counters : dict
        Kernel counters summed over replicas (as ``AnnealResult.counters``).
    seed : int
        The seed of every stream of the run.
    params : dict
        Everything that defines the run.
    elapsed : float
        Wall time of this call, seconds.
    resumed : bool
        Whether the run started from a checkpoint or a given state.
    tiling : str
        The particle's tiling.
    """

    temperatures: np.ndarray = field(repr=False)
    energy_trace: np.ndarray = field(repr=False)
    swap_acceptance: np.ndarray
    round_trips: int
    best_energy: float
    best_sites: np.ndarray = field(repr=False)
    state: ReplicaState = field(repr=False)
    counters: dict
    seed: int
    params: dict = field(repr=False)
    elapsed: float = 0.0
    resumed: bool = False
    tiling: str = "hexagon"


def _streams(seed: int, count: int):
    """The run's random streams, all from ``seed``: the kernel seed of each replica and the swap
    generator."""
    children = np.random.SeedSequence(seed).spawn(count + 1)
    replica_seeds = [int(c.generate_state(1, np.uint64)[0]) for c in children[:count]]
    return replica_seeds, np.random.default_rng(children[count])



def replica_exchange(particle, temperatures, *, g=None, Gamma=None, convention="measured", box=60, n=200, rounds=1000,
                     exchange_every=None, seed=None, options=None, quench_sweeps=50, threads=None, state=None,
                     checkpoint=None, checkpoint_interval=60.0, progress=True, record_sites=False, initial_sites=None,
                     trajectory=None, trajectory_every=None, **option_fields) -> ReplicaExchangeResult:
    """Replica exchange of ``n`` particles in a periodic ``box x box`` lattice (module docstring).

    Parameters
    ----------
    particle : any particle model (Hexagon, RandomHexagon, Triangle)
        Anything else raises ``TypeError``.
    temperatures : sequence of float
        The ladder, increasing, positive (``geometric_temperatures``); at least two.
    g : float, keyword only
        The binding energy per bound pair of sides (>= 0), in the particle's spring units, as in
        ``anneal`` (not the dimensionless ``Gamma``).
    Gamma : float, keyword only
        Or the dimensionless line tension (``Hexagon``, ``Triangle``), converted to ``g`` in
        ``convention``. Exactly one of ``g`` and ``Gamma``, by keyword.
    convention : {"measured", "supplement"}, keyword only
        How ``Gamma`` maps to ``g``, as in ``anneal``: ``"measured"`` (default) ``gamma = g``,
        ``"supplement"`` the printed ``gamma = 4 g / sqrt(3)``.
    box, n : int
        As in ``anneal``.
    rounds : int
        Exchange rounds; each replica attempts ``exchange_every`` moves per round (default ``n``,
        one sweep), so a run costs ``K * rounds * exchange_every`` moves.
    exchange_every : int or None
        Attempted moves per replica between two swap rounds (default ``n``).
    seed : int or None
        Seeds every stream of the run (module docstring); None draws one, which the result records.
    options : MonteCarloOptions or None
        The chain of each replica, as in ``anneal`` (the same defaults).
    quench_sweeps : int
        Sweeps at T = 0 (a descent: every move that lowers the energy is taken) of the coldest
        replica's final configuration, done on a copy so that ``state`` continues the sampling.
    threads : int or None
        Replicas run concurrently (default: the machine's cores, at most K).
    state : ReplicaState or None
        Continue from this state (same parameters); it is not modified.
    checkpoint : path or None
        File to resume from if it exists (same parameters) and to save the state to every
        ``checkpoint_interval`` seconds, on interruption and at the end: a data-only archive
        (``checkpoints``), written atomically; any other file is refused with a ``ValueError``.
    checkpoint_interval : float
        Seconds between checkpoint saves (with ``checkpoint``).
    progress : bool
        Show a tqdm progress bar.
    record_sites : bool
        Keep, in the result's ``params["sites_by_slot"]``, the sites at every temperature after
        every round (for tests; memory ``rounds * K * n`` integers).
    initial_sites : (n, 2) array (or (n, 3) with a sublattice) or None
        Start every replica from these sites (as ``BoxState.sites``: a finished anneal's
        configuration, to sample around it at low temperature) instead of particles at random.
        Ignored when resuming. Part of the checkpoint's parameters.
    trajectory : path or None
        Write the coldest temperature's configuration to this GSD file every
        ``trajectory_every`` rounds (default: about 100 frames), as ``anneal`` does
        (``configuration.step``: the round).
    trajectory_every : int or None
        Rounds between trajectory frames (default: about 100 frames over the run).
    **option_fields
        Fields of ``MonteCarloOptions``, replacing those of ``options``.

    Returns
    -------
    ReplicaExchangeResult
        The coldest temperature's configuration after a descent, the energy traces, swap
        acceptances, round trips, the best configuration seen and the ``state`` to continue.

    Raises
    ------
    TypeError
        ``particle`` is not a particle model, or an unknown keyword.
    ValueError
        Any other bad input, naming the parameter (as in ``anneal``).

    See Also
    --------
    anneal : Simulated annealing, from the same chain.
    geometric_temperatures : The usual ladder.

    Examples
    --------
    Ten hexagons at ell = 5, nu = 0.9 in a 6 x 6 box, the binding given as a binding energy per
    bond (``g``, spring units: the paper's ``Gamma = 0.5`` in the measured convention), three
    temperatures from a tenth of ``g`` to ``g``, 5 rounds, one thread, a fixed seed:

    >>> from pyfrustrate import Hexagon
    >>> from pyfrustrate.montecarlo import geometric_temperatures, replica_exchange
    >>> particle = Hexagon.from_continuum(ell=5.0, nu=0.9)
    >>> g = 0.00781588
    >>> ladder = geometric_temperatures(0.1 * g, g, 3)
    >>> result = replica_exchange(particle, ladder, g=g, box=6, n=10, rounds=5, threads=1, seed=2,
    ...                           quench_sweeps=5, progress=False)
    >>> result.energy_trace.shape, result.swap_acceptance.shape, result.sites.shape
    ((5, 3), (2,), (10, 2))
    >>> bool(abs(result.energy - (-g * result.bonds + result.deformation)) < 1e-12)
    True
    >>> bool(result.best_energy <= result.energy_trace[:, 0].min())
    True
    """
    g, box, n = box_run(particle, Gamma, g, convention, box, n)
    try:
        T = np.asarray(temperatures, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ValueError(f"temperatures must be a sequence of numbers, got {temperatures!r}") from None
    if T.size < 2 or not np.all(np.isfinite(T)) or T[0] <= 0 or np.any(np.diff(T) <= 0):
        raise ValueError(f"temperatures must be at least two positive, finite, increasing values, got {T.tolist()}")
    K = T.size
    rounds = integer("rounds", rounds, 0)
    exchange_every = n if exchange_every is None else integer("exchange_every", exchange_every, 1)
    quench_sweeps = integer("quench_sweeps", quench_sweeps, 0)
    opts = chain_options(options, option_fields)
    threads = min(K, os.cpu_count() or 1) if threads is None else integer("threads", threads, 1)
    if seed is None:
        seed = secrets.randbits(63)
    seed = integer("seed", seed, 0, 2**63 - 1)
    writer = Trajectory.for_run(trajectory, trajectory_every, particle, box, rounds)

    signature = dict(particle=particle_signature(particle), g=g, box=box, n=n, seed=seed,
                     temperatures=hashlib.sha256(T.tobytes()).hexdigest(), exchange_every=exchange_every,
                     **opts.signature())
    if initial_sites is not None:
        try:
            initial_sites = np.ascontiguousarray(initial_sites, dtype=np.int32)
        except (TypeError, ValueError):
            raise ValueError(f"initial_sites must be an integer array of sites, got {initial_sites!r}") from None
        signature["initial_sites"] = hashlib.sha256(initial_sites.tobytes()).hexdigest()
    replica_seeds, swap_rng = _streams(seed, K)

    resumed = False
    if state is None and checkpoint is not None and os.path.exists(checkpoint):
        state = read_checkpoint(checkpoint, signature)
    if state is not None:
        if not isinstance(state, ReplicaState):
            raise ValueError(f"state must be a ReplicaState, got {type(state).__name__}")
        state = copy.deepcopy(state)
        if len(state.replicas) != K:
            raise ValueError(f"state has {len(state.replicas)} replicas, the ladder {K} temperatures")
        chains = [new_chain(particle, g, box, n, s, opts, state=saved) for s, saved in zip(replica_seeds, state.replicas)]
        swap_rng.bit_generator.state = state.swap_rng
        resumed = True
    else:
        chains = [new_chain(particle, g, box, n, s, opts) for s in replica_seeds]
        if initial_sites is not None:
            try:
                for mc in chains:
                    mc.place(initial_sites)
            except ValueError as e:
                raise ValueError(f"initial_sites: {str(e).removeprefix('sites: ')}") from None
        state = ReplicaState(replicas=[], slot_of_replica=np.arange(K), swap_rng=swap_rng.bit_generator.state,
                             swaps_attempted=np.zeros(K - 1, np.int64), swaps_accepted=np.zeros(K - 1, np.int64),
                             last_end=np.full(K, -1))

    def capture():
        state.replicas = [mc.state for mc in chains]
        state.swap_rng = swap_rng.bit_generator.state
        return state

    sites_by_slot = []
    start = time.perf_counter()
    if writer is not None:
        writer.open(state.rounds)

    def advance(pool):
        def one_round(done):
            slot = state.slot_of_replica
            jobs = [pool.submit(mc.run, np.array([T[slot[k]]]), np.array([exchange_every], np.int64))
                    for k, mc in enumerate(chains)]
            for job in jobs:
                job.result()
            energy = np.array([mc.energy for mc in chains])
            replica_at = np.argsort(slot)  # replica holding each temperature
            first = state.rounds % 2
            for s in range(first, K - 1, 2):
                a, b = replica_at[s], replica_at[s + 1]
                log_ratio = (1.0 / T[s] - 1.0 / T[s + 1]) * (energy[a] - energy[b])
                state.swaps_attempted[s] += 1
                # A deviate per offer whatever the energies, so that round-off in an energy
                # can never shift the swap stream.
                u = swap_rng.random()
                if log_ratio >= 0 or u < math.exp(log_ratio):
                    slot[a], slot[b] = s + 1, s
                    replica_at[s], replica_at[s + 1] = b, a
                    state.swaps_accepted[s] += 1
            for k in range(K):
                if slot[k] == 0 and state.last_end[k] == K - 1:
                    state.round_trips += 1
                if slot[k] in (0, K - 1):
                    state.last_end[k] = slot[k]
            state.energy.append(energy[replica_at])
            cold = replica_at[0]
            if energy[cold] < state.best_energy:
                state.best_energy, state.best_sites = float(energy[cold]), np.asarray(chains[cold].particles)
            if record_sites:
                sites_by_slot.append([_sorted_sites(chains[r]) for r in replica_at])
            state.rounds += 1
            if writer is not None and state.rounds % writer.every == 0:
                writer.write(state.rounds, chains[cold].particles, float(energy[cold]), float(T[0]))
            return state.rounds, dict(E_cold=f"{energy[cold]:.5g}")
        return one_round

    try:
        with ThreadPoolExecutor(max_workers=threads) as pool:
            drive(state.rounds, rounds, advance(pool), lambda: _save(checkpoint, signature, capture()),
                  checkpoint=checkpoint, checkpoint_interval=checkpoint_interval, progress=progress,
                  desc=f"replica exchange K={K} n={n} box={box}", unit="round")
    finally:
        if writer is not None:
            writer.close()
    final = copy.deepcopy(capture())

    # The coldest configuration, quenched on a chain continuing its state (the sampling state is
    # left as is).
    cold = int(np.argsort(state.slot_of_replica)[0])
    quench = new_chain(particle, g, box, n, replica_seeds[cold], opts, state=final.replicas[cold])
    if quench_sweeps:
        quench.run(np.zeros(quench_sweeps), np.full(quench_sweeps, n, np.int64))
    counters: dict[str, int] = {}
    for r in final.replicas:
        for key, value in r.counters.items():
            counters[key] = counters.get(key, 0) + value
    with np.errstate(invalid="ignore", divide="ignore"):
        acceptance = final.swaps_accepted / final.swaps_attempted
    params = dict(signature, particle_type=type(particle).__name__, temperatures=T.tolist(), rounds=rounds,
                  quench_sweeps=quench_sweeps, threads=threads)
    if record_sites:
        params["sites_by_slot"] = np.array(sites_by_slot)
    return ReplicaExchangeResult(
        sites=np.asarray(quench.particles), box=box, n=n, g=g, energy=float(quench.energy), bonds=int(quench.bonds),
        deformation=float(quench.deformation), temperatures=T, energy_trace=np.asarray(final.energy).reshape(-1, K),
        swap_acceptance=acceptance, round_trips=final.round_trips, best_energy=final.best_energy,
        best_sites=final.best_sites,
        state=final, counters=counters, seed=seed, params=params, elapsed=time.perf_counter() - start,
        resumed=resumed, tiling=particle.tiling)


def _sorted_sites(mc) -> np.ndarray:
    """Occupied site indices of a kernel chain, sorted (as ``run(..., record_sites=True)`` gives)."""
    return np.asarray(mc.run(np.zeros(1), np.zeros(1, np.int64), True)["sites"][0])


def _save(path, signature, state: ReplicaState) -> None:
    no_sites = np.zeros((0, state.replicas[0].particles.shape[1]), np.int32)
    save(path, "replica_exchange", signature, state.replicas,
         dict(swap_rng=state.swap_rng, rounds=state.rounds, best_energy=state.best_energy, round_trips=state.round_trips),
         dict(slot_of_replica=state.slot_of_replica, energy=np.asarray(state.energy, float).reshape(-1, len(state.replicas)),
              swaps_attempted=state.swaps_attempted, swaps_accepted=state.swaps_accepted, last_end=state.last_end,
              best_sites=no_sites if state.best_sites is None else state.best_sites))


def read_checkpoint(path, signature=None) -> ReplicaState:
    """The ``ReplicaState`` a ``replica_exchange`` checkpoint holds.

    Parameters
    ----------
    path : str or path-like
        The checkpoint file (``replica_exchange(..., checkpoint=path)``).
    signature : dict or None, optional
        A run's defining parameters; the file is refused when it was written by a run with other
        ones. None accepts any ``replica_exchange`` checkpoint.

    Returns
    -------
    ReplicaState
        The state to pass to ``replica_exchange(..., state=)``.

    Raises
    ------
    FileNotFoundError
        No file at ``path``.
    ValueError
        The file is not a checkpoint of a ``replica_exchange`` run or, with ``signature``, of
        this run; the message names it (``checkpoints``).
    """
    metadata, arrays = read_checkpoint_file(path, "replica_exchange", signature)
    replicas = chain_states_from_disk(path, metadata, arrays)
    try:
        best_sites = arrays["best_sites"]
        return ReplicaState(replicas=replicas, slot_of_replica=np.asarray(arrays["slot_of_replica"], np.int64),
                            swap_rng=dict(metadata["swap_rng"]), rounds=int(metadata["rounds"]),
                            energy=list(np.asarray(arrays["energy"], float)),
                            swaps_attempted=np.asarray(arrays["swaps_attempted"], np.int64),
                            swaps_accepted=np.asarray(arrays["swaps_accepted"], np.int64),
                            best_energy=float(metadata["best_energy"]), best_sites=best_sites if len(best_sites) else None,
                            round_trips=int(metadata["round_trips"]), last_end=np.asarray(arrays["last_end"], np.int64))
    except (KeyError, TypeError, ValueError) as e:
        raise ValueError(f"checkpoint: {path!r} holds an incomplete replica-exchange state ({type(e).__name__}: {e}); "
                         "delete it or pass another checkpoint path to start the run afresh") from None
