"""pebi_grid: the seed's radial and composite grids, faults, wells, lattices, errors, UTM coordinates."""

from __future__ import annotations

import importlib
import itertools

import numpy as np
import pytest
import shapely
from seed_points import radial_points

import gridlib as gl
from gridlib.voronoi import Fault, PebiGrid, Rings, Well, grid_quality, pebi_grid, rectangle
from gridlib.voronoi.pebi_result import FAULT

bounded_module = importlib.import_module("gridlib.voronoi.bounded")
lattice_module = importlib.import_module("gridlib.voronoi.lattice")

RADIAL = Rings(inner=np.exp(-3.5), growth=np.exp(0.25), outer=1.0, sectors=16)  # r = exp(-3.5:0.25:0)
SIXTEEN_GON = np.column_stack(
    [np.cos(2 * np.pi * np.arange(16) / 16), np.sin(2 * np.pi * np.arange(16) / 16)]
)


def _lengths(g: gl.Grid) -> np.ndarray:
    e = g.faces.nodes.reshape(-1, 2)
    return np.linalg.norm(g.nodes.coords[e[:, 1]] - g.nodes.coords[e[:, 0]], axis=1)


def test_radial_grid_of_the_seed():
    """§3.3.2 Example 2 through the new API: 15 rings of 16 sites plus the centre in the 16-gon."""
    pg = pebi_grid(SIXTEEN_GON, 1.0, wells=[Well((0.0, 0.0), rings=RADIAL)])
    g = pg.grid
    geo = gl.compute_geometry(g)
    assert g.num_cells == 241
    assert geo.cell_volumes.sum() == pytest.approx(3.06146745892, abs=1e-11)
    assert geo.cell_volumes.sum() == pytest.approx(8 * np.sin(2 * np.pi / 16), rel=1e-14)
    gl.check_grid(g, geo)
    # the same grid as issue 2's pebi(triangle_grid(points)) of the book's points
    ref = gl.pebi(gl.triangle_grid(radial_points()))
    assert (
        (g.num_cells, g.num_faces, g.num_nodes)
        == (ref.num_cells, ref.num_faces, ref.num_nodes)
        == (241, 512, 272)
    )
    assert np.sort(gl.compute_geometry(ref).cell_volumes) == pytest.approx(
        np.sort(geo.cell_volumes), rel=1e-9
    )
    assert np.all(pg.cell_well == 1) and pg.well_names == ("W1",)
    # rings: 15 radii from exp(-3.5) to 1 exactly
    radii = np.unique(np.round(np.hypot(*pg.sites.T), 12))
    assert radii.size == 16 and radii[0] == 0.0
    np.testing.assert_allclose(radii[1:], np.exp(np.arange(-3.5, 1e-9, 0.25)), rtol=1e-10)


def test_two_well_composite_of_the_seed():
    """§3.5.2 Fig. 3.37: rings (r = exp(-3.5:0.2:-0.1), 28 sectors) at (2,2) and (12,6) in a 0.5 lattice."""
    rings = Rings(inner=np.exp(-3.5), growth=np.exp(0.2), count=18, sectors=28)
    pg = pebi_grid(
        ((0, 0), (14, 8)),
        0.5,
        wells=[Well((2, 2), rings=rings), Well((12, 6), rings=rings)],
        pattern="cartesian",
    )
    g = pg.grid
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(112.0, rel=1e-12)
    gl.check_grid(g, geo)
    # 28 x 16 lattice cells, 16 of them removed around each well, 18 x 28 + 1 cells per well
    assert np.bincount(pg.cell_well).tolist() == [448 - 32, 505, 505]
    assert g.num_cells == 1426
    # lattice cells away from the wells are exact 0.5 m squares (no half cells at the boundary)
    square = np.isclose(geo.cell_volumes, 0.25, rtol=1e-12, atol=0) & (pg.cell_well == 0)
    assert square.sum() == 384
    assert np.all(g.cells.num_faces[square] == 4)


def test_cartesian_and_hexagonal_lattices_fill_a_rectangle_exactly():
    cart = pebi_grid(rectangle(0, 0, 10, 6), 1.0, pattern="cartesian")
    geo = gl.compute_geometry(cart.grid)
    assert (cart.grid.num_cells, cart.grid.num_faces, cart.grid.num_nodes) == (60, 136, 77)
    np.testing.assert_allclose(geo.cell_volumes, 1.0, rtol=1e-14)
    hexa = pebi_grid(rectangle(0, 0, 10, 6), 1.0)
    geo = gl.compute_geometry(hexa.grid)
    assert hexa.grid.num_cells == 54
    assert geo.cell_volumes.sum() == pytest.approx(60.0, rel=1e-14)
    regular = np.isclose(geo.cell_volumes, np.sqrt(3) / 2, rtol=1e-12)
    assert regular.sum() == 28 and np.all(hexa.grid.cells.num_faces[regular] == 6)
    gl.check_grid(hexa.grid, geo)


def test_padding_frames_a_hexagonal_interior_with_squares():
    """Fig. 3.38: two rows of Cartesian cells along the boundary, hexagons inside."""
    pg = pebi_grid(rectangle(0, 0, 12, 8), 1.0, padding=2)
    geo = gl.compute_geometry(pg.grid)
    gl.check_grid(pg.grid, geo)
    assert geo.cell_volumes.sum() == pytest.approx(96.0, rel=1e-14)
    assert pg.grid.num_cells == 85
    unit = np.isclose(geo.cell_volumes, 1.0, rtol=1e-12)
    assert unit.sum() == 40  # the outer row (36) and the inner row's corners
    c = geo.cell_centroids[unit]
    assert np.all(np.minimum.reduce([c[:, 0], c[:, 1], 12 - c[:, 0], 8 - c[:, 1]]) < 2.0)


def test_graded_cell_size_refines_the_lattice_by_halving():
    """h = 0.25 for x < 5 and 1 elsewhere: three nested levels; the fine part is a 0.25 lattice."""
    pg = pebi_grid(rectangle(0, 0, 10, 6), lambda x, y: np.where(x < 5, 0.25, 1.0))
    geo = gl.compute_geometry(pg.grid)
    gl.check_grid(pg.grid, geo)
    assert geo.cell_volumes.sum() == pytest.approx(60.0, rel=1e-14)
    fine = geo.cell_centroids[:, 0] < 4
    assert np.median(geo.cell_volumes[fine]) == pytest.approx(np.sqrt(3) / 2 * 0.25**2, rel=1e-12)
    coarse = geo.cell_centroids[:, 0] > 6
    assert np.isclose(geo.cell_volumes[coarse], np.sqrt(3) / 2, rtol=1e-12).sum() >= 10
    assert pg.grid.num_cells == 570


def test_fault_faces_lie_on_the_trace():
    pg = pebi_grid(rectangle(0, 0, 10, 10), 1.0, faults=[Fault([(2, 2), (8, 7)], "main")])
    g = pg.grid
    tagged = g.faces.tag == 1
    assert set(np.unique(g.faces.tag).tolist()) == {0, 1}
    assert _lengths(g)[tagged].sum() == pytest.approx(np.hypot(6, 5), rel=1e-13)
    nodes = g.nodes.coords[np.unique(g.faces.nodes.reshape(-1, 2)[tagged])]
    assert np.abs((nodes[:, 1] - 2) * 6 - (nodes[:, 0] - 2) * 5).max() < 1e-12  # on the line
    # both sides of every fault face: a left and a right site (mirrored pairs)
    s = pg.sites[g.faces.neighbors[tagged]]
    side = np.sign((s[..., 1] - 2) * 6 - (s[..., 0] - 2) * 5)
    assert np.all(side[:, 0] * side[:, 1] < 0)
    assert pg.fault_names == ("main",) and g.faces.tag.dtype == np.int32


def test_crossing_and_touching_faults_meet_at_one_vertex():
    faults = [Fault([(1, 1), (9, 9)], "a"), Fault([(1, 9), (9, 1)], "b"), Fault([(5, 5), (5, 9)], "c")]
    pg = pebi_grid(rectangle(0, 0, 10, 10), 0.5, faults=faults)
    g = pg.grid
    gl.check_grid(g)
    e = g.faces.nodes.reshape(-1, 2)
    centre = np.flatnonzero(np.all(g.nodes.coords == [5.0, 5.0], axis=1))
    assert centre.size == 1  # the crossing is one node, exactly at (5, 5)
    tags = np.sort(g.faces.tag[np.any(e == centre[0], axis=1)])
    assert tags.tolist() == [0, 0, 0, 1, 1, 2, 2, 3]  # 2 arms of a, 2 of b, 1 of c; 3 gaps of 90 degrees
    length = _lengths(g)
    for k, want in enumerate([8 * np.sqrt(2), 8 * np.sqrt(2), 4.0], start=1):
        assert length[g.faces.tag == k].sum() == pytest.approx(want, rel=1e-12)


def test_fault_is_clipped_extended_and_named_in_notes():
    faults = [Fault([(-2, 3), (6, 7)], "cut"), Fault([(8.2, 1), (8.2, 9.8)], "short")]
    pg = pebi_grid(rectangle(0, 0, 10, 10), 0.5, faults=faults)
    length = _lengths(pg.grid)
    # "cut" enters at (0, 4); "short" stops 0.2 m below the top and is extended to it
    assert length[pg.grid.faces.tag == 1].sum() == pytest.approx(np.hypot(6, 3), rel=1e-12)
    assert length[pg.grid.faces.tag == 2].sum() == pytest.approx(9.0, rel=1e-12)
    assert any("'cut' (faults[0]): clipped to the domain" in n for n in pg.notes)
    assert any("'short' (faults[1]): its end at (8.2, 9.8) was extended by 0.2 m" in n for n in pg.notes)
    e = pg.grid.faces.nodes.reshape(-1, 2)[pg.grid.faces.tag == 1]
    assert np.any(np.all(pg.grid.nodes.coords[e.ravel()] == [0.0, 4.0], axis=1))


def test_sharp_bend_is_refined_until_the_empty_circle_condition_holds():
    faults = [Fault([(2, 1), (8, 1.5), (3, 4)], "hook")]  # turns by 157 degrees
    pg = pebi_grid(rectangle(0, 0, 10, 10), 0.5, faults=faults)
    gl.check_grid(pg.grid)
    want = np.hypot(6, 0.5) + np.hypot(5, 2.5)
    assert _lengths(pg.grid)[pg.grid.faces.tag == 1].sum() == pytest.approx(want, rel=1e-12)


def test_wells_own_their_cells():
    rings = Rings(inner=0.05, outer=1.2)
    wells = [Well((5, 2.5), "inj", rings=rings), Well((15, 6)), Well(path=[(11, 1.5), (14, 2.5), (17, 2.4)])]
    pg = pebi_grid(rectangle(0, 0, 20, 10), 0.5, wells=wells)
    gl.check_grid(pg.grid)
    counts = np.bincount(pg.cell_well, minlength=4)
    sectors = round(2 * np.pi * 1.2 / 0.5)  # 15
    n_rings = round(np.log(1.2 / 0.05) / (2 * np.pi / sectors)) + 1  # growth exp(2 pi / 15)
    assert counts[1] == 1 + sectors * n_rings == 1 + 15 * 9
    assert counts[2] == 1
    assert counts[3] == 1 + 6 + 6  # vertices and 0.5 m spacing along the two legs
    assert pg.well_names == ("inj", "W2", "W3")
    path_sites = pg.sites[pg.cell_well == 3]
    line = shapely.LineString([(11, 1.5), (14, 2.5), (17, 2.4)])
    assert shapely.distance(shapely.points(path_sites), line).max() < 1e-12


def test_utm_coordinates_give_the_same_grid():
    offset = np.array([5.3e5, 6.7e6])
    domain = np.array([(0, 0), (900, 80), (1000, 700), (420, 950), (-60, 600)], dtype=float)
    faults = [[(100, 100), (800, 600)], [(500, -50), (420, 500), (300, 1000)]]
    wells = [(200, 500), (750, 300)]

    def build(o):
        return pebi_grid(
            domain + o,
            25.0,
            [Fault(np.asarray(f) + o) for f in faults],
            [Well(np.asarray(w) + o, rings=Rings(inner=0.5, outer=60.0)) for w in wells],
        )

    local, utm = build(np.zeros(2)), build(offset)
    for g in (local, utm):
        gl.check_grid(g.grid)
    a, b = local.grid, utm.grid
    assert (a.num_cells, a.num_faces, a.num_nodes) == (b.num_cells, b.num_faces, b.num_nodes)
    # the same cells (sites come in the same order), faces between the same cells, same tags
    np.testing.assert_allclose(utm.sites - offset, local.sites, atol=1e-9)
    np.testing.assert_array_equal(local.cell_well, utm.cell_well)

    def faces(g, shift):
        e = g.faces.nodes.reshape(-1, 2)
        mid = 0.5 * (g.nodes.coords[e[:, 0]] + g.nodes.coords[e[:, 1]]) - shift
        key = np.column_stack([np.sort(g.faces.neighbors, axis=1), np.round(mid, 6), g.faces.tag])
        return key[np.lexsort(key.T[::-1])]

    np.testing.assert_allclose(faces(b, offset), faces(a, 0.0), atol=2e-6)
    va, vb = gl.compute_geometry(a).cell_volumes, gl.compute_geometry(b).cell_volumes
    np.testing.assert_allclose(vb, va, rtol=1e-8)
    assert vb.sum() == pytest.approx(shapely.Polygon(domain).area, rel=1e-10)


def test_lattice_shortcut_equals_one_delaunay_of_all_sites(monkeypatch):
    """Regular lattice cells are computed without Qhull; the grid is the same as with Qhull only."""
    args = (
        [(0, 0), (60, 5), (70, 50), (30, 70), (-5, 40)],
        3.0,
        [Fault([(5, 10), (60, 40)]), Fault([(30, 0), (35, 70)])],
        [Well((15, 40), rings=Rings(inner=0.2, outer=5.0))],
    )
    for pattern in ("hexagonal", "cartesian"):
        fast = pebi_grid(*args, pattern=pattern)
        with monkeypatch.context() as m:
            m.setattr(
                bounded_module,
                "hybrid_ridges",
                lambda sites, dom, lat: lattice_module.plain_ridges(sites, dom),
            )
            slow = pebi_grid(*args, pattern=pattern)
        a, b = fast.grid, slow.grid
        assert (a.num_cells, a.num_faces, a.num_nodes) == (b.num_cells, b.num_faces, b.num_nodes)
        np.testing.assert_allclose(
            gl.compute_geometry(a).cell_volumes, gl.compute_geometry(b).cell_volumes, rtol=1e-9, atol=0
        )
        assert (a.faces.tag > 0).sum() == (b.faces.tag > 0).sum()


def test_grid_quality_report():
    q = grid_quality(pebi_grid(rectangle(0, 0, 3, 2), 1.0, pattern="cartesian"))
    assert (q.num_cells, q.num_faces) == (6, 17)
    assert (q.area_min, q.area_median, q.area_max) == (1.0, 1.0, 1.0)
    assert q.face_length_min == 1.0
    assert q.orthogonality_sites_max == pytest.approx(0.0, abs=1e-9)
    assert q.orthogonality_centroids_max == pytest.approx(0.0, abs=1e-9)
    radial = pebi_grid(SIXTEEN_GON, 1.0, wells=[Well((0.0, 0.0), name="P", rings=RADIAL)])
    q = grid_quality(radial)
    assert q.cells_per_well == {"P": 241}
    assert q.orthogonality_sites_max < 1e-5  # degrees
    assert q.area_max == pytest.approx(gl.compute_geometry(radial.grid).cell_volumes.max())
    # sizes relative to each cell's target size (the well's rings: sqrt(arc x radial width))
    assert 0.3 < q.area_ratio_min < 1.0 and 0.1 < q.face_ratio_min < 1.0
    assert "area / h2 min 0.391" in str(q)
    np.testing.assert_array_equal(pebi_grid(rectangle(0, 0, 3, 2), 1.0).site_size[:3], 1.0)
    # a bare Grid has no sites
    q = grid_quality(gl.cart_grid([2, 2]))
    assert np.isnan(q.orthogonality_sites_max) and q.num_cells == 4
    assert np.isnan(q.area_ratio_min) and np.isnan(q.face_ratio_min)
    assert "cells per well" not in str(q) and "orthogonality" in str(q) and "area / h2" not in str(q)
    with pytest.raises(gl.GridError, match="grid_quality: expected a PebiGrid or a Grid"):
        grid_quality("grid")


def _relative_sizes(pg: PebiGrid) -> tuple[np.ndarray, np.ndarray]:
    """Cell areas / site_size^2 and face lengths / the smaller site_size of their cells."""
    g = pg.grid
    geo = gl.compute_geometry(g)
    nb = g.faces.neighbors
    h = np.minimum(
        pg.site_size[nb[:, 0]], np.where(nb[:, 1] >= 0, pg.site_size[np.maximum(nb[:, 1], 0)], np.inf)
    )
    return geo.cell_volumes / pg.site_size**2, geo.face_areas / h


def _site_orthogonality(pg: PebiGrid) -> np.ndarray:
    """Degrees between every interior face and the normal to its two sites."""
    g = pg.grid
    e = g.faces.nodes.reshape(-1, 2)
    inner = np.flatnonzero((g.faces.neighbors >= 0).all(axis=1))
    t = g.nodes.coords[e[inner, 1]] - g.nodes.coords[e[inner, 0]]
    s = pg.sites[g.faces.neighbors[inner, 1]] - pg.sites[g.faces.neighbors[inner, 0]]
    c = np.abs((t * s).sum(axis=1)) / (np.linalg.norm(t, axis=1) * np.linalg.norm(s, axis=1))
    return np.degrees(np.arcsin(np.minimum(c, 1.0)))


def test_no_slivers_or_tiny_faces_where_faults_wells_and_the_boundary_meet():
    """The benchmark's situation in small (bench/pebi.py): a non-convex domain at UTM coordinates,
    faults crossing (X), meeting (T) and reaching the boundary at a shallow angle, a radial well.
    Before, nearly co-circular sites gave faces of 7e-4 cell sizes (a lattice vertex a hair from the
    boundary, lattice sites next to fault and ring sites); now background sites are moved to make
    those configurations exact and no face is shorter than 1 % of its cells' size."""
    off = np.array([5.3e5, 6.7e6])
    domain = np.array(
        [(0, 0), (1200, 80), (1300, 700), (800, 650), (700, 1000), (100, 950), (-50, 500)], float
    )
    traces = [
        [(100, 150), (1100, 600)],
        [(300, 700), (900, 100)],
        [(600, 380), (700, 900)],
        [(1000, 200), (1290, 420)],
    ]
    pg = pebi_grid(
        domain + off,
        25.0,
        [Fault(np.asarray(f) + off) for f in traces],
        [Well(np.array([300.0, 400.0]) + off, rings=Rings(inner=0.3, outer=40.0))],
    )
    g = pg.grid
    geo = gl.compute_geometry(g)
    gl.check_grid(g, geo)
    assert geo.cell_volumes.sum() == pytest.approx(shapely.Polygon(domain).area, rel=1e-10)
    dom = shapely.Polygon(domain)
    for k, f in enumerate(traces, start=1):  # faces exactly on the traces (F3's end is extended by 5.6 m)
        a, b = np.asarray(f, dtype=float)
        u = (b - a) / np.linalg.norm(b - a)
        line = shapely.LineString([a - 10 * u, b + 10 * u]).intersection(dom)
        nodes = g.nodes.coords[np.unique(g.faces.nodes.reshape(-1, 2)[g.faces.tag == k])] - off
        assert shapely.distance(shapely.points(nodes), line).max() < 1e-6
    area, face = _relative_sizes(pg)
    assert area.min() > 0.25 and face.min() >= 0.01
    assert any("background site(s) moved slightly" in n for n in pg.notes)
    angle = _site_orthogonality(pg)
    contracted = sum(int(n.split()[0]) for n in pg.notes if "contracted" in n)
    assert angle.max() < 1.0 and (angle > 1e-3).sum() <= 8 * contracted
    q = grid_quality(pg)
    assert q.area_ratio_min == pytest.approx(area.min()) and q.face_ratio_min == pytest.approx(face.min())


@pytest.mark.parametrize("angle", [50.0, 60.0, 70.0])
def test_straight_faults_crossing_share_the_first_sites_of_both_acute_wedges(angle):
    """Two straight faults crossing make two equal acute wedges; the first sites of the two arms of each
    wedge coincide (one site on three circles), in both wedges, not only in the one that is tightest by
    round-off (the other pair used to be a hair apart: two thin cells and millimetre faces)."""
    d1 = np.array([1.0, 0.2]) / np.hypot(1.0, 0.2)
    a = np.radians(angle)
    d2 = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]) @ d1
    c = np.array([5.1, 4.9])
    faults = [Fault([c - 3.7 * d1, c + 3.9 * d1]), Fault([c - 3.6 * d2, c + 3.8 * d2])]
    pg = pebi_grid(rectangle(0, 0, 10, 10), 0.5, faults=faults)
    g = pg.grid
    gl.check_grid(g)
    node = np.flatnonzero(np.linalg.norm(g.nodes.coords - c, axis=1) < 1e-12)
    assert node.size == 1  # the crossing is one node
    at = np.any(g.faces.nodes.reshape(-1, 2) == node[0], axis=1)
    assert np.unique(g.faces.neighbors[at]).size == 6  # 8 first sites, two pairs shared
    assert _lengths(g)[g.faces.tag == 1].sum() == pytest.approx(7.6, rel=1e-12)
    assert _lengths(g)[g.faces.tag == 2].sum() == pytest.approx(7.4, rel=1e-12)
    area, face = _relative_sizes(pg)
    assert area.min() > 0.3 and face.min() > 0.01


def test_faults_meeting_at_a_small_angle_share_one_row_of_cells():
    """Two faults leaving one point 4.76 degrees apart (used to be refused): one row of cells fills the
    wedge between them, each cell's faces on both traces exactly, until the wedge is wide enough for two
    rows of mirrored sites; the first (triangular) cell keeps 1/8 of a step squared."""
    faults = [Fault([(2, 2), (8, 2)], "a"), Fault([(2, 2), (8, 2.5)], "b")]
    pg = pebi_grid(R10, 0.5, faults=faults)
    g = pg.grid
    geo = gl.compute_geometry(g)
    gl.check_grid(g, geo)
    assert geo.cell_volumes.sum() == pytest.approx(100.0, rel=1e-12)
    assert _lengths(g)[g.faces.tag == 1].sum() == pytest.approx(6.0, rel=1e-12)
    assert _lengths(g)[g.faces.tag == 2].sum() == pytest.approx(np.hypot(6, 0.5), rel=1e-12)
    on_both = np.intersect1d(g.faces.neighbors[g.faces.tag == 1], g.faces.neighbors[g.faces.tag == 2])
    assert on_both.size == 15 and np.all(pg.site_kind[on_both] == 2)
    assert (
        "fault 'a' (faults[0]) meets fault 'b' (faults[1]) at 4.76 degrees at (2, 2): one row of 15 cells"
        in (" ".join(pg.notes))
    )
    area, face = _relative_sizes(pg)
    assert area.min() == pytest.approx(0.125, rel=1e-9) and face.min() > 0.01
    assert _site_orthogonality(pg).max() < 1e-4


@pytest.mark.parametrize(
    "angles",
    [
        (0.0, 15.0, 30.0),
        (0.0, 12.0, 40.0),
        (0.0, 8.0, 16.0, 24.0),
        (0.0, 5.3, 32.0),
        (0.0, 9.8, 39.3),
        (0.0, 12.4, 17.7, 22.2),
        (0.0, 25.0, 30.9, 52.1),
    ],
)
def test_a_splay_of_faults_at_small_angles_builds(angles):
    """Three or four faults leaving one point a few degrees apart (a splay): the wedges between them
    share their middle arms, each with a row of cells on its ray (rays mirror images across the shared
    arms); every trace is followed exactly. Gaps of very different widths (5.3 beside 26.7 degrees,
    5.9 between 25 and 21.2) used to be refused: their rays kept off the sides of the wide gap, which
    left the narrow one's ray hugging one side and the shared arm's circles several steps wide."""
    c = np.array([20.0, 20.0])
    units = [np.array([np.cos(np.radians(a)), np.sin(np.radians(a))]) for a in angles]
    faults = [Fault([c, c + 12.0 * u]) for u in units]
    pg = pebi_grid(rectangle(0, 0, 40, 40), 2.0, faults=faults)
    g = pg.grid
    geo = gl.compute_geometry(g)
    gl.check_grid(g, geo)
    assert geo.cell_volumes.sum() == pytest.approx(1600.0, rel=1e-12)
    for k in range(1, len(angles) + 1):
        assert _lengths(g)[g.faces.tag == k].sum() == pytest.approx(12.0, rel=1e-12)
    gaps = " and ".join(f"{b - a:.3g}" for a, b in itertools.pairwise(angles))
    assert any(f"meet at {gaps} degrees at (20, 20)" in n for n in pg.notes), pg.notes
    area, face = _relative_sizes(pg)
    assert area.min() >= 0.1 and face.min() >= 0.01


def test_wells_next_to_a_fault_keep_clear_of_its_circles():
    """A well 1.2 cells from a fault (used to be refused) gets smaller rings, said in the notes; a well
    a tenth of a cell from it, closer than the fault's cells are wide, gets the fault cell on its side
    (tests/voronoi/test_pebi_wells_on_faults.py has the rest)."""
    fault = Fault([(2, 2), (8, 2)], "F")
    pg = pebi_grid(R10, 0.5, faults=[fault], wells=[Well((5, 2.6), "P", rings=Rings(0.1, 0.5))])
    gl.check_grid(pg.grid)
    assert (
        "well 'P' (wells[0]): rings shrunk to outer radius 0.175 m (from 0.5 m; 2 of 3 rings) to keep clear "
        "of fault 'F' (faults[0]), 0.6 m away"
    ) in pg.notes
    ring = np.hypot(*(pg.sites[pg.cell_well == 1] - [5, 2.6]).T)
    assert ring.max() == pytest.approx(0.175) and np.bincount(pg.cell_well).tolist()[1] == 1 + 2 * 6
    assert _lengths(pg.grid)[pg.grid.faces.tag == 1].sum() == pytest.approx(6.0, rel=1e-12)
    pg = pebi_grid(R10, 0.5, faults=[fault], wells=[Well((5, 2.05), "Q")])
    gl.check_grid(pg.grid)
    (mine,) = np.flatnonzero(pg.cell_well == 1)
    assert pg.site_kind[mine] == FAULT and pg.sites[mine, 1] > 2.0  # the fault cell on the well's side
    assert not any("refined locally" in n for n in pg.notes)
    assert _lengths(pg.grid)[pg.grid.faces.tag == 1].sum() == pytest.approx(6.0, rel=1e-12)


def test_well_paths_across_and_along_a_fault_get_its_cells():
    """A well path crossing a fault (used to be refused) has no site in the fault's circles: the two
    fault cells at the crossing are the well's; a path running along the trace 0.1 to 0.2 m off it
    gets the fault cells on its side."""
    fault = Fault([(2, 2), (8, 2)], "F")
    pg = pebi_grid(R10, 0.5, faults=[fault], wells=[Well(path=[(5, 1), (5, 3)], name="H")])
    gl.check_grid(pg.grid)
    mine = np.flatnonzero(pg.cell_well == 1)
    assert pg.site_kind[mine].tolist().count(2) == 2 and pg.site_kind[mine].tolist().count(4) == 4
    side = np.sign(pg.sites[mine[pg.site_kind[mine] == 2], 1] - 2.0)
    assert sorted(side.tolist()) == [-1.0, 1.0]  # one on each side of the trace
    assert any("'H' (wells[0]): 1 of its 5 sites would lie in the circles" in n for n in pg.notes)
    pg = pebi_grid(R10, 0.5, faults=[fault], wells=[Well(path=[(3, 2.1), (7, 2.2)], name="A")])
    gl.check_grid(pg.grid)
    mine = np.flatnonzero(pg.cell_well == 1)
    assert mine.size >= 7 and np.all(pg.site_kind[mine] == 2) and np.all(pg.sites[mine, 1] > 2.0)
    assert _lengths(pg.grid)[pg.grid.faces.tag == 1].sum() == pytest.approx(6.0, rel=1e-12)


def test_pebi_grid_is_exported():
    assert gl.voronoi.pebi_grid is pebi_grid
    assert isinstance(pebi_grid(rectangle(0, 0, 2, 2), 1.0), PebiGrid)


R10 = rectangle(0, 0, 10, 10)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (
            {"domain": [(0, 0), (1, 1), (0, 0)]},
            r"domain: a polygon needs at least 3 distinct vertices, got 2",
        ),
        (
            {"domain": [(0, 0), (2, 2), (2, 0), (0, 2)]},
            r"domain: the polygon's boundary intersects itself near \(1, 1\)",
        ),
        ({"domain": [(0, 0), (1, 1), (2, 2)]}, r"domain: the polygon encloses no area"),
        ({"domain": shapely.LineString([(0, 0), (1, 0), (1, 1)])}, r"domain: the line is not closed"),
        ({"domain": [(0, 0), (1, np.nan), (1, 1)]}, r"domain: vertex 1 is not finite"),
        (
            {"cell_size": 0.0},
            r"cell_size must be a positive length in metres or a callable h\(x, y\), got 0.0",
        ),
        ({"cell_size": -1}, r"cell_size must be a positive length .* got -1"),
        ({"cell_size": "big"}, r"cell_size must be a positive length .* got 'big'"),
        (
            {"cell_size": lambda x, y: x - 5},
            r"cell_size\(x, y\) must be a positive length, but it is -4.84375 at",
        ),
        ({"cell_size": lambda x, y: 0.0 * x}, r"cell_size\(x, y\) must be a positive length, but it is 0.0"),
        (
            {"faults": [Fault([(1, 1), (9, 9)]), Fault([(12, 2), (18, 2)], "F2")]},
            r"fault 'F2' \(faults\[1\]\): the trace lies outside the domain",
        ),
        (
            {"faults": [Fault([(1, 1)], "one")]},
            r"fault 'one' \(faults\[0\]\): a trace needs at least 2 points",
        ),
        (
            {"faults": [Fault([(1, 1), (9, 9), (1, 9), (9, 1)])]},
            r"fault 'F1' \(faults\[0\]\): the trace crosses itself",
        ),
        (
            {"faults": [Fault([(1, 1), (9, 9)], spacing=-1)]},
            r"fault 'F1' \(faults\[0\]\): spacing must be a positive",
        ),
        (
            {"faults": [Fault([(1, 5), (9, 5)], "a"), Fault([(3, 5), (7, 5)], "b")]},
            r"fault 'a' \(faults\[0\]\) and fault 'b' \(faults\[1\]\) overlap",
        ),
        (
            {"wells": [Well((15, 5))]},
            r"well 'W1' \(wells\[0\]\): its point \(15, 5\) lies outside the domain",
        ),
        (
            {"wells": [Well(path=[(5, 5), (12, 5)], name="H")]},
            r"well 'H' \(wells\[0\]\): the path leaves the domain",
        ),
        (
            {"wells": [Well((0.5, 5), rings=Rings(0.1, 1.0))]},
            r"well 'W1' \(wells\[0\]\): its rings \(outer radius 1 m\) reach outside the domain",
        ),
        (
            {
                "wells": [
                    Well((5, 5), "P1", rings=Rings(0.1, 1.0)),
                    Well((6.5, 5), "P2", rings=Rings(0.1, 1.0)),
                ]
            },
            r"well 'P1' \(wells\[0\]\) and well 'P2' \(wells\[1\]\) are too close: 1.5 m apart, "
            r"their rings and clearances need 2.25 m",
        ),
        (
            {"wells": [Well((5, 5), rings=Rings(inner=2.0, outer=1.0))]},
            r"well 'W1' \(wells\[0\]\): rings: outer \(1.0\) is smaller than inner",
        ),
        ({"wells": [Well()]}, r"well 'W1' \(wells\[0\]\): give either a point or a path"),
        ({"wells": [(5, 5)]}, r"wells\[0\]: expected a Well, got tuple"),
        ({"pattern": "triangles"}, r"pattern must be 'hexagonal' or 'cartesian', got 'triangles'"),
        ({"padding": -2}, r"padding must be a number of rows"),
        ({"padding": 2, "cell_size": lambda x, y: 1.0 + 0 * x}, r"padding needs a numeric cell_size"),
    ],
)
def test_bad_input_is_a_clear_error(kwargs, message):
    args = {"domain": R10, "cell_size": 0.5, "faults": (), "wells": ()}
    args.update(kwargs)
    with pytest.raises(gl.GridError, match=message):
        pebi_grid(args.pop("domain"), args.pop("cell_size"), **args)


@pytest.mark.parametrize("pattern", ["hexagonal", "cartesian"])
def test_lattice_cells_near_a_point_include_every_circumcircle_holding_it(pattern):
    """The stencil that marks lattice cells dirty misses no cell whose circumcircle holds a foreign site."""
    ii, jj = np.meshgrid(np.arange(-3, 9), np.arange(-3, 9), indexing="ij")
    lat = lattice_module.Lattice(
        pattern, np.array([0.3, -0.2]), 2.0, np.column_stack([ii.ravel(), jj.ravel()])
    )
    cells = lattice_module._Cells(lat)
    all_ids = np.arange(cells.n)
    centres = cells.centres(all_ids)
    p = np.random.default_rng(7).uniform(0, 8, (500, 2))
    holding = np.linalg.norm(centres[None, :, :] - p[:, None, :], axis=2) < cells.radius * (1 + 1e-6)
    pt, cid = cells.near(p)
    found = np.zeros_like(holding)
    found[pt, cid] = True
    assert holding.sum() > 500
    assert not np.any(holding & ~found)
