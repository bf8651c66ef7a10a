"""Tests of the candidate ground states of a Monte Carlo box (pyfrustrate.ground_states).

Independent references: the Monte Carlo kernel's own energy of each candidate placed in the box
(its cluster search, periodic wrapping and relaxation: a candidate that touched its image or
another aggregate, or was relaxed as the wrong scene, would disagree); the infinite straight
fibre's energy per particle (a period of one cell) for the fibre wrapping the box.
"""
import numpy as np
import pytest

from pyfrustrate import Hexagon, _kernel, relax, topology
from pyfrustrate.ground_states import BoxCandidates, box_bonds, box_candidates


@pytest.fixture(scope="module")
def particle():
    return Hexagon.from_continuum(ell=3, nu=0.9, eps=0.02)


@pytest.fixture(scope="module")
def candidates(particle):
    return box_candidates(particle, 60, 15)


def test_every_family_is_represented(candidates):
    families = set(candidates.family.tolist())
    assert {"single", "wrapping_fiber", "aggregates2", "aggregates3", "gas"} <= families


def test_each_candidate_is_a_configuration_of_the_box_with_the_kernels_energy(particle, candidates):
    mc = _kernel.MonteCarlo(particle._kernel_model, 0.0, candidates.box, candidates.n, 0, method="lbfgs",
                            tol=1e-8 * particle.force_scale)
    for k in range(len(candidates.family)):
        sites = candidates.sites[k]
        assert sites.shape == (candidates.n, 2) and len({tuple(s) for s in sites.tolist()}) == candidates.n
        mc.place(sites)
        assert mc.bonds == candidates.bonds[k], candidates.family[k]
        energy = mc.box_energy(True)
        # Absolute floor: the candidates are relaxed to tol 1e-5 of the force scale, which leaves
        # ~1e-9 where an aggregate is nearly stress-free (the bulk energy per particle is 0.011 here).
        floor = 1e-6 * candidates.n * particle.bulk_energy_per_particle
        assert energy == pytest.approx(candidates.deformation[k], rel=1e-5, abs=floor), candidates.family[k]


def test_box_bonds_counts_what_the_kernel_counts(particle, candidates):
    """The bonds of a configuration, counted in Python with periodic wrapping, against the Monte
    Carlo kernel's own count: every candidate, and random placements, sparse to dense, where
    pairs across the box's edges are common."""
    mc = _kernel.MonteCarlo(particle._kernel_model, 0.0, candidates.box, candidates.n, 0, method="linear")
    for sites in candidates.sites:
        mc.place(sites)
        assert box_bonds(sites, candidates.box) == mc.bonds == box_bonds(sites + 7 * candidates.box, candidates.box)
    rng = np.random.default_rng(5)
    for box, n in ((6, 30), (10, 20), (4, 15)):
        mc = _kernel.MonteCarlo(particle._kernel_model, 0.0, box, n, 0, method="linear")
        for _ in range(10):
            cells = rng.choice(box * box, size=n, replace=False)
            sites = np.column_stack([cells % box, cells // box])
            mc.place(sites)
            assert box_bonds(sites, box) == mc.bonds


def test_wrapping_fibre_has_the_infinite_fibres_energy_per_particle(particle, candidates):
    # 60 particles in a box of 15: four full rows wrapping the box.
    k = list(candidates.family).index("wrapping_fiber")
    cell = relax(particle, topology.fiber(4, 0, curved=False), method="newton", tol=1e-10)
    assert candidates.deformation[k] == pytest.approx(15 * cell.energy, rel=1e-6)
    assert candidates.bonds[k] == 15 * cell.n_bonds


def test_gas_wins_without_binding_and_the_best_is_the_lowest(candidates):
    assert candidates.best_family(0.0) == "gas"
    g = np.linspace(0, 0.05, 11)
    assert np.allclose(candidates.best_energy(g), candidates.total(g).min(axis=0))
    again = BoxCandidates.from_arrays(candidates.arrays())
    assert np.array_equal(again.best_energy(g), candidates.best_energy(g))


def test_a_box_too_small_for_the_gas_has_no_gas_candidate(particle):
    assert "gas" not in set(box_candidates(particle, 12, 5).family.tolist())


@pytest.mark.parametrize("n, box, message", [(0, 10, "n must"), (100, 10, "n must be smaller"), (10, 1, "box"),
                                            (None, 10, "n must be an integer"), (10, 7.5, "box must be an integer")])
def test_bad_input(particle, n, box, message):
    with pytest.raises(ValueError, match=message):
        box_candidates(particle, n, box)


def test_structure_of_each_candidate_is_its_family(candidates):
    # The candidates are built family by family; the structure is read from clusters alone.
    from pyfrustrate.ground_states import structure
    for family, sites in zip(candidates.family, candidates.sites):
        assert structure(sites, candidates.box) == family


def test_a_box_holding_many_small_best_aggregates_has_them_as_candidates():
    # Independent reference: the single aggregate of q particles with the lowest energy per
    # particle over every q (ansatz.finite_aggregates, q = 2 .. 30). With weak binding it is small,
    # and n = 6 q* particles can do no better than six copies of it (every candidate is made of
    # single aggregates, a wrapping fibre or the gas); with at most four aggregates the candidates
    # miss that state.
    from pyfrustrate import ansatz
    particle = Hexagon.from_continuum(ell=3, nu=0.4, eps=0.02)
    g = 1e-4
    per_particle = {}
    for q in range(2, 31):
        shapes = ansatz.finite_aggregates(particle, q)
        per_particle[q] = float(np.min(shapes.deformation - g * shapes.bonds)) / q
    q_best = min(per_particle, key=per_particle.get)
    assert q_best <= 10 and per_particle[q_best] < 0
    n = 6 * q_best
    six_copies = n * per_particle[q_best]
    candidates = box_candidates(particle, n, 30)
    assert candidates.best_energy(g) <= six_copies + 1e-12 * abs(six_copies)
    assert str(candidates.best_family(g)).startswith("aggregates")
    assert box_candidates(particle, n, 30, max_aggregates=4).best_energy(g) > six_copies + 1e-3 * abs(six_copies)


def test_aggregate_counts():
    from pyfrustrate.ground_states import aggregate_counts
    assert aggregate_counts(60, 4) == [2, 3, 4]
    counts = aggregate_counts(800)
    assert counts[:15] == list(range(2, 17)) and counts == sorted(set(counts))
    assert 800 // counts[-1] >= 7 and 800 // round(counts[-1] * 1.25) < 7
    with pytest.raises(ValueError, match="max_aggregates"):
        box_candidates(Hexagon.from_continuum(ell=3, nu=0.4, eps=0.02), 20, 10, max_aggregates=0)
