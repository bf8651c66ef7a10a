"""Tests of the aggregate topologies (``pyfrustrate.topology``) against brute-force counts.

The references never use the kernel's integer lattice arithmetic: sites, corners and bonds are
placed in the plane (lattice spacing 1, corners at 1/sqrt(3) from their site at 30, 90, ..., 330
degrees) and counted by distance, with periodic images reduced by floating-point coordinates
in the basis of the period vectors.
"""
import itertools

import numpy as np
import pytest

import pyfrustrate
from pyfrustrate import topology as T

SQRT3 = np.sqrt(3.0)
SLOT_ANGLES = np.deg2rad(30 + 60 * np.arange(6))  # slot s at 30 + 60 s degrees, even slots red


# --------------------------------------------------------------------------------------------
# Brute-force geometry
# --------------------------------------------------------------------------------------------

def xy(sites):
    s = np.asarray(sites, float).reshape(-1, 2)
    return np.column_stack([s[:, 0] + s[:, 1] / 2, SQRT3 / 2 * s[:, 1]])


def corner_xy(sites):
    """(n, 6, 2) reference corner positions of the particles at ``sites``."""
    offsets = np.column_stack([np.cos(SLOT_ANGLES), np.sin(SLOT_ANGLES)]) / SQRT3
    return xy(sites)[:, None, :] + offsets[None, :, :]


def count_bonds_finite(sites):
    """Pairs of particles at distance 1 (bound neighbours), by brute force over all pairs."""
    p = xy(sites)
    d = np.linalg.norm(p[:, None, :] - p[None, :, :], axis=-1)
    return int(np.sum(np.isclose(d, 1.0)) // 2)


def count_distinct_points(points, reduce=None):
    """Distinct points (to 1e-6), optionally after ``reduce`` maps each to a canonical image."""
    pts = np.asarray(points, float).reshape(-1, 2)
    if reduce is not None:
        pts = reduce(pts)
    return len({tuple(np.round(q, 6)) for q in pts})


def lattice_reducer(periods):
    """Map points to the cell spanned by ``periods`` (rows, lattice coordinates): 1 or 2 vectors."""
    basis = xy(periods)
    if len(basis) == 1:  # fibre: reduce along the axis only
        a = basis[0]

        def reduce(p):
            s = p @ a / (a @ a)
            return p - np.floor(s + 1e-9)[:, None] * a
        return reduce
    inv = np.linalg.inv(basis.T)

    def reduce(p):
        frac = p @ inv.T
        return p - np.floor(frac + 1e-9) @ basis
    return reduce


def count_bonds_periodic(sites, periods):
    """Bonds per cell: neighbours (distance 1) among all images, each pair counted once."""
    periods = np.asarray(periods).reshape(-1, 2)
    cell = lattice_reducer(periods)(xy(sites))  # first bring every site into the cell
    shifts = [np.asarray(m) @ xy(periods) for m in itertools.product(range(-2, 3), repeat=len(periods))]
    images = np.concatenate([cell + s for s in shifts])
    d = np.linalg.norm(cell[:, None, :] - images[None, :, :], axis=-1)
    return int(np.sum(np.isclose(d, 1.0)) // 2)  # images include the cell itself (m = 0)


def bfs_hexagon(R):
    """Sites within R neighbour steps of the origin (breadth-first search on the lattice)."""
    steps = [(1, 0), (0, 1), (-1, 1), (-1, 0), (0, -1), (1, -1)]
    seen, frontier = {(0, 0)}, [(0, 0)]
    for _ in range(R):
        frontier = [(i + a, j + b) for i, j in frontier for a, b in steps if (i + a, j + b) not in seen]
        frontier = list(dict.fromkeys(frontier))
        seen.update(frontier)
    return seen


# --------------------------------------------------------------------------------------------
# Disks (hexagonal aggregates)
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("R", [0, 1, 2, 3, 5, 8])
def test_disk_sites_are_the_hexagon_of_radius_R(R):
    top = T.disk(R)
    assert top.n_particles == 1 + 3 * R * (R + 1)
    assert {tuple(s) for s in top.sites} == bfs_hexagon(R)


@pytest.mark.parametrize("R", [0, 1, 2, 3, 5, 8])
def test_disk_bonds_and_corners_by_brute_force(R):
    top = T.disk(R)
    assert top.n_bonds == count_bonds_finite(top.sites)
    assert top.n_corners == count_distinct_points(corner_xy(top.sites))
    # Closed forms for the record (a hexagonal patch): 3 N - 3 (2 R + 1) bonds, 6 (R + 1)^2 corners.
    assert top.n_bonds == 3 * top.n_particles - 3 * (2 * R + 1)
    assert top.n_corners == 6 * (R + 1) ** 2


@pytest.mark.parametrize("R", [0, 1, 4, 10])
def test_disk_size_is_the_radius_of_the_disk_of_equal_area(R):
    n = 1 + 3 * R * (R + 1)
    assert T.disk(R).size == pytest.approx(np.sqrt(n * SQRT3 / 2 / np.pi), rel=1e-14)


def test_cluster_corner_graph_matches_the_geometry():
    # Every slot of every particle points at the corner at its geometric position, and equal
    # positions are one corner (shared by bound neighbours, yellow on yellow, red on red).
    sites = [(0, 0), (1, 0), (0, 1), (3, -1), (2, 2), (-1, 1)]
    top = T.cluster(sites)
    ref = np.asarray(top.kernel.reference)
    corners = np.asarray(top.kernel.corners)
    np.testing.assert_allclose(ref[corners], corner_xy(top.kernel.sites), atol=1e-12)
    assert top.n_corners == count_distinct_points(corner_xy(sites))
    assert top.n_bonds == count_bonds_finite(sites)
    colour = np.asarray(top.kernel.corner_color)
    assert np.all(colour[corners[:, 1::2]] == 1) and np.all(colour[corners[:, 0::2]] == 0)
    assert top.reference_state().shape == (2 * top.n_corners,)


# --------------------------------------------------------------------------------------------
# Fibres
# --------------------------------------------------------------------------------------------

AXIS_LENGTH = {0: 1.0, 1: SQRT3, 2: np.sqrt(7.0)}  # |a1|, |-a1 + 2 a2|, |2 a1 + a2|
FIBER_AXIS = {0: (1, 0), 1: (-1, 2), 2: (2, 1)}
FIBER_STEP = {0: (0, 1), 1: (-1, 1), 2: (-1, 0)}  # cross(axis, step) = 1: one site per lattice line


def strip_is_connected(width, cut):
    """Brute force: is the infinite strip of `width` lattice lines along the cut's axis one
    connected aggregate? Breadth-first search over bonds (distance 1) among 2K + 1 copies of
    the cell; connected iff every particle of copies 0 and 1 is reached from particle 0."""
    cell = xy(np.outer(np.arange(width), FIBER_STEP[cut]))
    K = width + 3
    points = np.concatenate([cell + m * xy(FIBER_AXIS[cut])[0] for m in range(-K, K + 1)])
    d = np.linalg.norm(points[:, None, :] - points[None, :, :], axis=-1)
    adjacent = np.isclose(d, 1.0)
    start = K * width  # particle 0 of copy 0
    seen, frontier = {start}, [start]
    while frontier:
        nxt = [j for i in frontier for j in np.flatnonzero(adjacent[i]) if j not in seen]
        seen.update(nxt)
        frontier = list(dict.fromkeys(nxt))
    return all(K * width + i in seen and (K + 1) * width + i in seen for i in range(width))


@pytest.mark.parametrize("cut", [0, 1, 2])
@pytest.mark.parametrize("width", [1, 2, 3, 4])
def test_disconnected_fibres_are_rejected(cut, width):
    # A cut-1 column of width 1 has its particles sqrt(3) apart; cut-2 strips need 3 lines.
    if strip_is_connected(width, cut):
        assert T.fiber(width, cut).n_particles == width
    else:
        with pytest.raises(ValueError, match="width"):
            T.fiber(width, cut)


@pytest.mark.parametrize("cut", [0, 1, 2])
@pytest.mark.parametrize("width", [1, 2, 3, 6, 11])
@pytest.mark.parametrize("curved", [True, False])
def test_fiber_cell_by_brute_force(cut, width, curved):
    if not strip_is_connected(width, cut):
        pytest.skip("disconnected strip (test_disconnected_fibres_are_rejected)")
    top = T.fiber(width, cut, curved=curved)
    axis = np.asarray(top.periods[0])
    assert np.linalg.norm(xy(axis)) == pytest.approx(AXIS_LENGTH[cut])
    assert top.n_particles == width
    # Continuum width: area per unit length, sqrt(3)/2 per particle.
    assert top.size == pytest.approx(width * SQRT3 / 2 / AXIS_LENGTH[cut], rel=1e-14)
    # The width particles of the cell lie on `width` distinct lattice lines parallel to the axis.
    normal = np.array([-xy(axis)[0, 1], xy(axis)[0, 0]]) / AXIS_LENGTH[cut]
    offsets = np.round(xy(top.sites) @ normal, 9)
    assert len(set(offsets)) == width
    assert np.allclose(np.diff(np.sort(offsets)), SQRT3 / 2 / AXIS_LENGTH[cut])
    assert top.n_bonds == count_bonds_periodic(top.sites, [axis])
    assert top.n_corners == count_distinct_points(corner_xy(top.sites), lattice_reducer([axis]))
    n_period = 3 if curved else 2
    assert top.reference_state().shape == (2 * top.n_corners + n_period,)


@pytest.mark.parametrize("width", [1, 2, 3, 5, 9])
def test_fiber_bond_counts_per_cell(width):
    # Cut 0 by hand: rows of one particle per period, 1 bond along the row + 2 to the next row.
    assert T.fiber(width, 0).n_bonds == 3 * width - 2
    # Cuts 1 and 2 by brute force (their lines are closer than the lattice spacing, so a
    # particle binds particles up to 2 (cut 1) or 3 (cut 2) lines away).
    for cut, axis in [(1, (-1, 2)), (2, (2, 1))]:
        if strip_is_connected(width, cut):
            assert T.fiber(width, cut).n_bonds == count_bonds_periodic(T.fiber(width, cut).sites, [axis])
    # Once the fibre is wider than the bond range, every added line is bulk-like (3 bonds per
    # particle): the bonds broken per cell (two edges) stop depending on the width.
    if width >= 4:
        for cut in (0, 1, 2):
            broken = 3 * width - T.fiber(width, cut).n_bonds
            assert broken == 3 * (width + 1) - T.fiber(width + 1, cut).n_bonds


def test_fiber_edge_bonds_per_unit_length():
    # Broken bonds per unit length of one edge (what sets the line tension, ansatz.edge_line_tension): a cut
    # along a lattice vector breaks 2 bonds per unit length per edge pair, i.e. 1 per edge;
    # the perpendicular (cut 1) one breaks 4/sqrt(3) per edge pair.
    w = 8
    for cut, per_length in [(0, 2.0), (1, 4 / SQRT3)]:
        broken = 3 * w - T.fiber(w, cut).n_bonds
        assert broken / AXIS_LENGTH[cut] == pytest.approx(per_length)


# --------------------------------------------------------------------------------------------
# Bulks
# --------------------------------------------------------------------------------------------

BULKS = [  # (topology factory, bonds per particle, corners per particle)
    (T.bulk, 3.0, 2.0),
    (lambda: T.bulk_with_holes("honeycomb"), 1.5, 3.0),
    (lambda: T.bulk_with_holes("kagome"), 2.0, 8 / 3),
    (lambda: T.periodic([(0, 0), (1, 0), (0, 1), (1, 1)], [(2, 0), (0, 2)]), 3.0, 2.0),
    (lambda: T.periodic([(i, j) for i in range(3) for j in range(2)], [(3, 0), (1, 2)]), 3.0, 2.0),
]


@pytest.mark.parametrize("factory, bonds_per_particle, corners_per_particle", BULKS)
def test_bulk_cells_by_brute_force(factory, bonds_per_particle, corners_per_particle):
    top = factory()
    periods = np.asarray(top.periods)
    assert top.n_bonds == count_bonds_periodic(top.sites, periods)
    assert top.n_corners == count_distinct_points(corner_xy(top.sites), lattice_reducer(periods))
    assert top.n_bonds / top.n_particles == pytest.approx(bonds_per_particle)
    assert top.n_corners / top.n_particles == pytest.approx(corners_per_particle)
    assert top.reference_state().shape == (2 * top.n_corners + 4,)
    assert np.isinf(top.size)


def test_honeycomb_has_no_corner_shared_by_three_particles():
    # The reason it costs no deformation energy: every corner joins at most two particles, so
    # each particle can take its rest shape (checked by relaxation in test_hexagon.py).
    top = T.bulk_with_holes("honeycomb")
    corners = np.asarray(top.kernel.corners).ravel()
    assert np.bincount(corners).max() == 2
    kagome = np.asarray(T.bulk_with_holes("kagome").kernel.corners).ravel()
    assert np.bincount(kagome).max() == 3


# --------------------------------------------------------------------------------------------
# Reduction modulo the periods
# --------------------------------------------------------------------------------------------

def _summary(top):
    return (top.n_particles, top.n_bonds, top.n_corners, sorted(map(tuple, np.asarray(top.kernel.sites))))


@pytest.mark.parametrize("periods, sites", [
    ([(2, 0), (0, 2)], [(0, 0), (1, 0), (1, 1)]),              # kagome-like
    ([(3, 0), (1, 2)], [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1)]),  # one hole in six
    ([(2, 0), (0, 3)], [(i, j) for i in range(2) for j in range(3)]),  # a full 6-site bulk cell
])
def test_equivalent_site_lists_give_the_same_bulk(periods, sites, rng):
    base = T.periodic(sites, periods)
    p = np.asarray(periods)
    for _ in range(4):
        shifted = [np.asarray(s) + rng.integers(-3, 4) * p[0] + rng.integers(-3, 4) * p[1] for s in sites]
        shifted = [shifted[i] for i in rng.permutation(len(shifted))]
        other = T.periodic(shifted, periods)
        assert _summary(other) == _summary(base)
    # ... and the same minimum deformation energy (L-BFGS to tol = 1e-6: energies within ~1e-9
    # relative; the linear solve is not used here because its O(eps^4) error depends on which
    # corners it pins against rigid motions, i.e. on the corner numbering).
    particle = pyfrustrate.Hexagon(k=1.0, kc=0.05, k_area=0.3, eps=0.01)
    e0 = pyfrustrate.relax(particle, base, x0="linear", tol=1e-6).energy
    e1 = pyfrustrate.relax(particle, T.periodic(shifted, periods), x0="linear", tol=1e-6).energy
    assert e1 == pytest.approx(e0, rel=1e-8)


@pytest.mark.parametrize("cut", [0, 1, 2])
def test_equivalent_site_lists_give_the_same_fiber(cut):
    base = T.fiber(4, cut, curved=False)
    axis = np.asarray(base.periods[0])
    shifted = np.asarray(base.sites) + np.array([[3], [-2], [0], [7]]) * axis
    other = T.Topology("fiber", shifted, "fiber", [axis, (0, 0)], curved=False, size=base.size)
    assert _summary(other) == _summary(base)


@pytest.mark.parametrize("make", [
    lambda: T.periodic([(0, 0), (2, 0)], [(2, 0), (0, 2)]),
    lambda: T.periodic([(0, 0), (1, 1), (3, 3)], [(2, 0), (1, 3)]),
    lambda: T.Topology("fiber", [(0, 0), (3, 0)], "fiber", [(1, 0), (0, 0)]),
])
def test_sites_equal_modulo_the_periods_are_rejected(make):
    with pytest.raises(ValueError, match="sites"):
        make()


# --------------------------------------------------------------------------------------------
# Bad input
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("make, name", [
    (lambda: T.cluster([]), "sites"),
    (lambda: T.cluster(np.zeros((0, 2))), "sites"),
    (lambda: T.cluster([(0.5, 0.0)]), "sites"),
    (lambda: T.cluster([(0, 0), (1, 0), (0, 0)]), "sites"),
    (lambda: T.cluster([(np.nan, 0)]), "sites"),
    (lambda: T.disk(-1), "R"),
    (lambda: T.disk(1.5), "R"),
    (lambda: T.fiber(0, 0), "width"),
    (lambda: T.fiber(2.5, 0), "width"),
    (lambda: T.fiber(3, 3), "cut"),
    (lambda: T.bulk_with_holes("square"), "pattern"),
    (lambda: T.periodic([(0, 0)], [(1, 0), (2, 0)]), "periods"),
    (lambda: T.periodic([(0, 0)], [(0, 0), (0, 1)]), "periods"),
])
def test_bad_topologies_raise_value_error_naming_the_parameter(make, name):
    with pytest.raises(ValueError, match=name):
        make()


def test_cluster_with_three_coordinates_names_sites():
    # Regression (pyfrustrate/topology.py, fixed): cluster() reshaped its input to (-1, 2) before
    # Topology validates the shape, so a site with three coordinates gives numpy's
    # "cannot reshape array of size 3 into shape (2)", which does not name the parameter.
    with pytest.raises(ValueError, match="sites"):
        T.cluster([(0, 0, 0)])


# --------------------------------------------------------------------------------------------
# Finite aggregates of n particles (the shapes of finite-size predictions)
# --------------------------------------------------------------------------------------------

@pytest.mark.parametrize("R", [0, 1, 2, 3])
def test_stadium_of_a_hexagonal_number_is_the_hexagon(R):
    """The 1 + 3R(R+1) sites nearest to a point are the hexagon of radius R (R <= 3: the next
    shell, at distance 2 sqrt(3), lies beyond the hexagon's farthest sites at 3)."""
    n = 1 + 3 * R * (R + 1)
    assert set(map(tuple, T.stadium_sites(n).tolist())) == set(map(tuple, T.hexagon_sites(R).tolist()))


@pytest.mark.parametrize("R", [0, 1, 4, 9])
def test_faceted_stadium_of_a_hexagonal_number_is_the_hexagon(R):
    """In the lattice's own distance every hexagonal number is a full hexagon, at any size."""
    n = 1 + 3 * R * (R + 1)
    assert set(map(tuple, T.stadium_sites(n, faceted=True).tolist())) == set(map(tuple, T.hexagon_sites(R).tolist()))


@pytest.mark.parametrize("R,r", [(1, 0), (4, 2), (9, 5)])
def test_faceted_stadium_with_a_hexagonal_hole_is_the_hexagonal_ring(R, r):
    """Leaving the 1 + 3r(r+1) nearest sites empty turns the hexagon of radius R into the ring
    between the hexagons of radii r and R, built here as a difference of two hexagons."""
    hole = 1 + 3 * r * (r + 1)
    n = 1 + 3 * R * (R + 1) - hole
    ring = set(map(tuple, T.hexagon_sites(R).tolist())) - set(map(tuple, T.hexagon_sites(r).tolist()))
    sites = T.stadium_sites(n, faceted=True, hole=hole)
    assert sites.shape == (n, 2) and set(map(tuple, sites.tolist())) == ring


@pytest.mark.parametrize("R,r", [(2, 1), (5, 3)])
def test_faceted_triangle_stadium_with_a_hole_of_6r2_is_the_ring_of_triangles(R, r):
    """The same on the triangle tiling: the hexagon of triangles of side R without that of side r."""
    ring = set(map(tuple, T.triangle_hexagon_sites(R).tolist())) - set(map(tuple, T.triangle_hexagon_sites(r).tolist()))
    sites = T.stadium_sites(6 * (R * R - r * r), faceted=True, tiling="triangle", hole=6 * r * r)
    assert set(map(tuple, sites.tolist())) == ring


@pytest.mark.parametrize("faceted", [False, True])
def test_a_hole_along_a_long_segment_is_a_slot(faceted):
    """On a long segment the emptied sites are those nearest to it: a slot along a1, inside the
    strip (every emptied site lies between the strip's sites on both sides across a1)."""
    n, hole, segment = 300, 20, 40.0
    solid = T.stadium_sites(n + hole, segment, faceted=faceted)
    holed = T.stadium_sites(n, segment, faceted=faceted, hole=hole)
    emptied = set(map(tuple, solid.tolist())) - set(map(tuple, holed.tolist()))
    assert len(emptied) == hole and len(holed) == n
    y_holed = T.site_positions(holed)[:, 1]
    for x, y in T.site_positions(np.array(sorted(emptied))):
        assert y_holed.min() < y < y_holed.max()
        assert abs(y) < 1.0  # on the segment's row or next to it


@pytest.mark.parametrize("R", [1, 2, 5])
def test_faceted_triangle_stadium_of_6R2_is_the_hexagon_of_triangles(R):
    """On the triangle tiling the 6 R^2 triangles nearest to a vertex in the lattice's own
    distance are the hexagon of side R around it (triangle_hexagon_sites, built from the
    vertices' hexagonal distance instead of the centres')."""
    sites = T.stadium_sites(6 * R * R, faceted=True, tiling="triangle")
    assert sites.shape == (6 * R * R, 3)
    assert set(map(tuple, sites.tolist())) == set(map(tuple, T.triangle_hexagon_sites(R).tolist()))


@pytest.mark.parametrize("faceted", [False, True])
def test_triangle_stadiums_are_single_strips_of_n_distinct_triangles(faceted):
    """A long segment gives one connected strip of exactly n distinct triangles, longer than
    wide along a1 (gyration dimensions; each triangle has at most three neighbours)."""
    n = 200
    sites = T.stadium_sites(n, segment=30.0, faceted=faceted, tiling="triangle")
    assert len(set(map(tuple, sites.tolist()))) == n
    cluster = T.cluster(sites, tiling="triangle")
    assert n - 1 <= cluster.n_bonds <= 3 * n // 2
    width, length = T.gyration_dimensions(sites, "triangle")
    assert length > 3 * width
    positions = T.site_positions(sites, "triangle")
    assert np.ptp(positions[:, 0]) > 3 * np.ptp(positions[:, 1])  # along a1


def test_compact_faceted_aggregates_hold_the_most_bonds_any_n_sites_can():
    """Harary and Harborth (1976): n sites of the triangular lattice share at most
    3 n - ceil(sqrt(12 n - 3)) nearest-neighbour pairs. The compact faceted shape reaches it for
    every n; the round disk falls short, by two at n = 200."""
    for n in range(1, 400):
        assert T.cluster(T.stadium_sites(n, faceted=True)).n_bonds == 3 * n - int(np.ceil(np.sqrt(12 * n - 3))), n
    assert T.cluster(T.stadium_sites(200)).n_bonds == 3 * 200 - 49 - 2


@pytest.mark.parametrize("faceted", [False, True])
@pytest.mark.parametrize("n,segment", [(1, 0.0), (57, 0.0), (200, 12.0), (300, 60.0)])
def test_stadium_sites_are_distinct_connected_and_deterministic(n, segment, faceted):
    sites = T.stadium_sites(n, segment, faceted=faceted)
    assert sites.shape == (n, 2) and len(set(map(tuple, sites.tolist()))) == n
    assert np.array_equal(sites, T.stadium_sites(n, segment, faceted=faceted))
    # Breadth-first search over the six neighbours reaches every site.
    members = set(map(tuple, sites.tolist()))
    seen, queue = {tuple(sites[0])}, [tuple(sites[0])]
    for u in queue:
        for d in T.NEIGHBOURS:
            v = (u[0] + int(d[0]), u[1] + int(d[1]))
            if v in members and v not in seen:
                seen.add(v)
                queue.append(v)
    assert len(seen) == n


@pytest.mark.parametrize("faceted", [False, True])
def test_long_stadium_is_a_strip_of_the_expected_width(faceted):
    """Area conservation: n particles of area sqrt(3)/2 along a segment L make a strip of width
    about n sqrt(3) / (2 L); the gyration width of a uniform strip is its width."""
    n, segment = 600, 100.0
    width, length = T.gyration_dimensions(T.stadium_sites(n, segment, faceted=faceted))
    assert width == pytest.approx(n * np.sqrt(3) / 2 / segment, rel=0.1)
    assert length == pytest.approx(segment, rel=0.1)


def test_gyration_dimensions_of_a_rectangle_and_a_hexagon():
    rows, columns = 8, 40
    rect = np.array([(i - r // 2, r) for r in range(rows) for i in range(columns)])
    width, length = T.gyration_dimensions(rect)
    # Discrete uniform rows: variance (spacing^2)(m^2 - 1)/12 along each side (up to the
    # half-site stagger of alternate rows, which tilts the tensor slightly).
    assert width == pytest.approx(np.sqrt(3) / 2 * np.sqrt(rows ** 2 - 1), rel=1e-3)
    assert length == pytest.approx(np.sqrt(columns ** 2 - 1), rel=0.01)
    w, l = T.gyration_dimensions(T.hexagon_sites(10))
    assert w == pytest.approx(l, rel=1e-12)  # six-fold symmetric: isotropic gyration tensor
    assert T.gyration_dimensions([(0, 0)]) == (0.0, 0.0)


@pytest.mark.parametrize("bad", [0, -3, 2.5, True])
def test_stadium_rejects_bad_n(bad):
    with pytest.raises(ValueError, match="n must be"):
        T.stadium_sites(bad)


@pytest.mark.parametrize("bad", [-1.0, float("nan"), float("inf")])
def test_stadium_rejects_bad_segment(bad):
    with pytest.raises(ValueError, match="segment"):
        T.stadium_sites(10, bad)


@pytest.mark.parametrize("bad", [-1, 2.5, True])
def test_stadium_rejects_bad_hole(bad):
    with pytest.raises(ValueError, match="hole must be"):
        T.stadium_sites(10, hole=bad)


def _all_shapes(n):
    """Every fixed polyhex of n sites (each once, translated to a canonical origin), by
    Redelmeier's enumeration over the kernel's neighbour table: an independent census."""
    offsets = [tuple(d) for d in T.neighbour_sites((0, 0))]
    origin = (0, 0)
    def allowed(site):  # sites "after" the origin, so every shape is grown from its least site once
        return site[1] > 0 or (site[1] == 0 and site[0] >= 0)
    shapes = []
    def grow(shape, untried, seen):
        while untried:
            site = untried.pop()
            shape.append(site)
            if len(shape) == n:
                shapes.append(frozenset(shape))
            else:
                new = [s for s in ((site[0] + di, site[1] + dj) for di, dj in offsets) if allowed(s) and s not in seen]
                grow(shape, untried + new, seen | set(new))
            shape.pop()
    grow([], [origin], {origin})
    return shapes


def _images(sites):
    """The 12 images of a shape under the lattice's rotations and reflections, each translated so
    that its least site (by row, then column) is the origin."""
    xy = T.site_positions(np.asarray(sites))
    basis = np.column_stack([T.site_positions(np.array([[1, 0]]))[0], T.site_positions(np.array([[0, 1]]))[0]])
    out = set()
    for k in range(6):
        c, s = np.cos(k * np.pi / 3), np.sin(k * np.pi / 3)
        for flip in (1, -1):
            turned = (np.array([[c, -s], [s, c]]) @ (xy * [1, flip]).T)
            ij = np.rint(np.linalg.solve(basis, turned).T).astype(int)
            least = min(map(tuple, ij[:, ::-1]))[::-1]
            out.add(frozenset((int(i - least[0]), int(j - least[1])) for i, j in ij))
    return out


@pytest.mark.parametrize("n", [7, 9, 10])
def test_the_complete_hexagon_is_the_only_outline_with_the_most_bonds(n):
    """Every shape of n sites, enumerated: the most bonds any holds is most_bonds(n); at the
    complete-hexagon numbers 7 and 10 (sides 2, 2, 2 and 2, 2, 3) every shape that holds them is an
    image of one shape, the faceted compact aggregate; at 9, not a complete hexagon, several are."""
    shapes = _all_shapes(n)
    assert len(shapes) == {7: 3652, 9: 77359, 10: 362671}[n]  # fixed polyhexes (OEIS A001207)
    bonds = [sum((i + di, j + dj) in s for i, j in s for di, dj in ((1, 0), (0, 1), (-1, 1))) for s in shapes]
    assert max(bonds) == T.most_bonds(n)
    best = {s for s, b in zip(shapes, bonds) if b == T.most_bonds(n)}
    hexagon = _images(T.stadium_sites(n, faceted=True))
    if T.complete_hexagon_sides(n) is None:
        assert len(best) > len(hexagon)
    else:
        assert best == hexagon


def test_complete_hexagon_numbers_are_the_largest_of_their_perimeter():
    """Those n are where one more site adds two bonds, not three (the minimal perimeter grows),
    with sides that differ by one at most; n = 200 is one (sides 8, 9, 9, 551 bonds)."""
    found = [n for n in range(2, 3000) if T.complete_hexagon_sides(n)]
    assert all(T.most_bonds(n + 1) - T.most_bonds(n) == 2 for n in found)
    assert len(found) == len(set(found)) and len(found) >= 90
    assert T.complete_hexagon_sides(200) == (8, 9, 9) and T.most_bonds(200) == 551
    assert T.complete_hexagon_sides(201) is None
    for bad in (0, -3, 2.5, True, None, "7"):  # None and "7": ValueError, not int()'s TypeError
        with pytest.raises(ValueError, match="n must be"):
            T.complete_hexagon_sides(bad)
        with pytest.raises(ValueError, match="n must be"):
            T.most_bonds(bad)
