"""Replica exchange (parallel tempering) over temperature for the aggregation Monte Carlo.

``K`` copies of the box (replicas) run the same Metropolis chain as ``anneal`` (single-particle
moves, optional cluster translations, delayed acceptance), each at one temperature of a ladder
``T_1 < ... < T_K``. After every round of ``exchange_every`` attempted moves per replica,
neighbouring temperatures offer to swap their configurations, accepted with probability

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
import pickle
import secrets
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from . import _kernel
from ._checks import integer, non_negative, probability
from .montecarlo import BoxState, _check_signature, _particle_signature, _write_atomically
from .relaxation import METHODS
from .topology import tiling_facts

__all__ = ["replica_exchange", "geometric_temperatures", "ReplicaState", "ReplicaExchangeResult"]

_CHECKPOINT_VERSION = 1


def geometric_temperatures(T_min: float, T_max: float, count: int) -> np.ndarray:
    """``count`` temperatures from ``T_min`` to ``T_max`` in geometric progression: the usual
    ladder when the heat capacity varies slowly (equal swap rates between neighbours)."""
    if not (math.isfinite(T_min) and math.isfinite(T_max) and 0 < T_min < T_max):
        raise ValueError(f"temperatures: need 0 < T_min < T_max, finite, got T_min={T_min!r}, T_max={T_max!r}")
    count = integer("count", count, 2)
    return np.geomspace(T_min, T_max, count)


@dataclass
class ReplicaState:
    """Everything a replica-exchange run needs to continue: a value, picklable.

    ``replicas``: per replica a dict of ``particles`` (sites), ``rng_state`` (the kernel stream),
    ``deformation`` and ``counters``; ``slot_of_replica[k]``: the temperature index replica ``k``
    holds; ``swap_rng``: the bit-generator state of the swap stream; ``rounds``: rounds done;
    ``energy`` (rounds, K): the energy at each temperature after each round; ``swaps_attempted``
    and ``swaps_accepted`` (K - 1,): per neighbouring pair; ``best_energy`` and ``best_sites``: the
    lowest energy seen at the coldest temperature after a round and its sites; ``round_trips``:
    how many times a replica came back to the coldest temperature after reaching the hottest,
    ``last_end`` (K,): the end of the ladder each replica last visited (-1: neither yet)."""

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
    """Outcome of ``replica_exchange``: the coldest temperature's configuration after the final
    zero-temperature descent (``sites``, ``energy``, ``bonds``, ``deformation``), the ladder
    (``temperatures``), the energy at each temperature after each round (``energy_trace``,
    (rounds, K)), the swap acceptance of each neighbouring pair (``swap_acceptance``), the number
    of replicas that went from the coldest to the hottest temperature and back (``round_trips``),
    the lowest energy seen at the coldest temperature (``best_energy``, ``best_sites``), the final
    ``state`` (to continue the run), kernel ``counters`` summed over replicas, ``seed``,
    ``params``, ``elapsed`` seconds and whether the run ``resumed``."""

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


def replica_exchange(particle, g, temperatures, box=60, n=200, rounds=1000, exchange_every=None, seed=None,
                     method="lbfgs", tol=1e-3, cluster_moves=0.0, cluster_link=1.0, bonded_moves=0.0, surface_moves=0.0,
                     delayed_acceptance=True, quench_sweeps=50,
                     threads=None, state=None, checkpoint=None, checkpoint_interval=60.0, progress=True,
                     record_sites=False, max_iter=100_000, initial_sites=None) -> ReplicaExchangeResult:
    """Replica exchange of ``n`` particles in a periodic ``box x box`` lattice (module docstring).

    Parameters
    ----------
    particle : any particle model (Hexagon, RandomHexagon, Triangle)
    g : float
        Binding energy per bound pair of sides (>= 0).
    temperatures : sequence of float
        The ladder, increasing, positive (``geometric_temperatures``); at least two.
    box, n : int
        As in ``anneal``.
    rounds : int
        Exchange rounds; each replica attempts ``exchange_every`` moves per round (default ``n``,
        one sweep), so a run costs ``K * rounds * exchange_every`` moves.
    seed : int or None
        Seeds every stream of the run (module docstring); None draws one, which the result records.
    method, tol, cluster_moves, cluster_link, bonded_moves, surface_moves, delayed_acceptance, max_iter
        The chain of each replica, as in ``anneal``.
    quench_sweeps : int
        Sweeps at T = 0 (a descent: every move that lowers the energy is taken) of the coldest
        replica's final configuration, done on a copy so that ``state`` continues the sampling.
    threads : int or None
        Replicas run concurrently (default: the machine's cores, at most K).
    state : ReplicaState or None
        Continue from this state (same parameters); it is not modified.
    checkpoint : path or None
        File to resume from if it exists (same parameters) and to save the state to every
        ``checkpoint_interval`` seconds, on interruption and at the end (atomically).
    initial_sites : (n, 2) array (or (n, 3) with a sublattice) or None
        Start every replica from these sites (as ``BoxState.sites``: a finished anneal's
        configuration, to sample around it at low temperature) instead of particles at random.
        Ignored when resuming. Part of the checkpoint's parameters.
    record_sites : bool
        Keep, in the result's ``params["sites_by_slot"]``, the sites at every temperature after
        every round (for tests; memory ``rounds * K * n`` integers).

    Bad input raises ``ValueError`` naming the parameter.
    """
    model = getattr(particle, "_kernel_model", None)
    if model is None or not hasattr(particle, "tiling"):
        raise ValueError(f"particle must be a particle model (Hexagon, RandomHexagon, Triangle), got {particle!r}")
    try:
        T = np.asarray(temperatures, dtype=float).ravel()
    except (TypeError, ValueError):
        raise ValueError(f"temperatures must be a sequence of numbers, got {temperatures!r}") from None
    if T.size < 2 or not np.all(np.isfinite(T)) or T[0] <= 0 or np.any(np.diff(T) <= 0):
        raise ValueError(f"temperatures must be at least two positive, finite, increasing values, got {T.tolist()}")
    K = T.size
    tiling = tiling_facts(particle.tiling)
    box = integer("box", box, 2, 30000)
    n = integer("n", n, 1)
    if n >= box * box * tiling["sublattices"]:
        raise ValueError(f"n must be smaller than the box's {box * box * tiling['sublattices']} sites, got {n}")
    g = non_negative("g", g)
    rounds = integer("rounds", rounds, 0)
    exchange_every = n if exchange_every is None else integer("exchange_every", exchange_every, 1)
    quench_sweeps = integer("quench_sweeps", quench_sweeps, 0)
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    if not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol > 0):
        raise ValueError(f"tol must be positive, got {tol!r}")
    threads = min(K, os.cpu_count() or 1) if threads is None else integer("threads", threads, 1)
    if seed is None:
        seed = secrets.randbits(63)
    seed = integer("seed", seed, 0, 2**63 - 1)

    bond_deformation = float(particle.bulk_energy_per_particle) / tiling["bulk_bonds_per_particle"]
    options = dict(method=method, tol=float(tol) * particle.force_scale, max_iter=integer("max_iter", max_iter, 1),
                   delayed_acceptance=bool(delayed_acceptance), bond_deformation=bond_deformation,
                   cluster_moves=probability("cluster_moves", cluster_moves),
                   cluster_link=probability("cluster_link", cluster_link),
                   bonded_moves=probability("bonded_moves", bonded_moves),
                   surface_moves=probability("surface_moves", surface_moves))
    signature = dict(particle=_particle_signature(particle), g=g, box=box, n=n, seed=seed,
                     temperatures=hashlib.sha256(T.tobytes()).hexdigest(), exchange_every=exchange_every,
                     **{k: v for k, v in options.items() if k != "tol"}, tol=float(tol))
    if initial_sites is not None:
        try:
            initial_sites = np.ascontiguousarray(initial_sites, dtype=np.int32)
        except (TypeError, ValueError):
            raise ValueError(f"initial_sites must be an integer array of sites, got {initial_sites!r}") from None
        signature["initial_sites"] = hashlib.sha256(initial_sites.tobytes()).hexdigest()
    replica_seeds, swap_rng = _streams(seed, K)
    chains = [_kernel.MonteCarlo(model, g, box, n, s, **options) for s in replica_seeds]

    resumed = False
    if state is None and checkpoint is not None and os.path.exists(checkpoint):
        state = _read_checkpoint(checkpoint, signature)
    if state is not None:
        state = copy.deepcopy(state)
        if len(state.replicas) != K:
            raise ValueError(f"state has {len(state.replicas)} replicas, the ladder {K} temperatures")
        for mc, saved in zip(chains, state.replicas):
            mc.place(saved["particles"])
            mc.rng_state = saved["rng_state"]
            mc.set_deformation(saved["deformation"])
            mc.counters = saved["counters"]
        swap_rng.bit_generator.state = state.swap_rng
        resumed = True
    else:
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
        state.replicas = [dict(particles=np.asarray(mc.particles), rng_state=mc.rng_state, deformation=mc.deformation,
                               counters=mc.counters) for mc in chains]
        state.swap_rng = swap_rng.bit_generator.state
        return state

    def save():
        _write_atomically(checkpoint, dict(version=_CHECKPOINT_VERSION, signature=signature, state=capture()))

    sites_by_slot = []
    start = time.perf_counter()
    from tqdm.auto import tqdm

    bar = tqdm(total=rounds, initial=min(state.rounds, rounds), disable=not progress, unit="round",
               desc=f"replica exchange K={K} n={n} box={box}", leave=False)
    last_save = time.monotonic()
    try:
        with ThreadPoolExecutor(max_workers=threads) as pool:
            while state.rounds < rounds:
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
                bar.update(1)
                bar.set_postfix(E_cold=f"{energy[cold]:.5g}", refresh=False)
                if checkpoint is not None and time.monotonic() - last_save >= checkpoint_interval:
                    save()
                    last_save = time.monotonic()
    except BaseException:
        if checkpoint is not None:
            save()
        raise
    finally:
        bar.close()
    final = copy.deepcopy(capture())
    if checkpoint is not None:
        save()

    # The coldest configuration, quenched on a fresh chain (the sampling state is left as is).
    cold = int(np.argsort(state.slot_of_replica)[0])
    quench = _kernel.MonteCarlo(model, g, box, n, replica_seeds[cold], **options)
    quench.place(final.replicas[cold]["particles"])
    quench.set_deformation(final.replicas[cold]["deformation"])
    if quench_sweeps:
        quench.run(np.zeros(quench_sweeps), np.full(quench_sweeps, n, np.int64))
    counters: dict[str, int] = {}
    for r in final.replicas:
        for key, value in r["counters"].items():
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


def _read_checkpoint(path, signature) -> ReplicaState:
    with open(path, "rb") as f:
        data = pickle.load(f)
    if not isinstance(data, dict) or data.get("version") != _CHECKPOINT_VERSION or "state" not in data:
        raise ValueError(f"checkpoint: {path} is not a replica-exchange checkpoint (version {_CHECKPOINT_VERSION})")
    saved = dict(data["signature"])
    saved.setdefault("cluster_link", 1.0)  # checkpoints written before linked cluster moves
    saved.setdefault("bonded_moves", 0.0)  # ... and before bonded particle moves
    saved.setdefault("surface_moves", 0.0)  # ... and before surface moves
    _check_signature(path, saved, signature)
    return data["state"]
