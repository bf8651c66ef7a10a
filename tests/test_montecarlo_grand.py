"""Grand-canonical sampling of one aggregate (outline moves, ``kernel/montecarlo/outline_move.hpp``)
against exact enumeration.

On a 3 x 3 periodic box every connected aggregate of 1 to 8 particles is enumerated, with the
kernel's exact relaxed energies, and weighted by exp(-(E - mu n) / T). At the chosen mu and T the
sizes spread over the whole range, and the Hastings ratio of an outline move (e(C) / d(C') for an
insertion: empty outline sites before over removable particles after) ranges over a factor of ~10,
so that

* the kernel's chain (outline moves mixed with surface and bonded particle moves, which must
  refuse to disconnect the aggregate) samples the exact weights, by the statistic of
  ``test_montecarlo.compare_with_boltzmann``, with and without delayed acceptance;
* an independent chain in Python (``montecarlo_reference``: removability by searching the rest,
  not by articulation points) with the right rule passes the same statistic at the same size;
* the same chain with the counts dropped, or swapped (reverse choices over forward ones), fails it.
"""
import itertools

import numpy as np
import pytest

from pyfrustrate import Hexagon, continuum

from montecarlo_reference import NEIGHBOURS, ReferenceChain
from test_montecarlo import boltzmann_statistics, kernel_mc
from test_montecarlo_rules import passes

BOX = 3
#: Sizes mix slowly through the least likely ones (3 and 4 particles): three times the fixed-size tests' samples.
SAMPLES = 600_000
T_OVER_G = 1.0
#: mu / g: sizes 1 .. 8 all carry weight at T = g (test_the_sizes_spread checks it).
MU_OVER_G = -2.45
MOVES = dict(outline_moves=0.5, surface_moves=0.5, bonded_moves=0.5)


def connected(sites, box=BOX):
    """Whether sites (numbered i + box j) form one cluster on the torus, by breadth-first search."""
    sites = set(sites)
    seen, queue = {min(sites)}, [min(sites)]
    for s in queue:
        i, j = s % box, s // box
        for u in {(i + di) % box + box * ((j + dj) % box) for di, dj in NEIGHBOURS} & sites - seen:
            seen.add(u)
            queue.append(u)
    return seen == sites


_ENUMERATED = {}


def enumerated():
    """(particle, g, states, E): every connected aggregate of the box, one particle short of full
    at most, and its energy recomputed from scratch by a kernel chain of that size."""
    if not _ENUMERATED:
        particle = Hexagon.from_continuum(ell=5, nu=0.9, eps=0.05)
        g = float(continuum.particle_parameters(5, 0.9, 0.1, eps=0.05).g)
        states, E = [], []
        for n in range(1, BOX * BOX):
            mc = kernel_mc(particle, g, BOX, n, 0)
            for s in itertools.combinations(range(BOX * BOX), n):
                if connected(s):
                    mc.place(np.array([(k % BOX, k // BOX) for k in s]))
                    states.append(s)
                    E.append(mc.box_energy(True))
        _ENUMERATED.update(particle=particle, g=g, states=states, E=np.array(E))
    return _ENUMERATED["particle"], _ENUMERATED["g"], _ENUMERATED["states"], _ENUMERATED["E"]


def grand_weights(states, E, g):
    """exp(-(E - mu n) / T), normalised, and the grand energies E - mu n."""
    H = E - MU_OVER_G * g * np.array([len(s) for s in states])
    w = np.exp(-(H - H.min()) / (T_OVER_G * g))
    return w / w.sum(), H


def grand_chain(particle, g, seed, **kw):
    """A chain of outline, surface and bonded moves from one particle at (0, 0)."""
    return kernel_mc(particle, g, BOX, 1, seed, **{"chemical_potential": MU_OVER_G * g, **MOVES, **kw})


def test_enumeration_counts_every_connected_aggregate():
    """An independent count: on the 3 x 3 torus a site touches 6 of the 8 others, and the sites
    that do not touch fall into three triples (i - j fixed modulo 3). A pair is disconnected iff
    it lies in one triple (9 of 36), a set of three iff it is one (3 of 84), and a larger set never
    (no site of it can miss all the others)."""
    _, _, states, _ = enumerated()
    sizes = np.bincount([len(s) for s in states])
    assert sizes[1] == 9 and sizes[2] == 27 and sizes[3] == 81
    for k in range(4, 9):
        assert sizes[k] == len(list(itertools.combinations(range(9), k)))


def test_the_sizes_spread():
    """Where the Hastings counts matter: every size holds at least 5 % of the weight."""
    _, g, states, E = enumerated()
    w, _ = grand_weights(states, E, g)
    per_size = np.bincount([len(s) for s in states], w)[1:]
    assert per_size.min() > 0.05, per_size


def sampled_ids(out, states):
    index = {s: k for k, s in enumerate(states)}
    return np.array([index[tuple(x for x in row if x >= 0)] for row in out["sites"].tolist()])


def statistics_of(ids, states, E, g):
    """The statistic of ``compare_with_boltzmann`` on the grand energies E - mu n."""
    _, H = grand_weights(states, E, g)
    return boltzmann_statistics(ids, states, H, T_OVER_G * g, g)


@pytest.mark.parametrize("delayed", [True, False])
def test_kernel_samples_the_grand_canonical_weights(delayed):
    particle, g, states, E = enumerated()
    mc = grand_chain(particle, g, 31 + delayed, delayed_acceptance=delayed)
    out = mc.run(np.full(SAMPLES, T_OVER_G * g), np.ones(SAMPLES, dtype=np.int64), True)
    statistics = statistics_of(sampled_ids(out, states), states, E, g)
    assert passes(statistics), statistics
    counters = mc.counters
    # The number of particles is the chain's: the start's plus insertions minus deletions.
    assert mc.n == 1 + counters["outline_inserted"] - counters["outline_removed"] == out["n"][-1]
    assert counters["outline_inserted"] > 1000 and counters["surface_accepted"] > 1000
    # The running energy is the energy of the state reached.
    assert mc.energy == pytest.approx(mc.box_energy(True), abs=1e-9 * g)


@pytest.mark.parametrize("wrong", [None, "outline_counts_dropped", "outline_counts_swapped"])
def test_an_independent_chain_passes_and_the_wrong_counts_fail(wrong):
    particle, g, states, E = enumerated()
    chain = ReferenceChain(states, E, g, BOX, surface_moves=MOVES["surface_moves"],
                           outline_moves=MOVES["outline_moves"], mu=MU_OVER_G * g, wrong=wrong, seed=7)
    statistics = statistics_of(chain.run(states[0], T_OVER_G * g, SAMPLES), states, E, g)
    if wrong is None:
        assert passes(statistics), statistics
    else:
        assert not passes(statistics)
        assert statistics[2] > 8, statistics  # with a margin: not a borderline rejection


def test_moves_never_disconnect_the_aggregate():
    """Particle moves to any empty site (no bonded or surface targets) mostly would: each state
    recorded is one connected aggregate."""
    particle, g, _, _ = enumerated()
    mc = kernel_mc(particle, g, 5, 1, 3, chemical_potential=MU_OVER_G * g, outline_moves=0.3)
    out = mc.run(np.full(3000, T_OVER_G * g), np.ones(3000, dtype=np.int64), True)
    assert all(connected([x for x in row if x >= 0], 5) for row in out["sites"].tolist())
    assert len(set(out["n"])) > 3
    assert mc.counters["outline_inserted"] > 0 and mc.counters["outline_removed"] > 0


def test_bad_input_is_refused():
    particle, g, _, _ = enumerated()
    for mu in (float("nan"), float("inf")):
        with pytest.raises(ValueError, match="chemical_potential"):
            grand_chain(particle, g, 0, chemical_potential=mu)
    # Two aggregates (two particles apart in a 5 x 5 box): the run refuses to start.
    mc = kernel_mc(particle, g, 5, 2, 0, outline_moves=0.5)
    mc.place(np.array([[0, 0], [2, 2]]))
    with pytest.raises(ValueError, match="one connected aggregate"):
        mc.run(np.array([0.1]), np.array([10]))
    with pytest.raises(ValueError, match="n must be at least 1"):
        kernel_mc(particle, g, 5, 0, 0, outline_moves=0.5)
