"""The steps that work a block at a time to bound the memory of a 1e7-cell stage give the same
bits as over the whole grid at once: the closure test of check_grid, the orientation angles of
the export's summary, and the geometry without face centroids that check_grid computes."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import gridlib as gl
from gridlib import checks, orientation


@pytest.fixture(scope="module")
def twisted():
    grid = gl.twister(gl.cart_grid([7, 5, 4], [700.0, 500.0, 40.0]))
    return grid, gl.compute_geometry(grid)


def _closure_whole(grid, geometry):
    """The closure defect over the surface area of every cell, over all half-faces at once."""
    hc = np.repeat(np.arange(grid.num_cells), np.diff(grid.cells.face_pos))
    cf = grid.cells.faces
    s = np.where(grid.faces.neighbors[cf, 0] == hc, 1.0, -1.0)
    net = np.stack([np.bincount(hc, s * geometry.face_normals[cf, i], grid.num_cells) for i in range(3)])
    surface = np.bincount(hc, geometry.face_areas[cf], grid.num_cells)
    return np.sqrt((net * net).sum(axis=0)) / surface


def test_closure_block_by_block_is_that_of_the_whole_grid(twisted, monkeypatch):
    grid, geo = twisted
    rng = np.random.default_rng(3)
    normals = np.array(geo.face_normals)
    tilted = rng.choice(grid.num_faces, 9, replace=False)
    normals[tilted] += 1e-6 * geo.face_areas[tilted, None] * rng.normal(size=(9, 3))
    geo = dataclasses.replace(geo, face_normals=normals)
    monkeypatch.setattr(checks, "_CELLS", 11)  # 140 cells: 13 blocks, the last one short
    cells = checks.degenerate_cells(grid, geo, 1e-10)
    expected = _closure_whole(grid, geo)
    assert cells.not_closed.tolist() == np.flatnonzero(expected > 1e-10).tolist()
    assert 9 <= cells.not_closed.size <= 18  # each tilted face opens its cell(s)
    assert cells.closure.tobytes() == expected[cells.not_closed].tobytes()


def test_face_angles_block_by_block_are_those_of_one_block(twisted, monkeypatch):
    grid, geo = twisted
    centres = np.array(geo.cell_centroids)
    centres[[4, 60]] = np.nan  # a cell without a centre: its faces are left out
    perm = np.random.default_rng(5).uniform(1.0, 500.0, size=(grid.num_cells, 3))
    perm[17] = 0.0  # no permeability: it does not count
    whole = orientation.face_angles(grid.faces.neighbors, geo.face_normals, centres, perm)
    monkeypatch.setattr(orientation, "_FACES", 37)
    blocks = orientation.face_angles(grid.faces.neighbors, geo.face_normals, centres, perm)
    assert blocks.faces.tolist() == whole.faces.tolist()
    assert blocks.angles.tobytes() == whole.angles.tobytes()
    assert blocks.k_angles.tobytes() == whole.k_angles.tobytes()
    interior = (grid.faces.neighbors >= 0).all(axis=1) & ~np.isin(grid.faces.neighbors, [4, 60]).any(axis=1)
    assert whole.faces.tolist() == np.flatnonzero(interior).tolist()
    assert 0.0 < np.nanmax(whole.angles) < 90.0  # twisted: off the centre line, never across it


def test_geometry_without_face_centroids_has_the_same_bits(twisted):
    grid, full = twisted
    lean = gl.compute_geometry(grid, face_centroids=False)
    assert lean.face_centroids.shape == (0, 3)
    for name in ("cell_volumes", "cell_centroids", "face_areas", "face_normals"):
        assert getattr(lean, name).tobytes() == getattr(full, name).tobytes(), name
