"""PEBI cells along well paths: mirrored side rows put the centroids of a straight path's cells
on the path (gridlib/voronoi/path_sites.py); bends, branches, points and faults still build; the
areal path of a trajectory inside the reservoir (gridlib/voronoi/areal.py)."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from scipy.spatial import cKDTree

import gridlib as gl
from gridlib.errors import GridError
from gridlib.voronoi import Fault, Well, areal_path, grid_quality, pebi_grid, rectangle
from gridlib.voronoi.path_sites import cells_along
from gridlib.voronoi.pebi_result import FAULT, WELL, WELL_SIDE

H = 10.0
AREA = 300.0 * 200.0
UTM = (5.3e5, 6.7e6)
HEXAGON = np.sqrt(3.0) / 2  # area of the Voronoi cell of a triangular lattice of spacing s: HEXAGON s^2


def _build(wells, faults=(), offset=(0.0, 0.0), orthogonality=1e-6):
    """The grid of the 300 m x 200 m box (cell size H) and its centroids less ``offset``; checked:
    a valid grid, the box's area, every face the perpendicular bisector of its two sites (to
    ``orthogonality`` degrees: a face contracted between well sites turns its neighbours a bit)."""
    o = np.asarray(offset)
    shift = [
        Well(path=[np.asarray(p) + o for p in w.path] if np.ndim(w.path[0]) == 2 else np.asarray(w.path) + o)
        for w in wells
    ]
    pg = pebi_grid(rectangle(*o, *(o + (300, 200))), H, [Fault(np.asarray(f) + o) for f in faults], shift)
    geo = gl.compute_geometry(pg.grid)
    gl.check_grid(pg.grid, geo)
    assert abs(geo.cell_volumes.sum() - AREA) <= 1e-10 * AREA
    assert grid_quality(pg).orthogonality_sites_max < orthogonality
    assert np.all(pg.cell_well[pg.site_kind == WELL_SIDE] == 0)  # the side rows are not the well's
    return pg, geo, pg.sites - o, geo.cell_centroids - o


def _path_cells(pg, sites, centroids, well, line):
    """The cells of the sites on the path: their sites' distance along ``line`` (m) and their
    centroids' distance from it / H."""
    mine = np.flatnonzero((pg.cell_well == well) & (pg.site_kind == WELL))
    along = shapely.line_locate_point(line, shapely.points(sites[mine]))
    return mine, along, shapely.distance(shapely.points(centroids[mine]), line) / H


def _assert_covers(pg, sites, well, line):
    """Every point of the path lies in one of the well's cells (the cell of its nearest site)."""
    pts = shapely.get_coordinates(shapely.segmentize(line, 0.05 * H))
    d = np.hypot(pts[:, None, 0] - sites[None, :, 0], pts[:, None, 1] - sites[None, :, 1])
    assert np.all(pg.cell_well[np.argmin(d, axis=1)] == well)


@pytest.mark.parametrize("offset", [(0.0, 0.0), UTM])
def test_a_straight_path_gets_regular_hexagons_centred_on_it(offset):
    """21 equal steps of 205.68 / 21 m: every path cell (the two ends too) is the regular hexagon
    around its site, so its centroid is its site, on the path (to 1e-9 of the cell size)."""
    path = [(50.0, 83.0), (250.0, 131.0)]
    pg, geo, sites, centroids = _build([Well(path=path, name="H")], offset=offset)
    line = shapely.LineString(path)
    mine, along, off = _path_cells(pg, sites, centroids, 1, line)
    step = np.hypot(200.0, 48.0) / 21
    assert np.sort(along) == pytest.approx(step * np.arange(22), abs=1e-9 * H)
    assert off.max() < 1e-9
    assert np.abs(centroids[mine] - sites[mine]).max() < 1e-9 * H
    assert geo.cell_volumes[mine] == pytest.approx(np.full(22, HEXAGON * step**2), rel=1e-9)
    assert np.count_nonzero(pg.cell_well) == 22
    assert np.count_nonzero(pg.site_kind == WELL_SIDE) == 2 * 19 + 2 * 5  # beside the steps, around the ends
    _assert_covers(pg, sites, 1, line)


def test_a_straight_path_with_vertices_and_unequal_steps():
    """Collinear vertices split the path into 8 steps of 10.375 m and 14 of 9.786 m: the cells are
    mirrored about the line (the one at the vertex not about its site): centroids on the path."""
    path = [(40.0, 100.0), (123.0, 100.0), (260.0, 100.0)]
    pg, _geo, sites, centroids = _build([Well(path=path)])
    mine, _along, off = _path_cells(pg, sites, centroids, 1, shapely.LineString(path))
    assert mine.size == 1 + 8 + 14 and off.max() < 1e-9
    assert np.abs(centroids[mine, 1] - 100.0).max() < 1e-9 * H


def test_an_l_shaped_path_has_centroids_on_its_legs():
    """A 90-degree bend: the cells from the second step after the bend on have their centroids on
    the path; the cells at the bend do not (by up to a few per cent of the cell size)."""
    path = [(40.0, 40.0), (150.0, 60.0), (150.0, 160.0)]
    pg, _geo, sites, centroids = _build([Well(path=path, name="L")])
    line = shapely.LineString(path)
    mine, along, off = _path_cells(pg, sites, centroids, 1, line)
    bend = np.hypot(110.0, 20.0)
    assert mine.size == 1 + 11 + 10
    far = np.abs(along - bend) > 1.5 * H
    assert np.count_nonzero(far) == 22 - 3 and off[far].max() < 1e-9
    assert 1e-3 < off[~far].max() < 0.05
    _assert_covers(pg, sites, 1, line)


def test_a_sharp_bend_builds():
    """A bend of 151 degrees: the legs are too close for side rows near the apex (dropped there);
    the grid is valid, the path runs through the well's cells, the far ends are exact."""
    path = [(40.0, 40.0), (150.0, 60.0), (60.0, 90.0)]
    pg, _geo, sites, centroids = _build([Well(path=path)])
    line = shapely.LineString(path)
    _mine, along, off = _path_cells(pg, sites, centroids, 1, line)
    bend = np.hypot(110.0, 20.0)
    far = np.abs(along - bend) > 6 * H
    assert np.count_nonzero(far) >= 10 and off[far].max() < 1e-9
    _assert_covers(pg, sites, 1, line)


def test_a_path_crossing_a_fault():
    """The fault cells at the crossing are the well's (on both sides), the fault faces follow the
    trace, the path cells two cells or more from the trace have their centroids on the path."""
    path = [(40.0, 100.0), (250.0, 100.0)]
    trace = [(100.0, 0.0), (130.0, 200.0)]
    pg, geo, sites, centroids = _build([Well(path=path, name="X")], faults=[trace])
    mine = np.flatnonzero(pg.cell_well == 1)
    fault_cells = mine[pg.site_kind[mine] == FAULT]
    ab = np.subtract(trace[1], trace[0])
    rel = sites[fault_cells] - trace[0]
    assert set(np.sign(ab[0] * rel[:, 1] - ab[1] * rel[:, 0]).tolist()) == {-1.0, 1.0}  # both sides
    tagged = geo.face_areas[pg.grid.faces.tag == 1].sum()
    assert tagged == pytest.approx(np.hypot(30.0, 200.0), rel=1e-12)
    line = shapely.LineString(path)
    cells, _along, off = _path_cells(pg, sites, centroids, 1, line)
    away = shapely.distance(shapely.points(sites[cells]), shapely.LineString(trace)) > 2 * H
    assert np.count_nonzero(away) >= 15 and off[away].max() < 1e-9
    _assert_covers(pg, sites, 1, line)


@pytest.mark.parametrize(
    ("branches", "count", "near"),
    [
        # a lateral leaving the main bore at 48 degrees from a point inside its segment (split there)
        ([[(40.0, 60.0), (260.0, 60.0)], [(150.0, 60.0), (230.0, 150.0)]], 4 + 10 + 10 + 11, 3.5),
        # three branches from one point, 120, 90 and 150 degrees apart
        (
            [[(150.0, 100.0), (40.0, 100.0)], [(150.0, 100.0), (200.0, 100 + 50 * 3**0.5)]]
            + [[(150.0, 100.0), (150.0 + 50 * 3**0.5, 50.0)]],
            4 + 10 + 9 + 9,
            1.5,
        ),
    ],
)
def test_multilateral_branches_share_the_junction(branches, count, near):
    """Branches of one well meeting at a point: one site at the junction, the grid is valid, every
    branch runs through the well's cells, centroids on the path farther than ``near`` steps from the
    junction (two steps where the branches are 90 degrees apart or more, four at 48 degrees)."""
    pg, _geo, sites, centroids = _build([Well(path=branches, name="ML")], orthogonality=1.0)
    assert np.count_nonzero(pg.cell_well == 1) == count
    junction = np.asarray(branches[1][0])
    assert np.count_nonzero(np.hypot(*(sites - junction).T) < 1e-9 * H) == 1
    for branch in branches:
        line = shapely.LineString(branch)
        _assert_covers(pg, sites, 1, line)
        mine = np.flatnonzero((pg.cell_well == 1) & (pg.site_kind == WELL))
        on = shapely.distance(shapely.points(sites[mine]), line) < 1e-9 * H
        far = on & (np.hypot(*(sites[mine] - junction).T) > near * H)
        off = shapely.distance(shapely.points(centroids[mine[far]]), line) / H
        assert np.count_nonzero(far) >= 7 and off.max() < 1e-9


def test_a_point_piece_is_one_hexagon():
    """A vertical part of a trajectory (a point) next to a horizontal part: the point's cell is the
    regular hexagon around it, the horizontal part's cells are centred on it."""
    pg, geo, sites, centroids = _build([Well(path=[[(60.0, 100.0)], [(100.0, 100.0), (240.0, 100.0)]])])
    mine = np.flatnonzero(pg.cell_well == 1)
    assert mine.size == 1 + 15
    point = mine[np.argmin(np.hypot(*(sites[mine] - (60.0, 100.0)).T))]
    assert np.abs(centroids[point] - (60.0, 100.0)).max() < 1e-9 * H
    assert geo.cell_volumes[point] == pytest.approx(HEXAGON * H**2, rel=1e-9)
    assert np.abs(centroids[mine, 1] - 100.0).max() < 1e-9 * H


@pytest.mark.parametrize(
    ("wells", "message"),
    [
        (
            [Well(path=[[(50.0, 50.0), (150.0, 150.0)], [(50.0, 150.0), (150.0, 50.0)]], name="X")],
            r"well 'X' \(wells\[0\]\): the path crosses itself",
        ),
        (
            [Well(path=[(50.0, 50.0), (50.0, 50.0), (100.0, 100.0)], name="C")],
            r"well 'C' \(wells\[0\]\): path points 0 and 1 coincide",
        ),
        (
            [Well(path=[[(50.0, 50.0)], [(100.0, 100.0), (350.0, 100.0)]], name="O")],
            r"well 'O' \(wells\[0\]\): the path\[1\] leaves the domain \(near \(350, 100\)\)",
        ),
        (
            [
                Well(path=[(50.0, 100.0), (250.0, 100.0)], name="A"),
                Well(path=[(50.0, 120.0), (250.0, 120.0)]),
            ],
            r"well 'A' \(wells\[0\]\) and well 'W2' \(wells\[1\]\) are too close: 20 m apart, they need "
            r"23.32 m",
        ),
    ],
)
def test_path_errors(wells, message):
    with pytest.raises(GridError, match=message):
        pebi_grid(rectangle(0, 0, 300, 200), H, wells=wells)


def test_areal_path_clips_a_trajectory_to_the_reservoir():
    """Vertical, then deviated across the top at t = 0.5, then horizontal: one polyline from the
    crossing, the collinear vertex dropped."""
    xyz = [(0, 0, 900), (0, 0, 1000), (60, 80, 1010), (240, 320, 1010)]
    got = areal_path(xyz, 1005.0, 1100.0)
    assert [p.tolist() for p in got] == [[[30.0, 40.0], [240.0, 320.0]]]
    assert areal_path(xyz, 1200.0, 1300.0) == []


def test_areal_path_pieces_points_and_callables():
    # in, out below the base, in again through an inside vertex: two pieces
    xyz = np.array([(0, 0, 1000), (100, 0, 1020), (200, 0, 1000), (300, 0, 1020)], dtype=float)
    got = areal_path(xyz, np.full(4, 990.0), np.full(4, 1010.0))
    assert [p.tolist() for p in got] == [[[0.0, 0.0], [50.0, 0.0]], [[150.0, 0.0], [250.0, 0.0]]]
    # a top that deepens eastwards, given as a function of (x, y): the path leaves it at x = 50
    got = areal_path([(0, 5, 1005), (200, 5, 1005)], lambda x, y: 1000 + 0.1 * x, 1100.0)
    assert [p.tolist() for p in got] == [[[0.0, 5.0], [50.0, 5.0]]]
    # nearly vertical: a point, half way along the part inside (z 1000 .. 1040)
    xyz = [(10, 20, 900), (10.2, 20, 1000), (10.6, 20.4, 1100)]
    got = areal_path(xyz, 1000.0, 1040.0, tolerance=1.0)
    assert len(got) == 1 and got[0].shape == (1, 2)
    assert got[0][0] == pytest.approx([10.2 + 0.4 * 0.2, 20.0 + 0.4 * 0.2], abs=1e-12)
    # touching the top at one point is no part
    assert areal_path([(0, 0, 990), (10, 0, 1000), (20, 0, 990)], 1000.0, 1100.0) == []


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (([(0, 0, 1)], 0.0, 2.0), r"xyz must be finite points \(n, 3\) with n >= 2"),
        (([(0, 0, 1), (1, 0, 1)], [0.0, np.nan], 2.0), r"top_depth is not finite at point 1 \(1, 0\)"),
        (([(0, 0, 1), (1, 0, 1)], 0.0, [2.0, 2.0, 2.0]), r"base_depth must give one depth per point"),
    ],
)
def test_areal_path_errors(args, message):
    with pytest.raises(GridError, match=message):
        areal_path(*args)


def test_cells_along_finds_a_cell_the_path_only_clips():
    """Sites A (0, 0), B (2, 0), C (1, 1): the segment at y = 1e-6 from x = 0.1 to 1.7 runs through
    C's cell for 2e-6 m around x = 1 (where x + y > 1 and x - y < 1); sampling at its ends and
    midpoint sees A and B only, the bisection finds C too."""
    sites = np.array([(0.0, 0.0), (2.0, 0.0), (1.0, 1.0)])
    tree = cKDTree(sites)
    steps = np.array([[(0.1, 1e-6), (1.7, 1e-6)], [(0.2, 0.5), (0.4, 0.5)]])
    cells, owner = cells_along(lambda p: tree.query(p)[1], steps, np.array([7, 8]), 1e-12)
    assert sorted(set(zip(owner.tolist(), cells.tolist(), strict=True))) == [(7, 0), (7, 1), (7, 2), (8, 0)]
