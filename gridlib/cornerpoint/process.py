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

from ..connectivity import cell_faces_from_neighbors, offsets, ragged_arange, renumbering
from ..errors import InputError
from ..grid import B, Cells, E, Faces, Grid, IntArray, N, Nodes, S, T, W
from ..stratigraphic.conformal import insert_edge_nodes
from ..stratigraphic.lateral import SideCells, lateral_faces
from ..stratigraphic.points import points_on_pillars, unique_points
from ..stratigraphic.vertical import vertical_faces
from .deck import Deck

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


# Corner offsets (a, b) of a cell's four pillars in the order of a top face cycle.
_CYCLE = np.array([[0, 0], [1, 0], [1, 1], [0, 1]])


def process_grdecl(
    deck: Deck, tolerance: float = 0.0, pinch: bool = False, pinch_threshold: float | None = None
) -> CornerPointGrid:
    """Process a corner-point deck into a grid, its NNCs and fault names.

    ``tolerance`` (deck length unit): depths on a pillar closer than this may be
    merged (MRST's quantisation); 0, the default, merges only equal depths.
    ``pinch``: connect cells across removed layers whose gap is at most
    ``pinch_threshold`` (default: the deck's PINCH threshold, else 0.001) as
    non-neighbour connections.
    """
    src = deck.source
    nx, ny, nz = deck.cart_dims
    notes: list[str] = []
    active = deck.active
    act = np.flatnonzero(active)
    if act.size == 0:
        raise InputError(f"{src}: no active cells (ACTNUM is all 0)")
    i = act % nx
    j = (act // nx) % ny
    k = act // (nx * ny)

    zc = deck.zcorn_array()
    a = np.array([0, 1, 0, 1, 0, 1, 0, 1])
    b = np.array([0, 0, 1, 1, 0, 0, 1, 1])
    c = np.array([0, 0, 0, 0, 1, 1, 1, 1])
    # corner z (n_act, 8): index (2k + c, 2j + b, 2i + a)
    z = zc[2 * k[:, None] + c, 2 * j[:, None] + b, 2 * i[:, None] + a]
    bad = ~np.isfinite(z).all(axis=1)
    if bad.any():
        raise InputError(
            f"{src}: ZCORN: active cell {_ijk(act[bad][0], nx, ny)} has a non-finite corner depth "
            f"({int(bad.sum())} active cells have NaN or infinite corners)"
        )
    lines = deck.pillars().reshape(-1, 2, 3).copy()
    if not np.isfinite(lines[_pillar_ids(i, j, nx)]).all():
        raise InputError(f"{src}: COORD: a pillar of an active cell is NaN or infinite")

    dz = z[:, 4:] - z[:, :4]  # bottom minus top on each pillar
    if (dz < 0).sum() > (dz > 0).sum():  # z grows upwards: make it depth
        z, lines[:, :, 2] = -z, -lines[:, :, 2]
        dz = -dz
        notes.append("z decreases with depth in this deck (z up): z was negated to depth")
    if (dz < 0).any():
        cell = act[np.flatnonzero((dz < 0).any(axis=1))[0]]
        raise InputError(f"{src}: ZCORN: cell {_ijk(cell, nx, ny)} has a top corner below its bottom corner")

    pillar = _pillar_ids(i[:, None] + a, j[:, None] + b, nx)
    if tolerance < 0:
        raise InputError(f"process_grdecl: tolerance must be >= 0, got {tolerance}")
    pts = unique_points(pillar.ravel(), z.ravel(), (nx + 1) * (ny + 1), tolerance)
    node = pts.node_of_corner.reshape(-1, 8)
    rank = node - pts.offset[pillar]
    xyz = points_on_pillars(lines, pts.pillar, pts.z)

    left_handed = _left_handed(lines, i, j, nx)
    if left_handed:
        notes.append("the deck is left-handed in plan view: every face was reversed")

    # Cells collapsed on all four pillars disappear; cells must not overlap in a column.
    keep = ~(node[:, :4] == node[:, 4:]).all(axis=1)
    _check_column_order(rank, keep, i, j, k, nx, ny, act, src)
    n_keep = int(keep.sum())
    kept = np.flatnonzero(keep)
    new_id = np.full(act.size, -1)
    new_id[kept] = np.arange(n_keep)

    side = _side_cells(i[kept], j[kept], k[kept], rank[kept], new_id[kept], nx, ny)
    n_ipairs = (nx + 1) * ny
    pi, pj = np.meshgrid(np.arange(nx + 1), np.arange(ny), indexing="xy")
    ip1, ip2 = _pillar_ids(pi.ravel(), pj.ravel(), nx), _pillar_ids(pi.ravel(), pj.ravel() + 1, nx)
    qi, qj = np.meshgrid(np.arange(nx), np.arange(ny + 1), indexing="xy")
    jp1, jp2 = _pillar_ids(qi.ravel(), qj.ravel(), nx), _pillar_ids(qi.ravel() + 1, qj.ravel(), nx)
    pair_p1, pair_p2 = np.concatenate([ip1, jp1]), np.concatenate([ip2, jp2])
    pair_i = np.concatenate([pi.ravel(), qi.ravel()])
    pair_j = np.concatenate([pj.ravel(), qj.ravel()])
    is_j_pair = np.arange(pair_p1.size) >= n_ipairs
    lat = lateral_faces(side, pair_p1, pair_p2, is_j_pair, pts, xyz)

    ver = vertical_faces(
        np.arange(n_keep),
        i[kept] + nx * j[kept],
        k[kept],
        node[kept][:, :4][:, [0, 1, 3, 2]],
        node[kept][:, 4:][:, [0, 1, 3, 2]],
        pts.z,
        _pinch_threshold(deck, pinch, pinch_threshold),
    )

    # --- assemble: lateral (i, then j) and vertical faces, cart_grid-like order ---
    lat_kind = is_j_pair[lat.pair].astype(np.int64)
    k_ref = np.where(lat.cell_a >= 0, lat.k_a, lat.k_b)
    n_ver = ver.upper.size
    kind = np.concatenate([lat_kind, np.full(n_ver, 2)])
    order = np.lexsort(
        (
            np.concatenate([lat.k_b, np.zeros(n_ver, np.int64)]),
            np.concatenate([pair_i[lat.pair], ver.column % nx]),
            np.concatenate([pair_j[lat.pair], ver.column // nx]),
            np.concatenate([k_ref, ver.level]),
            kind,
        )
    )
    coords = np.concatenate([xyz, lat.crossing_coords])
    crossing_ids = pts.num_nodes + np.arange(lat.crossing_coords.shape[0])
    ver_pos, ver_nodes = insert_edge_nodes(ver.nodes, lat.crossing_lines, crossing_ids, coords)
    counts = np.concatenate([np.diff(lat.node_pos), np.diff(ver_pos)])
    all_pos = offsets(counts)
    all_nodes = np.concatenate([lat.nodes, ver_nodes])
    neighbors = np.column_stack(
        [np.concatenate([lat.cell_a, ver.upper]), np.concatenate([lat.cell_b, ver.lower])]
    )
    tag_pair = np.where(lat_kind[:, None] == 0, np.array([E, W])[None, :], np.array([N, S])[None, :]).astype(
        np.int8
    )
    face_tags = np.concatenate([tag_pair, np.tile(np.array([B, T], np.int8), (n_ver, 1))])
    faulted_pair = _faulted_pairs(side, pair_p1.size, nz)
    fault, names = _fault_tags(
        deck, lat, faulted_pair, pair_p1, pair_p2, pair_i, pair_j, is_j_pair, act, kept, n_ver
    )

    # reorder
    counts = counts[order]
    nodes = all_nodes[ragged_arange(all_pos[:-1][order], counts)]
    neighbors, face_tags, fault, kind = neighbors[order], face_tags[order], fault[order], kind[order]
    pos = offsets(counts)

    # Zero-area faces can only come from coincident pillars: all pieces on a pair of
    # identical pillars, and top/bottom faces whose column has such a pair. They are
    # dropped; their cells keep the rest.
    same_pillars = (lines[pair_p1] == lines[pair_p2]).all(axis=(1, 2))
    suspect = np.zeros(counts.size, dtype=bool)
    face_pair = np.concatenate([lat.pair, np.full(n_ver, -1)])[order]
    suspect[face_pair >= 0] = same_pillars[face_pair[face_pair >= 0]]
    degenerate_column = _degenerate_columns(same_pillars, nx, ny)
    face_column = np.concatenate([np.full(lat.pair.size, -1), ver.column])[order]
    check = np.flatnonzero((face_column >= 0) & degenerate_column[np.maximum(face_column, 0)])
    if check.size:
        sub_counts = counts[check]
        sub_pos = offsets(sub_counts)
        sub_nodes = nodes[ragged_arange(pos[:-1][check], sub_counts)]
        area = _vector_area_norm(coords, sub_pos, sub_nodes)
        suspect[check] = area <= 1e-14 * np.abs(coords).max() ** 2
    good = ~suspect
    if not good.all():
        notes.append(f"{int((~good).sum())} faces of zero area were removed")
        counts = counts[good]
        nodes = nodes[ragged_arange(pos[:-1][good], counts)]
        pos = offsets(counts)
        neighbors, face_tags, fault, kind = neighbors[good], face_tags[good], fault[good], kind[good]
    if left_handed:
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
        neighbors, face_tags, fault, kind = neighbors[has], face_tags[has], fault[has], kind[has]
    cell_global = act[kept][alive]

    used = np.zeros(coords.shape[0], dtype=bool)
    used[nodes] = True
    node_map = renumbering(used)
    nc = int(alive.sum())
    face_pos, cell_faces = cell_faces_from_neighbors(neighbors, nc)
    half_tag = _half_face_tags(neighbors, face_tags, face_pos, cell_faces)
    grid = Grid(
        cells=Cells(face_pos, cell_faces, half_tag, cell_global),
        faces=Faces(pos, node_map[nodes], neighbors, fault),
        nodes=Nodes(coords[used]),
        griddim=3,
        cart_dims=(nx, ny, nz),
        history=("process_grdecl",),
    )
    nnc = _nnc(grid, kind == 2, ver.pinch_pairs, alive, nx, ny)
    return CornerPointGrid(grid, nnc, names, tuple(notes))


def _ijk(cell: int, nx: int, ny: int) -> str:
    """1-based (i, j, k) of a linear cell index, as users of decks count."""
    return f"({cell % nx + 1}, {cell // nx % ny + 1}, {cell // (nx * ny) + 1})"


def _pillar_ids(i: IntArray, j: IntArray, nx: int) -> IntArray:
    return i + (nx + 1) * j


def _left_handed(lines: np.ndarray, i: IntArray, j: IntArray, nx: int) -> bool:
    """Majority vote over active cells: does (i, j) turn clockwise in plan view?"""
    mid = lines.mean(axis=1)[:, :2]
    p00 = mid[_pillar_ids(i, j, nx)]
    ei = mid[_pillar_ids(i + 1, j, nx)] - p00
    ej = mid[_pillar_ids(i, j + 1, nx)] - p00
    cross = ei[:, 0] * ej[:, 1] - ei[:, 1] * ej[:, 0]
    return bool((cross < 0).sum() > (cross > 0).sum())


def _check_column_order(rank, keep, i, j, k, nx, ny, act, src) -> None:
    """Kept cells of a column may touch but not overlap (ZCORN must not decrease with k)."""
    idx = np.flatnonzero(keep)
    col = i[idx] + nx * j[idx]
    order = np.lexsort((k[idx], col))
    s = idx[order]
    same = col[order][1:] == col[order][:-1]
    overlap = same & (rank[s[1:], :4] < rank[s[:-1], 4:]).any(axis=1)
    if overlap.any():
        upper, lower = act[s[:-1][overlap][0]], act[s[1:][overlap][0]]
        raise InputError(
            f"{src}: ZCORN: cell {_ijk(upper, nx, ny)} reaches below the top of cell "
            f"{_ijk(lower, nx, ny)} in the same column (overlapping layers)"
        )


def _side_cells(i, j, k, rank, cell, nx, ny) -> SideCells:
    """Each kept cell on its four lateral pillar pairs (ranks of its corners there)."""
    n_ipairs = (nx + 1) * ny
    # corner order in rank: (a, b, c) = (0,0,0) (1,0,0) (0,1,0) (1,1,0) then c = 1
    t = rank[:, :4]
    b = rank[:, 4:]
    # i-pairs: A side uses a = 1 (corners 1, 3), B side a = 0 (corners 0, 2); p1 = b 0, p2 = b 1.
    # j-pairs: A side uses b = 1 (corners 2, 3), B side b = 0 (corners 0, 1); p1 = a 0, p2 = a 1.
    specs = (
        (i + 1 + (nx + 1) * j, 0, 1, 3),
        (i + (nx + 1) * j, 1, 0, 2),
        (n_ipairs + i + nx * (j + 1), 0, 2, 3),
        (n_ipairs + i + nx * j, 1, 0, 1),
    )
    cat = np.concatenate
    return SideCells(
        pair=cat([s[0] for s in specs]),
        side=cat([np.full(i.size, s[1]) for s in specs]),
        cell=np.tile(cell, 4),
        k=np.tile(k, 4),
        t1=cat([t[:, s[2]] for s in specs]),
        b1=cat([b[:, s[2]] for s in specs]),
        t2=cat([t[:, s[3]] for s in specs]),
        b2=cat([b[:, s[3]] for s in specs]),
    )


def _pinch_threshold(deck: Deck, pinch: bool, threshold: float | None) -> float | None:
    if not pinch:
        return None
    if threshold is not None:
        return float(threshold)
    if deck.pinch:
        return float(deck.pinch[0])
    return 0.001


def _faulted_pairs(side: SideCells, n_pairs: int, nz: int) -> np.ndarray:
    """Pairs where some layer has kept cells on both sides with different corner nodes."""
    key = side.pair * nz + side.k
    a, b = side.side == 0, side.side == 1
    ka, kb = key[a], key[b]
    order = np.argsort(kb)
    loc = np.minimum(np.searchsorted(kb[order], ka), max(kb.size - 1, 0))
    if kb.size == 0:
        return np.zeros(n_pairs, dtype=bool)
    jb = order[loc]
    match = kb[jb] == ka
    ia = np.flatnonzero(a)[match]
    ib = np.flatnonzero(b)[jb[match]]
    differ = (
        (side.t1[ia] != side.t1[ib])
        | (side.b1[ia] != side.b1[ib])
        | (side.t2[ia] != side.t2[ib])
        | (side.b2[ia] != side.b2[ib])
    )
    return np.bincount(side.pair[ia][differ], minlength=n_pairs) > 0


def _fault_tags(deck, lat, faulted_pair, pair_p1, pair_p2, pair_i, pair_j, is_j_pair, act, kept, n_ver):
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
    named = _named_fault_tags(deck, lat, pair_i, pair_j, is_j_pair, act, kept, seen) if seen else None
    offset = len(names)
    id_of_pair = np.zeros(n_pairs, dtype=np.int32)
    id_of_pair[fp] = offset + 1 + trace_id
    lat_tag[on_fault] = id_of_pair[lat.pair[on_fault]]
    names += [f"fault_{t + 1}" for t in range(traces.size)]
    if named is not None:
        lat_tag = np.where(named > 0, named, lat_tag)
    return np.concatenate([lat_tag, np.zeros(n_ver, np.int32)]), tuple(names)


def _named_fault_tags(deck, lat, pair_i, pair_j, is_j_pair, act, kept, seen) -> np.ndarray:
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


def _nnc(grid: Grid, vertical: np.ndarray, pinch_pairs, alive, nx, ny) -> NNC:
    """Connections between cells that are not logical ijk neighbours.

    A lateral face between cells of different layers or non-adjacent columns is a
    FAULT connection; a top/bottom face joining cells across collapsed layers,
    or a pinch pair (no face), is a PINCH connection.
    """
    nb = grid.faces.neighbors
    inner = np.flatnonzero((nb >= 0).all(axis=1))
    g = grid.cells.index_map[nb[inner]]
    gi, gj, gk = g % nx, (g // nx) % ny, g // (nx * ny)
    steps = np.abs(np.diff(gi, axis=1)) + np.abs(np.diff(gj, axis=1)) + np.abs(np.diff(gk, axis=1))
    nonlogical = steps[:, 0] != 1
    faces = inner[nonlogical]
    face_kind = np.where(vertical[faces], PINCH, FAULT).astype(np.int8)
    remap = np.full(alive.size, -1)
    remap[alive] = np.arange(int(alive.sum()))
    pp = remap[pinch_pairs] if pinch_pairs.size else np.zeros((0, 2), np.int64)
    if pp.size:
        pp = pp[(pp >= 0).all(axis=1)]
    all_cells = np.concatenate([nb[faces], pp]).astype(np.int64)
    kinds = np.concatenate([face_kind, np.full(pp.shape[0], PINCH, np.int8)])
    face_of = np.concatenate([faces, np.full(pp.shape[0], -1)])
    return NNC(all_cells, grid.cells.index_map[all_cells], kinds, face_of)
