"""Relaxation of an aggregate at fixed topology (main text Eq. 7, inner minimisation).

Two methods, a speed/accuracy knob:

``"lbfgs"``   NLopt's L-BFGS on the full nonlinear energy, to a gradient tolerance.
``"linear"``  one sparse Cholesky (LDL^T) solve of the quadratic expansion about the bulk
              reference, with the stiffness of the particles at eps = 0: exact as eps -> 0,
              error O(eps^2) relative in the energy, and far cheaper.
``"newton"``  the nonlinear minimum to the same tolerance as L-BFGS, by Newton steps that
              reuse that one factorisation (a few steps at small eps); L-BFGS takes over where
              they stall. Usually the fastest exact method.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from . import _kernel
from .topology import Topology

METHODS = ("lbfgs", "linear", "newton")


class ConvergenceWarning(RuntimeWarning):
    """A minimisation stopped before reaching its tolerance."""


@dataclass(frozen=True)
class Relaxation:
    """Result of ``relax``.

    Attributes
    ----------
    energy : float
        Deformation energy of the aggregate (of one cell if periodic).
    n_particles, n_bonds : int
        Particles and bound pairs of sides (per cell if periodic).
    state : ndarray
        Degrees of freedom: corners ``(x0, y0, x1, ...)`` then period-map parameters
        (fibre: ``tx, ty[, bend]`` with ``bend = bend_scale * angle`` between images, see
        ``Topology``; bulk: ``t1x, t1y, t2x, t2y``).
    converged : bool
        L-BFGS: the largest gradient component fell below ``tol * particle.force_scale``
        (``eps * max(k, |k_area|, kc)``); linear: the solve succeeded.
    iterations : int
        Energy and gradient evaluations (1 for the linear solve).
    gradient_norm : float
        Largest gradient component of the full energy at ``state``.
    status : str
        The minimiser's last word.
    method : str
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

    @property
    def energy_per_particle(self) -> float:
        return self.energy / self.n_particles

    @property
    def positions(self) -> np.ndarray:
        """Corner positions, shape (n_corners, 2)."""
        return self.state[: 2 * self.n_corners].reshape(-1, 2)

    @property
    def period(self) -> np.ndarray:
        """Period-map parameters (empty for a finite aggregate)."""
        return self.state[2 * self.n_corners:]


def relax(particle, topology: Topology, method: str = "lbfgs", tol: float = 1e-5, x0=None,
          max_iter: int = 500_000, memory: int = 10) -> Relaxation:
    """Minimise the deformation energy of ``topology`` made of ``particle``s.

    Parameters
    ----------
    particle : Hexagon or RandomHexagon
    topology : Topology
    method : {"lbfgs", "linear", "newton"}
    tol : float
        L-BFGS stops when the largest gradient component is below ``tol * particle.force_scale``
        (forces are of order ``eps * max(k, |k_area|)``).
    x0 : None, "linear" or array
        L-BFGS start: the bulk reference (None), the linear solution ("linear", usually the
        fastest route to the nonlinear minimum) or a given state (warm start, same layout as
        ``Relaxation.state``).
    max_iter : int
        Cap on energy and gradient evaluations.

    A run that stops short of ``tol`` returns ``converged=False`` and emits a
    ``ConvergenceWarning``; a non-finite energy raises ``RuntimeError``.
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    if not (tol > 0):
        raise ValueError(f"tol must be positive, got {tol!r}")
    model = particle._kernel_model
    if method == "linear":
        out = _kernel.relax_linear(model, topology.kernel)
    elif method == "newton":
        if x0 is not None:
            raise ValueError("x0: method='newton' always starts from the linear solution")
        out = _kernel.relax_newton(model, topology.kernel, tol * particle.force_scale, int(max_iter))
    else:
        if x0 is None:
            start = topology.reference_state()
        elif isinstance(x0, str):
            if x0 != "linear":
                raise ValueError(f"x0 must be None, 'linear' or an array, got {x0!r}")
            start = np.asarray(_kernel.relax_linear(model, topology.kernel)["x"])
        else:
            start = np.asarray(x0, dtype=float).ravel()
            if start.shape != topology.reference_state().shape:
                raise ValueError(f"x0 has {start.size} entries, the topology needs {topology.reference_state().size}")
        out = _kernel.relax_lbfgs(model, topology.kernel, start, tol * particle.force_scale, int(max_iter), int(memory))
    if not np.isfinite(out["energy"]):
        raise RuntimeError(f"relax: the energy became non-finite ({out['status']})")
    if out["energy"] < 0:
        # Every term is non-negative near the reference (the sheet is stable for k_area > -sqrt3 k);
        # a negative energy means the minimiser left that basin (k_area < 0 is unbounded below).
        raise RuntimeError(f"relax({topology.label}): the minimiser escaped the physical minimum (energy "
                           f"{out['energy']:.3g} < 0, {particle!r}); try x0='linear' or a larger tol")
    if not out["converged"]:
        warnings.warn(f"relax({topology.label}, method={method!r}) did not converge: {out['status']}, "
                      f"max gradient {out['gradient_norm']:.3g} after {out['iterations']} evaluations",
                      ConvergenceWarning, stacklevel=2)
    return Relaxation(float(out["energy"]), topology.n_particles, topology.n_bonds, np.asarray(out["x"]),
                      bool(out["converged"]), int(out["iterations"]), float(out["gradient_norm"]), out["status"],
                      method, topology.n_corners)


def energy(particle, topology: Topology, state) -> tuple[float, np.ndarray]:
    """Deformation energy at ``state`` and its gradient (same layout)."""
    return _kernel.energy(particle._kernel_model, topology.kernel, np.asarray(state, dtype=float))


def particle_energies(particle, topology: Topology, state) -> np.ndarray:
    """Deformation energy of each particle, shape (n_particles,)."""
    return np.asarray(_kernel.particle_energies(particle._kernel_model, topology.kernel, np.asarray(state, dtype=float)))


def particle_corners(particle, topology: Topology, state) -> np.ndarray:
    """Corner positions seen by each particle (periodic images applied), shape (n_particles, 6, 2)."""
    c = _kernel.particle_corners(particle._kernel_model, topology.kernel, np.asarray(state, dtype=float))
    return np.asarray(c).reshape(topology.n_particles, -1, 2)


def periodic_images(topology: Topology, state, corners, images=range(-1, 2)) -> np.ndarray:
    """Corners of several periods of a periodic cell, for drawing.

    ``corners``: (n_particles, m, 2) corners of the cell (``particle_corners``); ``images``:
    the period indices to generate (fibre) — a bulk cell is repeated over ``images x images``.
    Returns (n_images * n_particles, m, 2). A finite topology is returned unchanged.
    """
    state = np.asarray(state, float)
    corners = np.asarray(corners, float)
    if topology.periodicity == "none":
        return corners
    shifts = [(a, b) for a in images for b in images] if topology.periodicity == "bulk" else [(n, 0) for n in images]
    flat = corners.reshape(-1, 2)
    return np.concatenate([np.asarray(topology.kernel.image_points(state, flat, a, b)).reshape(corners.shape)
                           for a, b in shifts])


def fiber_curvature(topology: Topology, state) -> float:
    """Curvature (1/radius, lattice units) of a relaxed curved fibre: the angle between
    successive images over the period length. Zero for straight fibres."""
    if topology.periodicity != "fiber" or not topology.curved:
        return 0.0
    period = np.asarray(state, float)[2 * topology.n_corners:]
    return float(period[2] / topology.kernel.bend_scale / np.linalg.norm(period[:2]))
