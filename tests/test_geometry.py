"""compute_geometry against analytic values."""

from __future__ import annotations

import numpy as np
import pytest

import gridlib as gl


def test_hinge_tessellation_of_a_warped_face_matches_the_formula():
    """A single cell whose top face is warped: face values follow the book's (3.2)."""
    g = gl.cart_grid([1, 1, 1])
    c = np.array(g.nodes.coords)
    c[4, 2] += 0.3  # lift one bottom corner: the bottom face (z = 1) becomes non-planar
    g = gl.Grid(g.cells, g.faces, gl.Nodes(c), 3)
    geo = gl.compute_geometry(g)
    f = g.num_faces - 1  # bottom face
    p = c[g.faces.nodes[4 * f : 4 * f + 4]]
    h = p.mean(axis=0)
    tri_n = 0.5 * np.cross(np.roll(p, -1, axis=0) - p, h - p)
    tri_a = np.linalg.norm(tri_n, axis=1)
    tri_c = (p + np.roll(p, -1, axis=0) + h) / 3
    assert geo.face_areas[f] == pytest.approx(tri_a.sum(), rel=1e-15)
    np.testing.assert_allclose(geo.face_normals[f], tri_n.sum(axis=0), rtol=1e-15)
    np.testing.assert_allclose(
        geo.face_centroids[f], (tri_a[:, None] * tri_c).sum(0) / tri_a.sum(), rtol=1e-15
    )
    assert np.linalg.norm(geo.face_normals[f]) < geo.face_areas[f]
    # Volume: a unit cube plus the tetrahedra-fan bulge of the warped face.
    bulge = np.dot(h - c[0], tri_n.sum(axis=0)) / 3 - 1.0 / 3  # apex at node 0 sees the face
    assert geo.cell_volumes[0] == pytest.approx(1.0 + bulge, rel=1e-14)
    gl.check_grid(g, geo)


def test_prism_volume_and_centroid():
    tri = gl.triangle_grid([[0, 0], [3, 0], [0, 3]])
    g = gl.make_layered_grid(tri, thickness=[2.0])
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes[0] == pytest.approx(9.0, rel=1e-15)
    np.testing.assert_allclose(geo.cell_centroids[0], [1.0, 1.0, 1.0], rtol=1e-15)


def test_planar_polygon_area_and_centroid_of_an_l_shape():
    pts = [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]
    g = gl.tessellation_grid(pts, [[0, 1, 2, 3, 4, 5]])
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes[0] == pytest.approx(3.0, rel=1e-15)
    np.testing.assert_allclose(geo.cell_centroids[0], [5 / 6, 5 / 6], rtol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(geo.face_normals, axis=1), geo.face_areas, rtol=1e-15)


def test_volumes_are_translation_invariant_at_utm_magnitudes():
    g = gl.twister(gl.cart_grid([6, 5, 4], [600.0, 500.0, 40.0]))
    far = gl.translate_grid(g, [5.3e5, 6.7e6, 2500.0])
    a, b = gl.compute_geometry(g), gl.compute_geometry(far)
    np.testing.assert_allclose(b.cell_volumes, a.cell_volumes, rtol=1e-9)
    np.testing.assert_allclose(b.cell_centroids - [5.3e5, 6.7e6, 2500.0], a.cell_centroids, atol=1e-6)
    assert b.cell_volumes.sum() == pytest.approx(600 * 500 * 40.0, rel=1e-11)


def test_gauss_green_volume_agrees_on_planar_faces():
    g = gl.make_layered_grid(gl.pebi(gl.triangle_grid(np.random.default_rng(5).uniform(size=(50, 2)))), 2)
    geo = gl.compute_geometry(g)
    hc = np.repeat(np.arange(g.num_cells), g.cells.num_faces)
    f = g.cells.faces
    sign = np.where(g.faces.neighbors[f, 0] == hc, 1.0, -1.0)
    gg = np.bincount(hc, sign * (geo.face_centroids[f] * geo.face_normals[f]).sum(axis=1)) / 3
    np.testing.assert_allclose(gg, geo.cell_volumes, rtol=1e-12)


def test_zero_area_faces_are_reported():
    g = gl.cart_grid([1, 1, 1])
    c = np.array(g.nodes.coords)
    c[[1, 3, 5, 7], 0] = 0.0  # collapse the cell onto the x = 0 plane
    with pytest.raises(gl.GridError, match="zero area"):
        gl.compute_geometry(gl.Grid(g.cells, g.faces, gl.Nodes(c), 3))


def _exact_convex_cells(grid: gl.Grid) -> tuple[np.ndarray, np.ndarray]:
    """Volumes and centroids of convex cells by a Delaunay split of each cell's nodes."""
    from scipy.spatial import Delaunay

    vols, cents = [], []
    hc = np.repeat(np.arange(grid.num_cells), grid.cells.num_faces)
    for c in range(grid.num_cells):  # test oracle, small grids only
        faces = grid.cells.faces[hc == c]
        nodes = np.unique(
            np.concatenate(
                [grid.faces.nodes[grid.faces.node_pos[f] : grid.faces.node_pos[f + 1]] for f in faces]
            )
        )
        p = grid.nodes.coords[nodes]
        t = Delaunay(p).simplices
        d1, d2, d3 = (p[t[:, i]] - p[t[:, 0]] for i in (1, 2, 3))
        v = np.abs(np.einsum("ij,ij->i", np.cross(d1, d2), d3)) / 6
        vols.append(v.sum())
        cents.append((v[:, None] * p[t].mean(axis=1)).sum(axis=0) / v.sum())
    return np.array(vols), np.array(cents)


def test_centroids_of_trapezoid_cells_are_exact():
    g = gl.cart_grid([1, 1, 1])
    c = np.array(g.nodes.coords)
    c[:, :2] *= 2.0
    c[c[:, 2] == 0, :2] *= 0.5  # a frustum: top 1x1, bottom 2x2
    g = gl.Grid(g.cells, g.faces, gl.Nodes(c), 3)
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes[0] == pytest.approx(7.0 / 3.0, rel=1e-15)
    np.testing.assert_allclose(
        geo.cell_centroids[0], [0.80357142857142857, 0.80357142857142857, 0.6071428571428571], rtol=1e-14
    )


def test_centroids_of_layered_pebi_prisms_are_exact():
    areal = gl.pebi(gl.triangle_grid(np.random.default_rng(7).uniform(size=(60, 2)) * 100))
    g = gl.make_layered_grid(areal, thickness=[2.0, 3.0])
    geo, ageo = gl.compute_geometry(g), gl.compute_geometry(areal)
    col, layer = g.layering.column, g.layering.layer
    np.testing.assert_allclose(geo.cell_centroids[:, :2], ageo.cell_centroids[col], rtol=1e-12)
    np.testing.assert_allclose(geo.cell_centroids[:, 2], np.array([1.0, 3.5])[layer], rtol=1e-12)
    vol, cent = _exact_convex_cells(g)
    np.testing.assert_allclose(geo.cell_volumes, vol, rtol=1e-12)
    np.testing.assert_allclose(geo.cell_centroids, cent, rtol=1e-12, atol=1e-10)


def test_cells_with_hanging_nodes_keep_exact_centroids():
    glued = gl.glue_2d(gl.cart_grid([2, 2]), gl.translate_grid(gl.cart_grid([3, 3], [1, 2]), [2, 0]))
    g = gl.make_layered_grid(glued, 1)
    vol, cent = _exact_convex_cells(g)
    geo = gl.compute_geometry(g)
    np.testing.assert_allclose(geo.cell_volumes, vol, rtol=1e-13)
    np.testing.assert_allclose(geo.cell_centroids, cent, rtol=1e-13)


def test_non_convex_planar_faces_have_their_true_area():
    """A U-shaped polygon: the hinge (node mean) lies outside; signed triangles fix the area."""
    u = [[0, 0], [3, 0], [3, 3], [2, 3], [2, 1], [1, 1], [1, 3], [0, 3]]
    planar = gl.tessellation_grid(u, [list(range(8))])
    surface = gl.tessellation_grid(np.column_stack([u, np.full(8, 1000.0)]), [list(range(8))])
    for g in (planar, surface):
        geo = gl.compute_geometry(g)
        assert geo.cell_volumes[0] == pytest.approx(7.0, rel=1e-15)
        np.testing.assert_allclose(geo.cell_centroids[0][:2], [1.5, 9.5 / 7.0], rtol=1e-14)
    prism = gl.make_layered_grid(planar, thickness=[2.0])
    geo = gl.compute_geometry(prism)
    assert geo.cell_volumes[0] == pytest.approx(14.0, rel=1e-15)
    np.testing.assert_allclose(geo.face_areas[:2], 7.0, rtol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(geo.face_normals[:2], axis=1), 7.0, rtol=1e-15)
    np.testing.assert_allclose(geo.cell_centroids[0], [1.5, 9.5 / 7.0, 1.0], rtol=1e-14)


def test_geometry_does_not_depend_on_the_number_of_threads(monkeypatch):
    """Face blocks run on threads (GRIDLIB_NUM_THREADS); the sums are added in block order."""
    g = gl.twister(gl.cart_grid([40, 40, 20], [400.0, 400.0, 40.0]))  # ~1e5 faces: several blocks
    results = []
    for n in ("1", "2"):
        monkeypatch.setenv("GRIDLIB_NUM_THREADS", n)
        results.append(gl.compute_geometry(g))
    for name in ("cell_volumes", "cell_centroids", "face_areas", "face_normals", "face_centroids"):
        assert np.array_equal(getattr(results[0], name), getattr(results[1], name)), name
