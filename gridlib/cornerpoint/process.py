"""``process_grdecl``: a corner-point deck to an unstructured grid (the pillar engine's
Cartesian front end; ALGORITHMS.md §1).

Steps, all vectorised over cells, corners and pillar pairs:

1. inactive cells are masked before anything else: their corners (often junk:
   NaN, -1e20) are never read; active corners must be finite;
2. z-up decks (depths decreasing with k) are negated so z is depth; left-handed
   decks (k x j x i frame mirrored in plan view) get every face reversed at the
   end, so volumes are positive and normals point outwards either way;
3. the distinct depths on every pillar are numbered (``tolerance`` > 0 rounds
   them to multiples of it first) and corners become integer ranks;
4. cells collapsed on all four pillars are removed; lateral faces come from the
   pillar-pair engine (fault faces subdivided exactly), top/bottom faces from a
   walk down every column, with the crossing nodes of fault faces inserted into
   their edges so that every cell is watertight (exact closure even between
   skew pillars);
5. faces with fewer than three distinct nodes or zero area are dropped, then
   cells left with fewer than four faces.

Faces are numbered like ``cart_grid``'s: all i-faces, then j-faces, then
k-faces, each ordered by layer, then j, then i, so an unfaulted deck gives
exactly ``cart_grid``'s numbering. Fault faces carry a positive tag: the
FAULTS name's position + 1 where the deck names it, otherwise an id per
connected fault trace (``fault_names`` maps tags to names).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph

from ..connectivity import (
    cell_faces_from_neighbors,
    drop_repeated_nodes,
    offsets,
    ragged_arange,
    renumbering,
)
from ..grid import B, Cells, E, Faces, FloatArray, Grid, IntArray, N, Nodes, S, T, W
from ..stratigraphic.conformal import insert_edge_nodes
from ..stratigraphic.lateral import LateralFaces, SideCells, concat_lateral, general_pieces
from .corners import corner_nodes
from .deck import Deck
from .faces import structured_lateral, structured_vertical
from .volumes import hexahedron_volumes

FAULT, PINCH = 0, 1


@dataclass(frozen=True, eq=False)
class NNC:
    """Non-neighbour connections: cell pairs that are connected but not logical ijk neighbours.

    ``kind`` is 0 (FAULT: a geometric face joins cells of different layers or
    columns) or 1 (PINCH: cells joined across a thin removed layer, no face);
    ``face`` is the connecting face, or -1 for pinch connections.
    """

    cells: IntArray  # (n, 2) cells of the processed grid
    global_cells: IntArray  # (n, 2) linear ijk indices (i fastest)
    kind: np.ndarray
    face: IntArray

    @property
    def num(self) -> int:
        return self.cells.shape[0]


@dataclass(frozen=True, eq=False)
class CornerPointGrid:
    """What ``process_grdecl`` returns."""

    grid: Grid
    nnc: NNC
    fault_names: tuple[str, ...]  # faces.tag t > 0 belongs to fault_names[t - 1]
    notes: tuple[str, ...]
    bulk_volumes: FloatArray  # per grid cell, ECLIPSE/OPM's convention (see cornerpoint.volumes)


def process_grdecl(
    deck: Deck, tolerance: float = 0.0, pinch: bool = False, pinch_threshold: float | None = None
) -> CornerPointGrid:
    """Process a corner-point deck into a grid, its NNCs and fault names.

    ``tolerance`` (deck length unit): depths on a pillar closer than this may be
    merged (MRST's quantisation); 0, the default, merges only equal depths.
    ``pinch``: connect cells across removed layers whose gap is at most
    ``pinch_threshold`` (default: the deck's PINCH threshold, else 0.001) as
    non-neighbour connections.

    >>> from gridlib.cornerpoint.generators import simple_grdecl
    >>> r = process_grdecl(simple_grdecl([4, 2, 3], 0.12, flat=True))
    >>> r.grid.num_cells, r.grid.num_faces, int((r.grid.faces.tag > 0).sum())
    (24, 106, 14)
    """
    src = deck.source
    nx, ny, nz = deck.cart_dims
    cn = corner_nodes(deck, tolerance)
    notes = list(cn.notes)
    kept = cn.kept
    n_keep = int(kept.sum())
    cell_id = np.full(kept.shape, -1, dtype=np.int64)
    cell_id[kept] = np.arange(n_keep)  # kept cells keep the deck's (k, j, i) order
    cell_global = np.flatnonzero(kept.ravel())
    bulk = hexahedron_volumes(cn.xyz, cn.nodes[kept])
    if cn.left_handed:
        bulk = -bulk

    n_ipairs = (nx + 1) * ny
    pi, pj = np.meshgrid(np.arange(nx + 1), np.arange(ny), indexing="xy")
    qi, qj = np.meshgrid(np.arange(nx), np.arange(ny + 1), indexing="xy")
    pair_i = np.concatenate([pi.ravel(), qi.ravel()])
    pair_j = np.concatenate([pj.ravel(), qj.ravel()])
    is_j_pair = np.arange(pair_i.size) >= n_ipairs
    pair_p1 = _pillar_ids(pair_i, pair_j, nx)
    pair_p2 = np.where(is_j_pair, _pillar_ids(pair_i + 1, pair_j, nx), _pillar_ids(pair_i, pair_j + 1, nx))

    lat_i = structured_lateral(cn.nodes, kept, cell_id, False, 0)
    lat_j = structured_lateral(cn.nodes, kept, cell_id, True, n_ipairs)
    side = SideCells(
        *(
            np.concatenate([getattr(lat_i.side_cells, f), getattr(lat_j.side_cells, f)])
            for f in SideCells.__dataclass_fields__
        )
    )
    # The engine works on ranks along each pillar (node id minus the pillar's first id).
    o1, o2 = cn.points.offset[pair_p1[side.pair]], cn.points.offset[pair_p2[side.pair]]
    side = SideCells(
        side.pair, side.side, side.cell, side.k, side.t1 - o1, side.b1 - o1, side.t2 - o2, side.b2 - o2
    )
    general = general_pieces(side, pair_i.size, pair_p1, pair_p2, is_j_pair, cn.points, cn.xyz)
    quads = np.concatenate([lat_i.quads, lat_j.quads])
    q_a = np.concatenate([lat_i.cell_a, lat_j.cell_a])
    q_b = np.concatenate([lat_i.cell_b, lat_j.cell_b])
    q_k = np.concatenate([lat_i.k, lat_j.k])
    fast = LateralFaces(
        np.arange(0, 4 * q_a.size + 1, 4),
        quads.ravel(),
        q_a,
        q_b,
        np.concatenate([lat_i.pair, lat_j.pair]),
        np.where(q_a >= 0, q_k, -1),
        np.where(q_b >= 0, q_k, -1),
        np.zeros(q_a.size, dtype=bool),
        np.zeros((0, 3)),
        np.zeros((0, 2, 2), np.int64),
    )
    lat = concat_lateral(fast, general)
    faulted_pair = np.concatenate([lat_i.faulted, lat_j.faulted])
    ver = structured_vertical(
        cn.nodes, kept, cell_id, cn.points.z, _pinch_threshold(deck, pinch, pinch_threshold), src
    )

    # --- assemble: i-faces, j-faces, k-faces; each by layer, then j, then i (cart_grid's order) ---
    # Fast quads are already in that order; only the few general pieces and the
    # top/bottom faces are sorted, and crossing nodes go only into the top/bottom
    # faces of cells next to a general pair.
    def key(kind, k, j, i, tie):
        return (((kind * (nz + 1) + k) * (ny + 1) + j) * (nx + 1) + i) * (nz + 2) + tie

    n_if, n_jf = lat_i.quads.shape[0], lat_j.quads.shape[0]
    g_kind = is_j_pair[general.pair].astype(np.int64)
    g_kref = np.where(general.cell_a >= 0, general.k_a, general.k_b)
    g_order = np.argsort(
        key(g_kind, g_kref, pair_j[general.pair], pair_i[general.pair], general.k_b + 1), kind="stable"
    )
    g_i, g_j = g_order[g_kind[g_order] == 0], g_order[g_kind[g_order] == 1]
    lat_order = np.concatenate(
        [np.arange(n_if), n_if + n_jf + g_i, n_if + np.arange(n_jf), n_if + n_jf + g_j]
    )
    g_counts = np.diff(general.node_pos)
    lat_nodes = np.concatenate(
        [
            lat_i.quads.ravel(),
            general.nodes[ragged_arange(general.node_pos[:-1][g_i], g_counts[g_i])],
            lat_j.quads.ravel(),
            general.nodes[ragged_arange(general.node_pos[:-1][g_j], g_counts[g_j])],
        ]
    )
    lat_counts = np.concatenate([np.full(n_if, 4), g_counts[g_i], np.full(n_jf, 4), g_counts[g_j]])
    # A quad collapsed on one pillar (top = bottom there) is a triangle.
    lat_pos, lat_nodes = drop_repeated_nodes(offsets(lat_counts), lat_nodes)
    lat_counts = np.diff(lat_pos)

    v_order = np.argsort(key(2, ver.level, ver.j, ver.i, ver.sub), kind="stable")
    v_nodes, v_upper, v_lower = ver.nodes[v_order], ver.upper[v_order], ver.lower[v_order]
    coords = np.concatenate([cn.xyz, lat.crossing_coords])
    near_fault = np.zeros(n_keep + 1, dtype=bool)  # index -1 (outside) maps to the extra False
    near_fault[side.cell] = True
    touched = np.flatnonzero(near_fault[v_upper] | near_fault[v_lower])
    crossing_ids = cn.points.num_nodes + np.arange(lat.crossing_coords.shape[0])
    t_pos, t_nodes = insert_edge_nodes(v_nodes[touched], lat.crossing_lines, crossing_ids, coords)
    v_counts = np.full(v_order.size, 4)
    v_counts[touched] = np.diff(t_pos)
    v_pos = offsets(v_counts)
    v_flat = np.empty(int(v_pos[-1]), dtype=np.int64)
    plain = np.flatnonzero(v_counts == 4)
    plain = np.setdiff1d(plain, touched, assume_unique=True)
    v_flat[v_pos[plain][:, None] + np.arange(4)] = v_nodes[plain]
    v_flat[ragged_arange(v_pos[touched], v_counts[touched])] = t_nodes

    counts = np.concatenate([lat_counts, v_counts])
    nodes = np.concatenate([lat_nodes, v_flat])
    pos = offsets(counts)
    l_a, l_b, l_pair = lat.cell_a[lat_order], lat.cell_b[lat_order], lat.pair[lat_order]
    l_ka, l_kb = lat.k_a[lat_order], lat.k_b[lat_order]
    neighbors = np.column_stack([np.concatenate([l_a, v_upper]), np.concatenate([l_b, v_lower])])
    tag_pair = np.where(is_j_pair[l_pair][:, None], np.array([N, S])[None, :], np.array([E, W])[None, :])
    n_lat, n_ver = lat_order.size, v_order.size
    face_tags = np.concatenate([tag_pair.astype(np.int8), np.tile(np.array([B, T], np.int8), (n_ver, 1))])
    fault, names = _fault_tags(deck, lat, faulted_pair, pair_p1, pair_p2, pair_i, pair_j, is_j_pair, 0)
    fault = np.concatenate([fault[lat_order], np.zeros(n_ver, np.int32)])
    nnc_kind = np.concatenate(
        [
            np.where((l_a >= 0) & (l_b >= 0) & (l_ka != l_kb), FAULT, -1),
            np.where(ver.skips_layers[v_order], PINCH, -1),
        ]
    ).astype(np.int8)
    lat_pair = np.concatenate([l_pair, np.full(n_ver, -1)])
    ver_column = np.concatenate([np.full(n_lat, -1), (ver.i + nx * ver.j)[v_order]])

    # Zero-area faces can only come from coincident pillars: all pieces on a pair of
    # identical pillars, and top/bottom faces whose column has such a pair. They are
    # dropped; their cells keep the rest.
    same_pillars = (cn.lines[pair_p1] == cn.lines[pair_p2]).all(axis=(1, 2))
    zero = np.zeros(counts.size, dtype=bool)
    on_pair = lat_pair >= 0
    zero[on_pair] = same_pillars[lat_pair[on_pair]]
    degenerate_column = _degenerate_columns(same_pillars, nx, ny)
    check = np.flatnonzero((ver_column >= 0) & degenerate_column[np.maximum(ver_column, 0)])
    if check.size:
        sub_counts = counts[check]
        sub_nodes = nodes[ragged_arange(pos[:-1][check], sub_counts)]
        area = _vector_area_norm(coords, offsets(sub_counts), sub_nodes)
        zero[check] = area <= 1e-14 * np.abs(coords).max() ** 2
    if zero.any():
        notes.append(f"{int(zero.sum())} faces of zero area were removed")
        good = ~zero
        counts = counts[good]
        nodes = nodes[ragged_arange(pos[:-1][good], counts)]
        pos = offsets(counts)
        neighbors, face_tags, fault, nnc_kind = neighbors[good], face_tags[good], fault[good], nnc_kind[good]
    if cn.left_handed:
        owner = np.repeat(np.arange(counts.size), counts)
        local = np.arange(nodes.size) - pos[owner]
        nodes = nodes[pos[owner] + counts[owner] - 1 - local]

    # Cells with fewer than four faces are dropped (MRST); faces left without cells too.
    per_cell = np.bincount(neighbors[neighbors >= 0], minlength=n_keep)
    alive = per_cell >= 4
    if not alive.all():
        notes.append(f"{int((~alive).sum())} cells with fewer than four faces were removed")
        remap = renumbering(alive)
        neighbors = np.where(neighbors >= 0, remap[np.maximum(neighbors, 0)], -1)
        has = (neighbors >= 0).any(axis=1)
        counts = counts[has]
        nodes = nodes[ragged_arange(pos[:-1][has], counts)]
        pos = offsets(counts)
        neighbors, face_tags, fault, nnc_kind = neighbors[has], face_tags[has], fault[has], nnc_kind[has]
        cell_global = cell_global[alive]
        bulk = bulk[alive]
        pinch_pairs = remap[ver.pinch_pairs]
        pinch_pairs = pinch_pairs[(pinch_pairs >= 0).all(axis=1)]
    else:
        pinch_pairs = ver.pinch_pairs

    used = np.zeros(coords.shape[0], dtype=bool)
    used[nodes] = True
    node_map = renumbering(used)
    nc = cell_global.size
    face_pos, cell_faces = cell_faces_from_neighbors(neighbors, nc)
    grid = Grid(
        cells=Cells(
            face_pos, cell_faces, _half_face_tags(neighbors, face_tags, face_pos, cell_faces), cell_global
        ),
        faces=Faces(pos, node_map[nodes], neighbors, fault),
        nodes=Nodes(coords[used]),
        griddim=3,
        cart_dims=(nx, ny, nz),
        history=("process_grdecl",),
    )
    face_nnc = np.flatnonzero((nnc_kind >= 0) & (neighbors >= 0).all(axis=1))
    nnc_cells = np.concatenate([neighbors[face_nnc], pinch_pairs]).astype(np.int64)
    nnc = NNC(
        nnc_cells,
        cell_global[nnc_cells],
        np.concatenate([nnc_kind[face_nnc], np.full(pinch_pairs.shape[0], PINCH, np.int8)]),
        np.concatenate([face_nnc, np.full(pinch_pairs.shape[0], -1)]),
    )
    bulk.flags.writeable = False
    return CornerPointGrid(grid, nnc, names, tuple(notes), bulk)


def _pillar_ids(i: IntArray, j: IntArray, nx: int) -> IntArray:
    return i + (nx + 1) * j


def _pinch_threshold(deck: Deck, pinch: bool, threshold: float | None) -> float | None:
    if not pinch:
        return None
    if threshold is not None:
        return float(threshold)
    if deck.pinch:
        return float(deck.pinch[0])
    return 0.001


def _fault_tags(deck, lat, faulted_pair, pair_p1, pair_p2, pair_i, pair_j, is_j_pair, n_ver):
    """Per face fault tag (lateral pieces then vertical faces) and the tag names.

    On a faulted pair, a piece is on the fault if it joins cells whose lines
    differ, or a cell to a void (the fault exposes it); matched pieces (beyond a
    fault tip, say) are not.
    """
    n_lat = lat.pair.size
    n_pairs = pair_p1.size
    cell_void = (lat.cell_a < 0) | (lat.cell_b < 0)
    on_fault = faulted_pair[lat.pair] & (lat.mismatch | cell_void)
    # One id per connected fault trace: faulted pairs linked by shared pillars.
    fp = np.flatnonzero(faulted_pair)
    n_pil = int(max(pair_p1.max(), pair_p2.max())) + 1
    graph = sparse.coo_matrix((np.ones(fp.size), (pair_p1[fp], pair_p2[fp])), shape=(n_pil, n_pil))
    _, label = csgraph.connected_components(graph, directed=False)
    trace_of_pair = np.full(n_pairs, -1)
    trace_of_pair[fp] = label[pair_p1[fp]]
    traces, trace_id = np.unique(trace_of_pair[fp], return_inverse=True)
    lat_tag = np.zeros(n_lat, dtype=np.int32)

    names: list[str] = []
    seen: dict[str, int] = {}
    for seg in deck.faults:  # FAULTS keyword lines: a few hundred at most
        if seg.name not in seen:
            seen[seg.name] = len(seen) + 1
            names.append(seg.name)
    named = _named_fault_tags(deck, lat, pair_i, pair_j, is_j_pair, seen) if seen else None
    offset = len(names)
    id_of_pair = np.zeros(n_pairs, dtype=np.int32)
    id_of_pair[fp] = offset + 1 + trace_id
    lat_tag[on_fault] = id_of_pair[lat.pair[on_fault]]
    names += [f"fault_{t + 1}" for t in range(traces.size)]
    if named is not None:
        lat_tag = np.where(named > 0, named, lat_tag)
    return np.concatenate([lat_tag, np.zeros(n_ver, np.int32)]), tuple(names)


def _named_fault_tags(deck, lat, pair_i, pair_j, is_j_pair, seen) -> np.ndarray:
    """Tag the lateral pieces on the pillar pairs a FAULTS line names.

    A line (box, face X) names the +i faces of its cells: the pairs at i + 1 for
    the box's rows j, and there the pieces whose box-side layer (the A cell's k,
    or the B cell's where A is a void) lies in the box's layers. X- names the -i
    faces (pairs at i, box side B); Y and Y- the same along j.
    """
    n_lat = lat.pair.size
    tags = np.zeros(n_lat, dtype=np.int32)
    pi, pj, jp = pair_i[lat.pair], pair_j[lat.pair], is_j_pair[lat.pair]
    for seg in deck.faults:  # FAULTS lines: a few hundred at most, each vectorised
        if seg.face in ("Z", "Z-"):
            continue  # horizontal faults are rare; not tagged here
        plus = not seg.face.endswith("-")
        along_j = seg.face.startswith("Y")
        shift = 1 if plus else 0
        if along_j:
            covered = jp & (pi >= seg.i1) & (pi <= seg.i2) & (pj >= seg.j1 + shift) & (pj <= seg.j2 + shift)
        else:
            covered = ~jp & (pi >= seg.i1 + shift) & (pi <= seg.i2 + shift) & (pj >= seg.j1) & (pj <= seg.j2)
        own, other = (lat.k_a, lat.k_b) if plus else (lat.k_b, lat.k_a)
        k = np.where(own >= 0, own, other)
        tags[covered & (k >= seg.k1) & (k <= seg.k2)] = seen[seg.name]
    return tags


def _degenerate_columns(same_pillars: np.ndarray, nx: int, ny: int) -> np.ndarray:
    """Columns with at least one pair of coincident neighbouring pillars."""
    n_ipairs = (nx + 1) * ny
    ipair = same_pillars[:n_ipairs].reshape(ny, nx + 1)
    jpair = same_pillars[n_ipairs:].reshape(ny + 1, nx)
    bad = ipair[:, :-1] | ipair[:, 1:] | jpair[:-1, :] | jpair[1:, :]
    return bad.ravel()


def _vector_area_norm(coords: np.ndarray, pos: IntArray, nodes: IntArray) -> np.ndarray:
    """|vector area| of every face (Newell), for spotting zero-area faces."""
    owner = np.repeat(np.arange(pos.size - 1), np.diff(pos))
    nxt = np.arange(nodes.size) + 1
    nxt[pos[1:] - 1] = pos[:-1]
    origin = coords[nodes[pos[:-1]]][owner]
    p, q = coords[nodes] - origin, coords[nodes[nxt]] - origin
    cr = np.cross(p, q)
    area = np.stack([np.bincount(owner, cr[:, d], pos.size - 1) for d in range(3)], axis=1)
    return 0.5 * np.linalg.norm(area, axis=1)


def _half_face_tags(neighbors, face_tags, face_pos, cell_faces) -> np.ndarray:
    hc = np.repeat(np.arange(face_pos.size - 1), np.diff(face_pos))
    col = np.where(neighbors[cell_faces, 0] == hc, 0, 1)
    return face_tags[cell_faces, col]
