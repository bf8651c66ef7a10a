"""Continuum theory of the aggregates: two coupled elastic sheets (main text Eqs. 4-13, Fig. 3a).

The yellow and red triangle lattices are isotropic sheets (shear modulus ``mu``, Poisson ratio
``nu``) whose rest states are dilated/contracted by ``eps`` with respect to the bulk reference
state, coupled by ``kappa_c/2 (u_up - u_down)^2`` per unit area (main text Eq. 4). Lengths are
in units of the boundary-layer length ``ell`` (Eq. 10), energies per unit reference area in
units of ``e_bulk`` (Eq. 8), and ``Gamma = 2 gamma/((1 + nu) ell e_bulk)`` is the dimensionless
line tension. In every aggregate ``u_down = -u_up``.

Corrections to the printed paper, all checked in ``tests/test_continuum.py`` against direct
minimisations of Eq. 4:

* supplement S1: ``lam = 2 mu nu/(1 - nu)``, not ``mu nu/(1 - nu)``;
* Eq. 12: the disk displacement lacks a factor 2 (the supplement's edge condition
  ``lam (u - eps)/R`` should read ``lam u/R - 2 eps (lam + mu)``);
* Eq. 13: the deformation term of the disk energy lacks a factor ``1 + nu``;
* Eq. 2: the force balance of Eq. 1 has ``2 kc`` on the right, as Eq. 3 assumes.

The theory holds over the whole range of 2D elasticity, ``-1 < nu <= 1`` (auxetic sheets
included): every function takes it, and ``tests/test_continuum.py`` checks negative ``nu`` by the
same independent minimisations as positive ones.

All functions broadcast their arguments (numpy rules) and return an ndarray, or a numpy scalar
for scalar input. Invalid input raises ValueError naming the parameter.

Binding conventions. The discrete model binds each pair of touching sides with an energy ``-g``;
the continuum's line tension is ``gamma`` (energy per unit length of edge) and ``Gamma`` its
dimensionless form. How ``gamma`` follows from ``g`` is a convention, chosen by ``convention=``:

* ``measured`` (the default, every figure): ``gamma = g`` on hexagons, ``g / 2`` on triangles,
  the edge energy the discrete model has (``ansatz.edge_line_tension``);
* ``supplement``: the printed ``gamma = 4 g / sqrt(3)`` (hexagons only). The same ``Gamma`` then
  means a binding ``sqrt(3)/4 = 0.433`` times the measured one: the paper's 0.5 is our 0.217.

Routes between them: ``particle_parameters(ell, nu, Gamma, convention=...).g`` (``Gamma`` to
``g``), ``mapping(k, kc, k_area, g, eps, convention=...).Gamma`` (``g`` to ``Gamma``),
``line_tension`` and ``binding_energy`` (``g`` to ``gamma`` and back);
``ansatz.binding_energy_of`` and ``random_particles.binding_energy_of`` take a particle and use
the measured convention.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ive

LINE_TENSION_PER_BINDING_ENERGY = 1.0  # hexagon tiling (line_tension)
# What the triangle tiling changes (supplement, "Triangular particles"; derived in
# docs/topics/triangle.md, measured by tests/test_triangle.py): every lattice edge of each sheet
# carries two springs k (one per particle on either side) where the hexagon's carries one, and each
# particle its own coupling springs over half the area, so all three sheet moduli mu, lam, kappa_c
# double; nu and ell are unchanged. A flat edge along a1 breaks one bond per unit length and makes
# two edges: gamma = g / 2.
SHEET_MODULI_FACTOR = {"hexagon": 1.0, "triangle": 2.0}
LINE_TENSION_PER_BINDING = {"hexagon": LINE_TENSION_PER_BINDING_ENERGY, "triangle": 0.5}
# The binding convention (how Gamma maps to g), an explicit choice. "measured" is gamma = g, the
# edge energy the discrete hexagon model has (docs/topics/binding.md,
# results/ansatz/line_tension.json; every figure uses it). "supplement" is the printed gamma = 4 g /
# sqrt(3): the same Gamma then means a binding energy sqrt(3)/4 = 0.433 times ours, and the paper's
# Gamma = 0.5 is our 0.217. Hexagons only: the supplement gives no convention for triangles.
BINDING_CONVENTIONS = ("measured", "supplement")
_SUPPLEMENT_LINE_TENSION_PER_BINDING = 4.0 / math.sqrt(3.0)


def _tiling_constants(tiling, convention="measured"):
    if tiling not in SHEET_MODULI_FACTOR:
        raise ValueError(f"tiling must be one of {tuple(SHEET_MODULI_FACTOR)}, got {tiling!r}")
    if convention not in BINDING_CONVENTIONS:
        raise ValueError(f"convention must be one of {BINDING_CONVENTIONS}, got {convention!r}")
    if convention == "supplement":
        if tiling != "hexagon":
            raise ValueError(f"convention: the supplement's gamma = 4 g/sqrt(3) is for hexagons, not {tiling}s")
        return SHEET_MODULI_FACTOR[tiling], _SUPPLEMENT_LINE_TENSION_PER_BINDING
    return SHEET_MODULI_FACTOR[tiling], LINE_TENSION_PER_BINDING[tiling]
_SQRT3 = math.sqrt(3.0)


def _checked(name, value, lo=-np.inf, hi=np.inf, lo_open=False, hi_open=False, finite=True):
    """``value`` as a float array, or ValueError naming ``name`` if NaN, out of range or not
    numbers at all (numpy's own message would not say which argument)."""
    try:
        if np.asarray(value).dtype.kind in "USO":
            raise TypeError  # text ("1.0") would convert to a float, but is no number
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number or an array of numbers, got {value!r}") from None
    if np.isnan(a).any():
        raise ValueError(f"{name} must not be NaN")
    if finite and not np.isfinite(a).all():
        raise ValueError(f"{name} must be finite")
    bad = (a <= lo if lo_open else a < lo) | (a >= hi if hi_open else a > hi)
    if bad.any():
        lb, rb = "(" if lo_open else "[", ")" if hi_open else "]"
        raise ValueError(f"{name} must lie in {lb}{lo}, {hi}{rb}; got {a[bad].ravel()[0]!r}")
    return a


def _nu_gamma(nu, Gamma):
    nu, Gamma = np.broadcast_arrays(_checked("nu", nu, lo=-1.0, hi=1.0, lo_open=True),
                                    _checked("Gamma", Gamma, lo=0.0))
    return nu.ravel(), Gamma.ravel(), Gamma.shape


def _out(a):
    return np.asarray(a)[()]


# Parameter mapping (supplement S1) and the 1D chain (main text Eqs. 1-3)

@dataclass(frozen=True)
class ContinuumParameters:
    """Continuum parameters of a particle (broadcast ndarrays), from ``mapping``.

    Attributes
    ----------
    mu, lam : ndarray
        Lame coefficients of each sheet (energy per unit area).
    nu : ndarray
        2D Poisson ratio.
    kappa_c : ndarray
        Coupling between the sheets, per unit area.
    gamma : ndarray
        Line tension (energy per unit length of edge), ``line_tension(g)``.
    ell : ndarray
        Boundary-layer length (Eq. 10), in lattice spacings.
    e_bulk : ndarray
        Bulk deformation energy per unit reference area (Eq. 8).
    Gamma : ndarray
        Dimensionless line tension ``2 gamma / ((1 + nu) ell e_bulk)``.
    """

    mu: np.ndarray
    nu: np.ndarray
    lam: np.ndarray
    kappa_c: np.ndarray
    gamma: np.ndarray
    ell: np.ndarray
    e_bulk: np.ndarray
    Gamma: np.ndarray


@dataclass(frozen=True)
class ParticleParameters:
    """Particle parameters, from ``particle_parameters`` (broadcast ndarrays).

    Attributes
    ----------
    kc : ndarray
        Stiffness of the connecting springs.
    k_area : ndarray
        Areal stiffness of each triangle.
    g : ndarray
        Binding energy per bound pair of sides, in the chosen convention.
    """

    kc: np.ndarray
    k_area: np.ndarray
    g: np.ndarray


def line_tension(g, tiling="hexagon", convention="measured"):
    """Line tension ``gamma`` of a straight aggregate edge for a binding energy ``g`` per bond.

    ``gamma = LINE_TENSION_PER_BINDING_ENERGY * g``, the constant being 1: cutting the particle
    lattice (spacing 1) along a lattice vector breaks 2 bonds per unit length and creates two
    edges, so each edge costs ``g`` per unit length. A cut perpendicular to a lattice vector
    breaks ``4/sqrt(3)`` bonds per unit length, ``2 g/sqrt(3)`` per edge; the supplement prints
    ``gamma = 4 g/sqrt(3)``. The discrete model's measured edge energy confirms ``gamma = g``
    (``ansatz.edge_line_tension``, written to ``results/ansatz/line_tension.json``).

    Parameters
    ----------
    g : array_like
        Binding energy per bound pair of sides, ``>= 0``.
    tiling : {'hexagon', 'triangle'}, optional
        The particle's tiling.
    convention : {'measured', 'supplement'}, optional
        How ``gamma`` relates to ``g`` (module docstring): ``'measured'`` (default, every figure)
        ``gamma = g``; ``'supplement'`` the printed ``gamma = 4 g / sqrt(3)`` (hexagons only).

    Returns
    -------
    ndarray
        ``gamma``, energy per unit length (lattice spacings); ``g/2`` on the triangle tiling.

    Raises
    ------
    ValueError
        For a negative or non-numeric ``g``, or an unknown tiling or convention.

    Examples
    --------
    >>> from pyfrustrate import continuum
    >>> float(continuum.line_tension(0.01)), round(float(continuum.line_tension(0.01, convention="supplement")), 5)
    (0.01, 0.02309)
    """
    return _out(_tiling_constants(tiling, convention)[1] * _checked("g", g, lo=0.0))


def binding_energy(gamma, tiling="hexagon", convention="measured"):
    """Inverse of ``line_tension``: the binding energy per bond giving line tension ``gamma``.

    ``g = gamma`` (measured convention), ``g = sqrt(3) gamma/4`` (supplement), ``g = 2 gamma``
    (triangles).

    Parameters
    ----------
    gamma : array_like
        Line tension, energy per unit length, ``>= 0``.
    tiling : {'hexagon', 'triangle'}, optional
        The particle's tiling.
    convention : {'measured', 'supplement'}, optional
        How ``gamma`` relates to ``g`` (module docstring): ``'measured'`` (default, every figure)
        ``gamma = g``; ``'supplement'`` the printed ``gamma = 4 g / sqrt(3)`` (hexagons only).

    Returns
    -------
    ndarray
        ``g``.

    Raises
    ------
    ValueError
        For a negative or non-numeric ``gamma``, or an unknown tiling or convention.
    """
    return _out(_checked("gamma", gamma, lo=0.0) / _tiling_constants(tiling, convention)[1])


def mapping(k, kc, k_area, g, eps, tiling="hexagon", convention="measured"):
    """Continuum parameters of a spring particle (supplement S1, Lame typo fixed).

    ``mu = sqrt(3) k/4``, ``nu = (sqrt(3) k + 2 k_area)/(3 sqrt(3) k + 2 k_area)``,
    ``lam = 2 mu nu/(1 - nu) = (sqrt(3) k + 2 k_area)/4`` (misprinted ``mu nu/(1 - nu)``),
    ``kappa_c = 2 sqrt(3) kc``, ``gamma = line_tension(g)``,
    ``ell = sqrt((lam + 2 mu)/(2 kappa_c)) = sqrt(k/(8 (1 - nu) kc))`` (Eq. 10),
    ``e_bulk = 4 mu eps^2 (1 + nu)/(1 - nu) = 2 eps^2 (sqrt(3) k + k_area)`` (Eq. 8; times the
    area sqrt(3)/2 per particle: ``(3 k + sqrt(3) k_area) eps^2``),
    ``Gamma = 2 gamma/((1 + nu) ell e_bulk)``.

    ``k_area = inf`` is the incompressible limit ``nu = 1`` (``lam = ell = e_bulk = inf``,
    ``Gamma = 0``); ``kc = 0`` gives ``ell = inf``, ``Gamma = 0``. ``tiling="triangle"``: the
    triangular particle, whose moduli ``mu, lam, kappa_c`` and ``e_bulk`` are twice these
    (``SHEET_MODULI_FACTOR``; same ``nu``, ``ell`` and bulk energy per particle, area
    ``sqrt(3)/4`` per particle) and ``gamma = g/2``.

    Parameters
    ----------
    k : array_like
        Triangle spring stiffness, ``> 0``.
    kc : array_like
        Connecting spring stiffness, ``>= 0``.
    k_area : array_like
        Areal stiffness, ``> -sqrt(3) k`` (else ``nu <= -1``: unstable sheet); may be ``inf``.
    g : array_like
        Binding energy per bound pair of sides, ``>= 0``.
    eps : array_like
        Mismatch, in (0, 1).
    tiling : {'hexagon', 'triangle'}, optional
        The particle's tiling.
    convention : {'measured', 'supplement'}, optional
        How ``gamma`` relates to ``g`` (module docstring): ``'measured'`` (default, every figure)
        ``gamma = g``; ``'supplement'`` the printed ``gamma = 4 g / sqrt(3)`` (hexagons only).

    Returns
    -------
    ContinuumParameters
        Lengths in lattice spacings.

    Raises
    ------
    ValueError
        For any parameter out of range (named).

    Examples
    --------
    >>> from pyfrustrate import continuum
    >>> c = continuum.mapping(k=1.0, kc=0.0625, k_area=0.75**0.5, g=0.001, eps=0.01)
    >>> round(float(c.ell), 6), round(float(c.nu), 6), round(float(c.Gamma), 4)
    (2.0, 0.5, 1.283)
    """
    factor, _ = _tiling_constants(tiling, convention)
    k = _checked("k", k, lo=0.0, lo_open=True)
    kc = _checked("kc", kc, lo=0.0)
    k_area = _checked("k_area", k_area, finite=False)
    g = _checked("g", g, lo=0.0)
    eps = _checked("eps", eps, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    if (k_area <= -_SQRT3 * k).any():
        raise ValueError("k_area must exceed -sqrt(3) k (the sheet is unstable at nu <= -1)")
    k, kc, k_area, g, eps = np.broadcast_arrays(k, kc, k_area, g, eps)
    p_wave = factor * (3.0 * _SQRT3 * k + 2.0 * k_area) / 4.0  # lam + 2 mu: stays finite until nu = 1
    mu = factor * _SQRT3 * k / 4.0
    nu = 1.0 - 2.0 * mu / p_wave
    kappa_c = factor * 2.0 * _SQRT3 * kc
    with np.errstate(divide="ignore"):
        ell = np.sqrt(p_wave / (2.0 * kappa_c))
    e_bulk = factor * 2.0 * eps**2 * (_SQRT3 * k + k_area)
    gamma = np.asarray(line_tension(g, tiling, convention))
    return ContinuumParameters(mu=mu, nu=nu, lam=p_wave - 2.0 * mu, kappa_c=kappa_c, gamma=gamma,
                               ell=ell, e_bulk=e_bulk,
                               Gamma=2.0 * gamma / ((1.0 + nu) * ell * e_bulk))


def particle_parameters(ell, nu, Gamma, k=1.0, eps=0.01, tiling="hexagon", convention="measured"):
    """Particle parameters with continuum ``(ell, nu, Gamma)`` at given ``k, eps``: the route from
    the paper's ``Gamma`` to the binding energy ``g`` the discrete model takes.

    Inverse of ``mapping``: ``kc = k/(8 (1 - nu) ell^2)``,
    ``k_area = sqrt(3) k (3 nu - 1)/(2 (1 - nu))``, ``g = binding_energy(Gamma (1 + nu) ell
    e_bulk/2)`` with ``e_bulk = sqrt(3) k eps^2 (1 + nu)/(1 - nu)``. ``nu < 1/3`` needs
    ``k_area < 0``; ``nu = 1`` has no finite particle. ``tiling="triangle"``: the same ``kc`` and
    ``k_area``; ``g`` from that tiling's ``e_bulk`` and line tension (``mapping``).

    Parameters
    ----------
    ell : array_like
        Boundary-layer length, lattice spacings, positive and finite.
    nu : array_like
        2D Poisson ratio, in (-1, 1).
    Gamma : array_like
        Dimensionless line tension, ``>= 0``.
    k : array_like, optional
        Triangle spring stiffness (the energy unit), ``> 0``.
    eps : array_like, optional
        Mismatch, in (0, 1).
    tiling : {'hexagon', 'triangle'}, optional
        The particle's tiling.
    convention : {'measured', 'supplement'}, optional
        How ``gamma`` relates to ``g`` (module docstring): ``'measured'`` (default, every figure)
        ``gamma = g``; ``'supplement'`` the printed ``gamma = 4 g / sqrt(3)`` (hexagons only).
        ``"supplement"`` gives ``sqrt(3)/4`` times the measured convention's ``g`` for the same
        ``Gamma``: the paper's ``Gamma = 0.5`` read in the supplement's convention is our 0.217.

    Returns
    -------
    ParticleParameters
        ``kc``, ``k_area`` and ``g`` (per bound pair of sides, in units of ``k``).

    Raises
    ------
    ValueError
        For any parameter out of range (named).

    Examples
    --------
    The binding energy of the paper's point ``ell = 5, nu = 0.9, Gamma = 0.5``, both ways:

    >>> from pyfrustrate import continuum
    >>> p = continuum.particle_parameters(ell=5.0, nu=0.9, Gamma=0.5)
    >>> round(float(p.kc), 6), round(float(p.g), 8)
    (0.05, 0.00781588)
    >>> s = continuum.particle_parameters(ell=5.0, nu=0.9, Gamma=0.5, convention="supplement")
    >>> round(float(s.g / p.g), 4)  # sqrt(3)/4
    0.433
    """
    factor, _ = _tiling_constants(tiling, convention)
    ell = _checked("ell", ell, lo=0.0, lo_open=True)
    nu = _checked("nu", nu, lo=-1.0, hi=1.0, lo_open=True, hi_open=True)
    Gamma = _checked("Gamma", Gamma, lo=0.0)
    k = _checked("k", k, lo=0.0, lo_open=True)
    eps = _checked("eps", eps, lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    e_bulk = factor * _SQRT3 * k * eps**2 * (1.0 + nu) / (1.0 - nu)
    return ParticleParameters(
        kc=np.asarray(k / (8.0 * (1.0 - nu) * ell**2)),
        k_area=np.asarray(_SQRT3 * k * (3.0 * nu - 1.0) / (2.0 * (1.0 - nu))),
        g=np.asarray(binding_energy(Gamma * (1.0 + nu) * ell * e_bulk / 2.0, tiling, convention)))


def chain_ell(kc_over_k):
    """Boundary-layer length of the 1D toy model, main text Eq. 3 (in particles).

    ``ell = 1/ln[1 + x + sqrt(2 x + x^2)]``, ``x = kc/k``: the decay of the corner shift under
    ``k (d_{i+1} - 2 d_i + d_{i-1}) = 2 kc d_i`` (printed Eq. 2 drops the 2).
    ``ell ~ 1/sqrt(2 x)`` for small ``x``; ``x = 0`` gives ``inf``.

    Parameters
    ----------
    kc_over_k : array_like
        ``kc / k``, ``>= 0``.

    Returns
    -------
    ndarray
        ``ell``, in particles.

    Raises
    ------
    ValueError
        For a negative or non-numeric ratio.

    Examples
    --------
    >>> from pyfrustrate import continuum
    >>> round(float(continuum.chain_ell(0.01)), 4)
    7.077
    """
    x = _checked("kc_over_k", kc_over_k, lo=0.0, finite=False)
    with np.errstate(divide="ignore"):
        return _out(1.0 / np.log1p(x + np.sqrt(x) * np.sqrt(2.0 + x)))


def _bracketed_root(func, lo, hi, log=True):
    """Elementwise root of ``func`` bracketed by ``func(lo) < 0 <= func(hi)``.

    Illinois (modified regula falsi) in ``ln x`` (``log``: relative precision) or ``x``, with
    bisection when the secant leaves the bracket. An element stops once its step is below
    2**-46: convergence being superlinear, it is then within a few ulps (the noise of ``func``).
    """
    t = np.log if log else np.asarray
    a, b = t(np.asarray(lo, dtype=float)), t(np.asarray(hi, dtype=float))

    def f(v):
        return func(np.exp(v) if log else v)
    fa, fb = f(a), f(b)
    x, side, done = 0.5 * (a + b), np.zeros(a.shape), np.zeros(a.shape, dtype=bool)
    for _ in range(200):
        with np.errstate(divide="ignore", invalid="ignore"):
            c = (a * fb - b * fa) / (fb - fa)
        c = np.where((c >= a) & (c <= b), c, 0.5 * (a + b))
        done |= np.abs(c - x) <= 2.0**-46 * np.maximum(1.0, np.abs(c))
        x = np.where(done, x, c)
        if done.all():
            break
        fc = f(x)
        neg = fc < 0
        # Halve the stale endpoint's value when the same side is kept twice (Illinois).
        fa = np.where(~neg & (side > 0), 0.5 * fa, fa)
        fb = np.where(neg & (side < 0), 0.5 * fb, fb)
        a, fa = np.where(neg, x, a), np.where(neg, fc, fa)
        b, fb = np.where(neg, b, x), np.where(neg, fb, fc)
        side = np.where(neg, -1.0, 1.0)
    return np.exp(x) if log else x


# Fibre: infinite strip of width W = w ell (Eqs. 9-11)

def fiber_energy(w, nu, Gamma):
    """Mean energy per unit area of a fibre of width ``w = W/ell``, in units of ``e_bulk``.

    Main text Eq. 11 (correct as printed): ``1 - (1 + nu) tanh(w/2)/w + (1 + nu) Gamma/w``;
    ``w = inf`` is the bulk (1). Evaluated as the sum of positive terms
    ``(1 - nu)/2 + (1 + nu)(y - tanh y)/(2 y) + (1 + nu) Gamma/w``, ``y = w/2``, so narrow
    fibres keep full relative precision (the energy -> 0 as nu -> 1).

    A discrete fibre's ``W`` is its ``Topology.size`` (area per unit length, in lattice
    spacings: ``width * sqrt(3)/2`` for a cut-0 fibre of ``width`` rows), not its row count;
    its deformation energy per particle over ``bulk_energy_per_particle`` compares with this at
    ``Gamma = 0`` (``relax`` leaves the binding out).

    Parameters
    ----------
    w : array_like
        Width in units of ``ell``, ``> 0`` (``inf`` allowed).
    nu : array_like
        2D Poisson ratio, in (-1, 1].
    Gamma : array_like
        Dimensionless line tension, ``>= 0`` (``Gamma = 2 gamma / ((1 + nu) ell e_bulk)``).

    Returns
    -------
    ndarray
        Energy per unit area over ``e_bulk``, broadcast over the arguments.

    Raises
    ------
    ValueError
        For arguments out of range (named).

    Examples
    --------
    >>> from pyfrustrate import continuum
    >>> round(float(continuum.fiber_energy(2.0, 0.5, 0.0)), 4)
    0.4288
    >>> continuum.fiber_energy([1.0, 2.0, 4.0], 0.5, 0.2).round(4)
    array([0.6068, 0.5788, 0.7135])
    """
    w = _checked("w", w, lo=0.0, lo_open=True, finite=False)
    nu = _checked("nu", nu, lo=-1.0, hi=1.0, lo_open=True)
    Gamma = _checked("Gamma", Gamma, lo=0.0)
    y = w / 2.0
    small = y < 1.0
    ys = np.where(small, y, 1.0)
    term, series = ys**3 / 3.0, 0.0  # y cosh y - sinh y = sum_k 2k y^(2k+1)/(2k+1)!
    for k in range(1, 12):
        series = series + term
        term = term * ys * ys / ((2 * k) * (2 * k + 3))
    relaxed = np.where(small, series / (2.0 * ys * np.cosh(ys)),
                       0.5 - np.tanh(y) / np.where(small, 1.0, w))
    return _out((1.0 - nu) / 2.0 + (1.0 + nu) * relaxed + (1.0 + nu) * Gamma / w)


def fiber_displacement(x, w, nu):
    """Yellow-sheet displacement ``u_up/(eps ell)`` across a fibre, ``x`` in units of ``ell``.

    Main text Eq. 9 (correct as printed): ``(1 + nu) sinh(x)/cosh(w/2)``, ``|x| <= w/2``, along
    the fibre's normal; ``u_down = -u_up``. Written with ``exp(|x| - w/2)``: no overflow.

    Parameters
    ----------
    x : array_like
        Distance from the fibre's midline, in ``ell``, ``|x| <= w/2``.
    w : array_like
        Width in ``ell``, ``> 0``.
    nu : array_like
        2D Poisson ratio, in (-1, 1].

    Returns
    -------
    ndarray

    Raises
    ------
    ValueError
        For arguments out of range (named), or ``|x| > w/2``.
    """
    x = _checked("x", x)
    w = _checked("w", w, lo=0.0, lo_open=True)
    nu = _checked("nu", nu, lo=-1.0, hi=1.0, lo_open=True)
    x, w, nu = np.broadcast_arrays(x, w, nu)
    if (np.abs(x) > w / 2.0).any():
        raise ValueError("x must satisfy |x| <= w/2")
    ax = np.abs(x)
    shape = -np.exp(ax - w / 2.0) * np.expm1(-2.0 * ax) / (1.0 + np.exp(-w))
    return _out((1.0 + nu) * np.sign(x) * shape)


def _fiber_h(y):
    """``H = tanh y - y sech^2 y`` and ``1 - H`` without cancellation, ``y = w/2``: the fibre
    is stationary where ``H = Gamma``. Small ``y``: ``H = (sinh z - z)/(1 + cosh z)``, ``z = 2y``,
    summed as a series; large ``y``: both terms of ``1 - H`` are positive exponentials."""
    small = y < 0.5
    z = 2.0 * np.where(small, y, 0.5)
    term = sinh_minus_z = z**3 / 6.0
    for n in range(2, 12):
        term = term * z * z / ((2 * n) * (2 * n + 1))
        sinh_minus_z = sinh_minus_z + term
    h_small = sinh_minus_z / (1.0 + np.cosh(z))
    yl = np.where(small, 1.0, y)
    e = np.exp(-2.0 * yl)
    hc_large = 2.0 * e / (1.0 + e) + 4.0 * yl * e / (1.0 + e) ** 2
    return np.where(small, h_small, 1.0 - hc_large), np.where(small, 1.0 - h_small, hc_large)


def _fiber_optimum(G):
    """Optimal width and ``min_w (e_fiber - 1)/(1 + nu)`` for a flat array of ``Gamma``."""
    w = np.where(G == 0.0, 0.0, np.inf)
    tiny = (G > 0.0) & (G < 1e-30)
    w[tiny] = 2.0 * np.cbrt(1.5 * G[tiny])  # H = 2 y^3/3 to machine precision there
    todo = (G >= 1e-30) & (G < 1.0)
    if todo.any():
        g = G[todo]

        def f(y):
            h, hc = _fiber_h(y)
            return np.where(g < 0.5, h - g, (1.0 - g) - hc)
        # H(y) <= 2 y^3/3, and 1 - H(400) underflows to 0: the bracket holds.
        w[todo] = 2.0 * _bracketed_root(f, 0.5 * np.cbrt(1.5 * g), np.full_like(g, 400.0))
    ew = np.exp(-w)
    return w, -2.0 * ew / (1.0 + ew) ** 2  # the minimum is -d tanh(w/2)/dw at w*


def optimal_width(nu, Gamma):
    """Width ``W*/ell`` minimising the fibre energy per unit area (Eq. 11).

    Stationarity: ``tanh(w/2) - (w/2) sech^2(w/2) = Gamma``, whose left side rises from 0 to 1,
    so ``W*`` is finite iff ``Gamma < 1`` (the fibre then beats the bulk) and ``inf`` otherwise;
    0 at ``Gamma = 0``. Independent of ``nu`` (broadcast only). Multiply by ``ell`` for lattice
    spacings, and divide those by ``sqrt(3)/2`` for rows of a cut-0 fibre.

    Parameters
    ----------
    nu : array_like
        2D Poisson ratio, in (-1, 1].
    Gamma : array_like
        Dimensionless line tension, ``>= 0`` (``Gamma = 2 gamma / ((1 + nu) ell e_bulk)``).

    Returns
    -------
    ndarray
        ``W*/ell``.

    Raises
    ------
    ValueError
        For arguments out of range (named).

    Examples
    --------
    >>> from pyfrustrate import continuum
    >>> continuum.optimal_width(0.9, [0.0, 0.5, 1.0]).round(4)
    array([0.    , 2.5075,    inf])
    """
    nu, Gamma, shape = _nu_gamma(nu, Gamma)
    return _out(_fiber_optimum(Gamma)[0].reshape(shape))


# Disk of radius R = r ell (Eqs. 12-13)

def _sigma_series(n_terms=30):
    """Coefficients ``c_k`` of ``1 - I2(r)/I1(r) ~ sum_k c_k r^-k`` (``c_1 = 3/2``): Hankel's
    expansions of ``I_1, I_2`` divided as formal power series."""
    def hankel(n, j):
        return (-1) ** j * math.prod(4 * n * n - (2 * i - 1) ** 2 for i in range(1, j + 1)) / (
            math.factorial(j) * 8.0**j)
    c = []
    for k in range(n_terms):
        c.append(hankel(1, k) - hankel(2, k) - sum(c[i] * hankel(1, k - i) for i in range(k)))
    return np.array(c)


_SIGMA_C = _sigma_series()
_SIGMA_SWITCH = 20.0  # beyond it the 30-term series is accurate to ~4e-16


def _rho_sigma(r):
    """For r > 0: ``rho = I2/I1`` and ``sigma = 1 - rho`` to full relative precision (the
    subtraction would lose ``log10 r`` digits), and for ``r >= _SIGMA_SWITCH`` the series
    ``S = r sigma = sum_k c_k r^(1-k)`` and ``U = r (2 S - 3)`` (zero below the switch)."""
    r = np.asarray(r, dtype=float)
    big = r >= _SIGMA_SWITCH
    rho, S, U = np.empty_like(r), np.zeros_like(r), np.zeros_like(r)
    rs = r[~big]
    rho[~big] = np.where(rs < 1e-100, rs / 4.0, ive(2, rs) / np.maximum(ive(1, rs), 1e-300))
    x = 1.0 / r[big]
    s_big = u_big = 0.0
    for c in _SIGMA_C[:0:-1]:  # Horner
        s_big = s_big * x + c
    for c in _SIGMA_C[:1:-1]:
        u_big = u_big * x + c
    S[big], U[big] = s_big, 2.0 * u_big
    sigma = np.where(big, S * np.where(big, 1.0 / r, 0.0), 1.0 - rho)
    rho[big] = 1.0 - sigma[big]
    return rho, sigma, S, U


def _disk_s(r, nu, terms=None):
    """``s = 2 I1/D = r/p`` (edge displacement over ``eps ell``), ``q - 1`` where ``q = s - r s'``
    is the stationarity function, and ``s'``; ``p = r rho + 1 + nu``.

    By ``I1' = I2 + I1/r`` and ``I2' = I1 - 2 I2/r``: ``q = r^2 (r (1 - rho^2) - 2 rho)/p^2``
    and ``s' = (1 + nu - r (r (1 - rho^2) - 3 rho))/p^2``. Beyond ``_SIGMA_SWITCH`` the
    cancelling O(r) terms are removed through ``S, U``: full absolute precision at any ``r``.
    ``terms`` are precomputed ``_rho_sigma(r)``.
    """
    r = np.asarray(r, dtype=float)
    big = r >= _SIGMA_SWITCH
    rho, sigma, S, U = _rho_sigma(r) if terms is None else terms
    nu1 = 1.0 + nu
    p = r * rho + nu1
    numer = r * sigma * (2.0 - sigma) - 2.0 * rho
    qm1 = np.where(big, r * (U - S * S + 4.0 * S - 2.0 * nu1) - S * S - nu1**2 + 2.0 * S * nu1,
                   r * r * numer - p**2) / p**2
    n = np.where(big, nu1 - U + S * S - 3.0 * S, nu1 - r * (numer - rho))
    return r / p, qm1, n / p**2


def disk_energy(r, nu, Gamma):
    """Mean energy per unit area of a disk of radius ``r = R/ell``, in units of ``e_bulk``.

    Corrected main text Eq. 13 (print lacks the factor ``1 + nu`` on the deformation term):
    ``1 - (1 + nu)(I0 - I2)/D + (1 + nu) Gamma/r``, ``D = I0 + I2 + nu (I0 - I2)``, Bessel
    functions at ``r``. With ``I0 - I2 = 2 I1/r`` this is
    ``1/(1 + (1 + nu) I1/(r I2)) + (1 + nu) Gamma/r``, free of cancellation for small disks.
    It follows from ``E = E(u=0) + L[u*]/2`` (quadratic functional, ``L`` its linear part):
    ``1 - u_up(R)/(eps R)`` plus the line tension. ``r = inf`` is the bulk (1). A discrete
    disk's ``R`` is its ``Topology.size`` (the radius of the disk of equal area).

    Parameters
    ----------
    r : array_like
        Radius in units of ``ell``, ``> 0`` (``inf`` allowed).
    nu : array_like
        2D Poisson ratio, in (-1, 1].
    Gamma : array_like
        Dimensionless line tension, ``>= 0`` (``Gamma = 2 gamma / ((1 + nu) ell e_bulk)``).

    Returns
    -------
    ndarray
        Energy per unit area over ``e_bulk``.

    Raises
    ------
    ValueError
        For arguments out of range (named).

    Examples
    --------
    >>> from pyfrustrate import continuum
    >>> round(float(continuum.disk_energy(2.0, 0.5, 0.0)), 4)
    0.3661
    """
    r = _checked("r", r, lo=0.0, lo_open=True, finite=False)
    nu = _checked("nu", nu, lo=-1.0, hi=1.0, lo_open=True)
    Gamma = _checked("Gamma", Gamma, lo=0.0)
    with np.errstate(divide="ignore"):
        return _out(1.0 / (1.0 + (1.0 + nu) / (r * _rho_sigma(r)[0])) + (1.0 + nu) * Gamma / r)


def disk_displacement(rho, r, nu):
    """Radial yellow-sheet displacement ``u_up/(eps ell)`` in a disk, ``rho, r`` in ``ell``.

    Corrected main text Eq. 12 (print lacks a factor 2): ``2 (1 + nu) I1(rho)/D(r)``,
    ``D = I0 + I2 + nu (I0 - I2)``, ``0 <= rho <= r``, ``u_down = -u_up``; it follows from the
    free-edge condition ``(lam + 2 mu) u'(R) + lam u(R)/R = 2 eps (lam + mu)``. Uses ``ive``
    so that ``e^r`` cancels.

    Parameters
    ----------
    rho : array_like
        Distance from the centre, in ``ell``, ``0 <= rho <= r``.
    r : array_like
        Disk radius, in ``ell``, ``> 0``.
    nu : array_like
        2D Poisson ratio, in (-1, 1].

    Returns
    -------
    ndarray

    Raises
    ------
    ValueError
        For arguments out of range (named), or ``rho > r``.
    """
    rho = _checked("rho", rho, lo=0.0)
    r = _checked("r", r, lo=0.0, lo_open=True)
    nu = _checked("nu", nu, lo=-1.0, hi=1.0, lo_open=True)
    rho, r, nu = np.broadcast_arrays(rho, r, nu)
    if (rho > r).any():
        raise ValueError("rho must satisfy 0 <= rho <= r")
    ratio = ive(1, rho) / ive(1, r) * np.exp(rho - r)  # I1(rho)/I1(r)
    return _out((1.0 + nu) * r * ratio / (r * _rho_sigma(r)[0] + 1.0 + nu))


@functools.cache
def _radius_grid():
    """Log grid of radii (1e-3 .. 1e9) and its Bessel terms, to bracket roots."""
    r = np.logspace(-3.0, 9.0, 2401)
    return r, _rho_sigma(r)


def _grid_disk_s(i, nu):
    r, terms = _radius_grid()
    i = np.minimum(i, r.size - 1)
    return _disk_s(r[i], nu, tuple(t[i] for t in terms))


def _first_index(pred, lo, hi):
    """Elementwise binary search for the smallest grid index in ``[lo, hi)`` where ``pred``
    holds (``hi`` if none); ``pred(i)`` must be False then True along the grid."""
    while (lo < hi).any():
        active = lo < hi
        mid = (lo + hi) // 2
        t = pred(mid) & active
        lo, hi = np.where(active & ~t, mid + 1, lo), np.where(t, mid, hi)
    return lo


def _disk_optimum(nu, G):
    """Optimal radius and ``min_r (e_disk - 1)/(1 + nu)`` for flat arrays ``nu, G``.

    ``(e - 1)/(1 + nu) = (Gamma - s(r))/r`` has derivative ``(q - Gamma)/r^2``. ``q`` rises
    monotonically from 0 to its maximum (> 1 for nu < 1/2, then falls back to 1; for nu >= 1/2
    it tends to 1 from below), so the only candidate minimum is the first crossing
    ``q = Gamma``; it beats the bulk iff ``s' > 0`` there. Without a crossing the bulk wins.
    """
    r = np.where(G == 0.0, 0.0, np.inf)
    fmin = np.where(G == 0.0, -1.0 / (1.0 + nu), 0.0)
    tiny = (G > 0.0) & (G < 1e-30)
    r[tiny] = np.cbrt(2.0 * (1.0 + nu[tiny]) ** 2 * G[tiny])  # q = r^3/(2 (1+nu)^2) there
    todo = G >= 1e-30
    if todo.any():
        n_, g = nu[todo], G[todo]
        grid = _radius_grid()[0]
        last = np.full(g.shape, grid.size - 1)
        peak = _first_index(lambda i: _grid_disk_s(i + 1, n_)[1] <= _grid_disk_s(i, n_)[1],
                            0 * last, last)
        idx = _first_index(lambda i: _grid_disk_s(i, n_)[1] >= g - 1.0, 0 * last, peak + 1)
        lo = np.where(idx == 0, 0.5 * np.cbrt(2.0 * (1.0 + n_) ** 2 * g),
                      grid[np.clip(idx - 1, 0, last)])
        hi = np.where(idx <= peak, grid[np.minimum(idx, last)], 1e150)
        # Still rising at the grid's end (nu >= 1/2): a crossing of Gamma < 1 lies beyond.
        ok = (idx <= peak) | ((peak == last) & (g < 1.0))
        sub = np.full(g.shape, np.inf)
        sub[ok] = _bracketed_root(lambda x: _disk_s(x, n_[ok])[1] + (1.0 - g[ok]),
                                  lo[ok], hi[ok])
        r[todo] = sub
    finite = np.isfinite(r) & (r > 0.0)
    f = -_disk_s(r[finite], nu[finite])[2]  # (Gamma - s)/r = -s' at a stationary point
    r[finite], fmin[finite] = np.where(f < 0.0, r[finite], np.inf), np.minimum(f, 0.0)
    return r, fmin


def optimal_radius(nu, Gamma):
    """Radius ``R*/ell`` minimising the disk energy per unit area (corrected Eq. 13).

    Stationarity: ``s(r) - r s'(r) = Gamma``, ``s = 2 I1/D``. The left side overshoots 1 for
    ``nu < 1/2``, so ``R*`` stays finite slightly above ``Gamma = 1`` and jumps to ``inf`` at
    the disk-bulk boundary ``Gamma = max_r s(r)`` (first order). ``inf`` where the bulk is at
    least as good as every finite disk, 0 at ``Gamma = 0``.

    Parameters
    ----------
    nu : array_like
        2D Poisson ratio, in (-1, 1].
    Gamma : array_like
        Dimensionless line tension, ``>= 0`` (``Gamma = 2 gamma / ((1 + nu) ell e_bulk)``).

    Returns
    -------
    ndarray
        ``R*/ell``.

    Raises
    ------
    ValueError
        For arguments out of range (named).

    Examples
    --------
    >>> from pyfrustrate import continuum
    >>> continuum.optimal_radius(0.9, [0.0, 0.5, 2.0]).round(4)
    array([0.    , 2.3934,    inf])
    """
    nu, Gamma, shape = _nu_gamma(nu, Gamma)
    return _out(_disk_optimum(nu, Gamma)[0].reshape(shape))


# Phase diagram (Fig. 3a)

def phase(nu, Gamma):
    """The phase of lowest energy per unit area (Fig. 3a).

    Among the optimal fibre (Eq. 11), the optimal disk (corrected Eq. 13) and the bulk (1). Ties
    go to the bulk, then to the fibre (e.g. ``nu = 1, Gamma = 0``, where both reach 0).

    Parameters
    ----------
    nu : array_like
        2D Poisson ratio, in (-1, 1].
    Gamma : array_like
        Dimensionless line tension, ``>= 0`` (``Gamma = 2 gamma / ((1 + nu) ell e_bulk)``).

    Returns
    -------
    ndarray of str
        ``'bulk'``, ``'fiber'`` or ``'disk'``.

    Raises
    ------
    ValueError
        For arguments out of range (named).

    Examples
    --------
    >>> from pyfrustrate import continuum
    >>> continuum.phase([0.1, 0.5, 0.9], 0.5)
    array(['disk', 'disk', 'fiber'], dtype='<U5')
    >>> str(continuum.phase(0.9, 1.5))
    'bulk'
    """
    nu, Gamma, shape = _nu_gamma(nu, Gamma)
    ff, fd = _fiber_optimum(Gamma)[1], _disk_optimum(nu, Gamma)[1]
    out = np.where(np.minimum(ff, fd) >= 0.0, "bulk", np.where(fd < ff, "disk", "fiber"))
    return _out(out.reshape(shape))


@dataclass(frozen=True)
class CriticalLineTensions:
    """Phase boundaries of Fig. 3a at given ``nu`` (ndarrays, nan where absent).

    Attributes
    ----------
    fiber_bulk : ndarray
        1 (fibres beat the bulk iff ``Gamma < 1``).
    disk_bulk : ndarray
        ``max_r s(r)``, above 1 for ``nu < 1/2``, else 1.
    disk_fiber : ndarray
        The ``Gamma`` below which disks beat fibres.
    disk_fiber_upper : ndarray
        For ``nu_c < nu < 1/2`` (``nu_c ~ 0.4496``) fibres only win in
        ``disk_fiber < Gamma < disk_fiber_upper`` and disks again above, up to ``disk_bulk``; it
        tends to 1 at the triple point ``(nu, Gamma) = (1/2, 1)`` (set to 1 there). Below ``nu_c``
        disks win for every ``Gamma < disk_bulk`` and both disk-fibre entries are nan.
    """

    fiber_bulk: np.ndarray
    disk_bulk: np.ndarray
    disk_fiber: np.ndarray
    disk_fiber_upper: np.ndarray


def critical_line_tensions(nu):
    """Critical ``Gamma`` of the disk-bulk, fibre-bulk and disk-fibre transitions at ``nu``.

    ``Delta(Gamma) = min e_disk - min e_fiber`` has slope ``1/R* - 1/W*`` (envelope theorem),
    so it peaks where ``R* = W* = x``: at the first ``x`` with ``q(x) = H(x/2)``, where
    ``Delta = (tanh(x/2) - s(x))/x``. The disk-fibre boundaries are the roots of ``Delta`` on
    either side of that peak.

    Parameters
    ----------
    nu : array_like
        2D Poisson ratio, in (-1, 1].

    Returns
    -------
    CriticalLineTensions
        Shaped like ``nu``.

    Raises
    ------
    ValueError
        For ``nu`` out of range.

    Examples
    --------
    >>> from pyfrustrate import continuum
    >>> c = continuum.critical_line_tensions([0.2, 0.9])
    >>> c.disk_bulk.round(4), c.disk_fiber.round(4)
    (array([1.044, 1.   ]), array([   nan, 0.1221]))
    """
    nu = _checked("nu", nu, lo=-1.0, hi=1.0, lo_open=True)
    flat = nu.ravel()
    grid, terms = _radius_grid()
    size = grid.size
    # s' > 0 at grid[0] for every nu; s' changes sign once (nu < 1/2) or never.
    idx = _first_index(lambda i: _grid_disk_s(i, flat)[2] <= 0.0, np.zeros(flat.shape, int),
                       np.full(flat.shape, size))
    disk_bulk = np.ones_like(flat)
    m = idx < size
    r_max = _bracketed_root(lambda x: -_disk_s(x, flat[m])[2], grid[idx[m] - 1], grid[idx[m]])
    disk_bulk[m] = _disk_s(r_max, flat[m])[0]

    def q_minus_h(x, n, t=None):  # q(x) - H(x/2) > 0 while R* < W* at equal Gamma
        return _disk_s(x, n, t)[1] + _fiber_h(x / 2.0)[1]
    # It may change sign twice: scan the whole grid (in chunks) for the first change.
    idx = np.concatenate([np.where(d.any(axis=1), np.argmax(d, axis=1), -1) for d in (
        q_minus_h(grid, part[:, None], terms) <= 0.0
        for part in np.array_split(flat, 1 + flat.size // 256))])
    lower, upper = np.full_like(flat, np.nan), np.full_like(flat, np.nan)
    cross = np.flatnonzero(idx > 0)
    x1 = _bracketed_root(lambda x: -q_minus_h(x, flat[cross]), grid[idx[cross] - 1],
                         grid[idx[cross]])
    window = np.tanh(x1 / 2.0) > _disk_s(x1, flat[cross])[0]  # Delta > 0 at its peak
    cross, x1 = cross[window], x1[window]
    g_peak, n_ = _fiber_h(x1 / 2.0)[0], flat[cross]

    def delta(gg, nn):
        return _disk_optimum(nn, gg)[1] - _fiber_optimum(gg)[1]
    lower[cross] = _bracketed_root(lambda gg: delta(gg, n_), 0 * g_peak, g_peak, log=False)
    lower[flat == 1.0] = 0.0  # disk and fibre tie at Gamma = 0 only
    back = _disk_optimum(n_, np.ones_like(n_))[1] < 0.0  # disks beat the bulk at Gamma = 1
    up = np.full_like(g_peak, np.nan)
    up[back] = _bracketed_root(lambda gg: -delta(gg, n_[back]), g_peak[back],
                               np.ones(back.sum()), log=False)
    up[n_ == 0.5] = 1.0
    upper[cross] = up
    return CriticalLineTensions(fiber_bulk=np.ones(nu.shape), disk_bulk=disk_bulk.reshape(nu.shape),
                                disk_fiber=lower.reshape(nu.shape),
                                disk_fiber_upper=upper.reshape(nu.shape))
