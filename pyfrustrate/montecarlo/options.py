"""The options of a Monte Carlo chain, one type validated once, and the binding energy of a run.

``MonteCarloOptions`` serves ``anneal``, ``replica_exchange`` and the workflow
(``workflow/scripts/montecarlo_run.py``): it checks every value when it is made (``ValueError``
naming the field) and gives the kernel chain's keyword arguments, so nothing downstream checks
them again. Its defaults are the best settings measured for annealing the paper's sparse box
(``DEFAULTS_MEASURED`` says where).

``binding(particle, Gamma=..., g=..., convention=...)`` is the one way a Monte Carlo entry point
reads its binding: the dimensionless line tension ``Gamma`` with its convention
(``continuum.BINDING_CONVENTIONS``), or the binding energy per bound pair of sides ``g`` in the
particle's spring units, by keyword, exactly one of them.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from .. import _checks, continuum
from .._checks import integer, non_negative, probability
from ..relaxation import AUTO_METHOD, METHODS
from ..topology import tiling_facts

__all__ = ["MonteCarloOptions", "binding", "chain_options", "check_particle", "DEFAULTS_MEASURED"]

#: Where the defaults of ``MonteCarloOptions`` were measured: the paper profile's Monte Carlo
#: diagram (81 runs of 200 hexagons in 60 x 60, ell = 5), whose runs with these moves ended within
#: 5 bulk energies of the box's ground state most often of the settings tried (README, "With
#: surface moves, the paper profile's diagram"; config/paper.yaml, ``montecarlo``;
#: benchmarks/bench_equilibration.py compares the move settings at equal sweeps).
DEFAULTS_MEASURED = "README.md (paper profile's Monte Carlo diagram), config/paper.yaml, benchmarks/bench_equilibration.py"


def check_particle(particle):
    """The particle's kernel model (``_checks.particle``, the check every entry point shares).

    Parameters
    ----------
    particle : Hexagon, RandomHexagon or Triangle
        The particle model of a run.

    Returns
    -------
    object
        Its compiled model (``particle._kernel_model``).

    Raises
    ------
    TypeError
        ``particle`` is not a particle model.
    """
    return _checks.particle("particle", particle)._kernel_model


def binding(particle, *, Gamma=None, g=None, convention="measured") -> float:
    """The binding energy ``g`` of a run, given as ``g`` or as ``Gamma`` with its convention.

    Parameters
    ----------
    particle : Hexagon, RandomHexagon or Triangle
        The run's particle (its springs set the units; ``Gamma`` needs a spring particle).
    Gamma : float or None, keyword only
        The dimensionless line tension of a spring particle (``Hexagon``, ``Triangle``), >= 0,
        converted in ``convention`` (``continuum.mapping``: ``Gamma`` is linear in ``g``).
    g : float or None, keyword only
        The binding energy per bound pair of sides, >= 0, in the particle's spring units.
    convention : {"measured", "supplement"}, keyword only
        How ``Gamma`` maps to ``g`` (``continuum.BINDING_CONVENTIONS``): ``"measured"``
        ``gamma = g`` (hexagons; ``g / 2`` triangles), ``"supplement"`` ``gamma = 4 g / sqrt(3)``.

    Returns
    -------
    float
        ``g``, the binding energy per bound pair of sides in spring units.

    Raises
    ------
    ValueError
        Both or neither of ``Gamma`` and ``g``, a negative one, ``Gamma`` for a particle without
        a continuum mapping (``RandomHexagon``), or an unknown convention.

    Examples
    --------
    >>> from pyfrustrate import Hexagon
    >>> from pyfrustrate.montecarlo import binding
    >>> particle = Hexagon.from_continuum(ell=5.0, nu=0.9)
    >>> round(binding(particle, Gamma=0.5), 8), binding(particle, g=0.01)
    (0.00781588, 0.01)
    >>> round(binding(particle, Gamma=0.5, convention="supplement") / binding(particle, Gamma=0.5), 4)
    0.433
    """
    if (Gamma is None) == (g is None):
        raise ValueError("give the binding as exactly one of Gamma= (dimensionless line tension, with convention=) "
                         f"or g= (binding energy per bound pair of sides), got Gamma={Gamma!r}, g={g!r}")
    if g is not None:
        return non_negative("g", g)
    Gamma = non_negative("Gamma", Gamma)
    if not all(hasattr(particle, name) for name in ("k", "kc", "k_area", "eps")):
        raise ValueError(f"Gamma: {type(particle).__name__} has no continuum line tension mapping; pass g= instead")
    per_g = float(continuum.mapping(particle.k, particle.kc, particle.k_area, 1.0, particle.eps,
                                    tiling=particle.tiling, convention=convention).Gamma)
    return Gamma / per_g


@dataclass(frozen=True)
class MonteCarloOptions:
    """How a Monte Carlo chain moves and relaxes (the ``anneal`` docstring explains each field).

    Made once, checked once: a bad value raises ``ValueError`` naming it.

    Parameters
    ----------
    method : {"auto", "newton", "lbfgs", "linear"}
        Cluster relaxation; ``"auto"`` is ``relaxation.AUTO_METHOD``.
    tol : float
        Relative relaxation tolerance (> 0): max gradient <= ``tol * particle.force_scale``.
    max_iter : int
        Energy evaluations per L-BFGS relaxation, in [1, 2**31 - 1].
    warm_start : bool
        Newton: from the parents' relaxed displacements; L-BFGS: from the linear solution.
    delayed_acceptance : bool
        Screen each move with the bond count before relaxing (Christen & Fox 2005).
    cluster_moves : float
        Probability of a cluster move, in [0, 1].
    cluster_link : float
        Probability of following each bond when growing a moved cluster, in [0, 1].
    bonded_moves : float
        Probability of moving a particle next to another one, in [0, 1).
    surface_moves : float
        Probability of a surface move, in [0, 1).
    cache : bool
        The cluster-energy cache (speed only).
    parent_factor : bool
        Newton with ``warm_start``: a cluster a move changes by a few particles relaxes on its
        parent cluster's modified factor (off by default: benchmarks/bench_mc_goals.py measures
        it against the warm start).
    parent_factor_min_particles : int
        The smallest cluster that takes the parent-factor path.

    Raises
    ------
    ValueError
        A field out of range or of the wrong type, named.

    Examples
    --------
    >>> from pyfrustrate.montecarlo import MonteCarloOptions
    >>> options = MonteCarloOptions(cluster_moves=0.0)
    >>> options.resolved_method, options.replace(method="lbfgs").resolved_method
    ('newton', 'lbfgs')
    """

    method: str = "auto"
    tol: float = 1e-3
    max_iter: int = 100_000
    warm_start: bool = True
    delayed_acceptance: bool = True
    cluster_moves: float = 0.05
    cluster_link: float = 0.9
    bonded_moves: float = 0.5
    surface_moves: float = 0.2
    cache: bool = True
    parent_factor: bool = False
    parent_factor_min_particles: int = 0

    def __post_init__(self):
        if self.method not in METHODS:
            raise ValueError(f"method must be one of {METHODS}, got {self.method!r}")
        if isinstance(self.tol, bool) or not (isinstance(self.tol, (int, float)) and math.isfinite(self.tol)
                                              and self.tol > 0):
            raise ValueError(f"tol must be positive, got {self.tol!r}")
        set_ = object.__setattr__  # frozen: the checked values replace the given ones once
        set_(self, "tol", float(self.tol))
        set_(self, "max_iter", integer("max_iter", self.max_iter, 1, 2**31 - 1))
        for name in ("cluster_moves", "cluster_link"):
            set_(self, name, probability(name, getattr(self, name)))
        for name, why in (("bonded_moves", "a particle could never leave an aggregate"),
                          ("surface_moves", "a gas particle could never move")):
            value = probability(name, getattr(self, name))
            if value == 1:
                raise ValueError(f"{name} must lie in [0, 1), got 1 ({why})")
            set_(self, name, value)
        set_(self, "parent_factor_min_particles",
             integer("parent_factor_min_particles", self.parent_factor_min_particles, 0, 2**31 - 1))
        for name in ("warm_start", "delayed_acceptance", "cache", "parent_factor"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"{name} must be True or False, got {getattr(self, name)!r}")

    @property
    def resolved_method(self) -> str:
        """The method the kernel runs (``"auto"`` resolved)."""
        return AUTO_METHOD if self.method == "auto" else self.method

    def replace(self, **changes) -> "MonteCarloOptions":
        """A copy with ``changes``, checked as a new one.

        Parameters
        ----------
        **changes
            Fields and their new values.

        Returns
        -------
        MonteCarloOptions
            The copy.

        Raises
        ------
        ValueError
            A changed value out of range.
        TypeError
            A keyword that is no field.
        """
        return dataclasses.replace(self, **changes)

    def signature(self) -> dict:
        """What a checkpoint records of these options.

        Returns
        -------
        dict
            Every field that changes the chain (not ``cache``, which changes only its speed),
            ``method`` resolved.
        """
        d = dataclasses.asdict(self)
        d.pop("cache")
        d["method"] = self.resolved_method
        return d

    def kernel_arguments(self, particle) -> dict:
        """Keyword arguments of ``_kernel.MonteCarlo`` for ``particle``.

        Parameters
        ----------
        particle : Hexagon, RandomHexagon or Triangle
            The run's particle.

        Returns
        -------
        dict
            The tolerance in force units, the surrogate's deformation energy per bond (bulk
            energy per particle over bonds per bulk particle), warm starts as the method takes
            them, and the move probabilities.
        """
        method = self.resolved_method
        tiling = tiling_facts(particle.tiling)
        return dict(method=method, tol=self.tol * particle.force_scale, max_iter=self.max_iter, cache=self.cache,
                    warm_start=self.warm_start, delayed_acceptance=self.delayed_acceptance,
                    bond_deformation=float(particle.bulk_energy_per_particle) / tiling["bulk_bonds_per_particle"],
                    cluster_moves=self.cluster_moves, cluster_link=self.cluster_link,
                    bonded_moves=self.bonded_moves, surface_moves=self.surface_moves,
                    parent_start=self.warm_start and method == "newton",
                    parent_factor=self.parent_factor and self.warm_start and method == "newton",
                    parent_factor_min_particles=self.parent_factor_min_particles)


def chain_options(options, fields: dict) -> MonteCarloOptions:
    """The options of a run: ``options`` with the keyword ``fields`` replaced.

    Parameters
    ----------
    options : MonteCarloOptions or None
        The base options (None: ``MonteCarloOptions()``).
    fields : dict
        Fields given as keywords to an entry point.

    Returns
    -------
    MonteCarloOptions
        The options, checked.

    Raises
    ------
    TypeError
        A keyword that is no field, or ``options`` of another type.
    ValueError
        A field out of range.
    """
    names = {f.name for f in dataclasses.fields(MonteCarloOptions)}
    unknown = sorted(set(fields) - names)
    if unknown:
        raise TypeError(f"unexpected keyword argument(s) {', '.join(map(repr, unknown))}; the chain's options are "
                        f"{', '.join(sorted(names))}")
    if options is None:
        return MonteCarloOptions(**fields)
    if not isinstance(options, MonteCarloOptions):
        raise TypeError(f"options must be a MonteCarloOptions, got {type(options).__name__}")
    return options.replace(**fields) if fields else options
