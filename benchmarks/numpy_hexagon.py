"""Plain vectorised numpy implementation of the hexagon network energy and gradient.

The honest baseline for the benchmarks: the same model as ``kernel/hexagon.hpp`` summed over a
finite aggregate (``kernel/network.hpp`` without periodic images), written as well as numpy
allows -- one gather of all particles' corners (``np.take``), every spring of every particle at
once through a fixed (12 springs x 6 slots) incidence matrix, triangle areas from the triangle
sides, and one ``np.bincount`` per coordinate to scatter the forces onto the shared corners.
``NaiveNumpyHexagon`` is the straightforward version (particle-major arrays, ``np.add.at``),
10-20x slower, kept to show how much of the baseline is numpy craft.

Per particle (slots 0..5 at 30, 90, ..., 330 degrees; odd slots yellow, even red):

* yellow triangle springs (1,3), (3,5), (5,1): stiffness ``k``, rest ``1 + eps``;
* red triangle springs (0,2), (2,4), (4,0): stiffness ``k``, rest ``1 - eps``;
* connecting springs (s, s+1): stiffness ``kc``, rest
  ``sqrt(((1+eps)^2 + (1-eps)^2 - (1-eps^2)) / 3)``;
* areal terms ``k_area (A - A0)^2 / (2 A0)`` on the signed areas of the yellow (1,3,5) and red
  (0,2,4) triangles, ``A0 = sqrt(3)/4 (1 +- eps)^2``.

Usage::

    model = NumpyHexagon(particle, topology)      # pyfrustrate.Hexagon, finite or straight-fibre Topology
    E, g = model.energy_and_gradient(x)           # x = (x0, y0, x1, y1, ...)

``check_against_kernel`` compares it with the kernel and raises ``AssertionError`` on mismatch
(energy to 1e-12 relative, gradient to 1e-12 * max(1, max|x|) in units of k * eps).
"""
from __future__ import annotations

import numpy as np

SQRT3 = np.sqrt(3.0)

# Spring table: slot a, slot b, kind (0 yellow, 1 red, 2 connecting).
_SPRINGS = ([(1, 3, 0), (3, 5, 0), (5, 1, 0)]
            + [(0, 2, 1), (2, 4, 1), (4, 0, 1)]
            + [(s, (s + 1) % 6, 2) for s in range(6)])
_A = np.array([s[0] for s in _SPRINGS])
_B = np.array([s[1] for s in _SPRINGS])
_KIND = np.array([s[2] for s in _SPRINGS])
# Incidence (12 springs x 6 slots): spring vector d_j = r_b - r_a = (INCIDENCE @ r)_j, and the
# force f_j = dE/dd_j acts +f on slot b, -f on slot a: slot forces INCIDENCE.T @ f.
_INCIDENCE = np.zeros((len(_SPRINGS), 6))
_INCIDENCE[np.arange(len(_SPRINGS)), _B] += 1.0
_INCIDENCE[np.arange(len(_SPRINGS)), _A] -= 1.0
# Triangles: slots of one colour, counter-clockwise, are s, s+2, s+4. With
# (Q r)_s = r_{s+2} - r_{s-2}, the signed area has dA/dx_s = (Q y)_s / 2, dA/dy_s = -(Q x)_s / 2.
_Q = np.zeros((6, 6))
for _s in range(6):
    _Q[_s, (_s + 2) % 6] += 1.0
    _Q[_s, (_s - 2) % 6] -= 1.0


class NumpyHexagon:
    """Energy and gradient of a finite aggregate of hexagons, vectorised over particles.

    Arrays are laid out coordinate- and slot-major, ``(2, 6 or 12, n_particles)``: spring vectors
    are one small batched matmul ``INCIDENCE (12 x 6) @ corners (6 x P)``, slot forces its
    transpose, triangle areas and their gradients the same with ``Q``; nothing is fancy-indexed
    but the gather of the corners (``np.take``) and the scatter (``np.bincount``). Temporaries
    are preallocated and written with ``out=``: a fresh 100 kB-1 MB array per operation costs
    more in page faults than the arithmetic (``NaiveNumpyHexagon``, particle-major with fancy
    indexing and ``np.add.at``, is 10-20x slower). Not thread-safe (shared buffers).
    """

    def __init__(self, particle, topology):
        straight_fibre = topology.periodicity == "fiber" and not topology.curved
        if topology.periodicity != "none" and not straight_fibre:
            raise ValueError("NumpyHexagon handles finite aggregates and straight periodic fibres only")
        k, kc, k_area, eps = particle.k, particle.kc, particle.k_area, particle.eps
        yellow, red = 1.0 + eps, 1.0 - eps
        side = np.sqrt((yellow**2 + red**2 - yellow * red) / 3.0)
        self.stiffness = np.array([k, k, kc])[_KIND][:, None]           # (12, 1)
        self.rest = np.array([yellow, red, side])[_KIND][:, None]       # (12, 1)
        self.k_area = float(k_area)
        # Slot parity 0 = red (even slots), 1 = yellow (odd slots).
        self.rest_area = SQRT3 / 4.0 * np.array([red**2, yellow**2])[:, None]  # (2, 1)
        self.half_coef = 0.5 * self.k_area / self.rest_area             # (2, 1)
        corners = np.asarray(topology.kernel.corners, dtype=np.intp)    # (P, 6)
        self.corners_t = np.ascontiguousarray(corners.T)                # (6, P)
        self.n_corners = topology.n_corners
        # Straight fibre: slot s of particle p sees image n of its corner, r + n t, with the period
        # vector t = (tx, ty) the last two entries of the state.
        self.images_t = (np.ascontiguousarray(np.asarray(topology.kernel.images)[:, :, 0].T).astype(float)
                         if straight_fibre else None)                   # (6, P)
        self._flat = self.corners_t.ravel()
        P = corners.shape[0]
        self._c = np.empty((2, 6, P))       # corner coordinates
        self._g = np.empty((2, 6, P))       # forces on slots
        self._qc = np.empty((2, 6, P))      # Q @ corners (triangle geometry)
        self._d = np.empty((2, 12, P))      # spring vectors, then spring forces
        self._len = np.empty((12, P))
        self._stretch = np.empty((12, P))
        self._ks = np.empty((12, P))

    def energy_and_gradient(self, x):
        x = np.asarray(x, dtype=float)
        c, g, d, L, S, KS = self._c, self._g, self._d, self._len, self._stretch, self._ks
        n_dof = 2 * self.n_corners
        np.take(x[:n_dof].reshape(-1, 2).T, self.corners_t, axis=1, out=c)  # gather (2, 6, P)
        if self.images_t is not None:
            c[0] += self.images_t * x[n_dof]
            c[1] += self.images_t * x[n_dof + 1]
        np.matmul(_INCIDENCE, c, out=d)                                  # spring vectors
        if self.k_area != 0.0:
            # Signed areas from the triangle sides (springs 0, 2 yellow; 3, 5 red), not from the
            # corners' absolute positions: no cancellation far from the origin.
            area = 0.5 * (d[1, 0:4:3] * d[0, 2:6:3] - d[0, 0:4:3] * d[1, 2:6:3])[::-1]  # red, yellow
            excess = area - self.rest_area
            w = self.half_coef * excess                                   # (A - A0) k_a / (2 A0)
            energy = np.vdot(w, excess)
        else:
            energy = 0.0
        np.multiply(d[0], d[0], out=L)
        np.multiply(d[1], d[1], out=S)
        L += S
        np.sqrt(L, out=L)
        np.subtract(L, self.rest, out=S)
        np.multiply(self.stiffness, S, out=KS)
        energy += 0.5 * np.vdot(KS, S)
        if L.all():
            np.divide(KS, L, out=KS)
        else:  # a spring of zero length has no direction: its force is taken as zero
            np.divide(KS, L, out=KS, where=L > 0)
            KS[L == 0] = 0.0
        d *= KS                                                          # spring forces
        np.matmul(_INCIDENCE.T, d, out=g)                                # slot forces

        if self.k_area != 0.0:
            qc = self._qc
            np.matmul(_Q, c, out=qc)                                     # r_{s+2} - r_{s-2}
            g3 = g.reshape(2, 3, 2, -1)                                  # coord, pair, colour, P
            g3[0] += w * qc[1].reshape(3, 2, -1)
            g3[1] -= w * qc[0].reshape(3, 2, -1)

        grad = np.empty(x.size)
        grad[0:n_dof:2] = np.bincount(self._flat, weights=g[0].ravel(), minlength=self.n_corners)
        grad[1:n_dof:2] = np.bincount(self._flat, weights=g[1].ravel(), minlength=self.n_corners)
        if self.images_t is not None:
            grad[n_dof] = np.vdot(self.images_t, g[0])
            grad[n_dof + 1] = np.vdot(self.images_t, g[1])
        return float(energy), grad

    __call__ = energy_and_gradient


class NaiveNumpyHexagon(NumpyHexagon):
    """The first version one would write: particle-major (P, 6, 2) arrays, fancy indexing along
    the slot axis, ``np.add.at`` for the scatter, fresh temporaries everywhere. Same numbers;
    timed in bench_relax only to show how much of the baseline is numpy craft (~3-10x)."""

    def energy_and_gradient(self, x):
        if self.images_t is not None:
            raise ValueError("NaiveNumpyHexagon handles finite aggregates only")
        pos = np.asarray(x, dtype=float).reshape(-1, 2)
        corners = self.corners_t.T
        c = pos[corners]                                                 # (P, 6, 2)
        d = c[:, _B] - c[:, _A]                                          # (P, 12, 2)
        length = np.linalg.norm(d, axis=2)
        stretch = length - self.rest[:, 0]
        energy = 0.5 * np.sum(self.stiffness[:, 0] * stretch**2)
        f = (self.stiffness[:, 0] * stretch / length)[..., None] * d
        g = np.zeros_like(c)
        np.add.at(g, (slice(None), _B), f)
        np.add.at(g, (slice(None), _A), -f)
        if self.k_area != 0.0:
            for colour, slots in ((1, [1, 3, 5]), (0, [0, 2, 4])):
                a, b, cc = (c[:, s] for s in slots)
                area = 0.5 * ((b[:, 0] - a[:, 0]) * (cc[:, 1] - a[:, 1]) - (cc[:, 0] - a[:, 0]) * (b[:, 1] - a[:, 1]))
                w = 2.0 * self.half_coef[colour, 0] * (area - self.rest_area[colour, 0])
                energy += 0.5 * np.sum(w * (area - self.rest_area[colour, 0]))
                for s, (p, q) in zip(slots, ((b, cc), (cc, a), (a, b))):
                    g[:, s, 0] += 0.5 * w * (p[:, 1] - q[:, 1])
                    g[:, s, 1] += 0.5 * w * (q[:, 0] - p[:, 0])
        grad = np.zeros_like(pos)
        np.add.at(grad, corners.ravel(), g.reshape(-1, 2))
        return float(energy), grad.ravel()

    __call__ = energy_and_gradient


def check_against_kernel(particle, topology, states, rtol=1e-12):
    """Compare with ``pyfrustrate.relaxation.energy`` on each state; raise AssertionError if off.

    Energy: relative difference, at most ``rtol``. Gradient: max |difference| in units of the
    force scale ``k * eps``, at most ``rtol * max(1, max|x|)``: a spring's stretch (~eps) is the
    difference of two coordinates of size |x|, so float64 roundoff alone puts both codes
    ~|x| * 1e-16 / eps apart in these units (a few 1e-12 at R = 25). Relative to the gradient
    itself the test would be meaningless at a relaxed state, where forces of order k*eps cancel
    down to the tolerance. Returns the worst (energy, gradient) differences, each divided by
    its tolerance-free scale (i.e. the raw relative numbers).
    """
    try:  # the module was renamed relax -> relaxation
        from pyfrustrate.relaxation import energy as kernel_energy
    except ImportError:  # pragma: no cover
        from pyfrustrate.relax import energy as kernel_energy

    model = NumpyHexagon(particle, topology)
    worst = [0.0, 0.0]
    force = particle.k * particle.eps
    for name, x in states.items():
        x = np.asarray(x, dtype=float)
        e_k, g_k = kernel_energy(particle, topology, x)
        g_k = np.asarray(g_k)
        e_n, g_n = model(x)
        de = abs(e_n - e_k) / abs(e_k)
        dg = np.abs(g_n - g_k).max() / force
        worst = [max(worst[0], de), max(worst[1], dg)]
        gtol = rtol * max(1.0, np.abs(x).max())
        if not (de <= rtol and dg <= gtol):
            raise AssertionError(
                f"numpy baseline disagrees with the kernel on {topology.label} ({name} state): "
                f"energy {e_n!r} vs {e_k!r} (rel {de:.2e}, tol {rtol:g}), gradient max diff "
                f"{dg:.2e} k*eps (tol {gtol:.2g})")
    return tuple(worst)
