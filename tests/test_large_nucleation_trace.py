"""benchmarks/bench_large_nucleation.py, the trace of the large runs' nucleation (issue 33, item 3):
what it records of one configuration, counted against configurations built with known clusters,
and the summary it draws from a trace, against a trace written by hand."""
import importlib.util
import sys
from pathlib import Path

import numpy as np

from pyfrustrate import topology

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
spec = importlib.util.spec_from_file_location("bench_large_nucleation", ROOT / "benchmarks" / "bench_large_nucleation.py")
bench = importlib.util.module_from_spec(spec)
spec.loader.exec_module(bench)

BOX = 40


def indices(sites):
    """The kernel's site indices i + box j of lattice coordinates, taken modulo the box."""
    sites = np.asarray(sites) % BOX
    return sites[:, 0] + BOX * sites[:, 1]


def test_separate_disks_are_nuclei_and_the_isolated_particles_are_free():
    """Two disks of radius 2 (3 R^2 + 3 R + 1 = 19 particles each) far apart, a pair and three
    isolated particles: two nuclei of at least 10, the sizes in order, three free, one lobe."""
    disk = topology.hexagon_sites(2)
    sites = np.vstack([disk + (5, 5), disk + (20, 5), [(30, 30), (31, 30)], [(10, 30), (35, 15), (2, 20)]])
    row = bench.cluster_row(indices(sites), BOX, nucleus=10)
    assert row == dict(nuclei=2, size1=19, size2=19, size3=2, size4=1, free=3, lobes=1)
    assert bench.cluster_row(indices(sites), BOX, nucleus=20)["nuclei"] == 0


def test_disks_joined_by_a_neck_are_one_nucleus_of_two_lobes():
    """The same two disks moved next to each other along a row (compact_lobes' own example):
    one cluster of 38, read as two lobes; a third disk apart is a second nucleus."""
    disk = topology.hexagon_sites(2)
    sites = np.vstack([disk + (5, 5), disk + (10, 5), disk + (25, 25)])
    row = bench.cluster_row(indices(sites), BOX, nucleus=10)
    assert (row["nuclei"], row["size1"], row["size2"], row["lobes"], row["free"]) == (2, 38, 19, 2, 0)


def test_summary_reads_the_first_nucleus_the_most_and_the_last_stage():
    """A hand-written trace: nuclei appear at the second record, peak at four, and the last stage
    (T = 0.3) holds 3, 2, 2, 1 of them: its second half averages 1.5, between 1 and 2."""
    def record(sweep, T, nuclei, energy, free, size1=50, lobes=1):
        return dict(sweep=sweep, T_over_g=T, energy_over_g=str(energy), nuclei=nuclei, size1=size1, size2=0, size3=0,
                    size4=0, free=free, lobes=lobes)

    rows = [record(20, "1.0000", 0, -10.0, 90), record(40, "0.6000", 2, -50.0, 60),
            record(60, "0.6000", 4, -60.0, 40), record(80, "0.3000", 3, -80.0, 2),
            record(100, "0.3000", 2, -90.0, 0), record(120, "0.3000", 2, -92.0, 1),
            record(140, "0.3000", 1, -94.0, 1, size1=100, lobes=2)]
    s = bench.summary(rows)
    assert (s["first_nucleus_sweep"], s["first_nucleus_T_over_g"]) == (40, "0.6000")
    assert (s["nuclei_most"], s["nuclei_most_T_over_g"], s["last_several_sweep"]) == (4, "0.6000", 120)
    assert (s["last_T_over_g"], s["last_nuclei_mean"], s["last_nuclei_least"], s["last_nuclei_most"]) == \
        ("0.3000", "1.5", 1, 2)
    assert (s["last_energy_over_g"], s["last_free_mean"]) == ("-93.0", "1.0")
    assert (s["end_nuclei"], s["end_largest"], s["end_lobes"]) == (1, 100, 2)


def test_the_benchmarks_moves_are_the_workflows_large_runs():
    """bench_large_control.MOVES (which bench_large_nucleation and bench_large_merging run) are
    the moves config/config.yaml gives the large box's runs: a move family added to the workflow
    and not to the benchmarks would leave their tables measuring another chain."""
    import yaml
    mc = yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["montecarlo"]
    expected = dict(method=mc["large_method"], cluster_moves=mc["cluster_moves"], cluster_link=mc["cluster_link"],
                    bonded_moves=mc["large_bonded_moves"], surface_moves=mc["large_surface_moves"],
                    **{k: v for k, v in mc["large_collective"].items() if k.endswith("_moves") or k.endswith("_link")})
    moves = {k: v for k, v in bench.MOVES.items() if k != "tol"}
    assert moves == expected
