"""Unique points along pillars: node ids that increase with depth on every pillar.

Every cell corner lies on a pillar at some depth z. Sorting all corners by
(pillar, z) and numbering the distinct values gives node ids such that, on one
pillar, a deeper point has a larger id. All later topology tests then compare
integers (ranks), never floats (OPM's key idea), and are exact.

Distinct means distinct beyond rounding. Depths that are equal in the model but
computed along different paths (``z + throw`` on one side of a fault, the
lattice depth on the other; ``0.1 + 0.2`` against ``0.3``) differ by a few
units in the last place, and two such values as two points would make every
exact test afterwards see a real interval between them: the lines through them
would cross a hair's breadth from the pillar, giving faces of area ~1e-33 m²
(collinear triangles up to rounding) and connections between cells that do not
touch. So two depths on a pillar whose gap is at most its *depth resolution*

    rho = 64 * eps * max|z| (eps = 2**-52, max over the depths on that pillar)

are one point, which keeps the shallowest of them; a run of depths each within
rho of the previous one becomes one point (such runs are only ever a few
rounded copies of one value). rho is 1.4e-14 of the pillar's largest depth
(4e-11 m at 3000 m): far below any real layer thickness, and above the error of
the few dozen floating-point operations that produce a corner depth, even with
cancellation. Then the overlap of two cells on a pillar pair has positive area
exactly when the ranks say so (:mod:`~gridlib.pillars.lateral`), and a
face of zero area, one whose nodes lie within rounding of a line, is never made.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..grid import FloatArray, IntArray

RESOLUTION_ULPS = 64
"""Depths on a pillar closer than this many units in the last place of its largest depth are one point."""


def depth_resolution(scale: FloatArray) -> FloatArray:
    """The depth resolution rho (same unit as the depths) of pillars whose largest |depth| is ``scale``."""
    return (RESOLUTION_ULPS * np.finfo(np.float64).eps) * np.abs(scale)


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
    """Number the distinct depths on every pillar (up to rounding, or after quantising by ``tol``).

    Depths within the pillar's depth resolution of the previous one are the
    same point (see the module docstring). With ``tol > 0`` depths are first
    rounded to multiples of ``tol`` (MRST's semantics, vectorised): two depths
    closer than ``tol`` that straddle a rounding boundary stay distinct. The
    default, 0, merges only depths equal up to rounding.
    """
    zq = np.round(z / tol) * tol if tol > 0 else z
    order = np.lexsort((zq, pillar))
    ps, zs = pillar[order], zq[order]
    new = np.ones(order.size, dtype=bool)
    new[1:] = ps[1:] != ps[:-1]
    if zs.size:
        first = np.flatnonzero(new)  # each pillar's shallowest and deepest depth bound its |z|
        last = np.append(first[1:] - 1, zs.size - 1)
        rho = depth_resolution(np.maximum(np.abs(zs[first]), np.abs(zs[last])))
        run = np.cumsum(new) - 1
        new[1:] |= (zs[1:] - zs[:-1]) > rho[run[1:]]
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
    few presorted runs. Depths within the row's depth resolution of the
    previous one are the same point, as there. Points are numbered from
    ``first_id``, row by row and by depth within a row, so a table can be
    numbered in blocks of rows. Returns
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
    n_valid = valid.sum(axis=1)
    deepest = srt[np.arange(n_rows), np.maximum(n_valid - 1, 0)]
    with np.errstate(invalid="ignore"):  # rows without any depth: NaN, never compared
        rho = depth_resolution(np.maximum(np.abs(srt[:, 0]), np.abs(deepest)))
    new = valid.copy()
    with np.errstate(invalid="ignore"):
        new[:, 1:] &= (srt[:, 1:] - srt[:, :-1]) > rho[:, None]
    ids_sorted = np.cumsum(new, dtype=np.int64)
    ids_sorted += first_id - 1
    ids_sorted[~valid.ravel()] = -1
    ids = np.empty(n_rows * m, dtype=np.int64)
    ids[order.ravel()] = ids_sorted
    return ids.reshape(n_rows, m), new.sum(axis=1), srt[new]


def sorted_points_rows(rows: FloatArray, first_id: int = 0) -> tuple[IntArray, IntArray, FloatArray]:
    """:func:`unique_points_rows` without the sort, for rows whose depths already grow
    (non-decreasing along each row, NaN = no point): the same ids, counts and depths.

    A depth starts a new point where it lies more than the row's depth resolution below
    the previous depth of its row, exactly the test of the sorted rows there (repeated
    depths, which a sort would put next to each other, differ by 0). Corner-point decks
    without throws give such rows, one depth per layer interface.
    """
    n_rows, m = rows.shape
    valid = ~np.isnan(rows)
    column = np.arange(m)
    last_valid = np.maximum.accumulate(np.where(valid, column, -1), axis=1)
    previous = np.full((n_rows, m), -1, dtype=np.int64)
    previous[:, 1:] = last_valid[:, :-1]
    row = np.arange(n_rows)[:, None]
    shallowest = rows[row[:, 0], np.argmax(valid, axis=1)]
    deepest = rows[row[:, 0], np.maximum(last_valid[:, -1], 0)]
    with np.errstate(invalid="ignore"):  # rows without any depth: NaN, never compared
        rho = depth_resolution(np.maximum(np.abs(shallowest), np.abs(deepest)))
        new = valid & ((previous < 0) | ((rows - rows[row, np.maximum(previous, 0)]) > rho[:, None]))
    ids = np.cumsum(new, dtype=np.int64).reshape(n_rows, m)
    ids += first_id - 1
    ids[~valid] = -1
    return ids, new.sum(axis=1), rows[new]
