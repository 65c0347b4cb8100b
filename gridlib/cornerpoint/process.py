"""``process_grdecl``: a corner-point deck to an unstructured grid (the pillar engine's
Cartesian front end; ``docs/pillar-grids.md`` describes the engine, its pinch-outs, zero-area
faces and the two volume conventions).

Steps, all vectorised over cells, corners and pillar pairs:

1. inactive cells are masked before anything else: their corners (often junk:
   NaN, -1e20) are never read; active corners must be finite, and the pillars
   around them must not cross (:mod:`.crossing`: cells turned inside out in plan
   view overlap their neighbours, an InputError naming them);
2. z-up decks (depths decreasing with k) are negated so z is depth; left-handed
   decks (k x j x i frame mirrored in plan view) get every face reversed at the
   end, so volumes are positive and normals point outwards either way;
3. the distinct depths on every pillar are numbered (``tolerance`` > 0 rounds
   them to multiples of it first) and corners become integer ranks; depths
   equal up to rounding (within the pillar's depth resolution, 64 units in the
   last place of its largest depth: :mod:`~gridlib.pillars.pillar_points`) are
   one point, so that the exact rank tests never make a face of zero area
   (nodes collinear up to rounding) nor a connection between cells that do
   not touch;
4. cells collapsed on all four pillars are removed; lateral faces come from the
   pillar-pair engine (fault faces subdivided exactly), top/bottom faces from a
   walk down every column, with the crossing nodes of fault faces inserted into
   their edges so that every cell is watertight (exact closure even between
   skew pillars);
5. faces with fewer than three distinct nodes are dropped, and those of zero
   area that coincident pillars make (a pair of no width); then cells left
   with fewer than four faces.

Faces are numbered like ``cart_grid``'s: all i-faces, then j-faces, then
k-faces, each ordered by layer, then j, then i, so an unfaulted deck gives
exactly ``cart_grid``'s numbering; the lateral pieces of faulted (and other
irregular) pillar pairs follow the other faces of their orientation, in the
same order among themselves. Fault faces carry a positive tag: the
FAULTS name's position + 1 where the deck names it, otherwise an id per
connected fault trace (``fault_names`` maps tags to names).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph

from ..connectivity import cell_half_faces, drop_repeated_nodes, offsets, ragged_arange, renumbering
from ..errors import InputError
from ..grid import B, Cells, E, Faces, FloatArray, Grid, IntArray, N, Nodes, S, T, W
from ..memory import count_text, memory_shortfall
from ..pillars.conformal import insert_edge_nodes
from ..pillars.lateral import SideCells, general_pieces
from ..pillars.nnc import FAULT, NNC, PINCH
from .corners import corner_nodes
from .crossing import check_pillars_do_not_cross
from .deck import Deck
from .faces import structured_lateral, structured_vertical
from .pore_volume import (
    has_pore_volume,
    ijk_text,
    minimum_pore_volumes,
    pore_volumes,
    with_flow_activity,
)
from .volumes import hexahedron_volumes


@dataclass(frozen=True, eq=False)
class CornerPointGrid:
    """What ``process_grdecl`` returns."""

    grid: Grid
    nnc: NNC
    fault_names: tuple[str, ...]  # faces.tag t > 0 belongs to fault_names[t - 1]
    notes: tuple[str, ...]
    bulk_volumes: FloatArray  # per grid cell, ECLIPSE/OPM's convention (see cornerpoint.volumes)


# Peak bytes per deck cell of process_grdecl then deck_transmissibility, above the deck itself:
# about 520 and 790 measured (ru_maxrss) on faulted 100x100x20 and 200x200x20 decks; with room
# for the extra faces and nodes of a deck with more faults.
PROCESS_BYTES_PER_CELL = 1024


def _check_size(deck: Deck) -> None:
    """An InputError naming the deck if its grid would not fit in this machine's memory."""
    n = deck.num_cells
    refusal = memory_shortfall(
        n * PROCESS_BYTES_PER_CELL, f"{count_text(n)} cells", "to process with their transmissibilities"
    )
    if refusal is not None:
        nx, ny, nz = deck.cart_dims
        raise InputError(f"{deck.source}: {nx} x {ny} x {nz} grid: {refusal}")


def process_grdecl(
    deck: Deck,
    tolerance: float = 0.0,
    pinch: bool = False,
    pinch_threshold: float | None = None,
    minpv: float | None = None,
) -> CornerPointGrid:
    """Process a corner-point deck into a grid, its NNCs and fault names.

    ``tolerance`` (deck length unit): depths on a pillar closer than this may be
    merged (MRST's quantisation); 0, the default, merges only depths equal up
    to rounding (see the module docstring).
    ``pinch``: connect cells across removed layers whose gap is at most
    ``pinch_threshold`` (default: the deck's PINCH threshold, else 0.001) as
    non-neighbour connections.
    ``minpv`` (deck reservoir volume unit): cells whose pore volume is below it become
    inactive; default: the deck's MINPV (or MINPORV, else MINPVV per cell), if any; 0
    turns it off.

    Activity is OPM Flow's (:mod:`.pore_volume`): ACTNUM; cells whose pore volume is 0
    (PORO, NTG, MULTPV or PORV 0, PORO undefined) are inactive as if ACTNUM were 0; cells
    collapsed on all four pillars are removed; then MINPV. A deck without PORO and PORV
    keeps ACTNUM (no pore volume rule, no MINPV). ``notes`` say how many cells each rule
    removed.

    >>> from gridlib.cornerpoint.generators import simple_grdecl
    >>> r = process_grdecl(simple_grdecl([4, 2, 3], 0.12, flat=True))
    >>> r.grid.num_cells, r.grid.num_faces, int((r.grid.faces.tag > 0).sum())
    (24, 106, 14)
    """
    _check_size(deck)
    flow_deck = with_flow_activity(deck)  # zero pore volume: inactive, as ACTNUM 0
    if deck.active.any() and not flow_deck.active.any():
        raise InputError(f"{deck.source}: no active cells: every ACTNUM-active cell has zero pore volume")
    notes = list(flow_deck.notes[len(deck.notes) :])
    deck = flow_deck
    cn = corner_nodes(deck, tolerance)
    notes = list(cn.notes) + notes
    if not cn.kept.any():
        raise InputError(f"{deck.source}: every active cell has zero thickness (collapsed on all pillars)")
    check_pillars_do_not_cross(cn, deck.cart_dims, deck.source)
    bulk = hexahedron_volumes(cn.xyz, cn.table.reshape(8, -1), np.flatnonzero(cn.cells >= 0))
    if cn.left_handed:
        bulk = -bulk
    removed = _removed_by_pore_volume(deck, cn, bulk, minpv, notes)
    if removed is not None:
        cn, bulk = cn.without(removed), bulk[~removed]
    cell_global = np.flatnonzero(cn.kept.ravel())  # kept cells keep the deck's (k, j, i) order
    faces, coords, names, pinch_pairs = _faces(
        deck, cn, _pinch_threshold(deck, pinch, pinch_threshold), notes
    )
    left_handed = cn.left_handed
    del cn  # the corners (a 1e7-cell deck's: 1 GiB) are in the faces now
    if left_handed:
        faces.reverse_cycles()

    # Cells with fewer than four faces are dropped (MRST); faces left without cells too.
    face_pos, half_faces = cell_half_faces(faces.neighbors, cell_global.size)
    alive = np.diff(face_pos) >= 4
    if not alive.all():
        notes.append(f"{int((~alive).sum())} cells with fewer than four faces were removed")
        remap = renumbering(alive)
        faces.neighbors = np.where(faces.neighbors >= 0, remap[np.maximum(faces.neighbors, 0)], -1)
        faces.keep((faces.neighbors >= 0).any(axis=1))
        cell_global, bulk = cell_global[alive], bulk[alive]
        pinch_pairs = remap[pinch_pairs]
        pinch_pairs = pinch_pairs[(pinch_pairs >= 0).all(axis=1)]
        face_pos, half_faces = cell_half_faces(faces.neighbors, cell_global.size)

    names = _compact_fault_tags(faces.fault, names, len({seg.name for seg in deck.faults}))
    used = np.zeros(coords.shape[0], dtype=bool)
    used[faces.nodes] = True
    if not used.all():
        faces.renumber_nodes(renumbering(used))
        coords = coords[used]
    half_face_tags = faces.tags.reshape(-1)[half_faces]
    cell_faces = np.right_shift(half_faces, 1, out=half_faces)  # half-face 2 f + side -> face f
    grid = Grid(
        cells=Cells(face_pos, cell_faces, half_face_tags, cell_global),
        faces=Faces(offsets(faces.counts), faces.nodes, faces.neighbors, faces.fault),
        nodes=Nodes(coords),
        griddim=3,
        cart_dims=deck.cart_dims,
        history=("process_grdecl",),
    )
    bulk.flags.writeable = False
    return CornerPointGrid(grid, _nnc(faces, pinch_pairs, cell_global), names, tuple(notes), bulk)


@dataclass(frozen=True, eq=False)
class _PillarPairs:
    """All pillar pairs: the i-pairs (p1 = (i, j), p2 = (i, j + 1)), then the j-pairs
    (p1 = (i, j), p2 = (i + 1, j)), each with i fastest."""

    i: IntArray
    j: IntArray
    is_j: np.ndarray
    p1: IntArray
    p2: IntArray

    @classmethod
    def of(cls, nx: int, ny: int) -> _PillarPairs:
        pi, pj = np.meshgrid(np.arange(nx + 1), np.arange(ny), indexing="xy")
        qi, qj = np.meshgrid(np.arange(nx), np.arange(ny + 1), indexing="xy")
        i = np.concatenate([pi.ravel(), qi.ravel()])
        j = np.concatenate([pj.ravel(), qj.ravel()])
        is_j = np.arange(i.size) >= pi.size
        p1 = _pillar_ids(i, j, nx)
        p2 = np.where(is_j, _pillar_ids(i + 1, j, nx), _pillar_ids(i, j + 1, nx))
        return cls(i, j, is_j, p1, p2)

    @property
    def num(self) -> int:
        return self.i.size


def _faces(deck: Deck, cn, pinch_threshold: float | None, notes: list[str]):
    """All faces of the kept cells in the grid's face order, with zero-area faces removed.

    Order: i-faces, j-faces, k-faces (cart_grid's numbering on unfaulted decks).
    Lateral faces of one orientation: the quads of simple pairs in (k, j, i)
    order, then the pieces of the general pairs sorted by (layer, j, i); top and
    bottom faces by (interface, j, i). Crossing nodes go only into the
    top/bottom faces of cells next to a general pair. Returns the face arrays,
    the node coordinates (crossing nodes after the pillar nodes), the fault
    names and the pinch connections.
    """
    nx, ny, _ = deck.cart_dims
    pairs = _PillarPairs.of(nx, ny)
    lat_i = structured_lateral(cn.table, cn.cells, False, 0, cn.layered)
    lat_j = structured_lateral(cn.table, cn.cells, True, (nx + 1) * ny, cn.layered)
    side = _ranked_side_cells(lat_i.side_cells, lat_j.side_cells, cn.points.offset, pairs)
    general = general_pieces(side, pairs.num, pairs.p1, pairs.p2, pairs.is_j, cn.points, cn.xyz)
    faulted_pair = np.concatenate([lat_i.faulted, lat_j.faulted])
    g_fault, names, seen = _fault_tags(deck, general, faulted_pair, pairs.p1, pairs.p2)
    g_i, g_j = _general_order(general, pairs, deck.cart_dims)
    ver = structured_vertical(cn.table, cn.cells, cn.points.z, pinch_threshold, deck.source)

    coords = np.concatenate([cn.xyz, general.crossing_coords])
    near_fault = np.zeros(int(np.count_nonzero(cn.kept)) + 1, dtype=bool)  # -1 (outside): the extra False
    near_fault[side.cell] = True
    touched = np.flatnonzero(near_fault[ver.upper] | near_fault[ver.lower])
    crossing_ids = cn.points.num_nodes + np.arange(general.crossing_coords.shape[0])
    t_pos, t_nodes = insert_edge_nodes(
        ver.nodes(cn.table, touched), general.crossing_lines, crossing_ids, coords
    )

    n_quads = lat_i.quads.num + lat_j.quads.num
    n_lat = n_quads + general.pair.size
    faces = _FaceArrays(n_lat + ver.num, 4 * (n_quads + ver.num) + general.nodes.size + t_nodes.size)
    named_faults = _NamedFaults(deck, pairs, seen) if seen else None
    named = named_faults.tags if named_faults is not None else None
    for lat, pieces, tags in ((lat_i, g_i, (E, W)), (lat_j, g_j, (N, S))):
        _add_quads(faces, lat.quads, cn.table, tags, named)
        _add_pieces(faces, general, pieces, g_fault, tags, named)
    added = _add_vertical(faces, ver, cn.table, touched, t_pos, t_nodes)
    if named_faults is not None and named_faults.has_z:
        layer = np.flatnonzero(cn.kept.ravel()) // (nx * ny)  # k of every kept cell
        k_up = np.where(ver.upper >= 0, layer[ver.upper], -1)
        k_down = np.where(ver.lower >= 0, layer[ver.lower], -1)
        faces.fault[added] = named_faults.vertical_tags(ver.columns(), k_up, k_down)

    same_pillars = (cn.lines[pairs.p1] == cn.lines[pairs.p2]).all(axis=(1, 2))
    if same_pillars.any():
        lat_pair = np.concatenate([lat_i.quads.pair, general.pair[g_i], lat_j.quads.pair, general.pair[g_j]])
        zero = _zero_area_faces(faces, coords, same_pillars, lat_pair, ver.columns(), nx, ny)
        if zero.any():
            notes.append(f"{int(zero.sum())} faces of zero area were removed")
            faces.keep(~zero)
    return faces, coords, names, ver.pinch_pairs


def _ranked_side_cells(
    side_i: SideCells, side_j: SideCells, offset: IntArray, pairs: _PillarPairs
) -> SideCells:
    """The cells of the general pairs of both orientations, with ranks along each pillar.

    The engine works on ranks (node id minus the pillar's first id).
    """
    side = SideCells(
        *(np.concatenate([getattr(side_i, f), getattr(side_j, f)]) for f in SideCells.__dataclass_fields__)
    )
    o1, o2 = offset[pairs.p1[side.pair]], offset[pairs.p2[side.pair]]
    return SideCells(
        side.pair, side.side, side.cell, side.k, side.t1 - o1, side.b1 - o1, side.t2 - o2, side.b2 - o2
    )


def _general_order(general, pairs: _PillarPairs, dims: tuple[int, int, int]) -> tuple[IntArray, IntArray]:
    """The general pieces on i-pairs and on j-pairs, each sorted by (layer, j, i)."""
    nx, ny, nz = dims
    kind = pairs.is_j[general.pair].astype(np.int64)
    k_ref = np.where(general.cell_a >= 0, general.k_a, general.k_b)
    i, j = pairs.i[general.pair], pairs.j[general.pair]
    key = (((kind * (nz + 1) + k_ref) * (ny + 1) + j) * (nx + 1) + i) * (nz + 2) + general.k_b + 1
    order = np.argsort(key, kind="stable")
    return order[kind[order] == 0], order[kind[order] == 1]


def _add_quads(faces: _FaceArrays, quads, table: IntArray, tags: tuple[int, int], named) -> None:
    """The quads of the simple pairs of one orientation (never on a faulted pair, never an NNC)."""
    added = faces.add_quads(quads, table)
    faces.neighbors[added, 0], faces.neighbors[added, 1] = quads.cell_a, quads.cell_b
    faces.tags[added] = tags
    if named is not None:
        k = quads.k
        faces.fault[added] = named(
            quads.pair, np.where(quads.cell_a >= 0, k, -1), np.where(quads.cell_b >= 0, k, -1)
        )


def _add_pieces(
    faces: _FaceArrays, general, pieces: IntArray, g_fault: IntArray, tags: tuple[int, int], named
) -> None:
    """The general pieces ``pieces`` (of one orientation), in that order."""
    counts = np.diff(general.node_pos)[pieces]
    pos, nodes = drop_repeated_nodes(
        offsets(counts), general.nodes[ragged_arange(general.node_pos[:-1][pieces], counts)]
    )
    added = faces.add(np.diff(pos), nodes)
    cell_a, cell_b = general.cell_a[pieces], general.cell_b[pieces]
    k_a, k_b = general.k_a[pieces], general.k_b[pieces]
    faces.neighbors[added, 0], faces.neighbors[added, 1] = cell_a, cell_b
    faces.tags[added] = tags
    faces.fault[added] = g_fault[pieces]
    if named is not None:
        by_name = named(general.pair[pieces], k_a, k_b)
        faces.fault[added] = np.where(by_name > 0, by_name, g_fault[pieces])
    faces.nnc_kind[added] = np.where((cell_a >= 0) & (cell_b >= 0) & (k_a != k_b), FAULT, -1)


def _add_vertical(
    faces: _FaceArrays, ver, table: IntArray, touched: IntArray, t_pos: IntArray, t_nodes: IntArray
) -> slice:
    """The top and bottom faces; faces ``touched`` take the cycles (t_pos, t_nodes)."""
    added = faces.add_vertical(ver, table, touched, t_pos, t_nodes)
    faces.neighbors[added, 0], faces.neighbors[added, 1] = ver.upper, ver.lower
    faces.tags[added] = (B, T)
    faces.nnc_kind[added] = np.where(ver.skips_layers, PINCH, -1)
    return added


def _zero_area_faces(faces, coords, same_pillars, lat_pair, ver_column, nx: int, ny: int) -> np.ndarray:
    """Faces of zero area, which only coincident pillars make.

    They are all pieces on a pair of identical pillars, and those top/bottom
    faces of columns with such a pair whose area vanishes. They are dropped;
    their cells keep the rest.
    """
    n_lat = lat_pair.size
    zero = np.zeros(faces.num, dtype=bool)
    zero[:n_lat] = same_pillars[lat_pair]
    check = n_lat + np.flatnonzero(_degenerate_columns(same_pillars, nx, ny)[ver_column])
    if check.size:
        counts = faces.counts[check]
        nodes = faces.nodes[ragged_arange(faces.pos[:-1][check], counts)]
        area = _vector_area_norm(coords, offsets(counts), nodes)
        zero[check] = area <= 1e-14 * np.abs(coords).max() ** 2
    return zero


def _nnc(faces, pinch_pairs: IntArray, cell_global: IntArray) -> NNC:
    """Fault NNCs (faces between cells of different layers), then pinch connections."""
    candidates = np.flatnonzero(faces.nnc_kind >= 0)
    face_nnc = candidates[(faces.neighbors[candidates] >= 0).all(axis=1)]
    nnc_cells = np.concatenate([faces.neighbors[face_nnc], pinch_pairs]).astype(np.int64)
    return NNC(
        nnc_cells,
        cell_global[nnc_cells],
        np.concatenate([faces.nnc_kind[face_nnc], np.full(pinch_pairs.shape[0], PINCH, np.int8)]),
        np.concatenate([face_nnc, np.full(pinch_pairs.shape[0], -1)]),
    )


_CHUNK = 1 << 16  # faces handled per block when the face arrays are filled


class _FaceArrays:
    """The face arrays of the grid, allocated once and filled block by block in face order."""

    def __init__(self, num_faces: int, max_nodes: int) -> None:
        self.counts = np.empty(num_faces, dtype=np.int64)
        self._buffer = np.empty(max_nodes, dtype=np.int64)
        self.neighbors = np.empty((num_faces, 2), dtype=np.int64)
        self.tags = np.empty((num_faces, 2), dtype=np.int8)  # half-face tags of both sides
        self.fault = np.zeros(num_faces, dtype=np.int32)
        self.nnc_kind = np.full(num_faces, -1, dtype=np.int8)
        self.num = 0
        self.num_nodes = 0

    @property
    def nodes(self) -> IntArray:
        return self._buffer[: self.num_nodes]

    @property
    def pos(self) -> IntArray:
        return offsets(self.counts[: self.num])

    def add(self, counts: IntArray, nodes: IntArray) -> slice:
        """Append faces (ragged: node counts and flat node cycles); returns their slice."""
        added = slice(self.num, self.num + counts.size)
        self.counts[added] = counts
        self._buffer[self.num_nodes : self.num_nodes + nodes.size] = nodes
        self.num += counts.size
        self.num_nodes += nodes.size
        return added

    def add_quads(self, quads, table: IntArray) -> slice:
        """Append lateral quads; one collapsed on a pillar (top = bottom there) is a triangle."""
        first = self.num
        for start in range(0, quads.num, _CHUNK):
            q = quads.nodes(table, slice(start, start + _CHUNK))
            keep = q != q[:, [1, 2, 3, 0]]
            if keep.all():
                self.add(np.full(q.shape[0], 4), q.reshape(-1))
            else:
                self.add(keep.sum(axis=1), q[keep])
        return slice(first, self.num)

    def add_vertical(
        self, ver, table: IntArray, touched: IntArray, t_pos: IntArray, t_nodes: IntArray
    ) -> slice:
        """Append top/bottom faces; faces ``touched`` take the cycles (t_pos, t_nodes) instead."""
        first = self.num
        for start in range(0, ver.num, _CHUNK):
            stop = min(start + _CHUNK, ver.num)
            q = ver.nodes(table, slice(start, stop))
            lo, hi = np.searchsorted(touched, [start, stop])
            if lo == hi:
                self.add(np.full(q.shape[0], 4), q.reshape(-1))
                continue
            rows = touched[lo:hi] - start
            counts = np.full(q.shape[0], 4)
            counts[rows] = np.diff(t_pos[lo : hi + 1])
            pos = offsets(counts)
            nodes = np.empty(int(pos[-1]), dtype=np.int64)
            plain = np.ones(q.shape[0], dtype=bool)
            plain[rows] = False
            nodes[pos[:-1][plain][:, None] + np.arange(4)] = q[plain]
            nodes[ragged_arange(pos[:-1][rows], counts[rows])] = t_nodes[t_pos[lo] : t_pos[hi]]
            self.add(counts, nodes)
        return slice(first, self.num)

    def keep(self, keep: np.ndarray) -> None:
        """Keep only the faces where ``keep`` is True."""
        counts = self.counts[keep]
        self._buffer = self.nodes[ragged_arange(self.pos[:-1][keep], counts)]
        self.num_nodes = self._buffer.size
        self.counts, self.num = counts, counts.size
        self.neighbors, self.tags = self.neighbors[keep], self.tags[keep]
        self.fault, self.nnc_kind = self.fault[keep], self.nnc_kind[keep]

    def reverse_cycles(self) -> None:
        """Reverse the node cycle of every face in place (a block of faces at a time)."""
        pos, nodes = self.pos, self.nodes
        for start in range(0, self.num, _CHUNK):
            stop = min(start + _CHUNK, self.num)
            local = pos[start : stop + 1] - pos[start]
            counts = np.diff(local)
            owner = np.repeat(np.arange(stop - start), counts)
            within = np.arange(local[-1]) - local[owner]
            block = nodes[pos[start] : pos[stop]]
            block[:] = block[local[owner] + counts[owner] - 1 - within]

    def renumber_nodes(self, node_map: IntArray) -> None:
        """Replace every node id n by ``node_map[n]``, in place."""
        nodes = self.nodes
        for start in range(0, nodes.size, 1 << 20):
            block = nodes[start : start + (1 << 20)]
            block[:] = node_map[block]


def _removed_by_pore_volume(deck: Deck, cn, bulk, minpv: float | None, notes: list[str]):
    """Kept cells whose pore volume (``bulk`` x PORO x NTG x MULTPV, or PORV) is below MINPV
    (removed by Flow), or None when nothing is removed. Raises for a negative pore volume
    left active, or an infinite one."""
    threshold = minimum_pore_volumes(deck, minpv)
    if not has_pore_volume(deck):
        if threshold is not None:
            notes.append("MINPV not applied: the deck has no PORO (nor PORV)")
        return None
    kept = np.flatnonzero(cn.kept.ravel())
    pv = pore_volumes(deck, kept, bulk)
    small = pv < threshold[kept] if threshold is not None else np.zeros(kept.size, dtype=bool)
    negative = ~((pv >= 0) & np.isfinite(pv)) & ~small
    if negative.any():
        first = int(np.flatnonzero(negative)[0])
        raise InputError(
            f"{deck.source}: {int(negative.sum())} active cells have a negative or infinite pore volume "
            f"(first: cell {ijk_text(deck, int(kept[first]))}, {float(pv[first])!r}; "
            "from PORO, NTG, MULTPV or PORV)"
        )
    if not small.any():
        return None
    if small.all():
        raise InputError(f"{deck.source}: every cell has a pore volume below MINPV")
    shown = f"MINPV {threshold[0]:g}" if (threshold == threshold[0]).all() else "MINPVV"
    notes.append(f"{int(small.sum())} cells with a pore volume below {shown} were made inactive")
    return small


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


def _fault_tags(deck, general, faulted_pair, pair_p1, pair_p2):
    """Fault tags of the general pieces, the tag names, and the FAULTS names' tags.

    On a faulted pair, a piece is on the fault if it joins cells whose lines
    differ, or a cell to a void (the fault exposes it); matched pieces (beyond a
    fault tip, say) are not. Quads of simple pairs are never on a faulted pair.
    """
    n_pairs = pair_p1.size
    cell_void = (general.cell_a < 0) | (general.cell_b < 0)
    on_fault = faulted_pair[general.pair] & (general.mismatch | cell_void)
    # One id per connected fault trace: faulted pairs linked by shared pillars.
    fp = np.flatnonzero(faulted_pair)
    n_pil = int(max(pair_p1.max(), pair_p2.max())) + 1
    graph = sparse.coo_matrix((np.ones(fp.size), (pair_p1[fp], pair_p2[fp])), shape=(n_pil, n_pil))
    _, label = csgraph.connected_components(graph, directed=False)
    trace_of_pair = np.full(n_pairs, -1)
    trace_of_pair[fp] = label[pair_p1[fp]]
    traces, trace_id = np.unique(trace_of_pair[fp], return_inverse=True)

    names: list[str] = []
    seen: dict[str, int] = {}
    for seg in deck.faults:  # FAULTS keyword lines: a few hundred at most
        if seg.name not in seen:
            seen[seg.name] = len(seen) + 1
            names.append(seg.name)
    offset = len(names)
    id_of_pair = np.zeros(n_pairs, dtype=np.int32)
    id_of_pair[fp] = offset + 1 + trace_id
    tags = np.zeros(general.pair.size, dtype=np.int32)
    tags[on_fault] = id_of_pair[general.pair[on_fault]]
    names += [f"fault_{t + 1}" for t in range(traces.size)]
    return tags, tuple(names), seen


class _NamedFaults:
    """The FAULTS lines of a deck as lookup tables over (layer, pillar pair), for either side.

    A line (box, face X) names the +i faces of its cells: the pairs at i + 1 for
    the box's rows j, and there the faces whose box-side layer (the A cell's k,
    or the B cell's where A is a void) lies in the box's layers. X- names the -i
    faces (pairs at i, box side B); Y and Y- the same along j. Z names the bottom
    faces of its cells (also one joining a cell further down across removed
    cells), Z- their top faces: the horizontal steps of an inclined fault on
    vertical pillars. Where lines overlap, the later one wins (as if applied in
    order).
    """

    def __init__(self, deck: Deck, pairs: _PillarPairs, seen: dict[str, int]) -> None:
        nx, ny, nz = deck.cart_dims
        n_ipairs = (nx + 1) * ny
        # line number + 1 per (side, layer, pair), 0 = none; a loop over FAULTS lines, each a slice
        self.line = np.zeros((2, nz, pairs.num), dtype=np.int32)
        i_view = self.line[:, :, :n_ipairs].reshape(2, nz, ny, nx + 1)
        j_view = self.line[:, :, n_ipairs:].reshape(2, nz, ny + 1, nx)
        self.z_line = np.zeros((2, nz, ny * nx), dtype=np.int32)  # (Z: cell above, Z-: below; k, column)
        z_view = self.z_line.reshape(2, nz, ny, nx)
        for n, seg in enumerate(deck.faults):
            if seg.face in ("Z", "Z-"):
                below = int(seg.face == "Z-")
                z_view[below, seg.k1 : seg.k2 + 1, seg.j1 : seg.j2 + 1, seg.i1 : seg.i2 + 1] = n + 1
                continue
            plus = not seg.face.endswith("-")
            shift = 1 if plus else 0
            ks = slice(max(seg.k1, 0), seg.k2 + 1)
            if seg.face.startswith("Y"):
                j_view[0 if plus else 1, ks, seg.j1 + shift : seg.j2 + shift + 1, seg.i1 : seg.i2 + 1] = n + 1
            else:
                i_view[0 if plus else 1, ks, seg.j1 : seg.j2 + 1, seg.i1 + shift : seg.i2 + shift + 1] = n + 1
        self.tag_of_line = np.array([0] + [seen[seg.name] for seg in deck.faults], dtype=np.int32)

    @property
    def has_z(self) -> bool:
        return bool(self.z_line.any())

    def vertical_tags(self, column: IntArray, k_up: IntArray, k_down: IntArray) -> IntArray:
        """Name tags (0 = none) of the top/bottom faces in ``column`` between the cells of layers
        k_up (above) and k_down (below), -1 = outside."""
        line_up = np.where(k_up >= 0, self.z_line[0, np.maximum(k_up, 0), column], 0)
        line_down = np.where(k_down >= 0, self.z_line[1, np.maximum(k_down, 0), column], 0)
        return self.tag_of_line[np.maximum(line_up, line_down)]

    def tags(self, pair: IntArray, k_a: IntArray, k_b: IntArray) -> IntArray:
        """Name tags (0 = none) of the lateral faces on ``pair`` between layers k_a and k_b (-1 = void)."""
        line_a = self.line[0, np.where(k_a >= 0, k_a, k_b), pair]
        line_b = self.line[1, np.where(k_b >= 0, k_b, k_a), pair]
        return self.tag_of_line[np.maximum(line_a, line_b)]


def _compact_fault_tags(fault: IntArray, names: tuple[str, ...], n_named: int) -> tuple[str, ...]:
    """Drop the automatic fault names no face carries (FAULTS names took their faces) and
    renumber the automatic tags after the named ones; ``fault`` is changed in place."""
    used = np.zeros(len(names) + 1, dtype=bool)
    used[fault] = True
    used[: n_named + 1] = True
    if used.all():
        return names
    new_tag = (np.cumsum(used) - 1).astype(np.int32)
    fault[:] = new_tag[fault]
    return tuple(name for name, u in zip(names, used[1:], strict=True) if u)


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
