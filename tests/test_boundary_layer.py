"""Tests of the definitions of the boundary-layer length (pyfrustrate.boundary_layer).

Independent references: the kernel's sparse linear solve of a strip against the modes of the
transfer eigenproblem (the modal split must be exact); the mirror symmetry of the simple
particle (its two edges are equivalent); the batched palindromic polynomial for the slowest
mode; the simple particle's exact decay length for the paper's finite-depth protocol.
"""
import numpy as np
import pytest

import pyfrustrate
from pyfrustrate import boundary_layer as bl
from pyfrustrate import random_particles as rp


@pytest.fixture(scope="module")
def sample():
    return rp.elasticity_matrices(40, 11)


def simple_particle(ell=3.0, nu=0.5, eps=0.01):
    return rp.RandomHexagon.from_hexagon(pyfrustrate.Hexagon.from_continuum(ell, nu, eps))


def test_two_decaying_modes_and_the_slowest_is_the_batched_transfer_length(sample):
    exact = rp.boundary_layer_lengths(sample)
    for M, ell in zip(sample, exact):
        z = bl.decay_modes(M)
        assert np.all(np.abs(z) < 1) and abs(z[0]) >= abs(z[1])
        assert bl.decay_length(z[0]) == pytest.approx(ell, rel=1e-8)


def test_strip_response_is_exactly_the_two_modes_plus_uniform_strain(sample):
    # The strip is solved by the kernel's sparse Cholesky, the modes by a 16 x 16 eigenproblem:
    # the split can only be exact if both are right.
    for M in sample[:12]:
        modes = bl.edge_mode_shares(M)
        assert modes["residual"] < 1e-8
        assert np.allclose(modes["share"].sum(axis=1), 1.0)
        assert np.all((modes["share"] >= 0) & (modes["share"] <= 1))


def test_a_fit_with_the_wrong_decay_rates_leaves_a_residual(sample, monkeypatch):
    # The residual is a real check: perturb the rates and it grows by orders of magnitude.
    real = bl.decay_modes
    monkeypatch.setattr(bl, "decay_modes", lambda M: real(M) * 1.05)
    assert bl.edge_mode_shares(sample[0])["residual"] > 1e-4


def test_mirror_symmetric_particle_excites_its_modes_equally_at_both_edges():
    modes = bl.edge_mode_shares(simple_particle().M)
    assert np.allclose(modes["share"][0], modes["share"][1], atol=1e-7)


def test_excited_length_is_one_of_the_two_modes_and_the_slowest_for_a_tiny_share(sample):
    slowest = rp.boundary_layer_lengths(sample)
    for M, ell in zip(sample[:12], slowest):
        modes = bl.edge_mode_shares(M)
        assert bl.excited_boundary_layer_length(M, min_share=1e-12) == pytest.approx(ell, rel=1e-8)
        dominant = bl.excited_boundary_layer_length(M, min_share=0.5)
        assert any(dominant == pytest.approx(e, rel=1e-12) for e in modes["ell"])
        if abs(modes["z"][0].imag) < 1e-12 and modes["share"][:, 0].max() < 0.5:
            assert dominant == pytest.approx(modes["ell"][1], rel=1e-12)


def test_finite_depth_protocol_recovers_the_simple_particles_exact_length():
    # Far enough from the edge (the exp(-2 d / ell) part is 3e-3 at row 12), far from the other
    # edge (its tail is under 2 % of this edge's at row 22) and against the exact bulk, the paper's
    # fit must give back the slowest mode; fitted to the centre, the far edge's tail makes it long.
    particle = simple_particle(ell=3.0)
    exact = rp.boundary_layer_length(particle.M)
    window = bl.finite_depth_boundary_layer_length(particle.M, depth=60, reference="bulk", first_row=12, last_row=22)
    assert window == pytest.approx(exact, rel=0.02)
    to_centre = bl.finite_depth_boundary_layer_length(particle.M, depth=60, reference="bulk", first_row=8)
    assert to_centre > 1.03 * exact


def test_finite_depth_centre_reference_biases_a_shallow_slab_short():
    # Against its own central row, a slab only a few ell deep looks as if the excess decayed
    # faster than it does: the reference is not yet the bulk.
    particle = simple_particle(ell=3.0)
    exact = rp.boundary_layer_length(particle.M)
    assert bl.finite_depth_boundary_layer_length(particle.M, depth=10, reference="centre") < 0.9 * exact


@pytest.mark.parametrize("kwargs, message", [
    ({"depth": 4}, "depth"),
    ({"depth": 20, "reference": "middle"}, "reference"),
    ({"depth": 20, "first_row": 9}, "first_row"),
    ({"depth": 20, "last_row": 10}, "last_row"),
])
def test_finite_depth_protocol_rejects_bad_settings(sample, kwargs, message):
    with pytest.raises(ValueError, match=message):
        bl.finite_depth_boundary_layer_length(sample[0], **kwargs)


def test_excited_length_rejects_a_bad_share(sample):
    with pytest.raises(ValueError, match="min_share"):
        bl.excited_boundary_layer_length(sample[0], min_share=0.7)


def test_compare_definitions_and_summary_on_a_small_sample(sample):
    study = bl.compare_definitions(sample[:8], depths=(10,), min_shares=(0.1,))
    names = bl.definition_names(study)
    assert names == ["slowest", "excited_share0.1", "finite_depth10_bulk", "finite_depth10_centre"]
    assert np.allclose(study["slowest"], rp.boundary_layer_lengths(sample[:8]))
    table = bl.summarise(study)
    for row in table.values():
        assert 0 <= row["P_above"] <= 1 and row["median_ratio"] > 0
        assert sum(row[f"group{g}_fraction"] for g in range(3)) == pytest.approx(1 - row["not_decaying"])
    with pytest.raises(ValueError, match="Ms"):
        bl.compare_definitions(sample[0])
