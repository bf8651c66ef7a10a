"""pyfrustrate: self-assembly of ill-fitting, deformable particles.

Reproduces H. Le Roy, M. M. Terzi and M. Lenz, "Collective deformation modes promote fibrous
self-assembly in deformable particles", Phys. Rev. X 15, 011022 (2025).

Main entry points: ``Hexagon`` (the particle), ``Triangle`` (the triangular particle of the
supplement), ``topology`` (aggregates, on either tiling), ``relax`` (minimum
deformation energy at fixed topology), ``continuum`` (the analytic theory), ``chain`` (the 1D
toy model), ``anneal`` (Monte Carlo of topologies), ``random_particles`` and ``RandomHexagon``
(random-elasticity particles).

``import pyfrustrate as pf`` reaches every public submodule as an attribute (``pf.ansatz``,
``pf.ground_states``, ``pf.plotting``, ...), and no function bears the name of a submodule.
``pf.plotting`` is loaded on first use: it imports matplotlib, which a computation without
figures does not need to wait for.

Conventions that bite: positions are in lattice spacings and sites in lattice coordinates
(60-degree axes, ``topology``); ``topology.fiber(width)`` counts lattice lines, its continuum
width ``W`` is the topology's ``size``; ``relax`` returns deformation energy only (binding
excluded); ``Gamma`` maps to the binding ``g`` under an explicit convention
(``continuum.particle_parameters(..., convention=)``, module ``continuum``).

Examples
--------
A straight fibre of 10 rows relaxed, against the continuum fibre of the same width ``W``
(``size``, in units of ``ell`` = 2) at ``Gamma = 0``, both per unit area in units of ``e_bulk``:

>>> import pyfrustrate as pf
>>> p = pf.Hexagon.from_continuum(ell=2.0, nu=0.5)
>>> fibre = pf.topology.fiber(10, curved=False)
>>> r = pf.relax(p, fibre)
>>> round(float(r.energy_per_particle / p.bulk_energy_per_particle), 3)
0.661
>>> round(float(pf.continuum.fiber_energy(fibre.size / 2.0, 0.5, 0.0)), 3)
0.663
"""
import importlib as _importlib
from typing import TYPE_CHECKING

from . import (ansatz, boundary_layer, chain, continuum, ground_states, io, montecarlo, particles, provenance,
               random_particles, relaxation, topology)
from .particles import Hexagon, Particle, Triangle
from .relaxation import ConvergenceWarning, Relaxation, StiffnessCache, relax
from .montecarlo import AnnealResult, ReplicaExchangeResult, anneal, replica_exchange
from .random_particles import RandomHexagon

if TYPE_CHECKING:  # type checkers see the lazily loaded module as it is
    from . import plotting

__version__ = "0.1.0"

#: Submodules loaded on first attribute access (``pf.plotting``) rather than at import.
_LAZY_SUBMODULES = ("plotting",)

__all__ = ["ansatz", "boundary_layer", "chain", "continuum", "ground_states", "io", "montecarlo", "particles",
           "plotting", "provenance", "random_particles", "relaxation", "topology",
           "Hexagon", "Triangle", "Particle", "RandomHexagon", "relax", "Relaxation", "StiffnessCache",
           "ConvergenceWarning", "anneal", "AnnealResult", "replica_exchange", "ReplicaExchangeResult"]


def __getattr__(name: str):
    """Load a lazy submodule on first access (PEP 562)."""
    if name in _LAZY_SUBMODULES:
        return _importlib.import_module(f".{name}", __name__)  # binds it on the package: called once
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY_SUBMODULES))
