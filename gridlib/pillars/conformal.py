"""Insert crossing nodes into the top/bottom face edges they lie on.

Where the lines of two cells cross between two pillars, the crossing node is a
vertex of the lateral face pieces. It also lies on the top or bottom edge of
the horizontal faces of those cells, but skew pillars make the two lines skew,
so no point lies exactly on both. Inserting the node into those horizontal
faces makes every cell's surface watertight (each edge shared by two faces in
opposite directions), so the closure of every cell is exact whatever the
crossing-point convention.
"""

from __future__ import annotations

import numpy as np

from ..connectivity import offsets, ragged_arange
from ..grid import FloatArray, IntArray


def insert_edge_nodes(
    face_nodes: IntArray,
    crossing_lines: IntArray,
    crossing_ids: IntArray,
    coords: FloatArray,
) -> tuple[IntArray, IntArray]:
    """Ragged (pos, nodes) of faces ``face_nodes`` (nf, m) with crossings inserted.

    ``crossing_lines`` (nc, 2, 2) holds, for every crossing, its two lines as
    (node on p1, node on p2); ``crossing_ids`` its node id. A crossing is
    inserted into every face edge equal to one of its lines, ordered along the
    edge. (The faces of corner-point grids, all with m nodes; see
    :func:`edge_insertions` for faces of any sizes.)
    """
    nf, m = face_nodes.shape
    face_pos, flat = np.arange(0, nf * m + 1, m), face_nodes.ravel()
    slots, nodes = edge_insertions(face_pos, flat, crossing_lines, crossing_ids, coords)
    if slots.size == 0:
        return face_pos.copy(), flat.copy()
    owner = np.searchsorted(face_pos, slots, "right") - 1  # the face of every insertion
    face_counts = np.diff(face_pos) + np.bincount(owner, minlength=nf)
    return offsets(face_counts), insert_after(flat, slots, nodes)


def edge_insertions(
    face_pos: IntArray,
    face_nodes: IntArray,
    crossing_lines: IntArray,
    crossing_ids: IntArray,
    coords: FloatArray,
) -> tuple[IntArray, IntArray]:
    """The crossings to insert into the edges of ragged faces (``face_pos`` offsets, flat ``face_nodes``
    cycles; the crossings as in :func:`insert_edge_nodes`): ``(slots, nodes)``, ``nodes[i]`` to go right
    after ``face_nodes[slots[i]]`` (the edge from that node to the next), sorted by slot and along the
    edge (see :func:`insert_after`).

    >>> coords = np.array([[0.0, 0, 0], [2, 0, 0], [2, 2, 0], [0, 2, 0], [1, 0, 0], [0, -1, 0], [2, 1, 0]])
    >>> lines = np.array([[[0, 1], [5, 6]]])  # node 4: where the lines 0-1 and 5-6 cross
    >>> faces = np.array([0, 1, 2, 3, 3, 1, 0])  # a square and a triangle, both with an edge 0-1
    >>> slots, nodes = edge_insertions(np.array([0, 4, 7]), faces, lines, np.array([4]), coords)
    >>> slots.tolist(), nodes.tolist()
    ([0, 5], [4, 4])
    >>> insert_after(faces, slots, nodes).tolist()
    [0, 4, 1, 2, 3, 3, 1, 4, 0]
    """
    counts = np.diff(face_pos)
    a = face_nodes
    nxt = np.arange(1, a.size + 1)
    nxt[face_pos[1:][counts > 0] - 1] = face_pos[:-1][counts > 0]
    b = a[nxt] if a.size else a
    n_nodes = coords.shape[0]
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    edge_key = lo * n_nodes + hi

    l_lo = np.minimum(crossing_lines[:, :, 0], crossing_lines[:, :, 1]).ravel()
    l_hi = np.maximum(crossing_lines[:, :, 0], crossing_lines[:, :, 1]).ravel()
    node = np.repeat(crossing_ids, 2)
    span = coords[l_hi] - coords[l_lo]
    t = ((coords[node] - coords[l_lo]) * span).sum(axis=1) / (span * span).sum(axis=1)
    key = l_lo * n_nodes + l_hi
    order = np.lexsort((t, key))
    key, node, t = key[order], node[order], t[order]

    start = np.searchsorted(key, edge_key, "left")
    count = np.searchsorted(key, edge_key, "right") - start
    edge = np.flatnonzero(count)
    count, start = count[edge], start[edge]
    # Inserted nodes run from a to b: increasing t when a is the line's low node.
    local = ragged_arange(np.zeros(count.size, np.int64), count)
    which = np.repeat(np.arange(count.size), count)
    forward = a[edge][which] == lo[edge][which]
    src = start[which] + np.where(forward, local, count[which] - 1 - local)
    return edge[which], node[src]


def insert_after(values: IntArray, slots: IntArray, inserted: IntArray) -> IntArray:
    """``values`` with ``inserted[i]`` placed right after ``values[slots[i]]`` (``slots`` sorted;
    entries of the same slot keep their order).

    >>> insert_after(np.array([5, 6, 7]), np.array([0, 0, 2]), np.array([1, 2, 3])).tolist()
    [5, 1, 2, 6, 7, 3]
    """
    out = np.empty(values.size + slots.size, dtype=values.dtype)
    at = slots + 1 + np.arange(slots.size)
    keep = np.ones(out.size, dtype=bool)
    keep[at] = False
    out[keep] = values
    out[at] = inserted
    return out
