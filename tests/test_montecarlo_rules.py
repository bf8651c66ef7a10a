"""The exact-enumeration checks of the Monte Carlo can fail: each factor of the acceptance rule
matters in the boxes they use.

For each factor a case (box, temperature, moves) is chosen where it weighs: the deformation
energy (eps = 0.05, Gamma = 0.1 at T = 0.5 g, deformation energies up to ~0.4 T), the linked-move
factor (1 - link)^(b' - b) at link = 0.8, where (1 - link) and link differ fourfold (at 0.5 they
are equal and no statistic could tell them apart), and the surface-move Hastings ratio in a 5 x 5
box, where the counts of surface particles and perimeter sites change from move to move, the
vacancy-move ratio in a 4 x 4 box of 13 particles, where holes come and go, and the
isometry moves' factor (1 - link)^(b' - b) at link 0.8 (dropped: "no_isometry_factor") and their
count of b' against the rest alone, the set's old sites being left (counted as still occupied:
"stale_rest"; a turned or mirrored set always overlaps its image at the seed). Then:

* the kernel's chain samples the exact Boltzmann weights there (with and without delayed
  acceptance), by the statistic of ``test_montecarlo.compare_with_boltzmann``;
* an independent chain in Python on the kernel's exact energies (``montecarlo_reference``) with
  the right rules passes the same statistic at the same sample size;
* the same chain with one deliberately wrong rule (the deformation term doubled, ``link`` in
  place of ``1 - link``, the surface ratio dropped, the vacancy ratio dropped, the isometry factor dropped, b' counted against
  the set's old sites) fails it.
"""
import numpy as np
import pytest

from pyfrustrate import Hexagon, continuum

from montecarlo_reference import ReferenceChain
from test_montecarlo import boltzmann_statistics, compare_with_boltzmann, enumerate_states, kernel_mc

SAMPLES = 200_000
EPS = 0.05
CASES = {
    "double_deformation": dict(Gamma=0.1, box=4, n=3, moves={}),
    "link_p": dict(Gamma=0.1, box=4, n=3, moves=dict(cluster_moves=0.5, cluster_link=0.8)),
    "no_surface_ratio": dict(Gamma=0.5, box=5, n=3, moves=dict(surface_moves=0.9)),
    # 13 particles in a 4 x 4 box: holes come and go, and the counts of holes, interior,
    # surface and perimeter sites change from move to move; 560 states, so more samples for the
    # state distance.
    "no_vacancy_ratio": dict(Gamma=0.5, box=4, n=13, moves=dict(vacancy_moves=0.9, surface_moves=0.5),
                             samples=600_000),
    "no_isometry_factor": dict(Gamma=0.1, box=4, n=3, moves=dict(shift_moves=0.3, rotation_moves=0.3,
                                                                 reflection_moves=0.3, isometry_link=0.8)),
    "stale_rest": dict(Gamma=0.1, box=4, n=3, moves=dict(rotation_moves=0.5, reflection_moves=0.5, isometry_link=0.5)),
}
#: The kernel's option of each isometry family, as the reference chain names the family.
ISOMETRY_OPTIONS = {"shift": "shift_moves", "rotation": "rotation_moves", "reflection": "reflection_moves"}
T_OVER_G = 0.5


def passes(statistics):
    """The criterion of the kernel's Boltzmann tests: largest level z-score below 5, level
    distance below 0.02, state distance below 0.06."""
    tv_states, tv_levels, z = statistics
    return z < 5 and tv_levels < 0.02 and tv_states < 0.06


_ENUMERATED = {}


def case(name):
    """(particle, g, states, energies) of a case, enumerated once."""
    if name not in _ENUMERATED:
        c = CASES[name]
        particle = Hexagon.from_continuum(ell=5, nu=0.9, eps=EPS)
        g = float(continuum.particle_parameters(5, 0.9, c["Gamma"], eps=EPS).g)
        states, E = enumerate_states(kernel_mc(particle, g, c["box"], c["n"], 0), c["box"], c["n"])
        _ENUMERATED[name] = particle, g, states, E
    return _ENUMERATED[name]


@pytest.mark.parametrize("delayed", [True, False])
@pytest.mark.parametrize("name", sorted(CASES))
def test_kernel_samples_the_boltzmann_weights_where_each_factor_matters(name, delayed):
    particle, g, states, E = case(name)
    c = CASES[name]
    mc = kernel_mc(particle, g, c["box"], c["n"], 21, delayed_acceptance=delayed, **c["moves"])
    statistics = compare_with_boltzmann(mc, states, E, T_OVER_G * g, g, c.get("samples", SAMPLES))
    assert passes(statistics), statistics
    assert len(np.unique(np.round(E / g, 9))) >= 5


@pytest.mark.parametrize("delayed", [True, False])
def test_kernel_with_minimised_energies_samples_the_boltzmann_weights(delayed):
    """With Newton energies, second-stage rejections are decided by a lower bound on the energy
    change before relaxing (counter ``bounded``); in the case where the deformation term weighs,
    the chain still samples the exact weights (of the same Newton energies, enumerated)."""
    particle, g, _, _ = case("double_deformation")
    c = CASES["double_deformation"]
    states, E = enumerate_states(kernel_mc(particle, g, c["box"], c["n"], 0, "newton", tol=1e-7), c["box"], c["n"])
    mc = kernel_mc(particle, g, c["box"], c["n"], 21, "newton", tol=1e-7, delayed_acceptance=delayed)
    statistics = compare_with_boltzmann(mc, states, E, T_OVER_G * g, g, SAMPLES)
    assert passes(statistics), statistics
    assert mc.counters["bounded"] > 0


def reference_statistics(name, wrong):
    particle, g, states, E = case(name)
    c = CASES[name]
    moves = c["moves"]
    isometry = {kind: moves[option] for kind, option in ISOMETRY_OPTIONS.items() if option in moves}
    chain = ReferenceChain(states, E, g, c["box"], surface_moves=moves.get("surface_moves", 0.0),
                           cluster_moves=moves.get("cluster_moves", 0.0), link=moves.get("cluster_link", 1.0),
                           isometry_moves=isometry, isometry_link=moves.get("isometry_link", 0.3),
                           vacancy_moves=moves.get("vacancy_moves", 0.0), wrong=wrong, seed=5)
    ids = chain.run(states[0], T_OVER_G * g, c.get("samples", SAMPLES))
    return boltzmann_statistics(ids, states, E, T_OVER_G * g, g)


@pytest.mark.parametrize("name", sorted(CASES))
def test_an_independent_chain_with_the_right_rules_passes(name):
    statistics = reference_statistics(name, None)
    assert passes(statistics), statistics


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_deliberately_wrong_rule_fails(name):
    """The case named after a wrong rule is where that rule shows: the statistic rejects it."""
    tv_states, tv_levels, z = reference_statistics(name, name)
    assert not passes((tv_states, tv_levels, z))
    assert z > 8, z  # with a margin: not a borderline rejection
