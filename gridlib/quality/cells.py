"""Quality measures of the cells of any grid, from its faces (docs/quality.md).

* ``orientation_error``: per cell, the largest orientation angle (degrees) of its interior
  faces (:mod:`gridlib.orientation`: the angle between a face's normal and the line joining
  its two cells' centres); ``k_orientation_error`` the same with the angle between K n and
  that line (each side's K). NaN for a cell with no measured face.
* ``aspect_ratio``: the largest over the smallest distance from the cell's centroid to the
  planes of its faces (a face's plane: through its centroid, normal to its area vector);
  faces of zero area left out. 1 for a cube or a regular tetrahedron, L / l for an L x l x l
  box, (dx cos t) / dz ... for a cell sheared by t (see the tests).
* ``face_nonplanarity``: per face, the largest distance of its nodes from its plane divided by
  the square root of its area (a dimensionless fraction of the face's size: 0 for a planar
  face; for a quadrilateral, half the distance between the lines of its two diagonals along
  the normal, over sqrt(area)); per cell, the largest over its faces. NaN for 2-D grids,
  whose faces are segments.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..connectivity import half_face_cells, ragged_arange
from ..geometry import Geometry
from ..grid import FloatArray, Grid
from ..orientation import grid_face_angles

_BLOCK = 1 << 18  # face nodes per block


def cell_max(num_cells: int, cells: np.ndarray, values: np.ndarray) -> FloatArray:
    """Per cell, the largest of ``values`` at ``cells`` (NaN values ignored; NaN where none)."""
    out = np.full(num_cells, np.nan)
    np.fmax.at(out, cells, values)
    return out


def orientation_errors(
    grid: Grid, geometry: Geometry, centres: ArrayLike | None = None, perm: ArrayLike | None = None
) -> tuple[FloatArray, FloatArray | None]:
    """(orientation_error, k_orientation_error or None without ``perm``) per cell."""
    fa = grid_face_angles(grid, geometry, centres, perm)
    nb = grid.faces.neighbors[fa.faces]
    cells = nb.ravel()
    plain = cell_max(grid.num_cells, cells, np.repeat(fa.angles, 2))
    k = None if fa.k_angles is None else cell_max(grid.num_cells, cells, np.repeat(fa.k_angles, 2))
    return plain, k


def aspect_ratio(grid: Grid, geometry: Geometry) -> FloatArray:
    """Largest over smallest centroid-to-face-plane distance per cell (module docstring)."""
    hc = half_face_cells(grid)
    f = grid.cells.faces
    n = geometry.face_normals[f]
    size = np.sqrt((n * n).sum(axis=1))
    d = geometry.face_centroids[f] - geometry.cell_centroids[hc]
    with np.errstate(invalid="ignore", divide="ignore"):
        dist = np.abs((n * d).sum(axis=1)) / size
    dist[~(size > 0)] = np.nan
    hi = cell_max(grid.num_cells, hc, dist)
    lo = np.full(grid.num_cells, np.nan)
    np.fmin.at(lo, hc, dist)
    with np.errstate(invalid="ignore", divide="ignore"):
        return hi / lo


def face_nonplanarity(grid: Grid, geometry: Geometry) -> FloatArray:
    """Per face: the largest node distance from the face's plane over sqrt(area)."""
    nf = grid.num_faces
    if grid.griddim != 3:
        return np.full(nf, np.nan)
    out = np.zeros(nf)
    pos = grid.faces.node_pos
    coords = grid.nodes.coords
    area = geometry.face_areas
    normal = geometry.face_normals
    size = np.sqrt((normal * normal).sum(axis=1))
    step = max(1, _BLOCK // max(1, int(grid.faces.num_nodes.max(initial=1))))
    for f0 in range(0, nf, step):
        f1 = min(f0 + step, nf)
        count = np.diff(pos[f0 : f1 + 1])
        face = np.repeat(np.arange(f0, f1), count)
        x = coords[grid.faces.nodes[ragged_arange(pos[f0:f1], count)]] - geometry.face_centroids[face]
        dist = np.abs((x * normal[face]).sum(axis=1))
        out[f0:f1] = np.maximum.reduceat(dist, pos[f0:f1] - pos[f0]) if dist.size else 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        out = out / (size * np.sqrt(area))
    out[~(area > 0)] = 0.0  # a face of no area lies in any plane through its nodes
    return out


def cell_face_nonplanarity(grid: Grid, geometry: Geometry) -> FloatArray:
    """Per cell, the largest :func:`face_nonplanarity` of its faces."""
    per_face = face_nonplanarity(grid, geometry)
    if grid.griddim != 3:
        return np.full(grid.num_cells, np.nan)
    return cell_max(grid.num_cells, half_face_cells(grid), per_face[grid.cells.faces])
