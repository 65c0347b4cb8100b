"""Unique points along pillars: node ids that increase with depth on every pillar.

Every cell corner lies on a pillar at some depth z. Sorting all corners by
(pillar, z) and numbering the distinct values gives node ids such that, on one
pillar, a deeper point has a larger id. All later topology tests then compare
integers (ranks), never floats (OPM's key idea), and are exact.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..grid import FloatArray, IntArray


@dataclass(frozen=True, eq=False)
class PillarPoints:
    """The distinct points on every pillar.

    ``offset[p]:offset[p+1]`` are the node ids on pillar p, sorted by depth;
    ``rank = node - offset[pillar]`` is a node's position on its pillar.
    """

    node_of_corner: IntArray  # (m,) node id of every input corner
    offset: IntArray  # (n_pillars + 1,)
    pillar: IntArray  # (n_nodes,) pillar of every node
    z: FloatArray  # (n_nodes,) depth of every node

    @property
    def num_nodes(self) -> int:
        return self.z.size

    def rank(self, nodes: IntArray) -> IntArray:
        return nodes - self.offset[self.pillar[nodes]]


def unique_points(pillar: IntArray, z: FloatArray, n_pillars: int, tol: float = 0.0) -> PillarPoints:
    """Number the distinct depths on every pillar (exactly, or after quantising by ``tol``).

    With ``tol > 0`` depths are first rounded to multiples of ``tol`` (MRST's
    semantics, vectorised): two depths closer than ``tol`` that straddle a
    rounding boundary stay distinct. The default, 0, merges only equal depths.
    """
    zq = np.round(z / tol) * tol if tol > 0 else z
    order = np.lexsort((zq, pillar))
    ps, zs = pillar[order], zq[order]
    new = np.ones(order.size, dtype=bool)
    new[1:] = (ps[1:] != ps[:-1]) | (zs[1:] != zs[:-1])
    node_sorted = np.cumsum(new) - 1
    node_of_corner = np.empty(order.size, dtype=np.int64)
    node_of_corner[order] = node_sorted
    node_pillar = ps[new]
    offset = np.searchsorted(node_pillar, np.arange(n_pillars + 1)).astype(np.int64)
    return PillarPoints(node_of_corner, offset, node_pillar, zs[new])


def points_on_pillars(lines: FloatArray, pillar: IntArray, z: FloatArray) -> FloatArray:
    """Coordinates of points at depth ``z`` on straight pillars ``lines`` (n, 2, 3).

    A pillar whose top and bottom depths differ by less than 1e-6 (OPM's rule)
    has no usable direction and is treated as vertical through its top point.
    """
    top = lines[pillar, 0]
    bot = lines[pillar, 1]
    dz = bot[:, 2] - top[:, 2]
    vertical = np.abs(dz) < 1e-6
    t = np.where(vertical, 0.0, (z - top[:, 2]) / np.where(vertical, 1.0, dz))
    xy = top[:, :2] + t[:, None] * (bot[:, :2] - top[:, :2])
    return np.column_stack([xy, z])


def unique_points_rows(rows: FloatArray, tol: float = 0.0) -> tuple[IntArray, PillarPoints]:
    """Node ids of a (n_pillars, m) table of depths per pillar (NaN = no point), and the points.

    The structured twin of :func:`unique_points` for when every pillar's
    candidate depths fit in one row (corner-point decks): each row is sorted on
    its own (mostly presorted runs), which is much faster than one global sort.
    Returns ids of the same shape as ``rows`` (-1 where NaN).
    """
    if tol > 0:
        rows = np.round(rows / tol) * tol
    n_pillars, m = rows.shape
    order = np.argsort(rows, axis=1, kind="stable")  # NaN sorts last
    srt = np.take_along_axis(rows, order, axis=1)
    valid = ~np.isnan(srt)
    new = valid.copy()
    new[:, 1:] &= srt[:, 1:] != srt[:, :-1]
    ids_sorted = np.cumsum(new, axis=None).reshape(n_pillars, m) - 1
    ids_sorted[~valid] = -1
    ids = np.empty_like(ids_sorted)
    np.put_along_axis(ids, order, ids_sorted, axis=1)
    pillar, _ = np.nonzero(new)
    offset = np.searchsorted(pillar, np.arange(n_pillars + 1)).astype(np.int64)
    return ids, PillarPoints(np.zeros(0, np.int64), offset, pillar.astype(np.int64), srt[new])
