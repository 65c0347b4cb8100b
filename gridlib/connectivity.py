"""Pure, vectorised functions on connectivity arrays (offsets, ragged lists).

Nothing here loops over cells or faces in Python: ragged data is handled with
offset arrays, ``np.repeat``, ``bincount``, sorting and pointer jumping.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike

from .errors import GridError
from .grid import Cells, Grid, IntArray


def offsets(counts: ArrayLike) -> IntArray:
    """Offsets (n+1,) of a ragged list with the given counts."""
    counts = np.asarray(counts, dtype=np.int64)
    pos = np.zeros(counts.size + 1, dtype=np.int64)
    np.cumsum(counts, out=pos[1:])
    return pos


def repeat_ids(pos: IntArray) -> IntArray:
    """Owner id of every entry of a ragged list: ``[0]*n0 + [1]*n1 + ...``."""
    return np.repeat(np.arange(pos.size - 1, dtype=np.int64), np.diff(pos))


def ragged_arange(starts: ArrayLike, counts: ArrayLike) -> IntArray:
    """Concatenation of ``arange(s, s + n)`` for every (s, n), vectorised."""
    starts = np.asarray(starts, dtype=np.int64)
    counts = np.asarray(counts, dtype=np.int64)
    total = int(counts.sum())
    if total == 0:
        return np.zeros(0, dtype=np.int64)
    ends = np.cumsum(counts)
    out = np.arange(total, dtype=np.int64) - np.repeat(ends - counts - starts, counts)
    return out


def renumbering(keep: np.ndarray) -> IntArray:
    """Map old index -> new index for a boolean keep mask; -1 where dropped."""
    new = np.full(keep.size, -1, dtype=np.int64)
    new[keep] = np.arange(int(np.count_nonzero(keep)), dtype=np.int64)
    return new


def cell_faces_from_neighbors(neighbors: IntArray, num_cells: int) -> tuple[IntArray, IntArray]:
    """Transpose ``neighbors`` into (face_pos, faces): each cell's faces in face order."""
    pos, half = cell_half_faces(neighbors, num_cells)
    return pos, np.right_shift(half, 1, out=half)


def cell_half_faces(neighbors: IntArray, num_cells: int) -> tuple[IntArray, IntArray]:
    """Each cell's half-faces in face order, as (pos, h) with h = 2 f + s the side s of face f.

    ``h`` indexes ``neighbors.ravel()``: cell ``neighbors[f, s]`` owns half-face h.
    """
    cells = neighbors.ravel()  # face f contributes (f, 0) then (f, 1)
    order = np.argsort(cells, kind="stable")  # outside (-1) first, then cell by cell
    pos = offsets(np.bincount(cells + 1, minlength=num_cells + 1)[1:])
    return pos, order[order.size - int(pos[-1]) :]


def half_face_cells(grid: Grid) -> IntArray:
    """The cell of every half-face (entry of ``cells.faces``)."""
    return repeat_ids(grid.cells.face_pos)


def segment_reduce(
    ufunc: np.ufunc, values: np.ndarray, pos: IntArray, empty: float | int = np.nan
) -> np.ndarray:
    """Per segment ``values[pos[i]:pos[i + 1]]`` (e.g. a cell's half-faces, with
    ``pos = grid.cells.face_pos``), ``ufunc.reduceat`` of it; ``empty`` for an empty segment
    (reduceat alone would give the next segment's first value).

    >>> segment_reduce(np.maximum, np.array([3.0, 1.0, 5.0]), np.array([0, 2, 2, 3])).tolist()
    [3.0, nan, 5.0]
    """
    start = pos[:-1]
    has = pos[1:] > start
    out = np.full(start.size, empty, dtype=np.result_type(values, np.min_scalar_type(empty)))
    if values.size and has.any():
        out[has] = ufunc.reduceat(values, start[has])
    return out


def half_face_signs(grid: Grid) -> IntArray:
    """+1 where the half-face's cell is ``neighbors[f, 0]`` (normal points out), else -1."""
    hf_cells = half_face_cells(grid)
    first = grid.faces.neighbors[grid.cells.faces, 0]
    return np.where(first == hf_cells, 1, -1).astype(np.int64)


def boundary_faces(grid: Grid) -> IntArray:
    """Indices of faces with one neighbour outside."""
    return np.flatnonzero((grid.faces.neighbors < 0).any(axis=1))


def face_node_matrix(grid: Grid) -> IntArray:
    """(nf, m) node array when every face has the same number m of nodes."""
    counts = grid.faces.num_nodes
    if counts.size and np.any(counts != counts[0]):
        raise GridError("faces have different numbers of nodes; use the ragged arrays")
    m = int(counts[0]) if counts.size else 0
    return grid.faces.nodes.reshape(-1, m)


def cell_node_cycles_2d(grid: Grid) -> tuple[IntArray, IntArray]:
    """Nodes of every cell of a 2-D grid in cyclic order (pos, nodes).

    The cycle follows the half-faces oriented so that each cell lies on their
    left, i.e. counter-clockwise in (x, y) for a consistently oriented planar
    grid. The cycle starts at the first node of the cell's first half-face.
    Raises GridError if a cell's edges do not form one closed cycle.
    """
    start, slot = half_face_cycle_slots(grid)
    nodes = np.empty_like(start)
    nodes[slot] = start
    return grid.cells.face_pos.copy(), nodes


def half_face_cycle_slots(grid: Grid) -> tuple[IntArray, IntArray]:
    """Start node of every half-face (cell on its left) and its slot along the cell's cycle."""
    if grid.griddim != 2:
        raise GridError("2-D cell cycles need a 2-D grid (faces are edges)")
    fnodes = face_node_matrix(grid)
    cf = grid.cells.faces
    hc = half_face_cells(grid)
    forward = grid.faces.neighbors[cf, 0] == hc
    a = np.where(forward, fnodes[cf, 0], fnodes[cf, 1])
    b = np.where(forward, fnodes[cf, 1], fnodes[cf, 0])
    succ = _successors_in_cycles(hc, a, b, grid.num_nodes, "cell")
    rank = cycle_rank(succ, grid.cells.face_pos, hc)
    return a, grid.cells.face_pos[hc] + rank


def _successors_in_cycles(
    owner: IntArray, start: IntArray, end: IntArray, num_nodes: int, what: str
) -> IntArray:
    """For directed edges grouped by owner, the edge that starts where each one ends."""
    key_start = owner * num_nodes + start
    order = np.argsort(key_start, kind="stable")
    sorted_keys = key_start[order]
    if sorted_keys.size > 1 and np.any(sorted_keys[1:] == sorted_keys[:-1]):
        bad = owner[order[1:][sorted_keys[1:] == sorted_keys[:-1]][0]]
        raise GridError(f"{what} {bad}: a node starts two edges (boundary is not a simple cycle)")
    key_end = owner * num_nodes + end
    ends = np.sort(key_end)
    if ends.size > 1 and np.any(ends[1:] == ends[:-1]):
        bad = int(ends[1:][ends[1:] == ends[:-1]][0] // num_nodes)
        raise GridError(f"{what} {bad}: a node ends two edges (boundary is not a simple cycle)")
    loc = np.searchsorted(sorted_keys, key_end)
    loc = np.minimum(loc, sorted_keys.size - 1)
    found = sorted_keys[loc] == key_end
    if not np.all(found):
        bad = owner[np.flatnonzero(~found)[0]]
        raise GridError(f"{what} {bad}: its edges do not close (boundary is not a cycle)")
    return order[loc]


def cycle_rank(succ: IntArray, pos: IntArray, owner: IntArray) -> IntArray:
    """Position of each edge along its owner's cycle, starting at the owner's first edge.

    List ranking by pointer jumping: O(n log L) for cycles of length L.
    """
    n = succ.size
    idx = np.arange(n, dtype=np.int64)
    first = pos[:-1][owner]
    terminal = succ == first  # the last edge before returning to the start
    nxt = np.where(terminal, idx, succ)
    dist = np.where(terminal, 0, 1).astype(np.int64)
    lengths = np.diff(pos)
    steps = (max(int(lengths.max(initial=1)), 1) - 1).bit_length() + 1  # ceil(log2 n) + 1
    for _ in range(steps):
        dist = dist + dist[nxt]
        nxt = nxt[nxt]
    if not np.all(terminal[nxt]):
        bad = owner[np.flatnonzero(~terminal[nxt])[0]]
        raise GridError(f"cell {bad}: its edges form more than one cycle (cell has a hole?)")
    return (lengths[owner] - 1) - dist


def unique_rows(a: IntArray) -> tuple[IntArray, IntArray]:
    """Unique rows of an integer array (lexicographic order) and the inverse map."""
    if a.shape[0] == 0:
        return a.copy(), np.zeros(0, dtype=np.int64)
    uniq, inverse = np.unique(a, axis=0, return_inverse=True)
    return uniq, inverse.reshape(-1).astype(np.int64)


def order_cell_faces_2d(grid: Grid) -> Grid:
    """The same 2-D grid with each cell's half-faces listed in cycle order.

    The order follows the cell's boundary with the cell on the left
    (counter-clockwise for planar grids), starting at its first half-face.
    """
    _, slot = half_face_cycle_slots(grid)
    cf = grid.cells.faces
    faces = np.empty_like(cf)
    faces[slot] = cf
    tag = None
    if grid.cells.face_tag is not None:
        tag = np.empty_like(grid.cells.face_tag)
        tag[slot] = grid.cells.face_tag
    cells = Cells(grid.cells.face_pos, faces, tag, grid.cells.index_map)
    return replace(grid, cells=cells)


def drop_repeated_nodes(pos: IntArray, nodes: IntArray) -> tuple[IntArray, IntArray]:
    """Ragged node cycles with cyclically consecutive repeats removed (a quad with a collapsed
    edge becomes a triangle). Faces must not be empty."""
    owner = repeat_ids(pos)
    nxt = np.arange(1, nodes.size + 1, dtype=np.int64)
    nxt[pos[1:] - 1] = pos[:-1]
    keep = nodes != nodes[nxt]
    if keep.all():
        return pos, nodes
    counts = np.bincount(owner[keep], minlength=pos.size - 1)
    return offsets(counts), nodes[keep]
