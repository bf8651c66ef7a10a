"""Warm-started exact cluster energies in the Monte Carlo (``parent_start``, kernel/montecarlo/chain.hpp;
``anneal(method="newton", warm_start=True)``): each move's clusters are relaxed by Newton from the
relaxed displacements of the clusters they came from instead of from the linear solution of
their canonical representative.

The warm path also factorises with the kernel's own LDL^T on CHOLMOD's ordering (cholesky.cpp,
own_ldl), so these tests check that factorisation too (pivots, damping, solves) against CHOLMOD's.

References: the cold path (the same kernel with ``parent_start=False``, bit-for-bit the Newton
path before warm starts), an independent L-BFGS minimisation at a tight tolerance, and the exact
Boltzmann weights of a box small enough to enumerate.
"""
import numpy as np
import pytest

import pyfrustrate
from pyfrustrate import Hexagon, continuum

from test_montecarlo import compare_with_boltzmann, enumerate_states, kernel_mc

# The dense box's particle (nu = 0.4: loose clusters, far from the linear response) and one
# with a larger mismatch, where deformation energies weigh more in the Boltzmann factors.
DENSE = dict(ell=5, nu=0.4, eps=0.01)
STRONG = dict(ell=5, nu=0.9, eps=0.05)


def setup(params):
    particle = Hexagon.from_continuum(**params)
    g = float(continuum.particle_parameters(params["ell"], params["nu"], 0.5, eps=params["eps"]).g)
    return particle, g


def test_warm_energies_equal_cold_and_lbfgs_to_the_tolerance():
    """Along a warm-started chain, the running energy (a sum of warm-started relaxations) equals
    the cold Newton relaxation of every cluster from scratch and an independent L-BFGS at tol
    1e-9, to the relaxation tolerance. The tolerance is on the largest force (1e-3 F): in the
    loose clusters of nu = 0.4 (soft modes) the energy stops up to a few 1e-6 of the box's
    deformation scale above the minimum, the cold start as the warm one (measured over 60 states
    of 48 particles in 12 x 12: largest error warm 3.7e-7, cold 1.4e-6 of the box energy)."""
    particle, g = setup(DENSE)
    box, n = 10, 34
    scale = n * particle.bulk_energy_per_particle
    mc = kernel_mc(particle, g, box, n, 3, "newton", tol=1e-3, parent_start=True, cluster_moves=0.05)
    lbfgs = kernel_mc(particle, g, box, n, 0, "lbfgs", tol=1e-9)
    worst_cold = worst_lbfgs = worst_reference = 0.0
    for T_ in np.linspace(0.8 * g, 0.2 * g, 12):
        mc.run(np.array([T_]), np.array([150]))
        cold = mc.box_energy(True)  # cold Newton, canonical representatives, no cache
        lbfgs.place(mc.particles)
        worst_cold = max(worst_cold, abs(mc.energy - cold) / scale)
        worst_lbfgs = max(worst_lbfgs, abs(mc.energy - lbfgs.energy) / scale)
        worst_reference = max(worst_reference, abs(cold - lbfgs.energy) / scale)
    c = mc.counters
    assert c["warm_starts"] > 0.3 * c["minimisations"] > 30
    assert c["unconverged"] == 0
    assert worst_cold < 1e-5 and worst_lbfgs < 1e-5, (worst_cold, worst_lbfgs)
    assert worst_reference < 1e-5


def test_warm_starts_outside_the_basin_restart_from_the_linear_solution():
    """At a large mismatch (eps = 0.05) a moved particle's rigid fit can leave its cluster where
    the exact Hessian stays indefinite; Newton then restarts from the linear solution
    (warm_restarts) instead of handing the warm state to L-BFGS. The running energy still equals
    the cold relaxation of every cluster from scratch (measured: largest error 6e-5 of the box
    scale with restarts, 2.8e-4 when L-BFGS went on from the warm state)."""
    particle, g = setup(STRONG)
    box, n = 10, 34
    scale = n * particle.bulk_energy_per_particle
    mc = kernel_mc(particle, g, box, n, 3, "newton", tol=1e-3, parent_start=True, cluster_moves=0.05)
    worst = 0.0
    for T_ in np.linspace(0.8 * g, 0.2 * g, 12):
        mc.run(np.array([T_]), np.array([150]))
        worst = max(worst, abs(mc.energy - mc.box_energy(True)) / scale)
    c = mc.counters
    assert 0 < c["warm_restarts"] < c["warm_starts"]
    assert c["unconverged"] == 0
    assert worst < 1e-4, worst


def test_warm_chain_equals_cold_chain():
    """The same seed with warm and cold starts takes the same moves: energies differ within the
    tolerance only (as in the test above), far below what changes a Metropolis decision here."""
    particle, g = setup(DENSE)
    out = {}
    for warm in (True, False):
        mc = kernel_mc(particle, g, 12, 48, 5, "newton", tol=1e-3, parent_start=warm, cluster_moves=0.02)
        trace = mc.run(np.linspace(g, 0.1 * g, 30), np.full(30, 48))
        out[warm] = (mc, trace["energy"])
    (warm, e_warm), (cold, e_cold) = out[True], out[False]
    assert warm.counters["warm_starts"] > 0 and cold.counters["warm_starts"] == 0
    assert np.array_equal(warm.particles, cold.particles)
    for k in ("accepted", "screened", "minimisations"):
        assert warm.counters[k] == cold.counters[k]
    assert np.allclose(e_warm, e_cold, rtol=0, atol=1e-5 * 48 * particle.bulk_energy_per_particle)
    # The warm path does less work.
    assert warm.counters["factorizations"] < cold.counters["factorizations"]


def test_cold_path_unchanged_by_the_option():
    """parent_start=False is the former Newton path: energies from canonical representatives,
    equal to the from-scratch recomputation to round-off, whatever the cache."""
    particle, g = setup(DENSE)
    a = kernel_mc(particle, g, 8, 20, 2, "newton", tol=1e-3)
    b = kernel_mc(particle, g, 8, 20, 2, "newton", tol=1e-3, parent_start=False, cache=False)
    for mc in (a, b):
        mc.run(np.linspace(g, 0.2 * g, 10), np.full(10, 40))
    assert np.array_equal(a.particles, b.particles) and a.energy == pytest.approx(b.energy, rel=0, abs=1e-14)
    assert a.energy == pytest.approx(a.box_energy(True), rel=0, abs=1e-14)


@pytest.mark.parametrize("delayed,moves", [(True, {}), (False, {}), (True, dict(cluster_moves=0.5, cluster_link=0.5))])
def test_warm_chain_samples_the_boltzmann_weights(delayed, moves):
    """Detailed balance with warm starts: the states visited in a 4 x 4 box of 3 particles follow
    exp(-E/T) of the exact enumeration (cold Newton energies). Without the cache, so that every
    move relaxes its clusters, warm-started wherever a parent is known; with linked cluster moves
    too, whose shifted particles carry their displacements to where they land."""
    particle, g = setup(STRONG)
    box, n, T_ = 4, 3, 0.5 * g
    states, E = enumerate_states(kernel_mc(particle, g, box, n, 0, "newton", tol=1e-3), box, n)
    mc = kernel_mc(particle, g, box, n, 21 + delayed, "newton", tol=1e-3, parent_start=True,
                   delayed_acceptance=delayed, cache=False, **moves)
    _, tv_levels, z = compare_with_boltzmann(mc, states, E, T_, g, samples=100_000)
    assert len(np.unique(np.round(E / g, 9))) >= 5 and mc.counters["warm_starts"] > 0
    assert mc.counters["cluster_rebonded"] > (5000 if moves else -1)
    assert mc.counters["bounded"] > 0  # second-stage rejections decided by the lower bound
    assert z < 5 and tv_levels < 0.02


def test_anneal_newton_uses_warm_starts_unless_told_not_to():
    particle, g = setup(DENSE)
    kw = dict(box=10, n=30, steps=30 * 40, seed=4, method="newton", progress=False)
    warm = pyfrustrate.anneal(particle, g=g, **kw)
    cold = pyfrustrate.anneal(particle, g=g, warm_start=False, **kw)
    assert warm.counters["warm_starts"] > 0 and cold.counters["warm_starts"] == 0
    assert warm.energy == pytest.approx(cold.energy, rel=1e-6)
    with pytest.raises(ValueError, match="parent_start"):
        kernel_mc(particle, g, 8, 10, 1, "lbfgs", parent_start=True)
