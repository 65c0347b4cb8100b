"""The assembly of the column engine's grid: every cell's half-faces, all faces in grid order with
their tags and NNC kinds, the automatic fault tags, and faces of zero area."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph

from ..connectivity import drop_repeated_nodes, offsets, ragged_arange, renumbering
from ..grid import B, FloatArray, IntArray, T
from .column_lateral import ColumnLateral, PillarPairs
from .column_top_bottom import TopBottomFaces
from .conformal import insert_after
from .nnc import FAULT, NNC, PINCH


def construction_half_faces(
    top_face, bottom_face, lat, corners, pairs, kept, cell_id, n_h: int, n_q: int
) -> tuple[IntArray, IntArray]:
    """Every cell's half-faces ``2 f + side`` in increasing face order (what ``cell_half_faces``
    gives from ``neighbors``), straight from the construction, without sorting all half-faces.

    A kept cell's faces are its top and its bottom (top/bottom faces come first, by
    interface), its quads in increasing areal edge order (quads are numbered by layer, then
    edge), then its general pieces. Built a layer at a time (the cells of a layer are
    consecutive), so that the temporaries stay the size of the areal grid.
    """
    nl = kept.shape[0]
    pos2 = corners.pos
    hc = corners.owner[corners.hf_first]
    # The areal half-faces by (cell, edge): np.lexsort((hf_edge, hc)) as one stable sort of a combined
    # key, quick on the half-faces already grouped by cell.
    order = np.argsort(hc * max(pairs.num, 1) + pairs.hf_edge, kind="stable")
    edge, side, hc = pairs.hf_edge[order], pairs.hf_side[order], hc[order]
    n_pairs = pairs.num
    local = np.arange(edge.size) - pos2[hc]  # position among its cell's half-faces
    hs = 2 * edge + side
    if lat.every and lat.all_sides and lat.general_order.size == 0 and kept.all():
        # Every cell has its top, bottom and one quad per areal edge: the same pattern in every layer.
        ring_len = np.diff(pos2)
        first = offsets(2 + ring_len)
        half = np.empty(nl * int(first[-1]), dtype=np.int64)
        rows = half.reshape(nl, -1)
        rows[:, first[:-1]] = 2 * top_face + 1  # the cell is the lower neighbour of its top face
        rows[:, first[:-1] + 1] = 2 * bottom_face
        dst = first[:-1][hc] + 2 + local
        for k in range(nl):
            rows[k, dst] = hs + 2 * (n_h + k * n_pairs)
        return offsets(np.tile(2 + ring_len, nl)), half

    quad_has = np.concatenate([lat.quad_has(0), lat.quad_has(1)], axis=1)  # (nl, 2 n_pairs): A, then B
    slot = side * n_pairs + edge
    layer_first = n_h + offsets(np.count_nonzero(lat.sel, axis=1))  # the first quad of every layer
    present_all = quad_has[:, slot]  # (nl, n half-faces): a quad on the half-face
    if edge.size:
        nq = np.add.reduceat(present_all, pos2[:-1], axis=1, dtype=np.int64)
    else:
        nq = np.zeros(kept.shape, dtype=np.int64)

    g_face = n_h + n_q + np.arange(lat.general_order.size)
    g_cell = np.concatenate([lat.general.cell_a[lat.general_order], lat.general.cell_b[lat.general_order]])
    g_half = np.concatenate([2 * g_face, 2 * g_face + 1])
    ok = g_cell >= 0
    g_cell, g_half = g_cell[ok], g_half[ok]
    o = np.lexsort((g_half, g_cell))
    g_cell, g_half = g_cell[o], g_half[o]
    n_cells = int(np.count_nonzero(kept))
    ng = np.bincount(g_cell, minlength=n_cells)

    nq_kept = nq[kept]
    face_pos = offsets(2 + nq_kept + ng)
    start = face_pos[:-1]
    half = np.empty(int(face_pos[-1]), dtype=np.int64)
    half[start] = 2 * top_face[kept] + 1  # the cell is the lower neighbour of its top face
    half[start + 1] = 2 * bottom_face[kept]
    ring_len = np.diff(pos2)
    for k in range(nl):
        present = present_all[k]
        if not present.any():
            continue
        ids = cell_id[k]
        first = np.where(ids >= 0, start[ids] + 2, 0)
        if lat.every:
            qhalf = 2 * (n_h + k * n_pairs + edge) + side
        else:
            quad_id = np.cumsum(lat.sel[k])
            quad_id += layer_first[k] - 1
            qhalf = 2 * quad_id[edge] + side
        if (nq[k] == ring_len).all():  # a quad on every edge of every column: its position is its rank
            half[first[hc] + local] = qhalf
            continue
        # The rank of a present half-face among its column's (the half-faces are grouped by column,
        # column c at pos2[c]:pos2[c + 1]): the present ones before it, less those before its column.
        before = np.zeros(present.size + 1, dtype=np.int64)
        np.cumsum(present, out=before[1:])  # before[i]: the present half-faces before half-face i
        first -= before[pos2[:-1]]
        dst = first[hc]
        dst += before[:-1]
        half[dst[present]] = qhalf[present]
    g_start = offsets(ng)[:-1]
    g_rank = np.arange(g_cell.size) - g_start[g_cell]
    half[start[g_cell] + 2 + nq_kept[g_cell] + g_rank] = g_half
    return face_pos, half


@dataclass(frozen=True, eq=False)
class FaceList:
    """All faces in grid order, with what the grid, its tags and its NNCs need."""

    pos: IntArray
    nodes: IntArray
    neighbors: IntArray
    tag: np.ndarray  # int32 fault id
    half_tags: np.ndarray | None  # (nf, 2) int8 half-face tags of both sides
    nnc_kind: np.ndarray  # FAULT, PINCH or -1
    pair: IntArray | None  # areal edge of lateral faces, -1 for top/bottom faces (None: not needed)
    mismatch: np.ndarray  # a lateral piece whose sides' corners differ

    @property
    def num(self) -> int:
        return self.pos.size - 1

    @classmethod
    def join(
        cls, ver: TopBottomFaces, h_nodes, insert, lat: ColumnLateral, node_of, etag, pairs: PillarPairs
    ) -> FaceList:
        """Top/bottom faces (``ver``, nodes ``h_nodes`` with the crossing nodes ``insert`` = (slots,
        nodes) of :func:`insert_after`, or None), then the quads, then the general pieces (arrays
        filled once, in place)."""
        g, o = lat.general, lat.general_order
        g_counts = np.diff(g.node_pos)[o]
        g_pos, g_nodes = drop_repeated_nodes(
            offsets(g_counts), g.nodes[ragged_arange(g.node_pos[:-1][o], g_counts)]
        )
        n_h, n_q, n_g = ver.upper.size, lat.num_quads, o.size
        nf = n_h + n_q + n_g
        h, q = slice(0, n_h), slice(n_h, n_h + n_q)
        gs = slice(n_h + n_q, nf)
        pos = np.empty(nf + 1, dtype=np.int64)
        pos[: n_h + 1] = ver.pos
        if insert is not None:
            pos[: n_h + 1] += np.searchsorted(insert[0], ver.pos)  # the insertions before every face
        h_end = int(pos[n_h])
        q_counts = lat.quad_counts()
        if q_counts is None:
            pos[n_h + 1 : n_h + n_q + 1] = np.arange(h_end + 4, h_end + 4 * n_q + 1, 4)
        else:
            np.cumsum(q_counts, out=pos[n_h + 1 : n_h + n_q + 1])
            pos[n_h + 1 : n_h + n_q + 1] += h_end
        pos[n_h + n_q + 1 :] = g_pos[1:] + pos[n_h + n_q]
        nodes = np.empty(int(pos[-1]), dtype=np.int64)
        if insert is None:
            nodes[:h_end] = h_nodes
        else:
            nodes[:h_end] = insert_after(h_nodes, *insert)
        lat.write_quads(node_of, nodes[h_end : pos[n_h + n_q]])
        nodes[pos[n_h + n_q] :] = g_nodes
        neighbors = np.empty((nf, 2), dtype=np.int64)
        neighbors[h, 0], neighbors[h, 1] = ver.upper, ver.lower
        lat.write_cells(neighbors[q])
        neighbors[gs, 0], neighbors[gs, 1] = g.cell_a[o], g.cell_b[o]
        pair = None  # the areal edge of every face (-1: top/bottom), only for the automatic fault tags
        if (lat.faulted & (etag == 0)).any():
            pair = np.empty(nf, dtype=np.int64)
            pair[h], pair[gs] = -1, g.pair[o]
            lat.quad_values(np.arange(pairs.num), pair[q])
        tag = np.zeros(nf, dtype=np.int32)
        if etag.any():
            lat.quad_values(etag, tag[q])
            tag[gs] = etag[g.pair[o]]
        half_tags = None
        if pairs.side_tag is not None:
            half_tags = np.empty((nf, 2), dtype=np.int8)
            half_tags[h] = (B, T)  # the upper cell's bottom, the lower cell's top
            lat.quad_values(pairs.side_tag, half_tags[q])
            half_tags[gs] = pairs.side_tag[g.pair[o]]
        kind = np.full(nf, -1, dtype=np.int8)
        kind[h][ver.skips] = PINCH
        kind[gs][(neighbors[gs] >= 0).all(axis=1) & (g.k_a[o] != g.k_b[o])] = FAULT
        mismatch = np.zeros(nf, dtype=bool)
        mismatch[gs] = g.mismatch[o]
        return cls(pos, nodes, neighbors, tag, half_tags, kind, pair, mismatch)

    def subset(self, keep: np.ndarray) -> FaceList:
        counts = np.diff(self.pos)[keep]
        nodes = self.nodes[ragged_arange(self.pos[:-1][keep], counts)]
        return FaceList(
            offsets(counts),
            nodes,
            self.neighbors[keep],
            self.tag[keep],
            None if self.half_tags is None else self.half_tags[keep],
            self.nnc_kind[keep],
            None if self.pair is None else self.pair[keep],
            self.mismatch[keep],
        )

    def with_neighbors(self, neighbors: IntArray) -> FaceList:
        return FaceList(
            self.pos, self.nodes, neighbors, self.tag, self.half_tags, self.nnc_kind, self.pair, self.mismatch
        )

    def drop_unused_nodes(self, coords: FloatArray) -> tuple[FaceList, FloatArray]:
        """The faces with the nodes no face uses dropped, and the remaining coordinates."""
        used = np.zeros(coords.shape[0], dtype=bool)
        used[self.nodes] = True
        if used.all():
            return self, coords
        nodes = renumbering(used)[self.nodes]
        face_list = FaceList(
            self.pos, nodes, self.neighbors, self.tag, self.half_tags, self.nnc_kind, self.pair, self.mismatch
        )
        return face_list, coords[used]

    def nnc(self, index_map: IntArray) -> NNC:
        face = np.flatnonzero(self.nnc_kind >= 0)
        face = face[(self.neighbors[face] >= 0).all(axis=1)]
        cells = self.neighbors[face]
        return NNC(cells, index_map[cells], self.nnc_kind[face], face)


def name_unnamed_faults(
    faces: FaceList, names: list[str], lat: ColumnLateral, pairs: PillarPairs, etag
) -> tuple[str, ...]:
    """Tag the faults no edge tag names (faulted pairs, one id per connected trace), in place."""
    fp = np.flatnonzero(lat.faulted & (etag == 0))
    if fp.size == 0:
        return tuple(names)
    lateral = faces.pair >= 0
    pair = np.where(lateral, faces.pair, 0)
    void = (faces.neighbors < 0).any(axis=1)
    on = lateral & lat.faulted[pair] & (etag[pair] == 0) & (faces.mismatch | void)
    n_pil = int(max(pairs.p1.max(), pairs.p2.max())) + 1
    graph = sparse.coo_matrix((np.ones(fp.size), (pairs.p1[fp], pairs.p2[fp])), shape=(n_pil, n_pil))
    _, label = csgraph.connected_components(graph, directed=False)
    traces, trace_id = np.unique(label[pairs.p1[fp]], return_inverse=True)
    id_of_pair = np.zeros(pairs.num, dtype=np.int32)
    id_of_pair[fp] = len(names) + 1 + trace_id.reshape(-1)
    faces.tag[on] = id_of_pair[pair[on]]
    used = np.unique(faces.tag[on])
    auto = [f"fault_{t}" for t in range(len(names) + 1, len(names) + 1 + traces.size)]
    if used.size < traces.size:  # traces whose faces were all removed: renumber the others
        new = np.zeros(len(names) + 1 + traces.size, dtype=np.int32)
        new[: len(names) + 1] = np.arange(len(names) + 1)
        new[used] = len(names) + 1 + np.arange(used.size)
        faces.tag[on] = new[faces.tag[on]]
        auto = auto[: used.size]
    return (*names, *auto)


def zero_area_faces(coords: FloatArray, pos: IntArray, nodes: IntArray, faces: IntArray) -> np.ndarray:
    """Faces (of ``faces``) whose vector area vanishes (Newell's formula, relative to the extent)."""
    counts = pos[faces + 1] - pos[faces]
    p_local = offsets(counts)
    owner = np.repeat(np.arange(faces.size), counts)
    nxt = np.arange(1, p_local[-1] + 1)
    nxt[p_local[1:] - 1] = p_local[:-1]
    xyz = coords[nodes[ragged_arange(pos[faces], counts)]]  # the faces' nodes
    p = xyz - np.repeat(xyz[p_local[:-1]], counts, axis=0)  # from the face's first node
    q = p[nxt]
    # the cross product by components: np.cross takes 12 times as long on such long arrays
    cr = (
        p[:, 1] * q[:, 2] - p[:, 2] * q[:, 1],
        p[:, 2] * q[:, 0] - p[:, 0] * q[:, 2],
        p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0],
    )
    area = np.stack([np.bincount(owner, cr[d], faces.size) for d in range(3)], axis=1)
    extent = max((float(np.ptp(xyz[:, d])) for d in range(3)), default=1.0) if xyz.size else 1.0
    return 0.5 * np.linalg.norm(area, axis=1) <= 1e-14 * extent**2
