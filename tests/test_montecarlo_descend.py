"""``annealing.descend``: a run continued at T = 0 until a round gains nothing ends in a local
minimum of its moves (also after rounds at a small positive temperature, ``temperature=``). Checked by exact enumeration: from the final state of a small box, every
single-particle jump to an empty site (the moves of a chain with particle moves only) is relaxed
from scratch, and none lowers the energy; the state the descent started from, taken at a
temperature where the chain still climbs, is not such a minimum (the check can fail)."""
import numpy as np
import pytest

from pyfrustrate import Hexagon, anneal, continuum
from pyfrustrate.montecarlo import MonteCarloOptions, descend
from pyfrustrate.montecarlo.fixed_size import _seeded_chain

BOX, N = 5, 6
OPTIONS = MonteCarloOptions(method="newton", cluster_moves=0.0, bonded_moves=0.0, surface_moves=0.0)


def best_jump(particle, g, sites):
    """The lowest energy of the box after any one particle jumps to any empty site (every jump)."""
    occupied = {tuple(s) for s in sites.tolist()}
    empty = [(i, j) for i in range(BOX) for j in range(BOX) if (i, j) not in occupied]
    energies = []
    for k in range(len(sites)):
        for site in empty:
            moved = sites.copy()
            moved[k] = site
            energies.append(_seeded_chain(particle, moved, BOX, 1, g, OPTIONS).energy)
    return min(energies)


@pytest.fixture(scope="module")
def hot_run():
    particle = Hexagon.from_continuum(ell=5.0, nu=0.9, eps=0.01)
    g = float(continuum.particle_parameters(5.0, 0.9, 0.5, eps=0.01).g)
    run = anneal(particle, g=g, box=BOX, n=N, schedule=[(2.0 * g, 40 * N)], seed=3, options=OPTIONS, progress=False)
    return particle, g, run


def test_a_descent_ends_where_no_single_jump_lowers_the_energy(hot_run):
    particle, g, run = hot_run
    final, rounds, still = descend(particle, run, options=OPTIONS, sweeps_per_round=200, min_gain=1e-9)
    assert still and rounds >= 2  # at least one round that gained, then one that did not
    assert final.energy <= run.energy
    from_scratch = _seeded_chain(particle, final.sites, BOX, 1, g, OPTIONS).energy
    assert final.energy == pytest.approx(from_scratch, abs=1e-3 * g)  # relaxed to the tolerance
    assert best_jump(particle, g, final.sites) >= final.energy - 1e-3 * g


def test_the_hot_state_is_not_a_local_minimum(hot_run):
    """The same enumeration finds a jump that lowers the energy of the state the descent began from."""
    particle, g, run = hot_run
    assert best_jump(particle, g, run.sites) < run.energy - 0.1 * g


def test_rounds_that_run_out_while_gaining_are_not_a_minimum(hot_run):
    """One round from the hot state still gains (the enumeration above found a lower jump): the
    descent stops at max_rounds and says it is not in a minimum."""
    particle, g, run = hot_run
    final, rounds, still = descend(particle, run, options=OPTIONS, sweeps_per_round=200, max_rounds=1, min_gain=1e-9)
    assert rounds == 1 and not still and final.energy < run.energy - 1e-9 * g


def test_screened_rounds_then_a_descent_end_in_a_local_minimum(hot_run):
    """Rounds at a small positive temperature (moves that break bonds screened out by their bond
    count) run at that temperature; a descent at T = 0 after them ends, like one from the hot
    state, where the enumeration finds no single jump that lowers the energy."""
    particle, g, run = hot_run
    near, _, _ = descend(particle, run, options=OPTIONS, sweeps_per_round=200, max_rounds=5, min_gain=1e-9,
                         temperature=0.01 * g)
    assert np.all(near.temperature == 0.01 * g)
    final, rounds, still = descend(particle, near, options=OPTIONS, sweeps_per_round=200, min_gain=1e-9)
    assert still
    assert best_jump(particle, g, final.sites) >= final.energy - 1e-3 * g


@pytest.mark.parametrize("kwargs,match", [
    (dict(temperature=-1.0), "temperature"),
    (dict(sweeps_per_round=0), "sweeps_per_round"),
    (dict(max_rounds=0), "max_rounds"),
    (dict(min_gain=-1.0), "min_gain"),
])
def test_bad_input_is_refused_by_name(hot_run, kwargs, match):
    particle, _, run = hot_run
    with pytest.raises(ValueError, match=match):
        descend(particle, run, options=OPTIONS, **kwargs)


def test_a_result_without_state_is_refused(hot_run):
    particle, _, _ = hot_run
    with pytest.raises(ValueError, match="result"):
        descend(particle, object(), options=OPTIONS)
