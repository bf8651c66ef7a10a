"""Monte Carlo annealing of aggregate topologies (main text, "Monte-Carlo validation of the phase
diagram"; the snapshots of Fig. 3b).

``n`` particles occupy distinct sites of a periodic ``box x box`` patch of cells of the particle's
tiling (cell ``(i, j)`` at ``i a1 + j a2``, ``i, j`` modulo ``box``): ``box**2`` sites for hexagons,
``2 box**2`` (an up and a down triangle per cell) for triangles. A move takes a random particle
to a random empty site; the energy of a configuration is a sum over its connected clusters,

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

The kernel (``kernel/montecarlo.hpp``) recomputes only the clusters a move leaves and joins and
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

``"linear"``     ``T = T0 (1 - x)``, ``x`` the fraction of the run (0 on the first record block,
                 1 on the last), so the run ends at ``T = 0``.
``"geometric"``  ``T = T0 (T_end / T0)**y`` from ``T0`` on the first block to ``T_end`` on the
                 last but one (``y`` from 0 to 1), and ``T = 0`` on the last block.
callable         ``T = schedule(x)``, evaluated once per record block.
stages           a sequence of ``(T, n_steps)`` pairs, run in order (``steps`` is then their sum).

``T0`` defaults to ``g`` (the energy of one bond), or to the particle's bulk deformation energy per
particle when ``g = 0``. A record block is ``record_every`` attempted moves (default one sweep,
``n`` moves): the temperature is constant over a block and the energy is recorded after it.
"""
from __future__ import annotations

import dataclasses
import hashlib
import math
import os
import pickle
import secrets
import time
from dataclasses import dataclass, field

import numpy as np

from . import _kernel
from ._checks import integer, non_negative, probability
from .relaxation import METHODS
from .io import atomic_path
from .topology import neighbour_sites, site_columns, site_positions, tiling_facts

__all__ = ["anneal", "AnnealResult", "AnnealState", "read_checkpoint",
           "draw_snapshot", "clusters", "classify_aggregate", "SCHEDULES"]

SCHEDULES = ("linear", "geometric")
_CHECKPOINT_VERSION = 1
_CONTINUOUS_STAGES = 10  # acceptance is reported over tenths of a run without explicit stages
# Default length of a run, in sweeps of n attempted moves: at the paper's sizes (200 particles in
# 60 x 60, ell = 5) the linear schedule from T0 = g then ends in aggregates that no longer change
# over the last 30% of the run (acceptance < 1e-3), in about 15 s of one core
# (benchmarks/bench_montecarlo.py).
DEFAULT_SWEEPS = 10_000


@dataclass
class AnnealState:
    """Where an annealing run stands: a value, picklable, what a checkpoint holds on disk.

    ``done``: record blocks completed; ``particles``: the sites of every particle; ``rng_state``:
    the kernel's ``std::mt19937_64`` (the run's only random stream, seeded by ``seed``);
    ``deformation``: the running sum of cluster energies; ``counters``: the kernel's counters;
    ``energy_trace`` and ``accepted``: per completed block; ``elapsed``: seconds spent so far.
    Pass it to ``anneal(..., state=)`` (with the run's parameters) to continue the run."""

    done: int
    particles: np.ndarray = field(repr=False)
    rng_state: str = field(repr=False)
    deformation: float
    counters: dict = field(repr=False)
    energy_trace: np.ndarray = field(repr=False)
    accepted: np.ndarray = field(repr=False)
    elapsed: float = 0.0


@dataclass
class BoxState:
    """A final configuration of the periodic box, shared by ``AnnealResult`` and
    ``replica_exchange.ReplicaExchangeResult``: ``sites`` (n, 2) (or (n, 3)), ``box``, ``n``,
    ``g``, ``energy = -g * bonds + deformation``, ``bonds`` and ``deformation``."""

    sites: np.ndarray = field(repr=False)
    box: int
    n: int
    g: float
    energy: float
    bonds: int
    deformation: float

    def clusters(self) -> list[np.ndarray]:
        """Final clusters, largest first: unwrapped sites, each shape (k, 2) (or (k, 3) for tilings
        with several sublattices)."""
        return [c for c, _ in clusters(self.sites, self.box, getattr(self, "tiling", "hexagon"))]


@dataclass
class AnnealResult(BoxState):
    """Outcome of ``anneal``.

    Attributes
    ----------
    sites : ndarray, shape (n, 2), int
        Final lattice coordinates ``0 <= i, j < box`` of each particle (particle order).
    box, n : int
    g : float
        Binding energy per bound pair of sides.
    energy : float
        Final energy ``-g * bonds + deformation`` (running sum of the accepted moves).
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
        Kernel counters: ``attempted, accepted, screened`` (identical on resumption) and ``cache_hits,
        cache_misses, cache_clears, minimisations, evaluations, fallbacks, unconverged`` (these
        depend on the cache, which a checkpoint does not save).
    seed : int
    params : dict
        Everything that defines the run (particle, g, box, n, method, tol, schedule, ...).
    elapsed : float
        Wall time of this call, seconds.
    resumed : bool
        Whether the run started from a checkpoint or a given state.
    state : AnnealState
        Where the run stands at the end (to continue it: ``anneal(..., state=result.state)``).
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
        """Fraction of cluster energies taken from the cache (isolated particles excluded)."""
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


def _schedule_description(schedule):
    if isinstance(schedule, str):
        return schedule
    if callable(schedule):
        return getattr(schedule, "__name__", "callable")
    return [(float(t), int(m)) for t, m in schedule]


# ---------------------------------------------------------------------------------------------
# Checkpoints
# ---------------------------------------------------------------------------------------------

def _write_atomically(path, data):
    """Pickle ``data`` to ``path`` atomically (``io.atomic_path``: temporary file, then rename)."""
    with atomic_path(path) as tmp, open(tmp, "wb") as f:
        pickle.dump(data, f, protocol=4)
        f.flush()
        os.fsync(f.fileno())


def _particle_signature(particle) -> dict:
    """What identifies a particle in a checkpoint: its parameters (spring particles; the form
    checkpoints have always had for hexagons), or its type and a digest of ``M`` (random ones)."""
    if hasattr(particle, "M"):
        return dict(type=type(particle).__name__, eps=float(particle.eps),
                    M=hashlib.sha256(np.ascontiguousarray(particle.M, dtype=float).tobytes()).hexdigest())
    params = {k: float(getattr(particle, k)) for k in ("k", "kc", "k_area", "eps")}
    if particle.tiling != "hexagon":
        params["tiling"] = particle.tiling
    return params


def read_checkpoint(path, signature=None) -> AnnealState:
    """The ``AnnealState`` an ``anneal`` checkpoint holds; with ``signature`` (a run's defining
    parameters), refused when it was written by a run with other parameters."""
    data = _read_checkpoint(path, signature)
    return AnnealState(**{f.name: data[f.name] for f in dataclasses.fields(AnnealState)})


def _read_checkpoint(path, signature):
    with open(path, "rb") as f:
        data = pickle.load(f)
    if not isinstance(data, dict) or data.get("version") != _CHECKPOINT_VERSION:
        raise ValueError(f"checkpoint: {path} is not a pyfrustrate.anneal checkpoint (version {_CHECKPOINT_VERSION})")
    if signature is None:
        return data
    saved = dict(data["signature"])
    saved.setdefault("cluster_moves", 0.0)  # checkpoints written before cluster moves existed
    saved.setdefault("cluster_link", 1.0)  # ... and before linked cluster moves
    saved.setdefault("bonded_moves", 0.0)  # ... and before bonded particle moves
    saved.setdefault("surface_moves", 0.0)  # ... and before surface moves
    _check_signature(path, saved, signature)
    return data


def _check_signature(path, saved, signature):
    """Refuse a checkpoint written by a run whose defining parameters differ, naming them."""
    differ = sorted(k for k in set(saved) | set(signature) if saved.get(k) != signature.get(k))
    if differ:
        raise ValueError(f"checkpoint: {path} was written by a run with different parameters ({', '.join(differ)}); "
                         "delete it or pass another path")


# ---------------------------------------------------------------------------------------------
# The annealing
# ---------------------------------------------------------------------------------------------

def anneal(particle, g, box=60, n=200, steps=None, schedule="linear", seed=None, method="lbfgs", tol=1e-3,
           checkpoint=None, progress=True, *, T0=None, T_end=None, record_every=None, checkpoint_interval=60.0,
           cache=True, warm_start=True, delayed_acceptance=True, cluster_moves=0.0, cluster_link=1.0,
           bonded_moves=0.0, surface_moves=0.0, max_iter=100_000, callback=None, state=None) -> AnnealResult:
    """Simulated annealing of the topology of ``n`` particles in a periodic ``box x box`` lattice.

    Parameters
    ----------
    particle : Hexagon, RandomHexagon or Triangle (any ``particles.Particle``)
    g : float
        Binding energy per bound pair of sides (>= 0), in the units of the particle's springs.
    box : int
        Box side in lattice cells (>= 2). The paper: 60 (200 particles) and 30 (300 particles).
    n : int
        Number of particles, fewer than the box's sites (``box**2`` cells times the tiling's
        sublattices).
    steps : int
        Attempted moves in all (with a continuous schedule). Default ``DEFAULT_SWEEPS * n``
        (10000 sweeps).
    schedule : "linear", "geometric", callable or sequence of (T, steps)
        Temperature schedule (module docstring).
    seed : int or None
        Seed of the kernel's ``std::mt19937_64`` (``0 <= seed < 2**64``); None draws one, which the
        result records.
    method : {"lbfgs", "newton", "linear"}
        Cluster relaxation. ``"lbfgs"`` (default): the relaxed energy, to ``tol``, by L-BFGS
        warm-started from the linear solution (``warm_start=False``: from the bulk reference);
        ``"newton"``: the same minimum by Newton steps from the linear solution, faster (measured
        at ell = 5, eps = 0.01, 2000 sweeps: 200 in 60 x 60 3.5 s against 4.3 s; 300 in 30 x 30
        177 s against ~3x that; the workflow uses it); ``"linear"``: the linearised solve
        alone, about 4.7x faster than Newton in a dense box but biased upwards for loosely bound
        clusters (final box energies off by ~1-3 % at eps = 0.01, ell = 5): an approximation.
    tol : float
        Relaxation tolerance, relative as in ``relax``: max gradient <= ``tol * particle.force_scale``.
        The default 1e-3 leaves relative energy errors near 1e-6 (benchmarks/bench_tradeoff.py),
        far below what changes a Metropolis decision: a 1000-sweep run at ell = 5, nu = 0.9 takes
        the same moves as at tol = 1e-5, 3.8x faster.
    checkpoint : path or None
        File to resume from if it exists (same parameters required) and to save to every
        ``checkpoint_interval`` seconds, on interruption (KeyboardInterrupt or any exception, the
        last completed chunk is saved) and at the end. Written atomically (temporary file in the
        same directory, then ``os.replace``). The cluster cache is not saved: it only affects
        speed. A finished checkpoint is returned as is.
    progress : bool
        Show a tqdm progress bar.
    T0, T_end : float
        Start temperature (default ``g``) and the geometric schedule's last non-zero one
        (default ``T0 / 1000``).
    record_every : int
        Attempted moves per record block (default ``n``, one sweep).
    cache, warm_start : bool
        Cluster-energy cache and warm starts (speed knobs; ``warm_start`` changes L-BFGS minima
        within the tolerance, so it is part of a checkpoint's parameters, ``cache`` is not). With
        ``method="newton"``, ``warm_start`` relaxes the clusters a move makes from the relaxed
        displacements of the clusters they came from (the moved particle rigidly attached; exact
        Hessian from the first step) where every other particle's is known, instead of from the
        linear solution of the canonical representative (``warm_start=False``, the former path):
        the warm path also factorises with the kernel's own LDL^T instead of CHOLMOD's. Measured
        in the dense box (300 in 30 x 30, nu = 0.4): ~25 % fewer factorisations per relaxation,
        ~1.2x faster. Energies then agree with the cold start's to the tolerance, not to the last
        bit: they depend on the path and on the cache at that level, so a run resumed from a
        checkpoint (empty cache, no stored displacements) follows the uninterrupted one within
        the tolerance (the same moves, as tests/test_montecarlo_warm.py checks of warm against
        cold chains) rather than bit for bit.
    delayed_acceptance : bool
        Screen each move first with the surrogate energy ``-(g - e_b/3) * bonds`` (``e_b`` the
        particle's bulk deformation energy per particle), relaxing clusters only for moves that
        pass, then accept with the ratio of the true to the surrogate Boltzmann factors
        (delayed-acceptance Metropolis-Hastings, Christen & Fox 2005). The chain samples exactly
        the same Boltzmann distribution at every temperature as plain Metropolis (``False``) and
        skips most relaxations at low T; its moves are accepted somewhat less often.
    cluster_moves : float
        Probability, in [0, 1], that an attempted move is a cluster move instead: particles
        bonded to a random one (``cluster_link``) shifted by a uniformly random lattice vector,
        rejected if they would overlap another particle. With ``cluster_link=1`` the whole cluster
        moves and any new contact is refused: shape and energy are unchanged and the proposal is
        symmetric, so the sampled Boltzmann distribution is the same; aggregates then diffuse,
        where particle moves alone leave them to coarsen by slow evaporation. Default 0: the
        paper's single-particle moves.
    cluster_link : float
        In [0, 1]: the set a cluster move shifts is grown from the random particle by following
        each of its bonds with this probability, and the shift is accepted with the
        Metropolis-Hastings ratio ``min(1, exp(-dE/T) (1 - cluster_link)**(b' - b))`` (b, b' the
        bonds between the set and the rest before and after), so the Boltzmann distribution is
        kept exactly. Below 1, aggregates merge in one move when a shifted one lands in contact
        with another (and the reverse move splits them); those moves relax the clusters they
        make. 1 (default): whole clusters only, rejected on contact, as described above. The
        workflow uses 0.9 with ``cluster_moves=0.05`` (measured in the README).
    bonded_moves : float
        In [0, 1): the probability that a particle move takes the particle next to a random other
        particle (a random one of its neighbouring sites, refused if occupied) instead of to a
        random empty site (aggregation-volume-bias moves, Chen & Siepmann 2000). Accepted with the
        ratio of the reverse to the forward proposal probability, so the Boltzmann distribution is
        kept; surface moves that reshape aggregates are then proposed far more often than among
        all empty sites of a sparse box. Default 0.
    surface_moves : float
        In [0, 1): the probability that a move (other than a cluster move) takes a random particle
        with an empty neighbour to a random empty site with an occupied neighbour, accepted with
        the ratio ``n_s n_p / (n_s' n_p')`` of the numbers of such particles and sites before and
        after (and refused when the reverse move could not be proposed), so the Boltzmann
        distribution is kept. At low temperature it proposes the bond-neutral jumps between the
        kinks of an aggregate's outline far more often than particle or bonded moves, which pick
        the particle and the target among all of them. Default 0.
    max_iter : int
        Cap on energy evaluations per L-BFGS relaxation.
    callback : callable or None
        Called after every chunk of blocks as ``callback(steps_done, total_steps, energy)``; an
        exception raised there stops the run after saving the checkpoint.
    state : AnnealState or None
        Continue from this state (a run's ``result.state``, or ``read_checkpoint``), with the
        same parameters; it is not modified. Takes precedence over an existing checkpoint file.

    Returns
    -------
    AnnealResult

    Bad input raises ``ValueError`` naming the parameter.
    """
    model = getattr(particle, "_kernel_model", None)
    if model is None or not hasattr(particle, "tiling"):
        raise ValueError(f"particle must be a particle model (Hexagon, RandomHexagon, Triangle), got {particle!r}")
    tiling = tiling_facts(particle.tiling)
    box = integer("box", box, 2, 30000)
    n = integer("n", n, 1)
    n_sites = box * box * tiling["sublattices"]
    if n >= n_sites:
        raise ValueError(f"n must be smaller than the box's {n_sites} sites (a move needs an empty site), got {n}")
    g = non_negative("g", g)
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    if not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol > 0):
        raise ValueError(f"tol must be positive, got {tol!r}")
    if seed is None:
        seed = secrets.randbits(63)
    seed = integer("seed", seed, 0, 2**64 - 1)
    record_every = n if record_every is None else integer("record_every", record_every, 1)
    if T0 is None:
        T0 = g if g > 0 else particle.bulk_energy_per_particle
    T0 = non_negative("T0", T0)
    if steps is None and (isinstance(schedule, str) or callable(schedule)):
        steps = DEFAULT_SWEEPS * n
    max_iter = integer("max_iter", max_iter, 1)
    cluster_moves = probability("cluster_moves", cluster_moves)
    cluster_link = probability("cluster_link", cluster_link)
    bonded_moves = probability("bonded_moves", bonded_moves)  # the kernel refuses 1 (not ergodic)
    surface_moves = probability("surface_moves", surface_moves)  # ... and 1 (a gas particle would be stuck)
    temps, block_steps, stage_of_block, n_stages = _plan(steps, schedule, T0, T_end, record_every)
    total_steps = int(block_steps.sum())
    cum_steps = np.cumsum(block_steps)

    particle_params = _particle_signature(particle)
    plan_digest = hashlib.sha256(temps.tobytes() + block_steps.tobytes()).hexdigest()
    bond_deformation = float(particle.bulk_energy_per_particle) / tiling["bulk_bonds_per_particle"]
    signature = dict(particle=particle_params, g=g, box=box, n=n, seed=seed, method=method, tol=float(tol),
                     max_iter=max_iter, warm_start=bool(warm_start), delayed_acceptance=bool(delayed_acceptance),
                     cluster_moves=cluster_moves, cluster_link=cluster_link, bonded_moves=bonded_moves,
                     surface_moves=surface_moves, plan=plan_digest)
    params = dict(signature, particle_type=type(particle).__name__, schedule=_schedule_description(schedule),
                  T0=T0, T_end=T_end, steps=total_steps, record_every=record_every, cache=bool(cache),
                  bond_deformation=bond_deformation)

    mc = _kernel.MonteCarlo(model, g, box, n, seed, method=method, tol=float(tol) * particle.force_scale,
                            max_iter=max_iter, cache=bool(cache), warm_start=bool(warm_start),
                            delayed_acceptance=bool(delayed_acceptance), bond_deformation=bond_deformation,
                            cluster_moves=cluster_moves, cluster_link=cluster_link, bonded_moves=bonded_moves,
                            surface_moves=surface_moves, parent_start=bool(warm_start) and method == "newton")
    energies, accepted = [], []
    done, elapsed_before, resumed = 0, 0.0, False
    if state is None and checkpoint is not None and os.path.exists(checkpoint):
        state = read_checkpoint(checkpoint, signature)
    if state is not None:
        if not isinstance(state, AnnealState):
            raise ValueError(f"state must be an AnnealState, got {type(state).__name__}")
        if not 0 <= state.done <= len(temps) or len(state.energy_trace) != state.done:
            raise ValueError(f"state: {state.done} blocks done does not fit this run's {len(temps)} blocks")
        mc.place(state.particles)
        mc.rng_state = state.rng_state
        mc.set_deformation(state.deformation)
        mc.counters = dict(state.counters)
        energies, accepted = list(state.energy_trace), list(state.accepted)
        done, elapsed_before, resumed = int(state.done), float(state.elapsed), True

    start = time.perf_counter()

    def snapshot():
        return AnnealState(done=done, particles=np.asarray(mc.particles), rng_state=mc.rng_state,
                           deformation=mc.deformation, counters=mc.counters,
                           energy_trace=np.asarray(energies[:done], float),
                           accepted=np.asarray(accepted[:done], np.int64),
                           elapsed=elapsed_before + time.perf_counter() - start)

    def save(snap, complete=False):
        # On disk the checkpoint is the state's fields, with what identifies the run.
        _write_atomically(checkpoint, dict(dataclasses.asdict(snap), version=_CHECKPOINT_VERSION,
                                           signature=signature, params=params, complete=complete))

    last = snapshot()
    if done < len(temps):
        from tqdm.auto import tqdm

        bar = tqdm(total=total_steps, initial=int(cum_steps[done - 1]) if done else 0, disable=not progress,
                   unit="move", unit_scale=True, desc=f"anneal n={n} box={box}", leave=False)
        last_save, chunk = time.monotonic(), 1
        try:
            while done < len(temps):
                lo, hi = done, min(len(temps), done + chunk)
                t = time.perf_counter()
                out = mc.run(temps[lo:hi], block_steps[lo:hi])
                dt = time.perf_counter() - t
                energies.extend(out["energy"].tolist())
                accepted.extend(out["accepted"].tolist())
                done = hi
                last = snapshot()
                moves = int(block_steps[lo:hi].sum())
                bar.update(moves)
                rate = float(np.sum(out["accepted"])) / max(1, moves)
                bar.set_postfix(T=f"{temps[hi - 1]:.3g}", E=f"{energies[-1]:.5g}", acc=f"{rate:.3f}", refresh=False)
                # Chunks of about half a second and at most 1% of the run: prompt progress and
                # interruption. (Chunking does not change the chain.)
                chunk = int(min(max(1, chunk * 0.5 / max(dt, 1e-3)), 2 * chunk + 1, max(1, len(temps) // 100)))
                if checkpoint is not None and time.monotonic() - last_save >= checkpoint_interval:
                    save(last)
                    last_save = time.monotonic()
                if callback is not None:
                    callback(int(cum_steps[done - 1]), total_steps, energies[-1])
        except BaseException:
            if checkpoint is not None:
                save(last)
            raise
        finally:
            bar.close()
    if checkpoint is not None:
        save(last, complete=True)

    energy_trace, accepted_per_block = np.asarray(energies, float), np.asarray(accepted, np.int64)
    stage_attempted = np.bincount(stage_of_block, weights=block_steps, minlength=n_stages)
    stage_accepted = np.bincount(stage_of_block, weights=accepted_per_block, minlength=n_stages)
    with np.errstate(invalid="ignore", divide="ignore"):
        stage_acceptance = stage_accepted / stage_attempted
    counters = mc.counters
    return AnnealResult(sites=np.asarray(mc.particles), box=box, n=n, g=g, energy=float(mc.energy),
                        bonds=int(mc.bonds), deformation=float(mc.deformation), steps=cum_steps.copy(),
                        temperature=temps, energy_trace=energy_trace, accepted=accepted_per_block,
                        stage_acceptance=stage_acceptance,
                        acceptance=float(accepted_per_block.sum() / max(1, total_steps)), counters=counters, seed=seed,
                        params=params, elapsed=time.perf_counter() - start, resumed=resumed,
                        tiling=particle.tiling, state=last)


# ---------------------------------------------------------------------------------------------
# Clusters and snapshots
# ---------------------------------------------------------------------------------------------

def _box_sites(sites, box: int, tiling: str) -> np.ndarray:
    """Sites of a box state reduced into it, or ValueError naming ``sites``: reshaping any array
    into columns would make sites of garbage, and a site held twice would read as two clusters."""
    columns = site_columns(tiling)
    a = np.asarray(sites)
    if a.size == 0:
        return np.zeros((0, columns), np.int64)
    if a.ndim != 2 or a.shape[1] != columns:
        raise ValueError(f"sites must have shape (n, {columns}) for the {tiling} tiling, got {a.shape}")
    if a.dtype.kind not in "iu" and not (a.dtype.kind == "f" and np.all(np.isfinite(a)) and np.all(a == np.round(a))):
        raise ValueError("sites must be integer lattice coordinates")
    a = a.astype(np.int64)
    a[:, :2] %= box
    if columns == 3 and not np.all((a[:, 2] >= 0) & (a[:, 2] < tiling_facts(tiling)["sublattices"])):
        raise ValueError("sites: sublattice must be 0 or 1")
    if len({tuple(s) for s in a.tolist()}) < len(a):
        raise ValueError("sites: a site is occupied twice (modulo the box)")
    return a


def clusters(sites, box, tiling="hexagon") -> list[tuple[np.ndarray, int]]:
    """Connected clusters of occupied sites in the periodic ``box`` (edge neighbours of the tiling).

    Returns ``(coords, rank)`` pairs, largest cluster first: ``coords`` (k, 2) or (k, 3) are
    unwrapped sites (a breadth-first search from the cluster's first site, so neighbours are one
    lattice step apart), ``rank`` is 0 for a finite cluster, 1 if it wraps around the box in
    one direction, 2 in two.
    """
    box = integer("box", box, 1)
    sites = _box_sites(sites, box, tiling)

    def wrapped(v):
        return (v[0] % box, v[1] % box) + tuple(v[2:])

    where = {tuple(s): k for k, s in enumerate(sites.tolist())}
    seen = np.zeros(len(sites), bool)
    found = []
    for k0 in range(len(sites)):
        if seen[k0]:
            continue
        seen[k0] = True
        pos = {k0: tuple(sites[k0])}
        queue, wraps = [k0], []
        for k in queue:
            for v in neighbour_sites(pos[k], tiling):
                t = where.get(wrapped(v))
                if t is None:
                    continue
                if t not in pos:
                    pos[t] = v
                    seen[t] = True
                    queue.append(t)
                elif pos[t] != v:
                    wraps.append((v[0] - pos[t][0], v[1] - pos[t][1]))
        rank = int(np.linalg.matrix_rank(np.array(wraps))) if wraps else 0
        found.append((np.array([pos[k] for k in queue]), rank))
    found.sort(key=lambda c: -len(c[0]))
    return found


#: Gyration anisotropy sqrt(l1 / l2) above which a finite aggregate counts as elongated.
ELONGATION_THRESHOLD = 1.6
#: Bonds per particle, as a fraction of the bulk's, below which a large aggregate counts as an
#: open network (hexagons: 1.5 of 3 in the honeycomb pattern, about 2.5 in a compact disk of 100).
OPEN_NETWORK_BONDS = 2.0 / 3.0


def classify_aggregate(sites, box, tiling="hexagon") -> tuple[str, int]:
    """Kind of the largest aggregate of a Monte Carlo state, for phase diagrams: ``'bulk'``
    (wraps the box both ways), ``'fiber'`` (wraps one way, or finite and elongated: gyration
    anisotropy above ``ELONGATION_THRESHOLD``), ``'bulk_with_holes'`` (fewer than
    ``OPEN_NETWORK_BONDS`` times the bulk's bonds per particle), ``'disk'`` (compact), or ``'gas'`` (largest
    cluster of fewer than 3 particles). Returns ``(kind, size of the largest cluster)``.

    A heuristic with the limits of a finite box: an aggregate narrower than the optimal fibre
    width but too short to show it (few particles) reads as a disk.
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
    members = {tuple(c) for c in coords.tolist()}
    bonds = sum(v in members for c in coords.tolist() for v in neighbour_sites(c, tiling)) / 2
    if bonds / size < OPEN_NETWORK_BONDS * tiling_facts(tiling)["bulk_bonds_per_particle"]:
        return "bulk_with_holes", size
    xy = site_positions(coords, tiling)
    eigen = np.linalg.eigvalsh(np.cov(xy.T))
    return ("fiber" if np.sqrt(eigen[1] / max(eigen[0], 1e-12)) > ELONGATION_THRESHOLD else "disk"), size


def _reference_outlines(coords, tiling):
    """Outline polygons (n, m, 2) of particles at rest without mismatch: their site centres plus
    the kernel's corner offsets, for the outline slots (``plotting.OUTLINE_SLOTS``)."""
    from .plotting import OUTLINE_SLOTS

    facts = tiling_facts(tiling)
    offsets = np.asarray(facts["slot_offsets"])[:, OUTLINE_SLOTS[tiling]]  # (sublattices, m, 2)
    sub = coords[:, 2] if coords.shape[1] == 3 else np.zeros(len(coords), int)
    return site_positions(coords, tiling)[:, None, :] + offsets[sub]


def _placed(coords, box):
    """Unwrapped cluster sites shifted by whole boxes so that their centre lies in the box (where
    ``draw_snapshot`` draws them)."""
    coords = coords.copy()
    coords[:, :2] -= np.floor(coords[:, :2].mean(axis=0) / box).astype(int) * box
    return coords


def largest_cluster_extent(sites, box, tiling="hexagon") -> tuple[np.ndarray, np.ndarray]:
    """Lower-left and upper-right corners of the site centres of the largest cluster, as
    ``draw_snapshot`` places it: the window to centre a snapshot panel on."""
    coords, _ = clusters(sites, box, tiling)[0]
    xy = site_positions(_placed(coords, box), tiling)
    return xy.min(axis=0), xy.max(axis=0)


def draw_snapshot(sites, box, ax=None, particle=None, *, magnify=1.0, cmap="tab10", outline=True, tiling=None):
    """Draw particles as polygons at their lattice positions, one colour per cluster (isolated
    particles grey), each cluster unwrapped (so a cluster across the periodic boundary looks
    connected) and placed with its centre inside the box, whose outline is drawn.

    With ``particle`` given, finite clusters are drawn in their relaxed shapes (linear solve),
    displacements from the regular reference magnified by ``magnify``; wrapped clusters stay
    regular. ``tiling`` defaults to the particle's, else the hexagon's. Returns the matplotlib axes.
    """
    import matplotlib.pyplot as plt
    from .plotting import OUTLINE_SLOTS
    from matplotlib.collections import PolyCollection

    if ax is None:
        _, ax = plt.subplots(figsize=(5, 5 * np.sqrt(3) / 2 / 1.5))
    colours = plt.get_cmap(cmap)
    polys, faces = [], []
    multi = 0
    if tiling is None:
        tiling = particle.tiling if particle is not None else "hexagon"
    for coords, rank in clusters(sites, box, tiling):
        coords = _placed(coords, box)
        corners = _reference_outlines(coords, tiling)
        if particle is not None and rank == 0 and len(coords) > 1:
            from . import relaxation as _relax
            from .topology import cluster as _cluster

            top = _cluster(coords, tiling=tiling)
            r = _relax.relax(particle, top, method="linear")
            relaxed = _relax.particle_corners(particle, top, r.state)[:, OUTLINE_SLOTS[tiling]]
            corners = corners + magnify * (relaxed - corners)
        if len(coords) == 1:
            colour = (0.75, 0.75, 0.75, 1.0)
        else:
            colour = colours(multi % colours.N)
            multi += 1
        polys.extend(corners)
        faces.extend([colour] * len(coords))
    ax.add_collection(PolyCollection(polys, facecolors=faces, edgecolors="k", linewidths=0.2))
    if outline:
        # The box's cells: a rhombus, drawn around the sites' centres (a cell's sites lie within it).
        corner = site_positions([(0.5, 0.5)]) if tiling == "hexagon" else np.zeros((1, 2))
        rhombus = site_positions([(0, 0), (box, 0), (box, box), (0, box), (0, 0)]) - corner
        # Dotted and beneath the particles: a cropped view shows only part of the box, whose
        # edges must not read as cracks through an aggregate.
        ax.plot(rhombus[:, 0], rhombus[:, 1], color="0.55", lw=0.6, ls=":", zorder=0.5)
    allc = np.concatenate(polys) if polys else np.zeros((1, 2))
    pad = 1.0
    ax.set_xlim(min(allc[:, 0].min(), -1) - pad, max(allc[:, 0].max(), 1.5 * box) + pad)
    ax.set_ylim(min(allc[:, 1].min(), -1) - pad, max(allc[:, 1].max(), np.sqrt(3) / 2 * box) + pad)
    ax.set_aspect("equal")
    ax.set_axis_off()
    return ax
