"""The particle contract, checked for every particle model (``pyfrustrate.particles.Particle``;
the kernel's side in ``kernel/network.hpp``). A new model inherits these tests by joining
``MODELS``.

References are independent of the model's code: central finite differences for the gradient
and Hessian, rigid motions applied to corner positions, the symmetry group found from the
relaxed rest shape (a different computation from the declared group), and the linear solve
against the nonlinear minimum as eps -> 0.
"""
import numpy as np
import pytest

import pyfrustrate as pf
from pyfrustrate import _kernel, topology as T
from pyfrustrate.relaxation import particle_corners

MODELS = {
    "hexagon": lambda eps: pf.Hexagon(k=1.0, kc=0.02, k_area=0.3, eps=eps),
    "random": lambda eps: pf.RandomHexagon(pf.RandomHexagon.draw(5).M, eps=eps),
    "triangle": lambda eps: pf.Triangle(k=1.0, kc=0.02, k_area=0.3, eps=eps),
}
# Clusters with a bond and a ring of three or more particles, per tiling.
SMALL_CLUSTERS = {"hexagon": [(0, 0), (1, 0), (0, 1), (-1, 1)],
                  "triangle": [(0, 0, 0), (0, 0, 1), (1, 0, 0), (0, 1, 0), (1, 0, 1)]}


@pytest.fixture(params=sorted(MODELS))
def name(request):
    return request.param


def evaluator(name, eps=0.05):
    return MODELS[name](eps)._kernel_model


def energy(model, disp):
    return model.energy_of_displacement(np.asarray(disp, float))[0]


def test_every_model_meets_the_protocol(name):
    particle = MODELS[name](0.05)
    assert isinstance(particle, pf.Particle)
    model = particle._kernel_model
    assert model.tiling == particle.tiling
    assert model.corner_count == T.tiling_facts(particle.tiling)["corners"]
    assert model.rest_corners().shape == (2 * model.corner_count,)
    assert particle.force_scale > 0 and particle.bulk_energy_per_particle > 0


def test_gradient_and_hessian_match_finite_differences(name):
    model = evaluator(name)
    rng = np.random.default_rng(1)
    n = 2 * model.corner_count
    disp = 0.05 * rng.standard_normal(n)
    e, g, h = model.energy_of_displacement(disp)
    step = 1e-6
    g_fd = np.empty(n)
    h_fd = np.empty((n, n))
    for i in range(n):
        dp, dm = disp.copy(), disp.copy()
        dp[i] += step
        dm[i] -= step
        g_fd[i] = (energy(model, dp) - energy(model, dm)) / (2 * step)
        h_fd[:, i] = (model.energy_of_displacement(dp)[1] - model.energy_of_displacement(dm)[1]) / (2 * step)
    assert np.allclose(g, g_fd, rtol=1e-6, atol=1e-9 * np.abs(g).max())
    assert np.allclose(h, h_fd, rtol=1e-5, atol=1e-7 * np.abs(h).max())
    assert np.allclose(h, h.T, atol=1e-12)


def test_rest_shape_without_mismatch_is_at_rest(name):
    model = evaluator(name).without_mismatch()
    e, g, _ = model.energy_of_displacement(np.zeros(2 * model.corner_count))
    assert e < 1e-28
    assert np.abs(g).max() < 1e-14


def test_a_single_particle_relaxes_to_zero_energy(name):
    particle = MODELS[name](0.05)
    r = pf.relax(particle, T.disk(0, tiling=particle.tiling), tol=1e-12)
    assert r.energy < 1e-14 * particle.bulk_energy_per_particle


def test_rigid_motions_cost_nothing(name):
    model = evaluator(name)
    rng = np.random.default_rng(2)
    rest = model.rest_corners()
    disp = 0.03 * rng.standard_normal(rest.size)
    x = (rest + disp).reshape(-1, 2)
    for angle, shift in [(0.3, (0.0, 0.0)), (-2.0, (5.0, -3.0)), (np.pi, (0.5, 0.25))]:
        rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
        moved = x @ rot.T + np.array(shift)
        assert energy(model, moved.ravel() - rest) == pytest.approx(energy(model, disp), rel=1e-10)


def rest_shape_with_mismatch(particle):
    """The corners of a relaxed single particle about their centroid, turned (Kabsch) onto the
    orientation of the rest shape without mismatch: the rest shape with mismatch, whose corners
    of different colours no longer coincide."""
    top = T.disk(0, tiling=particle.tiling)
    r = pf.relax(particle, top, tol=1e-13)
    corners = particle_corners(particle, top, r.state)[0]
    corners = corners - corners.mean(axis=0)
    reference = particle._kernel_model.rest_corners().reshape(-1, 2)
    u, _, vt = np.linalg.svd(reference.T @ corners)
    return corners @ (u @ vt).T


def test_declared_point_group_is_exactly_the_symmetry_of_the_energy(name):
    """Among the twelve operations of the lattice's point group, find those that map the rest
    shape with mismatch onto itself (a permutation of the corners) and leave the energy of
    random deformations unchanged: they must be the declared group."""
    particle = MODELS[name](0.05)
    model = particle._kernel_model
    rest0 = model.rest_corners()
    shape = rest_shape_with_mismatch(particle)
    rng = np.random.default_rng(3)
    found = []
    for op in range(12):
        G = np.asarray(_kernel.point_operation_matrix(op))
        image = shape @ G.T
        distance = np.linalg.norm(image[:, None, :] - shape[None, :, :], axis=2)
        perm = distance.argmin(axis=1)  # corner k goes to corner perm[k]
        if distance.min(axis=1).max() > 1e-6 or len(set(perm)) != len(perm):
            continue
        invariant = True
        for _ in range(3):
            x = shape + 0.02 * rng.standard_normal(shape.shape)
            moved = np.empty_like(x)
            moved[perm] = x @ G.T
            e0 = energy(model, x.ravel() - rest0)
            invariant &= abs(energy(model, moved.ravel() - rest0) - e0) <= 1e-10 * e0
        if invariant:
            found.append(op)
    assert found == sorted(_kernel.point_group_operations(model.point_group))


def test_relaxed_energies_scale_as_eps_squared_and_the_linear_solve_becomes_exact(name):
    """Small clusters: E(eps)/eps^2 converges, and the linear solve (exact as eps -> 0) departs
    from the nonlinear minimum by O(eps)."""
    tiling = MODELS[name](0.01).tiling
    top = T.cluster(SMALL_CLUSTERS[tiling], tiling=tiling)
    gaps = []
    for eps in (1e-2, 1e-3):
        particle = MODELS[name](eps)
        nonlinear = pf.relax(particle, top, tol=1e-11).energy
        linear = pf.relax(particle, top, method="linear").energy
        gaps.append(abs(linear - nonlinear) / nonlinear)
        scaled = nonlinear / eps**2
        assert scaled > 0
    assert gaps[1] < gaps[0] / 5
    e1 = pf.relax(MODELS[name](1e-3), top, tol=1e-11).energy
    e2 = pf.relax(MODELS[name](2e-3), top, tol=1e-11).energy
    assert e2 / (4 * e1) == pytest.approx(1, abs=2e-2)


@pytest.mark.parametrize("spring_model", ["hexagon", "triangle"])
def test_reference_energy_is_even_in_eps(spring_model):
    """Spring particles: reversing eps swaps the yellow and red roles, a symmetry of their
    energy, so the energy of the reference shape is a_2 eps^2 + a_4 eps^4 + ...: successive
    differences of E/eps^2 at eps, 2 eps, 4 eps shrink fourfold (twofold with an odd term).
    (Random particles are not even: M couples the triangles' sides to the hexagon's, an eps^3
    term.)"""
    values = []
    for eps in (0.01, 0.02, 0.04):
        model = MODELS[spring_model](eps)._kernel_model
        values.append(energy(model, np.zeros(12)) / eps**2)
    assert (values[2] - values[1]) / (values[1] - values[0]) == pytest.approx(4, rel=0.05)


def test_tiling_slot_offsets_are_the_rest_shape_in_each_frame(name):
    """The tiling places corners (topology) and the model evaluates from its rest shape: the
    two views agree, sublattice by sublattice, once the rest shape is turned by the frame."""
    particle = MODELS[name](0.05)
    facts = T.tiling_facts(particle.tiling)
    rest = particle._kernel_model.rest_corners().reshape(-1, 2)
    for offsets, frame in zip(facts["slot_offsets"], facts["frames"]):
        assert np.allclose(np.asarray(offsets), rest @ np.asarray(frame).T, atol=1e-14)
