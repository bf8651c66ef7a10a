"""The coupling pseudo-modulus kappa_c does not depend on the direction in which the two
triangles are shifted (supplement, Fig. S4: "a horizontal or a vertical shift of the two
triangles, although any intermediate direction is also allowed. Due to the three-fold symmetry
of the particle, all these shifting protocols are associated with the same modulus").

Independent of the package's constant ``PSEUDO_MODULUS_VECTORS["kappa_c"]``: each protocol's
distance change is computed here from its corner displacements (yellow corners moved by half
the shift, red corners back by the other half) through ``distance_jacobian``, and its
pseudo-modulus ``dd^T M dd / A_hex`` compared across directions for random matrices drawn as in
the supplement. A matrix without the three-fold symmetry gives direction-dependent values: the
equality is the symmetry's, not the vectors'.
"""
import numpy as np
import pytest

from pyfrustrate import random_particles as rp

YELLOW_SLOTS = np.arange(6) % 2 == 1  # odd slots yellow, even red (REST_CORNERS)


def shift_distances(angle_degrees: float) -> np.ndarray:
    """Change of the nine distances (to first order) when the yellow triangle moves by half a
    unit length in direction ``angle_degrees`` and the red one by half a unit the other way: a
    relative shift of one unit."""
    direction = np.array([np.cos(np.deg2rad(angle_degrees)), np.sin(np.deg2rad(angle_degrees))])
    displacement = np.where(YELLOW_SLOTS[:, None], 0.5, -0.5) * direction
    return rp.distance_jacobian() @ displacement.ravel()


def shift_modulus(M, angle_degrees: float) -> np.ndarray:
    dd = shift_distances(angle_degrees)
    return np.einsum("i,...ij,j->...", dd, M, dd) / rp.HEXAGON_AREA


def test_the_horizontal_shift_is_the_packages_kappa_c_protocol():
    np.testing.assert_allclose(shift_distances(0.0), rp.PSEUDO_MODULUS_VECTORS["kappa_c"], atol=1e-12)


def test_a_shift_changes_only_the_hexagon_sides_and_the_vertical_one_differently():
    # Each triangle moves rigidly: its own sides keep their lengths; only the three hexagon
    # sides joining a red to a yellow corner change, with a direction-independent norm.
    horizontal, vertical = shift_distances(0.0), shift_distances(90.0)
    for dd in (horizontal, vertical):
        np.testing.assert_allclose(dd[:6], 0.0, atol=1e-12)
        assert np.linalg.norm(dd) == pytest.approx(np.linalg.norm(horizontal), rel=1e-12)
    assert not np.allclose(np.abs(vertical), np.abs(horizontal))  # a different protocol, not a sign flip


@pytest.mark.parametrize("seed", [1, 2025])
def test_vertical_and_horizontal_shifts_give_the_same_kappa_c_for_random_particles(seed):
    M = rp.elasticity_matrices(6, seed)
    horizontal, vertical = shift_modulus(M, 0.0), shift_modulus(M, 90.0)
    assert np.all(horizontal > 0)
    np.testing.assert_allclose(vertical, horizontal, rtol=1e-10)
    np.testing.assert_allclose(horizontal, rp.pseudo_moduli(M)["kappa_c"], rtol=1e-10)
    # ... and any direction in between
    np.testing.assert_allclose(shift_modulus(M, 37.0), horizontal, rtol=1e-10)


def test_without_three_fold_symmetry_the_shift_direction_matters(rng):
    A = rng.standard_normal((9, 9))
    M = A @ A.T  # symmetric positive definite, but not invariant under the 120-degree rotation
    assert abs(shift_modulus(M, 90.0) / shift_modulus(M, 0.0) - 1) > 1e-3
