"""Tests of the random-elasticity particle (main text Eq. 14, supplement S4-S7).

Independent references: finite differences; exact symmetries (rigid motions, the particle's
three-fold symmetry, which ties the kernel's distance order to the supplement's Omega); the
simple particle (``Hexagon``), whose linearised energy is a quadratic form in the distances and
must give back the same linear response, the continuum moduli of the mapping (supplement S1)
and the continuum boundary-layer length (Eq. 10); a direct L-BFGS minimisation of the bulk;
two algorithms for the transfer roots (companion pencil, scalar palindromic polynomial); the
paper's own protocol for ell (a fit of the edge energy profile of a relaxed strip).
"""
import warnings

import numpy as np
import pytest

import pyfrustrate
from pyfrustrate import ansatz
from pyfrustrate import random_particles as rp
from pyfrustrate import topology as T

SQRT3 = np.sqrt(3.0)


def rotated_120(corners):
    """The same deformed particle turned by 120 degrees about its centre: slot s takes the
    (rotated) corner of slot s - 2."""
    c = np.asarray(corners, float).reshape(6, 2)
    centre = c.mean(axis=0)
    R = np.array([[np.cos(2 * np.pi / 3), -np.sin(2 * np.pi / 3)], [np.sin(2 * np.pi / 3), np.cos(2 * np.pi / 3)]])
    return ((c[(np.arange(6) - 2) % 6] - centre) @ R.T + centre).ravel()


def deformed(rng, scale=0.05):
    return (rp.REST_CORNERS + scale * rng.standard_normal((6, 2))).ravel()


# --------------------------------------------------------------------------------------------
# Drawing M
# --------------------------------------------------------------------------------------------

def test_matrices_are_symmetric_positive_and_threefold():
    M = rp.elasticity_matrices(200, seed=3)
    np.testing.assert_allclose(M, np.swapaxes(M, 1, 2), atol=1e-12)
    assert np.linalg.eigvalsh(M).min() > -1e-10
    p = rp._rotation_permutation()
    np.testing.assert_allclose(M[:, p][:, :, p], M, atol=1e-12)
    # Omega acts on the three triples alike and has order 3.
    d = np.arange(9.0)
    np.testing.assert_array_equal(rp.rotate_distances(rp.rotate_distances(rp.rotate_distances(d))), d)


def test_matrices_depend_only_on_seed_and_index():
    whole = rp.elasticity_matrices(rp.MATRIX_CHUNK + 5, seed=7)
    piece = rp.elasticity_matrices(10, seed=7, start=rp.MATRIX_CHUNK - 5)
    np.testing.assert_array_equal(piece, whole[rp.MATRIX_CHUNK - 5:])
    assert not np.allclose(rp.elasticity_matrices(3, seed=8), whole[:3])
    np.testing.assert_array_equal(rp.RandomHexagon.draw(7, index=4).M, whole[4])


def test_bad_matrices_are_rejected_with_clear_errors():
    good = rp.elasticity_matrices(1, seed=1)[0]
    with pytest.raises(ValueError, match="M must have shape"):
        rp.RandomHexagon(np.eye(8))
    with pytest.raises(ValueError, match="symmetric"):
        rp.RandomHexagon(good + np.triu(np.ones((9, 9)), 1))
    with pytest.raises(ValueError, match="positive semi-definite"):
        rp.RandomHexagon(good - 2 * np.linalg.eigvalsh(good)[-1] * np.eye(9))
    bad = good.copy()
    bad[0, 0] = np.nan
    with pytest.raises(ValueError, match="finite"):
        rp.RandomHexagon(bad)
    with pytest.raises(ValueError, match="eps"):
        rp.RandomHexagon(good, eps=0)
    with pytest.raises(ValueError, match="n must be"):
        rp.elasticity_matrices(-1, seed=1)


# --------------------------------------------------------------------------------------------
# One particle
# --------------------------------------------------------------------------------------------

def test_energy_is_the_quadratic_form_of_the_distances(rng):
    p = rp.RandomHexagon.draw(11, eps=0.03)
    x = deformed(rng)
    c = x.reshape(6, 2)
    d = np.array([np.linalg.norm(c[b] - c[a]) for a, b in rp.DISTANCE_PAIRS])
    yellow, red = 1.03, 0.97
    d0 = np.r_[[yellow] * 3, [red] * 3, [np.sqrt((yellow**2 + red**2 - yellow * red) / 3)] * 3]
    out = p.evaluate(x)
    np.testing.assert_allclose(out["distances"], d, rtol=1e-14)
    np.testing.assert_allclose(out["energy"], 0.5 * (d - d0) @ p.M @ (d - d0), rtol=1e-12)


def test_gradient_and_hessian_match_finite_differences(rng):
    p = rp.RandomHexagon.draw(12, eps=0.05)
    x = deformed(rng)
    out = p.evaluate(x)
    h = 1e-6
    fd_grad = np.array([(p.evaluate(x + h * e)["energy"] - p.evaluate(x - h * e)["energy"]) / (2 * h) for e in np.eye(12)])
    fd_hess = np.array([(np.asarray(p.evaluate(x + h * e)["gradient"]) - np.asarray(p.evaluate(x - h * e)["gradient"])) / (2 * h)
                        for e in np.eye(12)])
    np.testing.assert_allclose(out["gradient"], fd_grad, atol=1e-7 * np.abs(fd_grad).max())
    np.testing.assert_allclose(out["hessian"], fd_hess, atol=1e-6 * np.abs(fd_hess).max())


def test_energy_is_invariant_under_rigid_motions_and_the_particles_threefold_rotation(rng):
    p = rp.RandomHexagon.draw(13, eps=0.05)
    x = deformed(rng, 0.1)
    e = p.evaluate(x)["energy"]
    a = 0.7
    R = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    moved = (x.reshape(6, 2) @ R.T + [3.0, -2.0]).ravel()
    np.testing.assert_allclose(p.evaluate(moved)["energy"], e, rtol=1e-12)
    # The shape turned by 120 degrees costs the same: the kernel's distance order and Omega agree.
    np.testing.assert_allclose(p.evaluate(rotated_120(x))["energy"], e, rtol=1e-12)
    # ... while a mirror image in general does not (M has no mirror symmetry).
    mirrored = x.reshape(6, 2)[[1, 0, 5, 4, 3, 2]] * [-1, 1]
    assert abs(p.evaluate(mirrored.ravel())["energy"] - e) > 1e-6 * e


def test_single_particle_relaxes_to_its_rest_shape():
    p = rp.RandomHexagon.draw(14, eps=0.02)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", pyfrustrate.ConvergenceWarning)
        r = pyfrustrate.relax(p, T.disk(0), tol=1e-9, max_iter=20_000)
    assert r.energy < 1e-12 * p.bulk_energy_per_particle
    d = p.evaluate(r.positions[np.asarray(T.disk(0).kernel.corners)[0]])["distances"]
    np.testing.assert_allclose(d[:6], [1.02] * 3 + [0.98] * 3, atol=1e-5)


@pytest.mark.parametrize("seed", [21, 22, 23])
def test_bulk_energy_closed_form_matches_a_full_minimisation(seed):
    p = rp.RandomHexagon.draw(seed, eps=0.01)
    r = pyfrustrate.relax(p, T.bulk(), x0="linear", tol=1e-8)
    assert r.converged
    np.testing.assert_allclose(r.energy_per_particle, p.bulk_energy_per_particle, rtol=1e-7)


# --------------------------------------------------------------------------------------------
# The simple particle as a random particle
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("nu", [0.1, 0.5, 0.9])
def test_simple_particle_in_distance_form_has_the_same_rest_hessian(nu):
    h = pyfrustrate.Hexagon.from_continuum(3.0, nu, eps=0.01)
    r = rp.RandomHexagon.from_hexagon(h)
    rest_h = pyfrustrate._kernel.HexagonModel(h.k, h.kc, h.k_area, 0.0).evaluate(rp.REST_CORNERS.ravel())["hessian"]
    rest_r = pyfrustrate._kernel.RandomHexagonModel(r.M, 0.0).evaluate(rp.REST_CORNERS.ravel())["hessian"]
    np.testing.assert_allclose(rest_r, rest_h, atol=1e-12 * np.abs(rest_h).max())


@pytest.mark.parametrize("make", [lambda: T.disk(3), lambda: T.fiber(6, 1), lambda: T.fiber(5, 0), lambda: T.bulk()],
                         ids=["disk", "fibre cut 1", "fibre cut 0", "bulk"])
def test_simple_particle_in_distance_form_has_the_same_linear_response(make):
    # Same stiffness, same mismatch forcing to first order in eps: energies agree to O(eps^2).
    top = make()
    for eps, tol in ((1e-2, 2e-3), (1e-3, 2e-5)):
        h = pyfrustrate.Hexagon.from_continuum(2.5, 0.7, eps=eps)
        r = rp.RandomHexagon.from_hexagon(h)
        eh = pyfrustrate.relax(h, top, method="linear").energy
        er = pyfrustrate.relax(r, top, method="linear").energy
        assert abs(er / eh - 1) < tol


@pytest.mark.parametrize("nu", [0.2, 0.5, 0.8])
def test_pseudo_moduli_of_the_simple_particle_give_the_continuum_moduli(nu):
    # kappa_c and K exactly; the decoupled-triangle Poisson ratio and ell_pred up to O(kc/k)
    # (the three hexagon sides outside d bring connecting-spring terms into the triangle blocks;
    # measured nu_up - nu = -(0.17 .. 0.29) kc/k, ell_pred / ell - 1 = (0.05 .. 0.11) kc/k).
    for ell in (5.0, 20.0):
        h = pyfrustrate.Hexagon.from_continuum(ell, nu, eps=0.01)
        c = h.continuum
        m = rp.RandomHexagon.from_hexagon(h).moduli
        np.testing.assert_allclose(m["kappa_c"], c.kappa_c, rtol=1e-10)
        np.testing.assert_allclose(m["K"], c.lam + c.mu, rtol=1e-10)
        kc_over_k = h.kc / h.k
        assert abs(m["nu_up"] - nu) < 0.5 * kc_over_k and abs(m["nu_down"] - nu) < 0.5 * kc_over_k
        assert abs(m["ell_pred"] / ell - 1) < 0.5 * kc_over_k


# --------------------------------------------------------------------------------------------
# Boundary-layer length
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("nu", [0.1, 0.5, 0.9])
def test_transfer_length_of_the_simple_particle_tends_to_the_continuum_ell(nu):
    # Measured ell_transfer / ell - 1 = 0.0104 / ell^2 at nu = 0.5: discreteness, vanishing as ell grows.
    for ell in (1.0, 3.0, 10.0, 50.0):
        h = pyfrustrate.Hexagon.from_continuum(ell, nu, eps=0.01)
        hess = pyfrustrate._kernel.HexagonModel(h.k, h.kc, h.k_area, 0.0).evaluate(rp.REST_CORNERS.ravel())["hessian"]
        assert abs(rp.boundary_layer_length(hessian=hess) / ell - 1) < 0.05 / ell**2


def test_batched_transfer_lengths_equal_the_companion_eigenproblem():
    M = rp.elasticity_matrices(300, seed=31)
    one_by_one = np.array([rp.boundary_layer_length(m) for m in M])
    np.testing.assert_allclose(rp.boundary_layer_lengths(M), one_by_one, rtol=1e-8)
    # ell does not depend on the scale of M (only ratios of stiffnesses matter).
    np.testing.assert_allclose(rp.boundary_layer_lengths(7.5 * M), one_by_one, rtol=1e-8)


def _slowest_is_real_and_isolated(M):
    z = rp.transfer_roots(rp.rest_hessian(M))
    z = z[np.argsort(np.abs(z - 1))][4:]
    z = z[np.abs(z) < 1]
    z = z[np.argsort(-np.abs(z))]
    return abs(z[0].imag) < 1e-12 and z[0].real > 0 and np.log(abs(z[1])) < 1.5 * np.log(abs(z[0]))


def test_paper_protocol_fit_agrees_with_the_transfer_length():
    # The paper's route (fit of the edge energy profile of a relaxed strip, window 3-8 ell)
    # against the exact slowest mode, for particles whose slowest mode should dominate the
    # profile (real, decaying at least 1.5x more slowly than the next one). Measured on these
    # 130 particles: median +0.7 %, 97 % within 6 %; the rest fit short (down to -38 %), where
    # the edge barely excites the slowest mode and the window sees the next one.
    s = rp.sample_properties(400, seed=5)
    deviations = []
    for index in s["index"][(s["ell"] > 0.8) & (s["ell"] < 3)]:
        p = rp.RandomHexagon.draw(5, index=int(index), eps=1e-4)
        if _slowest_is_real_and_isolated(p.M):
            deviations.append(rp.fitted_boundary_layer_length(p) / p.boundary_layer_length - 1)
    deviations = np.array(deviations)
    assert len(deviations) > 100
    assert abs(np.median(deviations)) < 0.015
    assert np.mean(np.abs(deviations) < 0.06) > 0.93
    assert deviations.max() < 0.06  # a fit cannot see a decay slower than the slowest mode's
    h = pyfrustrate.Hexagon.from_continuum(5.0, 0.5, eps=1e-4)
    assert abs(rp.fitted_boundary_layer_length(rp.RandomHexagon.from_hexagon(h)) / 5.0 - 1) < 0.02


def test_sample_properties_are_reproducible_and_select_uniform_spreads_evenly():
    a = rp.sample_properties(50, seed=9, start=100)
    b = rp.sample_properties(50, seed=9, start=100)
    for k in rp.SAMPLE_FIELDS:
        np.testing.assert_array_equal(a[k], b[k])
    np.testing.assert_array_equal(a["index"], np.arange(100, 150))
    values = np.r_[np.linspace(0, 0.1, 500), np.linspace(0.1, 1, 50)]
    chosen = rp.select_uniform(values, 40, np.linspace(0, 1, 5), seed=1)
    assert len(np.unique(chosen)) == len(chosen) == 40
    counts = np.histogram(values[chosen], np.linspace(0, 1, 5))[0]
    np.testing.assert_array_equal(counts, [10, 10, 10, 10])


# --------------------------------------------------------------------------------------------
# Aggregation
# --------------------------------------------------------------------------------------------

def test_binding_energy_of_the_simple_particle_matches_the_ansatz_convention():
    h = pyfrustrate.Hexagon.from_continuum(2.5, 0.8, eps=1e-3)
    r = rp.RandomHexagon.from_hexagon(h)
    G = np.array([0.1, 0.5, 1.2])
    np.testing.assert_allclose(rp.binding_energy_of(r, 2.5, 0.8, G), ansatz.binding_energy_of(h, 2.5, 0.8, G), rtol=1e-5)
    with pytest.raises(ValueError, match="ell"):
        rp.binding_energy_of(r, -1.0, 0.5, G)
    with pytest.raises(ValueError, match="nu"):
        rp.binding_energy_of(r, 1.0, 1.0, G)


def test_aggregation_line_of_the_simple_particle_matches_its_ansatz_diagram():
    # The same particle through the Hexagon model and through its distance form: same winners
    # (up to O(eps^2) shifts of the boundaries: at most one grid point per boundary).
    ell, nu = 2.5, 0.7
    h = pyfrustrate.Hexagon.from_continuum(ell, nu, eps=1e-3)
    G = np.linspace(0, 1.6, 81)
    cands = rp.catalogue_for(ell)
    line = rp.aggregation_line(rp.RandomHexagon.from_hexagon(h), G, ell, nu, candidates=cands)
    table = ansatz.relax_catalogue(h, cands, method="linear")
    expected = [rp.PHASE_CODES.index(ansatz.FAMILY_PHASE[f]) for f in
                table.family[table.winners(ansatz.binding_energy_of(h, ell, nu, G))]]
    assert np.sum(line["phase"] != expected) <= 2
    assert set(line["phase"].tolist()) >= {rp.PHASE_CODES.index("fiber"), rp.PHASE_CODES.index("bulk")}


def test_gamma_max_is_where_the_bulk_starts_to_win():
    p = rp.RandomHexagon.draw(41, eps=1e-3)
    ell, nu = p.boundary_layer_length, p.moduli["nu"]
    line = rp.aggregation_line(p, np.array([0.0]), ell, nu)
    gm = line["Gamma_max"]
    around = rp.aggregation_line(p, np.array([0.999 * gm, 1.001 * gm]), ell, nu)
    assert around["phase"][0] != rp.PHASE_CODES.index("bulk")
    assert around["phase"][1] == rp.PHASE_CODES.index("bulk")


def test_strip_protocol_rejects_bad_settings():
    p = rp.RandomHexagon.draw(51, eps=1e-4)
    with pytest.raises(ValueError, match="width"):
        rp.edge_energy_profile(p, 4)
    with pytest.raises(ValueError, match="window"):
        rp.fitted_boundary_layer_length(p, window=(5.0, 2.0))
    with pytest.raises(ValueError, match="exactly one"):
        rp.boundary_layer_length()
    with pytest.raises(ValueError, match="Ms must have shape"):
        rp.boundary_layer_lengths(np.eye(9))


def test_aggregation_line_flags_sizes_at_the_catalogues_largest_member():
    """A size is flagged capped exactly when the best fibre (disk) is the catalogue's widest
    (largest) of its family: with a small catalogue the continuum optimum outgrows it as Gamma
    rises, with a large one it does not at small Gamma."""
    ell, nu = 2.5, 0.7
    p = rp.RandomHexagon.from_hexagon(pyfrustrate.Hexagon.from_continuum(ell, nu, eps=1e-3))
    G = np.array([0.05, 0.9])
    small = ansatz.catalogue(max_radius=2, max_width=3)
    line = rp.aggregation_line(p, G, ell, nu, candidates=small)
    big = rp.aggregation_line(p, G, ell, nu, candidates=ansatz.catalogue(max_radius=12, max_width=20))
    assert line["width_capped"][1] and line["radius_capped"][1]  # optimum beyond width 3, R = 2
    assert not big["width_capped"][0] and not big["radius_capped"][0]
    largest_disk = max(c.topology.size for c in small if c.family == "disk")
    assert line["radius"][1] == pytest.approx(largest_disk)


def test_line_tension_grid_is_even_then_geometric():
    G = rp.line_tension_grid(50.0, 321)
    assert G[0] == 0.0 and G[-1] == pytest.approx(50.0) and len(G) == 321
    assert np.all(np.diff(G) > 0)
    even = G[G <= 2.0]
    assert np.allclose(np.diff(even), even[1] - even[0])
    tail = G[G >= 2.0]
    assert np.allclose(tail[1:] / tail[:-1], tail[1] / tail[0])
    assert np.array_equal(rp.line_tension_grid(1.6, 161), np.linspace(0, 1.6, 161))
    for bad in (dict(Gamma_max=0.0, count=10), dict(Gamma_max=5.0, count=3)):
        with pytest.raises(ValueError, match="Gamma_max|count"):
            rp.line_tension_grid(**bad)
