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

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..connectivity import segment_reduce
from ..errors import GridError
from ..geometry import Geometry
from ..grid import FloatArray, Grid, IntArray
from ..orientation import checked_perm, vector_angles
from ..threads import in_order
from .hexahedra import dot_components

_BLOCK = 1 << 18  # face nodes per block
_CELLS = 1 << 13  # cells per block of the face measures: their half-faces' arrays stay in cache
MAX_THREADS = 2  # blocks of cells measured at once


@dataclass(frozen=True)
class FaceArrays:
    """What the face measures of a block of cells read: the grid's cell-face and face-cell
    maps and the face and cell vectors components first ((d, n): one 1-D gather per
    component), with a last column for "no cell" where cells are indexed by neighbours."""

    face_pos: IntArray  # grid.cells.face_pos
    cell_faces: IntArray  # grid.cells.faces
    neighbors: IntArray  # grid.faces.neighbors
    normals: FloatArray  # (d, nf) area vectors
    centroids: FloatArray  # (d, nf) face centroids
    centres: FloatArray  # (d, nc + 1) the cells' centres (orientation), NaN in the last column
    cell_centroids: FloatArray  # (d, nc) (aspect ratio)
    perm: FloatArray | None  # (d, nc + 1) diagonal K, NaN in the last column
    nonplanarity: FloatArray  # (nf,) face_nonplanarity

    @classmethod
    def of(
        cls, grid: Grid, geometry: Geometry, centres: ArrayLike | None = None, perm: ArrayLike | None = None
    ) -> FaceArrays:
        x = geometry.cell_centroids if centres is None else np.asarray(centres, dtype=np.float64)
        if x.shape != geometry.cell_centroids.shape:
            raise GridError(f"cell_quality: expected centres {geometry.cell_centroids.shape}, got {x.shape}")
        k = None if perm is None else _outside_column(checked_perm(perm, x.shape))
        return cls(
            grid.cells.face_pos,
            grid.cells.faces,
            grid.faces.neighbors,
            np.ascontiguousarray(geometry.face_normals.T),
            np.ascontiguousarray(geometry.face_centroids.T),
            _outside_column(x),
            np.ascontiguousarray(geometry.cell_centroids.T),
            k,
            face_nonplanarity(grid, geometry),
        )


def _outside_column(rows: FloatArray) -> FloatArray:
    """(d, n + 1): the rows' components first, NaN for index -1 (no cell)."""
    out = np.empty((rows.shape[1], rows.shape[0] + 1))
    out[:, :-1] = rows.T
    out[:, -1] = np.nan
    return out


def face_measures(
    grid: Grid, geometry: Geometry, centres: ArrayLike | None = None, perm: ArrayLike | None = None
) -> dict[str, FloatArray]:
    """``orientation_error``, ``k_orientation_error`` (with ``perm``), ``aspect_ratio`` and
    ``face_nonplanarity`` per cell (module docstring), a block of cells at a time on up to two
    threads (each block alone: the same bits for any number of threads). The angles are those
    of :func:`gridlib.orientation.face_angles`: per cell, the face of smallest cosine is chosen
    first (the largest face number on a tie) and its angle alone computed."""
    arrays = FaceArrays.of(grid, geometry, centres, perm)
    nc = grid.num_cells
    names = ["orientation_error", "aspect_ratio", "face_nonplanarity"]
    names += [] if perm is None else ["k_orientation_error"]
    out = {name: np.empty(nc) for name in names}
    blocks = ((slice(c, min(c + _CELLS, nc)),) for c in range(0, nc, _CELLS))
    for part, values in in_order(lambda part: (part, block_face_measures(arrays, part)), blocks, MAX_THREADS):
        for name, v in values.items():
            out[name][part] = v
    return out


def block_face_measures(fa: FaceArrays, part: slice) -> dict[str, FloatArray]:
    """:func:`face_measures` of the cells ``part``, from their half-faces."""
    h0, h1 = fa.face_pos[part.start], fa.face_pos[part.stop]
    pos = fa.face_pos[part.start : part.stop + 1] - h0  # the block's cells' half-faces
    f = fa.cell_faces[h0:h1]
    a, b = fa.neighbors[f, 0], fa.neighbors[f, 1]  # -1: the last column, NaN
    n = fa.normals[:, f]
    d = fa.centres[:, b] - fa.centres[:, a]
    measured = (n != 0).any(axis=0) & (d != 0).any(axis=0) & np.isfinite(d).all(axis=0)
    d_len = np.sqrt(dot_components(d, d))
    n_len = np.sqrt(dot_components(n, n))
    with np.errstate(invalid="ignore", divide="ignore"):
        cos = dot_components(n, d) / (n_len * d_len)
    out = {"orientation_error": _largest_angle(cos, measured, f, pos, n, d)}
    if fa.perm is not None:
        side_cos = []
        for cell in (a, b):  # K n on each side of the face
            kn = fa.perm[:, cell] * n
            with np.errstate(invalid="ignore", divide="ignore"):
                side_cos.append(dot_components(kn, d) / (np.sqrt(dot_components(kn, kn)) * d_len))
        c0, c1 = (np.where(np.isnan(c), np.inf, c) for c in side_cos)
        second = c1 <= c0  # the side of the smaller cosine, the second on a tie
        kn = fa.perm[:, np.where(second, b, a)] * n
        out["k_orientation_error"] = _largest_angle(np.minimum(c0, c1), measured, f, pos, kn, d)
    hc = np.repeat(np.arange(part.start, part.stop), np.diff(pos))
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = n / n_len
    unit[:, ~(n_len > 0)] = np.nan  # faces of no area: left out
    dist = unit[0] * (fa.centroids[0][f] - fa.cell_centroids[0][hc])
    for i in range(1, n.shape[0]):
        dist += unit[i] * (fa.centroids[i][f] - fa.cell_centroids[i][hc])
    np.abs(dist, out=dist)
    with np.errstate(invalid="ignore", divide="ignore"):
        out["aspect_ratio"] = segment_reduce(np.fmax, dist, pos) / segment_reduce(np.fmin, dist, pos)
    out["face_nonplanarity"] = segment_reduce(np.fmax, fa.nonplanarity[f], pos)
    return out


def _largest_angle(
    cos: FloatArray, measured: np.ndarray, f: IntArray, pos: IntArray, u: FloatArray, w: FloatArray
) -> FloatArray:
    """Per cell (half-faces at ``pos``), the angle between ``u`` and ``w`` (d, k) at its
    measured half-face of smallest ``cos`` (NaN ones do not count; the largest face number
    ``f`` on a tie); NaN for a cell with none. Up to the rounding of the cosines, the largest
    angle: one arctangent per cell instead of one per face."""
    c = np.where(measured & ~np.isnan(cos), cos, np.inf)
    low = segment_reduce(np.minimum, c, pos, np.inf)
    hit = (c == np.repeat(low, np.diff(pos))) & (c < np.inf)
    key = np.where(hit, f, -1)
    best = segment_reduce(np.maximum, key, pos, -1)
    chosen = np.flatnonzero(hit & (key == np.repeat(best, np.diff(pos))))  # one per cell with one
    out = np.full(pos.size - 1, np.nan)
    out[best >= 0] = vector_angles(u[:, chosen].T, w[:, chosen].T)
    return out


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

    def block(f0: int, f1: int) -> tuple[int, int, FloatArray]:
        face = np.repeat(np.arange(f0, f1), np.diff(pos[f0 : f1 + 1]))
        nodes = grid.faces.nodes[pos[f0] : pos[f1]]  # the block's faces' nodes are contiguous
        dist = (xt[0][nodes] - ct[0][face]) * nt[0][face]
        for i in (1, 2):
            dist += (xt[i][nodes] - ct[i][face]) * nt[i][face]
        if not dist.size:
            return f0, f1, np.zeros(f1 - f0)
        return f0, f1, np.maximum.reduceat(np.abs(dist), pos[f0:f1] - pos[f0])

    blocks = ((f0, min(f0 + step, nf)) for f0 in range(0, nf, step))
    for f0, f1, values in in_order(block, blocks, MAX_THREADS):
        out[f0:f1] = values
    area = geometry.face_areas
    with np.errstate(invalid="ignore", divide="ignore"):
        out /= np.sqrt(dot_components(nt, nt)) * np.sqrt(area)
    out[~(area > 0)] = 0.0  # a face of no area lies in any plane through its nodes
    return out
