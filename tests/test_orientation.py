"""Orientation angles (gridlib.orientation) against analytic values."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import gridlib as gl
from gridlib.cornerpoint.generators import simple_grdecl
from gridlib.cornerpoint.process import process_grdecl
from gridlib.errors import GridError, InputError
from gridlib.orientation import (
    face_angles,
    grid_face_angles,
    orientation_figures,
    vector_angles,
)

DIP = 60.0  # degrees from the horizontal: pillars drift cot(dip) m per m of depth
DRIFT = 1.0 / np.tan(np.radians(DIP))


def _axis(grid: gl.Grid, faces: np.ndarray) -> np.ndarray:
    """0, 1, 2: the axis (x, y, z) each face of a Cartesian grid is normal to."""
    return np.abs(gl.compute_geometry(grid).face_normals[faces]).argmax(axis=1)


def _sheared(grid: gl.Grid, drift: float) -> gl.Grid:
    """x + drift * z: every pillar inclined at atan(1 / drift) from the horizontal, towards +x."""
    c = np.array(grid.nodes.coords)
    c[:, 0] += drift * c[:, 2]
    return gl.Grid(grid.cells, grid.faces, gl.Nodes(c), 3, grid.cart_dims)


def test_a_cartesian_box_has_no_angle_even_with_anisotropic_permeability():
    g = gl.tensor_grid([0.0, 1.0, 3.0, 3.5], [0.0, 2.0, 2.5], [1000.0, 1004.0, 1005.0, 1011.0])
    geo = gl.compute_geometry(g)
    perm = np.column_stack(
        [np.full(g.num_cells, 300.0), np.full(g.num_cells, 30.0), np.full(g.num_cells, 3.0)]
    )
    got = grid_face_angles(g, geo, perm=perm)
    interior = int((g.faces.neighbors >= 0).all(axis=1).sum())
    assert got.faces.size == interior == 2 * 2 * 3 + 3 * 1 * 3 + 3 * 2 * 2
    assert (got.angles == 0.0).all() and (got.k_angles == 0.0).all()
    assert orientation_figures(got.angles) == {"median": 0.0, "p95": 0.0, "max": 0.0}


def test_faces_along_pillars_inclined_at_the_dip_make_90_minus_dip_with_the_centre_line():
    """The parallelepiped x + s z: the faces along the pillars (normal (1, 0, -s)) and the layer
    faces (normal (0, 0, 1), centres s dz apart in x) make atan(s) = 90 - dip with the line
    between their cells' centroids; the faces normal to y stay at 0."""
    g = _sheared(gl.cart_grid([4, 3, 2], [400.0, 300.0, 20.0]), DRIFT)
    got = grid_face_angles(g, gl.compute_geometry(g))
    axis = _axis(gl.cart_grid([4, 3, 2]), got.faces)
    want = np.where(axis == 1, 0.0, 90.0 - DIP)
    np.testing.assert_allclose(got.angles, want, rtol=0, atol=1e-12)
    # 18 faces normal to x, 16 to y, 12 to z: the 28 inclined ones are the median and above.
    assert np.bincount(axis).tolist() == [18, 16, 12]
    figures = orientation_figures(got.angles)
    assert figures == pytest.approx({"median": 30.0, "p95": 30.0, "max": 30.0}, abs=1e-12)


def test_a_corner_point_deck_with_inclined_pillars_gives_the_same_angles():
    """The same parallelepiped written as COORD (both pillar points moved by s z) and processed
    as a deck: what the case builders' corner-point grids go through."""
    deck = simple_grdecl([4, 3, 2], undisturbed=True, phys_dims=(400.0, 300.0, 20.0))
    coord = np.array(deck.coord).reshape(-1, 2, 3)
    coord[:, :, 0] += DRIFT * coord[:, :, 2]
    grid = process_grdecl(replace(deck, coord=coord.ravel())).grid
    got = grid_face_angles(grid, gl.compute_geometry(grid))
    axis = np.abs(gl.compute_geometry(grid).face_normals[got.faces]).argmax(axis=1)
    want = np.where(axis == 1, 0.0, 90.0 - DIP)
    assert got.faces.size == 46
    np.testing.assert_allclose(got.angles, want, rtol=0, atol=1e-10)


def test_k_n_angle_of_anisotropic_cells_on_inclined_pillars():
    """K = diag(kx, ky, kz): on a face along the pillars K n = (kx, 0, -s kz) against the centre
    line (1, 0, 0): atan(s kz / kx); on a layer face K n = (0, 0, kz), the line (s, 0, 1):
    atan(s), whatever K; faces normal to y: 0."""
    kx, ky, kz = 200.0, 50.0, 20.0
    g = _sheared(gl.cart_grid([4, 3, 2], [400.0, 300.0, 20.0]), DRIFT)
    perm = np.tile([kx, ky, kz], (g.num_cells, 1))
    got = grid_face_angles(g, gl.compute_geometry(g), perm=perm)
    axis = _axis(gl.cart_grid([4, 3, 2]), got.faces)
    along = np.degrees(np.arctan(DRIFT * kz / kx))
    want = np.choose(axis, [along, 0.0, 90.0 - DIP])
    np.testing.assert_allclose(got.k_angles, want, rtol=0, atol=1e-12)
    np.testing.assert_allclose(got.angles, np.where(axis == 1, 0.0, 90.0 - DIP), rtol=0, atol=1e-12)
    assert orientation_figures(got.k_angles) == pytest.approx(
        {"median": along, "p95": 90.0 - DIP, "max": 90.0 - DIP}, abs=1e-12
    )


def test_each_side_of_a_face_counts_and_a_side_without_permeability_does_not():
    """Two square cells side by side, rotated by theta in plan: the face normal is along the
    centre line. Isotropic left cell: 0; right cell ky = 4 kx: K n = (cos t, 4 sin t), at
    atan(4 tan t) - t from the line. The face's K angle is the larger one; a cell with no
    permeability has no K n and does not count."""
    theta = np.radians(25.0)
    rot = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    g = gl.cart_grid([2, 1], [20.0, 10.0])
    g = gl.Grid(g.cells, g.faces, gl.Nodes(g.nodes.coords @ rot.T), 2, g.cart_dims)
    geo = gl.compute_geometry(g)
    right = np.degrees(np.arctan(4.0 * np.tan(theta)) - theta)
    got = grid_face_angles(g, geo, perm=[[1.0, 1.0], [1.0, 4.0]])
    assert got.faces.size == 1 and got.angles[0] == pytest.approx(0.0, abs=1e-12)
    assert got.k_angles[0] == pytest.approx(right, abs=1e-12)
    assert grid_face_angles(g, geo, perm=[[1.0, 4.0], [1.0, 1.0]]).k_angles[0] == pytest.approx(
        right, abs=1e-12
    )
    assert grid_face_angles(g, geo, perm=[[0.0, 0.0], [1.0, 1.0]]).k_angles[0] == pytest.approx(
        0.0, abs=1e-12
    )
    assert np.isnan(grid_face_angles(g, geo, perm=[[0.0, 0.0], [0.0, 0.0]]).k_angles[0])


def test_given_centres_replace_the_centroids_and_degenerate_faces_are_left_out():
    """Centres on the wrong side of the face give 180; a face of zero area, or of a cell without
    a finite centre (a zero-volume cell of a deck), is not measured."""
    nb = [[0, 1], [1, 2], [2, -1], [0, 2]]
    normals = [[1.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 0.0]]
    centres = [[0.0, 0.0], [1.0, 1.0], [0.0, 2.0]]
    got = face_angles(nb, normals, centres)
    assert got.faces.tolist() == [0, 1]
    np.testing.assert_allclose(got.angles, [45.0, 135.0], rtol=0, atol=1e-12)
    assert face_angles(nb, normals, [[1.0, 0.0], [0.0, 0.0], [0.0, 3.0]]).angles[0] == 180.0
    assert face_angles(nb, normals, [[0.0, 0.0], [1.0, 1.0], [np.nan, np.inf]]).faces.tolist() == [0]
    assert orientation_figures([]) == {"median": 0.0, "p95": 0.0, "max": 0.0}
    assert vector_angles([[1e-300, 0.0, 0.0]], [[1.0, 1e-300, 0.0]])[0] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize(
    ("args", "error", "message"),
    [
        (([[0, 1]], [[1.0, 0.0]], [[0.0, 0.0]]), GridError, "neighbors name cell 1, but there are 1 centres"),
        (([[0, 1]], [[1.0, 0.0, 0.0]], [[0.0, 0.0], [1.0, 0.0]]), GridError, "normals (nf, d)"),
        (([[0, 1]], [[1.0, 0.0]], [[0.0, 0.0], [1.0, 0.0]], [[1.0, 1.0], [1.0, -2.0]]), InputError, "cell 1"),
        (
            ([[0, 1]], [[1.0, 0.0]], [[0.0, 0.0], [1.0, 0.0]], [[1.0, 1.0, 1.0]] * 2),
            GridError,
            "expected perm",
        ),
    ],
)
def test_bad_input_is_one_clear_error(args, error, message):
    with pytest.raises(error, match=message.replace("(", r"\(").replace(")", r"\)")):
        face_angles(*args)
