"""Faces of a corner-point grid from its (k, j, i) structure, vectorised by slicing.

Lateral faces: for every pillar pair, compare the cells on its two sides layer
by layer. A pair is *regular* when both sides hold the same cells with the same
corner nodes (no fault): one quadrilateral per cell. A pair with cells on one
side only (the edge of the model, an inactive column) gives one boundary
quadrilateral per cell. Every other pair (faults, partly inactive neighbours,
pinch-outs) goes to the general pillar-pair engine. Quadrilaterals come out in
(k, j, i) order, ``cart_grid``'s face order.

Top and bottom faces: walk every column through its kept cells (array
accumulations along k); consecutive kept cells whose shared corners coincide
get one face, others a boundary face each.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..grid import IntArray
from ..stratigraphic.lateral import SideCells

# Corner slots (a + 2b + 4c) of the A and B side of an i-pair and a j-pair: (t1, t2, b1, b2).
_I_PAIR = ((1, 3, 5, 7), (0, 2, 4, 6))
_J_PAIR = ((2, 3, 6, 7), (0, 1, 4, 5))


@dataclass(frozen=True, eq=False)
class StructuredLateral:
    """Quadrilaterals of simple pairs and the cells of the other pairs."""

    quads: IntArray  # (n, 4) node cycles, normal from A to B
    cell_a: IntArray
    cell_b: IntArray
    pair: IntArray
    k: IntArray  # layer of the quad's cell(s)
    side_cells: SideCells  # for the general engine
    faulted: np.ndarray  # per pair: a layer where both sides differ


def structured_lateral(nodes: IntArray, kept: np.ndarray, cell_id: IntArray, along_j: bool, pair_base: int):
    """One orientation of lateral faces: i-pairs (``along_j`` False) or j-pairs."""
    axis = 1 if along_j else 2
    pad = [(0, 0)] * 4
    pad[axis] = (1, 1)
    nd = np.pad(np.where(kept[..., None], nodes, -1), pad, constant_values=-1)
    cid = np.pad(np.where(kept, cell_id, -1), pad[:3], constant_values=-1)
    sl_a = [slice(None)] * 3
    sl_b = [slice(None)] * 3
    sl_a[axis] = slice(None, -1)
    sl_b[axis] = slice(1, None)
    sa, sb = _J_PAIR if along_j else _I_PAIR
    A = nd[tuple(sl_a)]
    Bn = nd[tuple(sl_b)]
    at1, at2, ab1, ab2 = (A[..., s] for s in sa)
    bt1, bt2, bb1, bb2 = (Bn[..., s] for s in sb)
    ex_a = (at1 >= 0) & ((at1 < ab1) | (at2 < ab2))  # kept and not pinched on this pair
    ex_b = (bt1 >= 0) & ((bt1 < bb1) | (bt2 < bb2))
    same_corners = (at1 == bt1) & (at2 == bt2) & (ab1 == bb1) & (ab2 == bb2)
    regular = ((ex_a == ex_b) & (~ex_a | same_corners)).all(axis=0)
    one_side = ~ex_a.any(axis=0) | ~ex_b.any(axis=0)
    simple = regular | one_side
    faulted = (ex_a & ex_b & ~same_corners).any(axis=0)

    k, j, i = np.nonzero(simple[None] & (ex_a | ex_b))
    use_a = ex_a[k, j, i]
    t1 = np.where(use_a, at1[k, j, i], bt1[k, j, i])
    t2 = np.where(use_a, at2[k, j, i], bt2[k, j, i])
    b1 = np.where(use_a, ab1[k, j, i], bb1[k, j, i])
    b2 = np.where(use_a, ab2[k, j, i], bb2[k, j, i])
    # Template (t1, t2, b2, b1) has its normal along +i for i-pairs; j-pairs walk it backwards.
    quads = np.column_stack([t1, b1, b2, t2]) if along_j else np.column_stack([t1, t2, b2, b1])
    ca = cid[tuple(sl_a)][k, j, i]
    cb = cid[tuple(sl_b)][k, j, i]
    width = simple.shape[1]
    pair = pair_base + i + width * j

    # Cells on both sides of the other pairs, for the general engine.
    general = ~simple
    cells = []
    for side, ex, (t1s, t2s, b1s, b2s), cells_id in (
        (0, ex_a, (at1, at2, ab1, ab2), cid[tuple(sl_a)]),
        (1, ex_b, (bt1, bt2, bb1, bb2), cid[tuple(sl_b)]),
    ):
        kk, jj, ii = np.nonzero(general[None] & ex)
        cells.append(
            (
                pair_base + ii + width * jj,
                np.full(kk.size, side),
                cells_id[kk, jj, ii],
                kk,
                t1s[kk, jj, ii],
                b1s[kk, jj, ii],
                t2s[kk, jj, ii],
                b2s[kk, jj, ii],
            )
        )
    side_cells = SideCells(*(np.concatenate([c[f] for c in cells]).astype(np.int64) for f in range(8)))
    return StructuredLateral(quads, ca, cb, pair, k, side_cells, faulted.ravel())


@dataclass(frozen=True, eq=False)
class StructuredVertical:
    nodes: IntArray  # (n, 4) node cycles, normal +z (from the upper cell to the lower one)
    upper: IntArray
    lower: IntArray
    level: IntArray  # interface index (k of the lower cell; k + 1 under the last cell)
    j: IntArray
    i: IntArray
    sub: IntArray  # 0 for the bottom of an upper cell, 1 otherwise (orders faces at one level)
    skips_layers: np.ndarray  # an interior face joining cells more than one layer apart
    pinch_pairs: IntArray  # (n, 2) cell ids joined across a thin gap (no face)


def structured_vertical(
    nodes: IntArray,
    kept: np.ndarray,
    cell_id: IntArray,
    node_z: np.ndarray,
    pinch_threshold: float | None,
    source: str,
) -> StructuredVertical:
    nz, ny, nx, _ = nodes.shape
    top = nodes[..., [0, 1, 3, 2]]  # cycle (i, j), (i+1, j), (i+1, j+1), (i, j+1)
    bot = nodes[..., [4, 5, 7, 6]]
    karr = np.arange(nz)[:, None, None]
    last_kept = np.maximum.accumulate(np.where(kept, karr, -1), axis=0)
    prev = np.full((nz, ny, nx), -1)
    prev[1:] = last_kept[:-1]
    has_prev = kept & (prev >= 0)
    kk, jj, ii = np.nonzero(has_prev)
    pk = prev[kk, jj, ii]
    above = bot[pk, jj, ii]
    below = top[kk, jj, ii]
    if np.any(below < above):  # node ids grow with depth along a pillar
        bad = np.flatnonzero((below < above).any(axis=1))[0]
        raise InputError(
            f"{source}: ZCORN: cell ({ii[bad] + 1}, {jj[bad] + 1}, {pk[bad] + 1}) reaches below "
            "the top of cell "
            f"({ii[bad] + 1}, {jj[bad] + 1}, {kk[bad] + 1}) in the same column (overlapping layers)"
        )
    touch = (above == below).all(axis=1)
    touched = np.zeros((nz, ny, nx), dtype=bool)  # cell touches the kept cell above it
    touched[kk, jj, ii] = touch
    touched_below = np.zeros((nz, ny, nx), dtype=bool)  # cell touches the kept cell below it
    touched_below[pk[touch], jj[touch], ii[touch]] = True

    ki, ji, iint = kk[touch], jj[touch], ii[touch]
    kt, jt, it = np.nonzero(kept & ~touched)
    kb, jb, ib = np.nonzero(kept & ~touched_below)
    faces = np.concatenate([top[ki, ji, iint], top[kt, jt, it], bot[kb, jb, ib]])
    upper = np.concatenate([cell_id[pk[touch], ji, iint], np.full(kt.size, -1), cell_id[kb, jb, ib]])
    lower = np.concatenate([cell_id[ki, ji, iint], cell_id[kt, jt, it], np.full(kb.size, -1)])
    level = np.concatenate([ki, kt, kb + 1])
    sub = np.concatenate([np.ones(ki.size + kt.size, np.int64), np.zeros(kb.size, np.int64)])
    skips = np.concatenate([ki - pk[touch] > 1, np.zeros(kt.size + kb.size, bool)])

    pinch_pairs = np.zeros((0, 2), dtype=np.int64)
    if pinch_threshold is not None:
        gap_rows = np.flatnonzero(~touch)
        gap = (node_z[below[gap_rows]] - node_z[above[gap_rows]]).max(axis=1)
        ok = gap_rows[(gap >= 0) & (gap <= pinch_threshold)]
        pinch_pairs = np.column_stack(
            [cell_id[pk[ok], jj[ok], ii[ok]], cell_id[kk[ok], jj[ok], ii[ok]]]
        ).astype(np.int64)
    return StructuredVertical(
        faces,
        upper,
        lower,
        level,
        np.concatenate([ji, jt, jb]),
        np.concatenate([iint, it, ib]),
        sub,
        skips,
        pinch_pairs,
    )
