"""Tests of the 1D toy model (main text Eq. 1, Fig. 1): ``pyfrustrate.chain``.

Every reference is independent of the kernel:

* the energy is re-implemented here term by term from Eq. (1);
* the relaxed shift ``delta_i = x_up_i - x_down_i`` is compared with (a) a direct numpy solve of
  the tridiagonal force balance derived below and (b) the closed form
  ``delta_i = A sinh((i - n/2)/ell)`` with ``cosh(1/ell) = 1 + kc/k`` and ``A`` fixed by the
  force balance at the edge.

Derivation (by hand, from Eq. 1). Write ``s_i = x_up_i + x_down_i``. The two face terms of a
particle sum to ``k (ds/2 - 1)^2 + k/4 (d delta - 2 eps)^2``, so ``s`` and ``delta`` decouple,
``s`` relaxes to ``ds = 2`` and

    E = sum_{i=0}^{n-1} k/4 (delta_{i+1} - delta_i - 2 eps)^2
                        + kc/4 [(delta_{i+1} - eps)^2 + (delta_i + eps)^2].

Force balance: interior ``k (delta_{i+1} - 2 delta_i + delta_{i-1}) = 2 kc delta_i`` (the paper's
Eq. 2 prints ``kc``: a typo, see chain.py); left edge
``k (delta_1 - delta_0) - kc delta_0 = (2 k + kc) eps``; right edge
``k (delta_n - delta_{n-1}) + kc delta_n = (2 k + kc) eps``. The interior recursion is solved by
``sinh((i - n/2)/ell)`` with ``cosh(1/ell) = 1 + kc/k``; the edge equation fixes ``A``.
"""
import numpy as np
import pytest
from scipy.optimize import curve_fit

from pyfrustrate import chain, continuum


# --------------------------------------------------------------------------------------------
# Independent references
# --------------------------------------------------------------------------------------------

def eq1_energy(n, k, kc, eps, x_up, x_down):
    """Main text Eq. (1) summed over the n particles, written out term by term."""
    e = 0.0
    for i in range(n):
        e += k / 2 * ((x_up[i + 1] - x_up[i]) - (1 + eps)) ** 2
        e += k / 2 * ((x_down[i + 1] - x_down[i]) - (1 - eps)) ** 2
        e += kc / 4 * (x_up[i + 1] - x_down[i + 1] - eps) ** 2
        e += kc / 4 * (x_down[i] - x_up[i] - eps) ** 2
    return e


def shift_from_force_balance(n, k, kc, eps):
    """Solve the (n+1) x (n+1) tridiagonal force balance of the module docstring with numpy."""
    m = n + 1
    a = np.zeros((m, m))
    b = np.zeros(m)
    for i in range(1, n):  # interior: k d_{i-1} - (2k + 2kc) d_i + k d_{i+1} = 0
        a[i, i - 1], a[i, i], a[i, i + 1] = k, -2 * k - 2 * kc, k
    a[0, 0], a[0, 1], b[0] = -k - kc, k, (2 * k + kc) * eps           # left edge
    a[n, n - 1], a[n, n], b[n] = -k, k + kc, (2 * k + kc) * eps       # right edge
    return np.linalg.solve(a, b)


def shift_sinh(n, k, kc, eps):
    """``A sinh((i - n/2)/ell)``, ``cosh(1/ell) = 1 + kc/k``, ``A`` from the left-edge equation."""
    a = np.arccosh(1 + kc / k)  # 1/ell
    u0 = -n * a / 2
    amplitude = (2 * k + kc) * eps / (k * (np.sinh(u0 + a) - np.sinh(u0)) - kc * np.sinh(u0))
    return amplitude * np.sinh((np.arange(n + 1) - n / 2) * a)


def exact_state(n, k, kc, eps):
    """Exact minimiser (x_up, x_down): delta from the sinh form, s_i = 2 i."""
    d = shift_sinh(n, k, kc, eps)
    s = 2.0 * np.arange(n + 1)
    return (s + d) / 2, (s - d) / 2


# --------------------------------------------------------------------------------------------
# Energy and gradient
# --------------------------------------------------------------------------------------------

ENERGY_CASES = [  # (n, k, kc, eps)
    (1, 1.0, 0.01, 0.01),
    (5, 1.0, 0.0, 0.1),      # no connecting springs
    (12, 2.5, 0.3, 0.05),
    (30, 0.7, 1.7, 0.3),     # kc > k, large mismatch
]


@pytest.mark.parametrize("n, k, kc, eps", ENERGY_CASES)
def test_energy_matches_eq1_on_random_states(n, k, kc, eps, rng):
    for _ in range(3):
        x_up = np.arange(n + 1) + 0.2 * rng.standard_normal(n + 1)
        x_down = np.arange(n + 1) + 0.2 * rng.standard_normal(n + 1)
        e, _ = chain.energy(n, k, kc, eps, x_up, x_down)
        assert e == pytest.approx(eq1_energy(n, k, kc, eps, x_up, x_down), rel=1e-12, abs=1e-15)


@pytest.mark.parametrize("n, k, kc, eps", ENERGY_CASES)
def test_gradient_matches_central_differences(n, k, kc, eps, rng, fd_gradient):
    # The energy is exactly quadratic, so central differences are exact up to roundoff.
    m = n + 1
    for _ in range(3):
        x = np.concatenate([np.arange(m), np.arange(m)]) + 0.3 * rng.standard_normal(2 * m)
        _, grad = chain.energy(n, k, kc, eps, x[:m], x[m:])
        assert grad.shape == (2 * m,)
        fd = fd_gradient(lambda y: chain.energy(n, k, kc, eps, y[:m], y[m:])[0], x, 1e-4)
        np.testing.assert_allclose(grad, fd, rtol=0, atol=1e-9 * max(1.0, np.abs(fd).max()))


# --------------------------------------------------------------------------------------------
# Relaxed profile
# --------------------------------------------------------------------------------------------

PROFILE_CASES = [  # (n, k, kc, eps)
    (1, 1.0, 0.01, 0.01),    # a single particle: two corners per face
    (2, 1.0, 0.5, 0.02),
    (7, 0.5, 0.5, 0.1),      # kc = k: ell ~ 0.76
    (40, 1.0, 0.01, 0.01),   # ell ~ 7, n ~ 6 ell
    (15, 2.0, 0.02, 0.05),   # ell ~ 7 > n/2: boundary layers overlap
    (200, 1.0, 1e-3, 0.01),  # ell ~ 22
]

# Relaxation accuracy: L-BFGS stops at max|grad| <= tol k eps; the error in delta is then at most
# ~ tol k eps / (smallest stiffness ~ kc) per mode. Measured: |delta - exact| / max|delta| <= 1.5e-6
# over these cases at tol = 1e-6 (worst: n = 200, kc = 1e-3); 1e-5 leaves margin and is still far below any modelling error
# (e.g. kc instead of 2 kc in the force balance changes delta by > 1 %).
PROFILE_RTOL = 1e-5


def test_independent_references_agree():
    # The sinh closed form and the linear solve are two routes to the same minimiser, and both
    # make the hand-written energy stationary: a check of the derivation itself.
    for n, k, kc, eps in PROFILE_CASES:
        d_lin = shift_from_force_balance(n, k, kc, eps)
        d_sinh = shift_sinh(n, k, kc, eps)
        np.testing.assert_allclose(d_sinh, d_lin, rtol=1e-9, atol=1e-14)
        x_up, x_down = exact_state(n, k, kc, eps)
        for i in range(n + 1):  # stationarity of eq1_energy in delta_i at fixed s
            h = 1e-6
            up_p, down_p = x_up.copy(), x_down.copy()
            up_m, down_m = x_up.copy(), x_down.copy()
            up_p[i] += h / 2; down_p[i] -= h / 2
            up_m[i] -= h / 2; down_m[i] += h / 2
            slope = (eq1_energy(n, k, kc, eps, up_p, down_p) - eq1_energy(n, k, kc, eps, up_m, down_m)) / h
            assert abs(slope) < 1e-8 * k * eps


@pytest.mark.parametrize("n, k, kc, eps", PROFILE_CASES)
def test_relaxed_shift_is_the_exact_sinh_profile(n, k, kc, eps):
    r = chain.relax(n, k, kc, eps)
    assert r.converged, r.status
    assert r.x_up.shape == r.x_down.shape == (n + 1,)
    exact = shift_sinh(n, k, kc, eps)
    scale = np.abs(exact).max()
    np.testing.assert_allclose(r.shift, exact, rtol=0, atol=PROFILE_RTOL * scale)
    np.testing.assert_allclose(r.shift, shift_from_force_balance(n, k, kc, eps), rtol=0, atol=PROFILE_RTOL * scale)
    # The shift is antisymmetric about the centre and negative at the left edge (the top face,
    # longer at rest, overhangs the bottom one outwards).
    np.testing.assert_allclose(r.shift, -r.shift[::-1], rtol=0, atol=PROFILE_RTOL * scale)
    assert r.shift[0] < 0


@pytest.mark.parametrize("n, k, kc, eps", PROFILE_CASES)
def test_relaxed_energy_is_the_exact_minimum(n, k, kc, eps):
    r = chain.relax(n, k, kc, eps)
    e_exact = eq1_energy(n, k, kc, eps, *exact_state(n, k, kc, eps))
    # The minimiser cannot go below the true minimum (beyond roundoff), and stops within a
    # relative 1e-9 of it (the energy error is quadratic in the residual gradient).
    # (A single particle relaxes to zero energy: compare absolutely, on the scale k eps^2.)
    assert r.energy >= e_exact * (1 - 1e-12) - 1e-15 * k * eps**2
    assert r.energy == pytest.approx(e_exact, rel=1e-9, abs=1e-14 * k * eps**2)
    assert r.energy == pytest.approx(eq1_energy(n, k, kc, eps, r.x_up, r.x_down), rel=1e-12)


def test_bulk_energy_is_reached_in_the_middle_of_a_long_chain():
    # Deep inside (delta -> 0) each particle is a unit rectangle: faces strained by -+eps (energy
    # k eps^2) and both connecting springs stretched by eps (kc eps^2 / 2), i.e. k eps^2 + kc eps^2/2.
    n, k, kc, eps = 120, 1.0, 0.05, 0.02
    r = chain.relax(n, k, kc, eps)
    i = n // 2
    one = eq1_energy(1, k, kc, eps, r.x_up[i:i + 2], r.x_down[i:i + 2])
    assert one == pytest.approx(k * eps**2 + kc * eps**2 / 2, rel=1e-6)


# --------------------------------------------------------------------------------------------
# Decay length against main text Eq. (3)
# --------------------------------------------------------------------------------------------

# Fitted over the left half of the chain, excluding the ell closest to the centre (where delta
# changes sign) and every point where |delta| has decayed below 1e-3 of its edge value (there
# the relaxation error, ~ tol k eps / kc absolute, would bias log|delta|: at kc = k, ell = 0.76,
# the profile falls by e^13 before the centre). Measured |fitted/chain_ell - 1| <= 2.4e-5 over
# kc/k = 1e-4 .. 1 at tol = 1e-6 (the fit of the exact profile: < 1e-13). Eq. (3) differs from
# its small-kc approximation sqrt(k / 2 kc) by 0.8 % at kc/k = 0.1 and 7 % at kc/k = 1, i.e.
# 80 and 700 times the tolerance.
DECAY_RTOL = 1e-4


def fit_decay_length(delta, n, ell_guess):
    i = np.arange(n + 1)
    keep = (i <= n / 2 - max(ell_guess, 1.0)) & (np.abs(delta) >= 1e-3 * np.abs(delta).max())
    assert keep.sum() >= 5

    def model(i, log_a, inv_ell):
        return log_a + np.log(np.sinh((n / 2 - i) * inv_ell))

    popt, _ = curve_fit(model, i[keep], np.log(np.abs(delta[keep])),
                        p0=(np.log(abs(delta[0]) / np.sinh(n / 2 / ell_guess)), 1 / ell_guess))
    return 1 / popt[1]


@pytest.mark.parametrize("kc_over_k", [1e-4, 1e-3, 1e-2, 1e-1, 1.0])
@pytest.mark.parametrize("k", [1.0, 3.0])
def test_decay_length_matches_eq3_over_four_decades(kc_over_k, k):
    ell = float(continuum.chain_ell(kc_over_k))
    n = max(20, int(np.ceil(10 * ell)))  # n >= 10 ell: two well-separated boundary layers
    r = chain.relax(n, k, kc_over_k * k, 0.01)
    assert r.converged, r.status
    # The guess is deliberately off by 30 % so the fit has to find ell itself.
    fitted = fit_decay_length(r.shift, n, 1.3 * ell)
    assert fitted == pytest.approx(ell, rel=DECAY_RTOL)
    # Eq. (3) and its limit: at kc ~ k the exact discrete length differs from sqrt(k / 2 kc).
    if kc_over_k >= 0.1:
        assert abs(fitted / np.sqrt(1 / (2 * kc_over_k)) - 1) > 50 * DECAY_RTOL


def test_decay_length_small_kc_limit():
    # Main text: ell ~ sqrt(k / 2 kc) for kc << k (relative correction O(kc/k)).
    for x in [1e-6, 1e-4]:
        assert float(continuum.chain_ell(x)) == pytest.approx(np.sqrt(1 / (2 * x)), rel=x)


# --------------------------------------------------------------------------------------------
# Bad input and non-convergence
# --------------------------------------------------------------------------------------------

BAD_PARAMETERS = [  # (name, n, k, kc, eps)
    ("n", 0, 1.0, 0.01, 0.01),
    ("n", -3, 1.0, 0.01, 0.01),
    ("k", 5, 0.0, 0.01, 0.01),
    ("k", 5, -1.0, 0.01, 0.01),
    ("k", 5, float("nan"), 0.01, 0.01),
    ("k", 5, float("inf"), 0.01, 0.01),
    ("kc", 5, 1.0, -1e-3, 0.01),
    ("kc", 5, 1.0, float("nan"), 0.01),
    ("eps", 5, 1.0, 0.01, 0.0),
    ("eps", 5, 1.0, 0.01, 1.0),
    ("eps", 5, 1.0, 0.01, -0.1),
    ("eps", 5, 1.0, 0.01, 1.5),
    ("eps", 5, 1.0, 0.01, float("nan")),
]


@pytest.mark.parametrize("name, n, k, kc, eps", BAD_PARAMETERS)
def test_relax_rejects_bad_parameters_naming_them(name, n, k, kc, eps):
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        chain.relax(n, k, kc, eps)


@pytest.mark.parametrize("name, n, k, kc, eps", BAD_PARAMETERS)
def test_energy_rejects_bad_parameters_naming_them(name, n, k, kc, eps):
    m = max(n, 0) + 1
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        chain.energy(n, k, kc, eps, np.arange(m), np.arange(m))


def test_energy_rejects_wrong_state_size():
    with pytest.raises(ValueError, match=r"\bx\b"):
        chain.energy(4, 1.0, 0.01, 0.01, np.arange(5), np.arange(4))


@pytest.mark.parametrize("kwargs, name", [({"tol": 0.0}, "tol"), ({"tol": -1e-6}, "tol"),
                                          ({"max_iter": 0}, "max_iter")])
def test_relax_rejects_bad_options(kwargs, name):
    with pytest.raises(ValueError, match=name):
        chain.relax(10, 1.0, 0.01, 0.01, **kwargs)


def test_non_convergence_is_reported():
    r = chain.relax(200, 1.0, 1e-3, 0.01, max_iter=2)
    assert r.converged is False
    assert "iterations" in r.status
    assert r.gradient_norm > 1e-6 * 0.01  # the stopping criterion was not met
    assert np.isfinite(r.energy) and np.all(np.isfinite(r.shift))
    # ... and the same chain converges when allowed to.
    assert chain.relax(200, 1.0, 1e-3, 0.01).converged


@pytest.mark.parametrize("max_iter", [2, 20])
def test_max_iter_caps_the_evaluations(max_iter):
    # chain.relax documents max_iter as the cap on energy-and-gradient evaluations, and
    # `iterations` as the evaluations used. Regression (kernel/minimize.cpp, fixed): the cap was enforced by
    # throwing nlopt::forced_stop from the objective, but NLopt's C++ wrapper only sets a stop flag
    # that L-BFGS (Luksan) checks between line searches, so it keeps evaluating (returning
    # HUGE_VAL) and the callback keeps counting: max_iter = 2 gives 12 evaluations, 5 gives 26.
    r = chain.relax(200, 1.0, 1e-3, 0.01, max_iter=max_iter)
    assert r.iterations <= max_iter
