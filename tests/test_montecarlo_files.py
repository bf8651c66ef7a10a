"""What Monte Carlo runs read and write, and how they are called (``pyfrustrate.montecarlo``):
checkpoints that hold data only (every bad file refused by name, a crafted pickle never run),
GSD trajectories read back with the ``gsd`` package, the binding as ``g=`` or ``Gamma=`` by
keyword only, and the one options type.

References: the run itself uninterrupted (a resumed run and its trajectory must equal it), the
bonds of the final configuration counted again from the trajectory's positions (nearest
neighbours at distance 1 under HOOMD's minimum image), and ``continuum.particle_parameters`` for
the binding conventions.
"""
import os
import pickle

import numpy as np
import pytest

import pyfrustrate as pf
from pyfrustrate import continuum
from pyfrustrate.montecarlo import MonteCarloOptions, geometric_temperatures, read_checkpoint, replica_exchange
from pyfrustrate.montecarlo.checkpoints import FORMAT, write_checkpoint

from test_montecarlo import PARTICLE_MOVES_ONLY, g, particle  # noqa: F401 (fixtures: Hexagon ell 5, nu 0.9, eps 0.01 and g at Gamma 0.5)


RUN = dict(box=10, n=20, steps=20 * 30, seed=8, record_every=20, method="lbfgs", progress=False)


def run(particle, g, **kw):
    return pf.anneal(particle, g=g, **dict(RUN, **kw))


# --------------------------------------------------------------------------------------------
# Checkpoints
# --------------------------------------------------------------------------------------------

class Payload:
    """Unpickling this creates the file ``marker``: proof that a loader ran code from a file."""

    def __init__(self, marker):
        self.marker = marker

    def __reduce__(self):
        return (open, (self.marker, "w"))


def bad_files(tmp_path, good):
    """Each kind of file a run must refuse, written at a path of its own."""
    marker = tmp_path / "executed"
    content = good.read_bytes()
    files = {
        "empty": b"",
        "truncated": content[: len(content) // 2],
        "garbage": os.urandom(4096),
        "pickle": pickle.dumps(Payload(str(marker))),
        "text": b"not a checkpoint\n",
    }
    paths = {}
    for name, data in files.items():
        paths[name] = tmp_path / f"{name}.npz"
        paths[name].write_bytes(data)
    # An archive whose entry is a pickled object array (np.save would run the payload on load
    # with allow_pickle=True).
    paths["object_array"] = tmp_path / "object_array.npz"
    with open(paths["object_array"], "wb") as f:
        np.savez(f, metadata=np.array([Payload(str(marker))], dtype=object))
    # A well-formed archive of another format version, and one of another kind of run.
    for name, kind, version in (("version", "anneal", 1), ("kind", "replica_exchange", None)):
        paths[name] = tmp_path / f"{name}.npz"
        write_checkpoint(paths[name], kind, {}, dict(done=0), {})
        if version is not None:
            import json
            with np.load(paths[name]) as z:
                header = json.loads(str(z["metadata"]))
            header["version"] = version
            with open(paths[name], "wb") as f:
                np.savez(f, metadata=np.array(json.dumps(header)))
    return paths, marker


def test_every_bad_checkpoint_is_refused_by_name_and_none_runs_code(particle, g, tmp_path):
    good = tmp_path / "good.npz"
    run(particle, g, checkpoint=str(good))
    paths, marker = bad_files(tmp_path, good)
    for name, path in paths.items():
        before = path.read_bytes()
        with pytest.raises(ValueError) as info:
            run(particle, g, checkpoint=str(path))
        message = str(info.value)
        assert str(path) in message and "delete it" in message, (name, message)
        assert path.read_bytes() == before, name  # a refused file is left as it was
        with pytest.raises(ValueError, match="delete it"):
            read_checkpoint(str(path))
    assert not marker.exists(), "a checkpoint file ran code"
    # The refusals say what is wrong.
    with pytest.raises(ValueError, match="version 1"):
        run(particle, g, checkpoint=str(paths["version"]))
    with pytest.raises(ValueError, match="replica_exchange"):
        run(particle, g, checkpoint=str(paths["kind"]))
    with pytest.raises(ValueError, match="different parameters .*seed"):
        run(particle, g, checkpoint=str(good), seed=9)


def test_replica_exchange_refuses_bad_checkpoints_too(particle, g, tmp_path):
    T = geometric_temperatures(0.2 * g, g, 3)
    good = tmp_path / "good.npz"
    kw = dict(g=g, box=8, n=10, rounds=4, seed=1, method="linear", progress=False, quench_sweeps=0)
    replica_exchange(particle, T, checkpoint=good, **kw)
    paths, marker = bad_files(tmp_path, good)
    for name, path in paths.items():
        with pytest.raises(ValueError, match="delete it"):
            replica_exchange(particle, T, checkpoint=path, **kw)
    assert not marker.exists()
    with pytest.raises(ValueError, match="anneal"):  # an anneal's checkpoint is not an exchange's
        anneal_file = tmp_path / "anneal.npz"
        run(particle, g, checkpoint=str(anneal_file))
        replica_exchange(particle, T, checkpoint=anneal_file, **kw)


def test_a_checkpoint_is_a_data_only_archive(particle, g, tmp_path):
    path = tmp_path / "run.ckpt"
    r = run(particle, g, checkpoint=str(path))
    with np.load(path, allow_pickle=False) as z:  # loads without unpickling anything
        assert all(z[name].dtype.kind != "O" for name in z.files)
        assert FORMAT in str(z["metadata"])
    state = read_checkpoint(str(path))
    assert state.done == len(r.energy_trace) and np.array_equal(state.energy_trace, r.energy_trace)
    assert state.chain.rng_state == r.state.chain.rng_state and state.chain.deformation == r.deformation
    assert state.chain.counters == r.counters


# --------------------------------------------------------------------------------------------
# GSD trajectories
# --------------------------------------------------------------------------------------------

def min_image_bonds(frame):
    """Pairs of particles at distance 1 (neighbouring site centres) under the minimum image of
    the frame's triclinic box."""
    Lx, Ly, _, xy, _, _ = frame.configuration.box
    a1, a2 = np.array([Lx, 0.0]), np.array([xy * Ly, Ly])
    x = frame.particles.position[:, :2].astype(float)
    d = x[:, None, :] - x[None, :, :]
    basis = np.column_stack([a1, a2])
    f = np.linalg.solve(basis, d.reshape(-1, 2).T).T
    f -= np.round(f)
    shortest = np.full(len(f), np.inf)
    for i in (-1, 0, 1):  # the minimum image of a sheared cell: try the neighbouring images
        for j in (-1, 0, 1):
            shortest = np.minimum(shortest, np.linalg.norm((f + [i, j]) @ basis.T, axis=1))
    return int(np.sum(np.abs(shortest - 1) < 1e-4)) // 2


def test_anneal_writes_a_gsd_trajectory(particle, g, tmp_path):
    import gsd.hoomd

    path = tmp_path / "run.gsd"
    r = run(particle, g, trajectory=path, trajectory_every=3)
    with gsd.hoomd.open(path, "r") as f:
        frames = list(f)
    blocks = len(r.energy_trace)
    assert len(frames) == blocks // 3
    assert [fr.configuration.step for fr in frames] == r.steps[2::3].tolist()
    assert np.allclose([fr.log["pyfrustrate/energy"][0] for fr in frames], r.energy_trace[2::3], rtol=0, atol=0)
    assert np.allclose([fr.log["pyfrustrate/temperature"][0] for fr in frames], r.temperature[2::3])
    last = frames[-1]
    assert last.configuration.step == r.steps[-1] and last.particles.N == r.n
    assert last.configuration.dimensions == 2 and list(last.particles.types) == ["hexagon"]
    Lx, Ly, Lz, xy = last.configuration.box[:4]
    assert (Lx, Ly, xy) == pytest.approx((10, 10 * np.sqrt(3) / 2, 1 / np.sqrt(3)))
    assert np.all(np.abs(last.particles.position[:, 2]) == 0)
    assert min_image_bonds(last) == r.bonds  # the positions are the final configuration's sites


def test_triangle_types_and_replica_exchange_frames(tmp_path):
    import gsd.hoomd

    particle = pf.Triangle.from_continuum(2.5, 0.6, eps=0.01)
    g = 2 * particle.bulk_energy_per_particle
    r = pf.anneal(particle, g=g, box=6, n=12, steps=12 * 20, seed=2, method="linear", progress=False,
                  trajectory=tmp_path / "tri.gsd", trajectory_every=20)
    with gsd.hoomd.open(tmp_path / "tri.gsd", "r") as f:
        frame, = list(f)
    assert list(frame.particles.types) == ["up", "down"]
    assert sorted(frame.particles.typeid.tolist()) == sorted(r.sites[:, 2].tolist())
    x = replica_exchange(particle, [0.5 * g, g], g=g, box=6, n=12, rounds=6, seed=3, method="linear", progress=False,
                         quench_sweeps=0, trajectory=tmp_path / "x.gsd", trajectory_every=2)
    with gsd.hoomd.open(tmp_path / "x.gsd", "r") as f:
        frames = list(f)
    assert [fr.configuration.step for fr in frames] == [2, 4, 6]
    assert frames[-1].log["pyfrustrate/energy"][0] == x.energy_trace[-1, 0]


def test_a_resumed_run_continues_its_trajectory(particle, g, tmp_path):
    import gsd.hoomd

    whole = tmp_path / "whole.gsd"
    run(particle, g, trajectory=whole, trajectory_every=2)
    path, checkpoint = tmp_path / "part.gsd", tmp_path / "run.ckpt"

    def stop(done, total, energy):
        if done >= 20 * 13:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        run(particle, g, trajectory=path, trajectory_every=2, checkpoint=str(checkpoint), callback=stop)
    run(particle, g, trajectory=path, trajectory_every=2, checkpoint=str(checkpoint))
    with gsd.hoomd.open(whole, "r") as a, gsd.hoomd.open(path, "r") as b:
        fa, fb = list(a), list(b)
    assert [f.configuration.step for f in fb] == [f.configuration.step for f in fa]
    for x, y in zip(fa, fb):
        assert np.array_equal(x.particles.position, y.particles.position)
        assert x.log["pyfrustrate/energy"][0] == y.log["pyfrustrate/energy"][0]


# --------------------------------------------------------------------------------------------
# Calling conventions: the binding by keyword, the particle, the options
# --------------------------------------------------------------------------------------------

def test_the_binding_is_g_or_Gamma_by_keyword_only(particle, g):
    by_Gamma = run(particle, None, Gamma=0.5)
    by_g = run(particle, g)
    assert by_Gamma.g == pytest.approx(g, rel=1e-12)
    assert np.array_equal(by_Gamma.sites, by_g.sites)
    supplement = float(continuum.particle_parameters(5, 0.9, 0.5, eps=0.01, convention="supplement").g)
    assert run(particle, None, Gamma=0.5, convention="supplement", steps=20).g == pytest.approx(supplement, rel=1e-12)
    with pytest.raises(TypeError):
        pf.anneal(particle, 0.5, box=10, n=20, steps=20, progress=False)  # a bare number is never taken as g
    with pytest.raises(TypeError):
        replica_exchange(particle, g, [0.5, 1.0], box=10, n=20, rounds=1, progress=False)
    for kw in (dict(), dict(g=g, Gamma=0.5)):
        with pytest.raises(ValueError, match="exactly one of Gamma= .* or g="):
            pf.anneal(particle, **kw, box=10, n=20, steps=20, progress=False)
    with pytest.raises(ValueError, match="Gamma"):
        pf.anneal(particle, Gamma=-1.0, box=10, n=20, steps=20, progress=False)
    with pytest.raises(ValueError, match="pass g="):
        pf.anneal(pf.RandomHexagon.draw(1, eps=0.01), Gamma=0.5, box=10, n=20, steps=20, progress=False)


@pytest.mark.parametrize("thing", [None, "hexagon", 3.0, object()])
def test_a_non_particle_raises_type_error(thing, g):
    with pytest.raises(TypeError, match="particle"):
        pf.anneal(thing, g=g, box=10, n=20, steps=20, progress=False)
    with pytest.raises(TypeError, match="particle"):
        replica_exchange(thing, [0.5, 1.0], g=g, box=10, n=20, rounds=1, progress=False)


def test_one_options_type_checked_once(particle, g):
    options = MonteCarloOptions(method="lbfgs", cluster_moves=0.1)
    a = pf.anneal(particle, g=g, options=options, **{k: v for k, v in RUN.items() if k != "method"})
    b = run(particle, g, cluster_moves=0.1)  # the same fields as keywords
    assert np.array_equal(a.sites, b.sites) and a.params["cluster_moves"] == 0.1
    # "auto" is Newton, as in relax: the same chain.
    auto = run(particle, g, method="auto", steps=20 * 5)
    newton = run(particle, g, method="newton", steps=20 * 5)
    assert np.array_equal(auto.sites, newton.sites) and auto.energy == newton.energy
    assert auto.params["method"] == "newton"
    for bad, name in ((dict(method="auto2"), "method"), (dict(tol=float("nan")), "tol"), (dict(max_iter=0), "max_iter"),
                      (dict(bonded_moves=1.0), "bonded_moves"), (dict(cluster_link=2), "cluster_link"),
                      (dict(warm_start="yes"), "warm_start")):
        with pytest.raises(ValueError, match=name):
            MonteCarloOptions(**bad)
    with pytest.raises(TypeError, match="moves_per_sweep"):
        run(particle, g, moves_per_sweep=3)
    with pytest.raises(TypeError, match="options"):
        run(particle, g, options=dict(method="lbfgs"))


# --------------------------------------------------------------------------------------------
# The kernel's chain state as a value
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("moves", [dict(), dict(cluster_moves=0.3, cluster_link=0.7, bonded_moves=0.4, surface_moves=0.3)])
def test_a_chain_continued_from_its_state_equals_the_uninterrupted_one(particle, g, moves):
    """A state read from a chain and passed into a new one (the cache empty, the state rebuilt
    from its parts as a checkpoint would) continues the same chain: the same sites, energies,
    counters and random stream as one chain run throughout."""
    from pyfrustrate import _kernel

    def chain(**kw):
        return _kernel.MonteCarlo(particle._kernel_model, g, 8, 20, 5, method="lbfgs", tol=1e-6,
                                  force_scale=particle.force_scale, **{**PARTICLE_MOVES_ONLY, **moves}, **kw)

    T = np.linspace(g, 0.1 * g, 12)
    whole = chain()
    whole_energy = whole.run(T, np.full(12, 40))["energy"]
    first = chain()
    first_energy = first.run(T[:5], np.full(5, 40))["energy"]
    s = first.state
    rebuilt = _kernel.MonteCarloState(s.tiling, s.box, s.particles, s.rng_state, s.deformation, s.counters,
                                      s.displacement, s.known)
    second = chain(state=rebuilt)
    second_energy = second.run(T[5:], np.full(7, 40))["energy"]
    assert np.array_equal(np.concatenate([first_energy, second_energy]), whole_energy)
    assert np.array_equal(second.particles, whole.particles) and second.state.rng_state == whole.state.rng_state
    cache_free = ("cache_hits", "cache_misses", "minimisations", "evaluations", "factorizations")
    assert {k: v for k, v in second.counters.items() if k not in cache_free} == \
        {k: v for k, v in whole.counters.items() if k not in cache_free}
    # Each family's counters under its own name, as many as the chain attempted.
    c = whole.counters
    assert c["cluster_attempted"] + c["surface_attempted"] <= c["attempted"]
    assert (c["cluster_attempted"] > 0) == ("cluster_moves" in moves)
    with pytest.raises(ValueError, match="state"):
        _kernel.MonteCarlo(particle._kernel_model, g, 9, 20, 5, state=rebuilt)  # another box
