"""cart_grid, tensor_grid, twister, translate_grid, remove_cells: exact MRST structures."""

from __future__ import annotations

import numpy as np
import pytest

import gridlib as gl
from gridlib.grid import B, E, N, S, T, W


def test_remove_cells_reproduces_mrst_example_1():
    """Seed §3.4 Example 1: removeCells(cartGrid([3,2]), 2), 0-based."""
    g = gl.remove_cells(gl.cart_grid([3, 2]), [1])
    assert (g.num_cells, g.num_faces, g.num_nodes) == (5, 16, 12)
    assert g.cells.face_pos.tolist() == [0, 4, 8, 12, 16, 20]
    assert g.cells.index_map.tolist() == [0, 2, 3, 4, 5]
    assert g.cells.faces.reshape(-1, 4).tolist() == [
        [0, 8, 1, 10],
        [2, 9, 3, 12],
        [4, 10, 5, 13],
        [5, 11, 6, 14],
        [6, 12, 7, 15],
    ]
    assert g.cells.face_tag.reshape(-1, 4).tolist() == [[W, S, E, N]] * 5
    assert g.faces.nodes.reshape(-1, 2).tolist() == [
        [0, 4], [1, 5], [2, 6], [3, 7], [4, 8], [5, 9], [6, 10], [7, 11],
        [1, 0], [3, 2], [5, 4], [6, 5], [7, 6], [9, 8], [10, 9], [11, 10],
    ]  # fmt: skip
    assert g.faces.neighbors.tolist() == [
        [-1, 0], [0, -1], [-1, 1], [1, -1], [-1, 2], [2, 3], [3, 4], [4, -1],
        [-1, 0], [-1, 1], [0, 2], [-1, 3], [1, 4], [2, -1], [3, -1], [4, -1],
    ]  # fmt: skip
    assert g.history == ("tensor_grid", "cart_grid", "remove_cells")
    gl.check_grid(g)


def test_cart_grid_3d_counts_and_boundary():
    g = gl.cart_grid([4, 3, 2], [4, 3, 2])
    assert (g.num_cells, g.num_faces, g.num_nodes) == (24, 98, 60)
    assert int((g.faces.neighbors < 0).any(axis=1).sum()) == 52
    geo = gl.compute_geometry(g)
    np.testing.assert_allclose(geo.cell_volumes, 1.0, rtol=0, atol=1e-15)
    gl.check_grid(g, geo)


def test_cart_grid_numbering_follows_mrst():
    nx, ny, nz = 4, 3, 2
    g = gl.cart_grid([nx, ny, nz])
    # Nodes x fastest, then y, then z.
    c = g.nodes.coords
    assert c[1].tolist() == [1, 0, 0] and c[nx + 1].tolist() == [0, 1, 0]
    assert c[(nx + 1) * (ny + 1)].tolist() == [0, 0, 1]
    # All x-faces, then y-faces, then z-faces, with normals along +x, +y, +z.
    nfx, nfy = (nx + 1) * ny * nz, nx * (ny + 1) * nz
    n = gl.compute_geometry(g).face_normals
    np.testing.assert_array_equal(n[:nfx], np.tile([1.0, 0, 0], (nfx, 1)))
    np.testing.assert_array_equal(n[nfx : nfx + nfy], np.tile([0, 1.0, 0], (nfy, 1)))
    np.testing.assert_array_equal(n[nfx + nfy :], np.tile([0, 0, 1.0], (g.num_faces - nfx - nfy, 1)))
    # Half-faces W, E, S, N, T, B; cell 0's faces.
    assert g.cells.face_tag[:6].tolist() == [W, E, S, N, T, B]
    assert g.cells.faces[:6].tolist() == [0, 1, nfx, nfx + nx, nfx + nfy, nfx + nfy + nx * ny]
    # Neighbours of the first x-faces: outside | 0 | 1 ...
    assert g.faces.neighbors[:3].tolist() == [[-1, 0], [0, 1], [1, 2]]


def test_tensor_grid_volumes_and_areas():
    g = gl.tensor_grid([0, 1, 3, 6], [0, 2, 5], [0, 0.5, 1.5, 3])
    assert (g.num_cells, g.num_faces, g.num_nodes) == (18, 75, 48)
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(90.0, rel=1e-15)
    assert geo.cell_volumes.min() == pytest.approx(1.0, rel=1e-15)
    assert geo.cell_volumes.max() == pytest.approx(13.5, rel=1e-15)
    assert geo.face_areas.sum() == pytest.approx(234.0, rel=1e-15)
    # Last cell spans [3,6]x[2,5]x[1.5,3].
    np.testing.assert_allclose(geo.cell_centroids[-1], [4.5, 3.5, 2.25], rtol=1e-15)


def test_fictitious_domain_ellipsoid():
    """Seed §3.1: cells of a 20^3 tensor grid outside x^2 + y^2/4 + z^2/4 <= 1 removed."""
    x = np.linspace(-2, 2, 21)
    g = gl.tensor_grid(x, x, x)
    c = gl.compute_geometry(g).cell_centroids
    g = gl.remove_cells(g, c[:, 0] ** 2 + 0.25 * c[:, 1] ** 2 + 0.25 * c[:, 2] ** 2 > 1)
    assert (g.num_cells, g.num_faces, g.num_nodes) == (2128, 7020, 2815)
    assert int((g.faces.neighbors < 0).any(axis=1).sum()) == 1272
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(17.024, rel=1e-14)
    gl.check_grid(g, geo)


def test_tensor_grid_depth_z_follows_top_surface():
    x, y = np.array([0.0, 1.0, 2.0]), np.array([0.0, 1.0])
    top = 1000.0 + 0.1 * x[:, None] + 0.0 * y[None, :]
    g = gl.tensor_grid(x, y, [0.0, 2.0, 5.0], depth_z=top)
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(2 * 1 * 5, rel=1e-13)
    assert g.nodes.coords[:, 2].min() == 1000.0
    gl.check_grid(g, geo)


def test_twister_keeps_the_box_and_total_volume():
    g0 = gl.cart_grid([30, 20], [3.0, 2.0])
    g = gl.twister(g0)
    assert g.history[-1] == "twister"
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(6.0, rel=1e-13)
    assert geo.cell_volumes.min() < 0.01 < geo.cell_volumes.max()  # cells really deformed
    on_box = (np.isclose(g0.nodes.coords, 0) | np.isclose(g0.nodes.coords, [3.0, 2.0])).any(axis=1)
    # Box edges stay straight: boundary nodes keep the boundary coordinate.
    box = g0.nodes.coords[on_box]
    moved = g.nodes.coords[on_box]
    assert np.all(np.isclose(box, 0) == np.isclose(moved, 0))
    g3 = gl.twister(gl.cart_grid([5, 4, 3]))
    assert gl.compute_geometry(g3).cell_volumes.sum() == pytest.approx(60.0, rel=1e-13)
    gl.check_grid(g3)


def test_translate_grid_moves_centroids_only():
    g = gl.cart_grid([3, 2, 2], [30.0, 20.0, 4.0])
    shift = [5.3e5, 6.7e6, 1500.0]  # UTM-sized
    moved = gl.translate_grid(g, shift)
    a, b = gl.compute_geometry(g), gl.compute_geometry(moved)
    np.testing.assert_allclose(b.cell_volumes, a.cell_volumes, rtol=1e-9)
    np.testing.assert_allclose(b.cell_centroids - shift, a.cell_centroids, atol=1e-8)


@pytest.mark.parametrize(
    ("dims", "lengths", "message"),
    [
        ([3], None, "2 or 3 integers"),
        ([3, 2, 1, 1], None, "2 or 3 integers"),
        ([3, 0], None, "positive integers"),
        ([3, 2.5], None, "positive integers"),
        ([3, 2], [1.0, -2.0], "positive and finite"),
        ([3, 2], [1.0], "2 dims but 1 lengths"),
        ("ab", None, "2 or 3 integers"),
    ],
)
def test_cart_grid_rejects_bad_input(dims, lengths, message):
    with pytest.raises(gl.GridError, match=message):
        gl.cart_grid(dims, lengths)


def test_tensor_grid_rejects_non_increasing_axis():
    with pytest.raises(gl.GridError, match=r"y must be strictly increasing; y\[2\] = 1.0 <= y\[1\] = 2.0"):
        gl.tensor_grid([0, 1], [0, 2, 1])
    with pytest.raises(gl.GridError, match="x needs at least 2"):
        gl.tensor_grid([0], [0, 1])
    with pytest.raises(gl.GridError, match="NaN"):
        gl.tensor_grid([0, np.nan], [0, 1])


def test_remove_and_extract_reject_unknown_cells():
    g = gl.cart_grid([3, 2])
    with pytest.raises(gl.GridError, match=r"unknown cell indices \[6\]"):
        gl.remove_cells(g, [1, 6])
    with pytest.raises(gl.GridError, match="unknown cell indices"):
        gl.remove_cells(g, [-1])
    with pytest.raises(gl.GridError, match="boolean mask must have shape"):
        gl.remove_cells(g, np.ones(5, dtype=bool))
    with pytest.raises(gl.GridError, match="empty grid"):
        gl.remove_cells(g, np.arange(6))
    with pytest.raises(gl.GridError, match="no cells selected"):
        gl.extract_subgrid(g, [])


def test_extract_subgrid_maps_back_to_parent():
    parent = gl.cart_grid([4, 4, 4])
    keep = np.arange(0, 64, 3)
    sub = gl.extract_subgrid(parent, keep)
    assert sub.cells.tolist() == keep.tolist()
    pg, sg = gl.compute_geometry(parent), gl.compute_geometry(sub.grid)
    np.testing.assert_array_equal(sg.cell_centroids, pg.cell_centroids[sub.cells])
    np.testing.assert_array_equal(sg.face_centroids, pg.face_centroids[sub.faces])
    np.testing.assert_array_equal(sub.grid.nodes.coords, parent.nodes.coords[sub.nodes])
    gl.check_grid(sub.grid)


def test_translate_moves_the_footprint_and_twister_drops_it():
    g = gl.make_layered_grid(gl.cart_grid([2, 2], [100.0, 100.0]), 2)
    moved = gl.translate_grid(g, [5.3e5, 6.7e6, 1000.0])
    np.testing.assert_allclose(
        moved.layering.areal.nodes.coords, g.layering.areal.nodes.coords + [5.3e5, 6.7e6]
    )
    assert gl.twister(g).layering is None
