"""The relaxation engine against independent results: the exact Hessian against finite
differences of the gradient, Newton against L-BFGS, the displacement form against the positions,
and the minimisers' reports (which did the work, why they stopped)."""
import numpy as np
import pytest

import pyfrustrate as pf
from pyfrustrate import _kernel
from pyfrustrate import topology as T
from pyfrustrate.random_particles import RandomHexagon

PARTICLES = {
    "hexagon": pf.Hexagon.from_continuum(ell=3, nu=0.7, eps=0.1),
    "hexagon k_area<0": pf.Hexagon.from_continuum(ell=3, nu=0.1, eps=0.05),
    "random": RandomHexagon.draw(seed=7, index=3, eps=0.05),
}
SCENES = [T.disk(2), T.fiber(4, 1), T.fiber(5, 2), T.fiber(4, 0, curved=False), T.bulk(),
          T.bulk_with_holes("kagome")]


@pytest.mark.parametrize("name", PARTICLES)
@pytest.mark.parametrize("topo", SCENES, ids=lambda t: t.label)
def test_exact_hessian_is_the_derivative_of_the_gradient(name, topo):
    # Away from equilibrium (random displacement, a bent fibre): the curvature of the period map
    # contracted with the forces is part of the Hessian, and is checked here with the rest.
    p = PARTICLES[name]
    rng = np.random.default_rng(3)
    n = topo.reference_state().size
    u = 0.02 * rng.standard_normal(n)
    if topo.curved:
        u[-1] = 0.4
    H = _kernel.hessian(p._kernel_model, topo.kernel, u, True).toarray()
    assert np.array_equal(H, H.T)
    step = 1e-6
    fd = np.empty((n, n))
    for i in range(n):
        e = np.zeros(n)
        e[i] = step
        plus = _kernel.energy_of_displacement(p._kernel_model, topo.kernel, u + e)[1]
        minus = _kernel.energy_of_displacement(p._kernel_model, topo.kernel, u - e)[1]
        fd[:, i] = (plus - minus) / (2 * step)
    assert np.abs(H - fd).max() <= 1e-7 * np.abs(fd).max()
    # Its Gauss-Newton part differs from it only where the period map is curved.
    gn = _kernel.hessian(p._kernel_model, topo.kernel, u, False).toarray()
    if topo.periodicity == "fiber" and topo.curved:
        assert np.abs(H - gn).max() > 1e-6 * np.abs(H).max()


@pytest.mark.parametrize("topo", SCENES, ids=lambda t: t.label)
def test_displacement_form_agrees_with_positions(topo):
    p = PARTICLES["hexagon"]
    rng = np.random.default_rng(5)
    x = topo.reference_state() + 0.03 * rng.standard_normal(topo.reference_state().size)
    e_x, g_x = pf.relaxation.energy(p, topo, x)
    e_u, g_u = _kernel.energy_of_displacement(p._kernel_model, topo.kernel, x - topo.reference_state())
    assert e_u == pytest.approx(e_x, rel=1e-14)
    assert np.abs(g_u - g_x).max() <= 1e-14


@pytest.mark.parametrize("name", PARTICLES)
@pytest.mark.parametrize("topo", [T.disk(5), T.fiber(10, 1), T.bulk_with_holes("sqrt7")], ids=lambda t: t.label)
def test_newton_and_lbfgs_find_the_same_minimum(name, topo):
    p = PARTICLES[name]
    newton = pf.relax(p, topo, method="newton", tol=1e-11)
    lbfgs = pf.relax(p, topo, method="lbfgs", tol=1e-11)
    assert newton.converged and lbfgs.converged
    assert newton.energy == pytest.approx(lbfgs.energy, rel=1e-10)
    assert np.allclose(newton.state, topo.reference_state() + newton.displacement, rtol=0, atol=1e-12)
    # The largest force reported is the one at the returned state.
    _, g = pf.relaxation.energy(p, topo, newton.state)
    assert np.abs(g).max() == pytest.approx(newton.gradient_norm, rel=1e-3, abs=1e-13)


def test_auto_is_newton_and_reports_its_work():
    p = PARTICLES["hexagon"]
    r = pf.relax(p, T.disk(6), tol=1e-10)
    assert r.method == "newton" and r.converged
    assert r.newton_steps >= 1 and r.lbfgs_evaluations == 0
    assert "newton" in r.status
    # With a start, auto means L-BFGS (Newton starts from the linear response).
    assert pf.relax(p, T.disk(6), x0="linear").method == "lbfgs"


def test_newton_refuses_a_start_and_bad_caches():
    with pytest.raises(ValueError, match="x0"):
        pf.relax(PARTICLES["hexagon"], T.disk(2), method="newton", x0="linear")
    with pytest.raises(ValueError, match="switch_ratio"):
        _kernel.relax_newton(PARTICLES["hexagon"]._kernel_model, T.disk(2).kernel, 1e-8, 100, None, False, 0.0)


@pytest.mark.parametrize("name", ["hexagon", "hexagon k_area<0"])
@pytest.mark.parametrize("R", [1, 2, 6, 15])
def test_vectorised_evaluation_gives_the_scalar_bits(name, R):
    # Finite networks of hexagons run eight particles per AVX-512 instruction where the processor
    # has it (the partial last batch included); the operations mirror the scalar loop's, so the
    # energy and every gradient component are equal to the last bit. (Without AVX-512 both runs
    # take the scalar loop.)
    p = PARTICLES[name]
    topo = T.disk(R)
    u = 0.03 * np.random.default_rng(R).standard_normal(topo.reference_state().size)
    e_scalar, g_scalar = _kernel.energy_of_displacement(p._kernel_model, topo.kernel, u, vectorised=False)
    e_vector, g_vector = _kernel.energy_of_displacement(p._kernel_model, topo.kernel, u, vectorised=True)
    assert e_vector == e_scalar
    assert np.array_equal(g_vector, g_scalar)


def test_threads_sharing_a_cache_take_turns():
    # Relaxations release the GIL; a shared StiffnessCache is locked per call, so concurrent
    # relaxations of one topology give exactly the results of sequential ones.
    from concurrent.futures import ThreadPoolExecutor

    topo = T.disk(8)
    cache = pf.StiffnessCache(topo)
    particles = [pf.Hexagon.from_continuum(5, 0.5, eps) for eps in (0.005, 0.01, 0.02, 0.03)] * 3
    expected = [pf.relax(p, topo, tol=1e-10).energy for p in particles]
    with ThreadPoolExecutor(max_workers=4) as pool:
        got = list(pool.map(lambda p: pf.relax(p, topo, tol=1e-10, cache=cache).energy, particles))
    assert got == expected


@pytest.mark.parametrize("eps", [1e-8, 1e-5, 0.02])
def test_energy_at_the_reference_state_is_exact_at_small_eps(eps):
    # Every particle at the regular (eps = 0) shape: triangle sides 1 against rest lengths 1 +- eps,
    # hexagon sides 1/sqrt3 against sqrt((1 + 3 eps^2)/3), triangle areas sqrt3/4 against
    # sqrt3/4 (1 +- eps)^2. The kernel forms these from the geometry; at eps = 1e-8 a stretch
    # formed as a difference of lengths of size 1 would keep only 8 digits.
    p = pf.Hexagon.from_continuum(ell=4, nu=0.6, eps=eps)
    side = np.sqrt((1 + 3 * eps**2) / 3)
    a0 = np.sqrt(3) / 4
    # (differences written without cancellation: side - 1/sqrt3 = eps^2 / (side + 1/sqrt3), and
    # a0 (1 + s eps)^2 - a0 = a0 s eps (2 + s eps))
    per_particle = (3 * p.k * eps**2 + 3 * p.kc * (eps**2 / (side + 1 / np.sqrt(3)))**2
                    + sum(p.k_area * (a0 * s * eps * (2 + s * eps))**2 / (2 * a0 * (1 + s * eps)**2) for s in (1, -1)))
    topo = T.disk(3)
    e, _ = _kernel.energy_of_displacement(p._kernel_model, topo.kernel, np.zeros(topo.reference_state().size))
    assert e == pytest.approx(topo.n_particles * per_particle, rel=1e-12)


def test_lattice_slots_are_the_particles_rest_shape():
    # The topology places a particle's corners (slot offsets from its site) where the models take
    # their rest shape without mismatch: a regular hexagon of circumradius 1/sqrt3, corners at
    # 30, 90, ..., 330 degrees. Both must agree, or a particle at rest would be prestressed.
    topo = T.disk(0)
    p = PARTICLES["hexagon"]
    corners = pf.relaxation.particle_corners(p, topo, topo.reference_state())[0]
    angles = np.radians(30 + 60 * np.arange(6))
    regular = np.stack([np.cos(angles), np.sin(angles)], axis=1) / np.sqrt(3)
    assert np.abs(corners - regular).max() < 1e-15
    # and the model's energy there, displacement zero, is the mismatch energy alone (no prestress
    # from a misplaced corner): equal evaluated from the absolute corners and from the network.
    e_network, _ = _kernel.energy_of_displacement(p._kernel_model, topo.kernel, np.zeros(12))
    assert p.evaluate(regular)["energy"] == pytest.approx(e_network, rel=1e-14)


def test_relaxations_on_two_threads_at_once_equal_the_serial_one_bit_for_bit():
    # Replica exchange relaxes clusters in threads. A disk of 469 particles is factorised on dense
    # supernodes through the BLAS, which Debian's serial OpenBLAS does not make safe to call from
    # two threads: without the kernel's lock around those calls, 10 of 40 such relaxations
    # raised "not positive definite" and 20 of the others differed from the serial result.
    from concurrent.futures import ThreadPoolExecutor

    particle = pf.Hexagon.from_continuum(ell=5, nu=0.9, eps=0.05)
    disk = T.disk(12)
    serial = pf.relax(particle, disk, method="newton", tol=1e-10)
    with ThreadPoolExecutor(2) as pool:
        side_by_side = list(pool.map(lambda _: pf.relax(particle, disk, method="newton", tol=1e-10), range(40)))
    assert all(np.array_equal(r.state, serial.state) and r.energy == serial.energy for r in side_by_side)


def _pieces_by_search(sites, tiling):
    """Edge-connected pieces of a set of sites, by breadth-first search over neighbour_sites."""
    left, pieces = set(sites), 0
    while left:
        pieces += 1
        frontier = [left.pop()]
        while frontier:
            for n in T.neighbour_sites(frontier.pop(), tiling):
                if n in left:
                    left.remove(n)
                    frontier.append(n)
    return pieces


@pytest.mark.parametrize("tiling", ["hexagon", "triangle"])
@pytest.mark.parametrize("spread", [3, 40_000], ids=["compact", "spread"])
def test_rigid_pieces_counts_the_edge_connected_pieces(tiling, spread):
    # Blobs grown site by site, shifted apart: a few lattice spacings (the kernel's look-up table
    # over the bounding box) or tens of thousands (its sorted fallback), some blobs touching.
    rng = np.random.default_rng(11)
    width = 3 if tiling == "triangle" else 2
    for trial in range(6):
        sites = set()
        for blob in range(rng.integers(1, 5)):
            shift = rng.integers(-spread, spread + 1, size=2)
            seed_site = (int(shift[0]), int(shift[1])) + ((int(rng.integers(0, 2)),) if width == 3 else ())
            grown = [seed_site]
            for _ in range(rng.integers(0, 12)):
                options = T.neighbour_sites(grown[rng.integers(len(grown))], tiling)
                grown.append(options[rng.integers(len(options))])
            sites.update(grown)
        sites = sorted(sites)
        topology = T.cluster(np.array(sites), tiling=tiling)
        assert _kernel.rigid_pieces(topology.kernel) == _pieces_by_search(sites, tiling), (trial, sites)
