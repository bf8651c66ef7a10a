"""The one-dimensional toy model (main text Eq. 1, Fig. 1).

A row of ``n`` trapezoids: top (yellow) and bottom (red) faces are springs of stiffness ``k``
and rest lengths ``1 + eps`` and ``1 - eps``; two connecting springs of stiffness ``kc/2`` and
rest length ``eps`` centre the faces on each other. Neighbours share their vertical sides.
The corner shift ``delta_i = x_up_i - x_down_i`` decays from the edges into the aggregate as
``sinh`` with the boundary-layer length of main text Eq. (3), ``continuum.chain_ell``.

Note: force balance of Eq. (1) reads ``k (delta_{i+1} - 2 delta_i + delta_{i-1}) = 2 kc delta_i``;
the paper's Eq. (2) prints ``kc`` on the right, but its Eq. (3) (and our ``chain_ell``) follow
from the factor 2.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import _kernel


@dataclass(frozen=True)
class ChainRelaxation:
    """Relaxed 1D chain.

    Attributes
    ----------
    x_up, x_down : ndarray, shape (n + 1,)
        Corner coordinates of the top and bottom faces.
    energy : float
        Deformation energy, Eq. (1) summed over particles.
    converged : bool
        Whether the largest gradient component fell below the tolerance.
    iterations : int
        Energy and gradient evaluations used by L-BFGS.
    gradient_norm : float
        Largest gradient component at the returned state.
    status : str
        The minimiser's last word.
    """

    x_up: np.ndarray
    x_down: np.ndarray
    energy: float
    converged: bool
    iterations: int
    gradient_norm: float
    status: str

    @property
    def shift(self) -> np.ndarray:
        """``delta_i = x_up_i - x_down_i``, shape (n + 1,)."""
        return self.x_up - self.x_down


def relax(n: int, k: float = 1.0, kc: float = 0.01, eps: float = 0.01, *, tol: float = 1e-6,
          max_iter: int = 200_000) -> ChainRelaxation:
    """Minimise Eq. (1) for a chain of ``n`` particles with NLopt's L-BFGS.

    Starts from the bulk reference (unit rectangles). Converged means the largest gradient
    component is below ``tol * k * eps`` (forces are of order ``k * eps``). Invalid parameters raise ``ValueError`` naming them; a
    minimisation that does not reach ``tol`` within ``max_iter`` evaluations is reported through
    ``converged = False`` (and the status), never silently.
    """
    if not (tol > 0):
        raise ValueError(f"tol must be positive, got {tol!r}")
    out = _kernel.chain_relax(int(n), float(k), float(kc), float(eps), float(tol) * k * eps, int(max_iter))
    x = np.asarray(out["x"])
    m = int(n) + 1
    return ChainRelaxation(x[:m], x[m:], out["energy"], out["converged"], out["iterations"],
                           out["gradient_norm"], out["status"])


def energy(n: int, k: float, kc: float, eps: float, x_up, x_down) -> tuple[float, np.ndarray]:
    """Energy of Eq. (1) and its gradient with respect to ``(x_up, x_down)``, shape (2 (n + 1),)."""
    x = np.concatenate([np.asarray(x_up, float), np.asarray(x_down, float)])
    return _kernel.chain_energy(int(n), float(k), float(kc), float(eps), x)
