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
    # The candidates are built family by family; the structure is read from clusters alone. Fused
    # aggregates are one cluster.
    from pyfrustrate.ground_states import aggregate_count, family_structure, structure
    assert any(f.startswith("fused") for f in candidates.family)
    for family, sites in zip(candidates.family, candidates.sites):
        found = structure(sites, candidates.box)
        assert found == family_structure(family) == ("single" if family.startswith("fused") else family)
        assert aggregate_count(found) == aggregate_count(family)


def test_a_box_holding_many_small_best_aggregates_has_them_as_candidates():
    # Independent reference: the single aggregate of q particles with the lowest energy per
    # particle over every q (ansatz.finite_aggregates, q = 2 .. 30). With weak binding it is small,
    # and n = 6 q* particles can do no worse than six copies of it in a chain joined by five necks,
    # each worth g less a strain far below it (a neck of one bond is compliant); every other
    # candidate is made of single aggregates, apart or fused, a wrapping fibre or the gas. With at
    # most four aggregates the candidates miss that state.
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
    six_in_a_chain = six_copies - 5 * 0.9 * g
    assert candidates.best_energy(g) <= six_in_a_chain
    assert str(candidates.best_family(g)) in ("aggregates6", "fused6")
    assert box_candidates(particle, n, 30, max_aggregates=4).best_energy(g) > six_in_a_chain + 1e-3 * abs(six_copies)


def test_aggregate_counts():
    from pyfrustrate.ground_states import aggregate_counts
    assert aggregate_counts(60, 4) == [2, 3, 4]
    counts = aggregate_counts(800)
    assert counts[:15] == list(range(2, 17)) and counts == sorted(set(counts))
    assert 800 // counts[-1] >= 7 and 800 // round(counts[-1] * 1.25) < 7
    with pytest.raises(ValueError, match="max_aggregates"):
        box_candidates(Hexagon.from_continuum(ell=3, nu=0.4, eps=0.02), 20, 10, max_aggregates=0)


# Fused aggregates (the fused{m} family): disks joined by necks.

def bonds_between_by_distance(a, b) -> int:
    """Bound pairs between two sets of sites by brute force: pairs of centres one lattice spacing
    apart (Cartesian), independent of the neighbour table the placement uses."""
    xa, xb = topology.site_positions(np.asarray(a)), topology.site_positions(np.asarray(b))
    distance = np.linalg.norm(xa[:, None, :] - xb[None, :, :], axis=-1)
    assert distance.min() > 0.5, "copies overlap"
    return int((np.abs(distance - 1.0) < 1e-9).sum())


@pytest.mark.parametrize("m, pairs", [(2, 1), (3, 3), (4, 5), (7, 12)])
def test_fused_disks_touch_exactly_their_neighbours_at_one_bond(m, pairs):
    # Hexagonal disks on a compact triangular patch of m points (pair, triangle, rhombus, hexagon with
    # its centre) have `pairs` nearest-neighbour pairs; neighbouring disks meet corner to corner (one
    # bond: a hexagon's corner points along each lattice direction), the others not at all. A chain
    # touches only consecutive copies.
    from pyfrustrate.ground_states import fused_copies
    for R in (2, 3):
        disk = topology.hexagon_sites(R)
        copies = fused_copies(disk, m)
        centres = np.array([topology.site_positions(c).mean(axis=0) for c in copies])
        spacing = min(np.linalg.norm(centres[i] - centres[j]) for i in range(m) for j in range(i))
        touching = 0
        for i in range(m):
            for j in range(i):
                bonds = bonds_between_by_distance(copies[i], copies[j])
                neighbours = np.linalg.norm(centres[i] - centres[j]) < spacing + 1e-9
                assert bonds == (1 if neighbours else 0), (R, i, j)
                touching += neighbours
        assert touching == pairs
        chain = fused_copies(disk, m, arrangement="chain")
        for i in range(m):
            for j in range(i):
                assert bonds_between_by_distance(chain[i], chain[j]) == (1 if i - j == 1 else 0)


def test_fused_placement_of_every_part_shape_touches_without_overlap(particle):
    # The ansatz's part shapes, round and faceted, each copy the same shape (a translate), and a
    # remainder shape in the last place: the copies never overlap, each touches another (one
    # cluster), and neighbours along the placement's shifts touch.
    from pyfrustrate import ansatz
    from pyfrustrate.ground_states import ARRANGEMENTS, fused_copies
    from pyfrustrate.montecarlo import clusters
    shapes, remainder = ansatz.finite_aggregates(particle, 24), ansatz.finite_aggregates(particle, 26)
    for k, part in enumerate(shapes.sites):
        for arrangement in ARRANGEMENTS:
            for m in (2, 3, 4):
                copies = fused_copies(part, m, last=remainder.sites[k], arrangement=arrangement)
                if copies is None:
                    continue
                for i in range(m):
                    touches = [bonds_between_by_distance(copies[i], copies[j]) for j in range(m) if j != i]
                    assert max(touches) >= 1, (k, arrangement, m, i)
                for c in copies[:-1]:
                    assert sorted(map(tuple, (c - c.min(axis=0)).tolist())) == sorted(
                        map(tuple, (part - part.min(axis=0)).tolist()))
                assert len(copies[-1]) == 26
                assert len(clusters(np.concatenate(copies), 1000)) == 1


@pytest.fixture(scope="module")
def weak_tension():
    """ell = 5, nu = 0.4, Gamma = 0.2 (the large box's disk point where four separate disks were
    predicted, and a run seeded in them ended lower, joined by necks): particle, g."""
    from pyfrustrate import continuum
    return (Hexagon.from_continuum(5, 0.4, eps=0.01),
            float(continuum.particle_parameters(5, 0.4, 0.2, eps=0.01).g))


def test_a_fused_pair_strains_at_least_its_parts_and_adds_its_contact_bonds(weak_tension):
    # Binding two aggregates adds springs between them: the minimum of the whole can only be higher
    # than the two separate minima (an inequality that could fail if the pair were relaxed as the
    # wrong network), and its bonds are the parts' plus the contact's (counted by distance).
    from pyfrustrate import ansatz
    from pyfrustrate.ground_states import ARRANGEMENTS, LATTICE_DIRECTIONS, fused_copies, neck_shift
    particle, g = weak_tension

    def strain_per_bond(part, copy):
        alone = relax(particle, topology.cluster(part), method="newton", tol=1e-8)
        both = relax(particle, topology.cluster(np.concatenate([part, copy])), method="newton", tol=1e-8)
        contact = bonds_between_by_distance(part, copy)
        assert both.n_bonds == 2 * alone.n_bonds + contact
        assert both.energy >= 2 * alone.energy - 1e-8 * particle.bulk_energy_per_particle
        return contact, (both.energy - 2 * alone.energy) / contact

    for part in ansatz.finite_aggregates(particle, 37, method="newton", tol=1e-8).sites:
        pairs = [fused_copies(part, 2, arrangement=a) for a in ARRANGEMENTS]
        for a, b in pairs + [[part, part + neck_shift(part, d)] for d in LATTICE_DIRECTIONS]:
            strain_per_bond(a, b)
    # The physics the family rests on, for the best part of 100 at Gamma = 0.2 (the large box's
    # disks): a neck of one bond is compliant, its strain far below the bond's worth g; a flat
    # contact of several bonds ties the two outlines together and strains more than they are worth.
    parts = ansatz.finite_aggregates(particle, 100, method="newton", tol=1e-8)
    part = parts.sites[int(parts.best(g))]
    strains = dict(strain_per_bond(part, part + neck_shift(part, d)) for d in LATTICE_DIRECTIONS)
    assert strains[1] < 0.1 * g
    assert [c for c in strains if c >= 2] and all(s > g for c, s in strains.items() if c >= 2)


def test_at_weak_line_tension_disks_joined_by_a_neck_beat_separate_disks(weak_tension):
    # 200 particles, Gamma = 0.2: the best aggregate holds about 100 (four in the large box's 400),
    # so among separate aggregates two disks are best; a neck of one bond between them, relaxed on
    # its own here (the strain, against the bond's worth g), makes the box's ground state one cluster
    # of two disks fused by a neck, which the classifier reads as such.
    from pyfrustrate import ansatz
    from pyfrustrate.ground_states import aggregate_kind, fused_copies, structure, structure_verdict
    from pyfrustrate.montecarlo import clusters
    from pyfrustrate.montecarlo.analysis import compact_lobes
    particle, g = weak_tension
    n, box = 200, 45
    candidates = box_candidates(particle, n, box, max_aggregates=2, method="newton", tol=1e-8)
    apart = np.char.startswith(candidates.family.astype(str), "aggregates")
    assert candidates.family[apart][np.argmin(candidates.total(g)[apart])] == "aggregates2"
    parts = ansatz.finite_aggregates(particle, n // 2, method="newton", tol=1e-8)
    part = parts.sites[int(parts.best(g))]
    alone = relax(particle, topology.cluster(part), method="newton", tol=1e-8)
    a, b = fused_copies(part, 2, arrangement="chain")
    neck = bonds_between_by_distance(a, b)
    pair = relax(particle, topology.cluster(np.concatenate([a, b])), method="newton", tol=1e-8)
    strain = pair.energy - 2 * alone.energy
    assert neck == 1 and strain < g  # the bond is worth more than its strain
    best = int(candidates.best(g))
    assert candidates.family[best] == "fused2"
    two_apart = 2 * float(alone.energy - g * alone.n_bonds)
    assert candidates.best_energy(g) <= two_apart - (g - strain) + 1e-6 * particle.bulk_energy_per_particle
    sites = candidates.sites[best]
    assert structure(sites, box) == "single" and aggregate_kind(sites, box) == "fused_disks"
    assert len(compact_lobes(clusters(sites, box)[0][0])) == 2
    # A run in the two separate disks no longer has the predicted structure; one in the fused pair has.
    separate = candidates.sites[np.flatnonzero(apart)[np.argmin(candidates.total(g)[apart])]]
    e_bulk = particle.bulk_energy_per_particle
    verdict = structure_verdict(separate, box, candidates, g, candidates.best_energy(g) + g, e_bulk)
    assert (verdict["count"], verdict["count_predicted"], verdict["kind_predicted"]) == (2, 1, "fused_disks")
    assert not verdict["structure_match"]
    assert structure_verdict(sites, box, candidates, g, candidates.best_energy(g), e_bulk)["structure_match"]


def test_a_ring_of_necks_strains_and_a_chain_does_not(weak_tension):
    # Three disks pairwise at necks close a ring: the necks pin the disks' corners to a triangle of
    # fixed sides, which the frustrated disks (wider than the lattice says) cannot meet unstrained;
    # in a chain each neck is free to turn. Against the three disks relaxed apart.
    from pyfrustrate.ground_states import fused_copies
    particle, g = weak_tension
    disk = topology.hexagon_sites(5)
    apart = 3 * relax(particle, topology.cluster(disk), method="newton", tol=1e-8).energy
    strain = {}
    for arrangement, necks in (("compact", 3), ("chain", 2)):
        copies = fused_copies(disk, 3, arrangement=arrangement)
        assert sum(bonds_between_by_distance(copies[i], copies[j]) for i in range(3) for j in range(i)) == necks
        whole = relax(particle, topology.cluster(np.concatenate(copies)), method="newton", tol=1e-8)
        strain[arrangement] = (whole.energy - apart) / necks
    assert strain["chain"] < 0.1 * g < g < strain["compact"]


def test_box_candidates_without_holes_have_only_solid_shapes(particle):
    """hole_fraction = 0 keeps the solid family (the shapes that fit the box without touching
    themselves), and holes add candidates, never remove one."""
    solid = box_candidates(particle, 40, 12, max_aggregates=2, hole_fraction=0.0)
    holed = box_candidates(particle, 40, 12, max_aggregates=2)
    for family in ("single", "aggregates2"):
        assert np.count_nonzero(holed.family == family) > np.count_nonzero(solid.family == family) > 0
    g = np.linspace(0.0, 0.05, 11)
    assert np.all(holed.best_energy(g) <= solid.best_energy(g) + 1e-12)


def test_box_candidates_reuse_given_single_aggregates(particle):
    """Single aggregates relaxed beforehand (the finite-size rule's own) give the same candidates as
    those box_candidates relaxes itself; aggregates of another n are refused."""
    from pyfrustrate import ansatz
    own = box_candidates(particle, 40, 12, max_aggregates=2)
    given = box_candidates(particle, 40, 12, max_aggregates=2, single=ansatz.finite_aggregates(particle, 40))
    np.testing.assert_array_equal(given.family, own.family)
    np.testing.assert_allclose(given.deformation, own.deformation, rtol=1e-12)
    np.testing.assert_array_equal(given.bonds, own.bonds)
    with pytest.raises(ValueError, match="single"):
        box_candidates(particle, 41, 12, max_aggregates=2, single=ansatz.finite_aggregates(particle, 40))
