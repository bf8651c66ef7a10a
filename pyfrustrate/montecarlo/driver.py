"""The one driver of Monte Carlo runs, shared by ``anneal`` and ``replica_exchange``.

A run is a number of units (an anneal's record blocks, an exchange's rounds) advanced by the
caller's ``advance``; the driver shows progress, saves a checkpoint every ``checkpoint_interval``
seconds, on any interruption (the last completed unit: ``KeyboardInterrupt``, SIGTERM through
``io.sigterm_raises``, an exception from a callback) and at the end. A kernel chain's state is a
value (``ChainState``): read from a chain, passed into a new one, written to a checkpoint and read
back exactly (the random generator as text, the running deformation energy as a float).
"""
from __future__ import annotations

import hashlib
import time
import numpy as np

from .. import _kernel
from .._checks import integer
from ..topology import tiling_facts
from .checkpoints import write_checkpoint
from .options import MonteCarloOptions, binding, check_particle

__all__ = ["ChainState", "new_chain", "particle_signature", "drive", "box_run"]


def box_run(particle, Gamma, g, convention, box, n) -> tuple[float, int, int]:
    """``(g, box, n)`` of a run, checked.

    Parameters
    ----------
    particle : Hexagon, RandomHexagon or Triangle
        The run's particle.
    Gamma, g : float or None
        The binding, exactly one (``options.binding``).
    convention : {"measured", "supplement"}
        How ``Gamma`` maps to ``g``.
    box : int
        Box side in lattice cells, in [2, 30000].
    n : int
        Number of particles, fewer than the box's sites (a move needs an empty site).

    Returns
    -------
    tuple of (float, int, int)
        ``g`` (binding energy per bound pair of sides, spring units), ``box`` and ``n``.

    Raises
    ------
    TypeError
        ``particle`` is not a particle model.
    ValueError
        Any other bad value, naming the parameter.
    """
    check_particle(particle)
    g = binding(particle, Gamma=Gamma, g=g, convention=convention)
    box = integer("box", box, 2, 30000)
    n = integer("n", n, 1)
    n_sites = box * box * tiling_facts(particle.tiling)["sublattices"]
    if n >= n_sites:
        raise ValueError(f"n must be smaller than the box's {n_sites} sites (a move needs an empty site), got {n}")
    return g, box, n


def particle_signature(particle) -> dict:
    """What identifies a particle in a checkpoint.

    Parameters
    ----------
    particle : Hexagon, RandomHexagon or Triangle
        The run's particle.

    Returns
    -------
    dict
        Its parameters (spring particles), or its type, ``eps`` and a digest of ``M`` (random
        ones).
    """
    if hasattr(particle, "M"):
        return dict(type=type(particle).__name__, eps=float(particle.eps),
                    M=hashlib.sha256(np.ascontiguousarray(particle.M, dtype=float).tobytes()).hexdigest())
    params = {k: float(getattr(particle, k)) for k in ("k", "kc", "k_area", "eps")}
    if particle.tiling != "hexagon":
        params["tiling"] = particle.tiling
    return params


def new_chain(particle, g: float, box: int, n: int, seed: int, options: MonteCarloOptions, state=None):
    """A kernel chain of ``n`` particles at random in the box, or continuing ``state``.

    Parameters
    ----------
    particle : Hexagon, RandomHexagon or Triangle
        The run's particle.
    g : float
        Binding energy per bound pair of sides, spring units.
    box : int
        Box side, in lattice cells.
    n : int
        Number of particles.
    seed : int
        Seed of the chain's ``std::mt19937_64`` (unused when ``state`` is given).
    options : MonteCarloOptions
        The chain's moves and relaxation.
    state : ChainState or None
        A state of the same box and particles to continue.

    Returns
    -------
    _kernel.MonteCarlo
        The chain.
    """
    return _kernel.MonteCarlo(particle._kernel_model, g, box, n, seed, state=state,
                              **options.kernel_arguments(particle))


#: One kernel chain's state, a value (kernel/montecarlo/state.hpp): ``particles`` (sites),
#: ``rng_state`` (its ``std::mt19937_64`` as text), the running ``deformation``, ``counters``, and
#: the warm-start store (``displacement``, ``known``). Read from a chain (``chain.state``), passed
#: into a new one (``new_chain(..., state=)``); with the run's parameters it determines the rest of
#: the chain (only the cache, which changes Newton warm starts within the relaxation tolerance,
#: is not part of it).
ChainState = _kernel.MonteCarloState


def chain_states_to_disk(states) -> tuple[dict, dict]:
    """(metadata, arrays) of a list of chain states, for ``write_checkpoint``.

    Parameters
    ----------
    states : list of ChainState
        The chains of one run (same tiling and box).

    Returns
    -------
    tuple of (dict, dict)
        JSON-serialisable metadata and numeric arrays (one leading axis over ``states``).
    """
    metadata = dict(tiling=states[0].tiling, box=states[0].box, rng_states=[s.rng_state for s in states],
                    deformations=[s.deformation for s in states], counters=[s.counters for s in states])
    arrays = dict(particles=np.stack([np.asarray(s.particles, np.int32) for s in states]),
                  displacement=np.stack([s.displacement for s in states]), known=np.stack([s.known for s in states]))
    return metadata, arrays


def chain_states_from_disk(path, metadata: dict, arrays: dict) -> list:
    """The chain states ``chain_states_to_disk`` wrote.

    Parameters
    ----------
    path : str or path-like
        The checkpoint file (named in errors).
    metadata, arrays : dict
        What ``checkpoints.read_checkpoint_file`` read from it.

    Returns
    -------
    list of ChainState
        The chains' states.

    Raises
    ------
    ValueError
        Incomplete or inconsistent state, naming the file.
    """
    try:
        parts = zip(arrays["particles"], metadata["rng_states"], metadata["deformations"], metadata["counters"],
                    arrays["displacement"], arrays["known"], strict=True)
        return [ChainState(str(metadata["tiling"]), int(metadata["box"]), particles, str(rng), float(deformation),
                           {str(k): int(v) for k, v in counters.items()}, displacement, known)
                for particles, rng, deformation, counters, displacement, known in parts]
    except (KeyError, TypeError, ValueError, AttributeError, RuntimeError) as e:
        raise ValueError(f"checkpoint: {path!r} holds an incomplete chain state ({type(e).__name__}: {e}); delete it or "
                         "pass another checkpoint path to start the run afresh") from None


def save(path, kind, signature, states, metadata, arrays) -> None:
    """Checkpoint of a run of ``kind``, written atomically.

    Parameters
    ----------
    path : str or path-like
        The checkpoint file.
    kind : {"anneal", "replica_exchange"}
        The kind of run.
    signature : dict
        The run's defining parameters.
    states : list of ChainState
        Its chains.
    metadata, arrays : dict
        The run's own scalars and numeric arrays.
    """
    chain_metadata, chain_arrays = chain_states_to_disk(states)
    write_checkpoint(path, kind, signature, dict(metadata, **chain_metadata), dict(arrays, **chain_arrays))


def drive(done: int, total: int, advance, save_state, *, checkpoint, checkpoint_interval: float, progress: bool,
          desc: str, unit: str, position=lambda done: done, scale: int | None = None) -> int:
    """Advance a run from ``done`` to ``total`` units.

    Parameters
    ----------
    done, total : int
        Units done and units of the whole run.
    advance : callable
        ``advance(done) -> (new_done, postfix)``, ``postfix`` a dict shown on the progress bar.
    save_state : callable
        ``save_state()`` writes the last completed unit's state; called when ``checkpoint`` is
        set: every ``checkpoint_interval`` seconds, on any exception (re-raised) and at the end.
    checkpoint : path or None
        The checkpoint file (None: never save).
    checkpoint_interval : float
        Seconds between saves.
    progress : bool
        Show a tqdm progress bar.
    desc, unit : str
        The bar's description and unit.
    position : callable
        ``position(done)``: where the bar stands after ``done`` units.
    scale : int or None
        The bar's total (default ``total``).

    Returns
    -------
    int
        Units done, ``total``.
    """
    from tqdm.auto import tqdm

    bar = tqdm(total=scale if scale is not None else total, initial=position(done), disable=not progress, unit=unit,
               unit_scale=True, desc=desc, leave=False)
    last_save = time.monotonic()
    try:
        while done < total:
            done, postfix = advance(done)
            bar.update(position(done) - bar.n)
            bar.set_postfix(**postfix, refresh=False)
            if checkpoint is not None and time.monotonic() - last_save >= checkpoint_interval:
                save_state()
                last_save = time.monotonic()
    except BaseException:
        if checkpoint is not None:
            save_state()
        raise
    finally:
        bar.close()
    if checkpoint is not None:
        save_state()
    return done
