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


def test_every_outline_move_has_its_reverse():
    """Over every enumerated aggregate: a particle inserted on an outline site is removable
    afterwards, and a removed particle's site is an outline site of what remains (so the
    Hastings counts e and d are never zero where a move was made)."""
    _, g, states, E = enumerated()
    chain = ReferenceChain(states, E, g, BOX)
    for state in map(set, states):
        for b in chain._exposed(state)[1]:
            assert b in chain._removable(state | {b})
        for a in chain._removable(state):
            assert a in chain._exposed(state - {a})[1]


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


# --------------------------------------------------------------------------------------------
# pyfrustrate.montecarlo.grand_canonical
# --------------------------------------------------------------------------------------------

from pyfrustrate.montecarlo import binding, fixed_size  # noqa: E402
from pyfrustrate.montecarlo import grand_canonical as gc  # noqa: E402


@pytest.fixture(scope="module")
def fibre_point():
    """The fibre point of the validation (nu = 0.9, Gamma = 0.5, ell = 5) and its ansatz's
    threshold min_W e(W)."""
    particle = Hexagon.from_continuum(ell=5, nu=0.9, eps=0.01)
    g = binding(particle, Gamma=0.5)
    _, e = fixed_size.best_straight_fibre(particle, g, max_width=12)
    return particle, g, float(e.min())


def test_threshold_width_interpolates_the_crossing():
    """gap = e - mu linear in mu, crossing 0 at mu = -2.2 between the 2nd and 3rd points."""
    mu = np.array([-3.0, -2.5, -2.0, -1.5])
    e = -2.2 + 0.1 * (mu + 2.2)  # gap = -0.9 (mu + 2.2)
    W, mu_star = gc.threshold_width(mu, [5.0, 8.0, 12.0, 20.0], e)
    assert mu_star == pytest.approx(-2.2)
    assert W == pytest.approx(8.0 + (0.3 / 0.5) * 4.0)
    assert all(np.isnan(gc.threshold_width(mu, [1.0] * 4, mu - 1.0)))  # always above: no crossing
    with pytest.raises(ValueError, match="increasing"):
        gc.threshold_width(mu[::-1], [1.0] * 4, e)
    with pytest.raises(ValueError, match="one length"):
        gc.threshold_width(mu, [1.0] * 3, e)


def test_grand_options_refuse_bad_values():
    with pytest.raises(ValueError, match="chemical_potential"):
        gc.grand_options(float("nan"))
    with pytest.raises(ValueError, match="outline_moves"):
        gc.grand_options(-1.0, outline_moves=0.0)


def test_the_running_energy_follows_insertions_and_deletions_with_warm_starts(fibre_point):
    """Newton with warm starts and parent factors (the path of the workflow's runs): after many
    accepted insertions and deletions, the chain's running energy is the energy of the fibre it
    holds, recomputed from scratch."""
    particle, g, threshold = fibre_point
    options = gc.grand_options(threshold, method="newton", tol=1e-8, outline_moves=0.5, parent_factor=True)
    chain = fixed_size._seeded_chain(particle, fixed_size.fibre_seed(10, 3), 10, 4, g, options)
    chain.run(np.full(60, 0.5 * g), np.full(60, 30, dtype=np.int64))
    assert chain.options["parent_start"] and chain.options["parent_factor"]
    counters = chain.counters
    assert counters["outline_inserted"] + counters["outline_removed"] > 20, counters
    assert chain.n == 30 + counters["outline_inserted"] - counters["outline_removed"]
    assert chain.energy == pytest.approx(chain.box_energy(True), abs=1e-6 * g)


@pytest.mark.parametrize("offset, grows", [(-0.5, False), (0.5, True)])
def test_a_fibre_shrinks_below_the_threshold_and_grows_above(fibre_point, offset, grows):
    """Half a bond per particle below min_W e(W) the grand potential L W (e - mu) of every fibre
    is positive and the fibre loses particles; half a bond above it gains them."""
    particle, g, threshold = fibre_point
    sample = gc.hold_fibre(particle, 12, 4, 2, g=g, mu=threshold + offset * g, T=0.3 * g, sweeps=30,
                           options=gc.grand_options(threshold + offset * g, method="newton", tol=1e-3))
    assert sample.W_mean == pytest.approx(sample.n_mean / 12)
    assert sample.n[-1] == 48 + sample.counters["outline_inserted"] - sample.counters["outline_removed"]
    assert (sample.n[-1] > 48) == grows and sample.n[-1] != 48, sample.n


def test_runs_of_fixed_n_refuse_outline_moves():
    from pyfrustrate.montecarlo.options import chain_options
    with pytest.raises(ValueError, match="outline_moves must be 0"):
        chain_options(None, dict(outline_moves=0.2))
    with pytest.raises(ValueError, match="outline_moves must be 0"):
        chain_options(gc.grand_options(-1.0), {})


def test_hold_fibre_refuses_bad_input(fibre_point):
    particle, g, threshold = fibre_point
    with pytest.raises(ValueError, match="chemical_potential = mu"):
        gc.hold_fibre(particle, 12, 4, 0, g=g, mu=threshold, T=0.1, sweeps=2, options=gc.grand_options(0.0))
    with pytest.raises(ValueError, match="T"):
        gc.hold_fibre(particle, 12, 4, 0, g=g, mu=threshold, T=-1.0, sweeps=2)
    with pytest.raises(ValueError, match="equilibration"):
        gc.hold_fibre(particle, 12, 4, 0, g=g, mu=threshold, T=0.1, sweeps=2, equilibration=1.0)
