"""Tests of the 2D particle model: ``Hexagon`` (one particle), the network energy of an
aggregate (``pyfrustrate.relax``) and its relaxation, against independent results.

References used here, none of them a copy of the code under test:

* the particle energy re-implemented term by term from the main text ("Two-dimensional
  particle model"): yellow/red triangles of springs k with rest sides 1 +- eps, six connecting
  springs kc at rest when the triangles are at rest and centred (their rest length is measured
  on the rest geometry), areal terms k_area (A - A0)^2 / (2 A0);
* central finite differences for gradients and Hessians;
* exact symmetries (rigid motions, the D3 point group of the particle lattice);
* the bulk energy per particle (3 k + sqrt(3) k_area) eps^2 (main text Eq. 8, checked by hand);
* the continuum theory (main text Eqs. 8-13 as corrected in pyfrustrate.continuum, itself tested
  against direct minimisations of Eq. 4 in test_continuum.py) for fibres and disks, whose
  agreement with the discrete model must improve as ell grows;
* the boundary-layer length ell of the mapping (Eq. 10), fitted on wide fibres.

Units: lattice spacing 1; energies per particle over ``particle.bulk_energy_per_particle``.
"""
import warnings

import numpy as np
import pytest
from scipy.optimize import curve_fit

import pyfrustrate
from pyfrustrate import continuum
from pyfrustrate import topology as T

from pyfrustrate.relaxation import energy as network_energy  # noqa: E402
from pyfrustrate.relaxation import particle_corners, particle_energies  # noqa: E402,F401

SQRT3 = np.sqrt(3.0)
SLOT_ANGLES = np.deg2rad(30 + 60 * np.arange(6))  # even slots red, odd slots yellow

FIBER_AXIS = {0: (1, 0), 1: (-1, 2), 2: (2, 1)}
FIBER_STEP = {0: (0, 1), 1: (-1, 1), 2: (-1, 0)}  # cross(axis, step) = 1: one site per lattice line
AXIS_LENGTH = {0: 1.0, 1: SQRT3, 2: np.sqrt(7.0)}


def make_fiber(width, cut, curved):
    """``topology.fiber(width, cut, curved)``; wide ones are built directly from their sites.

    Why: topology.fiber's connectivity check (_strip_is_connected) costs O(width^3) in Python
    (1.5 s at width 100, 26 s at width 320), which would dominate this file; the topology is the
    same (sites equal modulo the axis, checked for moderate widths in test_wide_fibre_helper).
    """
    if width <= 40:
        return T.fiber(width, cut, curved=curved)
    sites = np.outer(np.arange(width), FIBER_STEP[cut])
    return T.Topology("fiber", sites, "fiber", [FIBER_AXIS[cut], (0, 0)], curved=curved,
                      size=width * SQRT3 / 2 / AXIS_LENGTH[cut], label=f"fibre cut {cut} width {width}")


def curved_fiber_map(top):
    """(pivot, bend_scale) of a curved fibre's image map g(r) = R(theta) (r - pivot) + pivot + t,
    with the state holding bend_scale * theta (both default to the older convention 0, 1)."""
    return (np.asarray(getattr(top.kernel, "pivot", np.zeros(2)), float),
            float(getattr(top.kernel, "bend_scale", 1.0)))


def fiber_angle(top, state):
    """Angle between successive images of a curved fibre."""
    return state[-1] / curved_fiber_map(top)[1]


@pytest.mark.parametrize("cut", [0, 1, 2])
@pytest.mark.parametrize("width", [3, 12])
def test_wide_fibre_helper(cut, width):
    # make_fiber's direct construction gives the topology of topology.fiber.
    ref = T.fiber(width, cut, curved=True)
    sites = np.outer(np.arange(width), FIBER_STEP[cut])
    direct = T.Topology("fiber", sites, "fiber", [FIBER_AXIS[cut], (0, 0)], curved=True)
    assert (direct.n_particles, direct.n_bonds, direct.n_corners) == (ref.n_particles, ref.n_bonds, ref.n_corners)
    particle = pyfrustrate.Hexagon.from_continuum(2.0, 0.5, eps=1e-3)
    e_ref = pyfrustrate.relax(particle, ref, method="linear").energy
    assert pyfrustrate.relax(particle, direct, method="linear").energy == pytest.approx(e_ref, rel=1e-9)
    assert make_fiber(width, cut, True).size == pytest.approx(ref.size, rel=1e-14)


# --------------------------------------------------------------------------------------------
# Independent single-particle reference
# --------------------------------------------------------------------------------------------

def rest_corners(eps, angle=0.0, shift=(0.0, 0.0)):
    """(6, 2) rest shape: yellow triangle (odd slots) of side 1 + eps, red of side 1 - eps."""
    radius = np.where(np.arange(6) % 2 == 1, 1 + eps, 1 - eps) / SQRT3
    a = SLOT_ANGLES + angle
    return np.column_stack([radius * np.cos(a), radius * np.sin(a)]) + np.asarray(shift)


def reference_terms(c, k, kc, k_area, eps):
    """(triangles, connecting, area) energies of one particle with corners c (6, 2)."""
    c = np.asarray(c, float).reshape(6, 2)
    dist = lambda a, b: np.linalg.norm(c[a] - c[b])
    tri = 0.0
    for a, b in [(1, 3), (3, 5), (5, 1)]:
        tri += k / 2 * (dist(a, b) - (1 + eps)) ** 2
    for a, b in [(0, 2), (2, 4), (4, 0)]:
        tri += k / 2 * (dist(a, b) - (1 - eps)) ** 2
    rest = rest_corners(eps)
    con = sum(kc / 2 * (dist(s, (s + 1) % 6) - np.linalg.norm(rest[s] - rest[(s + 1) % 6])) ** 2
              for s in range(6))
    area = 0.0
    for (a, b, d), side in [((1, 3, 5), 1 + eps), ((0, 2, 4), 1 - eps)]:
        u, v = c[b] - c[a], c[d] - c[a]
        signed = 0.5 * (u[0] * v[1] - u[1] * v[0])
        a0 = SQRT3 / 4 * side**2
        area += k_area * (signed - a0) ** 2 / (2 * a0)
    return tri, con, area


PARTICLES = [  # (k, kc, k_area, eps)
    (1.0, 0.01, 0.0, 0.01),
    (2.0, 0.3, 1.5, 0.05),
    (1.0, 0.05, -1.2, 0.02),   # negative areal stiffness (nu < 1/3), allowed down to -sqrt(3) k
    (0.7, 1.3, 4.0, 0.2),      # kc > k, large mismatch
]


@pytest.mark.parametrize("k, kc, k_area, eps", PARTICLES)
def test_rest_shape_has_zero_energy_and_force(k, kc, k_area, eps):
    particle = pyfrustrate.Hexagon(k, kc, k_area, eps)
    for angle, shift in [(0.0, (0, 0)), (0.7, (3.0, -2.0))]:
        out = particle.evaluate(rest_corners(eps, angle, shift))
        for term in ("triangles", "connecting", "area", "energy"):
            assert abs(out[term]) < 1e-14 * k
        assert np.abs(out["gradient"]).max() < 1e-12 * k


@pytest.mark.parametrize("k, kc, k_area, eps", PARTICLES)
def test_particle_energy_terms_match_the_model(k, kc, k_area, eps, rng):
    particle = pyfrustrate.Hexagon(k, kc, k_area, eps)
    for _ in range(5):
        c = rest_corners(eps, rng.uniform(0, 2 * np.pi)) + 0.1 * rng.standard_normal((6, 2))
        out = particle.evaluate(c)
        tri, con, area = reference_terms(c, k, kc, k_area, eps)
        assert out["triangles"] == pytest.approx(tri, rel=1e-12, abs=1e-16)
        assert out["connecting"] == pytest.approx(con, rel=1e-12, abs=1e-16)
        assert out["area"] == pytest.approx(area, rel=1e-12, abs=1e-16)
        assert out["energy"] == pytest.approx(tri + con + area, rel=1e-12, abs=1e-16)
        # Both input shapes are accepted.
        assert particle.evaluate(c.ravel())["energy"] == out["energy"]


def _isolated_term(term, k, kc, k_area, eps):
    """(energy of one term, gradient and Hessian of that term alone) as functions of corners.

    k > 0 is required, so the connecting and areal terms are isolated as differences between
    two particles that differ only in that stiffness (kc or k_area set to zero)."""
    full = pyfrustrate.Hexagon(k, kc if term != "area" else 0.0, k_area if term == "area" else 0.0, eps)
    bare = pyfrustrate.Hexagon(k, 0.0, 0.0, eps)

    def energy(c):
        return full.evaluate(c)[term]

    def derivatives(c):
        a, b = full.evaluate(c), bare.evaluate(c)
        if term == "triangles":
            return b["gradient"], b["hessian"]
        return a["gradient"] - b["gradient"], a["hessian"] - b["hessian"]
    return energy, derivatives


@pytest.mark.parametrize("term", ["triangles", "connecting", "area"])
@pytest.mark.parametrize("k, kc, k_area, eps", PARTICLES)
def test_gradient_and_hessian_of_each_term_match_finite_differences(term, k, kc, k_area, eps, rng, fd_gradient):
    if term == "area" and k_area == 0:
        pytest.skip("no areal term")
    energy, derivatives = _isolated_term(term, k, kc, k_area, eps)
    for amplitude in (0.05, 0.3):  # near rest, and far from it (the areal term is then strongly non-linear)
        c = (rest_corners(eps, rng.uniform(0, 2 * np.pi)) + amplitude * rng.standard_normal((6, 2))).ravel()
        grad, hess = derivatives(c)
        fd = fd_gradient(energy, c, 1e-6)
        scale = max(np.abs(fd).max(), 1e-3 * k * eps)
        np.testing.assert_allclose(grad, fd, rtol=0, atol=1e-7 * scale)
        # Hessian: central differences of the (exact) gradient, column by column.
        fd_h = np.column_stack([(derivatives(c + h)[0] - derivatives(c - h)[0]) / 2e-6
                                for h in 1e-6 * np.eye(12)])
        np.testing.assert_allclose(hess, hess.T, rtol=0, atol=1e-12 * np.abs(hess).max())
        np.testing.assert_allclose(hess, fd_h, rtol=0, atol=1e-6 * np.abs(fd_h).max())


# --------------------------------------------------------------------------------------------
# Network energy and gradient
# --------------------------------------------------------------------------------------------

def perturbed_state(top, rng, corner_noise=0.03, period_noise=0.02, theta=0.0):
    """Reference state with random corner displacements and period-map parameters."""
    x = top.reference_state().copy()
    nc = 2 * top.n_corners
    x[:nc] += corner_noise * rng.standard_normal(nc)
    n_period = x.size - nc
    if n_period:
        x[nc:nc + 2 if n_period < 4 else nc + 4] += period_noise * rng.standard_normal(2 if n_period < 4 else 4)
    if n_period == 3:  # curved fibre: a bent state exercises the rotation-angle degree of freedom
        x[-1] = theta * curved_fiber_map(top)[1]
    return x


NETWORKS = [
    ("cluster", lambda: T.cluster([(0, 0), (1, 0), (0, 1), (2, -1), (-1, 1), (3, 0)]), 0.0),
    ("disk", lambda: T.disk(2), 0.0),
    ("straight fibre cut 0", lambda: T.fiber(3, 0, curved=False), 0.0),
    ("curved fibre cut 0", lambda: T.fiber(3, 0, curved=True), 0.15),
    ("curved fibre cut 1", lambda: T.fiber(4, 1, curved=True), -0.1),
    ("curved fibre cut 2", lambda: T.fiber(3, 2, curved=True), 0.2),
    ("bulk", T.bulk, 0.0),
    ("periodic cell", lambda: T.periodic([(0, 0), (1, 0), (0, 1), (1, 1), (2, 1)], [(3, 0), (1, 2)]), 0.0),
    ("honeycomb", lambda: T.bulk_with_holes("honeycomb"), 0.0),
]


@pytest.mark.parametrize("name, make, theta", NETWORKS)
@pytest.mark.parametrize("k_area", [0.8, -0.9])
def test_network_gradient_matches_finite_differences(name, make, theta, k_area, rng, fd_gradient):
    top = make()
    particle = pyfrustrate.Hexagon(k=1.0, kc=0.07, k_area=k_area, eps=0.05)
    for _ in range(2):
        x = perturbed_state(top, rng, theta=theta)
        e, grad = network_energy(particle, top, x)
        assert grad.shape == x.shape
        fd = fd_gradient(lambda y: network_energy(particle, top, y)[0], x, 1e-6)
        np.testing.assert_allclose(grad, fd, rtol=0, atol=1e-7 * np.abs(fd).max())


@pytest.mark.parametrize("name, make, theta", NETWORKS)
def test_network_energy_is_the_sum_of_particle_energies(name, make, theta, rng):
    # Cross-check of the period map: the corners each particle sees, fed to the single-particle
    # evaluator, give the network energy.
    top = make()
    particle = pyfrustrate.Hexagon(k=1.0, kc=0.07, k_area=0.5, eps=0.05)
    x = perturbed_state(top, rng, theta=theta)
    e, _ = network_energy(particle, top, x)
    corners = particle_corners(particle, top, x)
    per_particle = [particle.evaluate(c)["energy"] for c in corners]
    np.testing.assert_allclose(particle_energies(particle, top, x), per_particle, rtol=1e-12, atol=1e-16)
    assert e == pytest.approx(sum(per_particle), rel=1e-12)
    # At the reference state every particle sees a regular hexagon of side 1/sqrt(3) about its
    # site (periodic images included).
    ref = particle_corners(particle, top, top.reference_state())
    sites = np.asarray(top.kernel.sites)
    site_xy = np.column_stack([sites[:, 0] + sites[:, 1] / 2, SQRT3 / 2 * sites[:, 1]])
    np.testing.assert_allclose(ref - site_xy[:, None, :], np.broadcast_to(rest_corners(0.0), ref.shape), atol=1e-12)


# --------------------------------------------------------------------------------------------
# Rigid motions and lattice symmetries
# --------------------------------------------------------------------------------------------

def rotation(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


def rigidly_moved(top, x, angle, shift):
    """The state moved by r -> Q r + c: corners rotated and shifted, period translations rotated.
    A curved fibre's image map g(r) = R (r - p) + p + t (R = R(theta), pivot p) becomes
    g'(r) = R (r - p) + p + t' with t' = Q t + (1 - R)(c + (Q - 1) p), since Q and R commute;
    its angle is unchanged."""
    q = rotation(angle)
    c = np.asarray(shift, float)
    y = x.copy()
    nc = 2 * top.n_corners
    y[:nc] = (x[:nc].reshape(-1, 2) @ q.T + c).ravel()
    rest = x.size - nc
    if rest >= 2:
        y[nc:nc + 2] = q @ x[nc:nc + 2]
    if rest == 3:
        pivot, _ = curved_fiber_map(top)
        r = rotation(fiber_angle(top, x))
        y[nc:nc + 2] += (np.eye(2) - r) @ (c + (q - np.eye(2)) @ pivot)
    if rest == 4:
        y[nc + 2:nc + 4] = q @ x[nc + 2:nc + 4]
    return y


@pytest.mark.parametrize("name, make, theta", NETWORKS)
def test_energy_is_invariant_under_rigid_motions(name, make, theta, rng):
    top = make()
    particle = pyfrustrate.Hexagon(k=1.0, kc=0.07, k_area=-0.4, eps=0.05)
    x = perturbed_state(top, rng, theta=theta)
    e, g = network_energy(particle, top, x)
    for angle, shift in [(0.3, (1.5, -2.0)), (2.0, (-7.0, 0.25)), (np.pi, (0.0, 0.0))]:
        y = rigidly_moved(top, x, angle, shift)
        e2, g2 = network_energy(particle, top, y)
        assert e2 == pytest.approx(e, rel=1e-11)
        # The forces on the corners rotate with the aggregate.
        nc = 2 * top.n_corners
        np.testing.assert_allclose(g2[:nc].reshape(-1, 2), g[:nc].reshape(-1, 2) @ rotation(angle).T,
                                   rtol=0, atol=1e-10 * np.abs(g).max())


def rotate_sites_120(s):
    """Lattice sites rotated by 120 degrees about a site: a1 -> a2 - a1, a2 -> -a1."""
    s = np.asarray(s)
    return np.column_stack([-s[:, 0] - s[:, 1], s[:, 0]])


def rotate_sites_60(s):
    """Lattice sites rotated by 60 degrees: a1 -> a2, a2 -> a2 - a1."""
    s = np.asarray(s)
    return np.column_stack([-s[:, 1], s[:, 0] + s[:, 1]])


def mirror_sites(s):
    """Mirror image through the vertical axis (x -> -x), which passes through yellow corners."""
    s = np.asarray(s)
    return np.column_stack([-s[:, 0] - s[:, 1], s[:, 1]])


# An asymmetric cluster with a weakly bound particle, so that symmetry is not trivially met.
ASYMMETRIC_CLUSTER = [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (-1, 2), (3, -1), (2, 1), (0, 2)]


def relaxed_energy(particle, sites, **kwargs):
    return pyfrustrate.relax(particle, T.cluster(sites), x0="linear", tol=1e-6, **kwargs).energy


@pytest.mark.parametrize("eps", [0.02, 0.005])
def test_d3_symmetry_of_the_particle_lattice(eps):
    # The yellow corners of a particle sit at 90, 210 and 330 degrees: rotations by 120 degrees
    # and mirrors through a yellow corner map every particle (and its colours) onto a particle of
    # the rotated site set, so the relaxed energies are equal. L-BFGS, warm-started at the linear
    # solution, reaches the same minimum to ~1e-13 relative.
    particle = pyfrustrate.Hexagon.from_continuum(3.0, 0.6, eps=eps)
    e = relaxed_energy(particle, ASYMMETRIC_CLUSTER)
    for transform in (rotate_sites_120, lambda s: rotate_sites_120(rotate_sites_120(s)), mirror_sites):
        assert relaxed_energy(particle, transform(ASYMMETRIC_CLUSTER)) == pytest.approx(e, rel=1e-9)


def test_60_degree_rotation_swaps_colours_odd_in_eps():
    # A 60-degree rotation maps yellow corners onto red ones: the rotated cluster is the original
    # one with the colours swapped, i.e. with eps -> -eps. The energy is even in eps only to
    # leading order, so the two energies differ, by a relative amount proportional to eps
    # (measured: -0.0425 eps for this cluster; the 180-degree rotation, 60 + 120, equals it).
    rel = []
    epss = np.array([0.02, 0.01, 0.005])
    for eps in epss:
        particle = pyfrustrate.Hexagon.from_continuum(3.0, 0.6, eps=eps)
        e = relaxed_energy(particle, ASYMMETRIC_CLUSTER)
        e60 = relaxed_energy(particle, rotate_sites_60(ASYMMETRIC_CLUSTER))
        e180 = relaxed_energy(particle, rotate_sites_60(rotate_sites_60(rotate_sites_60(ASYMMETRIC_CLUSTER))))
        assert e180 == pytest.approx(e60, rel=1e-9)
        rel.append(e60 / e - 1)
    rel = np.array(rel)
    assert np.all(np.abs(rel) > 1e-6)             # different ...
    assert np.all(np.abs(rel) < 0.1 * epss)       # ... but close: O(eps) relative
    slope = np.polyfit(np.log(epss), np.log(np.abs(rel)), 1)[0]
    assert slope == pytest.approx(1.0, abs=0.1)


def test_linear_solve_is_independent_of_the_orientation_of_the_site_set():
    # Regression (kernel/relax.hpp, fixed by projecting out rigid modes): the linear solve pinned corner 0 and one
    # coordinate of the corner farthest from it against rigid motions, so its solution carries a
    # linearised rotation that depends on the corner numbering; the reported energy is the full
    # non-linear energy of that state, in which a linearised rotation is not free. A rotated
    # copy of the same cluster (an identical physical problem) then gets a different energy:
    # measured +22 % at eps = 0.01 for the 120-degree copy of this cluster (L-BFGS: 1e-13).
    # (Even without the spurious rotation, the linear energy of this loosely bound cluster is
    # 15 % above the minimum at eps = 0.01.)
    particle = pyfrustrate.Hexagon.from_continuum(3.0, 0.6, eps=0.01)
    e = pyfrustrate.relax(particle, T.cluster(ASYMMETRIC_CLUSTER), method="linear").energy
    e120 = pyfrustrate.relax(particle, T.cluster(rotate_sites_120(ASYMMETRIC_CLUSTER)), method="linear").energy
    assert e120 == pytest.approx(e, rel=1e-6)


# --------------------------------------------------------------------------------------------
# Bulk
# --------------------------------------------------------------------------------------------

BULK_EPS = np.array([0.002, 0.005, 0.01, 0.02, 0.05])
# The relaxed bulk energy per particle is (3 k + sqrt(3) k_area) eps^2 (1 + O(eps^2)), the
# energy being even in eps. Measured: |relative deviation| = c eps^2 with c = 0.04 (k_area = 0),
# 0.2 (k_area = k), 0.8-0.9 (k_area = -k/2), i.e. fitted exponents of the absolute deviation
# 4.00 +- 0.003. We require an exponent >= 3.5 (the issue asks for O(eps^3) or better) and a
# relative deviation below BULK_REL_DEV_COEFF eps^2.
BULK_MIN_EXPONENT = 3.5
BULK_REL_DEV_COEFF = 2.0
BULK_CELLS = [
    ("one-site cell", T.bulk),
    ("2x2 cell", lambda: T.periodic([(0, 0), (1, 0), (0, 1), (1, 1)], [(2, 0), (0, 2)])),
    ("skewed 6-site cell", lambda: T.periodic([(i, j) for i in range(3) for j in range(2)], [(3, 0), (1, 2)])),
]


@pytest.mark.parametrize("name, make", BULK_CELLS)
@pytest.mark.parametrize("k, kc, k_area", [(1.0, 0.05, 0.0), (1.0, 0.05, 1.0), (2.0, 0.5, -1.0), (1.0, 0.01, -0.5)])
def test_bulk_energy_per_particle(name, make, k, kc, k_area):
    top = make()
    deviations = []
    for eps in BULK_EPS:
        particle = pyfrustrate.Hexagon(k, kc, k_area, eps)
        expected = (3 * k + SQRT3 * k_area) * eps**2
        assert particle.bulk_energy_per_particle == pytest.approx(expected, rel=1e-14)
        r = pyfrustrate.relax(particle, top, x0="linear", tol=1e-6)
        assert r.converged, r.status
        assert r.n_bonds == 3 * r.n_particles
        rel = r.energy_per_particle / expected - 1
        assert abs(rel) < BULK_REL_DEV_COEFF * eps**2
        deviations.append(abs(r.energy_per_particle - expected))
    exponent = np.polyfit(np.log(BULK_EPS), np.log(deviations), 1)[0]
    assert exponent >= BULK_MIN_EXPONENT


@pytest.mark.parametrize("name, make", BULK_CELLS[1:])
def test_larger_periodic_cells_have_the_bulk_energy_per_particle(name, make):
    # A larger cell could break the one-site periodicity; it does not lower the energy.
    particle = pyfrustrate.Hexagon.from_continuum(2.5, 0.7, eps=0.02)
    one = pyfrustrate.relax(particle, T.bulk(), x0="linear", tol=1e-6).energy_per_particle
    many = pyfrustrate.relax(particle, make(), x0="linear", tol=1e-6).energy_per_particle
    assert many == pytest.approx(one, rel=1e-8)


# --------------------------------------------------------------------------------------------
# Discrete aggregates against the continuum theory
# --------------------------------------------------------------------------------------------

# eps -> 0: the linear solve is exact up to relative O((eps ell)^2) (the shift between the
# triangles grows like eps ell); 1e-4 makes that negligible even at ell = 20.
CONTINUUM_EPS = 1e-4
ELLS = [2.5, 5.0, 10.0, 20.0]

# Deviation := relative error of the boundary-layer gain, (1 - e) / (1 - e_continuum) - 1, with
# e the energy per particle over the bulk value. Measured at nu in {0.1, 0.5, 0.9}, W/ell in
# {1, 2, 3}, ell = 2.5 .. 20 (deviation x ell^p, worst case):
#   straight cut-0 fibre: ~ 1/ell^2, ell^2 x dev <= 0.0072  (0.115 % at ell = 2.5)
#   curved cut-0 fibre (the continuum fibre is straight): ~ 1/ell^2, <= 0.92
#   cut-1 and cut-2 fibres (zig-zag and stepped edges): ~ 1/ell, ell x dev <= 0.56
#   disks, R/ell in {1, 2}: dev <= 6.9 % at ell = 2.5, <= 0.52 % at ell = 20; the hexagonal
#   aggregate is not a disk, so a shape term survives (its perimeter is 5 % longer at equal
#   area: the gain of large aggregates tends to 1.05 times the disk's, hence R <= 2 ell here).
# Bounds, with ~30 % margin:
DEVIATION_BOUND = {
    "cut 0 straight": lambda ell: 0.015 / ell**2,
    "cut 0 curved": lambda ell: 1.2 / ell**2,
    "cut 1": lambda ell: 0.75 / ell,
    "cut 2 curved": lambda ell: 0.75 / ell,
    "disk": lambda ell: 0.25 / ell + 0.008,
}


def continuum_case(kind, nu, size, ell):
    """(topology, continuum e/e_bulk) for an aggregate of continuum size ~ size * ell."""
    if kind == "disk":
        R = max(1, int(round(size * ell * np.sqrt(2 * np.pi / (3 * SQRT3)))))  # equal-area hexagon
        top = T.disk(R)
        return top, float(continuum.disk_energy(top.size / ell, nu, 0.0))
    cut = int(kind.split()[1])
    width = max(1, int(round(size * ell * AXIS_LENGTH[cut] / (SQRT3 / 2))))
    top = make_fiber(width, cut, curved="curved" in kind)
    return top, float(continuum.fiber_energy(top.size / ell, nu, 0.0))


def gain_deviation(kind, nu, size, ell, method="linear"):
    particle = pyfrustrate.Hexagon.from_continuum(ell, nu, eps=CONTINUUM_EPS)
    top, e_cont = continuum_case(kind, nu, size, ell)
    r = pyfrustrate.relax(particle, top, method=method)
    e = r.energy_per_particle / particle.bulk_energy_per_particle
    return (1 - e) / (1 - e_cont) - 1


CONTINUUM_CASES = [(kind, nu, size)
                   for kind in ("cut 0 straight", "cut 0 curved", "cut 1", "cut 2 curved")
                   for nu in (0.1, 0.5, 0.9) for size in (1, 2, 3)]
CONTINUUM_CASES += [("disk", nu, size) for nu in (0.1, 0.5, 0.9) for size in (1, 2)]


@pytest.mark.parametrize("kind, nu, size", CONTINUUM_CASES)
def test_aggregate_energies_converge_to_the_continuum(kind, nu, size):
    dev = np.array([gain_deviation(kind, nu, size, ell) for ell in ELLS])
    bound = np.array([DEVIATION_BOUND[kind](ell) for ell in ELLS])
    assert np.all(np.abs(dev) <= bound), f"deviations {dev} vs bounds {bound}"
    assert abs(dev[-1]) < abs(dev[0])


@pytest.mark.parametrize("kind, size", [("cut 0 curved", 2), ("disk", 1.5)])
def test_lbfgs_from_the_bulk_reference_agrees_with_the_linear_solve(kind, size):
    # The non-linear minimiser, started from the bulk reference (not from the linear solution),
    # lands on the same minimum: a cross-check of both methods at small eps. The linear energy
    # is that of an admissible state, hence an upper bound.
    ell, nu, eps = 5.0, 0.6, 1e-3
    particle = pyfrustrate.Hexagon.from_continuum(ell, nu, eps=eps)
    top, _ = continuum_case(kind, nu, size, ell)
    lin = pyfrustrate.relax(particle, top, method="linear")
    nonlin = pyfrustrate.relax(particle, top)
    assert nonlin.converged, nonlin.status
    assert nonlin.energy <= lin.energy * (1 + 1e-12)
    assert nonlin.energy == pytest.approx(lin.energy, rel=1e-3)


# --------------------------------------------------------------------------------------------
# Linear vs non-linear as eps -> 0
# --------------------------------------------------------------------------------------------

SCALING_EPS = np.array([0.02, 0.01, 0.005, 0.0025])
# (linear - lbfgs) / lbfgs ~ C eps^2: measured exponents 1.98-1.99 (disk R = 5, fibres of width
# 10, ell = 2.5 and 5, nu = 0.5 and 0.9), C = 3.5 .. 45.
SCALING_EXPONENT_TOL = 0.15


@pytest.mark.parametrize("make", [lambda: T.disk(5), lambda: T.fiber(10, 0), lambda: T.fiber(10, 1, curved=False)],
                         ids=["disk R=5", "curved fibre cut 0", "straight fibre cut 1"])
@pytest.mark.parametrize("ell, nu", [(5.0, 0.5), (2.5, 0.9)])
def test_linear_solve_error_scales_as_eps_squared(make, ell, nu):
    top = make()
    rel = []
    for eps in SCALING_EPS:
        particle = pyfrustrate.Hexagon.from_continuum(ell, nu, eps=eps)
        lin = pyfrustrate.relax(particle, top, method="linear")
        nonlin = pyfrustrate.relax(particle, top, x0="linear")
        assert nonlin.converged, nonlin.status
        rel.append((lin.energy - nonlin.energy) / nonlin.energy)
    rel = np.array(rel)
    assert np.all(rel > 0)  # the linear state is admissible: its energy is an upper bound
    exponent = np.polyfit(np.log(SCALING_EPS), np.log(rel), 1)[0]
    assert exponent == pytest.approx(2.0, abs=SCALING_EXPONENT_TOL)


# --------------------------------------------------------------------------------------------
# Boundary layer of a wide fibre
# --------------------------------------------------------------------------------------------

def fiber_profile(ell, nu, width_in_ell):
    """Cut-1 (mirror-symmetric) straight fibre of width W = width_in_ell * ell: particle
    centres x across the fibre (sorted), the shift (yellow minus red triangle centroid) along x,
    and the energy per particle over the bulk value."""
    particle = pyfrustrate.Hexagon.from_continuum(ell, nu, eps=CONTINUUM_EPS)
    top = make_fiber(int(round(2 * width_in_ell * ell)), 1, curved=False)  # W = width / 2 for cut 1
    r = pyfrustrate.relax(particle, top, method="linear")
    c = particle_corners(particle, top, r.state)
    shift = c[:, 1::2, :].mean(axis=1) - c[:, 0::2, :].mean(axis=1)
    x = c.mean(axis=1)[:, 0]  # the fibre axis (-a1 + 2 a2) is vertical
    order = np.argsort(x)
    e = particle_energies(particle, top, r.state) / particle.bulk_energy_per_particle
    return top, x[order], shift[order], e[order]


# Measured |fitted/ell - 1| from the sinh fit: 1.3 %, 0.4 %, 0.16 % (nu = 0.5) and 8.6 %,
# 3.1 %, 1.2 % (nu = 0.9) at ell = 3, 5, 8: a clean C / ell^2 with C <= 0.77.
DECAY_FIT_COEFF = 1.0
# Measured profile deviation from the continuum u_up - u_down = 2 eps ell
# (1 + nu) sinh(x/ell)/cosh(W/2 ell) (Eq. 9), max over the fibre over the max: 0.17 / ell.
PROFILE_DEV_COEFF = 0.25


@pytest.mark.parametrize("nu", [0.1, 0.5, 0.9])
@pytest.mark.parametrize("ell", [3.0, 5.0, 8.0])
def test_boundary_layer_shift_decays_over_ell(ell, nu):
    top, x, shift, _ = fiber_profile(ell, nu, 10)
    s = shift[:, 0]
    # Mirror symmetry: no shift along the fibre, an odd profile across it.
    assert np.abs(shift[:, 1]).max() < 1e-9 * np.abs(s).max()
    np.testing.assert_allclose(s, -s[::-1], atol=1e-9 * np.abs(s).max())
    xc = 0.5 * (x[0] + x[-1])
    inner = slice(2, -2)  # the two outermost rows on each side feel the discrete edge

    def model(x, a, length):
        return a * np.sinh((x - xc) / length)
    (a, length), _ = curve_fit(model, x[inner], s[inner], p0=(s[0] / np.sinh((x[0] - xc) / ell), 1.3 * ell))
    assert abs(length / ell - 1) <= DECAY_FIT_COEFF / ell**2
    continuum_shift = 2 * CONTINUUM_EPS * ell * continuum.fiber_displacement((x - xc) / ell, top.size / ell, nu)
    assert np.abs(s - continuum_shift).max() <= PROFILE_DEV_COEFF / ell * np.abs(continuum_shift).max()


# The excess energy per particle 1 - e(d) at distance d from the edge goes like
# a exp(-d/ell) - b exp(-2d/ell), so a log-linear fit overestimates ell unless it
# starts a few ell in; on a fibre of width 20 ell, fitted over 3 ell < d < 8 ell, measured
# ell_fit/ell - 1 = 1.0-1.2 % (nu = 0.1, 0.5), 9.2 %, 4.0 %, 2.1 % (nu = 0.9, ell = 3, 5, 8).
ENERGY_DECAY_TOL = 0.15


@pytest.mark.parametrize("nu", [0.1, 0.5, 0.9])
def test_boundary_layer_excess_energy_decays_over_ell(nu):
    errors = []
    for ell in (3.0, 8.0):
        _, x, _, e = fiber_profile(ell, nu, 20)
        d = x - x[0] + 0.25  # the edge line lies half a row (1/4) beyond the first row
        window = (d > 3 * ell) & (d < 8 * ell)
        assert np.all(1 - e[window] > 0)  # particles near the edge are less deformed
        fitted = -1 / np.polyfit(d[window], np.log(1 - e[window]), 1)[0]
        errors.append(fitted / ell - 1)
        assert abs(errors[-1]) < ENERGY_DECAY_TOL
    assert abs(errors[1]) <= abs(errors[0]) + 1e-3


# --------------------------------------------------------------------------------------------
# Zero-energy aggregates, curved fibres
# --------------------------------------------------------------------------------------------

# nu = 0.1 (k_area < 0) exercises the L-BFGS runaway reported in
# test_lbfgs_finds_the_local_minimum_for_negative_areal_stiffness.
ZERO_ENERGY_NU = [0.1, 0.5, 0.9]
ZERO_ENERGY_TOL = 1e-8  # energy per particle over the bulk value (measured <= 2.3e-11)


@pytest.mark.parametrize("nu", ZERO_ENERGY_NU)
@pytest.mark.parametrize("make", [lambda: T.disk(0), lambda: T.cluster([(4, -7)])], ids=["disk R=0", "lone site"])
def test_single_particle_relaxes_to_zero_energy(make, nu):
    particle = pyfrustrate.Hexagon.from_continuum(2.5, nu, eps=0.02)
    top = make()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pyfrustrate.ConvergenceWarning)
        r = pyfrustrate.relax(particle, top, max_iter=20_000)
    assert r.converged, r.status
    assert r.energy_per_particle < ZERO_ENERGY_TOL * particle.bulk_energy_per_particle
    # ... in its rest shape.
    c = r.positions[np.asarray(top.kernel.corners)[0]]
    yellow = [np.linalg.norm(c[a] - c[b]) for a, b in [(1, 3), (3, 5), (5, 1)]]
    red = [np.linalg.norm(c[a] - c[b]) for a, b in [(0, 2), (2, 4), (4, 0)]]
    np.testing.assert_allclose(yellow, 1.02, atol=1e-5)
    np.testing.assert_allclose(red, 0.98, atol=1e-5)


@pytest.mark.parametrize("nu", ZERO_ENERGY_NU)
def test_honeycomb_bulk_with_holes_is_stress_free_and_kagome_is_not(nu):
    # Honeycomb: no corner is shared by three particles, so every particle keeps its rest shape.
    # Kagome: triangles of three particles share corners, which frustrates them (measured
    # 0.2 .. 0.77 of the bulk energy per particle).
    particle = pyfrustrate.Hexagon.from_continuum(2.5, nu, eps=0.01)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pyfrustrate.ConvergenceWarning)
        honeycomb = pyfrustrate.relax(particle, T.bulk_with_holes("honeycomb"), max_iter=20_000)
    assert honeycomb.converged, honeycomb.status
    assert 0 <= honeycomb.energy_per_particle < ZERO_ENERGY_TOL * particle.bulk_energy_per_particle
    kagome = pyfrustrate.relax(particle, T.bulk_with_holes("kagome"), x0="linear")
    assert kagome.converged, kagome.status
    assert kagome.energy_per_particle > 0.1 * particle.bulk_energy_per_particle


@pytest.mark.parametrize("ell, nu", [(2.5, 0.5), (2.5, 0.9), (5.0, 0.7)])
@pytest.mark.parametrize("width", [4, 9])
def test_cut0_fibre_curves_and_cut1_fibre_stays_straight(ell, nu, width):
    particle = pyfrustrate.Hexagon.from_continuum(ell, nu, eps=0.01)
    curved = pyfrustrate.relax(particle, T.fiber(width, 0, curved=True), x0="linear")
    straight = pyfrustrate.relax(particle, T.fiber(width, 0, curved=False), x0="linear")
    assert curved.converged and straight.converged
    # Left-right asymmetric edges (yellow tips on one side, red on the other): bending pays.
    # Measured: 1.2 .. 23 % lower energy, |theta| = 1.2e-3 .. 8e-3 rad per lattice spacing.
    top = T.fiber(width, 0, curved=True)
    assert curved.energy < straight.energy * (1 - 1e-3)
    assert abs(fiber_angle(top, curved.state)) > 1e-4
    # The mirror-symmetric cut-1 fibre has no reason to bend: same energy as when held straight.
    sym_top = T.fiber(2 * width, 1, curved=True)
    sym = pyfrustrate.relax(particle, sym_top, x0="linear")
    sym_straight = pyfrustrate.relax(particle, T.fiber(2 * width, 1, curved=False), x0="linear")
    assert abs(fiber_angle(sym_top, sym.state)) < 1e-6
    assert sym.energy == pytest.approx(sym_straight.energy, rel=1e-8)


# --------------------------------------------------------------------------------------------
# Bad input, non-convergence, robustness
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, name", [
    ({"k": 0.0}, "k"), ({"k": -1.0}, "k"), ({"k": np.nan}, "k"),
    ({"kc": -0.01}, "kc"), ({"kc": np.inf}, "kc"),
    ({"k_area": -SQRT3}, "k_area"), ({"k_area": -2.0}, "k_area"), ({"k_area": np.nan}, "k_area"),
    ({"eps": 0.0}, "eps"), ({"eps": 1.0}, "eps"), ({"eps": -0.01}, "eps"), ({"eps": np.nan}, "eps"),
])
def test_bad_particle_parameters_raise_value_error_naming_them(kwargs, name):
    params = dict(k=1.0, kc=0.01, k_area=0.0, eps=0.01) | kwargs
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        pyfrustrate.Hexagon(**params)


def test_areal_stiffness_just_above_the_stability_limit_is_accepted():
    assert pyfrustrate.Hexagon(k=1.0, kc=0.01, k_area=-SQRT3 + 1e-9, eps=0.01).k_area > -SQRT3


@pytest.mark.parametrize("kwargs, name", [({"ell": 0.0, "nu": 0.5}, "ell"), ({"ell": np.inf, "nu": 0.5}, "ell"),
                                          ({"ell": 5.0, "nu": 1.0}, "nu"), ({"ell": 5.0, "nu": -1.0}, "nu")])
def test_bad_continuum_parameters_raise_value_error(kwargs, name):
    with pytest.raises(ValueError, match=name):
        pyfrustrate.Hexagon.from_continuum(**kwargs)


@pytest.mark.parametrize("kwargs, name", [
    ({"method": "bfgs"}, "method"),
    ({"tol": 0.0}, "tol"),
    ({"x0": "bulk"}, "x0"),
    ({"x0": np.zeros(5)}, "x0"),
    ({"x0": "nan"}, "x0"),
])
def test_bad_relax_arguments_raise_value_error_naming_them(kwargs, name):
    top = T.disk(1)
    if isinstance(kwargs.get("x0"), str) and kwargs["x0"] == "nan":
        x0 = top.reference_state()
        x0[3] = np.nan
        kwargs = {"x0": x0}
    with pytest.raises(ValueError, match=name):
        pyfrustrate.relax(pyfrustrate.Hexagon(), top, **kwargs)


def test_energy_of_a_wrong_state_raises_value_error():
    top = T.fiber(3, 0)
    with pytest.raises(ValueError, match=r"\bstate\b"):  # the Python argument's name, not the kernel's
        network_energy(pyfrustrate.Hexagon(), top, np.zeros(top.reference_state().size - 1))
    with pytest.raises(ValueError, match="non-finite"):
        network_energy(pyfrustrate.Hexagon(), top, np.full(top.reference_state().size, np.inf))


@pytest.mark.parametrize("method", ["lbfgs", "newton"])
def test_non_convergence_warns_and_is_reported(method):
    particle = pyfrustrate.Hexagon.from_continuum(5.0, 0.5, eps=0.01)
    with pytest.warns(pyfrustrate.ConvergenceWarning, match="maximum number of iterations"):
        r = pyfrustrate.relax(particle, T.disk(4), method=method, tol=1e-12, max_iter=1 if method == "newton" else 3)
    assert r.converged is False
    assert r.gradient_norm > 1e-5 * particle.k * particle.eps
    assert np.isfinite(r.energy) and np.all(np.isfinite(r.state))
    with warnings.catch_warnings():
        warnings.simplefilter("error", pyfrustrate.ConvergenceWarning)  # a converging run is silent
        assert pyfrustrate.relax(particle, T.disk(4)).converged


def test_converged_means_the_gradient_tolerance_was_met():
    # Regression: NLopt used to keep evaluating after the forced stop, and a later point of
    # lower energy replaced the converged state (1.6e-7 returned against a 1e-7 tolerance).
    particle = pyfrustrate.Hexagon.from_continuum(1.0, 0.9, eps=0.01)
    top = T.bulk_with_holes("kagome")
    r = pyfrustrate.relax(particle, top, x0="linear")
    _, g = network_energy(particle, top, r.state)
    assert r.gradient_norm == pytest.approx(np.abs(g).max(), rel=1e-12)
    assert r.converged
    assert r.gradient_norm <= 1e-5 * particle.force_scale


@pytest.mark.parametrize("amplitude", [0.3, 3.0])
def test_wildly_deformed_start_gives_a_finite_result(amplitude, rng):
    # Positive stiffnesses: every energy term is >= 0, so whatever the minimiser does the result
    # must be finite and non-negative; it either converges or says it did not.
    particle = pyfrustrate.Hexagon.from_continuum(3.0, 0.6, eps=0.01)
    for top in (T.disk(2), T.fiber(4, 0), T.bulk()):
        x0 = top.reference_state() + amplitude * rng.standard_normal(top.reference_state().size)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            r = pyfrustrate.relax(particle, top, x0=x0, max_iter=20_000)
        assert np.isfinite(r.energy) and r.energy >= 0 and np.all(np.isfinite(r.state))
        assert r.converged or any(issubclass(w.category, pyfrustrate.ConvergenceWarning) for w in caught)


@pytest.mark.parametrize("make", [lambda: T.disk(0), lambda: T.disk(3), lambda: T.fiber(6, 1, curved=False)],
                         ids=["single particle", "disk R=3", "straight fibre cut 1"])
def test_lbfgs_finds_the_local_minimum_for_negative_areal_stiffness(make):
    # Regression (kernel/minimize.cpp, fixed by eps-scaled variables): with k_area < 0 (nu < 1/3)
    # the energy is unbounded below far from the reference (the areal term ~ -|k_area| A^2 beats
    # the springs ~ k L^2 once triangles are large), so the physical state is a local minimum.
    # minimize_lbfgs multiplies the objective by 1e-4 / (tol k eps) (1e3 at the defaults and
    # eps = 0.01), which makes NLopt's first L-BFGS trial step move corners by ~10 lattice
    # spacings: the run escapes into the unbounded region and returns energies ~ -1e75 after
    # max_iter evaluations (20 s at the default max_iter), even for a single particle.
    particle = pyfrustrate.Hexagon.from_continuum(5.0, 0.1, eps=0.01)
    top = make()
    lin = pyfrustrate.relax(particle, top, method="linear")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pyfrustrate.ConvergenceWarning)
        r = pyfrustrate.relax(particle, top, max_iter=20_000)
    assert r.converged, r.status
    assert 0 <= r.energy <= lin.energy * (1 + 1e-12)


# --- method="newton": the nonlinear minimum by Newton steps with the reference stiffness ------

@pytest.mark.parametrize("nu", [0.2, 0.9])
@pytest.mark.parametrize("make", [lambda: T.disk(8), lambda: T.fiber(12, 0), lambda: T.fiber(12, 1), T.bulk],
                         ids=["disk", "fibre cut 0", "fibre cut 1", "bulk"])
def test_newton_reaches_the_lbfgs_minimum(nu, make):
    """Two different algorithms, one minimum: Newton with the fixed eps = 0 stiffness (falling
    back on L-BFGS where it stalls) and NLopt's L-BFGS agree to the tolerance."""
    particle = pyfrustrate.Hexagon.from_continuum(5.0, nu, eps=0.01)
    topo = make()
    newton = pyfrustrate.relax(particle, topo, method="newton", tol=1e-6)
    lbfgs = pyfrustrate.relax(particle, topo, method="lbfgs", tol=1e-6)
    assert newton.converged and newton.gradient_norm <= 1e-6 * particle.force_scale
    assert newton.energy == pytest.approx(lbfgs.energy, rel=1e-8)


def test_newton_is_a_few_steps_at_small_eps():
    particle = pyfrustrate.Hexagon.from_continuum(5.0, 0.5, eps=0.01)
    r = pyfrustrate.relax(particle, T.fiber(30, 1), method="newton")
    assert r.converged and r.iterations <= 12 and "newton" in r.status


def test_newton_rejects_a_start_and_respects_its_cap():
    particle = pyfrustrate.Hexagon.from_continuum(5.0, 0.5, eps=0.01)
    with pytest.raises(ValueError, match="x0"):
        pyfrustrate.relax(particle, T.disk(3), method="newton", x0="linear")
    with pytest.warns(pyfrustrate.ConvergenceWarning):
        r = pyfrustrate.relax(particle, T.disk(6), method="newton", tol=1e-12, max_iter=2)
    assert not r.converged and r.iterations <= 2


@pytest.mark.parametrize("method", ["linear", "newton"])
def test_energy_per_particle_does_not_depend_on_how_the_cell_is_written(method):
    """One fibre or bulk, two cells (one period vs six; one site vs six): the same energy per
    particle, also for the linear solve, whose rigid rotation is fixed by the period vector."""
    particle = pyfrustrate.Hexagon.from_continuum(5.0, 0.5, eps=0.01)
    long_fibre = np.array([(i, j) for i in range(6) for j in range(8)])
    pairs = [(T.fiber(8, 0, curved=False), T.Topology("fiber", long_fibre, "fiber", [(6, 0), (0, 0)])),
             (T.bulk(), T.periodic([(i, j) for i in range(3) for j in range(2)], [(3, 0), (0, 2)]))]
    for small, large in pairs:
        e_small = pyfrustrate.relax(particle, small, method=method).energy_per_particle
        e_large = pyfrustrate.relax(particle, large, method=method).energy_per_particle
        assert e_large == pytest.approx(e_small, rel=1e-10)


@pytest.mark.parametrize("make", [lambda: T.fiber(3, 0), lambda: T.fiber(4, 2), lambda: T.bulk_with_holes("kagome")],
                         ids=["curved cut 0", "curved cut 2", "bulk cell"])
def test_image_points_are_the_corners_the_energy_sees(make):
    """Drawing helpers place periodic images with ``Topology.image_points``: for every corner a
    particle takes from a neighbouring image, that map gives the position the energy used."""
    particle = pyfrustrate.Hexagon.from_continuum(2.5, 0.5, eps=0.04)
    topo = make()
    state = pyfrustrate.relax(particle, topo, x0="linear").state
    seen = particle_corners(particle, topo, state)
    corners = state[: 2 * topo.n_corners].reshape(-1, 2)
    checked = 0
    for p, (ids, images) in enumerate(zip(topo.kernel.corners, topo.kernel.images)):
        for slot, (c, (n1, n2)) in enumerate(zip(ids, images)):
            if n1 or n2:
                mapped = topo.kernel.image_points(state, corners[c][None, :], int(n1), int(n2))[0]
                np.testing.assert_allclose(mapped, seen[p, slot], atol=1e-12)
                checked += 1
    assert checked > 0
    with pytest.raises(ValueError, match="state"):
        topo.kernel.image_points(state[:-1], corners, 1, 0)
