"""Particle models: the parameters of one particle, handed to the kernel's stateless evaluators.

``Hexagon`` is the particle of the paper (main text Fig. 2a), ``Triangle`` the triangular one of
the supplement (Fig. S6, our reconstruction of its lost design: README). Their continuum
counterparts are given by the mapping of supplement S1 (``continuum.mapping``, per tiling).

``Particle`` is the contract every particle model meets (the kernel's side is written in
``kernel/network.hpp``); ``tests/test_particle_contract.py`` checks it for every model, and a new
model inherits those tests by being listed there.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar, Protocol, runtime_checkable

import numpy as np

from . import _kernel, continuum


@runtime_checkable
class Particle(Protocol):
    """What the package asks of a particle model (a ``typing.Protocol``, checkable with
    ``isinstance``).

    Instances are immutable and pickle by their parameters. Every entry point that takes a
    particle refuses anything else with a ``TypeError`` naming the parameter
    (``pyfrustrate._checks.particle``).

    Attributes
    ----------
    tiling : str
        The tiling its topologies use (``topology.TILINGS``).
    eps : float
        The mismatch (dimensionless, in (0, 1)).
    force_scale : float
        A typical corner force (the unit of relaxation tolerances).
    bulk_energy_per_particle : float
        The leading-order deformation energy of a bulk particle.
    _kernel_model : object
        The kernel's evaluator (its class carries ``corner_count``, ``point_group``,
        ``rest_corners()``, ``energy_of_displacement``, ``without_mismatch``).

    Examples
    --------
    >>> from pyfrustrate import Hexagon, Particle, RandomHexagon
    >>> isinstance(Hexagon(), Particle), isinstance(RandomHexagon.draw(seed=1), Particle)
    (True, True)
    """

    tiling: str
    eps: float

    @property
    def force_scale(self) -> float:
        """A typical corner force: the unit of relaxation tolerances."""
        ...

    @property
    def bulk_energy_per_particle(self) -> float:
        """The leading-order deformation energy of a bulk particle."""
        ...


def _real(name: str, value) -> float:
    """``value`` as a float, or TypeError naming ``name``: float() alone would take text
    ("1.0") and report other types without saying which parameter they were."""
    try:
        if isinstance(value, (str, bytes)):
            raise TypeError
        return float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a real number, got {value!r}") from None


def _corners(corners) -> np.ndarray:
    """One particle's corners as the flat (12,) array the kernel's ``evaluate`` takes, or
    ValueError: a corner at NaN or inf would come back as a NaN energy."""
    c = np.asarray(corners, dtype=float)
    if c.size != 12 or c.shape not in ((12,), (6, 2)):
        raise ValueError(f"corners must have shape (6, 2) or (12,), got {c.shape}")
    if not np.all(np.isfinite(c)):
        raise ValueError("corners contain non-finite values")
    return c.reshape(12)


@dataclass(frozen=True)
class _SpringParticle:
    """Shared by the particles built of two spring triangles: parameters, kernel evaluator,
    continuum mapping (per tiling) and scales."""

    k: float = 1.0
    kc: float = 0.01
    k_area: float = 0.0
    eps: float = 0.01
    _kernel_model: _kernel.HexagonModel | _kernel.TriangleModel = field(init=False, repr=False, compare=False)
    tiling: ClassVar[str] = "hexagon"
    _kernel_class: ClassVar[Any] = None

    def __post_init__(self):
        for name in ("k", "kc", "k_area", "eps"):
            _real(name, getattr(self, name))
        if not (0 < self.eps < 1):
            raise ValueError(f"eps must lie in (0, 1), got {self.eps!r}")
        # The kernel checks k, kc and k_area (kernel/hexagon.hpp, triangle.hpp), naming them.
        object.__setattr__(self, "_kernel_model",
                           self._kernel_class(float(self.k), float(self.kc), float(self.k_area), float(self.eps)))

    def __reduce__(self):
        # Pickled by its parameters (the kernel evaluator is rebuilt), for process pools.
        return (type(self), (self.k, self.kc, self.k_area, self.eps))

    @classmethod
    def from_continuum(cls, ell: float, nu: float, eps: float = 0.01, k: float = 1.0):
        """The particle whose continuum limit has boundary-layer length ``ell`` and Poisson ratio ``nu``.

        Inverse of supplement S1, the same for both tilings: ``kc = k / (8 (1 - nu) ell^2)``,
        ``k_area = sqrt(3) k (3 nu - 1) / (2 (1 - nu))``, for ``-1 < nu < 1``: negative ``nu``
        (auxetic sheets) takes ``k_area`` below ``-sqrt(3) k / 2``, down to the stability limit
        ``-sqrt(3) k`` at ``nu = -1``. ``nu = 1`` is singular (``k_area`` infinite): use ``nu < 1``.
        The binding is not a property of the particle: it enters as ``g`` where energies are totalled
        (``continuum.particle_parameters(ell, nu, Gamma).g``).

        Parameters
        ----------
        ell : float
            Boundary-layer length, in lattice spacings, positive and finite.
        nu : float
            2D Poisson ratio, in (-1, 1).
        eps : float, optional
            Mismatch, in (0, 1).
        k : float, optional
            Stiffness of the triangle springs (the energy unit), positive.

        Returns
        -------
        Hexagon or Triangle
            Of the class it is called on.

        Raises
        ------
        TypeError
            If a parameter is not a real number.
        ValueError
            If a parameter is out of range, or ``ell``/``nu`` lie beyond floating point.

        Examples
        --------
        >>> from pyfrustrate import Hexagon
        >>> p = Hexagon.from_continuum(ell=2.0, nu=0.5)
        >>> p
        Hexagon(k=1.0, kc=0.0625, k_area=0.866..., eps=0.01)
        >>> float(p.continuum.ell), float(p.continuum.nu)
        (2.0, 0.5)
        """
        if not np.isfinite(_real("ell", ell)) or ell <= 0:
            raise ValueError(f"ell must be positive and finite, got {ell!r}")
        if not (-1 < _real("nu", nu) < 1):
            raise ValueError(f"nu must lie in (-1, 1) for a discrete particle, got {nu!r}")
        with np.errstate(over="ignore", divide="ignore"):  # refused just below, by name
            p = continuum.particle_parameters(ell, nu, 0.0, k=k, eps=eps, tiling=cls.tiling)
        kc, k_area = float(p.kc), float(p.k_area)
        # Extreme ell overflow kc to inf or flush it to 0 (ell = inf): neither is the particle
        # asked for, and the kernel's complaint would name kc, which the caller never gave.
        if not (0 < kc < np.inf):
            raise ValueError(f"ell = {ell!r} is out of reach in floating point: kc = k / (8 (1 - nu) ell^2) = {kc!r}")
        if not np.isfinite(k_area):
            raise ValueError(f"nu = {nu!r} is too close to 1: k_area = {k_area!r}")
        return cls(k=k, kc=kc, k_area=k_area, eps=eps)

    @property
    def continuum(self):
        """Continuum parameters at ``g = 0`` (``continuum.ContinuumParameters``: ``mu, nu, lam,
        kappa_c, ell, e_bulk``; supplement S1), ``ell`` in lattice spacings.
        """
        return continuum.mapping(self.k, self.kc, self.k_area, 0.0, self.eps, tiling=self.tiling)

    @property
    def force_scale(self) -> float:
        """Typical force on a corner, ``eps * max(k, |k_area|, kc)``: the unit of the relaxation
        tolerance (stiff areal terms at nu -> 1 raise both the forces and the precision floor).
        """
        return self.eps * max(self.k, abs(self.k_area), self.kc)

    @property
    def bulk_energy_per_particle(self) -> float:
        """Leading-order bulk deformation energy per particle, ``(3 k + sqrt(3) k_area) eps^2``.

        It is ``e_bulk`` (main text Eq. 8) times the area per particle, the same for both tilings:
        dividing a relaxed energy per particle by it gives the continuum's energy per unit area in
        units of ``e_bulk``.
        """
        return (3 * self.k + np.sqrt(3) * self.k_area) * self.eps ** 2

    def evaluate(self, corners) -> dict:
        """Energy terms, gradient and Hessian of one particle from its corners.

        Parameters
        ----------
        corners : array_like, shape (6, 2) or (12,)
            Corner positions in lattice spacings, in the kernel's slot order (``Hexagon``:
            counter-clockwise from 30 degrees, even slots red; ``Triangle``: yellow nodes at the
            vertices v0, v1, v2, then red ones).

        Returns
        -------
        dict
            ``triangles``, ``connecting``, ``area`` (the energy's terms), ``energy`` (their sum),
            ``gradient`` (12,) and ``hessian`` (12, 12).

        Raises
        ------
        ValueError
            For a wrong shape or non-finite corners.
        """
        return self._kernel_model.evaluate(_corners(corners))


@dataclass(frozen=True)
class Hexagon(_SpringParticle):
    """Hexagonal ill-fitting particle (main text Fig. 2a).

    A yellow triangle of springs ``k`` with rest length ``1 + eps`` and a red one with rest length
    ``1 - eps`` share a centre; six connecting springs ``kc`` form the hexagon's sides. Lengths are
    in lattice spacings, energies in units of ``k`` times a squared lattice spacing. Usually made
    by ``Hexagon.from_continuum(ell, nu)``.

    Parameters
    ----------
    k : float
        Stiffness of the yellow and red triangle springs (rest lengths ``1 + eps``, ``1 - eps``).
    kc : float
        Stiffness of each of the six connecting springs (the hexagon's sides).
    k_area : float
        Areal stiffness of each triangle, energy ``k_area (A - A0)^2 / (2 A0)``. May be negative
        down to ``-sqrt(3) k`` (exclusive): Poisson ratios below 1/3 need it (``from_continuum``:
        ``k_area = sqrt(3) k (3 nu - 1) / (2 (1 - nu))``).
    eps : float
        Mismatch, in (0, 1).

    Raises
    ------
    TypeError
        If a parameter is not a real number.
    ValueError
        If a parameter is out of range (named).

    Examples
    --------
    >>> from pyfrustrate import Hexagon
    >>> p = Hexagon(k=1.0, kc=0.05, k_area=0.0, eps=0.01)
    >>> round(float(p.continuum.ell), 4), round(float(p.continuum.nu), 4)
    (1.9365, 0.3333)
    >>> round(float(p.bulk_energy_per_particle), 6)  # (3 k + sqrt(3) k_area) eps^2
    0.0003
    """

    tiling: ClassVar[str] = "hexagon"
    _kernel_class: ClassVar[type[_kernel.HexagonModel]] = _kernel.HexagonModel


@dataclass(frozen=True)
class Triangle(_SpringParticle):
    """Triangular ill-fitting particle (supplement Fig. S6; the design is our reconstruction).

    Every vertex carries a yellow and a red node; the yellow triangle has springs ``k`` of rest
    length ``1 + eps``, the red one ``1 - eps``; each edge ``(a, b)`` carries two coupling springs
    ``kc`` (``Y_a-R_b``, ``Y_b-R_a``, at rest for concentric triangles: length
    ``sqrt(1 + eps^2/3)``); areal stiffness ``k_area`` on both triangles. Bound neighbours share
    the nodes of their common edge. Same parameters, limits and continuum theory as ``Hexagon``
    (twice its sheet moduli, the same ``nu`` and ``ell``); line tension ``gamma = g/2``.
    Topologies for it take ``tiling="triangle"``.

    Parameters
    ----------
    k, kc, k_area, eps : float
        As for ``Hexagon``.

    Raises
    ------
    TypeError
        If a parameter is not a real number.
    ValueError
        If a parameter is out of range (named).

    Examples
    --------
    >>> from pyfrustrate import Triangle, relax, topology
    >>> t = Triangle.from_continuum(ell=2.0, nu=0.5)
    >>> r = relax(t, topology.disk(1, tiling="triangle"))  # six triangles around a vertex
    >>> r.converged, r.n_particles, r.n_bonds
    (True, 6, 6)
    """

    tiling: ClassVar[str] = "triangle"
    _kernel_class: ClassVar[type[_kernel.TriangleModel]] = _kernel.TriangleModel


#: The spring particle of each tiling.
PARTICLE_OF_TILING = {"hexagon": Hexagon, "triangle": Triangle}


def particle_class(tiling: str):
    """The spring particle model of a tiling.

    Parameters
    ----------
    tiling : {'hexagon', 'triangle'}
        The tiling.

    Returns
    -------
    type
        ``Hexagon`` or ``Triangle``.

    Raises
    ------
    ValueError
        For an unknown tiling.
    """
    if tiling not in PARTICLE_OF_TILING:
        raise ValueError(f"tiling must be one of {tuple(PARTICLE_OF_TILING)}, got {tiling!r}")
    return PARTICLE_OF_TILING[tiling]
