"""Top and bottom faces: walk every column through its kept cells in layer order.

Between two consecutive kept cells of a column, if the upper cell's bottom nodes
equal the lower cell's top nodes on every pillar they share one interior face
(this includes cells separated only by collapsed, zero-thickness layers: they
touch, as in MRST); otherwise each gets its own boundary face. The first kept
cell's top and the last one's bottom are boundary faces.

Optional pinch connections (ECLIPSE PINCH, MRST ``processPINCH``): consecutive
kept cells that do not touch, separated only by removed (inactive or collapsed)
cells with a gap no thicker than a threshold on every pillar, are connected by
a non-neighbour connection rather than a face.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..grid import FloatArray, IntArray


@dataclass(frozen=True, eq=False)
class VerticalFaces:
    nodes: IntArray  # (nf, m) node cycles (normal +z: from the upper cell to the lower one)
    upper: IntArray  # cell above the face, -1 = outside
    lower: IntArray  # cell below the face, -1 = outside
    level: IntArray  # layer interface index (k of the lower cell, or k + 1 below the last)
    column: IntArray
    pinch_pairs: IntArray  # (n, 2) cells connected across a pinched gap


def vertical_faces(
    cell: IntArray,
    column: IntArray,
    k: IntArray,
    top: IntArray,
    bottom: IntArray,
    node_z: FloatArray,
    pinch_threshold: float | None = None,
) -> VerticalFaces:
    """Horizontal faces of kept cells; ``top``/``bottom`` are (n, m) node ids per cell."""
    order = np.lexsort((k, column))
    cell, column, k, top, bottom = cell[order], column[order], k[order], top[order], bottom[order]
    n = cell.size
    same = column[1:] == column[:-1]
    touch = same & np.all(bottom[:-1] == top[1:], axis=1)
    matched_above = np.zeros(n, dtype=bool)
    matched_above[1:] = touch
    matched_below = np.zeros(n, dtype=bool)
    matched_below[:-1] = touch

    inner = np.flatnonzero(touch)  # face between inner and inner + 1
    tops = np.flatnonzero(~matched_above)
    bots = np.flatnonzero(~matched_below)
    nodes = np.concatenate([top[inner + 1], top[tops], bottom[bots]])
    upper = np.concatenate([cell[inner], np.full(tops.size, -1), cell[bots]])
    lower = np.concatenate([cell[inner + 1], cell[tops], np.full(bots.size, -1)])
    level = np.concatenate([k[inner + 1], k[tops], k[bots] + 1])
    col = np.concatenate([column[inner + 1], column[tops], column[bots]])

    pinch_pairs = np.zeros((0, 2), dtype=np.int64)
    if pinch_threshold is not None:
        gap_pairs = np.flatnonzero(same & ~touch)
        gap = (node_z[top[gap_pairs + 1]] - node_z[bottom[gap_pairs]]).max(axis=1)
        ok = (gap >= 0) & (gap <= pinch_threshold)
        pinch_pairs = np.column_stack([cell[gap_pairs[ok]], cell[gap_pairs[ok] + 1]])
    return VerticalFaces(nodes, upper, lower, level, col, pinch_pairs)
