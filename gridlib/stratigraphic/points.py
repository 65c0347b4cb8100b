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


def points_on_pillars(
    lines: FloatArray, pillar: IntArray, z: FloatArray, out: FloatArray | None = None
) -> FloatArray:
    """Coordinates of points at depth ``z`` on straight pillars ``lines`` (n, 2, 3).

    A pillar whose top and bottom depths differ by less than 1e-6 (OPM's rule)
    has no usable direction and is treated as vertical through its top point.
    The (n, 3) result is written to ``out`` if given.
    """
    top = lines[:, 0]
    dz = lines[:, 1, 2] - top[:, 2]
    vertical = np.abs(dz) < 1e-6
    t = (z - top[pillar, 2]) / np.where(vertical, 1.0, dz)[pillar]
    t[vertical[pillar]] = 0.0
    xyz = np.empty((z.size, 3)) if out is None else out
    for d in (0, 1):
        xyz[:, d] = top[pillar, d] + t * (lines[:, 1, d] - top[:, d])[pillar]
    xyz[:, 2] = z
    return xyz


def unique_points_rows(
    rows: FloatArray, tol: float = 0.0, first_id: int = 0
) -> tuple[IntArray, IntArray, FloatArray]:
    """Node ids of a (n_rows, m) table of depths, one row per pillar (NaN = no point).

    The structured twin of :func:`unique_points` for when every pillar's
    candidate depths fit in one row (corner-point decks): each row is sorted on
    its own, which is much faster than one global sort when rows are made of a
    few presorted runs. Points are numbered from ``first_id``, row by row and by
    depth within a row, so a table can be numbered in blocks of rows. Returns
    the ids (the shape of ``rows``, -1 where NaN), the number of points of each
    row and their depths (row by row, increasing).
    """
    if tol > 0:
        rows = np.round(rows / tol) * tol
    n_rows, m = rows.shape
    order = np.argsort(rows, axis=1, kind="stable")  # NaN sorts last
    order += (np.arange(n_rows) * m)[:, None]  # positions in the flattened table
    srt = np.ravel(rows)[order]
    valid = ~np.isnan(srt)
    new = valid.copy()
    new[:, 1:] &= srt[:, 1:] != srt[:, :-1]
    ids_sorted = np.cumsum(new, dtype=np.int64)
    ids_sorted += first_id - 1
    ids_sorted[~valid.ravel()] = -1
    ids = np.empty(n_rows * m, dtype=np.int64)
    ids[order.ravel()] = ids_sorted
    return ids.reshape(n_rows, m), new.sum(axis=1), srt[new]
