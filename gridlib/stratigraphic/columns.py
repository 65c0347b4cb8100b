"""``extrude_columns``: the pillar engine on the columns of any areal 2-D grid (generalised pillar grids).

The areal grid's cells (polygons of any sizes: Voronoi/PEBI cells, triangles,
quadrilaterals) are the *columns*, its nodes the *pillars* and every areal edge
a *pillar pair* with at most two columns (ALGORITHMS.md §3.4, "a cleaner design
for us"). A *corner* is a (cell, position in its node ring) pair, the ring being
:func:`areal_corners`' cycle; each corner has a depth at every layer interface
(level): the top of layer k is level k, its bottom level k + 1, within a column.
Across a fault edge the two columns carry different depths on the same pillar.
From there on everything is the corner-point engine (ALGORITHMS.md §1):

1. cells masked by ``active`` are removed before anything else: their corners
   (possibly junk) are never read; the used corners must be finite, and no
   active cell may have its bottom above its top;
2. the distinct depths on every pillar are numbered (node ids grow with depth
   along a pillar; pillars where every column agrees at every level take a
   fast path), so that all topology tests compare integer ranks; depths equal
   up to rounding (within the pillar's depth resolution,
   :mod:`~gridlib.stratigraphic.points`) are one point, so that no face of zero
   area (nodes collinear up to rounding) is ever made;
3. cells of zero thickness on all their pillars are removed (the cells above
   and below then touch and share a face, as in ``process_grdecl``);
4. lateral faces: pairs whose two sides hold the same cells with the same
   corner nodes (no fault) or cells on one side only give one quadrilateral per
   cell (a triangle where collapsed on one pillar); the others go to
   :func:`~gridlib.stratigraphic.lateral.general_pieces`, which subdivides them
   exactly where fault throw makes the corners mismatch, with crossing nodes;
5. top and bottom faces by walking every column through its kept cells, with
   the crossing nodes inserted into their edges (every cell watertight);
6. with inclined pillars, faces of zero area (on pillars that coincide, a
   pair of no width) are removed; then cells with fewer than four faces.

Orientation: the column on the left of an areal edge p1 -> p2 (in plan view,
x right and y up) is side A, as the lower-i column of an i-pair in
``process_grdecl``; it is ``neighbors[e, 0]`` of the areal grid (its 2-D
convention), with p1, p2 the edge's nodes swapped if the whole areal grid is
oriented clockwise. Lateral normals point from A to B, top/bottom normals down
(+z, from the upper cell to the lower one): volumes are positive.

Numbering, as ``make_layered_grid`` (which it reproduces exactly, nodes,
faces and cells, on unfaulted input with vertical pillars): nodes by their rank
along their pillar, then pillar (layer interface by interface where no fault
adds points), crossing nodes last; faces are first the top/bottom faces by
interface, then column (the bottom face of an upper cell before the top face of
a lower one where they do not touch), then the lateral quadrilaterals by layer,
then areal edge, then the pieces of the subdivided pairs by (layer, edge).
Cells are numbered layer by layer, columns in areal order; ``index_map`` is
``layer * n_areal_cells + column``, or the index in the logical box when the
areal grid has 2-D ``cart_dims`` (then ``cart_dims`` gets the number of layers).

Units: metres; z is depth, positive downwards.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from contextlib import suppress
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike
from scipy import sparse
from scipy.sparse import csgraph

from ..connectivity import (
    cell_half_faces,
    cell_node_cycles_2d,
    drop_repeated_nodes,
    half_face_cycle_slots,
    offsets,
    ragged_arange,
    renumbering,
    repeat_ids,
)
from ..errors import GridError, InputError
from ..grid import B, Cells, Faces, FloatArray, Grid, IntArray, Layering, Nodes, T
from ..threads import num_threads
from .conformal import edge_insertions, insert_after
from .lateral import LateralFaces, SideCells, general_pieces
from .nnc import FAULT, NNC, PINCH
from .points import depth_resolution, points_on_pillars, unique_points

__all__ = ["ColumnGrid", "areal_corners", "extrude_columns"]

_BLOCK = 1 << 14  # pairs per block when quads are written


@dataclass(frozen=True, eq=False)
class ColumnGrid:
    """What :func:`extrude_columns` returns.

    ``nnc``: cell pairs sharing a face whose layers differ, as in
    ``process_grdecl``: kind FAULT for lateral faces across faults, kind PINCH
    for top/bottom faces joining cells across removed (collapsed) layers;
    ``nnc.global_cells`` are ``cells.index_map`` values.
    ``fault_names[t - 1]`` names fault tag t of ``faces.tag``.
    """

    grid: Grid
    nnc: NNC
    fault_names: tuple[str, ...]
    notes: tuple[str, ...]


def areal_corners(areal: Grid) -> tuple[IntArray, IntArray]:
    """The corners of an areal grid: ``(pos, ring)``, cell c's node ring ``ring[pos[c]:pos[c+1]]``.

    Corner q = pos[c] + i is the i-th node of cell c's ring; the depths given to
    :func:`extrude_columns` are per corner in this order. The ring follows the
    cell's edges with the cell on their left (counter-clockwise for a grid
    oriented as gridlib's 2-D convention), as
    :func:`~gridlib.connectivity.cell_node_cycles_2d`.

    >>> from gridlib import cart_grid
    >>> pos, ring = areal_corners(cart_grid([2, 1]))
    >>> pos.tolist(), ring.tolist()
    ([0, 4, 8], [3, 0, 1, 4, 4, 1, 2, 5])
    """
    if not isinstance(areal, Grid) or areal.griddim != 2:
        what = f"a {areal.griddim}-D grid" if isinstance(areal, Grid) else type(areal).__name__
        raise GridError(f"areal: expected a 2-D grid (griddim 2), got {what}")
    return cell_node_cycles_2d(areal)


def extrude_columns(
    areal: Grid,
    z: ArrayLike,
    *,
    pillars: ArrayLike | None = None,
    active: ArrayLike | None = None,
    edge_tag: ArrayLike | None = None,
    fault_names: tuple[str, ...] | None = None,
) -> ColumnGrid:
    """Cells between layer interfaces in every column of ``areal`` (see the module docstring).

    ``z`` (n_levels >= 2, n_corners): depth (m, z down) of every corner (the
    order of :func:`areal_corners`) at every layer interface, top first; layer
    k lies between levels k and k + 1. ``pillars``: None for vertical pillars
    through the areal nodes, or (n_areal_nodes, 2, 3) straight pillars, the top
    and bottom points (x, y, z) of each, as COORD (a corner lies where its
    pillar reaches its depth). ``active`` (n_layers, n_areal_cells) booleans:
    False cells are removed before anything else (their depths are never
    read). ``edge_tag`` (n_areal_edges,): fault id of every areal edge (default
    the areal grid's ``faces.tag``), carried by every lateral face on the edge;
    ``fault_names`` names those ids (default ``fault_<id>``). Faulted edges
    without a tag get an id per connected fault trace, as in ``process_grdecl``.

    >>> from gridlib import cart_grid, compute_geometry
    >>> areal = cart_grid([2, 1], [2.0, 1.0])
    >>> z = np.array([[100.0] * 8, [110.0] * 4 + [112.0] * 4, [120.0] * 8])  # a throw in layer 0
    >>> r = extrude_columns(areal, z)
    >>> r.grid.num_cells, r.grid.num_faces, r.nnc.num, r.fault_names
    (4, 21, 1, ('fault_1',))
    >>> compute_geometry(r.grid).cell_volumes.tolist()
    [10.0, 12.0, 10.0, 8.0]
    """
    return extrude_column_corners(areal, ColumnCorners.of(areal), z, pillars, active, edge_tag, fault_names)


def extrude_column_corners(
    areal, corners, z, pillars, active, edge_tag, fault_names, step: str = "extrude_columns"
) -> ColumnGrid:
    """:func:`extrude_columns` with the areal corners already known (``ColumnCorners.of(areal)``);
    ``step`` is the entry the grid's history gets after the areal grid's."""
    pos2, owner = corners.pos, corners.owner
    nc2, nn2 = areal.num_cells, areal.num_nodes
    z = _depths(z, corners.num)
    n_levels = z.shape[0]
    nl = n_levels - 1
    act = _active(active, nl, nc2)
    lines = pillar_lines(pillars, nn2)
    etag = _edge_tags(edge_tag, areal)
    names = _names(fault_names, etag)
    notes: list[str] = []

    reverse = _clockwise(areal, corners)
    if reverse:  # orient every ring counter-clockwise: top normals point down
        corners = corners.reversed()
        z = z[:, corners.perm]
    ring = corners.ring

    everything = bool(act.all())
    used = None
    if not everything:
        if not act.any():
            raise InputError("active: no active cell")
        used_cell = np.zeros((n_levels, nc2), dtype=bool)
        used_cell[:-1] |= act
        used_cell[1:] |= act
        used = np.take(used_cell, owner, axis=1)
    _check_used_depths(z, used, act, owner, pos2)

    pts, node_of = _number_points(z, ring, used, nn2)
    del z, used  # the depths are ranks from here on (and the caller's may be the only other reference)

    # Cells: active and not collapsed on all their pillars, numbered layer by layer.
    collapsed = np.logical_and.reduceat(node_of[1:] == node_of[:-1], pos2[:-1], axis=1)
    kept = ~collapsed if everything else act & ~collapsed
    n_collapsed = int(np.count_nonzero(act & collapsed))
    if n_collapsed:
        notes.append(f"{n_collapsed} cells of zero thickness on all their pillars were removed")
    n_cells = int(np.count_nonzero(kept))
    if n_cells == 0:
        raise InputError("z: every active cell has zero thickness (collapsed on all pillars)")
    cell_id = np.full((nl, nc2), -1, dtype=np.int64)
    cell_id[kept] = np.arange(n_cells)

    pairs = PillarPairs.of(areal, corners, reverse)
    ver, h_nodes = _vertical(node_of, kept, cell_id, pos2)
    xy = areal.nodes.coords[:, :2]
    lat = _lateral(pairs, node_of, kept, cell_id, pts, _NodeCoords(pts, xy, lines))
    n_points, n_cross = pts.num_nodes, lat.general.crossing_coords.shape[0]
    coords = pts.coords(xy, lines, n_cross)
    coords[n_points:] = lat.general.crossing_coords
    del pts

    # Crossing nodes go into the top/bottom faces of the cells next to a subdivided pair.
    insert = None
    if n_cross:
        near = np.zeros(n_cells + 1, dtype=bool)  # index -1 (outside): the extra False
        near[lat.general_cells] = True
        touched = np.flatnonzero(near[ver.upper] | near[ver.lower])
        insert = _crossings_in_faces(ver.pos, h_nodes, touched, lat.general, n_points, coords)

    n_h, n_q = ver.upper.size, lat.num_quads
    top_face, bottom_face = ver.top_face, ver.bottom_face
    # The cells' half-faces as the construction gives them (used unless faces are removed below),
    # on a second thread while the faces are assembled: the two only read what they share.
    structured_cells = _in_background(
        _cell_half_faces, top_face, bottom_face, lat, corners, pairs, kept, cell_id, n_h, n_q
    )
    faces = _FaceList.join(ver, h_nodes, insert, lat, node_of, etag, pairs)
    del node_of, h_nodes, insert, ver  # in the faces now
    structured = True  # the cells' faces follow from the construction (else: transpose neighbors)
    if lines is not None:  # inclined pillars may coincide (a deck's collapsed pillars): pairs of no width
        zero = _zero_area(coords, faces.pos, faces.nodes, np.arange(faces.num))
        if zero.any():
            notes.append(f"{int(zero.sum())} faces of zero area were removed")
            faces = faces.subset(~zero)
            structured = False

    cell_k, cell_c = np.nonzero(kept)
    if structured:
        face_pos, half = structured_cells()
    else:
        with suppress(Exception):  # not needed: wait for it, whatever it gives
            structured_cells()
        face_pos, half = cell_half_faces(faces.neighbors, n_cells)
    alive = np.diff(face_pos) >= 4
    if not alive.all():
        notes.append(f"{int((~alive).sum())} cells with fewer than four faces were removed")
        remap = renumbering(alive)
        nb = np.where(faces.neighbors >= 0, remap[np.maximum(faces.neighbors, 0)], -1)
        faces = faces.with_neighbors(nb).subset((nb >= 0).any(axis=1))
        cell_k, cell_c = cell_k[alive], cell_c[alive]
        n_cells = cell_k.size
        face_pos, half = cell_half_faces(faces.neighbors, n_cells)

    if not (kept.all() and faces.num == n_h + n_q + lat.num_general):
        # Every node is used when every cell is kept and no face was removed: each point is a
        # corner of a kept cell's top or bottom (or shared) face; crossing nodes are in pieces.
        faces, coords = faces.drop_unused_nodes(coords)
    names = _fault_names(faces, names, lat, pairs, etag)
    half_tags = None if faces.half_tags is None else faces.half_tags.reshape(-1)[half]
    cell_faces = np.right_shift(half, 1, out=half)

    if areal.cart_dims is not None and len(areal.cart_dims) == 2:
        nx, ny = areal.cart_dims
        im2 = np.arange(nc2) if areal.cells.index_map is None else areal.cells.index_map
        index_map = im2[cell_c] + cell_k * (nx * ny)
        cart_dims = (nx, ny, nl)
    else:
        index_map, cart_dims = cell_k * nc2 + cell_c, None
    grid = Grid(
        cells=Cells(face_pos, cell_faces, half_tags, index_map),
        faces=Faces(faces.pos, faces.nodes, faces.neighbors, faces.tag),
        nodes=Nodes(coords),
        griddim=3,
        cart_dims=cart_dims,
        history=(*areal.history, step),
        layering=Layering(areal, cell_c, cell_k, nl),
    )
    return ColumnGrid(grid, faces.nnc(index_map), names, tuple(notes))


def _in_background(fn, *args):
    """Start ``fn(*args)`` on another thread (numpy releases the GIL in its loops) where there
    is a second core; return a function that waits for its result (or re-raises its error)."""
    if num_threads(2) < 2:
        result = fn(*args)
        return lambda: result
    pool = ThreadPoolExecutor(1)
    future = pool.submit(fn, *args)
    pool.shutdown(wait=False)
    return future.result


@dataclass(frozen=True, eq=False)
class ColumnCorners:
    """The corners of the areal cells: ring ``pos``/``ring``, the cell of every corner, and for
    every areal half-face (entry h of ``cells.faces``) the corner of its first and second node
    walking with the cell on the left; ``perm`` maps corners to the caller's order."""

    pos: IntArray
    ring: IntArray
    owner: IntArray
    hf_first: IntArray
    hf_second: IntArray
    perm: IntArray | None = None

    @classmethod
    def of(cls, areal: Grid) -> ColumnCorners:
        if not isinstance(areal, Grid) or areal.griddim != 2:
            areal_corners(areal)  # raises
        start, slot = half_face_cycle_slots(areal)
        pos = areal.cells.face_pos
        ring = np.empty_like(start)
        ring[slot] = start
        owner = repeat_ids(pos)
        nxt = np.arange(1, ring.size + 1)
        nxt[pos[1:] - 1] = pos[:-1]
        return cls(pos, ring, owner, slot, nxt[slot])

    @property
    def num(self) -> int:
        return self.ring.size

    def reversed(self) -> ColumnCorners:
        """Every ring walked backwards (a reversal within each cell is its own inverse)."""
        local = np.arange(self.num) - self.pos[self.owner]
        perm = self.pos[self.owner] + (np.diff(self.pos)[self.owner] - 1 - local)
        return ColumnCorners(
            self.pos, self.ring[perm], self.owner, perm[self.hf_first], perm[self.hf_second], perm
        )


# --------------------------------------------------------------------------- inputs


def _depths(z: ArrayLike, n_corners: int) -> FloatArray:
    try:
        arr = np.asarray(z, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"z: expected an array of depths (n_levels, {n_corners}) ({exc})") from exc
    if arr.ndim != 2 or arr.shape[1] != n_corners or arr.shape[0] < 2:
        raise InputError(
            f"z: expected depths of shape (n_levels >= 2, {n_corners}) (one per level and areal cell "
            f"corner), got shape {arr.shape}"
        )
    return arr


def _active(active: ArrayLike | None, nl: int, nc2: int) -> np.ndarray:
    if active is None:
        return np.ones((nl, nc2), dtype=bool)
    arr = np.asarray(active)
    if arr.shape != (nl, nc2):
        raise InputError(f"active: expected shape (n_layers, n_areal_cells) = ({nl}, {nc2}), got {arr.shape}")
    if arr.dtype != bool:
        if not np.issubdtype(arr.dtype, np.number) or not np.isin(arr, (0, 1)).all():
            raise InputError("active: expected booleans (or 0/1) per layer and areal cell")
        arr = arr != 0
    return arr


def pillar_lines(pillars: ArrayLike | None, nn2: int) -> FloatArray | None:
    if pillars is None:
        return None
    try:
        arr = np.asarray(pillars, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"pillars: expected ({nn2}, 2, 3) top and bottom points ({exc})") from exc
    if arr.shape == (nn2, 6):
        arr = arr.reshape(nn2, 2, 3)
    if arr.shape != (nn2, 2, 3):
        raise InputError(
            f"pillars: expected the top and bottom points (x, y, z) of one pillar per areal node, "
            f"shape ({nn2}, 2, 3) or ({nn2}, 6), got {arr.shape}"
        )
    if not np.isfinite(arr).all():
        raise InputError("pillars: coordinates must be finite")
    return arr


def _edge_tags(edge_tag: ArrayLike | None, areal: Grid) -> IntArray:
    if edge_tag is None:
        return np.asarray(areal.faces.tag, dtype=np.int64)
    arr = np.asarray(edge_tag)
    if arr.shape != (areal.num_faces,) or not np.issubdtype(arr.dtype, np.integer) or (arr < 0).any():
        raise InputError(
            f"edge_tag: expected one non-negative integer per areal edge ({areal.num_faces}), "
            f"got {arr.dtype} of shape {arr.shape}"
        )
    return arr.astype(np.int64)


def _names(fault_names, etag: IntArray) -> list[str]:
    n = int(etag.max(initial=0))
    if fault_names is None:
        return [f"fault_{t}" for t in range(1, n + 1)]
    names = list(fault_names)
    if len(names) < n or not all(isinstance(s, str) for s in names):
        raise InputError(f"fault_names: expected at least {n} names (one per edge tag), got {fault_names!r}")
    return names


def _clockwise(areal: Grid, corners: ColumnCorners) -> bool:
    """Whether every ring turns clockwise in plan view (raises if some do and some do not)."""
    pos2, ring = corners.pos, corners.ring
    xy = areal.nodes.coords[:, :2]
    local = xy - xy.mean(axis=0)  # shoelace products lose digits at UTM sizes
    nxt = np.arange(1, ring.size + 1)
    nxt[pos2[1:] - 1] = pos2[:-1]
    a, b = local[ring], local[ring[nxt]]
    area2 = np.bincount(corners.owner, a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1], pos2.size - 1)
    if np.any(area2 == 0):
        raise GridError(f"areal: cell {int(np.flatnonzero(area2 == 0)[0])} has zero area in plan view")
    flip = area2 < 0
    if flip.any() and not flip.all():
        raise GridError(
            f"areal: the grid folds over itself in plan view (cells {np.flatnonzero(flip)[:5].tolist()} "
            "turn clockwise, the others counter-clockwise)"
        )
    return bool(flip[0])


def _check_used_depths(z: FloatArray, used, act: np.ndarray, owner: IntArray, pos2: IntArray) -> None:
    """Depths of the corners of active cells (``used`` corners, None: all) must be finite,
    bottoms at or below tops."""
    finite = np.isfinite(z)
    if not finite.all():
        bad = ~finite if used is None else ~finite & used
        if bad.any():
            k, q = np.argwhere(bad)[0]
            raise InputError(
                f"z: level {k}, corner {q} (areal cell {owner[q]}) of an active cell is NaN or infinite "
                f"({int(bad.sum())} such depths; mask undefined cells with active=)"
            )
    with np.errstate(invalid="ignore"):
        inverted = z[1:] < z[:-1]
        if used is not None:
            inverted &= np.take(act, owner, axis=1)
    if inverted.any():
        k, q = np.argwhere(inverted)[0]
        raise InputError(
            f"z: the cell in layer {k} of areal cell {owner[q]} has its bottom above its top at its corner "
            f"{q - pos2[owner[q]]} ({z[k, q]:g} > {z[k + 1, q]:g}); depths must not decrease downwards"
        )


# --------------------------------------------------------------------------- points


@dataclass(frozen=True, eq=False)
class _LevelMajor:
    """Node ids of the points on the pillars, numbered by rank along their pillar, then pillar
    (``make_layered_grid``'s level-major order: the nodes of a layer interface are close in
    memory). The first ``dense`` ranks, which every pillar has, are numbered in closed form,
    ``rank * n_pillars + pillar``; the points of higher ranks (on pillars with more points than
    the others: faults, masks) by the position of their key ``rank * n_pillars + pillar`` in the
    sorted ``tail``, after the dense ones."""

    n_pillars: int
    dense: int
    tail: IntArray

    @classmethod
    def of(cls, count: IntArray) -> _LevelMajor:
        """The numbering of pillars with ``count[p]`` points."""
        n = count.size
        dense = int(count.min()) if n else 0
        extra = count - dense
        tall = np.flatnonzero(extra)
        rank = ragged_arange(np.full(tall.size, dense), extra[tall])
        tail = rank * n + np.repeat(tall, extra[tall])
        tail.sort()
        return cls(n, dense, tail)

    @property
    def num(self) -> int:
        return self.dense * self.n_pillars + self.tail.size

    def ids(self, rank: IntArray, pillar: IntArray | int) -> IntArray:
        """The id of the point of rank ``rank`` on pillar ``pillar`` (broadcast together)."""
        ids = rank * self.n_pillars + pillar
        if self.tail.size:
            high = np.flatnonzero(ids.reshape(-1) >= self.dense * self.n_pillars)
            flat = ids.reshape(-1)
            flat[high] = self.dense * self.n_pillars + np.searchsorted(self.tail, flat[high])
        return ids

    def keys(self, ids: IntArray) -> IntArray:
        """``rank * n_pillars + pillar`` of the points ``ids`` (1-D)."""
        keys = ids.copy()
        high = np.flatnonzero(ids >= self.dense * self.n_pillars)
        keys[high] = self.tail[ids[high] - self.dense * self.n_pillars]
        return keys

    def rank(self, ids: IntArray) -> IntArray:
        return self.keys(ids) // self.n_pillars


@dataclass(frozen=True, eq=False)
class _Points:
    """The distinct points on the pillars: their ids (:class:`_LevelMajor`), depths ``z`` in that
    order, and ``offset`` (n_pillars + 1,) of the pillar-major numbering ``offset[p] + rank`` in
    which the general pillar-pair engine works (``pm_to_ids`` maps those to ours)."""

    ids: _LevelMajor
    z: FloatArray
    offset: IntArray

    @property
    def num_nodes(self) -> int:
        return self.z.size

    def pm_to_ids(self, pm: IntArray) -> IntArray:
        pillar = np.searchsorted(self.offset, pm, "right") - 1
        return self.ids.ids(pm - self.offset[pillar], pillar)

    def coords(self, xy: FloatArray, lines: FloatArray | None, n_extra: int) -> FloatArray:
        """(num_nodes + n_extra, 3) node coordinates, the ``n_extra`` last rows left to fill."""
        n, dense, tail = self.ids.n_pillars, self.ids.dense, self.ids.tail
        n_dense = dense * n
        out = np.empty((self.num_nodes + n_extra, 3))
        if lines is None:
            out[:n_dense].reshape(dense, n, 3)[:, :, :2] = xy  # the dense ranks: every pillar in order
            out[n_dense : self.num_nodes, :2] = xy[tail % n]
            out[: self.num_nodes, 2] = self.z
        else:
            pillar = np.concatenate([np.tile(np.arange(n), dense), tail % n])
            points_on_pillars(lines, pillar, self.z, out=out[: self.num_nodes])
        return out


class _NodeCoords:
    """``self[pm]``: the coordinates of points given by pillar-major ids (as the general engine
    asks for them), without the whole coordinate array."""

    def __init__(self, pts: _Points, xy: FloatArray, lines: FloatArray | None) -> None:
        self.pts, self.xy, self.lines = pts, xy, lines

    def __getitem__(self, pm: IntArray) -> FloatArray:
        pts = self.pts
        ids = pts.pm_to_ids(pm)
        pillar, z = pts.ids.keys(ids) % pts.ids.n_pillars, pts.z[ids]
        if self.lines is None:
            return np.column_stack([self.xy[pillar], z])
        return points_on_pillars(self.lines, pillar, z)


def _number_points(
    z: FloatArray, ring: IntArray, used: np.ndarray | None, nn2: int
) -> tuple[_Points, IntArray]:
    """The distinct points on every pillar and the node (n_levels, n_corners) of every corner.

    ``used`` (n_levels, n_corners): the corners of active cells (None: all).
    Fast path: on a pillar where every corner has the same depth as one
    reference corner at every level (no fault, no masked junk) and those depths
    do not decrease, the points are the reference's distinct depths in level
    order (distinct beyond the pillar's depth resolution). The other pillars
    number the depths of their used corners with
    :func:`~gridlib.stratigraphic.points.unique_points`, which decides
    distinctness the same way. Unused corners of those get node -1. Node ids
    grow with depth along every pillar.
    """
    n_corners = z.shape[1]
    ref = np.full(nn2, -1, dtype=np.int64)
    ref[ring] = np.arange(n_corners)  # any corner of the pillar will do
    has = ref >= 0
    differ = np.zeros(n_corners, dtype=bool)
    ref_of_corner = ref[ring]
    with np.errstate(invalid="ignore"):
        for level in z:  # a level at a time: small temporaries
            differ |= level != level[ref_of_corner]  # NaN differs from everything
        zp = np.take(z, ref, axis=1)  # (n_levels, nn2); junk where a pillar has no corner
        regular = has & (np.diff(zp, axis=0) >= 0).all(axis=0) & np.isfinite(zp).all(axis=0)
    regular[ring[differ]] = False

    new = np.ones(zp.shape, dtype=bool)
    with np.errstate(invalid="ignore"):  # junk (NaN, inf) on pillars that are not regular: unused
        rho = depth_resolution(np.maximum(np.abs(zp[0]), np.abs(zp[-1])))
        np.greater(zp[1:] - zp[:-1], rho, out=new[1:])  # equal up to rounding: one point
    rank = np.cumsum(new, axis=0)
    rank -= 1
    count = np.where(regular, rank[-1] + 1, 0)

    irr_corner = np.flatnonzero(~regular[ring])
    irr = None
    if irr_corner.size:
        sub = np.ones((z.shape[0], irr_corner.size), bool) if used is None else used[:, irr_corner]
        lev, q = np.nonzero(sub)
        q = irr_corner[q]
        irr = unique_points(ring[q], z[lev, q], nn2)
        count += np.diff(irr.offset)
    ids = _LevelMajor.of(count)

    table = ids.ids(rank, np.arange(nn2))  # (n_levels, nn2): node of every level of a regular pillar
    if irr is None and has.all() and ids.num == table.size:  # every level a point of its own
        z_ids = zp.reshape(-1)
    else:
        z_ids = np.empty(ids.num)
        first = new & regular  # the first level at every point of a regular pillar
        z_ids[table[first]] = zp[first]
    if irr is not None:
        irr_rank = np.arange(irr.num_nodes) - irr.offset[irr.pillar]
        irr_ids = ids.ids(irr_rank, irr.pillar)
        z_ids[irr_ids] = irr.z
    node_of = np.take(table, ring, axis=1)
    if irr is not None:
        node_of[:, irr_corner] = -1
        node_of[lev, q] = irr_ids[irr.node_of_corner]
    return _Points(ids, z_ids, offsets(count)), node_of


# --------------------------------------------------------------------------- lateral faces


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
class _Lateral:
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


def _lateral(
    pairs: PillarPairs, node_of: IntArray, kept: np.ndarray, cell_id: IntArray, pts: _Points, node_xyz
) -> _Lateral:
    """Quads of the simple pairs, general pieces of the others (see ``structured_lateral``).

    ``node_xyz[pm]`` gives the coordinates of points by pillar-major id (see :class:`_Points`).
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
    return _Lateral(
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


def _general_pieces(pairs, node_of, ex, simple, cell_ext, pts: _Points, node_xyz):
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

    def __init__(self, pts: _Points) -> None:
        self.offset, self.num_nodes = pts.offset, pts.num_nodes


def _to_ids(pts: _Points, pm: IntArray) -> IntArray:
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


# --------------------------------------------------------------------------- top and bottom faces


@dataclass(frozen=True, eq=False)
class _Vertical:
    """Top and bottom faces by (interface, column, bottom before top); normals +z (down)."""

    pos: IntArray
    upper: IntArray  # cell above the face (-1 = outside)
    lower: IntArray
    skips: np.ndarray  # an interior face joining cells more than one layer apart
    top_face: IntArray  # (n_layers, n_areal_cells): face of every kept cell's top
    bottom_face: IntArray  # and of its bottom


def _vertical(
    node_of: IntArray, kept: np.ndarray, cell_id: IntArray, pos2: IntArray
) -> tuple[_Vertical, IntArray]:
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
        ver = _Vertical(
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
    ver = _Vertical(
        offsets(counts),
        np.where(bottom, ids, joined_to[cell]),
        np.where(bottom, -1, ids),
        ~bottom & far_above[cell],
        top_face,
        bottom_face,
    )
    return ver, nodes


def _crossings_in_faces(h_pos, h_nodes, touched, general: LateralFaces, first_crossing: int, coords):
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


# --------------------------------------------------------------------------- assembly


def _cell_half_faces(
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
class _FaceList:
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
        cls, ver: _Vertical, h_nodes, insert, lat: _Lateral, node_of, etag, pairs: PillarPairs
    ) -> _FaceList:
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

    def subset(self, keep: np.ndarray) -> _FaceList:
        counts = np.diff(self.pos)[keep]
        nodes = self.nodes[ragged_arange(self.pos[:-1][keep], counts)]
        return _FaceList(
            offsets(counts),
            nodes,
            self.neighbors[keep],
            self.tag[keep],
            None if self.half_tags is None else self.half_tags[keep],
            self.nnc_kind[keep],
            None if self.pair is None else self.pair[keep],
            self.mismatch[keep],
        )

    def with_neighbors(self, neighbors: IntArray) -> _FaceList:
        return _FaceList(
            self.pos, self.nodes, neighbors, self.tag, self.half_tags, self.nnc_kind, self.pair, self.mismatch
        )

    def drop_unused_nodes(self, coords: FloatArray) -> tuple[_FaceList, FloatArray]:
        """The faces with the nodes no face uses dropped, and the remaining coordinates."""
        used = np.zeros(coords.shape[0], dtype=bool)
        used[self.nodes] = True
        if used.all():
            return self, coords
        nodes = renumbering(used)[self.nodes]
        face_list = _FaceList(
            self.pos, nodes, self.neighbors, self.tag, self.half_tags, self.nnc_kind, self.pair, self.mismatch
        )
        return face_list, coords[used]

    def nnc(self, index_map: IntArray) -> NNC:
        face = np.flatnonzero(self.nnc_kind >= 0)
        face = face[(self.neighbors[face] >= 0).all(axis=1)]
        cells = self.neighbors[face]
        return NNC(cells, index_map[cells], self.nnc_kind[face], face)


def _fault_names(
    faces: _FaceList, names: list[str], lat: _Lateral, pairs: PillarPairs, etag
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


def _zero_area(coords: FloatArray, pos: IntArray, nodes: IntArray, faces: IntArray) -> np.ndarray:
    """Faces (of ``faces``) whose vector area vanishes (Newell's formula, relative to the extent)."""
    counts = pos[faces + 1] - pos[faces]
    p_local = offsets(counts)
    owner = np.repeat(np.arange(faces.size), counts)
    nxt = np.arange(1, p_local[-1] + 1)
    nxt[p_local[1:] - 1] = p_local[:-1]
    xyz = coords[nodes[ragged_arange(pos[faces], counts)]]  # the faces' nodes
    p = xyz - np.repeat(xyz[p_local[:-1]], counts, axis=0)  # from the face's first node
    cr = np.cross(p, p[nxt])
    area = np.stack([np.bincount(owner, cr[:, d], faces.size) for d in range(3)], axis=1)
    extent = max((float(np.ptp(xyz[:, d])) for d in range(3)), default=1.0) if xyz.size else 1.0
    return 0.5 * np.linalg.norm(area, axis=1) <= 1e-14 * extent**2
