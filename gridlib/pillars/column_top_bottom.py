"""The top and bottom faces of the column engine: every column walked through its kept cells, and
where the crossing nodes of subdivided lateral faces go into their edges."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..connectivity import offsets, ragged_arange
from ..grid import IntArray
from .conformal import edge_insertions
from .lateral import LateralFaces


@dataclass(frozen=True, eq=False)
class TopBottomFaces:
    """Top and bottom faces by (interface, column, bottom before top); normals +z (down)."""

    pos: IntArray
    upper: IntArray  # cell above the face (-1 = outside)
    lower: IntArray
    skips: np.ndarray  # an interior face joining cells more than one layer apart
    top_face: IntArray  # (n_layers, n_areal_cells): face of every kept cell's top
    bottom_face: IntArray  # and of its bottom


def top_bottom_faces(
    node_of: IntArray, kept: np.ndarray, cell_id: IntArray, pos2: IntArray
) -> tuple[TopBottomFaces, IntArray]:
    """Walk every column through its kept cells (as ``structured_vertical`` on a (k, column) layout);
    the faces and their nodes (flat, a view of ``node_of`` when every cell is kept).

    Consecutive kept cells touch (share one face) when the lower one's top nodes
    are the upper one's bottom nodes: always in adjacent layers (a column's
    layers share their interface), across removed cells only if those are
    collapsed (zero thickness everywhere).
    """
    nl, nc2 = kept.shape
    n_corners = node_of.shape[1]
    ring_len = np.diff(pos2)
    if kept.all():  # every cell kept: interface L of column c is face L * nc2 + c (make_layered_grid's)
        cells = np.arange(nl * nc2)
        edge = np.full(nc2, -1)
        faces = cells.reshape(nl, nc2)
        ver = TopBottomFaces(
            offsets(np.tile(ring_len, nl + 1)),
            np.concatenate([edge, cells]),
            np.concatenate([cells, edge]),
            np.zeros((nl + 1) * nc2, dtype=bool),
            faces,
            faces + nc2,
        )
        return ver, node_of.reshape(-1)
    index = np.arange(nl * nc2).reshape(nl, nc2)
    last_kept = np.maximum.accumulate(np.where(kept, index, -1), axis=0)
    prev = np.full(nl * nc2, -1)
    prev[nc2:] = last_kept[:-1].ravel()
    rows = np.flatnonzero(kept.ravel() & (prev >= 0))  # kept cells with a kept cell above
    up = prev[rows]
    touch = np.ones(rows.size, dtype=bool)
    far = np.flatnonzero(up < rows - nc2)  # removed cells between: compare the two interfaces
    if far.size:
        col = rows[far] % nc2
        cnt = ring_len[col]
        q = ragged_arange(pos2[col], cnt)
        who = np.repeat(np.arange(far.size), cnt)
        lev_up = up[far] // nc2 + 1
        lev_lo = rows[far] // nc2
        differ = node_of[lev_up[who], q] != node_of[lev_lo[who], q]
        touch[far] = np.bincount(who, differ, minlength=far.size) == 0
    cells_flat = cell_id.ravel()
    joined_to = np.full(nl * nc2, -1)
    joined_to[rows[touch]] = cells_flat[up[touch]]
    far_above = np.zeros(nl * nc2, dtype=bool)
    far_above[rows[touch]] = up[touch] < rows[touch] - nc2
    touched_below = np.zeros(nl * nc2, dtype=bool)
    touched_below[up[touch]] = True

    present = np.zeros((nl + 1, nc2, 2), dtype=bool)
    present[1:, :, 0] = kept & ~touched_below.reshape(nl, nc2)  # bottom of the cell above the interface
    present[:-1, :, 1] = kept  # top of the cell below it
    at = np.flatnonzero(present)
    bottom = (at & 1) == 0
    slot = at >> 1  # interface * nc2 + column
    cell = slot - np.where(bottom, nc2, 0)
    ids = cells_flat[cell]
    level, column = np.divmod(slot, nc2)
    counts = ring_len[column]
    if at.size == (nl + 1) * nc2 and not bottom[: nl * nc2].any():  # every interface once: no gaps
        nodes = node_of.reshape(-1)
    else:
        nodes = node_of.reshape(-1)[ragged_arange(level * n_corners + pos2[column], counts)]
    # Every kept cell's top and bottom face (that of the cell below it where they touch).
    face_at = np.full(present.size, -1, dtype=np.int64)
    face_at[at] = np.arange(at.size)
    face_at = face_at.reshape(nl + 1, nc2, 2)
    top_face = face_at[:-1, :, 1]
    bottom_face = face_at[1:, :, 0].copy()
    bottom_face.reshape(-1)[up[touch]] = top_face.reshape(-1)[rows[touch]]
    ver = TopBottomFaces(
        offsets(counts),
        np.where(bottom, ids, joined_to[cell]),
        np.where(bottom, -1, ids),
        ~bottom & far_above[cell],
        top_face,
        bottom_face,
    )
    return ver, nodes


def crossings_in_faces(h_pos, h_nodes, touched, general: LateralFaces, first_crossing: int, coords):
    """Where the crossing nodes go into the top/bottom faces ``touched`` (the others have none):
    (positions in ``h_nodes`` after which they are inserted, sorted; the nodes inserted)."""
    counts = np.diff(h_pos)[touched]
    sub_pos = offsets(counts)
    slots, nodes = edge_insertions(
        sub_pos,
        h_nodes[ragged_arange(h_pos[:-1][touched], counts)],
        general.crossing_lines,
        first_crossing + np.arange(general.crossing_coords.shape[0]),
        coords,
    )
    face = np.searchsorted(sub_pos, slots, "right") - 1
    return h_pos[touched[face]] + (slots - sub_pos[face]), nodes
