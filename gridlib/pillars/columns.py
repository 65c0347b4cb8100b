"""``extrude_columns``: the pillar engine on the columns of any areal 2-D grid (generalised pillar grids).

The areal grid's cells (polygons of any sizes: Voronoi/PEBI cells, triangles,
quadrilaterals) are the *columns*, its nodes the *pillars* and every areal edge
a *pillar pair* with at most two columns (``docs/pillar-grids.md`` describes the
engine as a whole). A *corner* is a (cell, position in its node ring) pair, the ring being
:func:`areal_corners`' cycle; each corner has a depth at every layer interface
(level): the top of layer k is level k, its bottom level k + 1, within a column.
Across a fault edge the two columns carry different depths on the same pillar.
From there on everything is the corner-point engine, as ``process_grdecl`` runs it on decks:

1. cells masked by ``active`` are removed before anything else: their corners
   (possibly junk) are never read; the used corners must be finite, and no
   active cell may have its bottom above its top;
2. the distinct depths on every pillar are numbered (node ids grow with depth
   along a pillar; pillars where every column agrees at every level take a
   fast path), so that all topology tests compare integer ranks; depths equal
   up to rounding (within the pillar's depth resolution,
   :mod:`~gridlib.pillars.pillar_points`) are one point, so that no face of zero
   area (nodes collinear up to rounding) is ever made;
3. cells of zero thickness on all their pillars are removed (the cells above
   and below then touch and share a face, as in ``process_grdecl``);
4. lateral faces: pairs whose two sides hold the same cells with the same
   corner nodes (no fault) or cells on one side only give one quadrilateral per
   cell (a triangle where collapsed on one pillar); the others go to
   :func:`~gridlib.pillars.lateral.general_pieces`, which subdivides them
   exactly where fault throw makes the corners mismatch, with crossing nodes;
5. top and bottom faces by walking every column through its kept cells, with
   the crossing nodes inserted into their edges (every cell watertight);
6. with inclined pillars, faces of zero area (on pillars that coincide, a
   pair of no width) are removed; then cells with fewer than four faces.

The phases live in :mod:`~gridlib.pillars.column_inputs` (1),
:mod:`~gridlib.pillars.column_nodes` (2), :mod:`~gridlib.pillars.column_lateral` (4),
:mod:`~gridlib.pillars.column_top_bottom` (5) and
:mod:`~gridlib.pillars.column_assembly` (6); this module runs them.

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
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..connectivity import cell_half_faces, cell_node_cycles_2d, renumbering
from ..errors import InputError
from ..grid import Cells, Faces, FloatArray, Grid, IntArray, Layering, Nodes
from ..threads import num_threads
from .column_assembly import FaceList, construction_half_faces, name_unnamed_faults, zero_area_faces
from .column_inputs import (
    ColumnCorners,
    check_active,
    check_areal,
    check_depths,
    check_used_depths,
    clockwise,
    edge_tags,
    fault_name_list,
    pillar_lines,
)
from .column_lateral import PillarPairs, lateral_faces
from .column_nodes import NodeCoords, PillarNodes, number_points
from .column_top_bottom import crossings_in_faces, top_bottom_faces
from .nnc import NNC

__all__ = ["ColumnGrid", "areal_corners", "extrude_columns"]


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
    check_areal(areal)
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
    ``step`` is the entry the grid's history gets after the areal grid's.

    The phases of the module docstring: inputs checked, depths ranked per pillar, cells kept,
    lateral and top/bottom faces, faces and cells cleaned up, the grid packaged."""
    nc2, nn2 = areal.num_cells, areal.num_nodes
    z = check_depths(z, corners.num)
    nl = z.shape[0] - 1
    act = check_active(active, nl, nc2)
    lines = pillar_lines(pillars, nn2)
    etag = edge_tags(edge_tag, areal)
    names = fault_name_list(fault_names, etag)
    notes: list[str] = []

    reverse = clockwise(areal, corners)
    if reverse:  # orient every ring counter-clockwise: top normals point down
        corners = corners.reversed()
        z = z[:, corners.perm]
    pts, node_of = _ranked_depths(z, corners, act, nn2)
    del z  # the depths are ranks from here on (and the caller's may be the only other reference)
    kept, cell_id = _kept_cells(node_of, act, corners.pos, notes)
    n_cells = int(np.count_nonzero(kept))

    pairs = PillarPairs.of(areal, corners, reverse)
    ver, h_nodes = top_bottom_faces(node_of, kept, cell_id, corners.pos)
    xy = areal.nodes.coords[:, :2]
    lat = lateral_faces(pairs, node_of, kept, cell_id, pts, NodeCoords(pts, xy, lines))
    n_points, n_cross = pts.num_nodes, lat.general.crossing_coords.shape[0]
    coords = pts.coords(xy, lines, n_cross)
    coords[n_points:] = lat.general.crossing_coords
    del pts
    insert = _crossing_insertions(lat, ver, h_nodes, n_cells, n_points, coords)

    n_h, n_q = ver.upper.size, lat.num_quads
    # The cells' half-faces as the construction gives them (used unless faces are removed below),
    # on a second thread while the faces are assembled: the two only read what they share.
    structured_cells = _in_background(
        construction_half_faces, ver.top_face, ver.bottom_face, lat, corners, pairs, kept, cell_id, n_h, n_q
    )
    faces = FaceList.join(ver, h_nodes, insert, lat, node_of, etag, pairs)
    del node_of, h_nodes, insert, ver  # in the faces now
    faces, coords, cell_k, cell_c, face_pos, half = _cleaned(
        faces, coords, lines is not None, kept, structured_cells, notes
    )
    if not (kept.all() and faces.num == n_h + n_q + lat.num_general):
        # Every node is used when every cell is kept and no face was removed: each point is a
        # corner of a kept cell's top or bottom (or shared) face; crossing nodes are in pieces.
        faces, coords = faces.drop_unused_nodes(coords)
    names = name_unnamed_faults(faces, names, lat, pairs, etag)
    grid, index_map = _packaged(areal, faces, coords, face_pos, half, cell_k, cell_c, nl, step)
    return ColumnGrid(grid, faces.nnc(index_map), names, tuple(notes))


def _ranked_depths(
    z: FloatArray, corners: ColumnCorners, act: np.ndarray, nn2: int
) -> tuple[PillarNodes, IntArray]:
    """The depths of the corners of active cells checked, and numbered as points per pillar
    (:func:`~gridlib.pillars.column_nodes.number_points`)."""
    pos2, owner = corners.pos, corners.owner
    used = None
    if not act.all():
        if not act.any():
            raise InputError("active: no active cell")
        used_cell = np.zeros((z.shape[0], pos2.size - 1), dtype=bool)
        used_cell[:-1] |= act
        used_cell[1:] |= act
        used = np.take(used_cell, owner, axis=1)
    check_used_depths(z, used, act, owner, pos2)
    return number_points(z, corners.ring, used, nn2)


def _kept_cells(
    node_of: IntArray, act: np.ndarray, pos2: IntArray, notes: list[str]
) -> tuple[np.ndarray, IntArray]:
    """Cells active and not collapsed on all their pillars (n_layers, n_areal_cells), and their ids
    (-1 for the others), numbered layer by layer."""
    collapsed = np.logical_and.reduceat(node_of[1:] == node_of[:-1], pos2[:-1], axis=1)
    kept = ~collapsed if act.all() else act & ~collapsed
    n_collapsed = int(np.count_nonzero(act & collapsed))
    if n_collapsed:
        notes.append(f"{n_collapsed} cells of zero thickness on all their pillars were removed")
    n_cells = int(np.count_nonzero(kept))
    if n_cells == 0:
        raise InputError("z: every active cell has zero thickness (collapsed on all pillars)")
    cell_id = np.full(kept.shape, -1, dtype=np.int64)
    cell_id[kept] = np.arange(n_cells)
    return kept, cell_id


def _crossing_insertions(lat, ver, h_nodes, n_cells: int, n_points: int, coords: FloatArray):
    """Where the crossing nodes go into the top/bottom faces of the cells next to a subdivided pair
    (:func:`~gridlib.pillars.column_top_bottom.crossings_in_faces`), None if there are none."""
    if not lat.general.crossing_coords.shape[0]:
        return None
    near = np.zeros(n_cells + 1, dtype=bool)  # index -1 (outside): the extra False
    near[lat.general_cells] = True
    touched = np.flatnonzero(near[ver.upper] | near[ver.lower])
    return crossings_in_faces(ver.pos, h_nodes, touched, lat.general, n_points, coords)


def _cleaned(faces: FaceList, coords: FloatArray, inclined: bool, kept: np.ndarray, structured_cells, notes):
    """Faces of zero area removed (only ``inclined`` pillars can coincide: a deck's collapsed pillars,
    pairs of no width), then cells with fewer than four faces; the faces, coordinates, the kept
    cells' layer and column, and the cells' half-faces (``face_pos``, ``half``)."""
    structured = True  # the cells' faces follow from the construction (else: transpose neighbors)
    if inclined:
        zero = zero_area_faces(coords, faces.pos, faces.nodes, np.arange(faces.num))
        if zero.any():
            notes.append(f"{int(zero.sum())} faces of zero area were removed")
            faces = faces.subset(~zero)
            structured = False
    cell_k, cell_c = np.nonzero(kept)
    n_cells = cell_k.size
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
    return faces, coords, cell_k, cell_c, face_pos, half


def _packaged(
    areal: Grid, faces: FaceList, coords, face_pos, half, cell_k, cell_c, nl: int, step: str
) -> tuple[Grid, IntArray]:
    """The 3-D grid: cells (layer ``cell_k``, column ``cell_c``) with their half-faces ``half`` (2 f +
    side), faces, nodes, its logical box and its layering over ``areal``; and the cells' index map."""
    nc2 = areal.num_cells
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
    return grid, index_map


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
