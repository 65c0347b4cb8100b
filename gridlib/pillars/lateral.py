"""Lateral faces between the columns on either side of every pillar pair.

Each pillar pair (p1, p2) has a column on side A and one on side B (or none at
the edge of the model). On each side, the cells are intervals between a top
line and a bottom line (each line joins a node on p1 to a node on p2). With
voids between consecutive cells and sentinels above and below, each side is a
partition of the whole pillar band; every overlap between an A interval and a B
interval with positive area is a face piece: cell-cell pieces are interior
faces (non-neighbour connections when the layers differ), cell-void pieces are
boundary faces. Because the pieces of a cell tile its lateral face exactly,
cells stay closed however the fault throws.

All tests run on integer ranks (node ids along a pillar grow with depth):

* A_i and B_j share area iff they overlap on p1, or on p2, or their tops cross
  strictly between the pillars, or their bottoms do (exact once intervals of
  zero thickness on both pillars are dropped). This is also the zero-area
  criterion: a piece is degenerate (its corners collinear) exactly when the
  test fails, so none is made. Because depths equal up to rounding are one
  point (:mod:`~gridlib.pillars.pillar_points`), a rounding difference never
  passes for an overlap or a crossing: a fault whose throw varies along the
  trace and meets another layer's depth at a pillar touches it there, it does
  not leave a triangle of ~1e-33 m² and a connection between cells that do
  not touch;
* candidates come from one ``searchsorted`` over all pairs at once, on keys
  ``pair * R + rank``, since bottoms (and tops) grow with depth along a side;
* the piece {max(tops) <= z <= min(bottoms)} is a convex polygon of at most 6
  vertices, filled into MRST/OPM's 8-slot cyclic template: top of p1, top-top
  crossing, top of p2, envelope crossing near p2, bottom of p2, bottom-bottom
  crossing, bottom of p1, envelope crossing near p1;
* a crossing node is identified by its pair and the node ids of its two lines,
  so the up to four pieces that meet there share it. Its position is on the
  first line where the two lines' depths agree (MRST's convention; exact for
  coplanar pillars).

With the template order, the piece's normal points from A to B when p1 -> p2
runs along +y for an i-pair (A = lower i); pairs marked ``reverse`` (j-pairs,
p1 -> p2 along +x) walk it backwards from slot 0, which gives exactly
``cart_grid``'s node cycles on unfaulted grids.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..connectivity import offsets, ragged_arange
from ..grid import FloatArray, IntArray


@dataclass(frozen=True, eq=False)
class SideCells:
    """The cells on either side of every pillar pair, with their ranks on p1 and p2."""

    pair: IntArray
    side: IntArray  # 0 = A, 1 = B
    cell: IntArray
    k: IntArray  # order of the cells along the side (increasing with depth)
    t1: IntArray
    b1: IntArray
    t2: IntArray
    b2: IntArray


@dataclass(frozen=True, eq=False)
class LateralFaces:
    """Face pieces on pillar pairs; nodes >= n_pillar_nodes are crossing nodes."""

    node_pos: IntArray
    nodes: IntArray
    cell_a: IntArray  # -1 where side A is a void
    cell_b: IntArray
    pair: IntArray
    k_a: IntArray  # layer order of the A interval (-1 for voids)
    k_b: IntArray
    mismatch: np.ndarray  # the two sides' lines differ on a pillar (a fault piece)
    crossing_coords: FloatArray  # (n_crossings, 3)
    crossing_lines: IntArray  # (n_crossings, 2, 2): the two lines (node on p1, node on p2)


@dataclass(frozen=True, eq=False)
class _Intervals:
    pair: IntArray
    cell: IntArray  # -1 for voids
    k: IntArray
    t1: IntArray
    b1: IntArray
    t2: IntArray
    b2: IntArray


def _side_intervals(cells: SideCells, side: int, n_pairs: int, big: int) -> _Intervals:
    """One side of every pair as a partition: void, cell, void, ..., cell, void."""
    sel = cells.side == side
    pair, k = cells.pair[sel], cells.k[sel]
    order = np.argsort(pair * (int(k.max(initial=0)) + 1) + k, kind="stable")
    pair, k, cell = pair[order], k[order], cells.cell[sel][order]
    t1, b1, t2, b2 = (getattr(cells, a)[sel][order] for a in ("t1", "b1", "t2", "b2"))
    m = pair.size
    first = np.ones(m, dtype=bool)
    first[1:] = pair[1:] != pair[:-1]
    last = np.ones(m, dtype=bool)
    last[:-1] = pair[1:] != pair[:-1]
    idx = np.arange(m)
    pos = idx - np.maximum.accumulate(np.where(first, idx, 0))
    prev_b1 = np.where(first, -1, np.roll(b1, 1))
    prev_b2 = np.where(first, -1, np.roll(b2, 1))
    count = np.bincount(pair, minlength=n_pairs)
    empty = np.flatnonzero(count == 0)
    n_void_end = int(last.sum())
    cat = np.concatenate
    all_pair = cat([pair, pair, pair[last], empty])
    seq = cat([2 * pos, 2 * pos + 1, 2 * (pos[last] + 1), np.zeros(empty.size, np.int64)])
    big_last = np.full(n_void_end, big)
    out_t1 = cat([prev_b1, t1, b1[last], np.full(empty.size, -1)])
    out_b1 = cat([t1, b1, big_last, np.full(empty.size, big)])
    out_t2 = cat([prev_b2, t2, b2[last], np.full(empty.size, -1)])
    out_b2 = cat([t2, b2, big_last, np.full(empty.size, big)])
    out_cell = cat([np.full(m, -1), cell, np.full(n_void_end + empty.size, -1)])
    out_k = cat([np.full(m, -1), k, np.full(n_void_end + empty.size, -1)])
    keep = (out_cell >= 0) | (out_t1 < out_b1) | (out_t2 < out_b2)
    o = np.argsort(all_pair[keep] * (int(seq.max(initial=0)) + 1) + seq[keep], kind="stable")
    return _Intervals(*(a[keep][o] for a in (all_pair, out_cell, out_k, out_t1, out_b1, out_t2, out_b2)))


def general_pieces(cells, n_pairs, pair_p1, pair_p2, reverse, points, node_xyz) -> LateralFaces:
    """All face pieces of the pillar pairs whose cells are listed in ``cells`` (see the module
    docstring); pairs without a fault are better served by the front ends' fast paths."""
    max_rank = int(np.diff(points.offset).max(initial=1))
    big = max_rank + 1
    stride = max_rank + 3  # keys: rank r -> r + 1, sentinel -1 -> 0, big -> max_rank + 2
    A = _side_intervals(cells, 0, n_pairs, big)
    B = _side_intervals(cells, 1, n_pairs, big)
    ia, ib = _candidates(A, B, stride)

    tA1, bA1, tA2, bA2 = A.t1[ia], A.b1[ia], A.t2[ia], A.b2[ia]
    tB1, bB1, tB2, bB2 = B.t1[ib], B.b1[ib], B.t2[ib], B.b2[ib]
    T1, B1 = np.maximum(tA1, tB1), np.minimum(bA1, bB1)
    T2, B2 = np.maximum(tA2, tB2), np.minimum(bA2, bB2)
    cross_top = (tA1 - tB1) * (tA2 - tB2) < 0
    cross_bot = (bA1 - bB1) * (bA2 - bB2) < 0
    piece = (T1 < B1) | (T2 < B2) | cross_top | cross_bot
    ia, ib = ia[piece], ib[piece]
    tA1, bA1, tA2, bA2, tB1, bB1, tB2, bB2 = (a[piece] for a in (tA1, bA1, tA2, bA2, tB1, bB1, tB2, bB2))
    T1, B1, T2, B2 = T1[piece], B1[piece], T2[piece], B2[piece]
    cross_top, cross_bot = cross_top[piece], cross_bot[piece]
    pair = A.pair[ia]
    p1, p2 = pair_p1[pair], pair_p2[pair]
    o1, o2 = points.offset[p1], points.offset[p2]

    n = pair.size
    slots = np.full((n, 8), -1, dtype=np.int64)
    ov1, touch1, ov2, touch2 = T1 < B1, T1 == B1, T2 < B2, T2 == B2
    slots[:, 0] = np.where(ov1, o1 + T1, -1)
    slots[:, 6] = np.where(ov1, o1 + B1, -1)
    slots[:, 7] = np.where(touch1, o1 + T1, -1)
    slots[:, 2] = np.where(ov2, o2 + T2, -1)
    slots[:, 4] = np.where(ov2, o2 + B2, -1)
    slots[:, 3] = np.where(touch2, o2 + T2, -1)

    # Lines as (node on p1, node on p2); crossings need the two lines of each kind.
    lines = {
        "tA": (o1 + tA1, o2 + tA2),
        "tB": (o1 + tB1, o2 + tB2),
        "bA": (o1 + bA1, o2 + bA2),
        "bB": (o1 + bB1, o2 + bB2),
    }
    requests = []  # (slot, mask, line L, line M)
    requests.append((1, cross_top, lines["tA"], lines["tB"]))
    requests.append((5, cross_bot, lines["bA"], lines["bB"]))
    # Envelope crossing near a pillar without overlap: deeper top x shallower bottom.
    for slot, no_ov, a_deeper in ((7, ~ov1 & ~touch1, tA1 > tB1), (3, ~ov2 & ~touch2, tA2 > tB2)):
        top = tuple(np.where(a_deeper, lines["tA"][i], lines["tB"][i]) for i in range(2))
        bot = tuple(np.where(a_deeper, lines["bB"][i], lines["bA"][i]) for i in range(2))
        requests.append((slot, no_ov, top, bot))

    crossing_coords, crossing_lines = _crossing_nodes(slots, pair, requests, points.num_nodes, node_xyz)

    node_pos, nodes, good = _piece_cycles(slots, reverse[pair])
    mismatch = (tA1 != tB1) | (bA1 != bB1) | (tA2 != tB2) | (bA2 != bB2)
    return LateralFaces(
        node_pos,
        nodes,
        A.cell[ia][good],
        B.cell[ib][good],
        pair[good],
        A.k[ia][good],
        B.k[ib][good],
        mismatch[good],
        crossing_coords,
        crossing_lines,
    )


def _candidates(A: _Intervals, B: _Intervals, stride: int) -> tuple[IntArray, IntArray]:
    """The pairs (ia, ib) of intervals of sides A and B of one pillar pair that may overlap (by their
    sorted keys ``pair * stride + rank + 1``), with a cell on at least one side."""

    def key(iv: _Intervals, ranks: IntArray) -> IntArray:
        return iv.pair * stride + ranks + 1

    lo = np.minimum(
        np.searchsorted(key(B, B.b1), key(A, A.t1), "right"),
        np.searchsorted(key(B, B.b2), key(A, A.t2), "right"),
    )
    hi = (
        np.maximum(
            np.searchsorted(key(B, B.t1), key(A, A.b1), "left"),
            np.searchsorted(key(B, B.t2), key(A, A.b2), "left"),
        )
        - 1
    )
    count = np.maximum(hi - lo + 1, 0)
    ia = np.repeat(np.arange(A.pair.size), count)
    ib = ragged_arange(lo, count)
    keep = (A.cell[ia] >= 0) | (B.cell[ib] >= 0)
    return ia[keep], ib[keep]


def _crossing_nodes(slots: IntArray, pair: IntArray, requests, first_crossing: int, node_xyz):
    """The crossing nodes the pieces ask for: ``requests`` are (slot, which pieces, line L, line M),
    the lines as (node on p1, node on p2). Each distinct crossing of two lines of a pair becomes one
    node, numbered from ``first_crossing`` and written into ``slots`` (in place); returns their
    coordinates and their two lines (n, 2, 2)."""
    cross_rows, cross_slots, keys = [], [], []
    for slot, mask, line_l, line_m in requests:
        rows = np.flatnonzero(mask)
        la = np.column_stack([line_l[0][rows], line_l[1][rows]])
        lb = np.column_stack([line_m[0][rows], line_m[1][rows]])
        swap = (la[:, 0] > lb[:, 0]) | ((la[:, 0] == lb[:, 0]) & (la[:, 1] > lb[:, 1]))
        first, second = np.where(swap[:, None], lb, la), np.where(swap[:, None], la, lb)
        keys.append(np.column_stack([pair[rows], first, second]))
        cross_rows.append(rows)
        cross_slots.append(np.full(rows.size, slot))
    keys_all = np.concatenate(keys) if keys else np.zeros((0, 5), np.int64)
    if not keys_all.shape[0]:
        return np.zeros((0, 3)), np.zeros((0, 2, 2), np.int64)
    uniq, inverse = np.unique(keys_all, axis=0, return_inverse=True)
    inverse = inverse.reshape(-1)
    slots[np.concatenate(cross_rows), np.concatenate(cross_slots)] = first_crossing + inverse
    return _crossing_points(uniq[:, 1:3], uniq[:, 3:5], node_xyz), uniq[:, 1:5].reshape(-1, 2, 2)


def _crossing_points(line_u: IntArray, line_v: IntArray, xyz: FloatArray) -> FloatArray:
    """Where line u (nodes u1 on p1, u2 on p2) crosses line v, on the pillar pair's surface.

    At the fraction s along the pair where both lines have the same depth z, the point
    is the fraction s of the way from pillar 1 to pillar 2, both taken at depth z: a
    point of the bilinear surface the two pillars span, as OPM's corner-point processing
    places it (the straight lines u and v themselves leave that surface where the
    pillars are not parallel), so that fault faces are the simulator's.
    """
    u1, u2 = xyz[line_u[:, 0]], xyz[line_u[:, 1]]
    v1, v2 = xyz[line_v[:, 0]], xyz[line_v[:, 1]]
    d1 = u1[:, 2] - v1[:, 2]
    d2 = u2[:, 2] - v2[:, 2]
    s = (d1 / (d1 - d2))[:, None]
    z = u1[:, 2:] + s * (u2[:, 2:] - u1[:, 2:])
    on_p1 = u1 + (z - u1[:, 2:]) / (v1[:, 2:] - u1[:, 2:]) * (v1 - u1)  # pillar 1 at depth z
    on_p2 = u2 + (z - u2[:, 2:]) / (v2[:, 2:] - u2[:, 2:]) * (v2 - u2)
    out = on_p1 + s * (on_p2 - on_p1)
    out[:, 2] = z[:, 0]
    return out


def _piece_cycles(slots: IntArray, reverse: np.ndarray) -> tuple[IntArray, IntArray, np.ndarray]:
    """Node cycles of the pieces with at least three distinct nodes, and which pieces those are.

    Most pieces are plain quadrilaterals (slots 0, 2, 4, 6 only, all distinct):
    they take a fast path; the others are compacted slot by slot. Reversed
    pieces walk the template backwards, still starting at slot 0.
    """
    corner = slots[:, [0, 2, 4, 6]]
    plain = (slots[:, [1, 3, 5, 7]] < 0).all(axis=1) & (corner >= 0).all(axis=1)
    plain &= (corner[:, 0] != corner[:, 3]) & (corner[:, 1] != corner[:, 2])
    counts = np.full(slots.shape[0], 4, dtype=np.int64)
    other = np.flatnonzero(~plain)
    template = slots[other]
    rev = reverse[other]
    template[rev] = template[rev][:, [0, 7, 6, 5, 4, 3, 2, 1]]
    o_pos, o_nodes = _compact_cycles(template)
    counts[other] = np.diff(o_pos)
    good = counts >= 3
    pos = offsets(np.where(good, counts, 0))
    nodes = np.empty(int(pos[-1]), dtype=np.int64)
    quads = np.flatnonzero(plain)
    quad_nodes = np.where(reverse[quads][:, None], corner[quads][:, [0, 3, 2, 1]], corner[quads])
    nodes[pos[quads][:, None] + np.arange(4)] = quad_nodes
    keep_other = good[other]
    o_counts = np.diff(o_pos)[keep_other]
    src = ragged_arange(o_pos[:-1][keep_other], o_counts)
    dst = ragged_arange(pos[other[keep_other]], o_counts)
    nodes[dst] = o_nodes[src]
    counts = counts[good]
    return offsets(counts), nodes, good


def _compact_cycles(slots: IntArray) -> tuple[IntArray, IntArray]:
    """Ragged node cycles from (n, 8) slot rows: drop -1 and cyclically repeated nodes."""
    n = slots.shape[0]
    valid = slots >= 0
    # The previous *valid* slot of each entry (cyclically) decides repetition.
    col = np.arange(8)
    last_valid = np.where(valid, col, -1)
    run = np.maximum.accumulate(last_valid, axis=1)
    wrap = run[:, -1:]  # last valid column, used for entries before the first valid one
    prev_col = np.where(np.roll(run, 1, axis=1) >= 0, np.roll(run, 1, axis=1), wrap)
    prev_col[:, 0] = wrap[:, 0]
    prev_node = np.take_along_axis(slots, np.maximum(prev_col, 0), axis=1)
    keep = valid & (slots != prev_node)
    # A face whose valid nodes are all equal would drop everything; keep one.
    none = ~keep.any(axis=1) & valid.any(axis=1)
    keep[none, np.argmax(valid[none], axis=1)] = True
    counts = keep.sum(axis=1)
    return offsets(counts), slots[keep] if n else np.zeros(0, np.int64)
