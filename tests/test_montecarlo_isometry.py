"""Collective isometry moves (``kernel/montecarlo/isometry_move.hpp``): a linked set shifted to a
neighbouring site, turned by +-60 degrees about its seed particle's site, or mirrored about an
axis through it.

References: the maps written as integer matrices of lattice coordinates and checked on Cartesian
geometry (a turn by 60 degrees, six mirrors, each sending the hexagon's corners onto its corners,
neighbours to neighbours and the box's periods to periods); exact Boltzmann weights of every
configuration of a small box (``test_montecarlo.compare_with_boltzmann``), sampled by each family
alone; a recomputation of the energy from scratch along an anneal. ``test_montecarlo_rules.py``
shows the same statistic rejecting a chain without the factor (1 - link)^(b' - b), or with b'
counted against the set's old sites.
"""
import itertools

import numpy as np
import pytest

import pyfrustrate
from pyfrustrate import Hexagon, continuum
from pyfrustrate import topology as T
from pyfrustrate.montecarlo import MonteCarloOptions

from montecarlo_reference import MIRRORS, TURNS
from test_montecarlo import assert_running_totals, compare_with_boltzmann, enumerate_states, kernel_mc

SQRT3 = np.sqrt(3.0)
BASIS = np.array([[1.0, 0.5], [0.0, SQRT3 / 2]])  # columns a1, a2
FAMILIES = ("shift_moves", "rotation_moves", "reflection_moves")


def cartesian_map(linear):
    """The Cartesian matrix of an integer map of lattice coordinates."""
    return BASIS @ linear @ np.linalg.inv(BASIS)


def test_the_turns_and_mirrors_are_the_lattice_isometries_about_a_site():
    """The reference's integer maps are a rotation by +60 and -60 degrees and six distinct
    mirrors (orthogonal, determinant -1, involutions) in Cartesian coordinates."""
    for linear, angle in zip(TURNS, (60, -60)):
        c, s = np.cos(np.deg2rad(angle)), np.sin(np.deg2rad(angle))
        np.testing.assert_allclose(cartesian_map(linear), [[c, -s], [s, c]], atol=1e-12)
    axes = set()
    for linear in MIRRORS:
        m = cartesian_map(linear)
        np.testing.assert_allclose(m @ m.T, np.eye(2), atol=1e-12)
        assert np.linalg.det(m) == pytest.approx(-1)
        np.testing.assert_array_equal(linear @ linear, np.eye(2, dtype=int))
        w, v = np.linalg.eigh(0.5 * (m + m.T))
        axis = v[:, np.argmax(w)]  # the mirror's fixed line
        axes.add(round(np.rad2deg(np.arctan2(axis[1], axis[0])) % 180, 6))
    assert len(axes) == 6


@pytest.mark.parametrize("box", [3, 4, 7])
def test_each_isometry_maps_the_box_and_the_hexagon_to_themselves(box):
    """About any site of an L x L box: periods go to periods, the six neighbour vectors to
    neighbour vectors (bonds inside a moved set are kept), and the hexagon's six corners (at 30 +
    60 k degrees, circumradius 1/sqrt(3)) onto the image hexagon's corners."""
    corners = np.array([[np.cos(a), np.sin(a)] for a in np.deg2rad(30 + 60 * np.arange(6))]) / SQRT3
    neighbours = {tuple(int(x) for x in d) for d in T.NEIGHBOURS}
    for linear in TURNS + MIRRORS:
        for period in ((box, 0), (0, box)):
            assert np.all(linear @ np.array(period) % box == 0)
        assert {tuple(int(x) for x in linear @ np.array(d)) for d in neighbours} == neighbours
        turned = corners @ cartesian_map(linear).T
        distance = np.linalg.norm(turned[:, None, :] - corners[None, :, :], axis=2)
        assert np.all(distance.min(axis=1) < 1e-12)


def sensitive_particle(Gamma=0.1):
    """eps = 0.05: deformation energies weigh at T = 0.5 g (test_montecarlo.sensitive_particle)."""
    return (Hexagon.from_continuum(ell=5, nu=0.9, eps=0.05),
            float(continuum.particle_parameters(5, 0.9, Gamma, eps=0.05).g))


_STATES = {}


def states_of(box, n):
    if (box, n) not in _STATES:
        particle, g = sensitive_particle()
        _STATES[box, n] = enumerate_states(kernel_mc(particle, g, box, n, 0), box, n)
    return _STATES[box, n]


@pytest.mark.parametrize("family,box,n,link,delayed", [
    ("shift_moves", 4, 3, 0.5, True), ("rotation_moves", 4, 3, 0.5, False), ("rotation_moves", 3, 4, 0.8, True),
    ("reflection_moves", 4, 3, 0.8, True), ("reflection_moves", 3, 4, 0.5, False)])
def test_each_family_keeps_the_boltzmann_weights(family, box, n, link, delayed):
    """Most moves of one family (a 4 x 4 box of three particles, where sets meet and leave the
    rest, and a 3 x 3 one of four, where most turns collide): the chain samples exp(-E/T)
    exactly, its sets making and breaking bonds with the rest."""
    particle, g = sensitive_particle()
    states, E = states_of(box, n)
    mc = kernel_mc(particle, g, box, n, 17, delayed_acceptance=delayed, isometry_link=link, **{family: 0.8})
    tv_states, tv_levels, z = compare_with_boltzmann(mc, states, E, 0.5 * g, g, 200_000)
    prefix = family.split("_")[0]
    c = mc.counters
    assert c[f"{prefix}_attempted"] == pytest.approx(0.8 * c["attempted"], rel=0.02)
    assert c[f"{prefix}_rebonded"] > 500, c
    assert mc.energy == pytest.approx(mc.box_energy(True), rel=0, abs=1e-12)
    assert len(np.unique(np.round(E / g, 9))) >= 5
    assert z < 5 and tv_levels < 0.02 and tv_states < 0.06, (tv_states, tv_levels, z)


@pytest.mark.parametrize("method,kw", [("linear", {}), ("newton", dict(parent_start=True, parent_factor=True))])
def test_isometry_moves_keep_the_incremental_bookkeeping(method, kw):
    """Along an anneal mixing every family (sets turned and mirrored in place, overlapping their
    images; with Newton, warm starts from the stored displacements of the sites they keep), the
    running energy and bonds equal a recomputation from scratch."""
    particle, g = sensitive_particle(0.5)
    box, n = 12, 40
    mc = kernel_mc(particle, g, box, n, 6, method, tol=1e-7, shift_moves=0.2, rotation_moves=0.2, reflection_moves=0.2,
                   isometry_link=0.5, cluster_moves=0.05, cluster_link=0.9, surface_moves=0.3, **kw)
    assert_running_totals(mc, particle, box, n, np.linspace(g, 0.1 * g, 8), 400, 1e-9)
    c = mc.counters
    assert min(c["shift_rebonded"], c["rotation_rebonded"], c["reflection_rebonded"]) > 10, c


def test_turns_and_mirrors_refuse_the_triangle_tiling():
    """A 60-degree turn or a mirror about a triangle's centre does not map triangles onto
    triangles: the chain refuses the move by name; shifts (lattice translations) are fine."""
    particle = pyfrustrate.Triangle.from_continuum(2.5, 0.6, eps=0.05)
    g = float(continuum.particle_parameters(2.5, 0.6, 0.5, eps=0.05, tiling="triangle").g)
    for family in ("rotation_moves", "reflection_moves"):
        mc = kernel_mc(particle, g, 6, 10, 3, bond_deformation=0.0, **{family: 0.5})
        with pytest.raises(ValueError, match=f"{family}.*triangle tiling"):
            mc.run(np.array([g]), np.array([50]))
    mc = kernel_mc(particle, g, 6, 10, 3, bond_deformation=0.0, shift_moves=0.5)
    mc.run(np.array([g]), np.array([500]))
    assert mc.counters["shift_accepted"] > 0
    assert mc.energy == pytest.approx(mc.box_energy(True), rel=0, abs=1e-12)


def test_options_check_the_isometry_fields():
    """The fields come from the kernel's table: ranges checked, named in the error."""
    options = MonteCarloOptions(rotation_moves=0.1, reflection_moves=0.1, shift_moves=0.1, isometry_link=0.5)
    assert options.rotation_moves == 0.1 and options.isometry_link == 0.5
    for name, bad in itertools.product((*FAMILIES, "isometry_link"), (-0.1, 1.5, float("nan"))):
        with pytest.raises(ValueError, match=name):
            MonteCarloOptions(**{name: bad})


# The carry: a set grown with cluster_link translated by a cell vector of at most three neighbour
# steps (kCarryRadius), so that disks and lobes slide a few sites as one.

def carry_vectors(radius=3):
    """Every non-zero cell vector of at most ``radius`` neighbour steps (the reference set)."""
    return {(i, j) for i in range(-radius, radius + 1) for j in range(-radius, radius + 1)
            if 1 <= max(abs(i), abs(j), abs(i + j)) <= radius}


def test_carry_vectors_reach_three_steps_and_are_closed_under_negation():
    """The reference set of the carry's displacements: 3 R (R + 1) = 36 vectors, symmetric, and
    each is a sum of at most three neighbour vectors and no fewer than its hexagonal distance."""
    vectors = carry_vectors()
    assert len(vectors) == 36 and {(-i, -j) for i, j in vectors} == vectors
    neighbours = [tuple(int(x) for x in d) for d in T.NEIGHBOURS]
    reach, frontier = {(0, 0): 0}, [(0, 0)]
    for steps in (1, 2, 3):  # breadth-first: the fewest neighbour steps to each vector
        frontier = [(a + di, b + dj) for a, b in frontier for di, dj in neighbours if (a + di, b + dj) not in reach]
        reach.update({v: steps for v in frontier})
    assert vectors == {v for v, steps in reach.items() if steps >= 1}


@pytest.mark.parametrize("box,n,link,delayed", [(4, 3, 0.5, True), (4, 3, 0.8, False), (3, 4, 0.5, True)])
def test_carry_keeps_the_boltzmann_weights(box, n, link, delayed):
    """Most moves carries (sets grown with cluster_link, translated up to three steps, which
    wrap round the small box): the chain samples exp(-E/T) exactly, its sets making and breaking
    bonds with the rest; isometry_link does not enter."""
    particle, g = sensitive_particle()
    states, E = states_of(box, n)
    mc = kernel_mc(particle, g, box, n, 23, delayed_acceptance=delayed, cluster_link=link, isometry_link=0.01,
                   carry_moves=0.8)
    tv_states, tv_levels, z = compare_with_boltzmann(mc, states, E, 0.5 * g, g, 200_000)
    c = mc.counters
    assert c["carry_attempted"] == pytest.approx(0.8 * c["attempted"], rel=0.02)
    assert c["carry_rebonded"] > 500, c
    assert mc.energy == pytest.approx(mc.box_energy(True), rel=0, abs=1e-12)
    assert z < 5 and tv_levels < 0.02 and tv_states < 0.06, (tv_states, tv_levels, z)


@pytest.mark.parametrize("method,kw", [("linear", {}), ("newton", dict(parent_start=True, parent_factor=True))])
def test_carry_keeps_the_incremental_bookkeeping(method, kw):
    """Along an anneal with carries beside the other moves (whole clusters carried rigidly,
    others joining and leaving), the running energy and bonds equal a recomputation from scratch."""
    particle, g = sensitive_particle(0.5)
    box, n = 12, 40
    mc = kernel_mc(particle, g, box, n, 8, method, tol=1e-7, carry_moves=0.2, shift_moves=0.1, cluster_moves=0.05,
                   cluster_link=0.9, surface_moves=0.3, **kw)
    assert_running_totals(mc, particle, box, n, np.linspace(g, 0.1 * g, 8), 400, 1e-9)
    assert mc.counters["carry_rebonded"] > 10, mc.counters
    with pytest.raises(ValueError, match="carry_moves"):
        MonteCarloOptions(carry_moves=1.5)
