"""Random-elasticity particles (main text "Extension to random particles", Eq. 14; supplement
sections on drawing M, on predicting ell and on the unsuccessful predictor).

A particle's shape is the vector ``d`` of nine corner distances (``DISTANCE_PAIRS``): the yellow
triangle's sides, the red triangle's sides and three alternate sides of the hexagon, each triple
in the order a 120-degree rotation permutes it. Its energy is ``(d - d0)^T M (d - d0) / 2`` with
``M`` symmetric, positive semi-definite and three-fold symmetric.

Three ways to look at one matrix, from cheap to costly:

``pseudo_moduli``
    the supplement's single-particle proxies (kappa_c, K, nu) and the predictors ``ell_pred`` (via
    main text Eq. 10) and ``ell_eigen``.
``boundary_layer_length``
    the decay length of the slowest collective mode of a half-plane in linear response, exactly,
    from the layer-to-layer transfer problem (a 16 x 16 eigenvalue problem; ``transfer_roots``).
``fitted_boundary_layer_length``
    the paper's route (Fig. 5b): relax a wide strip and fit the decay of the excess energy per
    particle away from an edge.
"""
from __future__ import annotations

import numpy as np
import scipy.linalg

from . import _checks, _kernel
from .particles import _corners
from .topology import ROW_SPACING, SQRT3

DISTANCE_PAIRS = tuple(tuple(p) for p in _kernel.RandomHexagonModel.distance_pairs)
HEXAGON_AREA = SQRT3 / 2  # A_0^hex of the supplement's pseudo-modulus (zeroth order in eps)

# Slot s of a particle at rest (bulk reference, eps = 0): 1/sqrt(3) from its site at 30 + 60 s
# degrees; even slots red, odd yellow (the kernel's rest shape, kernel/hexagon.hpp).
REST_CORNERS = np.asarray(_kernel.RandomHexagonModel.rest_corners()).reshape(6, 2)

# Deformation vectors of the supplement's pseudo-moduli (Eqs. S24-S28).
_S = 2 ** -1.5
PSEUDO_MODULUS_VECTORS = {
    "kappa_c": np.array([0, 0, 0, 0, 0, 0, -SQRT3 / 2, 0, SQRT3 / 2]),
    "K": np.array([-_S, -_S, -_S, _S, _S, _S, 0, 0, 0]),
    "K_up": np.array([0.5, 0.5, 0.5, 0, 0, 0, 0, 0, 0]),
    "mu_up": np.array([0, -SQRT3 / 4, SQRT3 / 4, 0, 0, 0, 0, 0, 0]),
    "K_down": np.array([0, 0, 0, 0.5, 0.5, 0.5, 0, 0, 0]),
    "mu_down": np.array([0, 0, 0, SQRT3 / 4, 0, -SQRT3 / 4, 0, 0, 0]),
}


def _rotation_permutation() -> np.ndarray:
    """Omega of the supplement (block-diagonal 3-cycle) as an index permutation: (Omega d)_i =
    d[perm[i]]."""
    block = np.array([2, 0, 1])
    return np.concatenate([block, block + 3, block + 6])


MATRIX_CHUNK = 10_000  # matrices drawn per random stream; matrix i comes from stream i // MATRIX_CHUNK
MATRIX_BYTES = 9 * 9 * 8  # one elasticity matrix in float64


def elasticity_matrices(n: int, seed: int, start: int = 0) -> np.ndarray:
    """Random elasticity matrices number ``start`` to ``start + n - 1`` of the sample ``seed``.

    By the supplement's procedure: ``M0`` with i.i.d. N(0, 1) entries,
    ``M1 = (M0 + W M0 W^-1 + W^2 M0 W^-2) / 3`` with ``W`` the block-diagonal 3-cycle,
    ``M = M1 M1^T``. Matrix ``i`` depends only on ``(seed, i)`` (stream ``i // MATRIX_CHUNK`` of
    the seed), so a sample drawn in pieces, in parallel, or regenerated later for one index, is
    the same.

    Parameters
    ----------
    n : int
        Number of matrices, ``>= 0``.
    seed : int
        The sample's seed.
    start : int, optional
        Index of the first matrix.

    Returns
    -------
    ndarray, shape (n, 9, 9)
        In units of ``k`` (energy per squared lattice spacing).

    Raises
    ------
    ValueError
        For a bad ``n`` or ``start``, or ``n`` too large for memory.

    Examples
    --------
    >>> import numpy as np
    >>> from pyfrustrate import random_particles as rp
    >>> M = rp.elasticity_matrices(3, seed=1)
    >>> M.shape, bool(np.allclose(M[2], rp.elasticity_matrices(1, seed=1, start=2)[0]))
    ((3, 9, 9), True)
    """
    for name, value in (("n", n), ("start", start)):
        if int(value) != value or value < 0:
            raise ValueError(f"{name} must be a non-negative integer, got {value!r}")
    n, start = int(n), int(start)
    # The result (n, 9, 9) and one chunk's draws and their symmetrised copies.
    _checks.affordable(f"elasticity_matrices(n={n})", (n + 4 * MATRIX_CHUNK) * MATRIX_BYTES)
    p = _rotation_permutation()
    p2 = p[p]
    out = np.empty((n, 9, 9))
    first, last = start // MATRIX_CHUNK, (start + n - 1) // MATRIX_CHUNK
    for chunk in range(first, last + 1) if n else ():
        m0 = np.random.default_rng([int(seed), chunk]).standard_normal((MATRIX_CHUNK, 9, 9))
        lo = max(start, chunk * MATRIX_CHUNK)
        hi = min(start + n, (chunk + 1) * MATRIX_CHUNK)
        m0 = m0[lo - chunk * MATRIX_CHUNK:hi - chunk * MATRIX_CHUNK]
        # W M W^-1 for a permutation matrix W: rows and columns permuted alike.
        m1 = (m0 + m0[:, p][:, :, p] + m0[:, p2][:, :, p2]) / 3
        out[lo - start:hi - start] = m1 @ np.swapaxes(m1, -1, -2)
    return out


def rotate_distances(d) -> np.ndarray:
    """The distances of the same particle turned by 120 degrees (the permutation Omega).

    Parameters
    ----------
    d : array_like, shape (..., 9)
        Distances in the order of ``DISTANCE_PAIRS``.

    Returns
    -------
    ndarray, shape (..., 9)
    """
    return np.asarray(d)[..., _rotation_permutation()]


def distance_jacobian(corners=REST_CORNERS) -> np.ndarray:
    """Derivative of the nine distances with respect to the corner coordinates.

    Parameters
    ----------
    corners : array_like, shape (6, 2) or (12,), optional
        Corner positions in lattice spacings (default: the rest shape ``REST_CORNERS``).

    Returns
    -------
    ndarray, shape (9, 12)
    """
    c = np.asarray(corners, float).reshape(6, 2)
    J = np.zeros((9, 12))
    for i, (a, b) in enumerate(DISTANCE_PAIRS):
        u = (c[b] - c[a]) / np.linalg.norm(c[b] - c[a])
        J[i, 2 * b:2 * b + 2] = u
        J[i, 2 * a:2 * a + 2] = -u
    return J


def checked_matrix(M) -> np.ndarray:
    """``M`` as a (9, 9) float array if it is a valid elasticity matrix.

    Finite, symmetric, positive semi-definite, not zero: the kernel's own checks
    (``kernel/random_hexagon.hpp``). A zero or non-finite ``M`` would otherwise give a
    boundary-layer length of 0 or NaN without complaint.

    Parameters
    ----------
    M : array_like, shape (9, 9)
        The candidate elasticity matrix.

    Returns
    -------
    ndarray, shape (9, 9)

    Raises
    ------
    ValueError
        Naming ``M``, if it is not a valid elasticity matrix.
    """
    M = np.asarray(M, dtype=float)
    if M.shape != (9, 9):
        raise ValueError(f"M must have shape (9, 9), got {M.shape}")
    _kernel.RandomHexagonModel(M, 0.5)
    return M


def _finite_stack(name: str, Ms) -> np.ndarray:
    Ms = np.asarray(Ms, float)
    if Ms.shape[-2:] != (9, 9) or (name == "Ms" and Ms.ndim != 3):
        raise ValueError(f"{name} must have shape {'(n, 9, 9)' if name == 'Ms' else '(..., 9, 9)'}, got {Ms.shape}")
    if not np.all(np.isfinite(Ms)):
        raise ValueError(f"{name} must be finite")
    return Ms


def pseudo_moduli(M) -> dict:
    """Single-particle proxies of the continuum moduli (supplement, "Predicting the boundary layer
    thickness").

    Parameters
    ----------
    M : array_like, shape (9, 9) or (..., 9, 9)
        Elasticity matrices.

    Returns
    -------
    dict of ndarray, each of shape (...)
        ``kappa_c``, ``K``: pseudo-moduli ``dd^T M dd / A_hex`` of a relative shift of the two
        triangles and of a yellow-shrinks/red-grows bulk change; ``K_up, mu_up, K_down, mu_down``:
        bulk and shear moduli of each triangle alone (the rest of ``M`` decoupled, which is the
        affine response of a lattice of such triangles); ``nu_up, nu_down`` =
        ``(K - mu)/(K + mu)`` and their mean ``nu``; ``ell_pred = sqrt(K / ((1 + nu) kappa_c))``
        (Eq. S23, lattice spacings); ``ell_eigen = 1 / sqrt(lowest eigenvalue of M)`` (the
        predictor that fails, Fig. S5). For the simple particle they coincide with the continuum
        mapping up to O(kc/k) (tested).

    Raises
    ------
    ValueError
        For a wrong shape or non-finite entries.
    """
    M = _finite_stack("M", M)
    out = {name: np.einsum("i,...ij,j->...", v, M, v) / HEXAGON_AREA for name, v in PSEUDO_MODULUS_VECTORS.items()}
    for side in ("up", "down"):
        K, mu = out[f"K_{side}"], out[f"mu_{side}"]
        out[f"nu_{side}"] = (K - mu) / (K + mu)
    out["nu"] = 0.5 * (out["nu_up"] + out["nu_down"])
    with np.errstate(divide="ignore", invalid="ignore"):
        out["ell_pred"] = np.sqrt(out["K"] / ((1 + out["nu"]) * out["kappa_c"]))
        lowest = np.linalg.eigvalsh(M)[..., 0]
        out["ell_eigen"] = 1 / np.sqrt(np.clip(lowest, 0, None))
    return out


# --------------------------------------------------------------------------------------------
# Boundary-layer length from the layer-to-layer transfer problem
# --------------------------------------------------------------------------------------------

def _slot_lattice_offsets():
    """Sublattice (0 yellow, 1 red) and row offset j of each slot's corner: yellow corners are
    Y(i, j) = site(i, j) + (0, 1/sqrt 3), red ones R(i, j) = site(i, j) - (0, 1/sqrt 3)."""
    sub, row = [], []
    for s, r in enumerate(REST_CORNERS):
        colour = 0 if s % 2 else 1
        y = r[1] - (1 / SQRT3 if colour == 0 else -1 / SQRT3)
        j = y / (SQRT3 / 2)
        assert abs(j - round(j)) < 1e-12
        sub.append(colour)
        row.append(int(round(j)))
    return np.array(sub), np.array(row)


_SUBLATTICE, _ROW = _slot_lattice_offsets()


def rest_hessian(M) -> np.ndarray:
    """Hessian of one particle's energy at its rest shape without mismatch, ``J^T M J`` (at rest the
    distances' own curvature carries no force).

    Parameters
    ----------
    M : array_like, shape (9, 9)
        Elasticity matrix.

    Returns
    -------
    ndarray, shape (12, 12)
    """
    J = distance_jacobian()
    return J.T @ np.asarray(M, float) @ J


def _transfer_blocks(hessian):
    """Coefficients A_m (m = -2..2, each 4 x 4 over the yellow and red sublattices) of the bulk
    force balance for displacements phi z^j uniform along rows: sum_m A_m z^m phi = 0."""
    H = np.asarray(hessian, float).reshape(6, 2, 6, 2)
    A = np.zeros((5, 4, 4))
    for s in range(6):
        for t in range(6):
            m = _ROW[t] - _ROW[s]
            a, b = 2 * _SUBLATTICE[s], 2 * _SUBLATTICE[t]
            A[m + 2, a:a + 2, b:b + 2] += H[s, :, t, :]
    return A


def transfer_roots(hessian) -> np.ndarray:
    """All roots ``z`` of ``det(sum_m A_m z^m) = 0``, the layer-to-layer transfer problem
    (companion linearisation of the quartic matrix polynomial).

    Parameters
    ----------
    hessian : array_like, shape (12, 12)
        A particle's rest Hessian (``rest_hessian``).

    Returns
    -------
    ndarray of complex
        The finite roots, sorted by decreasing modulus.
    """
    A = _transfer_blocks(hessian)
    n, deg = 4, 4
    # z^2 sum_m A_m z^m = sum_k C_k z^k with C_k = A_{k-2}, k = 0..4: P(z) = C_4 z^4 + ... + C_0.
    C = A
    L0 = np.zeros((n * deg, n * deg))
    L1 = np.eye(n * deg)
    L0[: n * (deg - 1), n:] = np.eye(n * (deg - 1))
    for k in range(deg):
        L0[n * (deg - 1):, n * k:n * (k + 1)] = -C[k]
    L1[n * (deg - 1):, n * (deg - 1):] = C[deg]
    z = scipy.linalg.eigvals(L0, L1)
    z = z[np.isfinite(z)]
    return z[np.argsort(-np.abs(z))]


def boundary_layer_length(M=None, *, hessian=None) -> float:
    """Boundary-layer length of a half-plane aggregate with its edge along a lattice vector, in
    linear response.

    ``-row_spacing / ln|z|`` for the slowest-decaying bulk mode ``z`` (``|z| < 1``) of the
    layer-to-layer transfer problem. The four roots at z = 1 (translations and uniform strains)
    are not decay modes and are dropped.

    Parameters
    ----------
    M : array_like, shape (9, 9), optional
        A random particle's elasticity matrix.
    hessian : array_like, shape (12, 12), optional
        Instead of ``M``: the rest Hessian of any hexagonal particle (e.g. ``Hexagon.evaluate``
        at the regular hexagon with ``eps`` tiny). Give exactly one.

    Returns
    -------
    float
        ``ell``, in lattice spacings.

    Raises
    ------
    ValueError
        Unless exactly one of ``M``, ``hessian`` is given and valid.
    RuntimeError
        If no mode decays (a floppy collective mode).

    Examples
    --------
    >>> from pyfrustrate import Hexagon, random_particles as rp
    >>> round(rp.boundary_layer_length(rp.elasticity_matrices(1, seed=1)[0]), 4)
    0.7149
    >>> simple = rp.RandomHexagon.from_hexagon(Hexagon.from_continuum(ell=2.0, nu=0.5))
    >>> round(rp.boundary_layer_length(simple.M), 2)  # the continuum's 2, to O(kc/k)
    2.01
    """
    if (M is None) == (hessian is None):
        raise ValueError("give exactly one of M or hessian")
    H = rest_hessian(checked_matrix(M)) if M is not None else np.asarray(hessian, float)
    if H.shape != (12, 12) or not np.all(np.isfinite(H)):
        raise ValueError(f"hessian must be a finite (12, 12) array, got shape {H.shape}")
    z = transfer_roots(H)
    z = z[np.argsort(np.abs(z - 1))][4:]  # drop the four at z = 1
    inside = np.abs(z[np.abs(z) < 1])
    if inside.size == 0:
        raise RuntimeError("boundary_layer_length: no decaying mode (the particle has a floppy collective mode)")
    slowest = inside.max()
    return float(-ROW_SPACING / np.log(slowest)) if slowest > 0 else 0.0


def boundary_layer_lengths(Ms, chunk: int = 20000) -> np.ndarray:
    """``boundary_layer_length`` for a stack of matrices, vectorised.

    The same roots through the scalar polynomial ``P(z) = z^4 det D(z)`` instead of the companion
    pencil. ``P`` has degree 8 and is palindromic (``D(1/z) = D(z)^T``), so ``P(z) / z^4`` is a
    quartic in ``s = z + 1/z``; its double root ``s = 2`` (the four roots at z = 1) is divided
    out exactly and the remaining quadratic is solved in closed form. Coefficients come from ``P``
    on 16 roots of unity (FFT). Faster than the companion eigenproblem
    (``benchmarks/bench_random.py``), same values to ~1e-11 (tested); the relative error grows
    like ell^2 (5e-5 at ell = 200).

    Parameters
    ----------
    Ms : array_like, shape (n, 9, 9)
        Elasticity matrices.
    chunk : int, optional
        Matrices per vectorised batch (bounds the temporary memory).

    Returns
    -------
    ndarray, shape (n,)
        Lattice spacings.

    Raises
    ------
    ValueError
        For a wrong shape or non-finite entries.
    """
    Ms = _finite_stack("Ms", Ms)
    out = np.empty(len(Ms))
    J = distance_jacobian()
    w = np.exp(2j * np.pi * np.arange(16) / 16)
    for start in range(0, len(Ms), chunk):
        H = np.einsum("ai,nab,bj->nij", J, Ms[start:start + chunk], J)
        A = _transfer_blocks_batched(H)  # (n, 3, 4, 4): z^-1, z^0, z^1
        pencil = A[:, None, 0] + A[:, None, 1] * w[None, :, None, None] + A[:, None, 2] * w[None, :, None, None] ** 2
        c = (np.fft.fft(np.linalg.det(pencil), axis=1) / 16).real[:, :9]  # P(z) = sum_n c_n z^n
        # P(z)/z^4 = c4 + sum_{n=1..4} c_{4+n} (z^n + z^-n) (palindromic: use both halves).
        half = 0.5 * (c[:, 5:] + c[:, 3::-1])  # n = 1..4
        # z^n + z^-n as polynomials in s (highest power first): p0 = 2, p1 = s, p_{n+1} = s p_n - p_{n-1}.
        p = [np.array([2.0]), np.array([1.0, 0.0])]
        for _ in range(3):
            p.append(np.polysub(np.polymul([1.0, 0.0], p[-1]), p[-2]))
        Q = np.zeros((len(c), 5))
        Q[:, -1] += c[:, 4]
        for n in range(1, 5):
            Q[:, 5 - len(p[n]):] += half[:, n - 1, None] * p[n]
        # Divide out (s - 2)^2 by synthetic division (twice), keep the quadratic quotient.
        for _ in range(2):
            q = np.zeros_like(Q[:, :-1])
            q[:, 0] = Q[:, 0]
            for k in range(1, Q.shape[1] - 1):
                q[:, k] = Q[:, k] + 2 * q[:, k - 1]
            Q = q
        a, b, cc = Q[:, 0].astype(complex), Q[:, 1].astype(complex), Q[:, 2].astype(complex)
        disc = np.sqrt(b * b - 4 * a * cc)
        with np.errstate(divide="ignore", invalid="ignore"):
            roots_s = np.stack([(-b + disc) / (2 * a), (-b - disc) / (2 * a)], axis=1)
            linear = np.abs(a) <= 1e-14 * np.abs(Q).max(axis=1)  # leading coefficient lost: one root
            roots_s[linear, 0] = -cc[linear] / b[linear]
            roots_s[linear, 1] = np.nan
            z = 0.5 * (roots_s - np.sqrt(roots_s * roots_s - 4))
            z = np.where(np.abs(z) > 1, 1 / z, z)  # the decaying one of the pair z, 1/z
            slowest = np.nanmax(np.abs(z), axis=1)
            out[start:start + chunk] = -ROW_SPACING / np.log(slowest)
    return out


def _transfer_blocks_batched(H):
    """Like ``_transfer_blocks`` for a stack of rest Hessians, in the gauge where red corners
    carry row index j - 1 (same roots, polynomial degree 2 instead of 4)."""
    H = H.reshape(-1, 6, 2, 6, 2)
    row = _ROW - (_SUBLATTICE == 1)
    A = np.zeros((len(H), 3, 4, 4))
    for s in range(6):
        for t in range(6):
            m = row[t] - row[s]
            a, b = 2 * _SUBLATTICE[s], 2 * _SUBLATTICE[t]
            A[:, m + 1, a:a + 2, b:b + 2] += H[:, s, :, t, :]
    return A


# --------------------------------------------------------------------------------------------
# The particle
# --------------------------------------------------------------------------------------------

class RandomHexagon:
    """Hexagonal particle with random elasticity (main text Eq. 14).

    Works with ``relax``, ``anneal`` and the topologies of ``pyfrustrate.topology`` like
    ``Hexagon`` (its point group is C3: ``M`` is not mirror-symmetric in general).

    Parameters
    ----------
    M : array_like, shape (9, 9)
        Symmetric, positive semi-definite elasticity matrix over the distances ``DISTANCE_PAIRS``,
        in units of ``k``.
    eps : float, optional
        Mismatch, in (0, 1): rest distances ``d0`` are triangle sides ``1 +- eps`` and the
        hexagon side of the ill-fitting hexagon.

    Raises
    ------
    ValueError
        For a wrong shape, an invalid matrix or ``eps`` out of range.

    Examples
    --------
    >>> from pyfrustrate import relax, topology
    >>> from pyfrustrate.random_particles import RandomHexagon
    >>> p = RandomHexagon.draw(seed=1)  # particle 0 of sample 1
    >>> p
    RandomHexagon(eps=0.01, ell=0.715, nu=0.444)
    >>> relax(p, topology.disk(2)).converged
    True
    """

    tiling = "hexagon"

    def __init__(self, M, eps: float = 0.01):
        M = np.array(M, dtype=float)
        if M.shape != (9, 9):
            raise ValueError(f"M must have shape (9, 9), got {M.shape}")
        if not (0 < eps < 1):
            raise ValueError(f"eps must lie in (0, 1), got {eps!r}")
        M.setflags(write=False)
        self.M = M
        self.eps = float(eps)
        self._kernel_model = _kernel.RandomHexagonModel(M, self.eps)

    @classmethod
    def draw(cls, seed: int, index: int = 0, eps: float = 0.01) -> "RandomHexagon":
        """Particle number ``index`` of the random sample ``seed`` (``elasticity_matrices``).

        Parameters
        ----------
        seed : int
            The sample.
        index : int, optional
            The particle's index in it.
        eps : float, optional
            Mismatch.

        Returns
        -------
        RandomHexagon
        """
        return cls(elasticity_matrices(1, seed, start=index)[0], eps)

    @classmethod
    def from_hexagon(cls, hexagon) -> "RandomHexagon":
        """The simple particle's linearised energy written as a quadratic form in the distances.

        ``M = J^+T H J^+`` with ``H`` its Hessian at rest (eps = 0) and ``J`` the distance Jacobian
        (exact: both vanish on rigid motions). Same linear response, same eps.

        Parameters
        ----------
        hexagon : Hexagon
            The simple particle (its ``k, kc, k_area, eps``).

        Returns
        -------
        RandomHexagon
        """
        rest = _kernel.HexagonModel(hexagon.k, hexagon.kc, hexagon.k_area, 0.0)
        H = np.asarray(rest.evaluate(REST_CORNERS.ravel())["hessian"])
        Jp = np.linalg.pinv(distance_jacobian())
        M = Jp.T @ H @ Jp
        return cls(0.5 * (M + M.T), hexagon.eps)

    def __reduce__(self):
        return (type(self), (np.array(self.M), self.eps))

    def __repr__(self):
        return f"RandomHexagon(eps={self.eps}, ell={self.boundary_layer_length:.3g}, nu={self.moduli['nu']:.3g})"

    @property
    def moduli(self) -> dict:
        """``pseudo_moduli(M)`` as floats."""
        return {k: float(v) for k, v in pseudo_moduli(self.M).items()}

    @property
    def boundary_layer_length(self) -> float:
        """``boundary_layer_length(M)``: the exact linear-response decay length of a half-plane, in
        lattice spacings.
        """
        return boundary_layer_length(self.M)

    @property
    def force_scale(self) -> float:
        """Typical force on a corner, ``eps * |M|`` (largest eigenvalue): the unit of ``relax``'s
        tolerance.
        """
        return self.eps * float(np.linalg.eigvalsh(self.M)[-1])

    @property
    def bulk_energy_per_particle(self) -> float:
        """Exact bulk deformation energy per particle.

        Every hexagon of the bulk is regular with lattice constant ``a`` (three-fold symmetry), so
        ``d = a dhat`` and the energy is minimised over ``a`` in closed form.
        """
        d0 = np.asarray(self._kernel_model.rest_distances())
        dhat = np.array([1, 1, 1, 1, 1, 1, 1 / SQRT3, 1 / SQRT3, 1 / SQRT3])
        stiff = dhat @ self.M @ dhat
        return float(0.5 * d0 @ self.M @ d0 - 0.5 * (dhat @ self.M @ d0) ** 2 / stiff)

    def evaluate(self, corners) -> dict:
        """Energy, distances, gradient and Hessian of one particle from its corners.

        Parameters
        ----------
        corners : array_like, shape (6, 2) or (12,)
            Corner positions, lattice spacings, slots counter-clockwise from 30 degrees.

        Returns
        -------
        dict
            ``energy``, ``distances`` (9,), ``gradient`` (12,), ``hessian`` (12, 12).

        Raises
        ------
        ValueError
            For a wrong shape or non-finite corners.
        """
        return self._kernel_model.evaluate(_corners(corners))


# --------------------------------------------------------------------------------------------
# The paper's route to ell (Fig. 5b): the decay of the excess energy away from an edge
# --------------------------------------------------------------------------------------------

def edge_energy_profile(particle, width: int) -> tuple[np.ndarray, np.ndarray]:
    """Excess deformation energy per particle against the distance from an edge.

    On a straight strip of ``width`` rows parallel to a lattice vector (cut 0), in linear
    response, relative to the interior. A free strip of random particles is pulled by a uniform
    strain O(1/width) and, held straight, by a bending stress odd about its centre; adding the two
    halves cancels the odd part, and taking the centre as reference removes the uniform one
    (checked: the fitted length converges in width).

    Parameters
    ----------
    particle : RandomHexagon or Hexagon
        The particle model.
    width : int
        Rows of the strip, ``>= 8``.

    Returns
    -------
    distance : ndarray, shape (width // 2,)
        From the edge line, lattice spacings.
    excess : ndarray, shape (width // 2,)
        Both edges added, in units of the interior energy per particle.

    Raises
    ------
    TypeError
        If ``particle`` is not a particle model.
    ValueError
        For a strip narrower than 8 rows.
    """
    from .relaxation import particle_corners, particle_energies, relax
    from .topology import fiber
    _checks.particle("particle", particle)
    width = int(width)
    if width < 8:
        raise ValueError(f"width must be at least 8 rows, got {width}")
    top = fiber(width, 0, curved=False)
    r = relax(particle, top, method="linear")
    e = particle_energies(particle, top, r.state)
    order = np.argsort(particle_corners(particle, top, r.state).mean(axis=1)[:, 1])
    e = e[order]
    both = (e + e[::-1])[: width // 2]
    distance = (np.arange(width // 2) + 0.5) * ROW_SPACING  # the edge line is half a row out
    return distance, both / both[-1] - 1


def fitted_boundary_layer_length(particle, window=(3.0, 8.0), width=None, iterations: int = 20) -> float:
    """Boundary-layer length by the paper's protocol (Fig. 5b).

    The decay length of a log-linear fit of the excess energy per particle against the distance
    from a strip's edge (``edge_energy_profile``), over ``window`` in units of the length itself,
    iterated to a fixed point from ``ell_pred``. Near the edge the excess is a sum of decaying
    modes (for the simple particle ``exp(-d/ell) - exp(-2 d/ell)``), so a window that starts too
    close overestimates; for small ell a window holds few rows and the fit is coarse. Compare
    ``boundary_layer_length`` (exact slowest mode).

    Parameters
    ----------
    particle : RandomHexagon or Hexagon
        The particle model.
    window : tuple of float, optional
        Start and end of the fit window, in units of the length being fitted.
    width : int, optional
        Rows of the strip (default ``40 ell`` within 60..600).
    iterations : int, optional
        Cap on fixed-point iterations.

    Returns
    -------
    float
        Lattice spacings.

    Raises
    ------
    TypeError
        If ``particle`` is not a particle model.
    ValueError
        For a bad window.
    RuntimeError
        If the strip holds too few rows in the window, or shows no decay.
    """
    _checks.particle("particle", particle)
    lo, hi = window
    if not (0 <= lo < hi):
        raise ValueError(f"window must satisfy 0 <= start < end, got {window!r}")
    ell = float(pseudo_moduli(particle.M)["ell_pred"]) if hasattr(particle, "M") else particle.continuum.ell
    if not np.isfinite(ell) or ell <= 0:
        ell = 1.0
    width = int(width) if width is not None else int(np.clip(40 * ell, 60, 600))
    d, excess = edge_energy_profile(particle, width)
    for _ in range(iterations):
        inside = (d >= lo * ell) & (d <= hi * ell) & (np.abs(excess) > 0)
        if inside.sum() < 3:  # at least three rows: extend the window outwards
            inside = (d >= lo * ell) & (np.abs(excess) > 0)
            inside &= np.cumsum(inside) <= 3
        if inside.sum() < 2:
            raise RuntimeError("fitted_boundary_layer_length: fewer than two rows in the fit window; widen the strip")
        slope = np.polyfit(d[inside], np.log(np.abs(excess[inside])), 1)[0]
        new = -1 / slope if slope < 0 else np.inf
        if not np.isfinite(new) or new > d[-1]:
            raise RuntimeError(f"fitted_boundary_layer_length: no decay over the strip (fit gave {new:.3g}); widen it")
        if abs(new - ell) <= 1e-6 * ell:
            return float(new)
        ell = new
    return float(ell)


# --------------------------------------------------------------------------------------------
# Samples
# --------------------------------------------------------------------------------------------

SAMPLE_FIELDS = ("index", "ell", "ell_pred", "ell_eigen", "nu", "nu_up", "nu_down", "kappa_c", "K")


def sample_properties(n: int, seed: int, start: int = 0) -> dict:
    """Boundary-layer lengths, predictors and Poisson ratios of a sample of random particles.

    Of the random particles ``start`` to ``start + n - 1`` of sample ``seed``: exact lengths
    (``boundary_layer_lengths``) and the ``pseudo_moduli`` predictors.

    Parameters
    ----------
    n : int
        Particles, ``>= 0``.
    seed : int
        The sample.
    start : int, optional
        Index of the first.

    Returns
    -------
    dict of ndarray, each of shape (n,)
        Named as ``SAMPLE_FIELDS``; ``index`` regenerates a particle with ``RandomHexagon.draw``.

    Raises
    ------
    ValueError
        For a bad ``n`` or ``start``, or ``n`` too large for memory.

    Examples
    --------
    >>> from pyfrustrate import random_particles as rp
    >>> s = rp.sample_properties(5, seed=1)
    >>> s["index"].tolist(), s["ell"].round(3).tolist()
    ([0, 1, 2, 3, 4], [0.715, 0.93, 0.557, 1.092, 0.861])
    """
    # The matrices, then pseudo_moduli's per-matrix products of the same order.
    _checks.affordable(f"sample_properties(n={n})", 3 * _checks.integer("n", n, 0) * MATRIX_BYTES)
    M = elasticity_matrices(n, seed, start)
    out = {k: v for k, v in pseudo_moduli(M).items() if k in SAMPLE_FIELDS}
    out["ell"] = boundary_layer_lengths(M)
    out["index"] = np.arange(start, start + n)
    return {k: out[k] for k in SAMPLE_FIELDS}


def select_uniform(values, count: int, bins, seed: int) -> np.ndarray:
    """Indices of up to ``count`` entries spread evenly over ``bins``.

    An equal share per bin, drawn at random without replacement, seeded: the paper's selection of
    particles with a near-uniform distribution of Poisson ratios (supplement, Fig. S4b). Bins
    with fewer entries than their share give all they have.

    Parameters
    ----------
    values : array_like, shape (n,)
        The values binned (e.g. Poisson ratios).
    count : int
        How many to select.
    bins : array_like
        Bin edges, increasing.
    seed : int
        Seed of the draw.

    Returns
    -------
    ndarray of int
        Sorted indices into ``values``.
    """
    values = np.asarray(values, float)
    bins = np.asarray(bins, float)
    rng = np.random.default_rng(seed)
    which = np.digitize(values, bins) - 1
    share = int(np.ceil(count / (len(bins) - 1)))
    chosen = []
    for b in range(len(bins) - 1):
        members = np.flatnonzero(which == b)
        chosen.append(rng.choice(members, size=min(share, members.size), replace=False) if members.size else members)
    return np.sort(np.concatenate(chosen))


# --------------------------------------------------------------------------------------------
# Aggregation of random particles (Figs. 5d, 6, S2)
# --------------------------------------------------------------------------------------------

PHASE_CODES = ("bulk_with_holes", "disk", "fiber", "bulk")


def binding_energy_of(particle, ell: float, nu: float, Gamma):
    """Binding energy ``g`` per bound pair of sides giving line tension ``Gamma`` to a particle of
    boundary-layer length ``ell`` and Poisson ratio ``nu``.

    The arguments come in the order of ``ansatz.binding_energy_of``; the two differ in ``e_bulk``:
    this one measures it on the particle (a random particle has no continuum moduli to compute it
    from), the ansatz's computes it from the particle's ``(k, eps)``.

    Main text ``Gamma = 2 gamma / ((1 + nu) ell e_bulk)`` with ``gamma = g`` (the measured
    convention, ``continuum``) and ``e_bulk`` the bulk deformation energy per unit reference area.

    Parameters
    ----------
    particle : RandomHexagon or Hexagon
        The particle model (its ``bulk_energy_per_particle``).
    ell : float
        Boundary-layer length, lattice spacings, positive and finite.
    nu : float
        Poisson ratio, in (-1, 1).
    Gamma : array_like
        Dimensionless line tension(s).

    Returns
    -------
    ndarray
        ``g``, shape of ``Gamma``.

    Raises
    ------
    TypeError
        If ``particle`` is not a particle model.
    ValueError
        For ``ell`` or ``nu`` out of range.
    """
    from .topology import AREA_PER_PARTICLE
    _checks.particle("particle", particle)
    if not (np.isfinite(ell) and ell > 0):
        raise ValueError(f"ell must be positive and finite, got {ell!r}")
    if not (-1 < nu < 1):
        raise ValueError(f"nu must lie in (-1, 1), got {nu!r}")
    e_bulk = particle.bulk_energy_per_particle / AREA_PER_PARTICLE
    return 0.5 * np.asarray(Gamma, float) * (1 + nu) * ell * e_bulk


def catalogue_for(ell: float, radius_per_ell=6.0, width_per_ell=8.0, radius_limits=(6, 40), width_limits=(10, 60)):
    """The pre-made aggregates for a particle of boundary-layer length ``ell``: disks and fibres out
    to a few ``ell`` (optimal sizes are ~ell, main text Fig. 5d), within limits.

    Parameters
    ----------
    ell : float
        Boundary-layer length, lattice spacings.
    radius_per_ell, width_per_ell : float, optional
        Largest disk radius and fibre width, in units of ``ell``.
    radius_limits, width_limits : tuple of int, optional
        Bounds on them, in lattice steps and lattice lines.

    Returns
    -------
    list of ansatz.Candidate
    """
    from .ansatz import catalogue
    R = int(np.clip(np.ceil(radius_per_ell * ell), *radius_limits))
    W = int(np.clip(np.ceil(width_per_ell * ell), *width_limits))
    return catalogue(R, W)


def line_tension_grid(Gamma_max: float, count: int, linear_until: float = 2.0) -> np.ndarray:
    """Line tensions of the aggregation diagrams (Fig. 6).

    Half the points evenly on ``[0, linear_until]``, where the phases change, the rest geometric
    up to ``Gamma_max``, where the bulk of small-ell particles takes over (their Gamma_max reaches
    tens: Gamma is measured in units of the particle's own ell).

    Parameters
    ----------
    Gamma_max : float
        Largest line tension, positive and finite.
    count : int
        Points, ``>= 4``.
    linear_until : float, optional
        End of the evenly spaced part.

    Returns
    -------
    ndarray, shape (count,)

    Raises
    ------
    ValueError
        For a bad ``Gamma_max`` or ``count``, or ``count`` too large for memory.

    Examples
    --------
    >>> from pyfrustrate import random_particles as rp
    >>> rp.line_tension_grid(10.0, 8).round(3)
    array([ 0.   ,  0.667,  1.333,  2.   ,  2.991,  4.472,  6.687, 10.   ])
    """
    if not (Gamma_max > 0 and np.isfinite(Gamma_max)):
        raise ValueError(f"Gamma_max must be positive and finite, got {Gamma_max!r}")
    if int(count) != count or count < 4:
        raise ValueError(f"count must be an integer >= 4, got {count!r}")
    _checks.affordable(f"line_tension_grid(count={count})", 3 * 8 * int(count))  # two pieces and their join
    if Gamma_max <= linear_until:
        return np.linspace(0.0, Gamma_max, int(count))
    n_linear = int(count) // 2
    tail = np.geomspace(linear_until, Gamma_max, int(count) - n_linear + 1)[1:]
    return np.concatenate([np.linspace(0.0, linear_until, n_linear), tail])


def aggregation_line(particle, Gamma, ell: float, nu: float, candidates=None, method: str = "linear",
                     relative: bool = False) -> dict:
    """One particle's line of an aggregation diagram (main text Fig. 6) and its optimal sizes
    (Fig. 5d).

    Every candidate of ``catalogue_for(ell)`` is relaxed once, then compared at each ``Gamma``.

    Parameters
    ----------
    particle : RandomHexagon or Hexagon
        The particle model.
    Gamma : array_like
        Line tensions (measured convention, ``binding_energy_of``).
    ell, nu : float
        The particle's boundary-layer length (lattice spacings) and Poisson ratio.
    candidates : list of ansatz.Candidate, optional
        Default ``catalogue_for(ell)``.
    method : {'auto', 'newton', 'lbfgs', 'linear'}, optional
        ``'linear'`` (default) is exact as eps -> 0, where Gamma captures all of the eps
        dependence.
    relative : bool, optional
        Read ``Gamma`` in units of ``Gamma_max`` (Fig. S2).

    Returns
    -------
    dict
        ``phase`` (index into ``PHASE_CODES`` of the lowest total energy per particle, per
        ``Gamma``); ``width`` (W* of the best fibre among fibres, lattice spacings); ``radius`` (R*
        of the best disk among disks and the single particle); ``width_capped``,
        ``radius_capped`` (whether that best fibre or disk is the largest of its family in the
        catalogue: the optimum may then lie beyond it); ``Gamma_max`` (the line tension above
        which the bulk wins, exact: every total energy is linear in g); ``converged``.

    Raises
    ------
    TypeError
        If ``particle`` is not a particle model.
    """
    from .ansatz import FAMILY_PHASE, relax_catalogue
    _checks.particle("particle", particle)
    candidates = catalogue_for(ell) if candidates is None else candidates
    energies = relax_catalogue(particle, candidates, method=method)
    bulk = np.flatnonzero(energies.family == "bulk")[0]
    others = energies.bonds < energies.bonds[bulk]
    g_max = np.max((energies.deformation[bulk] - energies.deformation[others]) / (energies.bonds[bulk] - energies.bonds[others]))
    Gamma_max = float(g_max / binding_energy_of(particle, ell, nu, 1.0))
    g = binding_energy_of(particle, ell, nu, np.asarray(Gamma, float) * (Gamma_max if relative else 1.0))
    phase_of = np.array([PHASE_CODES.index(FAMILY_PHASE[f]) for f in energies.family])
    fibers = [f for f in set(energies.family.tolist()) if f.startswith("fiber")]
    best_fiber = energies.winners(g, fibers)
    best_disk = energies.winners(g, ["single", "disk"])
    largest = {f: energies.size[energies.family == f].max() for f in set(energies.family.tolist())}
    capped = np.array([energies.size[i] == largest[energies.family[i]] for i in range(len(energies.family))])
    return {"phase": phase_of[energies.winners(g)].astype(np.int8), "width": energies.length[best_fiber],
            "radius": energies.length[best_disk],
            "width_capped": capped[best_fiber] & np.isfinite(energies.length[best_fiber]),
            "radius_capped": capped[best_disk] & (energies.family[best_disk] == "disk"),
            "Gamma_max": Gamma_max, "converged": bool(energies.converged.all())}
