"""Small grids the picture tests draw: a dipping box with two vertical faults."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

import gridlib
from gridlib.geometry import compute_geometry

DIP = 0.05  # depth increases by 5 m per 100 m east


def faulted_box(dims=(6, 4, 3), lengths=(600.0, 400.0, 30.0)) -> gridlib.Grid:
    """A box dipping east (z += DIP x) with fault 1 on the faces at x = 300 and fault 2 on
    those at y = 200 (both vertical)."""
    grid = gridlib.cart_grid(dims, lengths)
    xyz = grid.nodes.coords.copy()
    xyz[:, 2] += DIP * xyz[:, 0]
    grid = replace(grid, nodes=replace(grid.nodes, coords=xyz))
    geo = compute_geometry(grid)
    c = geo.face_centroids
    interior = (grid.faces.neighbors >= 0).all(axis=1)
    tag = np.zeros(grid.num_faces, dtype=np.int32)
    tag[interior & np.isclose(c[:, 0], 300.0) & np.isclose(geo.face_normals[:, 1], 0.0)] = 1
    tag[interior & np.isclose(c[:, 1], 200.0) & np.isclose(geo.face_normals[:, 0], 0.0)] = 2
    return replace(grid, faces=replace(grid.faces, tag=tag))
