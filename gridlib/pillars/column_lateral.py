"""The lateral faces of the column engine: one quadrilateral per cell on the pillar pairs whose two
sides agree (no fault), the others subdivided by :func:`~gridlib.pillars.lateral.general_pieces`
where fault throw makes the corners mismatch."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..grid import Grid, IntArray
from .column_inputs import ColumnCorners
from .column_nodes import PillarNodes
from .lateral import LateralFaces, SideCells, general_pieces

_BLOCK = 1 << 14  # pairs per block when quads are written


@dataclass(frozen=True, eq=False)
class PillarPairs:
    """Every areal edge as a pillar pair: p1, p2, the columns on sides A (left) and B, and the
    corner of each side's column on p1 and on p2 (-1 where a side has no column)."""

    p1: IntArray
    p2: IntArray
    col: tuple[IntArray, IntArray]
    q1: tuple[IntArray, IntArray]
    q2: tuple[IntArray, IntArray]
    side_tag: np.ndarray | None  # (n_edges, 2) areal half-face tags of sides A and B
    hf_edge: IntArray  # the edge of every areal half-face (``cells.faces``)
    hf_side: IntArray  # and its side (0 = A)

    @classmethod
    def of(cls, areal: Grid, corners: ColumnCorners, reverse: bool) -> PillarPairs:
        e = areal.faces.nodes.reshape(-1, 2)
        p1, p2 = (e[:, 1], e[:, 0]) if reverse else (e[:, 0], e[:, 1])
        nb = areal.faces.neighbors
        nf2 = areal.num_faces
        hc = corners.owner[corners.hf_first]  # the cell of every areal half-face
        cf = areal.cells.faces
        side = np.where(nb[cf, 0] == hc, 0, 1)
        # Walking with the cell on its left, a half-face runs n0 -> n1 on side A, n1 -> n0 on side B.
        at_p1 = np.where((side == 0) != reverse, corners.hf_first, corners.hf_second)
        at_p2 = np.where((side == 0) != reverse, corners.hf_second, corners.hf_first)
        q1 = np.full((2, nf2), -1, dtype=np.int64)
        q2 = np.full((2, nf2), -1, dtype=np.int64)
        q1[side, cf], q2[side, cf] = at_p1, at_p2
        side_tag = None
        if areal.cells.face_tag is not None:
            side_tag = np.zeros((nf2, 2), dtype=np.int8)
            side_tag[cf, side] = areal.cells.face_tag
        return cls(p1, p2, (nb[:, 0], nb[:, 1]), (q1[0], q1[1]), (q2[0], q2[1]), side_tag, cf, side)

    @property
    def num(self) -> int:
        return self.p1.size


@dataclass(frozen=True, eq=False)
class ColumnLateral:
    """Lateral faces: quads (t1, t2, b2, b1) of the simple pairs (by layer, then pair), then the
    general pieces. A quad's nodes are those of one side's corners ``q1``, ``q2`` of its pair
    (side A unless it has no cell there) at the layer's two levels: they are gathered from the
    corners' nodes and written straight into the grid's arrays, a layer at a time."""

    q1: IntArray  # (n_pairs,): the corner on p1 of the side the quads take their nodes from
    q2: IntArray  # ... on p2
    col: tuple[IntArray, IntArray]  # (n_pairs,): the column on side A, B (-1 = none)
    cell_ext: IntArray  # (n_layers, n_areal_cells + 1): cell ids, -1 in the last column (none)
    ex: tuple[np.ndarray, np.ndarray]  # (n_layers, n_pairs): a kept cell, not pinched there, on A, B
    sel: np.ndarray  # (n_layers, n_pairs): a quad there
    thin: np.ndarray | None  # (n_layers, n_pairs): the quad is collapsed on a pillar (None: none is)
    every: bool  # a quad at every (layer, pair)
    all_sides: bool  # ... with a cell on every side that has a column
    general: LateralFaces
    general_order: IntArray  # the pieces in face order
    general_cells: IntArray  # cells on the subdivided pairs
    faulted: np.ndarray  # per pair: both sides have cells whose corners differ

    @property
    def num_general(self) -> int:
        return self.general_order.size

    @property
    def pinched(self) -> bool:
        """Some quads are triangles (collapsed on a pillar)."""
        return self.thin is not None

    @property
    def num_quads(self) -> int:
        return self.sel.size if self.every else int(np.count_nonzero(self.sel))

    def quad_has(self, side: int) -> np.ndarray:
        """(n_layers, n_pairs): a quad with a cell on ``side`` (0 = A)."""
        return self.ex[side] & self.sel

    def _layers(self):
        """(layer, its pairs with a quad (None: all), the range of its quads)."""
        start = 0
        for k in range(self.sel.shape[0]):
            pairs = None if self.every else np.flatnonzero(self.sel[k])
            stop = start + (self.sel.shape[1] if pairs is None else pairs.size)
            yield k, pairs, slice(start, stop)
            start = stop

    def quad_values(self, values: np.ndarray, out: np.ndarray) -> None:
        """Per-pair ``values`` (n_pairs, ...) into ``out`` (n_quads, ...), the row of every quad."""
        for _, pairs, rows in self._layers():
            out[rows] = values if pairs is None else values[pairs]

    def quad_counts(self) -> IntArray | None:
        """Node count of every quad (None: all 4)."""
        if self.thin is None:
            return None
        return 4 - (self.thin.reshape(-1) if self.every else self.thin[self.sel]).astype(np.int64)

    def write_quads(self, node_of: IntArray, out: IntArray) -> None:
        """The quads' node cycles into ``out`` (flat, sized by :meth:`quad_counts`)."""
        written = 0
        for k, pairs, rows in self._layers():
            for part in _blocks(rows.stop - rows.start):  # quads of the layer, a cache-sized block at a time
                sub = part if pairs is None else pairs[part]
                q1, q2 = self.q1[sub], self.q2[sub]
                top, bottom = node_of[k], node_of[k + 1]
                quad = np.stack([top[q1], top[q2], bottom[q2], bottom[q1]], axis=1)
                if self.thin is not None:
                    quad = quad[quad != quad[:, [1, 2, 3, 0]]]
                out[written : written + quad.size] = quad.reshape(-1)
                written += quad.size

    def write_cells(self, out: IntArray) -> None:
        """The quads' neighbours (cells on sides A and B) into ``out`` (n_quads, 2)."""
        for k, pairs, rows in self._layers():
            for s in (0, 1):
                c = self.cell_ext[k][self.col[s]]
                c[~self.ex[s][k]] = -1
                out[rows, s] = c if pairs is None else c[pairs]


def _blocks(n: int):
    """Slices of at most ``_BLOCK`` of range(n)."""
    return (slice(start, min(start + _BLOCK, n)) for start in range(0, n, _BLOCK))


def lateral_faces(
    pairs: PillarPairs, node_of: IntArray, kept: np.ndarray, cell_id: IntArray, pts: PillarNodes, node_xyz
) -> ColumnLateral:
    """Quads of the simple pairs, general pieces of the others (see ``structured_lateral``).

    ``node_xyz[pm]`` gives the coordinates of points by pillar-major id (see :class:`PillarNodes`).
    """
    nl = kept.shape[0]
    kept_ext = np.concatenate([kept, np.zeros((nl, 1), dtype=bool)], axis=1)  # column -1: no cell
    cell_ext = np.concatenate([cell_id, np.full((nl, 1), -1)], axis=1)
    ex, eq, thin = _compare_sides(pairs, node_of, kept_ext)
    same = eq[1:] & eq[:-1]
    both = ex[0] & ex[1]
    regular = ~((ex[0] != ex[1]) | (both & ~same)).any(axis=0)
    has_a, has_b = ex[0].any(axis=0), ex[1].any(axis=0)
    simple = regular | ~has_a | ~has_b
    faulted = (both & ~same).any(axis=0)

    # One quadrilateral (t1, t2, b2, b1) per cell of a simple pair; a triangle if collapsed on a pillar.
    # On a simple pair both sides agree wherever both have a cell: take side A unless it has none.
    q1 = np.where(has_a, pairs.q1[0], pairs.q1[1])
    q2 = np.where(has_a, pairs.q2[0], pairs.q2[1])
    sel = ex[0] | ex[1]
    sel &= simple
    every = bool(sel.all())
    thin = np.where(has_a, thin[0], thin[1])
    thin &= sel
    pinched = bool(thin.any())

    general, general_cells = _general_pieces(pairs, node_of, ex, simple, cell_ext, pts, node_xyz)
    k_ref = np.where(general.cell_a >= 0, general.k_a, general.k_b)
    order = np.lexsort((general.k_b, general.pair, k_ref))
    all_sides = every and all(bool((ex[s] | (pairs.col[s] < 0)[None, :]).all()) for s in (0, 1))
    return ColumnLateral(
        q1,
        q2,
        pairs.col,
        cell_ext,
        tuple(ex),
        sel,
        thin if pinched else None,
        every,
        all_sides,
        general,
        order,
        general_cells,
        faulted,
    )


def _compare_sides(pairs: PillarPairs, node_of: IntArray, kept_ext: np.ndarray):
    """Per (layer, pair) and side, the kept cell not pinched there (``ex``) and the cell collapsed
    on a pillar (``thin``); per (level, pair), both sides' corners on the same nodes (``eq``,
    junk where a side has no column). A level at a time, gathering the corners' nodes."""
    n_levels, n_pairs = node_of.shape[0], pairs.num
    ex = [np.empty((n_levels - 1, n_pairs), dtype=bool) for _ in (0, 1)]
    thin = [np.empty((n_levels - 1, n_pairs), dtype=bool) for _ in (0, 1)]
    eq = np.empty((n_levels, n_pairs), dtype=bool)
    corners = (pairs.q1[0], pairs.q2[0], pairs.q1[1], pairs.q2[1])  # -1 (no column): junk, masked
    above = None
    for level in range(n_levels):
        nodes = [node_of[level][q] for q in corners]
        np.equal(nodes[0], nodes[2], out=eq[level])
        eq[level] &= nodes[1] == nodes[3]
        if above is not None:
            k = level - 1
            for s in (0, 1):
                on1, on2 = nodes[2 * s], nodes[2 * s + 1]
                np.greater(on1, above[2 * s], out=ex[s][k])
                ex[s][k] |= on2 > above[2 * s + 1]
                ex[s][k] &= kept_ext[k][pairs.col[s]]
                np.equal(on1, above[2 * s], out=thin[s][k])
                thin[s][k] |= on2 == above[2 * s + 1]
        above = nodes
    return ex, eq, thin


def _general_pieces(pairs, node_of, ex, simple, cell_ext, pts: PillarNodes, node_xyz):
    """The pieces of the pairs that are not simple, through the general partition-and-overlap engine
    (on ranks), numbered locally so that its per-pair work covers them only; and the cells on them."""
    n_pairs = pairs.num
    gp = np.flatnonzero(~simple)
    local = np.full(n_pairs, -1, dtype=np.int64)
    local[gp] = np.arange(gp.size)
    fields = []
    for s in (0, 1):
        gk, ge = np.nonzero(ex[s][:, gp])
        ge = gp[ge]
        q1, q2 = pairs.q1[s][ge], pairs.q2[s][ge]
        fields.append(
            (
                local[ge],
                np.full(ge.size, s),
                cell_ext[gk, pairs.col[s][ge]],
                gk,
                pts.ids.rank(node_of[gk, q1]),
                pts.ids.rank(node_of[gk + 1, q1]),
                pts.ids.rank(node_of[gk, q2]),
                pts.ids.rank(node_of[gk + 1, q2]),
            )
        )
    side = SideCells(*(np.concatenate([f[i] for f in fields]).astype(np.int64) for i in range(8)))
    if gp.size == 0:
        return _no_pieces(), side.cell
    # The general engine numbers points pillar by pillar (offset + rank): map its nodes to ours.
    general = general_pieces(
        side, gp.size, pairs.p1[gp], pairs.p2[gp], np.zeros(gp.size, bool), _PillarMajor(pts), node_xyz
    )
    return replace(
        general,
        pair=gp[general.pair],
        nodes=_to_ids(pts, general.nodes),
        crossing_lines=_to_ids(pts, general.crossing_lines),
    ), side.cell


class _PillarMajor:
    """What the general engine needs of the points: their pillar-major offsets and number."""

    def __init__(self, pts: PillarNodes) -> None:
        self.offset, self.num_nodes = pts.offset, pts.num_nodes


def _to_ids(pts: PillarNodes, pm: IntArray) -> IntArray:
    """Our ids of the general engine's nodes: points by pillar-major id, crossing nodes (numbered
    from ``num_nodes``) kept."""
    out = pm.copy()
    point = np.flatnonzero(pm.reshape(-1) < pts.num_nodes)
    out.reshape(-1)[point] = pts.pm_to_ids(pm.reshape(-1)[point])
    return out


def _no_pieces() -> LateralFaces:
    empty = np.zeros(0, dtype=np.int64)
    return LateralFaces(
        np.zeros(1, np.int64),
        empty,
        empty,
        empty,
        empty,
        empty,
        empty,
        np.zeros(0, bool),
        np.zeros((0, 3)),
        np.zeros((0, 2, 2), np.int64),
    )
