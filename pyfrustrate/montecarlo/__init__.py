"""Monte Carlo of aggregate topologies (main text, "Monte-Carlo validation of the phase diagram";
the snapshots of Fig. 3b): simulated annealing and replica exchange over the kernel's chain
(``kernel/montecarlo/``).

Modules: ``options`` (``MonteCarloOptions``, the one options type, checked once; ``binding``,
``Gamma=`` or ``g=``), ``annealing`` (schedules, ``window_schedule``, ``anneal``), ``exchange`` (``replica_exchange``),
``driver`` (the run loop both share, a chain's state as a value), ``checkpoints`` (data-only
checkpoint files), ``trajectory`` (GSD snapshots), ``analysis`` (clusters through the kernel,
classification of aggregates, ``BoxState``), ``drawing`` (``draw_snapshot``), ``fixed_size``
(single aggregates sampled at fixed size: the Monte Carlo's own ``W*`` and ``n*``) and
``grand_canonical`` (one fibre exchanging particles with a reservoir: its width against the
chemical potential, and ``W*`` at a temperature).

Units and conventions: sites are lattice coordinates on the 60-degree axes ``a1 = (1, 0)``,
``a2 = (1/2, sqrt(3)/2)`` of a periodic ``box x box`` patch of cells; energies and temperatures are
in the particle's spring units. Every entry point takes the binding by keyword, as ``g=`` (the
binding energy per bound pair of sides, spring units) or as ``Gamma=`` (the dimensionless line
tension) with ``convention=`` (``"measured"``, the default, or ``"supplement"``; the ``continuum``
module docstring lists every route between the two).
"""
from .analysis import (ELONGATION_THRESHOLD, OPEN_NETWORK_BONDS, BoxState, classify_aggregate, clusters,
                       largest_cluster_extent)
from .annealing import (DEFAULT_SWEEPS, SCHEDULES, AnnealResult, AnnealState, anneal, descend, read_checkpoint,
                        window_schedule)
from .drawing import draw_snapshot
from .driver import ChainState
from .exchange import ReplicaExchangeResult, ReplicaState, geometric_temperatures, replica_exchange
from .options import DEFAULTS_MEASURED, MonteCarloOptions, binding
from . import fixed_size, grand_canonical

__all__ = ["anneal", "AnnealResult", "AnnealState", "read_checkpoint", "SCHEDULES", "DEFAULT_SWEEPS", "window_schedule",
           "descend",
           "replica_exchange", "ReplicaExchangeResult", "ReplicaState", "geometric_temperatures",
           "MonteCarloOptions", "DEFAULTS_MEASURED", "binding", "ChainState", "BoxState",
           "clusters", "classify_aggregate", "largest_cluster_extent", "draw_snapshot",
           "ELONGATION_THRESHOLD", "OPEN_NETWORK_BONDS"]
