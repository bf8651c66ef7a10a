"""pyfrustrate: self-assembly of ill-fitting, deformable particles.

Reproduces H. Le Roy, M. M. Terzi and M. Lenz, "Collective deformation modes promote fibrous
self-assembly in deformable particles", Phys. Rev. X 15, 011022 (2025).

Main entry points: ``Hexagon`` (the particle), ``Triangle`` (the triangular particle of the
supplement), ``topology`` (aggregates, on either tiling), ``relax`` (minimum
deformation energy at fixed topology), ``continuum`` (the analytic theory), ``chain`` (the 1D
toy model), ``anneal`` (Monte Carlo of topologies), ``random_particles`` and ``RandomHexagon``
(random-elasticity particles).
"""
from . import chain, continuum, random_particles, topology
from .particles import Hexagon, Particle, Triangle
from .relaxation import ConvergenceWarning, Relaxation, StiffnessCache, relax
from . import montecarlo
from .montecarlo import AnnealResult, ReplicaExchangeResult, anneal, replica_exchange
from .random_particles import RandomHexagon

__version__ = "0.1.0"
__all__ = ["chain", "continuum", "topology", "random_particles", "Hexagon", "Triangle", "Particle", "RandomHexagon", "relax", "Relaxation", "StiffnessCache",
           "ConvergenceWarning", "anneal", "AnnealResult", "replica_exchange", "ReplicaExchangeResult"]
