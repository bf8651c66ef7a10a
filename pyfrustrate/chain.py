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
from ._checks import affordable, integer


#: Bytes per particle of a chain's relaxation: its 2 (n + 1) coordinates, the gradient and
#: L-BFGS's stored pairs of updates (10 by default in NLopt), with headroom.
CHAIN_BYTES_PER_PARTICLE = 512


@dataclass(frozen=True)
class ChainRelaxation:
    """Relaxed 1D chain, from ``relax``.

    Attributes
    ----------
    x_up, x_down : ndarray, shape (n + 1,)
        Corner coordinates of the top and bottom faces (particle widths).
    energy : float
        Deformation energy, Eq. (1) summed over particles, in units of ``k`` times a squared width.
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

    Starts from the bulk reference (unit rectangles). A minimisation that does not reach ``tol``
    within ``max_iter`` evaluations is reported through ``converged = False`` (and the status),
    never silently.

    Parameters
    ----------
    n : int
        Particles, ``>= 1``.
    k : float, optional
        Face spring stiffness (the energy unit).
    kc : float, optional
        Connecting spring stiffness (two springs ``kc/2`` per particle).
    eps : float, optional
        Mismatch.
    tol : float, optional
        Converged when the largest gradient component is below ``tol * k * eps`` (forces are of
        order ``k * eps``).
    max_iter : int, optional
        Cap on energy and gradient evaluations.

    Returns
    -------
    ChainRelaxation

    Raises
    ------
    ValueError
        For invalid parameters (named), or ``n`` too large for memory.

    Examples
    --------
    The relaxed shift against the exact solution and its decay length against Eq. 3:

    >>> import numpy as np
    >>> from pyfrustrate import chain, continuum
    >>> r = chain.relax(40, k=1.0, kc=0.01, eps=0.01)
    >>> exact = chain.analytic_shift(40, 1.0, 0.01, 0.01)
    >>> r.converged, bool(np.abs(r.shift - exact).max() < 1e-5 * np.abs(exact).max())
    (True, True)
    >>> round(float(chain.fit_decay_length(exact)), 3), round(float(continuum.chain_ell(0.01)), 3)
    (7.077, 7.077)
    """
    if not (tol > 0):
        raise ValueError(f"tol must be positive, got {tol!r}")
    n = integer("n", n, 1)
    affordable(f"chain.relax(n={n})", n * CHAIN_BYTES_PER_PARTICLE)
    out = _kernel.chain_relax(int(n), float(k), float(kc), float(eps), float(tol) * k * eps, int(max_iter))
    x = np.asarray(out["x"])
    m = int(n) + 1
    return ChainRelaxation(x[:m], x[m:], out["energy"], out["converged"], out["iterations"],
                           out["gradient_norm"], out["status"])


def energy(n: int, k: float, kc: float, eps: float, x_up, x_down) -> tuple[float, np.ndarray]:
    """Energy of Eq. (1) and its gradient.

    Parameters
    ----------
    n : int
        Particles, ``>= 1``.
    k, kc, eps : float
        As for ``relax``.
    x_up, x_down : array_like, shape (n + 1,)
        Corner coordinates of the top and bottom faces.

    Returns
    -------
    energy : float
    gradient : ndarray, shape (2 (n + 1),)
        With respect to ``(x_up, x_down)``.

    Raises
    ------
    ValueError
        For a bad ``n``.
    """
    x = np.concatenate([np.asarray(x_up, float), np.asarray(x_down, float)])
    return _kernel.chain_energy(integer("n", n, 1), float(k), float(kc), float(eps), x)


def analytic_shift(n: int, k: float, kc: float, eps: float) -> np.ndarray:
    """Exact relaxed shift ``delta_i``, i = 0..n, of a chain of ``n`` particles.

    Eq. (1) is quadratic, so force balance inside the chain,
    ``k (delta_{i+1} - 2 delta_i + delta_{i-1}) = 2 kc delta_i``, holds exactly and gives
    ``delta_i = -A sinh((n/2 - i)/ell)`` with ``ell = continuum.chain_ell(kc/k)`` (Eq. 3). The
    free edge (difference of the force balances of its top and bottom corners) fixes
    ``A = (2k + kc) eps / (k [sinh(s) - sinh(s - 1/ell)] + kc sinh(s))``, ``s = n / (2 ell)``.

    Parameters
    ----------
    n : int
        Particles, ``>= 1``.
    k : float
        Face stiffness, ``> 0``.
    kc : float
        Connecting stiffness, ``>= 0``.
    eps : float
        Mismatch, in (0, 1).

    Returns
    -------
    ndarray, shape (n + 1,)

    Raises
    ------
    ValueError
        For invalid parameters (named), or ``n`` too large for memory.
    """
    from .continuum import _checked, chain_ell

    n = integer("n", n, 1)
    affordable(f"analytic_shift(n={n})", n * CHAIN_BYTES_PER_PARTICLE)
    k = float(_checked("k", k, lo=0.0, lo_open=True))
    kc = float(_checked("kc", kc, lo=0.0))
    eps = float(_checked("eps", eps, lo=0.0, hi=1.0, lo_open=True, hi_open=True))
    ell = float(chain_ell(kc / k))
    i = np.arange(n + 1)
    if not np.isfinite(ell):  # kc = 0: no coupling, each face relaxes on its own (linear shift)
        return 2 * eps * (i - n / 2)
    s, h = n / (2 * ell), 1 / ell
    # sinh(a) / sinh(s) in overflow-free form, so long chains (n >> ell) stay finite.
    def sinh_ratio(a):
        return np.exp(a - s) * (1 - np.exp(-2 * a)) / (1 - np.exp(-2 * s)) if s > 0 else 0.0

    edge_shift = (2 * k + kc) * eps / (k * (1 - sinh_ratio(s - h)) + kc)  # -delta_0 = A sinh(s)
    x = (n / 2 - i) / ell
    return -edge_shift * np.sign(x) * sinh_ratio(np.abs(x))


def fit_decay_length(shift: np.ndarray, window: tuple[float, float] = (0.05, 0.45)) -> float:
    """Decay length of a relaxed shift profile.

    A least-squares fit of ``delta_i = -A sinh((n/2 - i)/ell)`` to the profile.

    Parameters
    ----------
    shift : array_like, shape (n + 1,)
        The profile (``ChainRelaxation.shift`` or ``analytic_shift``).
    window : tuple of float, optional
        Fractions of the chain kept, measured from the left edge; the default keeps the
        half-chain away from its edge.

    Returns
    -------
    float
        ``ell``, in particles.
    """
    from scipy.optimize import curve_fit

    shift = np.asarray(shift, float)
    n = shift.size - 1
    i = np.arange(n + 1)
    keep = (i >= window[0] * n) & (i <= window[1] * n)
    x = (n / 2 - i[keep]) / n  # in units of the chain length, to keep the fit well scaled

    def model(x, log_amp, inv_ell):
        return -np.exp(log_amp) * np.sinh(x * inv_ell)

    # Starting guess: the q = n/ell for which sinh(x q) matches the ratio of the window's ends.
    from scipy.optimize import brentq

    def log_sinh(z):
        return z + np.log1p(-np.exp(-2 * z)) - np.log(2)

    ratio = shift[keep][-1] / shift[keep][0]
    target = lambda q: log_sinh(x[-1] * q) - log_sinh(x[0] * q) - np.log(ratio)  # noqa: E731
    q0 = brentq(target, 1e-6, 600 / x[0]) if target(1e-6) * target(600 / x[0]) < 0 else 2.0
    amp0 = np.log(abs(shift[keep][0]) / np.sinh(x[0] * q0))
    (log_amp, q), _ = curve_fit(model, x, shift[keep], p0=(amp0, q0), maxfev=20000)
    return n / q
