"""Tests of fixed-size sampling of single aggregates (pyfrustrate.montecarlo.fixed_size).

Independent references: the seeds' shapes counted site by site and their bonds by
``ground_states.box_bonds`` (a count of its own, not the kernel's) against the closed forms (a
straight fibre of W rows wrapping a period L: 3 L W - 2 L bonds; the compact disk: Harary and
Harborth's most bonds); the chain's energy of a seeded fibre or disk against ``relax`` of the same
aggregate built as a topology (another path through the kernel: a periodic fibre with a free period
length, or a finite cluster) and unchanged by a T = 0 run; the optimum's extraction on synthetic
energies with a known minimum; the ansatz's best straight fibre against the continuum's optimal
width and its best disk against the catalogue's winner among disks.
"""
import numpy as np
import pytest

from pyfrustrate import Hexagon, ansatz, relax, topology
from pyfrustrate.ground_states import box_bonds
from pyfrustrate.montecarlo import binding, clusters
from pyfrustrate.montecarlo import fixed_size as fs

ELL = 5.0


@pytest.fixture(scope="module")
def fibre_particle():
    return Hexagon.from_continuum(ell=ELL, nu=0.9, eps=0.01)


@pytest.fixture(scope="module")
def options():
    return fs.fixed_size_options(method="newton", tol=1e-6)


@pytest.mark.parametrize("length, width", [(8, 1), (8, 3), (11, 6), (20, 15)])
def test_fibre_seed_is_full_rows_wrapping_the_box(length, width):
    sites = fs.fibre_seed(length, width)
    assert sites.shape == (length * width, 2)
    assert len({tuple(s) for s in (sites % length).tolist()}) == length * width
    # Rows 0 .. width - 1, each holding every column once.
    rows = np.bincount(sites[:, 1], minlength=length)
    assert rows[:width].tolist() == [length] * width and not rows[width:].any()
    assert all(sorted(sites[sites[:, 1] == j, 0].tolist()) == list(range(length)) for j in range(width))
    # In-row bonds L W, two between neighbouring rows per column: 3 L W - 2 L.
    assert box_bonds(sites, length) == 3 * length * width - 2 * length
    (cluster, rank), = clusters(sites, length)
    assert len(cluster) == length * width and rank == 1  # one aggregate, wrapping one way


@pytest.mark.parametrize("n", [7, 20, 61, 100])
def test_disk_seed_is_one_compact_aggregate_with_the_most_bonds(n):
    box = fs.disk_box(n, margin=3)
    sites = fs.disk_seed(n, box)
    assert sites.shape == (n, 2) and len({tuple(s) for s in sites.tolist()}) == n
    assert sites.min() >= 0 and sites.max() < box
    assert box_bonds(sites, box) == topology.most_bonds(n)
    (cluster, rank), = clusters(sites, box)
    assert len(cluster) == n and rank == 0
    # Three empty rows on each side along every lattice direction: the margin asked for.
    i, j = sites.T
    assert box - max(np.ptp(i), np.ptp(j), np.ptp(i + j)) - 1 == 6


@pytest.mark.parametrize("n", [14, 61, 331])
def test_two_disks_seed_is_one_disk_against_two_halves_in_one_box(n):
    one, two, box = fs.two_disks_seed(n, margin=3)
    for sites in (one, two):
        assert sites.shape == (n, 2) and len({tuple(s) for s in (sites % box).tolist()}) == n
        assert sites.min() >= 0 and sites.max() < box
    assert [(len(c), rank) for c, rank in clusters(one, box)] == [(n, 0)]
    assert sorted(len(c) for c, rank in clusters(two, box) if rank == 0) == sorted([n // 2, n - n // 2])
    # Each half is compact (the most bonds of its size) and the halves do not touch.
    assert box_bonds(two, box) == topology.most_bonds(n // 2) + topology.most_bonds(n - n // 2)
    assert box_bonds(one, box) == topology.most_bonds(n)


@pytest.mark.parametrize("width, length", [(1, 3), (3, 6), (15, 24)])
def test_fibre_and_disk_seeds_hold_as_many_particles_in_one_box(width, length):
    fibre, disk, box = fs.fibre_and_disk_seeds(width, length, margin=3)
    n = box * width
    assert box >= length and fibre.shape == disk.shape == (n, 2)
    assert [(len(c), rank) for c, rank in clusters(fibre, box)] == [(n, 1)]  # wraps one way
    assert [(len(c), rank) for c, rank in clusters(disk, box)] == [(n, 0)]  # finite
    assert box_bonds(disk, box) == topology.most_bonds(n)
    # The smallest such box: one side less cannot hold the disk of its own fibre with the margin.
    assert box == length or fs.disk_box((box - 1) * width, 3) > box - 1


@pytest.mark.parametrize("n", [19, 100, 331])
def test_disk_and_fibre_seeds_fill_rows_of_the_disk_box(n):
    disk, fibre, box = fs.disk_and_fibre_seeds(n, margin=3)
    assert box == fs.disk_box(n, 3) and disk.shape == fibre.shape == (n, 2)
    assert [(len(c), rank) for c, rank in clusters(disk, box)] == [(n, 0)]
    (cluster, rank), = clusters(fibre, box)
    assert len(cluster) == n and rank == 1
    rows = np.bincount(fibre[:, 1])
    assert (rows[:-1] == box).all() and 0 < rows[-1] <= box  # full rows, the last one partly
    # Full rows as in a fibre (3 L W - 2 L); a partial row of r particles adds r - 1 bonds in the
    # row (it does not wrap) and two per particle to the full row below.
    full, r = divmod(n, box)
    expected = 3 * box * full - 2 * box + (3 * r - 1 if r else 0)
    assert box_bonds(fibre, box) == expected


def _point(fibre_energy, disk_energy, W=15, n=331, nu=0.5, Gamma=0.5):
    return dict(fibre_energy_per_particle=fibre_energy, disk_energy_per_particle=disk_energy, W_ansatz=W,
                n_ansatz=n, nu=nu, Gamma=Gamma)


def test_two_sided_seeds_pit_the_predicted_kind_against_its_competitor():
    fibre_wins = _point([-1.0, -2.0, -1.5], [-1.2, -1.9])
    disk_wins = _point([-1.0, -1.8], [-1.2, -1.9, -1.85])
    assert fs.ansatz_margin(fibre_wins) == pytest.approx(0.1) and fs.predicted_kind(fibre_wins) == "fibre"
    assert fs.ansatz_margin(disk_wins) == pytest.approx(-0.1) and fs.predicted_kind(disk_wins) == "disk"
    seeds = fs.two_sided_seeds(fibre_wins, "other_kind", fibre_length=24, margin=3)
    assert seeds["predicted_kind"] == "fibre" and seeds["competitor_state"] == "one disk"
    assert [rank for _, rank in clusters(seeds["predicted"], seeds["box"])] == [1]
    assert [rank for _, rank in clusters(seeds["competitor"], seeds["box"])] == [0]
    seeds = fs.two_sided_seeds(disk_wins, "other_kind", fibre_length=24, margin=3)
    assert seeds["n"] == 331 and seeds["competitor_state"] == "a fibre wrapping the box"
    seeds = fs.two_sided_seeds(disk_wins, "two_disks", fibre_length=24, margin=3)
    assert sorted(len(c) for c, _ in clusters(seeds["competitor"], seeds["box"])) == [165, 166]
    with pytest.raises(ValueError, match="predicts a fibre"):
        fs.two_sided_seeds(fibre_wins, "two_disks", fibre_length=24)
    with pytest.raises(ValueError, match="competitor must be one of"):
        fs.two_sided_seeds(fibre_wins, "three_disks", fibre_length=24)


@pytest.mark.parametrize("kind, outside, wraps, expected", [
    ("fibre", 0, 1, True), ("fibre", 0, 0, False), ("fibre", 2, 1, False),
    ("disk", 0, 0, True), ("disk", 0, 1, False), ("disk", 1, 0, False)])
def test_persists_asks_one_aggregate_of_the_seeded_kind(kind, outside, wraps, expected):
    assert fs.persists(kind, outside, wraps) is expected


def test_seeded_fibre_energy_is_the_relaxed_straight_fibre_and_stays_at_zero_temperature(fibre_particle, options):
    length, width = 8, 3
    g = binding(fibre_particle, Gamma=0.5)
    sites = fs.fibre_seed(length, width)
    state = fs.seeded_state(fibre_particle, sites, length, 7, g=g, options=options)
    fibre = topology.Topology("fiber", sites, "fiber", np.array([(length, 0), (0, 0)]), curved=False)
    r = relax(fibre_particle, fibre, tol=1e-8)
    assert r.converged and r.n_bonds == 3 * length * width - 2 * length
    assert state.chain.deformation == pytest.approx(r.energy, rel=1e-7)
    # At T = 0 a perfect fibre has no move that lowers its energy: it stays, energy and all.
    result = fs.sample(fibre_particle, sites, length, 7, g=g, schedule=[(0.0, 40 * len(sites))], options=options)
    assert result.energy == pytest.approx(r.energy - g * r.n_bonds, rel=1e-7)
    assert result.bonds == r.n_bonds and result.outside == 0 and result.wraps == 1
    assert sorted(map(tuple, result.result.sites.tolist())) == sorted(map(tuple, sites.tolist()))


def test_seeded_disk_energy_is_the_relaxed_cluster(fibre_particle, options):
    n = 19
    box = fs.disk_box(n)
    sites = fs.disk_seed(n, box)
    state = fs.seeded_state(fibre_particle, sites, box, 3, g=0.0, options=options)
    r = relax(fibre_particle, topology.cluster(sites), tol=1e-8)
    assert state.chain.deformation == pytest.approx(r.energy, rel=1e-7)
    # The seed with 19 particles is the complete hexagon of radius 2.
    assert r.n_bonds == topology.disk(2).n_bonds


def test_a_held_sample_is_counted_consistently(fibre_particle, options):
    """A short hold and quench: the final energy and bonds are those of the final sites."""
    g = binding(fibre_particle, Gamma=0.5)
    n = 30
    box = fs.disk_box(n)
    schedule = fs.sample_schedule(0.4 * g, n, hold_sweeps=4, cool_sweeps=4, quench_sweeps=2)
    s = fs.sample(fibre_particle, fs.disk_seed(n, box), box, 5, g=g, schedule=schedule, options=options)
    assert s.moves == sum(steps for _, steps in schedule) and s.n == n
    assert s.bonds == box_bonds(s.result.sites, box)
    parts = clusters(s.result.sites, box)
    assert s.outside == n - len(parts[0][0])
    deformation = sum(relax(fibre_particle, topology.cluster(c), tol=1e-8).energy for c, _ in parts if len(c) > 1)
    assert s.energy == pytest.approx(deformation - g * s.bonds, rel=1e-6)
    assert s.energy_per_particle == pytest.approx(s.energy / n)


def test_size_of_lowest_energy_finds_a_known_minimum():
    # e(W) = -1 + a / W + b W^2 has its minimum at (a / (2 b))^(1/3) = 12 exactly.
    b = 1e-4
    a = 2 * b * 12.0**3
    sizes = np.array([15, 6, 9, 12, 18, 10, 13, 11, 14])
    assert fs.size_of_lowest_energy(sizes, -1 + a / sizes + b * sizes**2) == (12.0, True)
    # Noise smaller than the curve's step does not move it; a minimum on the edge is flagged.
    rng = np.random.default_rng(0)
    noisy = -1 + a / sizes + b * sizes**2 + rng.normal(0, 1e-6, sizes.size)
    assert fs.size_of_lowest_energy(sizes, noisy) == (12.0, True)
    assert fs.size_of_lowest_energy([6, 8, 10], -1 + a / np.array([6, 8, 10]) + b * np.array([6, 8, 10])**2) == \
        (10.0, False)


def test_fitted_optimum_averages_noise_over_the_scan():
    # A parabola in log(size) with its vertex between grid points, plus noise that moves the
    # lowest sample.
    sizes = np.arange(9, 22)
    exact = 0.05 * np.log(sizes / 15.4) ** 2
    assert fs.fitted_optimum(sizes, exact) == pytest.approx(15.4, rel=1e-9)
    rng = np.random.default_rng(3)
    lowest, fitted = [], []
    for _ in range(50):
        noisy = exact + rng.normal(0, 3e-4, sizes.size)
        lowest.append(fs.size_of_lowest_energy(sizes, noisy)[0])
        fitted.append(fs.fitted_optimum(sizes, noisy))
    # The noise moves the lowest sample by rows, the fit far less.
    assert np.mean(np.abs(np.array(fitted) - 15.4)) < 0.5 * np.mean(np.abs(np.array(lowest) - 15.4))
    # The disk-like asymmetry e = 1/sqrt(n) + n / (2 n0^1.5) (minimum at n0 = 300): the fit in
    # log n lands within 5 %.
    n = np.array([150, 200, 250, 300, 375, 450, 600])
    assert fs.fitted_optimum(n, 1 / np.sqrt(n) + n / (2 * 300**1.5)) == pytest.approx(300, rel=0.05)
    assert np.isnan(fs.fitted_optimum([1, 2, 3], [0.0, 1.0, 0.0]))  # a maximum, no minimum
    with pytest.raises(ValueError, match="distinct"):
        fs.fitted_optimum([1, 1, 2], [0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match="positive"):
        fs.fitted_optimum([0, 1, 2], [0.0, 1.0, 2.0])


@pytest.mark.parametrize("sizes, energies, message", [
    ([1, 2], [0.0, 1.0], "at least three"),
    ([1, 2, 3], [0.0, 1.0], "one length"),
    ([1, 2, 2], [0.0, 1.0, 2.0], "distinct"),
    ([1, 2, 3], [0.0, np.nan, 2.0], "finite"),
])
def test_size_of_lowest_energy_refuses_bad_input(sizes, energies, message):
    with pytest.raises(ValueError, match=message):
        fs.size_of_lowest_energy(sizes, energies)


def test_reshaping_temperature_reads_the_window_from_a_trace():
    n, g = 100, 2.0
    T = np.repeat([0.1, 0.2, 0.3, 0.4], 6)
    # Excess bonds per particle 0, 0, 0.02, 0.2 (melted); acceptance 0, 2 %, 5 %, 10 %.
    excess = np.repeat([0.0, 0.0, 0.02, 0.2], 6)
    E = -300.0 + excess * n * g
    accepted = np.repeat([0, 2, 5, 10], 6)
    T_hold, stages = fs.reshaping_temperature(T, E, accepted, n=n, g=g, reference_energy=-300.0, max_excess=0.03)
    assert T_hold == 0.3
    assert [s["holds"] for s in stages] == [True, True, True, False]
    assert [s["reshapes"] for s in stages] == [False, True, True, True]
    assert stages[2]["excess"] == pytest.approx(0.02) and stages[1]["acceptance"] == pytest.approx(0.02)
    # Only the second half of a stage counts: a stage that ends melted does not hold.
    E_late_melt = E.copy()
    E_late_melt[15:18] = -300.0 + 0.2 * n * g
    assert fs.reshaping_temperature(T, E_late_melt, accepted, n=n, g=g, reference_energy=-300.0,
                                    max_excess=0.03)[0] == 0.2


def test_reshaping_temperature_refuses_bad_input():
    T, E, A = [0.1, 0.1, 0.2, 0.2], [0.0] * 4, [5] * 4
    with pytest.raises(ValueError, match="no stage"):
        fs.reshaping_temperature(T, E, [0] * 4, n=10, g=1.0, reference_energy=0.0)
    with pytest.raises(ValueError, match="rise"):
        fs.reshaping_temperature([0.2, 0.2, 0.1, 0.1], E, A, n=10, g=1.0, reference_energy=0.0)
    with pytest.raises(ValueError, match="one length"):
        fs.reshaping_temperature(T, E[:3], A, n=10, g=1.0, reference_energy=0.0)
    with pytest.raises(ValueError, match="g must be positive"):
        fs.reshaping_temperature(T, E, A, n=10, g=0.0, reference_energy=0.0)
    with pytest.raises(ValueError, match="min_acceptance"):
        fs.reshaping_temperature(T, E, A, n=10, g=1.0, reference_energy=0.0, min_acceptance=2.0)


def test_bad_seeds_and_scans_are_refused(fibre_particle, options):
    with pytest.raises(ValueError, match="width"):
        fs.fibre_seed(10, 9)  # one empty row: the edges would bind across the box
    with pytest.raises(ValueError, match="length"):
        fs.fibre_seed(2.5, 1)
    with pytest.raises(ValueError, match="box"):
        fs.disk_seed(61, 9)
    with pytest.raises(ValueError, match="margin"):
        fs.disk_box(10, 0)
    with pytest.raises(ValueError, match="scan"):
        fs.scan_sizes("bulk", 10, [0, 1, 2])
    with pytest.raises(ValueError, match="distinct"):
        fs.scan_sizes("disk", 10, [1.0, 1.01, 2.0])
    with pytest.raises(ValueError, match="sites"):
        fs.seeded_state(fibre_particle, [(0, 0), (5, 0)], 5, 1, g=0.01, options=options)  # the same site mod 5
    with pytest.raises(ValueError, match="cool_sweeps"):
        fs.sample_schedule(0.1, 10, hold_sweeps=1, cool_sweeps=2, quench_sweeps=1)
    with pytest.raises(ValueError, match="temperatures"):
        fs.heating_ladder(fibre_particle, fs.fibre_seed(8, 2), 8, 1, g=0.01, temperatures=[0.2, 0.1], sweeps=2,
                          options=options)
    with pytest.raises(TypeError):
        fs.seeded_state("hexagon", [(0, 0)], 5, 1, g=0.01, options=options)


def test_run_seeds_are_distinct_streams():
    seeds = {fs.run_seed(1, size, role) for size in range(10, 20) for role in (0, 1)}
    assert len(seeds) == 20 and all(0 <= s < 2**64 for s in seeds)
    with pytest.raises(ValueError, match="seed"):
        fs.run_seed(-1, 3)


def test_ansatz_optima_against_the_continuum_and_the_catalogue(fibre_particle):
    g = binding(fibre_particle, Gamma=0.5)
    width, energy = fs.best_straight_fibre(fibre_particle, g, max_width=30)
    optimum = fs.continuum_optima(ELL, 0.9, 0.5)
    assert abs(width - optimum["W_rows"]) <= 1  # the discrete optimum within a row of the continuum's
    assert energy.shape == (30,) and int(np.argmin(energy)) + 1 == width
    disk_particle = Hexagon.from_continuum(ell=ELL, nu=0.4, eps=0.01)
    g_disk = binding(disk_particle, Gamma=0.5)
    n, R, _ = fs.best_disk(disk_particle, g_disk, max_radius=16)
    energies = ansatz.relax_catalogue(disk_particle, ansatz.catalogue(max_radius=16, max_width=1, cuts=(0,)))
    best = energies.winners(g_disk, families=["disk"])
    assert R == int(energies.size[best]) and n == int(energies.n_particles[best]) == 1 + 3 * R * (R + 1)
    # The discrete disk's finite-size corrections leave it within a quarter of the continuum's.
    assert abs(n / fs.continuum_optima(ELL, 0.4, 0.5)["n_disk"] - 1) < 0.25
