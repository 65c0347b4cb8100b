"""Exact values of the quality measures: a Cartesian grid, a sheared grid (analytic angles),
a twisted hexahedron, a tetrahedron and a planar grid."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from gridlib import cart_grid, compute_geometry
from gridlib.cornerpoint.deck import Deck
from gridlib.cornerpoint.process import process_grdecl
from gridlib.grid import Nodes
from gridlib.quality import MEASURES, XTGEO_NAMES, cell_quality
from gridlib.quality.cells import face_nonplanarity
from gridlib.units import QUANTITIES
from gridlib.unstructured import tetrahedral_grid

HEXAHEDRAL = [m.name for m in MEASURES if m.hexahedral_only]


def test_measures_are_named_once_with_known_units():
    names = [m.name for m in MEASURES]
    assert len(set(names)) == len(names)
    assert {m.unit for m in MEASURES} <= set(QUANTITIES)
    assert XTGEO_NAMES == (
        "minangle_topbase", "maxangle_topbase", "minangle_topbase_proj", "maxangle_topbase_proj",
        "minangle_sides", "maxangle_sides", "collapsed", "faulted", "negative_thickness", "concave_proj",
    )  # fmt: skip


def test_cartesian_grid():
    g = cart_grid([3, 2, 2], [3.0, 2.0, 2.0])
    q = cell_quality(g, compute_geometry(g), perm=np.tile([100.0, 50.0, 5.0], (g.num_cells, 1)))
    assert list(q) == [m.name for m in MEASURES]
    expected = dict.fromkeys(XTGEO_NAMES[:6], 90.0) | dict.fromkeys(XTGEO_NAMES[6:], 0.0)
    expected |= {"twist": 0.0, "orientation_error": 0.0, "k_orientation_error": 0.0}
    expected |= {"aspect_ratio": 1.0, "face_nonplanarity": 0.0}
    for name, value in expected.items():
        np.testing.assert_array_equal(q[name], np.full(g.num_cells, value), err_msg=name)


def test_sheared_grid_angles_are_the_shear_angle():
    """x += z tan(t): i-faces lean by t, so the centre lines of k neighbours and the normals of
    i-faces both turn by t; with kz = 10 kx, K n of an i-face turns by atan(10 tan t)."""
    t = math.radians(20.0)
    g = cart_grid([3, 2, 2], [3.0, 2.0, 2.0])
    xyz = g.nodes.coords.copy()
    xyz[:, 0] += xyz[:, 2] * math.tan(t)  # machine-independent: a constant
    g = replace(g, nodes=Nodes(xyz))
    q = cell_quality(g, compute_geometry(g), perm=np.tile([1.0, 1.0, 10.0], (g.num_cells, 1)))
    deg = math.degrees(t)
    expected = {
        "orientation_error": deg,
        "k_orientation_error": math.degrees(math.atan(10.0 * math.tan(t))),  # machine-independent: test
        "minangle_sides": 90.0 - deg,
        "maxangle_sides": 90.0 + deg,
        "minangle_topbase": 90.0,
        "maxangle_topbase_proj": 90.0,
        "aspect_ratio": 1.0 / math.cos(t),
        "twist": 0.0,
        "face_nonplanarity": 0.0,
        "concave_proj": 0.0,
    }
    for name, value in expected.items():
        np.testing.assert_allclose(q[name], value, rtol=1e-13, atol=1e-12, err_msg=name)


def twisted_cube(degrees: float) -> Deck:
    """One cell: the unit square at depth 0, its base at depth 1 turned by ``degrees`` about the
    vertical through its centre."""
    top = np.array([[-0.5, -0.5], [0.5, -0.5], [-0.5, 0.5], [0.5, 0.5]])  # pillars (a, b): a + 2b
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    bottom = top @ np.array([[c, s], [-s, c]])  # machine-independent: 2x2 exact-enough test data
    coord = np.concatenate([top, np.zeros((4, 1)), bottom, np.ones((4, 1))], axis=1)
    zcorn = np.repeat([0.0, 1.0], 4)
    return Deck((1, 1, 1), coord.ravel(), zcorn)


def test_twisted_hexahedron():
    deck = twisted_cube(30.0)
    grid = process_grdecl(deck).grid
    geo = compute_geometry(grid)
    for q in (cell_quality(grid, geo, deck=deck), cell_quality(grid, geo)):
        np.testing.assert_allclose(q["twist"], [30.0], rtol=1e-13)
        np.testing.assert_allclose(q["minangle_topbase"], [90.0], rtol=1e-13)
        np.testing.assert_allclose(q["maxangle_topbase"], [90.0], rtol=1e-13)
        assert q["concave_proj"].tolist() == [0.0]
    # a quadrilateral's nodes lie +-h/2 off its plane, h the distance between the lines of its
    # diagonals along their common normal: the measure is h / 2 / sqrt(area)
    per_face = face_nonplanarity(grid, geo)
    expected = np.zeros(grid.num_faces)
    for f in range(grid.num_faces):
        x = grid.nodes.coords[grid.faces.nodes[grid.faces.node_pos[f] : grid.faces.node_pos[f + 1]]]
        assert x.shape == (4, 3)
        m = np.cross(x[2] - x[0], x[3] - x[1])
        expected[f] = abs(np.sum(m * (x[1] - x[0]))) / np.sqrt(np.sum(m * m)) / 2 / np.sqrt(geo.face_areas[f])
    np.testing.assert_allclose(per_face, expected, rtol=1e-12, atol=1e-15)
    assert (expected[grid.faces.num_nodes == 4] > 0.05).sum() == 4  # the four sides, not top and base
    np.testing.assert_allclose(cell_quality(grid, geo)["face_nonplanarity"], [expected.max()], rtol=1e-15)


def test_regular_tetrahedron_and_planar_grid():
    tet = tetrahedral_grid([[1.0, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]])
    q = cell_quality(tet, compute_geometry(tet))
    for name in HEXAHEDRAL:
        assert np.isnan(q[name]).all(), name
    np.testing.assert_allclose(q["aspect_ratio"], [1.0], rtol=1e-14)
    np.testing.assert_allclose(q["face_nonplanarity"], [0.0], atol=1e-15)
    assert np.isnan(q["orientation_error"]).all()  # one cell: no interior face
    flat = cart_grid([2, 3], [2.0, 6.0])
    q = cell_quality(flat, compute_geometry(flat))
    np.testing.assert_array_equal(q["aspect_ratio"], np.full(6, 2.0))
    np.testing.assert_array_equal(q["orientation_error"], np.zeros(6))
    for name in (*HEXAHEDRAL, "face_nonplanarity"):
        assert np.isnan(q[name]).all(), name


def test_the_same_bits_on_one_thread_or_two(monkeypatch):
    """Blocks of cells are measured on threads (GRIDLIB_NUM_THREADS): each block writes its own
    rows, so one thread or two give identical arrays, from the deck and from the grid's faces."""
    from gridlib.cornerpoint.generators import make_model3

    deck = make_model3([50, 44, 32])  # 70,400 cells: two deck blocks, three blocks of hexahedra
    grid = process_grdecl(deck).grid
    geometry = compute_geometry(grid)
    perm = np.tile([100.0, 100.0, 10.0], (grid.num_cells, 1))
    runs = []
    for n in ("1", "2"):
        monkeypatch.setenv("GRIDLIB_NUM_THREADS", n)
        runs.append(
            (cell_quality(grid, geometry, deck=deck, perm=perm), cell_quality(grid, geometry, perm=perm))
        )
    (one_deck, one_grid), (two_deck, two_grid) = runs
    for name in one_deck:
        assert np.array_equal(one_deck[name], two_deck[name], equal_nan=True), name
        assert np.array_equal(one_grid[name], two_grid[name], equal_nan=True), name
    assert np.count_nonzero(runs[0][0]["faulted"] == 1.0) > 0  # the fault is in the blocks measured


def test_orientation_errors_are_the_largest_face_angle_of_each_cell(monkeypatch):
    """Per cell, the face of smallest cosine carries the largest of gridlib.orientation's face
    angles (plain and with K on each side), on a faulted, pinched grid with random
    anisotropic permeability, measured in blocks of 37 cells; cells without a measured face
    are NaN."""
    from gridlib.cornerpoint.generators import make_model3
    from gridlib.orientation import face_angles
    from gridlib.quality import cells
    from gridlib.quality.cells import face_measures

    monkeypatch.setattr(cells, "_CELLS", 37)

    grid = process_grdecl(make_model3([9, 8, 6])).grid
    geometry = compute_geometry(grid)
    perm = np.random.default_rng(3).lognormal(size=(grid.num_cells, 3))
    measures = face_measures(grid, geometry, perm=perm)
    plain, k = measures["orientation_error"], measures["k_orientation_error"]
    fa = face_angles(grid.faces.neighbors, geometry.face_normals, geometry.cell_centroids, perm)
    want_plain, want_k = np.full(grid.num_cells, np.nan), np.full(grid.num_cells, np.nan)
    for face, angle, k_angle in zip(fa.faces, fa.angles, fa.k_angles, strict=True):
        for cell in grid.faces.neighbors[face]:
            want_plain[cell] = np.fmax(want_plain[cell], angle)
            want_k[cell] = np.fmax(want_k[cell], k_angle)
    assert np.count_nonzero(~np.isnan(want_plain)) == grid.num_cells
    np.testing.assert_allclose(plain, want_plain, rtol=1e-13, atol=1e-12)
    np.testing.assert_allclose(k, want_k, rtol=1e-13, atol=1e-12)
    assert np.nanmax(k) > 30.0  # the anisotropy shows
