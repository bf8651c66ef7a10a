"""Numerical soundness of the relaxations at the extremes of the parameters and sizes.

Every case asks for a tight tolerance (1e-10 of the force scale, 1e-12 where round-off allows)
and checks that the result is finite, converged (or not converged with its reason), and
physically right against an independent statement: another algorithm (L-BFGS against Newton),
the eps^2 scaling of the energy and its linear-response limit, the leading-order bulk energy, or
the edge energy of wide fibres converging with the width. Fast cases run by default; the large
ones (R = 100, width 1000) are marked slow (``bash scripts/test.sh -m slow``).
"""
import math
import warnings

import numpy as np
import pytest

import pyfrustrate as pf
from pyfrustrate import topology as T

TIGHT = 1e-10


def relax_quiet(particle, topo, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pf.ConvergenceWarning)
        return pf.relax(particle, topo, **kw)


def assert_sound(r, particle, tol=TIGHT):
    """Finite, and converged to tol, or stopped with its reason and close to it."""
    assert np.isfinite(r.energy) and np.all(np.isfinite(r.state)) and np.all(np.isfinite(r.displacement))
    assert r.energy >= 0
    if r.converged:
        assert r.gradient_norm <= tol * particle.force_scale
    else:
        assert "round-off" in r.status or "maximum" in r.status, r.status


@pytest.mark.parametrize("nu", [0.0, 0.5, 0.9, 1 - 1e-6, 1 - 1.7e-8])
def test_poisson_ratio_extremes_converge_and_agree_with_lbfgs(nu):
    # nu = 0: k_area = -sqrt(3)/2 k (negative areal stiffness); nu -> 1: k_area up to 1e8 k.
    p = pf.Hexagon.from_continuum(ell=5, nu=nu, eps=0.01)
    topo = T.disk(5)
    newton = pf.relax(p, topo, method="newton", tol=TIGHT)
    assert newton.converged, newton.status
    assert_sound(newton, p)
    lbfgs = pf.relax(p, topo, method="lbfgs", tol=TIGHT)
    assert lbfgs.converged, lbfgs.status
    assert lbfgs.energy == pytest.approx(newton.energy, rel=1e-9)


@pytest.mark.parametrize("margin, eps", [(0.1, 0.01), (0.01, 1e-4), (1e-3, 1e-6)])
def test_areal_stiffness_near_the_stability_limit(margin, eps):
    # k_area -> -sqrt(3) k: the sheet's Poisson ratio -> -1, its bulk modulus -> 0. Stable while
    # the margin exceeds the mismatch; Newton and L-BFGS then find the same minimum.
    p = pf.Hexagon(k=1.0, kc=0.01, k_area=-math.sqrt(3) * (1 - margin), eps=eps)
    for topo in (T.disk(4), T.bulk(), T.fiber(6, 0)):
        r = pf.relax(p, topo, method="newton", tol=TIGHT)
        assert r.converged, r.status
        assert_sound(r, p)
        lbfgs = relax_quiet(p, topo, method="lbfgs", tol=1e-8, x0="linear")
        assert lbfgs.energy == pytest.approx(r.energy, rel=1e-7)


def test_beyond_the_stability_limit_the_relaxation_says_so():
    # Margin below the mismatch: no minimum near the reference, the energy is unbounded below
    # (quartic area terms of negative stiffness against quadratic springs). A clear error, fast.
    p = pf.Hexagon(k=1.0, kc=0.01, k_area=-math.sqrt(3) * (1 - 1e-2), eps=0.01)
    for topo in (T.disk(4), T.bulk()):
        with pytest.raises(RuntimeError, match="escaped the physical minimum"):
            relax_quiet(p, topo, method="newton", tol=TIGHT)


@pytest.mark.parametrize("topo", [T.disk(6), T.fiber(12, 0), T.fiber(12, 1)], ids=lambda t: t.label)
def test_long_boundary_layers_kc_to_zero(topo):
    # ell = 1e3: kc ~ 1e-7 k, the connecting springs barely hold the lattice together.
    p = pf.Hexagon.from_continuum(ell=1e3, nu=0.5, eps=0.01)
    r = pf.relax(p, topo, method="newton", tol=TIGHT)
    assert r.converged, r.status
    assert_sound(r, p)
    lbfgs = pf.relax(p, topo, method="lbfgs", tol=TIGHT)
    assert lbfgs.energy == pytest.approx(r.energy, rel=1e-9)


@pytest.mark.parametrize("topo", [T.disk(4), T.fiber(10, 1), T.bulk()], ids=lambda t: t.label)
def test_energy_scales_as_eps_squared_down_to_1e_8(topo):
    # Stretches are formed from reference edges and displacement differences (elements.hpp):
    # forces keep their digits at eps = 1e-8, and tol 1e-12 is met there.
    reduced = {}
    for eps in (1e-8, 1e-6, 1e-4, 1e-2, 0.1, 0.3):
        p = pf.Hexagon.from_continuum(ell=5, nu=0.7, eps=eps)
        r = pf.relax(p, topo, method="newton", tol=1e-12 if eps < 0.1 else TIGHT)
        assert r.converged, (eps, r.status)
        assert_sound(r, p, tol=1e-12 if eps < 0.1 else TIGHT)
        reduced[eps] = r.energy / eps**2
    # E = eps^2 E2 + O(eps^4): the reduced energy is flat at small eps, and curves at large eps.
    for small in (1e-8, 1e-6):
        assert reduced[small] == pytest.approx(reduced[1e-4], rel=1e-6)
    assert abs(reduced[0.3] / reduced[1e-4] - 1) > 1e-3


def test_linear_response_is_the_eps_to_zero_limit():
    topo = T.fiber(8, 2)
    errors = []
    for eps in (1e-1, 1e-2, 1e-3):
        p = pf.Hexagon.from_continuum(ell=3, nu=0.6, eps=eps)
        exact = relax_quiet(p, topo, method="newton", tol=1e-12)
        assert_sound(exact, p, tol=1e-12)
        linear = pf.relax(p, topo, method="linear")
        errors.append((linear.energy - exact.energy) / exact.energy)
    # Relative error O(eps^2): a decade of eps gives two of error.
    assert errors[0] > errors[1] > errors[2] >= 0
    assert errors[1] / errors[2] == pytest.approx(100, rel=0.3)


@pytest.mark.parametrize("topo", [T.bulk(), T.bulk_with_holes("honeycomb"), T.bulk_with_holes("kagome"),
                                  T.bulk_with_holes("sqrt7")], ids=lambda t: t.label)
def test_bulk_and_holes_converge_to_1e_12(topo):
    p = pf.Hexagon.from_continuum(ell=5, nu=0.9, eps=0.01)
    r = pf.relax(p, topo, method="newton", tol=1e-12)
    assert r.converged, r.status
    assert_sound(r, p, tol=1e-12)


def test_bulk_energy_is_the_leading_order_value():
    # Main text Eq. 8: (3 k + sqrt(3) k_area) eps^2 per particle, to O(eps^4).
    for eps in (1e-3, 1e-5, 1e-8):
        p = pf.Hexagon.from_continuum(ell=5, nu=0.4, eps=eps)
        r = pf.relax(p, T.bulk(), tol=1e-12)
        assert r.converged, r.status
        assert r.energy_per_particle == pytest.approx(p.bulk_energy_per_particle, rel=10 * eps**2)


def test_curved_fibre_converges_to_1e_12_with_the_exact_hessian():
    p = pf.Hexagon.from_continuum(ell=5, nu=0.95, eps=0.05)
    topo = T.fiber(10, 1)
    r = pf.relax(p, topo, method="newton", tol=1e-12)
    assert r.converged, r.status
    assert pf.relaxation.fiber_curvature(topo, r.state) != 0


def test_lbfgs_never_stops_short_silently():
    # NLopt's L-BFGS ends on its own ftol/xtol/roundoff near 1e-7-1e-8 here; Newton finishes.
    p = pf.Hexagon.from_continuum(ell=5, nu=0.5, eps=0.01)
    for topo in (T.disk(12), T.fiber(20, 0)):
        r = pf.relax(p, topo, method="lbfgs", tol=1e-11)
        assert r.converged, r.status
        assert r.gradient_norm <= 1e-11 * p.force_scale
        if r.newton_steps:
            assert "then newton" in r.status and r.lbfgs_evaluations > 0


def test_stiffness_cache_is_reused_and_checked():
    topo = T.disk(6)
    cache = pf.StiffnessCache(topo)
    p1 = pf.Hexagon.from_continuum(ell=5, nu=0.5, eps=0.01)
    first = pf.relax(p1, topo, method="linear", cache=cache)
    # Another eps has the same eps = 0 stiffness: no refactorisation, and the same result as without a cache.
    p2 = pf.Hexagon.from_continuum(ell=5, nu=0.5, eps=0.02)
    again = pf.relax(p2, topo, method="newton", tol=1e-10, cache=cache)
    assert cache.reference_factorizations == 1
    assert again.energy == pytest.approx(pf.relax(p2, topo, method="newton", tol=1e-10).energy, rel=1e-12)
    assert first.energy == pytest.approx(pf.relax(p1, topo, method="linear").energy, rel=1e-13)
    # Another stiffness refactorises (numerically), on the same analysis.
    pf.relax(pf.Hexagon.from_continuum(ell=3, nu=0.5, eps=0.01), topo, method="linear", cache=cache)
    assert cache.reference_factorizations == 2
    with pytest.raises(ValueError, match="cache"):
        pf.relax(p1, T.disk(6), cache=cache)  # an equal but different topology object
    with pytest.raises(ValueError, match="cache"):
        pf.relax(p1, topo, cache="yes")


@pytest.mark.slow
def test_disk_of_radius_100():
    p = pf.Hexagon.from_continuum(ell=5, nu=0.5, eps=0.01)
    topo = T.disk(100)
    r = pf.relax(p, topo, method="newton", tol=TIGHT)
    assert r.converged, r.status
    assert_sound(r, p)
    # Far larger than ell: the energy per particle is the bulk value plus an edge term ~ 1/R.
    small = pf.relax(p, T.disk(50), method="newton", tol=TIGHT)
    excess = [(x.energy_per_particle / p.bulk_energy_per_particle - 1) for x in (small, r)]
    assert excess[1] == pytest.approx(excess[0] / 2, rel=0.1)


@pytest.mark.slow
@pytest.mark.parametrize("cut", [0, 1])
def test_fibres_of_width_1000_approach_the_edge_energy_limit(cut):
    p = pf.Hexagon.from_continuum(ell=5, nu=0.9, eps=0.01)
    bulk = pf.relax(p, T.bulk(), method="newton", tol=TIGHT).energy_per_particle  # exact, not Eq. 8's leading order
    edge = []
    for width in (250, 500, 1000):
        topo = T.fiber(width, cut)
        r = pf.relax(p, topo, method="newton", tol=TIGHT)
        assert r.converged, r.status
        assert_sound(r, p)
        # Energy of the two edges of one period: what the cell has beyond its particles' bulk energy.
        edge.append(r.energy - topo.n_particles * bulk)
    # Wide fibres: the excess over the bulk is carried by the two edges, independent of the width.
    assert edge[2] == pytest.approx(edge[1], rel=0.02)
    assert abs(edge[2] - edge[1]) <= abs(edge[1] - edge[0])


@pytest.mark.slow
def test_large_mismatch_and_stiff_areas_on_a_large_disk():
    # Strongly nonlinear: the exact Hessian stays indefinite far from the minimum, Newton hands
    # over to L-BFGS and finishes after it. Every step descends from the linear response.
    for nu, eps in ((1 - 1e-6, 0.01), (0.5, 0.3)):
        p = pf.Hexagon.from_continuum(ell=5, nu=nu, eps=eps)
        topo = T.disk(20)
        r = pf.relax(p, topo, method="newton", tol=TIGHT)
        assert r.converged, r.status
        assert_sound(r, p)
        assert r.energy <= pf.relax(p, topo, method="linear").energy


@pytest.mark.parametrize("eps", [1e-8, 1e-4, 0.05])
def test_random_particles_converge_to_1e_12(eps):
    # The random-elasticity particle forms its distances the same way: exact at small eps too.
    p = pf.RandomHexagon.draw(seed=3, index=1, eps=eps)
    for topo in (T.disk(5), T.fiber(8, 2)):
        r = pf.relax(p, topo, tol=1e-12)
        assert r.converged, (eps, topo.label, r.status)
        assert r.gradient_norm <= 1e-12 * p.force_scale
