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

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .. import _checks, _kernel, continuum
from .._checks import non_negative
from ..relaxation import AUTO_METHOD
from ..topology import tiling_facts

__all__ = ["MonteCarloOptions", "binding", "chain_options", "check_particle", "DEFAULTS_MEASURED",
           "KERNEL_OPTION_FIELDS"]

#: Where the defaults of ``MonteCarloOptions`` were measured: the paper profile's Monte Carlo
#: diagram (81 runs of 200 hexagons in 60 x 60, ell = 5), whose runs with these moves ended within
#: 5 bulk energies of the box's ground state most often of the settings tried (the documentation's
#: results log, "With surface moves, the paper profile's diagram"; config/paper.yaml,
#: ``montecarlo``; benchmarks/bench_equilibration.py compares the move settings at equal sweeps).
DEFAULTS_MEASURED = ("docs/results_log.md (the paper profile's Monte Carlo diagram with surface moves), config/paper.yaml, "
                     "benchmarks/bench_equilibration.py")


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


#: The kernel's table of the chain's options (kernel/montecarlo/options.hpp), one dict per field:
#: name, kind, scope, default, range, doc. The fields of scope ``"run"`` are ``MonteCarloOptions``'s;
#: the others the kernel takes from the particle (``kernel_arguments``) or only benchmarks set.
KERNEL_OPTION_FIELDS = tuple(_kernel.monte_carlo_option_fields())
_RUN_FIELDS = tuple(f for f in KERNEL_OPTION_FIELDS if f["scope"] == "run")
_PYTHON_TYPES = {"flag": bool, "real": float, "integer": int, "method": str}


class MonteCarloOptions:
    # The docstring and the fields are the kernel table's (below the class): nothing here repeats
    # a name, a default or a range.
    if TYPE_CHECKING:  # made at import from the table: a type checker sees keywords and attributes
        def __init__(self, **fields: Any) -> None: ...

        def __getattr__(self, name: str) -> Any: ...

    def __post_init__(self):
        # The one check, the kernel's: a bad value raises ValueError naming its field and range.
        checked = _kernel.check_monte_carlo_options(**self._values())
        for field in _RUN_FIELDS:  # frozen: the checked values replace the given ones once
            object.__setattr__(self, field["name"], checked[field["name"]])

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
        return type(self)(**{**self._values(), **changes})

    def _values(self) -> dict:
        """Every field by name, in the table's order."""
        return {field["name"]: getattr(self, field["name"]) for field in _RUN_FIELDS}

    def signature(self) -> dict:
        """What a checkpoint records of these options.

        Returns
        -------
        dict
            Every field that changes the chain (not ``cache``, which changes only its speed),
            ``method`` resolved.
        """
        d = self._values()
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
            These fields (``method`` resolved) and those the kernel takes from the particle: its
            force scale (the unit of ``tol``), the surrogate's deformation energy per bond (bulk
            energy per particle over bonds per bulk particle), and warm starts as the method
            takes them (``parent_start``: Newton from the parents' relaxed state; ``parent_factor``
            only with it).
        """
        method = self.resolved_method
        tiling = tiling_facts(particle.tiling)
        parent_start = self.warm_start and method == "newton"
        return dict(self._values(), method=method, force_scale=float(particle.force_scale),
                    bond_deformation=float(particle.bulk_energy_per_particle) / tiling["bulk_bonds_per_particle"],
                    parent_start=parent_start, parent_factor=self.parent_factor and parent_start)


def _field_list(fields) -> str:
    """A numpydoc Parameters section of the kernel table's ``fields``."""
    return "\n".join(f"    {f['name']} : {_PYTHON_TYPES[f['kind']].__name__}\n        {f['doc'][0].upper()}{f['doc'][1:]}; "
                     f"{f['range']}, default ``{f['default']!r}``." for f in fields)


MonteCarloOptions.__doc__ = f"""How a Monte Carlo chain moves and relaxes (the ``anneal`` docstring explains each field).

    Made once, checked once, by the kernel (``kernel/montecarlo/options.hpp``, whose table gives
    the fields, their defaults and ranges): a bad value raises ``ValueError`` naming it.

    Parameters
    ----------
{_field_list(_RUN_FIELDS)}

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
    >>> MonteCarloOptions(cluster_link=2)
    Traceback (most recent call last):
    ...
    ValueError: cluster_link must be a number in [0, 1], got 2
    """
MonteCarloOptions.__annotations__ = {f["name"]: _PYTHON_TYPES[f["kind"]] for f in _RUN_FIELDS}
for _field in _RUN_FIELDS:
    setattr(MonteCarloOptions, _field["name"], _field["default"])
dataclass(frozen=True)(MonteCarloOptions)  # in place: the class keeps its name for type checkers
del _field


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
        A field out of range, or outline moves (a run of fixed ``n``: ``anneal`` and
        ``replica_exchange`` record ``n`` particles per block; grand-canonical sampling is
        ``montecarlo.grand_canonical``).
    """
    names = {field["name"] for field in _RUN_FIELDS}
    unknown = sorted(set(fields) - names)
    if unknown:
        raise TypeError(f"unexpected keyword argument(s) {', '.join(map(repr, unknown))}; the chain's options are "
                        f"{', '.join(sorted(names))}")
    if options is not None and not isinstance(options, MonteCarloOptions):
        raise TypeError(f"options must be a MonteCarloOptions, got {type(options).__name__}")
    checked = MonteCarloOptions(**fields) if options is None else options.replace(**fields) if fields else options
    if checked.outline_moves > 0:
        raise ValueError(f"outline_moves must be 0 in a run of fixed n, got {checked.outline_moves}; grand-canonical "
                         "sampling of one aggregate is pyfrustrate.montecarlo.grand_canonical")
    return checked
