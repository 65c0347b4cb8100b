"""make_layered_grid: Cartesian and PEBI columns, depths per node, surfaces, bad layers."""

from __future__ import annotations

import numpy as np
import pytest
from seed_points import radial_points

import gridlib as gl
from gridlib.grid import B, T


def test_layered_cartesian_equals_cart_grid_3d():
    lay = gl.make_layered_grid(gl.cart_grid([4, 3], [4.0, 3.0]), thickness=[0.5, 1.5])
    ref = gl.tensor_grid(np.arange(5.0), np.arange(4.0), [0.0, 0.5, 2.0])
    assert lay.cart_dims == (4, 3, 2)
    a, b = gl.compute_geometry(lay), gl.compute_geometry(ref)
    # Same cells in the same (i fastest, then j, then k) order.
    np.testing.assert_allclose(a.cell_volumes, b.cell_volumes, rtol=1e-15)
    np.testing.assert_allclose(a.cell_centroids, b.cell_centroids, rtol=1e-15)
    assert lay.cells.index_map.tolist() == list(range(24))
    # Tags carried over, T and B added; MRST numbering: interfaces first.
    assert lay.cells.face_tag[:2].tolist() == [T, B]
    assert lay.faces.neighbors[:3].tolist() == [[-1, 0], [-1, 1], [-1, 2]]
    np.testing.assert_allclose(a.face_normals[: 3 * 12], np.tile([0, 0, 1.0], (36, 1)))
    gl.check_grid(lay, a)


def test_layer_depths_per_node_tilted_plane_volume_is_exact():
    areal = gl.pebi(gl.triangle_grid(radial_points() * 100.0))
    x, y = areal.nodes.coords.T
    top = 2000.0 + 0.05 * x - 0.02 * y
    depths = np.stack([top, top + 10.0, top + 25.0])  # two layers of 10 m and 15 m
    g = gl.make_layered_grid(areal, depths=depths)
    geo = gl.compute_geometry(g)
    area = gl.compute_geometry(areal).cell_volumes.sum()
    assert geo.cell_volumes.sum() == pytest.approx(25.0 * area, rel=1e-12)
    layer_vol = np.bincount(g.layering.layer, geo.cell_volumes)
    np.testing.assert_allclose(layer_vol, [10.0 * area, 15.0 * area], rtol=1e-12)
    assert g.layering.num_layers == 2 and g.layering.column.max() == areal.num_cells - 1
    gl.check_grid(g, geo)


def test_layered_surface_grid_follows_its_z():
    pts = np.random.default_rng(4).uniform(size=(60, 2)) * 100
    z = 1500.0 + 0.1 * pts[:, 0]
    g = gl.make_layered_grid(gl.triangle_grid(np.column_stack([pts, z])), thickness=[2.0, 3.0])
    geo = gl.compute_geometry(g)
    planar_area = gl.compute_geometry(gl.triangle_grid(pts)).cell_volumes.sum()
    assert geo.cell_volumes.sum() == pytest.approx(5.0 * planar_area, rel=1e-12)
    assert g.nodes.coords[:, 2].min() == pytest.approx(z.min())
    gl.check_grid(g, geo)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({}, "exactly one of"),
        ({"num_layers": 0}, "positive integer"),
        ({"thickness": [1.0, -1.0]}, "positive numbers"),
        ({"depths": [0.0, 1.0, 1.0]}, "layer 1 has thickness 0.0 <= 0 at areal node 0"),
        ({"depths": np.zeros((2, 3))}, r"depths must have shape \(nl\+1,\) or \(nl\+1, 9\)"),
    ],
)
def test_make_layered_grid_rejects_bad_layers(kwargs, message):
    with pytest.raises(gl.GridError, match=message):
        gl.make_layered_grid(gl.cart_grid([2, 2]), **kwargs)
