"""Tests of replica exchange (pyfrustrate.montecarlo.exchange).

Independent reference: the exact Boltzmann weights of every configuration of a box small enough
to enumerate, at each temperature of the ladder (a wrong swap rule, or a swap that moved a
configuration without its temperature, would bias the coldest slot towards the hot ones).
Reproducibility: a run continued from its state, or from a checkpoint, equals the uninterrupted
run; threads do not change the chain.
"""
import itertools

import numpy as np
import pytest

from pyfrustrate import Hexagon, _kernel, continuum
from pyfrustrate.montecarlo import ReplicaState, geometric_temperatures, replica_exchange


@pytest.fixture(scope="module")
def particle():
    # eps = 0.05 makes deformation energies a sizeable part of the weights.
    return Hexagon.from_continuum(ell=5, nu=0.9, eps=0.05)


@pytest.fixture(scope="module")
def g():
    return float(continuum.particle_parameters(5, 0.9, 0.5, eps=0.05).g)


def exact_energies(particle, g, box, n):
    mc = _kernel.MonteCarlo(particle._kernel_model, g, box, n, 0, method="lbfgs", tol=1e-6 * particle.force_scale)
    states = list(itertools.combinations(range(box * box), n))
    energies = []
    for s in states:
        mc.place(np.array([(k % box, k // box) for k in s]))
        energies.append(mc.box_energy(True))
    return {s: k for k, s in enumerate(states)}, np.array(energies)


@pytest.mark.parametrize("box,n,cluster_moves,cluster_link,surface_moves,initial_sites",
                         [(3, 3, 0.0, 1.0, 0.0, None), (4, 3, 0.5, 1.0, 0.0, None), (4, 3, 0.5, 0.5, 0.0, None),
                          (4, 3, 0.2, 0.5, 0.5, None), (4, 3, 0.2, 0.5, 0.5, [(0, 0), (1, 0), (0, 1)])])
def test_every_temperature_samples_its_boltzmann_weights(particle, g, box, n, cluster_moves, cluster_link, surface_moves,
                                                          initial_sites):
    # The last case starts every replica from the same compact triangle (the workflow's exchange
    # after an anneal): the chains still forget it and sample the same weights.
    T = np.array([0.25, 0.5, 1.0]) * g
    rounds = 40_000
    r = replica_exchange(particle, T, g=g, box=box, n=n, rounds=rounds, exchange_every=5, seed=box + n, threads=1,
                         method="lbfgs", tol=1e-6, cluster_moves=cluster_moves, cluster_link=cluster_link, quench_sweeps=0,
                         surface_moves=surface_moves, progress=False, initial_sites=initial_sites,
                         record_sites=True)
    assert np.all(r.swap_acceptance > 0.2) and r.round_trips > 100  # the ladder is really used
    index, E = exact_energies(particle, g, box, n)
    levels = np.unique(np.round(E / g, 9), return_inverse=True)[1]
    assert levels.max() >= 4
    for slot in range(len(T)):
        ids = np.array([index[tuple(s)] for s in r.params["sites_by_slot"][:, slot].tolist()])
        w = np.exp(-(E - E.min()) / T[slot])
        w /= w.sum()
        w_levels = np.bincount(levels, w)
        batches = np.array([np.bincount(levels[b], minlength=len(w_levels)) / len(b) for b in np.array_split(ids, 20)])
        error = np.maximum(batches.std(axis=0, ddof=1) / np.sqrt(20), 1.0 / rounds)
        assert np.max(np.abs(batches.mean(axis=0) - w_levels) / error) < 5
        assert 0.5 * np.abs(np.bincount(levels[ids], minlength=len(w_levels)) / rounds - w_levels).sum() < 0.02
        h = np.bincount(ids, minlength=len(E)) / rounds
        assert 0.5 * np.abs(h - w).sum() < 0.06


def test_continuing_from_the_state_equals_the_uninterrupted_run(particle, g):
    kw = dict(box=10, n=20, seed=7, method="linear", progress=False, temperatures=geometric_temperatures(0.2 * g, g, 4))
    whole = replica_exchange(particle, g=g, rounds=60, **kw)
    half = replica_exchange(particle, g=g, rounds=30, **kw)
    rest = replica_exchange(particle, g=g, rounds=60, state=half.state, **kw)
    assert rest.resumed and half.state.rounds == 30  # the state passed in is not modified
    assert np.array_equal(rest.energy_trace, whole.energy_trace)
    assert np.array_equal(rest.sites, whole.sites) and rest.energy == whole.energy
    assert np.array_equal(rest.state.slot_of_replica, whole.state.slot_of_replica)
    assert rest.round_trips == whole.round_trips


def test_checkpoint_resumes_and_threads_do_not_change_the_chain(particle, g, tmp_path):
    kw = dict(box=10, n=20, seed=8, method="linear", progress=False, temperatures=geometric_temperatures(0.2 * g, g, 4))
    whole = replica_exchange(particle, g=g, rounds=40, threads=1, **kw)
    path = tmp_path / "pt.pkl"
    first = replica_exchange(particle, g=g, rounds=20, threads=2, checkpoint=path, **kw)
    assert path.exists() and not first.resumed
    again = replica_exchange(particle, g=g, rounds=40, threads=2, checkpoint=path, **kw)
    assert again.resumed
    assert np.array_equal(again.energy_trace, whole.energy_trace) and np.array_equal(again.sites, whole.sites)
    with pytest.raises(ValueError, match="different parameters"):
        replica_exchange(particle, g=1.1 * g, rounds=40, checkpoint=path, **kw)


def test_quench_ends_in_a_local_minimum_of_the_coldest_configuration(particle, g):
    r = replica_exchange(particle, geometric_temperatures(0.2 * g, g, 3), g=g, box=10, n=20, rounds=30, seed=2,
                         method="linear", quench_sweeps=100, progress=False)
    cold = r.energy_trace[-1, 0]
    assert r.energy <= cold + 1e-12
    mc = _kernel.MonteCarlo(particle._kernel_model, g, 10, 20, 5, method="linear")
    mc.place(r.sites)
    assert mc.box_energy(True) == pytest.approx(r.energy, rel=1e-9)


def test_initial_sites_start_every_replica_and_enter_the_checkpoint(particle, g, tmp_path):
    rng = np.random.default_rng(3)
    cells = rng.choice(100, 20, replace=False)
    sites = np.column_stack([cells % 10, cells // 10])
    kw = dict(box=10, n=20, seed=4, method="linear", progress=False, temperatures=geometric_temperatures(0.2 * g, g, 3))
    mc = _kernel.MonteCarlo(particle._kernel_model, g, 10, 20, 0, method="linear")
    mc.place(sites)
    start = mc.box_energy(True)
    r = replica_exchange(particle, g=g, rounds=0, quench_sweeps=0, initial_sites=sites, **kw)
    def occupied(a):
        return sorted(map(tuple, np.asarray(a).tolist()))

    assert occupied(r.sites) == occupied(sites)
    assert r.energy == pytest.approx(start, rel=1e-9)
    assert all(occupied(rep.particles) == occupied(sites) for rep in r.state.replicas)
    # A descent from those sites never ends above them.
    assert replica_exchange(particle, g=g, rounds=0, quench_sweeps=20, initial_sites=sites, **kw).energy <= start + 1e-12
    path = tmp_path / "pt.pkl"
    replica_exchange(particle, g=g, rounds=5, checkpoint=path, initial_sites=sites, **kw)
    with pytest.raises(ValueError, match="different parameters"):
        replica_exchange(particle, g=g, rounds=10, checkpoint=path, initial_sites=sites[::-1], **kw)


@pytest.mark.parametrize("kwargs, message", [
    ({"initial_sites": [(0, 0), (1, 0), (2, 0)]}, "initial_sites: expected 4 sites"),
    ({"initial_sites": [(0, 0), (1, 0), (2, 0), (0, 5)]}, "initial_sites: .* occupied twice"),
    ({"initial_sites": "corner"}, "initial_sites"),
    ({"temperatures": [1.0]}, "temperatures"),
    ({"temperatures": [1.0, 0.5]}, "temperatures"),
    ({"temperatures": [0.0, 1.0]}, "temperatures"),
    ({"temperatures": [1.0, np.nan]}, "temperatures"),
    ({"box": 1}, "box"),
    ({"n": 100}, "n must be smaller"),
    ({"rounds": -1}, "rounds"),
    ({"cluster_moves": 2.0}, "cluster_moves"),
    ({"surface_moves": 1.0}, "surface_moves"),
    ({"method": "magic"}, "method"),
    ({"g": -1.0}, "g must"),
    ({"state": ReplicaState(replicas=[{}], slot_of_replica=np.arange(1), swap_rng={})}, "replicas"),
])
def test_bad_input_is_rejected_naming_the_parameter(particle, g, kwargs, message):
    kw = dict(g=g, temperatures=[0.5, 1.0], box=5, n=4, rounds=2, progress=False) | kwargs
    with pytest.raises(ValueError, match=message):
        replica_exchange(particle, **kw)


def test_geometric_ladder():
    T = geometric_temperatures(0.1, 1.0, 5)
    assert T[0] == pytest.approx(0.1) and T[-1] == pytest.approx(1.0)
    assert np.allclose(T[1:] / T[:-1], T[1] / T[0])
    with pytest.raises(ValueError, match="T_min"):
        geometric_temperatures(1.0, 0.5, 3)
