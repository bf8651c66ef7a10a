"""Tests of pyfrustrate.continuum against independent results.

Reference solutions never reuse the closed forms under test: they minimise the energy functional
of main text Eq. (4) directly, either by solving its Euler-Lagrange equations with
``scipy.integrate.solve_bvp`` and integrating Eq. (4) at the solution, or by minimising a
finite-difference discretisation of Eq. (4) (a sparse linear least-squares problem). Units:
``eps = mu = ell = 1``, so ``kappa_c = (lam + 2 mu)/2``.
"""
import math
import warnings

import numpy as np
import pytest
import scipy.sparse as sp
from scipy.integrate import simpson, solve_bvp
from scipy.sparse.linalg import spsolve

from pyfrustrate import continuum

EPS, MU = 1.0, 1.0


def moduli(nu):
    lam = 2.0 * MU * nu / (1.0 - nu)
    return lam, (lam + 2.0 * MU) / 2.0  # kappa_c for ell = 1


def sheet_density(lam, du, dv, exx, eyy):
    """Eq. (4) density of one sheet with principal displacement gradients du, dv and rest
    strains exx = eyy = +-eps (no shear in the fibre and disk geometries)."""
    return lam / 2.0 * (du + dv - exx - eyy) ** 2 + MU * ((du - exx) ** 2 + (dv - eyy) ** 2)


def bulk_density(nu):
    lam, _ = moduli(nu)
    return 2.0 * sheet_density(lam, 0.0, 0.0, EPS, EPS)  # u = 0: both sheets, no coupling


# --------------------------------------------------------------------------------------------
# Reference 1: Euler-Lagrange equations of Eq. (4) with natural boundary conditions
# --------------------------------------------------------------------------------------------

def fiber_bvp(w, nu):
    """Strip |x| < w/2, both sheets, plus the uniform longitudinal strain phi (u_y = phi y) as an
    unknown parameter fixed by dE/dphi = 0, i.e. zero total longitudinal tension T(w/2)."""
    lam, kap = moduli(nu)
    pw = lam + 2.0 * MU

    def sxx(du, phi, e):  # dE/d(u'): zero at a free edge
        return lam * (du + phi - 2.0 * e) + 2.0 * MU * (du - e)

    def rhs(x, y, p):
        phi = p[0]
        syy = (lam * (y[1] + phi - 2 * EPS) + 2 * MU * (phi - EPS)
               + lam * (y[3] + phi + 2 * EPS) + 2 * MU * (phi + EPS))
        return np.vstack([y[1], kap * (y[0] - y[2]) / pw, y[3], kap * (y[2] - y[0]) / pw, syy])

    def bc(ya, yb, p):
        # The sum of both edge stresses is conserved, so three stress conditions suffice; the
        # fourth row fixes the common translation (a zero mode of Eq. 4).
        return np.array([sxx(ya[1], p[0], EPS), sxx(yb[1], p[0], EPS),
                         sxx(ya[3], p[0], -EPS), ya[0] + ya[2] + yb[0] + yb[2], ya[4], yb[4]])

    x = np.linspace(-w / 2.0, w / 2.0, 41)
    sol = solve_bvp(rhs, bc, x, np.zeros((5, x.size)), p=[0.0], tol=1e-10, max_nodes=200000)
    assert sol.success, sol.message
    xs = np.linspace(-w / 2.0, w / 2.0, 20001)
    u, du, v, dv, _ = sol.sol(xs)
    phi = sol.p[0]
    dens = (sheet_density(lam, du, phi, EPS, EPS) + sheet_density(lam, dv, phi, -EPS, -EPS)
            + kap / 2.0 * (u - v) ** 2)
    assert abs(sxx(sol.sol(w / 2)[3], phi, -EPS)) < 1e-7
    return sol, simpson(dens, x=xs) / w, phi


def disk_bvp(r, nu):
    """Radial displacements of both sheets on [0, r]; states (u, theta = u' + u/rho) per sheet,
    regular at the centre through solve_bvp's singular term."""
    lam, kap = moduli(nu)
    pw = lam + 2.0 * MU
    S = np.diag([-1.0, 0.0, -1.0, 0.0])

    def srr(theta, u, rho, e):  # dE/d(u') = radial stress
        return lam * (theta - 2.0 * e) + 2.0 * MU * (theta - u / rho - e)

    def rhs(x, y):
        return np.vstack([y[1], kap * (y[0] - y[2]) / pw, y[3], kap * (y[2] - y[0]) / pw])

    def bc(ya, yb):
        return np.array([ya[0], ya[2], srr(yb[1], yb[0], r, EPS), srr(yb[3], yb[2], r, -EPS)])

    x = np.linspace(0.0, r, 41)
    sol = solve_bvp(rhs, bc, x, np.zeros((4, x.size)), S=S, tol=1e-10, max_nodes=200000)
    assert sol.success, sol.message
    rs = np.linspace(0.0, r, 20001)
    u, th, v, tv = sol.sol(rs)
    with np.errstate(invalid="ignore", divide="ignore"):
        uo, vo = np.where(rs > 0, u / rs, th / 2.0), np.where(rs > 0, v / rs, tv / 2.0)
    dens = (sheet_density(lam, th - uo, uo, EPS, EPS) + sheet_density(lam, tv - vo, vo, -EPS, -EPS)
            + kap / 2.0 * (u - v) ** 2)
    return sol, simpson(dens * 2.0 * np.pi * rs, x=rs) / (np.pi * r**2)


# Negative nu (auxetic sheets) down to -0.95: 2D elasticity allows nu > -1.
CASES = [(w, nu) for w in (0.4, 2.0, 7.0) for nu in (-0.95, -0.5, 0.0, 0.3, 0.99)]


@pytest.mark.parametrize("w, nu", CASES)
def test_fiber_matches_euler_lagrange_solution(w, nu):
    sol, e_num, phi = fiber_bvp(w, nu)
    e_ref = e_num / bulk_density(nu)
    err_e = abs(continuum.fiber_energy(w, nu, 0.0) / e_ref - 1.0)
    x = np.linspace(-w / 2.0, w / 2.0, 9)
    u = sol.sol(x)[0]
    err_u = np.max(np.abs(continuum.fiber_displacement(x, w, nu) - u)) / np.max(np.abs(u))
    print(f"fibre BVP w={w} nu={nu}: energy rel err {err_e:.1e}, displacement {err_u:.1e}, "
          f"phi {phi:.1e}")
    assert err_e < 1e-11 and err_u < 1e-11 and abs(phi) < 1e-11
    assert np.allclose(sol.sol(x)[2], -u, atol=1e-8)  # u_down = -u_up


@pytest.mark.parametrize("r, nu", CASES)
def test_disk_matches_euler_lagrange_solution(r, nu):
    sol, e_num = disk_bvp(r, nu)
    err_e = abs(continuum.disk_energy(r, nu, 0.0) / (e_num / bulk_density(nu)) - 1.0)
    rho = np.linspace(0.0, r, 9)
    u = sol.sol(rho)[0]
    err_u = np.max(np.abs(continuum.disk_displacement(rho, r, nu) - u)) / np.max(np.abs(u))
    print(f"disk BVP r={r} nu={nu}: energy rel err {err_e:.1e}, displacement {err_u:.1e}")
    assert err_e < 1e-11 and err_u < 1e-11
    assert np.allclose(sol.sol(rho)[2], -u, atol=1e-8)


# --------------------------------------------------------------------------------------------
# Reference 2: direct minimisation of a finite-difference discretisation of Eq. (4)
# --------------------------------------------------------------------------------------------

def least_squares_energy(rows, ncols):
    """min_z sum_i w_i (a_i . z - b_i)^2 given rows (weight, {col: coef}, b): normal equations."""
    data, ri, ci, b = [], [], [], []
    for i, (wt, coefs, rhs) in enumerate(rows):
        sw = math.sqrt(wt)
        for col, val in coefs.items():
            ri.append(i), ci.append(col), data.append(sw * val)
        b.append(sw * rhs)
    A = sp.csr_matrix((data, (ri, ci)), shape=(len(rows), ncols))
    b = np.array(b)
    z = spsolve((A.T @ A).tocsc(), A.T @ b)
    return float(np.sum((A @ z - b) ** 2)), z


def fiber_fd(w, nu, n):
    """Midpoint rule on n intervals; unknowns u_up (n+1), u_down (n+1), phi."""
    lam, kap = moduli(nu)
    h, iphi, rows = w / n, 2 * n + 2, []
    for j in range(n):
        for off, e in ((0, EPS), (n + 1, -EPS)):
            grad = {off + j + 1: 1.0 / h, off + j: -1.0 / h}
            # mu (a^2 + b^2) + lam/2 (a + b)^2 (strains from rest a, b) written as positive
            # squares for every nu > -1: (lam + mu)/2 (a + b)^2 + mu/2 (a - b)^2.
            rows.append((h * (lam + MU) / 2, {**grad, iphi: 1.0}, 2 * e))
            rows.append((h * MU / 2, {**grad, iphi: -1.0}, 0.0))
        rows.append((h * kap / 2, {j: 0.5, j + 1: 0.5, n + 1 + j: -0.5, n + 2 + j: -0.5}, 0.0))
    rows.append((1.0, {0: 1.0, n: 1.0, n + 1: 1.0, 2 * n + 1: 1.0}, 0.0))  # translation gauge
    energy, z = least_squares_energy(rows, 2 * n + 3)
    return energy / (w * bulk_density(nu)), z[: n + 1]


def disk_fd(r, nu, n):
    """Midpoint rule on n radial intervals, u(0) = 0; unknowns u_up(rho_1..n), u_down(...)."""
    lam, kap = moduli(nu)
    h, rows = r / n, []
    for j in range(n):
        rm, wt = (j + 0.5) * h, 2.0 * np.pi * (j + 0.5) * h * h
        mids = []
        for off, e in ((-1, EPS), (n - 1, -EPS)):  # node i > 0 of a sheet is column off + i
            left = {off + j: 1.0} if j > 0 else {}
            grad = {**{k: -v / h for k, v in left.items()}, off + j + 1: 1.0 / h}
            mid = {**{k: v / 2 for k, v in left.items()}, off + j + 1: 0.5}
            hoop = {k: v / rm for k, v in mid.items()}
            both = {k: grad.get(k, 0.0) + hoop.get(k, 0.0) for k in {**grad, **hoop}}
            minus = {k: grad.get(k, 0.0) - hoop.get(k, 0.0) for k in {**grad, **hoop}}
            rows += [(wt * (lam + MU) / 2, both, 2 * e), (wt * MU / 2, minus, 0.0)]  # as fiber_fd
            mids.append(mid)
        diff = {k: mids[0].get(k, 0.0) - mids[1].get(k, 0.0) for k in {**mids[0], **mids[1]}}
        rows.append((wt * kap / 2, diff, 0.0))
    energy, z = least_squares_energy(rows, 2 * n)
    return energy / (np.pi * r**2 * bulk_density(nu)), np.concatenate([[0.0], z[:n]])


@pytest.mark.parametrize("geometry, size, nu", [("fiber", 3.0, 0.0), ("fiber", 1.5, 0.99),
                                                ("disk", 3.0, 0.0), ("disk", 1.5, 0.99),
                                                ("disk", 4.0, 0.45), ("fiber", 2.0, -0.7),
                                                ("disk", 2.0, -0.7)])
def test_finite_differences_converge_to_closed_forms(geometry, size, nu):
    solver, exact = {"fiber": (fiber_fd, continuum.fiber_energy),
                     "disk": (disk_fd, continuum.disk_energy)}[geometry]
    e_exact = float(exact(size, nu, 0.0))
    ns = (50, 100, 200, 400)
    results = [solver(size, nu, n) for n in ns]
    errs = np.array([abs(e / e_exact - 1.0) for e, _ in results])
    orders = np.log2(errs[:-1] / errs[1:])
    richardson = (4.0 * results[-1][0] - results[-2][0]) / 3.0
    err_rich = abs(richardson / e_exact - 1.0)
    grid = np.linspace(0.0, size, ns[-1] + 1) - (size / 2.0 if geometry == "fiber" else 0.0)
    disp = (continuum.fiber_displacement(grid, size, nu) if geometry == "fiber"
            else continuum.disk_displacement(grid, size, nu))
    err_u = np.max(np.abs(results[-1][1] - disp)) / np.max(np.abs(disp))
    print(f"FD {geometry} size={size} nu={nu}: rel errors {errs}, orders {orders}, "
          f"Richardson {err_rich:.1e}, displacement {err_u:.1e}")
    assert np.all((orders > 1.9) & (orders < 2.1))
    assert errs[-1] < 1e-5 and err_rich < 1e-9 and err_u < 1e-5


# --------------------------------------------------------------------------------------------
# Optimal sizes and the phase diagram
# --------------------------------------------------------------------------------------------

SIZES = np.logspace(-3, 4, 140001)
COARSE = np.logspace(-3, 4, 14001)


@pytest.mark.parametrize("nu, gamma", [(0.95, 0.5), (0.2, 0.5), (0.0, 1e-4), (0.3, 0.9),
                                       (0.0, 1.05), (0.45, 0.999), (0.7, 0.99), (-0.5, 0.5),
                                       (-0.9, 1.5), (-0.9, 3.5), (-0.3, 1e-4)])
@pytest.mark.parametrize("kind", ["fiber", "disk"])
def test_optimal_sizes_are_stationary_global_minima(nu, gamma, kind):
    energy, best = {"fiber": (continuum.fiber_energy, continuum.optimal_width),
                    "disk": (continuum.disk_energy, continuum.optimal_radius)}[kind]
    x = float(best(nu, gamma))
    brute = energy(SIZES, nu, gamma)
    if np.isinf(x):
        assert brute.min() >= 1.0 - 1e-15  # no finite size beats the bulk
        return
    e0 = float(energy(x, nu, gamma))
    d = 1e-4 * x
    slope = (energy(x + d, nu, gamma) - energy(x - d, nu, gamma)) / (2 * d)
    curvature = (energy(x + d, nu, gamma) - 2 * e0 + energy(x - d, nu, gamma)) / d**2
    scale = (1.0 + nu) * max(gamma, 1e-3) / x**2  # size of the two cancelling terms
    assert abs(slope) < 1e-6 * scale and curvature > 0
    assert e0 < 1.0 and brute.min() >= e0 - 1e-14
    assert abs(SIZES[np.argmin(brute)] / x - 1.0) < 2e-3


def test_fiber_width_diverges_at_gamma_one_and_vanishes_at_zero():
    assert continuum.optimal_width(0.3, 0.0) == 0.0 and continuum.optimal_radius(0.3, 0.0) == 0.0
    w = continuum.optimal_width(0.5, np.array([0.99, 0.999999, 1 - 1e-15, 1.0, 3.0]))
    assert np.all(np.diff(w[:3]) > 0) and np.all(np.isinf(w[3:]))
    assert np.all(continuum.phase(np.linspace(0.5, 1.0, 6), 0.999) == "fiber")


def brute_minima(nu, gamma, sizes=SIZES):
    ef = continuum.fiber_energy(sizes, nu, gamma).min()
    ed = continuum.disk_energy(sizes, nu, gamma).min()
    return min(ef, 1.0), min(ed, 1.0)


def test_disk_bulk_line_against_brute_force_and_triple_point():
    nus = np.array([-0.9, -0.5, 0.0, 0.25, 0.45, 0.49, 0.499, 0.4999, 0.5, 0.7, 1.0])
    crit = continuum.critical_line_tensions(nus)
    for nu, g in zip(nus, crit.disk_bulk):
        s = SIZES * (1.0 - continuum.disk_energy(SIZES, nu, 0.0)) / (1.0 + nu)  # 2 I1(r)/D(r)
        # Refined on a fine linear grid around the coarse maximum (sharp peaks at nu -> -1).
        i = int(np.argmax(s))
        fine = np.linspace(SIZES[max(i - 1, 0)], SIZES[min(i + 1, SIZES.size - 1)], 20001)
        s_fine = fine * (1.0 - continuum.disk_energy(fine, nu, 0.0)) / (1.0 + nu)
        assert g == pytest.approx(max(s.max(), s_fine.max(), 1.0), abs=1e-9)
    assert np.all(np.isnan(crit.disk_fiber[:2]))  # auxetic sheets: disks beat fibres outright
    crit = continuum.critical_line_tensions(nus[2:])
    nus = nus[2:]
    below = crit.disk_bulk[:6]
    assert np.all(below > 1.0) and np.all(np.diff(below) < 0) and below[-1] - 1.0 < 1e-6
    assert np.all(crit.disk_bulk[6:] == 1.0) and np.all(crit.fiber_bulk == 1.0)
    # Disks jump to infinite size at the transition; beyond nu = 1/2 they never beat the bulk.
    assert np.isfinite(continuum.optimal_radius(0.25, crit.disk_bulk[1] - 1e-9))
    assert np.isinf(continuum.optimal_radius(0.25, crit.disk_bulk[1] + 1e-9))
    assert np.all(np.isinf(continuum.optimal_radius(np.array([0.5, 0.6, 1.0]), 1.0)))
    assert np.all(continuum.phase(np.array([0.5, 0.6, 1.0]), 1.0) == "bulk")


def test_disk_fiber_line_meets_the_triple_point():
    nus = np.array([0.2, 0.35, 0.45, 0.47, 0.49, 0.499, 0.4999, 0.5, 0.6, 0.8, 0.95, 1.0])
    crit = continuum.critical_line_tensions(nus)
    lower, upper = crit.disk_fiber, crit.disk_fiber_upper
    assert np.all(np.isnan(lower[:2]) & np.isnan(upper[:2]))  # disks win outright at low nu
    assert np.all(np.diff(upper[2:7]) > 0) and 1.0 - upper[6] < 1e-6 and upper[7] == 1.0
    assert np.all(np.isnan(upper[8:])) and lower[-1] == 0.0 and np.all(np.diff(lower[2:]) < 0)
    # Each boundary separates disk from fibre: check with brute-force minima on both sides
    # (not within 1e-5 of the triple point, where the energy gaps drop below grid resolution).
    for nu, lo, up in zip(nus, lower, upper):
        for g, sign in ((lo, -1), (lo, 1), (up, -1), (up, 1)):
            if np.isnan(g) or g == 0.0 or g > 1.0 - 1e-5:
                continue
            gg = g + sign * 1e-7
            ef, ed = brute_minima(nu, gg)
            disk_wins = ed < ef
            expected = (sign < 0) if g == lo else (sign > 0)
            assert disk_wins == expected, (nu, g, sign)
            assert continuum.phase(nu, gg) == ("disk" if expected else "fiber")


@pytest.mark.parametrize("nu", [-0.9, -0.5, 0.0, 0.3, 0.46, 0.6, 0.9])
def test_phase_agrees_with_brute_force(nu):
    gammas = np.linspace(0.0, 1.15, 24)[1:]
    got = continuum.phase(nu, gammas)
    for g, p in zip(gammas, got):
        ef, ed = brute_minima(nu, g, COARSE)  # minima to ~1e-7: skip closer calls
        best = "bulk" if min(ef, ed) >= 1.0 else ("disk" if ed < ef else "fiber")
        if abs(ef - ed) > 1e-6 and abs(min(ef, ed) - 1.0) > 1e-6:
            assert p == best, (nu, g)


# --------------------------------------------------------------------------------------------
# Limits, extremes and numerical soundness
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("nu", [0.0, 0.4, 1.0])
@pytest.mark.parametrize("gamma", [0.0, 0.5])
def test_large_sizes_approach_bulk_with_edge_gain(nu, gamma):
    for x in (1e3, 1e4, 1e5):
        deficit = (1.0 + nu) * (1.0 - gamma) / x  # deformation gain (1+nu) ell e_bulk/2 per edge
        assert 1.0 - continuum.fiber_energy(x, nu, gamma) == pytest.approx(deficit, rel=1e-10)
        assert 1.0 - continuum.disk_energy(x, nu, gamma) == pytest.approx(deficit, rel=2.0 / x)
    assert continuum.fiber_energy(np.inf, nu, gamma) == 1.0
    assert continuum.disk_energy(np.inf, nu, gamma) == 1.0


def test_small_sizes_relax_fully():
    # A disk much smaller than ell relaxes both sheets completely; a thin fibre only across.
    x = 1e-6
    assert continuum.disk_energy(x, 0.3, 0.0) == pytest.approx(x**2 / (4 * 1.3), rel=1e-9)
    assert continuum.fiber_energy(x, 1.0, 0.0) == pytest.approx(x**2 / 12, rel=1e-9)
    assert continuum.fiber_energy(x, 0.2, 0.0) == pytest.approx(0.4, rel=1e-12)
    assert continuum.disk_displacement(x, x, 0.3) == pytest.approx(x, rel=1e-9)
    assert continuum.fiber_displacement(x / 2, x, 0.3) == pytest.approx(1.3 * x / 2, rel=1e-9)


@pytest.mark.parametrize("nu", [0.0, 1.0])
@pytest.mark.parametrize("size", [1e-6, 1e6])
@pytest.mark.parametrize("gamma", [0.0, 0.5, 2.0])
def test_extremes_are_finite_and_warning_free(nu, size, gamma):
    # Underflow to 0 (e.g. exp(-1e6)) is benign; overflow, 0/0 and x/0 are not.
    with warnings.catch_warnings(), np.errstate(over="raise", invalid="raise", divide="raise"):
        warnings.simplefilter("error")
        values = [continuum.fiber_energy(size, nu, gamma), continuum.disk_energy(size, nu, gamma),
                  continuum.fiber_displacement(np.array([-size / 2, 0.0, size / 2]), size, nu),
                  continuum.disk_displacement(np.array([0.0, size / 2, size]), size, nu),
                  continuum.optimal_width(nu, gamma), continuum.optimal_radius(nu, gamma),
                  continuum.phase(nu, gamma), continuum.critical_line_tensions(nu).disk_bulk]
    for v in values[:4]:
        assert np.all(np.isfinite(v))
    edge = values[2][-1]  # u(W/2)/(eps ell) = (1+nu) tanh(w/2)
    assert edge == pytest.approx((1 + nu) * math.tanh(size / 2), rel=1e-12)


def test_broadcasting_shapes():
    nu = np.linspace(0, 1, 3)[:, None]
    gamma = np.array([0.1, 0.5, 0.9, 1.2])
    for f in (continuum.optimal_width, continuum.optimal_radius, continuum.phase):
        assert f(nu, gamma).shape == (3, 4)
    assert continuum.fiber_energy(np.ones((2, 1, 1)), nu, gamma).shape == (2, 3, 4)
    assert continuum.critical_line_tensions(nu).disk_fiber.shape == (3, 1)


# --------------------------------------------------------------------------------------------
# Parameter mapping (supplement S1) and the 1D chain (main text Eqs. 1-3)
# --------------------------------------------------------------------------------------------

def test_bulk_energy_per_particle_from_particle_geometry():
    """Springs and triangle areas of one regular bulk hexagon, computed at finite eps."""
    k, k_area, eps = 1.3, 0.7, 1e-4
    spring = 3 * k / 2 * ((1 - (1 + eps)) ** 2 + (1 - (1 - eps)) ** 2)
    area0 = [math.sqrt(3) / 4 * (1 + e) ** 2 for e in (eps, -eps)]
    area = math.sqrt(3) / 4
    e_particle = spring + sum(k_area * (area - a0) ** 2 / (2 * a0) for a0 in area0)
    p = continuum.mapping(k, 0.1, k_area, 0.0, eps)
    assert p.e_bulk * math.sqrt(3) / 2 == pytest.approx(e_particle, rel=1e-6)


def test_mapping_values_and_limits():
    p = continuum.mapping(2.0, 0.05, 0.0, 0.3, 0.01)  # no areal term: spring network
    assert p.nu == pytest.approx(1 / 3) and p.lam == pytest.approx(p.mu)  # Cauchy relation
    assert p.ell == pytest.approx(math.sqrt((p.lam + 2 * p.mu) / (2 * p.kappa_c)))
    assert p.Gamma == pytest.approx(2 * p.gamma / ((1 + p.nu) * p.ell * p.e_bulk))
    assert p.gamma == continuum.line_tension(0.3) == 0.3 * continuum.LINE_TENSION_PER_BINDING_ENERGY
    q = continuum.mapping(1.0, np.array([0.0, 0.1]), np.array([[np.inf], [-math.sqrt(3) / 2]]),
                          0.2, 0.01)
    assert q.nu.shape == (2, 2) and np.all(q.nu[0] == 1.0) and np.all(q.Gamma[0] == 0.0)
    assert np.all(np.isinf(q.ell[0])) and np.isinf(q.ell[1, 0]) and q.Gamma[1, 0] == 0.0
    assert q.nu[1, 1] == pytest.approx(0.0, abs=1e-15)


@pytest.mark.parametrize("ell, nu, gamma", [(5.0, 0.2, 0.5), (2.5, 0.95, 0.9), (1.0, 0.0, 0.0),
                                             (10.0, -0.5, 1.2), (3.0, 1 / 3, 0.7)])
def test_mapping_round_trip(ell, nu, gamma):
    k, eps = 1.7, 0.02
    pp = continuum.particle_parameters(ell, nu, gamma, k=k, eps=eps)
    p = continuum.mapping(k, pp.kc, pp.k_area, pp.g, eps)
    assert (p.ell, p.nu, p.Gamma) == pytest.approx((ell, nu, gamma), rel=1e-12, abs=1e-15)
    assert continuum.binding_energy(continuum.line_tension(pp.g)) == pytest.approx(pp.g)


def relaxed_chain_shifts(x, n=40):
    """Relax the quadratic energy of main text Eq. (1) for n particles (k = 1, kc = x) by
    linear least squares and return the corner shifts delta_i = x_up_i - x_down_i."""
    eps, rows = 0.01, []
    up, dn = (lambda i: i), (lambda i: n + 1 + i)
    for i in range(n):
        rows.append((0.5, {up(i + 1): 1.0, up(i): -1.0}, 1 + eps))
        rows.append((0.5, {dn(i + 1): 1.0, dn(i): -1.0}, 1 - eps))
        rows.append((x / 4, {up(i + 1): 1.0, dn(i + 1): -1.0}, eps))
        rows.append((x / 4, {dn(i): 1.0, up(i): -1.0}, eps))
    rows.append((1.0, {up(0): 1.0}, 0.0))  # translation gauge
    _, z = least_squares_energy(rows, 2 * n + 2)
    return z[: n + 1] - z[n + 1:]


@pytest.mark.parametrize("x", [1e-3, 0.05, 1.0, 10.0])
def test_chain_ell_against_relaxed_chain_and_characteristic_roots(x):
    d = relaxed_chain_shifts(x)
    i = 3  # any interior corner obeys the linear recurrence exactly
    ell_relaxed = 1.0 / np.arccosh((d[i + 1] + d[i - 1]) / (2 * d[i]))
    # Force balance of Eq. (1): k (d_{i+1} - 2 d_i + d_{i-1}) = 2 kc d_i -> z^2 - 2(1+x) z + 1.
    ell_roots = 1.0 / np.log(np.max(np.abs(np.roots([1.0, -2.0 * (1.0 + x), 1.0]))))
    ell = continuum.chain_ell(x)
    print(f"chain x={x}: relaxed {abs(ell / ell_relaxed - 1):.1e}, "
          f"roots {abs(ell / ell_roots - 1):.1e}")
    assert ell == pytest.approx(ell_roots, rel=1e-12)
    assert ell == pytest.approx(ell_relaxed, rel=1e-10)


def test_chain_ell_limits():
    x = np.array([1e-12, 1e-8, 1e-4])
    assert np.allclose(continuum.chain_ell(x) * np.sqrt(2 * x), 1.0, rtol=np.sqrt(x))
    assert continuum.chain_ell(0.0) == np.inf and continuum.chain_ell(np.inf) == 0.0
    assert continuum.chain_ell(1e300) == pytest.approx(1 / math.log(2e300))


# --------------------------------------------------------------------------------------------
# Input validation
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("call, name", [
    (lambda: continuum.mapping(-1.0, 0.1, 0.0, 0.1, 0.01), "k"),
    (lambda: continuum.mapping(1.0, -0.1, 0.0, 0.1, 0.01), "kc"),
    (lambda: continuum.mapping(1.0, 0.1, -1.8, 0.1, 0.01), "k_area"),
    (lambda: continuum.mapping(1.0, 0.1, np.nan, 0.1, 0.01), "k_area"),
    (lambda: continuum.mapping(1.0, 0.1, 0.0, -0.1, 0.01), "g"),
    (lambda: continuum.mapping(1.0, 0.1, 0.0, 0.1, 0.0), "eps"),
    (lambda: continuum.mapping(1.0, 0.1, 0.0, 0.1, 1.0), "eps"),
    (lambda: continuum.particle_parameters(0.0, 0.3, 0.5), "ell"),
    (lambda: continuum.particle_parameters(2.0, 1.0, 0.5), "nu"),
    (lambda: continuum.particle_parameters(2.0, 0.3, -0.5), "Gamma"),
    (lambda: continuum.fiber_energy(0.0, 0.3, 0.5), "w"),
    (lambda: continuum.fiber_energy(1.0, 1.1, 0.5), "nu"),
    (lambda: continuum.fiber_energy(1.0, -1.0, 0.5), "nu"),
    (lambda: continuum.disk_energy(-1.0, 0.3, 0.5), "r"),
    (lambda: continuum.disk_energy(1.0, 0.3, -1e-3), "Gamma"),
    (lambda: continuum.disk_energy(1.0, np.nan, 0.5), "nu"),
    (lambda: continuum.fiber_displacement(0.6, 1.0, 0.3), "x"),
    (lambda: continuum.disk_displacement(1.1, 1.0, 0.3), "rho"),
    (lambda: continuum.optimal_width(0.3, np.nan), "Gamma"),
    (lambda: continuum.optimal_radius(2.0, 0.5), "nu"),
    (lambda: continuum.phase(0.3, -1.0), "Gamma"),
    (lambda: continuum.critical_line_tensions(-1.1), "nu"),
    (lambda: continuum.chain_ell(-1.0), "kc_over_k"),
    (lambda: continuum.line_tension(-1.0), "g"),
    (lambda: continuum.binding_energy(-1.0), "gamma"),
])
def test_invalid_input_raises_naming_the_parameter(call, name):
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        call()


def test_binding_conventions_count_the_bonds_of_their_cuts():
    # "measured": gamma = g, one edge of a cut along a lattice vector (cut 0) counted on the
    # lattice; "supplement": the printed gamma = 4 g / sqrt(3), the bonds a cut perpendicular to a
    # lattice vector (cut 1) breaks per unit length, over both its edges.
    from pyfrustrate import ansatz
    assert continuum.line_tension(1.0) == pytest.approx(ansatz.edge_line_tension(0))
    assert continuum.line_tension(1.0, convention="supplement") == pytest.approx(2 * ansatz.edge_line_tension(1))
    for convention in continuum.BINDING_CONVENTIONS:
        p = continuum.particle_parameters(5.0, 0.9, 0.5, eps=0.01, convention=convention)
        back = continuum.mapping(1.0, p.kc, p.k_area, p.g, 0.01, convention=convention)
        assert back.Gamma == pytest.approx(0.5) and back.ell == pytest.approx(5.0)
    # The paper's Gamma = 0.5 (supplement convention) is Gamma = 0.217 in ours.
    g_paper = continuum.particle_parameters(5.0, 0.9, 0.5, eps=0.01, convention="supplement")
    ours = continuum.mapping(1.0, g_paper.kc, g_paper.k_area, g_paper.g, 0.01)
    assert ours.Gamma == pytest.approx(0.5 * math.sqrt(3) / 4) and round(float(ours.Gamma), 3) == 0.217
    with pytest.raises(ValueError, match="convention"):
        continuum.line_tension(1.0, convention="printed")
    with pytest.raises(ValueError, match="hexagons"):
        continuum.particle_parameters(5.0, 0.9, 0.5, tiling="triangle", convention="supplement")
