"""Relaxation of an aggregate at fixed topology (main text Eq. 7, inner minimisation).

Methods, a speed/accuracy knob:

``"auto"``    (default) the fastest exact method for the scene, chosen by measurement: ``"newton"``
              (see ``AUTO_METHOD`` and benchmarks/README.md).
``"newton"``  the nonlinear minimum to ``tol``, down to round-off: from the linear response,
              quasi-Newton steps on the factorised eps = 0 stiffness while they are cheaper,
              then exact-Hessian steps (the period map's curvature included; damped where the
              Hessian is indefinite), each with a line search that guarantees descent; strongly
              nonlinear scenes go to L-BFGS and back. CHOLMOD's supernodal Cholesky; its
              symbolic analysis is made once per topology (``StiffnessCache``).
``"lbfgs"``   NLopt's L-BFGS on the full nonlinear energy, to a gradient tolerance; when NLopt
              stops short of it (ftol, xtol, roundoff) Newton steps finish the job, and the
              result's ``status`` says which did the work.
``"linear"``  one sparse Cholesky solve of the quadratic expansion about the bulk reference, with
              the stiffness of the particles at eps = 0: exact as eps -> 0, error O(eps^2)
              relative in the energy, and cheaper still.

All work on the displacement from the bulk reference (``Relaxation.displacement``): a particle
is evaluated in its own frame, so forces keep their digits however large the aggregate.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from . import _kernel
from . import _checks
from ._checks import integer
from .topology import Topology

METHODS = ("auto", "lbfgs", "linear", "newton")
#: What ``method="auto"`` runs: Newton was the fastest exact method on every scene measured
#: (benchmarks/bench_relax.py: disks R = 10-100 and fibres of width 30 and 300, tol 1e-5 to 1e-10).
AUTO_METHOD = "newton"


class StiffnessCache:
    """What repeated relaxations of one topology reuse.

    The sparsity pattern of its Hessian, CHOLMOD's symbolic analysis (fill-reducing ordering,
    supernodes) and the factorised eps = 0 stiffness of the last particle stiffness it served
    (refactorised, numerically only, when another particle comes). The caller owns it; pass it as
    ``relax(..., cache=...)``. Threads sharing one take turns (each relaxation holds it for its
    duration).

    Parameters
    ----------
    topology : Topology
        The one topology it serves; ``relax`` refuses it for another.

    Examples
    --------
    >>> from pyfrustrate import Hexagon, StiffnessCache, relax, topology
    >>> disk = topology.disk(3)
    >>> cache = StiffnessCache(disk)
    >>> for nu in (0.3, 0.5, 0.7):
    ...     _ = relax(Hexagon.from_continuum(ell=2, nu=nu), disk, cache=cache)
    >>> cache.reference_factorizations  # one symbolic analysis, a numeric factorisation per particle
    3
    """

    def __init__(self, topology: Topology):
        self.topology = topology
        self._kernel = _kernel.StiffnessCache(topology.kernel)

    @property
    def reference_factorizations(self) -> int:
        """How many times the eps = 0 stiffness was factorised."""
        return self._kernel.reference_factorizations

    @property
    def factor_nonzeros(self) -> int:
        """Nonzeros of the Cholesky factor (-1 before the first solve)."""
        return self._kernel.factor_nonzeros

    def __repr__(self):
        return f"StiffnessCache({self.topology.label}, factorised {self.reference_factorizations}x)"


class ConvergenceWarning(RuntimeWarning):
    """A minimisation stopped before reaching its tolerance (the result says ``converged=False``)."""


@dataclass(frozen=True)
class Relaxation:
    """Result of ``relax``.

    Energies are **deformation energies** only, in the particle's energy unit (``k`` times squared
    lattice spacings): the binding is not included. The total energy at binding energy ``g`` per
    bound pair of sides is ``energy - g * n_bonds``.

    Attributes
    ----------
    energy : float
        Deformation energy of the aggregate (of one cell if periodic).
    n_particles, n_bonds : int
        Particles and bound pairs of sides (per cell if periodic).
    state : ndarray, shape (2 n_corners + n_period_parameters,)
        Degrees of freedom: corners ``(x0, y0, x1, ...)`` in lattice spacings, then period-map
        parameters (fibre: ``tx, ty[, bend]`` with ``bend = bend_scale * angle`` between images,
        see ``Topology``; bulk: ``t1x, t1y, t2x, t2y``).
    converged : bool
        The largest gradient component fell below ``tol * particle.force_scale``
        (``eps * max(k, |k_area|, kc)``); linear: the solve succeeded.
    iterations : int
        Energy and gradient evaluations (1 for the linear solve).
    gradient_norm : float
        Largest gradient component of the full energy at ``state``.
    status : str
        The minimisers' last word: which did the work and why it stopped.
    method : str
        The method run (``"auto"`` resolved).
    n_corners : int
        Distinct corners of the topology.
    displacement : ndarray, shape like ``state``
        ``state`` minus the bulk reference state, exact to round-off (``state`` rounds it to
        the size of the coordinates).
    newton_steps, factorizations, lbfgs_evaluations : int
        Newton steps taken, exact Hessians factorised, evaluations spent in L-BFGS.
    factor : RelaxedCluster or None
        With ``keep_factor=True`` or a ``parent`` (Newton): this aggregate with its Hessian
        factor, to pass as ``parent`` when relaxing an aggregate a few particles away.
    from_parent : bool
        The parent's factor was modified and used (else the relaxation was made fresh).
    """

    energy: float
    n_particles: int
    n_bonds: int
    state: np.ndarray
    converged: bool
    iterations: int
    gradient_norm: float
    status: str
    method: str
    n_corners: int
    displacement: np.ndarray
    newton_steps: int = 0
    factorizations: int = 0
    lbfgs_evaluations: int = 0
    factor: object = None
    from_parent: bool = False

    @property
    def energy_per_particle(self) -> float:
        """Deformation energy per particle (``energy / n_particles``); divide by the particle's
        ``bulk_energy_per_particle`` for the continuum's unit, ``e_bulk`` per unit area.
        """
        return self.energy / self.n_particles

    @property
    def positions(self) -> np.ndarray:
        """Corner positions in lattice spacings, shape (n_corners, 2)."""
        return self.state[: 2 * self.n_corners].reshape(-1, 2)

    @property
    def period(self) -> np.ndarray:
        """Period-map parameters, shape (n_period_parameters,) (empty for a finite aggregate)."""
        return self.state[2 * self.n_corners:]


def relax(particle, topology: Topology, method: str = "auto", tol: float = 1e-5, x0=None,
          max_iter: int = 500_000, memory: int = 10, cache: StiffnessCache | None = None,
          parent=None, keep_factor: bool = False) -> Relaxation:
    """Minimise the deformation energy of ``topology`` made of ``particle`` s at fixed topology.

    The inner minimisation of main text Eq. 7. The result is the **deformation energy only**: the
    binding is not included. To compare with the continuum theory, take the continuum at
    ``Gamma = 0``: ``energy_per_particle / particle.bulk_energy_per_particle`` is the energy per
    unit area in units of ``e_bulk``, to set against e.g. ``continuum.fiber_energy(W / ell, nu,
    0)`` with ``W`` the topology's ``size``. Or add the binding yourself: the total energy is
    ``energy - g * n_bonds``, with ``g`` from ``continuum.particle_parameters`` (whose
    ``convention`` says how Gamma maps to ``g``).

    Parameters
    ----------
    particle : Hexagon, Triangle or RandomHexagon
        The particle model (any ``Particle`` of the topology's tiling).
    topology : Topology
        The aggregate (``pyfrustrate.topology``).
    method : {"auto", "newton", "lbfgs", "linear"}, optional
        ``"auto"`` runs the fastest exact method (``AUTO_METHOD``); see the module docstring.
    tol : float, optional
        Stop when the largest gradient component is below ``tol * particle.force_scale``
        (forces are of order ``eps * max(k, |k_area|)``). Newton reaches 1e-12 where round-off
        allows; a run stopped by round-off says so in ``status``.
    x0 : None, "linear" or array_like, optional
        L-BFGS start: the bulk reference (None), the linear solution ("linear") or a given
        state (warm start, same layout as ``Relaxation.state``). Newton always starts from the
        linear solution.
    max_iter : int, optional
        Cap on energy and gradient evaluations.
    memory : int, optional
        L-BFGS's stored pairs of updates.
    cache : StiffnessCache, optional
        Reuse the symbolic analysis and reference factorisation of earlier relaxations of the
        same topology (one is made and dropped otherwise).
    parent : RelaxedCluster, optional
        ``Relaxation.factor`` of an aggregate that differs from ``topology`` by a few particles
        (same tiling, sites matched): Newton starts from its relaxed state and modifies its
        factor (rows added and deleted, low-rank updates) instead of making one; the energy is
        exact to ``tol`` as always (kernel/parent_factor.hpp). Periodic cells relax fresh.
    keep_factor : bool, optional
        Return this aggregate's factor as ``Relaxation.factor`` (Newton).

    Returns
    -------
    Relaxation
        A run that stops short of ``tol`` returns ``converged=False`` and emits a
        ``ConvergenceWarning`` with the reason.

    Raises
    ------
    TypeError
        If ``particle`` is not a particle model or ``topology`` not a ``Topology``.
    ValueError
        For a bad method, tolerance, start, cache, or a topology in several pieces with
        ``method='linear'`` or ``'newton'``.
    RuntimeError
        If the energy becomes non-finite or the minimiser leaves the physical minimum.

    Examples
    --------
    A straight fibre of 6 rows against the continuum at the same ``ell`` and ``nu``, at
    ``Gamma = 0`` since ``relax`` returns deformation energy only:

    >>> from pyfrustrate import Hexagon, continuum, relax, topology
    >>> p = Hexagon.from_continuum(ell=2.0, nu=0.5)
    >>> f = topology.fiber(6, curved=False)
    >>> r = relax(p, f)
    >>> r.converged, r.n_particles, r.n_bonds
    (True, 6, 16)
    >>> round(float(r.energy_per_particle / p.bulk_energy_per_particle), 3)
    0.502
    >>> round(float(continuum.fiber_energy(f.size / 2.0, 0.5, 0.0)), 3)  # W / ell, nu, Gamma = 0
    0.503
    """
    _check_scene(particle, topology)
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    if not (isinstance(tol, (int, float, np.floating, np.integer)) and 0 < tol < np.inf):
        # tol = inf would stop every method at once and call the start converged.
        raise ValueError(f"tol must be positive and finite, got {tol!r}")
    for name, value in (("max_iter", max_iter), ("memory", memory)):
        integer(name, value, 1, 2**31 - 1)  # the kernel's int
    if cache is not None:
        if not isinstance(cache, StiffnessCache):
            raise ValueError(f"cache must be a StiffnessCache, got {type(cache).__name__}")
        if cache.topology is not topology:
            raise ValueError(f"cache: it was made for {cache.topology.label}, not for {topology.label}")
    if method == "newton" and x0 is not None:
        raise ValueError("x0: method='newton' always starts from the linear solution")
    if parent is not None and not isinstance(parent, _kernel.RelaxedCluster):
        raise TypeError(f"parent must be the .factor of an earlier Relaxation (relax(..., keep_factor=True)), "
                        f"got {type(parent).__name__}")
    model = particle._kernel_model
    start, from_linear = None, False
    if isinstance(x0, str):
        if x0 != "linear":
            raise ValueError(f"x0 must be None, 'linear' or an array, got {x0!r}")
        from_linear = True
    elif x0 is not None:
        state = np.asarray(x0, dtype=float).ravel()
        if state.shape != topology.reference_state().shape:
            raise ValueError(f"x0 has {state.size} entries, the topology needs {topology.reference_state().size}")
        if not np.all(np.isfinite(state)):
            raise ValueError("x0 contains non-finite values")
        start = state - topology.reference_state()
    # The kernel's one policy (kernel/relax_policy.hpp) picks the method for "auto", its start and
    # fallbacks; a parent's factor is modified instead of a new one made.
    out = _kernel.relax(model, topology.kernel, method, tol * particle.force_scale, int(max_iter), int(memory),
                        start=start, lbfgs_from_linear=from_linear, cache=cache._kernel if cache is not None else None,
                        parent=parent, keep_factor=bool(keep_factor or parent is not None))
    method = out["method"]
    if not np.isfinite(out["energy"]):
        raise RuntimeError(f"relax: the energy became non-finite ({out['status']})")
    if out["energy"] < -10 * topology.n_particles * particle.force_scale * particle.eps:
        # The energy is of order eps^2 max(k, |k_area|) per particle in the physical basin; far
        # below, the minimiser left it (k_area < 0 is unbounded below: the area term is quartic
        # in the coordinates, the springs quadratic). Near the sheet's stability limit a
        # minimum may be slightly negative, which is not flagged.
        raise RuntimeError(f"relax({topology.label}): the minimiser escaped the physical minimum (energy "
                           f"{out['energy']:.3g} < 0, {particle!r}); try x0='linear' or a larger tol")
    if not out["converged"]:
        warnings.warn(f"relax({topology.label}, method={method!r}) did not converge: {out['status']}, "
                      f"max gradient {out['gradient_norm']:.3g} = {out['gradient_norm'] / particle.force_scale:.2g} "
                      f"force_scale (tol {tol:g}) after {out['iterations']} evaluations",
                      ConvergenceWarning, stacklevel=2)
    return Relaxation(float(out["energy"]), topology.n_particles, topology.n_bonds, np.asarray(out["x"]),
                      bool(out["converged"]), int(out["iterations"]), float(out["gradient_norm"]), out["status"],
                      method, topology.n_corners, np.asarray(out["displacement"]), int(out["newton_steps"]),
                      int(out["factorizations"]), int(out["lbfgs_evaluations"]), out["factor"],
                      bool(out["from_parent"]))


def _check_scene(particle, topology) -> None:
    """TypeError naming the argument that is not a particle model or not a ``Topology`` (rather
    than an AttributeError from deep inside). A particle of another tiling is the kernel's to refuse."""
    _checks.particle("particle", particle)
    if not isinstance(topology, Topology):
        raise TypeError(f"topology must be a pyfrustrate.topology.Topology, got {type(topology).__name__}")


def _state(particle, topology: Topology, state) -> np.ndarray:
    """``state`` as the flat float array the topology's degrees of freedom need, or ValueError."""
    _check_scene(particle, topology)
    try:
        x = np.asarray(state, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"state must be an array of numbers, got {type(state).__name__}") from None
    size = 2 * topology.n_corners + topology.kernel.n_period_parameters
    if x.ndim != 1 or x.size != size:
        raise ValueError(f"state must have shape ({size},) for this topology, got {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("state contains non-finite values")
    return x


def energy(particle, topology: Topology, state) -> tuple[float, np.ndarray]:
    """Deformation energy at a given state, and its gradient.

    Parameters
    ----------
    particle : Hexagon, Triangle or RandomHexagon
        The particle model (any ``Particle`` of the topology's tiling).
    topology : Topology
        The aggregate (``pyfrustrate.topology``).
    state : array_like, shape (2 n_corners + n_period_parameters,)
        Degrees of freedom, laid out as ``Relaxation.state`` (corners, then period parameters).

    Returns
    -------
    energy : float
        Deformation energy (of one cell if periodic), binding not included.
    gradient : ndarray, shape like ``state``
        Its derivative with respect to ``state``.

    Raises
    ------
    TypeError
        If ``particle`` is not a particle model or ``topology`` not a ``Topology``.
    ValueError
        If ``state`` has the wrong shape or non-finite entries.
    """
    x = _state(particle, topology, state)  # checks the particle before its attributes are read
    return _kernel.energy(particle._kernel_model, topology.kernel, x)


def particle_energies(particle, topology: Topology, state) -> np.ndarray:
    """Deformation energy of each particle at a given state.

    Parameters
    ----------
    particle : Hexagon, Triangle or RandomHexagon
        The particle model (any ``Particle`` of the topology's tiling).
    topology : Topology
        The aggregate (``pyfrustrate.topology``).
    state : array_like, shape (2 n_corners + n_period_parameters,)
        Degrees of freedom, laid out as ``Relaxation.state`` (corners, then period parameters).

    Returns
    -------
    ndarray, shape (n_particles,)
        In the order of ``topology.sites``; they sum to the aggregate's energy.

    Raises
    ------
    TypeError
        If ``particle`` is not a particle model or ``topology`` not a ``Topology``.
    ValueError
        If ``state`` has the wrong shape or non-finite entries.

    Examples
    --------
    >>> import numpy as np
    >>> from pyfrustrate import Hexagon, relax, topology
    >>> from pyfrustrate.relaxation import particle_energies
    >>> p, disk = Hexagon.from_continuum(ell=2.0, nu=0.5), topology.disk(1)
    >>> r = relax(p, disk)
    >>> e = particle_energies(p, disk, r.state)
    >>> np.round(e / p.bulk_energy_per_particle, 3)  # the centre (site (0, 0)) deforms least
    array([0.067, 0.067, 0.067, 0.02 , 0.067, 0.067, 0.067])
    >>> bool(np.isclose(e.sum(), r.energy))
    True
    """
    x = _state(particle, topology, state)
    return np.asarray(_kernel.particle_energies(particle._kernel_model, topology.kernel, x))


def particle_corners(particle, topology: Topology, state) -> np.ndarray:
    """Corner positions seen by each particle, periodic images applied.

    Parameters
    ----------
    particle : Hexagon, Triangle or RandomHexagon
        The particle model (any ``Particle`` of the topology's tiling).
    topology : Topology
        The aggregate (``pyfrustrate.topology``).
    state : array_like, shape (2 n_corners + n_period_parameters,)
        Degrees of freedom, laid out as ``Relaxation.state`` (corners, then period parameters).

    Returns
    -------
    ndarray, shape (n_particles, corners per particle, 2)
        In lattice spacings, in the kernel's slot order (``Hexagon.evaluate``).

    Raises
    ------
    TypeError
        If ``particle`` is not a particle model or ``topology`` not a ``Topology``.
    ValueError
        If ``state`` has the wrong shape or non-finite entries.
    """
    x = _state(particle, topology, state)
    c = _kernel.particle_corners(particle._kernel_model, topology.kernel, x)
    return np.asarray(c).reshape(topology.n_particles, -1, 2)


def periodic_images(topology: Topology, state, corners, images=range(-1, 2)) -> np.ndarray:
    """Corners of several periods of a periodic cell, for drawing.

    Parameters
    ----------
    topology : Topology
        The cell.
    state : array_like
        Its relaxed state (``Relaxation.state``).
    corners : array_like, shape (n_particles, m, 2)
        Corners of the cell (``particle_corners``).
    images : iterable of int, optional
        The period indices to generate (fibre); a bulk cell is repeated over ``images x images``.

    Returns
    -------
    ndarray, shape (n_images * n_particles, m, 2)
        A finite topology's corners are returned unchanged.

    Raises
    ------
    ValueError
        If ``state`` or ``corners`` hold non-finite values.
    """
    state = np.asarray(state, float)
    corners = np.asarray(corners, float)
    for name, value in (("state", state), ("corners", corners)):
        if not np.all(np.isfinite(value)):
            raise ValueError(f"{name} contains non-finite values")
    if topology.periodicity == "none":
        return corners
    shifts = [(a, b) for a in images for b in images] if topology.periodicity == "bulk" else [(n, 0) for n in images]
    flat = corners.reshape(-1, 2)
    return np.concatenate([np.asarray(topology.kernel.image_points(state, flat, a, b)).reshape(corners.shape)
                           for a, b in shifts])


def relaxed_drawing(particle, topology: Topology, images=None, **relax_options):
    """What a figure draws of a relaxed aggregate.

    Parameters
    ----------
    particle : Hexagon, Triangle or RandomHexagon
        The particle model (any ``Particle`` of the topology's tiling).
    topology : Topology
        The aggregate (``pyfrustrate.topology``).
    images : iterable of int, optional
        Periods of a periodic cell to repeat (``periodic_images``); None: the cell alone.
    **relax_options
        Passed to ``relax``.

    Returns
    -------
    corners : ndarray, shape (n, corners per particle, 2)
        Each particle's corners (``particle_corners``), repeated over ``images``.
    energies : ndarray, shape (n,)
        Each particle's deformation energy (``particle_energies``), repeated alike.
    relaxation : Relaxation
        The relaxation of the cell.

    Raises
    ------
    TypeError, ValueError, RuntimeError
        As ``relax``.

    Examples
    --------
    >>> from pyfrustrate import Hexagon, topology
    >>> from pyfrustrate.relaxation import relaxed_drawing
    >>> p = Hexagon.from_continuum(ell=2.0, nu=0.5)
    >>> corners, energies, r = relaxed_drawing(p, topology.fiber(3), images=range(-1, 2))
    >>> corners.shape, energies.shape  # three periods of a 3-particle cell
    ((9, 6, 2), (9,))

    Drawn with ``pyfrustrate.plotting.draw_hexagons(ax, corners, energies)``.
    """
    r = relax(particle, topology, **relax_options)
    corners = particle_corners(particle, topology, r.state)
    energies = particle_energies(particle, topology, r.state)
    if images is not None and topology.periodicity != "none":
        count = len(images) if topology.periodicity == "fiber" else len(images) ** 2
        corners = periodic_images(topology, r.state, corners, images=images)
        energies = np.tile(energies, count)
    return corners, energies, r


def fiber_curvature(topology: Topology, state) -> float:
    """Curvature of a relaxed curved fibre: the angle between successive images over the period
    length.

    Parameters
    ----------
    topology : Topology
        The fibre.
    state : array_like
        Its relaxed state.

    Returns
    -------
    float
        In inverse lattice spacings; 0 for straight fibres and other topologies.
    """
    if topology.periodicity != "fiber" or not topology.curved:
        return 0.0
    period = np.asarray(state, float)[2 * topology.n_corners:]
    return float(period[2] / topology.kernel.bend_scale / np.linalg.norm(period[:2]))
