"""Quality measures of the cells of any grid, from its faces (docs/quality.md).

* ``orientation_error``: per cell, the largest orientation angle (degrees) of its interior
  faces (:mod:`gridlib.orientation`: the angle between a face's normal and the line joining
  its two cells' centres); ``k_orientation_error`` the same with the angle between K n and
  that line (each side's K). NaN for a cell with no measured face.
* ``aspect_ratio``: the largest over the smallest distance from the cell's centroid to the
  planes of its faces (a face's plane: through its centroid, normal to its area vector);
  faces of zero area left out. 1 for a cube or a regular tetrahedron, L / l for an L x l x l
  box, 1 / cos t for a unit cube sheared by t (x + z tan t: its i-faces lean by t).
* ``face_nonplanarity``: per face, the largest distance of its nodes from its plane divided by
  the square root of its area (a dimensionless fraction of the face's size: 0 for a planar
  face; for a quadrilateral, half the distance between the lines of its two diagonals along
  the normal, over sqrt(area)); per cell, the largest over its faces. NaN for 2-D grids,
  whose faces are segments. The plane, centroid and area are :mod:`gridlib.geometry`'s.

Units: lengths in the grid's unit, angles in degrees; the ratios are dimensionless.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..connectivity import half_face_cells
from ..geometry import Geometry
from ..grid import FloatArray, Grid
from ..orientation import checked_perm, face_vectors, smallest_cosine_rows, vector_angles
from .hexahedra import dot_components

_BLOCK = 1 << 18  # face nodes per block


def cell_max(num_cells: int, cells: np.ndarray, values: np.ndarray) -> FloatArray:
    """Per cell, the largest of ``values`` at ``cells`` (NaN values ignored; NaN where none)."""
    out = np.full(num_cells, np.nan)
    np.fmax.at(out, cells, values)
    return out


def orientation_errors(
    grid: Grid, geometry: Geometry, centres: ArrayLike | None = None, perm: ArrayLike | None = None
) -> tuple[FloatArray, FloatArray | None]:
    """(orientation_error, k_orientation_error or None without ``perm``) per cell: the largest
    of :func:`gridlib.orientation.face_angles`'s angles over each cell's measured faces (the
    face of smallest cosine chosen first, one angle computed per cell)."""
    x = geometry.cell_centroids if centres is None else np.asarray(centres, dtype=np.float64)
    nc = grid.num_cells
    faces, n, d = face_vectors(grid.faces.neighbors, geometry.face_normals, x)
    pair = grid.faces.neighbors[faces]  # each face counts for both its cells
    nt, dt = np.ascontiguousarray(n.T), np.ascontiguousarray(d.T)  # components first: fast
    d_len = np.sqrt(dot_components(dt, dt))
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = dot_components(nt, dt) / (np.sqrt(dot_components(nt, nt)) * d_len)
    row = smallest_cosine_rows(cos, pair, nc)
    plain = np.full(nc, np.nan)
    some = row >= 0
    plain[some] = vector_angles(n[row[some]], d[row[some]])
    if perm is None:
        return plain, None
    k = checked_perm(perm, x.shape)
    cos = []
    for side in (0, 1):  # K n of each side of the face, for both its cells
        kn = np.ascontiguousarray(k[pair[:, side]].T) * nt
        with np.errstate(invalid="ignore", divide="ignore"):
            cos.append(dot_components(kn, dt) / (np.sqrt(dot_components(kn, kn)) * d_len))
    row = smallest_cosine_rows(np.concatenate(cos), np.concatenate([pair, pair]), nc)
    k_err = np.full(nc, np.nan)
    some = row >= 0
    face, side = row[some] % faces.size, row[some] // faces.size
    k_err[some] = vector_angles(k[pair[face, side]] * n[face], d[face])
    return plain, k_err


def aspect_ratio(grid: Grid, geometry: Geometry) -> FloatArray:
    """Largest over smallest centroid-to-face-plane distance per cell (module docstring)."""
    hc = half_face_cells(grid)
    f = grid.cells.faces
    nt = np.ascontiguousarray(geometry.face_normals.T)  # components first: 1-D gathers
    ft = np.ascontiguousarray(geometry.face_centroids.T)
    xt = np.ascontiguousarray(geometry.cell_centroids.T)
    size = np.sqrt(dot_components(nt, nt))
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = nt / size
    unit[:, ~(size > 0)] = np.nan  # faces of no area: left out
    dist = unit[0][f] * (ft[0][f] - xt[0][hc])
    for i in range(1, nt.shape[0]):
        dist += unit[i][f] * (ft[i][f] - xt[i][hc])
    np.abs(dist, out=dist)
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
    pos = grid.faces.node_pos
    xt = np.ascontiguousarray(grid.nodes.coords.T)  # components first: 1-D gathers
    ct = np.ascontiguousarray(geometry.face_centroids.T)
    nt = np.ascontiguousarray(geometry.face_normals.T)
    out = np.zeros(nf)
    step = max(1, _BLOCK // max(1, int(grid.faces.num_nodes.max(initial=1))))
    for f0 in range(0, nf, step):
        f1 = min(f0 + step, nf)
        face = np.repeat(np.arange(f0, f1), np.diff(pos[f0 : f1 + 1]))
        nodes = grid.faces.nodes[pos[f0] : pos[f1]]  # the block's faces' nodes are contiguous
        dist = (xt[0][nodes] - ct[0][face]) * nt[0][face]
        for i in (1, 2):
            dist += (xt[i][nodes] - ct[i][face]) * nt[i][face]
        if dist.size:
            out[f0:f1] = np.maximum.reduceat(np.abs(dist), pos[f0:f1] - pos[f0])
    area = geometry.face_areas
    with np.errstate(invalid="ignore", divide="ignore"):
        out /= np.sqrt(dot_components(nt, nt)) * np.sqrt(area)
    out[~(area > 0)] = 0.0  # a face of no area lies in any plane through its nodes
    return out


def cell_face_nonplanarity(grid: Grid, geometry: Geometry) -> FloatArray:
    """Per cell, the largest :func:`face_nonplanarity` of its faces."""
    per_face = face_nonplanarity(grid, geometry)
    if grid.griddim != 3:
        return np.full(grid.num_cells, np.nan)
    return cell_max(grid.num_cells, half_face_cells(grid), per_face[grid.cells.faces])
