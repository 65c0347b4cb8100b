"""The cells a well path crosses, on any 3-D grid (corner-point, PEBI, layered, tetrahedral).

A cell is the region bounded by its faces, each face triangulated exactly as
:mod:`gridlib.geometry` does: a fan of triangles (p_k, p_k+1, h) about the face's hinge h,
the mean of its nodes. Two neighbours share the same triangles, so the cells tile their
union without gaps or overlaps, also with non-planar faces and with faces subdivided at
fault walls, and each cell's volume is the one ``compute_geometry`` reports.

For every straight segment of the path (in MD order):

1. the candidate cells are those whose bounding box it crosses (:mod:`.spatial_index`);
2. the segment's parameters t in [0, 1] where it crosses a triangle of a candidate cell's
   faces come from the Möller-Trumbore test, vectorised over all (segment, triangle) pairs;
   the test is inclusive (barycentric coordinates down to -1e-9) so that a path along a face
   still meets the edges of the faces across it; a triangle parallel to the segment gives none;
3. the segment is split at these parameters and at its ends; parameters closer than 1e-9 of
   the grid's extent are one;
4. each piece's midpoint is located by the generalized winding number of every candidate
   cell whose box holds it: the sum over the cell's oriented triangles of their solid angles
   (Van Oosterom and Strackee's formula) over 4 pi, 1 inside, 0 outside. On a face, an edge
   or a node the cells that meet there share the winding (1/2, 1/4, ...; a triangle the
   point lies on counts 0): the piece goes to the cell of largest winding, ties within 1e-9
   to the lowest cell index, so a path along a face, an edge, a node or a fault wall is in
   exactly one cell and no length is lost or counted twice. A piece of largest winding
   below 1e-6 is outside every cell (outside the grid, or in a hole of inactive cells) and
   is dropped. Cells are closed: a path along the grid's outer surface counts (or not, as
   rounding puts the point on one side of it).
5. consecutive pieces of one segment in the same cell are merged (a spurious split from the
   inclusive test is undone); pieces are kept split at the path's vertices, and consecutive
   pieces in the same cell, with no gap between them, share a ``run``.

Every step is vectorised over all segments, pieces, candidate cells and triangles. Lengths
in the grid's unit; x east, y north, z depth (positive down); MD linear along each segment.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import reproducible as rp
from ..arrays import frozen_array
from ..connectivity import offsets, ragged_arange, repeat_ids
from ..errors import GridError, InputError
from ..geometry import Geometry
from ..grid import FloatArray, Grid, IntArray
from .path import WellPath
from .spatial_index import CellIndex, cell_index, point_cells, segment_cells

__all__ = ["CellIndex", "PathCells", "cell_index", "path_cells"]

BARYCENTRIC_SLACK = 1e-9  # Möller-Trumbore accepts barycentric coordinates down to -this
SAME_POINT = 1e-9  # crossings closer than this fraction of the grid's extent are one
TIE = 1e-9  # windings closer than this are a tie (to the lowest cell index)
INSIDE = 1e-6  # a piece whose largest winding is below this is outside every cell


@dataclass(frozen=True, eq=False)
class PathCells:
    """The pieces of a path inside cells, in MD order: piece i is the straight sub-segment
    ``entry[i]`` -> ``exit[i]`` (xyz), MD ``entry_md[i]`` to ``exit_md[i]``, inside cell
    ``cell[i]`` (a row of the grid). Pieces are split at cell faces and at the path's
    vertices; consecutive pieces in the same cell with no gap between them share a ``run``
    id (0, 1, ... in MD order): a cell the path enters twice has two runs."""

    cell: IntArray
    entry_md: FloatArray
    exit_md: FloatArray
    entry: FloatArray
    exit: FloatArray
    run: IntArray

    def __post_init__(self) -> None:
        for name, dtype, ndim in (
            ("cell", np.int64, 1),
            ("entry_md", np.float64, 1),
            ("exit_md", np.float64, 1),
            ("entry", np.float64, 2),
            ("exit", np.float64, 2),
            ("run", np.int64, 1),
        ):
            object.__setattr__(
                self, name, frozen_array(getattr(self, name), dtype, f"PathCells.{name}", ndim)
            )

    @property
    def num(self) -> int:
        return self.cell.size

    @property
    def length(self) -> FloatArray:
        """(m,) straight length of each piece, |exit - entry|."""
        d = self.exit - self.entry
        return np.sqrt(np.einsum("ij,ij->i", d, d))


def path_cells(
    grid: Grid, geometry: Geometry, path: WellPath, *, index: CellIndex | None = None
) -> PathCells:
    """The pieces of ``path`` inside the cells of the 3-D ``grid`` (module docstring).

    ``index`` (:func:`cell_index` of the same grid) is built when not given; build it once
    to locate many wells. ``geometry`` is the grid's (only its size is used: cells are
    located from the nodes).

    >>> from gridlib import cart_grid, compute_geometry
    >>> g = cart_grid([2, 1, 2], [20.0, 10.0, 20.0])
    >>> pc = path_cells(g, compute_geometry(g), WellPath.from_points([(5, 5, -5), (15, 5, 15), (25, 5, 15)]))
    >>> pc.cell.tolist(), pc.run.tolist()  # into cell 3 across the path's vertex: one run
    ([0, 1, 3, 3], [0, 1, 2, 2])
    >>> pc.entry_md.round(4).tolist(), pc.exit_md.round(4).tolist()
    ([5.5902, 11.1803, 16.7705, 22.3607], [11.1803, 16.7705, 22.3607, 27.3607])
    """
    if grid.griddim != 3 or grid.dim != 3:
        raise InputError(f"well {path.name!r}: locating a well path needs a 3-D grid")
    if index is None:
        index = cell_index(grid, geometry)
    elif index.num_cells != grid.num_cells:
        raise GridError("path_cells: the index is not this grid's (a different number of cells)")
    a, b = path.segments
    seg, cand = segment_cells(index, a, b)
    t_seg, t = _crossings(grid, seg, cand, a, b)
    same = SAME_POINT * float(np.max(index.size * index.shape))  # of the grid's extent
    piece_seg, t0, t1 = _split(t_seg, t, a.shape[0], same / np.sqrt(np.einsum("ij,ij->i", b - a, b - a)))
    tm = 0.5 * (t0 + t1)
    mid = (1.0 - tm)[:, None] * a[piece_seg] + tm[:, None] * b[piece_seg]
    cell = locate(grid, index, mid)
    keep = cell >= 0
    piece_seg, t0, t1, cell = piece_seg[keep], t0[keep], t1[keep], cell[keep]
    piece_seg, t0, t1, cell, run = _merge(piece_seg, t0, t1, cell)
    md = path.md

    def at(t: FloatArray, values: FloatArray) -> FloatArray:
        lo, hi = values[:-1][piece_seg], values[1:][piece_seg]
        w = t if values.ndim == 1 else t[:, None]
        return (1.0 - w) * lo + w * hi

    return PathCells(cell, at(t0, md), at(t1, md), at(t0, path.xyz), at(t1, path.xyz), run)


def face_hinges(grid: Grid, faces: IntArray) -> FloatArray:
    """(k, 3) hinge of each face: the mean of its nodes, summed in node order and times 1/m,
    the same bits as :mod:`gridlib.geometry`'s."""
    pos, nodes, xyz = grid.faces.node_pos, grid.faces.nodes, grid.nodes.coords
    m = pos[faces + 1] - pos[faces]
    h = xyz[nodes[pos[faces]]].copy()
    for k in range(1, int(m.max(initial=1))):
        more = np.flatnonzero(m > k)
        h[more] += xyz[nodes[pos[faces[more]] + k]]
    h *= (1.0 / m)[:, None]
    return h


def _triangles(grid: Grid, faces: IntArray) -> tuple[IntArray, IntArray, IntArray]:
    """The hinge triangles of ``faces`` (the pairs of some owner with a face), in face order:
    (the entry of ``faces`` each belongs to, its nodes p_k and p_k+1)."""
    pos, nodes = grid.faces.node_pos, grid.faces.nodes
    m = pos[faces + 1] - pos[faces]
    owner = repeat_ids(offsets(m))
    k = ragged_arange(np.zeros_like(m), m)
    start = pos[faces][owner]
    nxt = np.where(k + 1 == m[owner], 0, k + 1)
    return owner, nodes[start + k], nodes[start + nxt]


def _owner_faces(grid: Grid, owner: IntArray, cell: IntArray) -> tuple[IntArray, IntArray, FloatArray]:
    """The (owner, cell) pairs' half-faces as (owner, face, sign): sign +1 where the face's
    normal points out of the cell."""
    fpos = grid.cells.face_pos
    n = fpos[cell + 1] - fpos[cell]
    half = ragged_arange(fpos[cell], n)
    face = grid.cells.faces[half]
    cell_of = np.repeat(cell, n)
    sign = np.where(grid.faces.neighbors[face, 0] == cell_of, 1.0, -1.0)
    return np.repeat(owner, n), face, sign


def _crossings(
    grid: Grid, seg: IntArray, cand: IntArray, a: FloatArray, b: FloatArray
) -> tuple[IntArray, FloatArray]:
    """(segment, t): the parameters t in [0, 1] along segment a -> b where it crosses a
    triangle of a face of one of its candidate cells (Möller-Trumbore, module docstring)."""
    owner, face, _ = _owner_faces(grid, seg, cand)
    key = np.unique(owner * grid.num_faces + face)  # each (segment, face) once
    seg_f, face = key // grid.num_faces, key % grid.num_faces
    hinge = face_hinges(grid, face)
    tri, n0, n1 = _triangles(grid, face)
    s = seg_f[tri]
    o, d = a[s], b[s] - a[s]
    xyz = grid.nodes.coords
    v0 = xyz[n0] - o
    e1 = xyz[n1] - o - v0
    e2 = hinge[tri] - o - v0
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    ok = det != 0.0
    det = np.where(ok, det, 1.0)
    u = -np.einsum("ij,ij->i", v0, p) / det
    q = np.cross(-v0, e1)
    v = np.einsum("ij,ij->i", d, q) / det
    t = np.einsum("ij,ij->i", e2, q) / det
    eps = BARYCENTRIC_SLACK
    hit = ok & (u >= -eps) & (v >= -eps) & (u + v <= 1.0 + eps) & (t >= -eps) & (t <= 1.0 + eps)
    return s[hit], np.clip(t[hit], 0.0, 1.0)


def _split(
    t_seg: IntArray, t: FloatArray, n_seg: int, same_t: FloatArray
) -> tuple[IntArray, FloatArray, FloatArray]:
    """Pieces (segment, t0, t1) between the sorted parameters of every segment (its crossings,
    0 and 1), parameters closer than ``same_t`` (per segment) being one."""
    ends = np.arange(n_seg)
    s = np.concatenate([ends, ends, t_seg])
    t = np.concatenate([np.zeros(n_seg), np.ones(n_seg), t])
    order = np.lexsort((t, s))
    s, t = s[order], t[order]
    new = np.ones(s.size, dtype=bool)
    new[1:] = (s[1:] != s[:-1]) | (t[1:] - t[:-1] > same_t[s[1:]])
    s, t = s[new], t[new]
    last = np.ones(s.size, dtype=bool)
    last[:-1] = s[1:] != s[:-1]
    t[last] = 1.0  # the cluster holding the segment's end is its end
    first = ~last
    return s[first], t[first], t[np.flatnonzero(first) + 1]


def locate(grid: Grid, index: CellIndex, p: FloatArray) -> IntArray:
    """The cell holding each point p (k, 3), -1 if none: the largest generalized winding
    number, ties to the lowest cell (module docstring)."""
    point, cell = point_cells(index, p)
    w = winding_numbers(grid, p, point, cell)
    found = np.full(p.shape[0], -1, dtype=np.int64)
    if point.size == 0:
        return found
    start = np.flatnonzero(np.r_[True, point[1:] != point[:-1]])
    best = np.maximum.reduceat(w, start)
    best_of = np.repeat(best, np.diff(np.r_[start, point.size]))
    pick = np.where(w >= best_of - TIE, cell, np.iinfo(np.int64).max)
    chosen = np.minimum.reduceat(pick, start)
    inside = best > INSIDE
    found[point[start][inside]] = chosen[inside]
    return found


def winding_numbers(grid: Grid, p: FloatArray, point: IntArray, cell: IntArray) -> FloatArray:
    """The generalized winding number of each cell ``cell[i]`` at point ``p[point[i]]``: the
    solid angles of its outward hinge triangles over 4 pi (module docstring).

    The solid angle of a (point, face) is computed once and shared, with opposite signs, by
    the face's two cells, so the windings at a point of the cells around it add up to 1."""
    pair = np.arange(point.size)
    owner, face, sign = _owner_faces(grid, pair, cell)
    key, inverse = np.unique(point[owner] * grid.num_faces + face, return_inverse=True)
    pf_point, pf_face = key // grid.num_faces, key % grid.num_faces
    hinge = face_hinges(grid, pf_face)
    tri, n0, n1 = _triangles(grid, pf_face)
    x = p[pf_point[tri]]
    xyz = grid.nodes.coords
    omega = solid_angles(xyz[n0] - x, xyz[n1] - x, hinge[tri] - x)
    face_omega = np.bincount(tri, omega, key.size)
    total = np.bincount(owner, sign * face_omega[inverse], point.size)
    return total / (4.0 * np.pi)


def solid_angles(a: FloatArray, b: FloatArray, c: FloatArray) -> FloatArray:
    """Signed solid angle (sr) of triangles (a, b, c) (vectors from the point, (k, 3) each):
    2 atan2(a . (b x c), |a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|) (Van Oosterom and
    Strackee 1983), positive when the point sees a, b, c counter-clockwise about the normal
    (b - a) x (c - a) pointing away from it. A point on the triangle's plane gets 0."""
    det = np.einsum("ij,ij->i", a, np.cross(b, c))
    la, lb, lc = (np.sqrt(np.einsum("ij,ij->i", v, v)) for v in (a, b, c))
    den = la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", a, c) * lb
    den += np.einsum("ij,ij->i", b, c) * la
    return np.where(det == 0.0, 0.0, 2.0 * rp.arctan2(det, den))


def _merge(
    seg: IntArray, t0: FloatArray, t1: FloatArray, cell: IntArray
) -> tuple[IntArray, FloatArray, FloatArray, IntArray, IntArray]:
    """Consecutive pieces of one segment in the same cell, touching, merged into one; the run
    of every piece (a new one where the cell changes or the path left the cells)."""
    joined = np.zeros(seg.size, dtype=bool)
    touch = np.zeros(seg.size, dtype=bool)
    if seg.size > 1:
        same_cell = cell[1:] == cell[:-1]
        on_seg = (seg[1:] == seg[:-1]) & (t0[1:] == t1[:-1])
        across = (seg[1:] == seg[:-1] + 1) & (t1[:-1] == 1.0) & (t0[1:] == 0.0)
        joined[1:] = same_cell & on_seg
        touch[1:] = same_cell & (on_seg | across)
    first = ~joined
    last = np.append(first[1:], True)[: seg.size]
    run = np.cumsum(~touch) - 1
    return seg[first], t0[first], t1[last], cell[first], run[first]
