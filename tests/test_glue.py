"""glue_2d: matching and non-matching interfaces, the seed's multiblock grid, bad input."""

from __future__ import annotations

import numpy as np
import pytest

import gridlib as gl


def test_glue_matching_and_non_matching_interfaces():
    left = gl.cart_grid([2, 2])
    right = gl.translate_grid(gl.cart_grid([3, 3], [1.0, 2.0]), [2.0, 0.0])
    g = gl.glue_2d(left, right)
    assert g.num_cells == 13
    # Interface x = 2 is split at y = 0, 2/3, 1, 4/3, 2: 4 shared pieces.
    inner = (g.faces.neighbors >= 0).all(axis=1)
    geo = gl.compute_geometry(g)
    on_x2 = inner & np.isclose(geo.face_centroids[:, 0], 2.0)
    assert on_x2.sum() == 4
    assert geo.face_areas[on_x2].sum() == pytest.approx(2.0, rel=1e-14)
    assert geo.cell_volumes.sum() == pytest.approx(6.0, rel=1e-14)
    assert g.cells.num_faces[1] == 5  # the left cell now has a hanging node
    gl.check_grid(g, geo)


def test_glue_multiblock_of_the_seed():
    """§3.5.4: three blocks glued, padded above and below, twisted: 600 cells, area 9."""
    g1, g2, g3 = gl.cart_grid([5, 5], [1, 1]), gl.cart_grid([20, 20], [1, 1]), gl.cart_grid([15, 5], [3, 1])
    g = gl.glue_2d(g1, gl.translate_grid(g2, [1, 0]))
    g = gl.glue_2d(g, gl.translate_grid(g1, [2, 0]))
    g = gl.glue_2d(g3, gl.translate_grid(g, [0, 1]))
    g = gl.glue_2d(g, gl.translate_grid(g3, [0, 2]))
    g = gl.twister(g)
    geo = gl.compute_geometry(g)
    assert g.num_cells == 600
    assert int((g.faces.neighbors < 0).any(axis=1).sum()) == 60
    assert geo.cell_volumes.sum() == pytest.approx(9.0, rel=1e-13)
    gl.check_grid(g, geo)
    layered = gl.make_layered_grid(g, 5)
    assert gl.compute_geometry(layered).cell_volumes.sum() == pytest.approx(45.0, rel=1e-13)
    gl.check_grid(layered)


def test_glue_rejects_non_planar():
    with pytest.raises(gl.GridError, match="g2 must be a planar 2-D grid"):
        gl.glue_2d(gl.cart_grid([2, 2]), gl.cart_grid([2, 2, 2]))
