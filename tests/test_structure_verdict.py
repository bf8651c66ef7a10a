"""A large run judged by structure (``ground_states.structure_verdict``): count, kind and width
of the run against the box's predicted ground state, read by the same functions, and the energy
gate max(5 bulk energies, 2 bonds).

References: configurations built by hand (fibres of known rows, separate blobs, a compact disk),
whose counts, kinds and widths are known by construction; the predicted ground state judged
against itself.
"""
import numpy as np
import pytest

from pyfrustrate.ground_states import (EQUILIBRATED_GAP, GATE_BONDS, BoxCandidates, aggregate_structure, box_bonds,
                                       structure_verdict, width_in_rows)

BOX = 40


def rows(length, width, i0=0, j0=0):
    """``width`` rows of ``length`` particles along a1, stacked so that they form a straight strip
    (each row shifted back by half a step: i0 - j // 2)."""
    return np.array([(i0 + i - j // 2, j0 + j) for j in range(width) for i in range(length)])


def disk(radius, i0=0, j0=0):
    return np.array([(i0 + i, j0 + j) for i in range(-radius, radius + 1) for j in range(-radius, radius + 1)
                     if abs(i + j) <= radius])


def candidates_of(best_sites):
    """Two candidates of len(best_sites) particles: ``best_sites`` (deformation 0) and the gas."""
    n = len(best_sites)
    gas = np.array([(3 * (k % 13), 3 * (k // 13)) for k in range(n)])
    sites = (np.mod(best_sites, BOX), gas)
    return BoxCandidates(n, BOX, np.array(["single", "gas"]), np.zeros(2),
                         np.array([box_bonds(s, BOX) for s in sites]), sites, np.ones(2, bool))


@pytest.mark.parametrize("width", [1, 2, 3, 5])
def test_width_in_rows_counts_the_rows_of_a_strip_and_of_a_wrapping_fibre(width):
    assert width_in_rows(rows(30, width), BOX) == pytest.approx(width, abs=1e-9)
    assert width_in_rows(np.array(sorted(parallelogram(30, width))), BOX) == pytest.approx(width, abs=1e-9)
    assert width_in_rows([(i, j) for j in range(width) for i in range(BOX)], BOX) == pytest.approx(width, abs=1e-9)


def parallelogram(length, width, i0=0, j0=0):
    return {(i0 + i, j0 + j) for j in range(width) for i in range(length)}


def bent(width, angle, arm=24):
    """A fibre of ``width`` rows that turns by ``angle`` degrees: an arm along a1, then one along
    a2 (60) or a2 - a1 (120), sharing the corner."""
    first = parallelogram(30, width)
    if angle == 60:
        second = {(30 - width + i, j) for i in range(width) for j in range(arm)}
    else:
        second = {(29 - j - i, j) for j in range(arm) for i in range(width)}
    return np.array(sorted(first | second))


@pytest.mark.parametrize("width", [3, 6, 10, 13])
@pytest.mark.parametrize("angle", [60, 120])
def test_width_in_rows_reads_a_bent_fibre_by_its_arms(width, angle):
    # The arms' width is known by construction; the extent across the principal axis would read
    # the bend's span instead (twice to seven times the width for these shapes).
    assert width_in_rows(bent(width, angle), 200) == pytest.approx(width, abs=0.25)


def test_width_in_rows_refuses_a_bulk_and_reads_a_disk_as_compact():
    with pytest.raises(ValueError, match="both ways"):
        width_in_rows([(i, j) for i in range(6) for j in range(6)], 6)
    # A hexagonal disk of radius R is more compact than any strip of its n particles: the square
    # strip of its exposed sides, whose rows are at most sqrt(n).
    R = 6
    n = 3 * R * R + 3 * R + 1
    assert width_in_rows(disk(R), BOX) <= np.sqrt(n) + 1e-9


def fused_chain(disks, radius=3):
    """``disks`` hexagonal disks of ``radius`` in a row along a1, each touching the next at the
    ends of their middle rows (a neck)."""
    one = disk(radius)
    return np.unique(np.vstack([one + (5 + k * (2 * radius + 1), 12) for k in range(disks)]), axis=0)


def test_fused_disks_match_only_with_as_many_disks():
    # Disks fused by necks are one cluster whatever their number: the verdict counts the disks
    # (the compact lobes), so three fused disks are not the two predicted, and two are.
    predicted = fused_chain(2)
    c = candidates_of(predicted)
    g, bulk = 0.1, 0.05
    ground = -g * box_bonds(predicted, BOX)
    same = structure_verdict(predicted, BOX, c, g, ground, bulk)
    assert (same["kind"], same["lobes"], same["lobes_predicted"]) == ("fused_disks", 2, 2)
    assert same["structure_match"] and same["lobes_ok"] and same["width"] is None
    three = structure_verdict(fused_chain(3), BOX, c, g, ground, bulk)
    assert (three["count_ok"], three["kind"], three["lobes"], three["lobes_predicted"]) == (True, "fused_disks", 3, 2)
    assert not three["lobes_ok"] and not three["structure_match"]
    # Against a single disk: each side's own size is reported, the kind alone fails.
    one_disk = disk(7, 20, 20)
    against_disk = structure_verdict(fused_chain(3), BOX, candidates_of(one_disk), g, ground, bulk)
    assert (against_disk["lobes"], against_disk["lobes_predicted"], against_disk["width_predicted"]) == (3, None, None)
    assert not against_disk["kind_ok"] and against_disk["lobes_ok"] and not against_disk["structure_match"]


def test_aggregate_structure_reads_count_kind_and_size_of_shapes_built_by_hand():
    # What figX_mc_finite_size writes over its snapshots: a bent fibre by its arms' rows (the
    # gyration extent would read the bend's span), fused disks by how many disks, a disk by kind.
    count, kind, rows_read = aggregate_structure(bent(6, 60), 200)
    assert (count, kind) == (1, "fiber") and rows_read == pytest.approx(6, abs=0.25)
    assert aggregate_structure(fused_chain(3), BOX) == (1, "fused_disks", 3)
    blob = rows(3, 3, i0=2, j0=30)  # 9 particles, far from the disk: a second aggregate
    assert aggregate_structure(np.vstack([disk(4, 20, 12), blob]), BOX) == (2, "disk", None)


def test_the_prediction_judged_against_itself_matches_with_no_gap():
    fibre = rows(20, 3)
    c = candidates_of(fibre)
    g, bulk = 0.1, 0.05
    v = structure_verdict(fibre + (7, 5), BOX, c, g, -g * box_bonds(fibre, BOX), bulk)
    assert v["structure_match"] and v["gap_ok"] and v["gap"] == pytest.approx(0)
    assert not v["below_prediction"]
    # The same structure one bond (two bulk energies) lower than the prediction: the candidates
    # missed it; a hundredth of a bulk energy lower is relaxation, not a better state.
    ground = -g * box_bonds(fibre, BOX)
    assert structure_verdict(fibre, BOX, c, g, ground - g, bulk)["below_prediction"]
    assert not structure_verdict(fibre, BOX, c, g, ground - 0.01 * bulk, bulk)["below_prediction"]
    assert (v["count"], v["kind"]) == (1, "fiber") == (v["count_predicted"], v["kind_predicted"])
    assert v["width"] == pytest.approx(v["width_predicted"])
    assert v["gap_gate"] == pytest.approx(max(EQUILIBRATED_GAP, GATE_BONDS * g / bulk))


@pytest.mark.parametrize("run,field", [
    (rows(30, 2), None),                       # one row narrower: within the tolerance
    (rows(38, 1), "width_ok"),                 # two rows narrower
    (disk(3), "kind_ok"),                      # compact
    (np.vstack([rows(10, 3), rows(10, 3, 20, 20)]), "count_ok"),  # two fibres
])
def test_each_criterion_fails_alone(run, field):
    c = candidates_of(rows(20, 3))
    v = structure_verdict(run, BOX, c, 0.1, 0.0, 0.05)
    failed = [k for k in ("count_ok", "kind_ok", "width_ok") if not v[k]]
    assert failed == ([field] if field else [])
    assert v["structure_match"] == (field is None)


def test_the_energy_gate_takes_the_larger_of_five_bulk_energies_and_two_bonds():
    fibre = rows(20, 3)
    c = candidates_of(fibre)
    ground = -1.0 * box_bonds(fibre, BOX)
    # g = 1, bulk 0.1: two bonds are 20 bulk energies.
    assert structure_verdict(fibre, BOX, c, 1.0, ground + 1.9, 0.1)["gap_ok"]
    assert not structure_verdict(fibre, BOX, c, 1.0, ground + 2.1, 0.1)["gap_ok"]
    # g = 0.1, bulk 0.1: two bonds are 2, the gate 5 bulk energies.
    ground = -0.1 * box_bonds(fibre, BOX)
    assert structure_verdict(fibre, BOX, c, 0.1, ground + 0.49, 0.1)["gap_ok"]
    assert not structure_verdict(fibre, BOX, c, 0.1, ground + 0.51, 0.1)["gap_ok"]


def test_bad_input_is_refused_by_name():
    c = candidates_of(rows(20, 3))
    with pytest.raises(ValueError, match="box"):
        structure_verdict(rows(20, 3), BOX + 1, c, 0.1, 0.0, 0.05)
    with pytest.raises(ValueError, match="bulk_energy"):
        structure_verdict(rows(20, 3), BOX, c, 0.1, 0.0, 0.0)


def test_a_structure_within_the_gate_of_the_prediction_is_told_from_one_outside_it():
    """Two fibres where one is predicted: the strict match fails either way; the run's structure
    counts as within the gate only when the box's two-fibre candidate lies within the gate of the
    prediction (its deformation set by hand to 4 or to 6 bulk energies above the fibre's)."""
    fibre, two = rows(20, 3), np.vstack([rows(10, 3), rows(10, 3, 20, 20)])
    g, bulk = 0.1, 0.05
    gate = max(EQUILIBRATED_GAP, GATE_BONDS * g / bulk)
    run = np.vstack([rows(10, 3, 1, 2), rows(10, 3, 21, 22)])  # two fibres, elsewhere
    for above, within in ((gate - 1, True), (gate + 1, False)):
        # The two-fibre candidate's energy above the fibre's: its bonds' difference plus a deformation.
        deformation = above * bulk - g * (box_bonds(fibre, BOX) - box_bonds(two, BOX))
        c = BoxCandidates(len(fibre), BOX, np.array(["single", "aggregates2"]), np.array([0.0, deformation]),
                          np.array([box_bonds(fibre, BOX), box_bonds(two, BOX)]),
                          (np.mod(fibre, BOX), np.mod(two, BOX)), np.ones(2, bool))
        v = structure_verdict(run, BOX, c, g, 0.0, bulk)
        assert not v["structure_match"] and not v["count_ok"]
        assert v["structure_within_gate"] == within
        assert v["candidates_within_gate"] == (2 if within else 1)
        # The prediction itself is always among the candidates within its gate.
        assert structure_verdict(fibre, BOX, c, g, 0.0, bulk)["structure_within_gate"]


@pytest.mark.parametrize("width", [3, 6])
def test_a_fibre_bent_by_120_degrees_with_similar_arms_reads_as_a_disk(width):
    # A known limit of the kind (gyration anisotropy), stated in docs/topics/montecarlo.md: the
    # width would be read right, the kind is not. A change of classifier that reads the bend must
    # update that page.
    assert aggregate_structure(bent(width, 120, arm=24), 200)[1] == "disk"
    assert aggregate_structure(bent(width, 60, arm=24), 200)[1] == "fiber"


def test_figX_mc_finite_size_measures_a_bent_fibre_by_its_arms():
    """(a) and (b) of figX_mc_finite_size plot a fibre's gyration measure as that of the straight
    strip of its rows: a fibre of 6 rows bent by 60 degrees plots the width of a straight strip of
    6 rows built here (within a row's spacing), where its own gyration tensor reads the span of the
    bend, more than twice as wide; a disk keeps its own gyration measure."""
    import importlib.util
    from pathlib import Path

    from pyfrustrate.topology import gyration_dimensions
    path = Path(__file__).resolve().parents[1] / "figures" / "figX_mc_finite_size.py"
    spec = importlib.util.spec_from_file_location("figX_mc_finite_size", path)
    figure = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(figure)
    fibre = bent(6, 60)
    plotted_width, plotted_length = figure.plotted_dimensions(dict(sites=fibre, box=200))
    straight_width, straight_length = gyration_dimensions(rows(len(fibre) // 6, 6))
    assert plotted_width == pytest.approx(straight_width, abs=np.sqrt(3) / 2)
    assert plotted_length == pytest.approx(straight_length, rel=0.1)
    assert gyration_dimensions(fibre)[0] > 2 * plotted_width
    compact = disk(7, 20, 20)
    assert figure.plotted_dimensions(dict(sites=compact, box=BOX)) == pytest.approx(gyration_dimensions(compact), rel=1e-12)
