"""Faces of a corner-point grid from its (k, j, i) structure, vectorised by slicing.

Lateral faces: for every pillar pair, compare the cells on its two sides layer
by layer. A pair is *regular* when, in every layer, both sides hold the same cell
with the same corner nodes (no fault), or one side a cell that nothing of the other
side overlaps (an inactive neighbour: :func:`_alone`): one quadrilateral per cell.
A pair with cells on one side only (the edge of the model, an inactive column)
gives one boundary quadrilateral per cell. Every other pair (faults, inactive
neighbours next to a throw, pinch-outs) goes to the general pillar-pair engine.
Quadrilaterals come out in (k, j, i) order, ``cart_grid``'s face order.

Top and bottom faces: walk every column through its kept cells (array
accumulations along k); consecutive kept cells whose shared corners coincide
get one face, others a boundary face each. They come out ordered by layer
interface, then j, then i, the bottom face of an upper cell before the top face
of a lower one.

Both kinds are described by the padded table position of the cell whose corners
they use (see :class:`~gridlib.cornerpoint.corners.CornerNodes`); their node ids
are read from the table when the grid's arrays are filled, a block at a time.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..grid import IntArray
from ..pillars.lateral import SideCells

# Corner slots (a + 2b + 4c) of the A and B side of an i-pair and a j-pair: (t1, t2, b1, b2).
_I_PAIR = ((1, 3, 5, 7), (0, 2, 4, 6))
_J_PAIR = ((2, 3, 6, 7), (0, 1, 4, 5))
# Node cycles of the quads with their normal from A to B: (t1, t2, b2, b1) for i-pairs,
# the same walked backwards, (t1, b1, b2, t2), for j-pairs; as slots of side A and side B.
_I_QUAD = (np.array([1, 3, 7, 5]), np.array([0, 2, 6, 4]))
_J_QUAD = (np.array([2, 6, 7, 3]), np.array([0, 4, 5, 1]))
# Top and bottom cycles (i, j), (i+1, j), (i+1, j+1), (i, j+1): normal +z, downwards.
_TOP = np.array([0, 1, 3, 2])
_BOTTOM = _TOP + 4


@dataclass(frozen=True, eq=False)
class LateralQuads:
    """Quadrilaterals of the simple pairs of one orientation, in (k, j, i) order."""

    source: IntArray  # table position of the cell whose corners the quad uses
    use_a: np.ndarray  # that cell is on side A (else on side B)
    cycle: tuple[np.ndarray, np.ndarray]  # the quad's corner slots on side A, on side B
    cell_a: IntArray
    cell_b: IntArray
    where: IntArray  # flat index into the (k, pair row, pair column) grid of this orientation
    pairs_per_layer: int
    pair_base: int  # id of this orientation's first pair

    @property
    def num(self) -> int:
        return self.source.size

    @property
    def k(self) -> IntArray:
        return self.where // self.pairs_per_layer

    @property
    def pair(self) -> IntArray:
        return self.pair_base + self.where % self.pairs_per_layer

    def nodes(self, table: IntArray, rows: slice | IntArray) -> IntArray:
        """(m, 4) node cycles of the quads ``rows``."""
        slots = np.where(self.use_a[rows, None], self.cycle[0], self.cycle[1])
        return table.reshape(-1)[slots * table[0].size + self.source[rows, None]]


@dataclass(frozen=True, eq=False)
class StructuredLateral:
    """Quadrilaterals of simple pairs and the cells of the other pairs."""

    quads: LateralQuads
    side_cells: SideCells  # for the general engine
    faulted: np.ndarray  # per pair: a layer where both sides differ


def structured_lateral(
    table: IntArray, cells: IntArray, along_j: bool, pair_base: int, layered: bool = False
) -> StructuredLateral:
    """One orientation of lateral faces: i-pairs (``along_j`` False) or j-pairs.

    ``table`` and ``cells`` are :class:`~gridlib.cornerpoint.corners.CornerNodes`'s
    padded node table and cell numbering. ``layered``: every pillar is layered
    (:attr:`~gridlib.cornerpoint.corners.CornerNodes.layered`), so every pair is simple and
    none faulted, and the tests that would find it are skipped: two kept cells of one layer
    on a pair have the same corners there, and a cell facing a removed one is alone (the
    cells above and below it on the other side end at its top and start at its bottom, node
    ids growing down the interfaces).
    """
    nxp = table.shape[3]
    if along_j:  # pair (i, j) lies between cells (i, j - 1) and (i, j)
        side_a, side_b, step = (
            (slice(None), slice(None, -1), slice(1, -1)),
            (slice(None), slice(1, None), slice(1, -1)),
            nxp,
        )
    else:  # pair (i, j) lies between cells (i - 1, j) and (i, j)
        side_a, side_b, step = (
            (slice(None), slice(1, -1), slice(None, -1)),
            (slice(None), slice(1, -1), slice(1, None)),
            1,
        )
    sa, sb = _J_PAIR if along_j else _I_PAIR
    ex_a, ex_b = (_has_face(table, slots, side) for slots, side in ((sa, side_a), (sb, side_b)))
    if layered:
        simple = np.ones(ex_a.shape[1:], dtype=bool)
        faulted = np.zeros(ex_a.shape[1:], dtype=bool)
    else:
        at1, at2, ab1, ab2 = (table[s][side_a] for s in sa)
        bt1, bt2, bb1, bb2 = (table[s][side_b] for s in sb)
        same_corners = (at1 == bt1) & (at2 == bt2) & (ab1 == bb1) & (ab2 == bb2)
        lone_a = _alone(ex_a, ex_b, (at1, at2, ab1, ab2), (bt1, bt2, bb1, bb2))
        lone_b = _alone(ex_b, ex_a, (bt1, bt2, bb1, bb2), (at1, at2, ab1, ab2))
        regular = (((ex_a == ex_b) & (~ex_a | same_corners)) | lone_a | lone_b).all(axis=0)
        one_side = ~ex_a.any(axis=0) | ~ex_b.any(axis=0)
        simple = regular | one_side
        faulted = (ex_a & ex_b & ~same_corners).any(axis=0)
    pairs_per_layer = ex_a[0].size
    position_a = np.arange(cells.size).reshape(cells.shape)[side_a]  # table position of the A cell

    selected = simple[None] & (ex_a | ex_b)
    where = np.flatnonzero(selected)
    use_a = ex_a.reshape(-1)[where]
    use_b = ex_b.reshape(-1)[where]
    pos_a = position_a[selected]
    cells_flat = cells.reshape(-1)
    quads = LateralQuads(
        np.where(use_a, pos_a, pos_a + step),
        use_a,
        _J_QUAD if along_j else _I_QUAD,
        # A cell pinched on this pair (no thickness on either pillar) is not a neighbour here.
        np.where(use_a, cells_flat[pos_a], -1),
        np.where(use_b, cells_flat[pos_a + step], -1),
        where,
        pairs_per_layer,
        pair_base,
    )

    if layered:
        no_cells = np.zeros(0, dtype=np.int64)
        return StructuredLateral(quads, SideCells(*[no_cells] * 8), faulted.ravel())

    # Cells on both sides of the other pairs, for the general engine.
    general = ~simple
    by_slot = table.reshape(8, -1)
    fields = []
    for side, ex, slots, shift in ((0, ex_a, sa, 0), (1, ex_b, sb, step)):
        on_side = general[None] & ex
        at = np.flatnonzero(on_side)
        pos = position_a[on_side] + shift
        t1, t2, b1, b2 = (by_slot[s][pos] for s in slots)
        fields.append(
            (
                pair_base + at % pairs_per_layer,
                np.full(at.size, side),
                cells_flat[pos],
                at // pairs_per_layer,
                t1,
                b1,
                t2,
                b2,
            )
        )
    side_cells = SideCells(*(np.concatenate([f[n] for f in fields]).astype(np.int64) for n in range(8)))
    return StructuredLateral(quads, side_cells, faulted.ravel())


def _has_face(table: IntArray, slots: tuple[int, ...], side: tuple[slice, ...]) -> np.ndarray:
    """(nz, pairs): the cells of one side are kept and not pinched on the pair (a thickness on
    one of its pillars at least)."""
    t1, t2, b1, b2 = (table[s][side] for s in slots)
    return (t1 >= 0) & ((t1 < b1) | (t2 < b2))


def _alone(ex: np.ndarray, ex_other: np.ndarray, corners: tuple, other: tuple) -> np.ndarray:
    """(nz, pairs): the cell of this side is a plain boundary quad on the pair: it has a face
    there (``ex``), the other side has no cell in its layer, and the other side's cells
    above end at or above its top and those below start at or below its bottom, on both
    pillars (node ids grow with depth along a pillar), so nothing of the other side
    overlaps or splits it. An inactive cell in an unfaulted deck makes such pairs, which
    then need no pillar-pair engine."""
    t1, t2, b1, b2 = corners
    ot1, ot2, ob1, ob2 = other
    kept_other = ot1 >= 0
    if not (ex & ~ex_other).any():
        return np.zeros_like(ex)
    alone = ex & ~kept_other
    nz = ex.shape[0]
    for top, bottom, o_top, o_bottom in ((t1, b1, ot1, ob1), (t2, b2, ot2, ob2)):
        above = np.maximum.accumulate(np.where(kept_other, o_bottom, -1), axis=0)
        alone[1:] &= above[:-1] <= top[1:]
        del above
        big = np.iinfo(o_top.dtype).max
        below = np.minimum.accumulate(np.where(kept_other, o_top, big)[::-1], axis=0)[::-1]
        alone[: nz - 1] &= below[1:] >= bottom[: nz - 1]
    return alone


@dataclass(frozen=True, eq=False)
class StructuredVertical:
    """Top and bottom faces, ordered by layer interface, then j, then i, then ``bottom`` first."""

    source: IntArray  # table position of the cell whose top (or bottom) the face is
    bottom: np.ndarray  # the face is the bottom of its source cell (else its top)
    upper: IntArray  # cell above the face (-1 = outside); the normal points from it downwards
    lower: IntArray
    skips_layers: np.ndarray  # an interior face joining cells more than one layer apart
    pinch_pairs: IntArray  # (n, 2) cell ids joined across a thin gap (no face)
    padded_dims: tuple[int, int]  # (ny + 2, nx + 2) of the table layout

    @property
    def num(self) -> int:
        return self.source.size

    def nodes(self, table: IntArray, rows: slice | IntArray) -> IntArray:
        """(m, 4) node cycles of the faces ``rows`` (normal +z)."""
        slots = np.where(self.bottom[rows, None], _BOTTOM, _TOP)
        return table.reshape(-1)[slots * table[0].size + self.source[rows, None]]

    def columns(self) -> IntArray:
        """Column (i + nx j) of every face."""
        nyp, nxp = self.padded_dims
        row, col = np.divmod(self.source % (nyp * nxp), nxp)
        return (row - 1) * (nxp - 2) + col - 1


def structured_vertical(
    table: IntArray,
    cells: IntArray,
    node_z: np.ndarray,
    pinch_threshold: float | None,
    source: str,
) -> StructuredVertical:
    """Top and bottom faces of the kept cells (``table``, ``cells`` as :func:`structured_lateral`)."""
    _, nz, nyp, nxp = table.shape
    ny, nx = nyp - 2, nxp - 2
    layer = ny * nx
    kept = cells[:, 1:-1, 1:-1] >= 0
    index = np.arange(nz * layer).reshape(nz, ny, nx)  # (k, j, i) index of every cell
    position = np.arange(cells.size).reshape(cells.shape)[:, 1:-1, 1:-1].ravel()  # its table position
    # The last kept cell above each cell of a column (indices grow with k along a column).
    last_kept = np.maximum.accumulate(np.where(kept, index, -1), axis=0)
    prev = np.full(nz * layer, -1)
    prev[layer:] = last_kept[:-1].ravel()

    # Consecutive kept cells of every column: ``rows`` and the cell above it, ``up``.
    rows = np.flatnonzero(kept.ravel() & (prev >= 0))
    up = prev[rows]
    pos_k, pos_pk = position[rows], position[up]
    by_slot = table.reshape(8, -1)
    above = [by_slot[s][pos_pk] for s in _BOTTOM]
    below = [by_slot[s][pos_k] for s in _TOP]
    overlap = np.logical_or.reduce([b < a for a, b in zip(above, below, strict=True)])
    if overlap.any():  # node ids grow with depth along a pillar
        bad = np.flatnonzero(overlap)[0]
        (kb, jb, ib), kt = np.unravel_index(up[bad], (nz, ny, nx)), rows[bad] // layer
        raise InputError(
            f"{source}: ZCORN: cell ({ib + 1}, {jb + 1}, {kb + 1}) reaches below "
            "the top of cell "
            f"({ib + 1}, {jb + 1}, {kt + 1}) in the same column (overlapping layers)"
        )
    touch = np.logical_and.reduce([a == b for a, b in zip(above, below, strict=True)])
    cells_flat = cells.reshape(-1)
    joined_to = np.full(nz * layer, -1)  # the kept cell above that a cell touches
    joined_to[rows[touch]] = cells_flat[pos_pk[touch]]
    far_above = np.zeros(nz * layer, dtype=bool)  # ... and lies more than one layer up
    far_above[rows[touch]] = rows[touch] - up[touch] > layer
    touched_below = np.zeros(nz * layer, dtype=bool)  # cell touches the kept cell below it
    touched_below[up[touch]] = True

    # Faces at (interface L, j, i, 0): bottom of cell L - 1 unless it touches the cell
    # below; (L, j, i, 1): top of cell L, shared with the cell above if they touch.
    present = np.zeros((nz + 1, layer, 2), dtype=bool)
    present[1:, :, 0] = kept.reshape(nz, layer) & ~touched_below.reshape(nz, layer)
    present[:-1, :, 1] = kept.reshape(nz, layer)
    at = np.flatnonzero(present)
    bottom = (at & 1) == 0
    cell = (at >> 1) - np.where(bottom, layer, 0)  # index of the face's own cell
    own = position[cell]
    ids = cells_flat[own]
    upper = np.where(bottom, ids, joined_to[cell])
    lower = np.where(bottom, -1, ids)
    skips = ~bottom & far_above[cell]

    pinch_pairs = np.zeros((0, 2), dtype=np.int64)
    if pinch_threshold is not None:
        gap_rows = np.flatnonzero(~touch)
        gap = np.maximum.reduce(
            [node_z[b[gap_rows]] - node_z[a[gap_rows]] for a, b in zip(above, below, strict=True)]
        )
        ok = gap_rows[(gap >= 0) & (gap <= pinch_threshold)]
        pinch_pairs = np.column_stack([cells_flat[pos_pk[ok]], cells_flat[pos_k[ok]]]).astype(np.int64)
    return StructuredVertical(own, bottom, upper, lower, skips, pinch_pairs, (nyp, nxp))
