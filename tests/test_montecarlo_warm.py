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
import os
import subprocess
import sys

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


def wrapping_fibre_chains(seed, rows=4, box=10):
    """Warm and cold chains from one straight fibre of ``rows`` rows wrapping a ``box`` x ``box``
    box along its first lattice vector (ell = 5, nu = 0.9, as the validation's fibre scan), with
    particle and surface moves and no cache, so that every move relaxes its clusters."""
    particle, g = setup(dict(ell=5, nu=0.9, eps=0.01))
    sites = np.array([(i, j) for j in range(rows) for i in range(box)])
    out = {}
    for warm in (True, False):
        mc = kernel_mc(particle, g, box, len(sites), seed, "newton", tol=1e-3, parent_start=warm, surface_moves=0.5,
                       cache=False)
        mc.place(sites)
        out[warm] = mc
    return particle, g, out


def test_wrapping_clusters_are_warm_started_to_the_cold_energies():
    """A cluster that wraps the box relaxes its period vector, so its displacements grow by the
    period's change from one image to the next: the store keeps them less the cluster's strain
    (chain.hpp, kSiteRecord). Held at 0.5 g, where particles leave and rejoin the fibre's outline
    (a straight fibre's own moves all break bonds, and are screened out at lower temperatures),
    the relaxations of the fibre start warm (the chain used to relax every wrapping cluster cold),
    and the running energy equals the cold relaxation of every cluster from scratch to the
    relaxation tolerance, as for finite clusters (first test)."""
    particle, g, chains = wrapping_fibre_chains(seed=3)
    mc = chains[True]
    n = len(mc.particles)
    scale = n * particle.bulk_energy_per_particle
    worst = 0.0
    for _ in range(8):
        mc.run(np.array([0.5 * g]), np.array([4 * n]))
        worst = max(worst, abs(mc.energy - mc.box_energy(True)) / scale)
    c = mc.counters
    assert c["warm_starts"] > 0.2 * c["minimisations"] > 20, (c["warm_starts"], c["minimisations"])
    assert c["unconverged"] == 0
    assert worst < 1e-5, worst


def test_warm_fibre_chain_equals_cold_fibre_chain():
    """The same seed from the same wrapping fibre, warm and cold: the same moves, and energies
    equal within the tolerance. (On a fibre this thin the warm chain factorises no less: the
    cold path's first steps on the reference stiffness converge nearly as fast here.)"""
    particle, g, chains = wrapping_fibre_chains(seed=5)
    traces = {warm: mc.run(np.full(6, 0.5 * g), np.full(6, 4 * len(mc.particles)))["energy"]
              for warm, mc in chains.items()}
    warm, cold = chains[True], chains[False]
    assert np.array_equal(warm.particles, cold.particles)
    for k in ("accepted", "screened", "minimisations"):
        assert warm.counters[k] == cold.counters[k]
    atol = 1e-5 * len(warm.particles) * particle.bulk_energy_per_particle
    assert np.allclose(traces[True], traces[False], rtol=0, atol=atol)
    assert warm.counters["warm_starts"] > 0 and cold.counters["warm_starts"] == 0


@pytest.mark.parametrize("value,expected", [(None, 16 << 20), ("0", 0), ("1048576", 1 << 20)])
def test_the_heap_top_pad_follows_its_environment_variable(value, expected):
    """The kernel's heap top pad (kernel/module.cpp) is set at import, per process: 16 MiB unless
    PYFRUSTRATE_MALLOC_TOP_PAD says otherwise (0: glibc's default, nothing set)."""
    env = {k: v for k, v in os.environ.items() if k != "PYFRUSTRATE_MALLOC_TOP_PAD"}
    if value is not None:
        env["PYFRUSTRATE_MALLOC_TOP_PAD"] = value
    out = subprocess.run([sys.executable, "-c", "from pyfrustrate import _kernel; print(_kernel.allocator_top_pad)"],
                         env=env, capture_output=True, text=True, check=True, cwd=os.path.dirname(__file__))
    assert int(out.stdout) == expected


def test_a_bad_heap_top_pad_is_refused_by_name():
    env = dict(os.environ, PYFRUSTRATE_MALLOC_TOP_PAD="lots")
    out = subprocess.run([sys.executable, "-c", "import pyfrustrate"], env=env, capture_output=True, text=True,
                         cwd=os.path.dirname(__file__))
    assert out.returncode != 0 and "PYFRUSTRATE_MALLOC_TOP_PAD" in out.stderr and "'lots'" in out.stderr
