"""The top of a 3-D grid as a map: its faces, a plan-view triangulation of their depths, the
fault traces along it and the grid's lateral cell size. Used by the plan view and the section.

Which faces are the top (z is depth, positive down; a face faces up where its outward normal
has a negative z):

* the boundary faces facing up, and of those
* on a logically Cartesian grid (corner-point and deck grids: ``cells.face_tag``) only the top
  half-faces (tag T), else only those tilted less than 60 degrees from horizontal (a side face
  of a column is steeper);
* where the grid has columns (a layered grid's ``layering``, or the (i, j) of a logically
  Cartesian grid's ``index_map``) only the faces of the shallowest cell of each column: a deck's
  inactive cells leave holes whose floor faces up too, under cells that hide it from above.

A grid without columns (tetrahedra) keeps every boundary face facing up: the upper side of a
body, seen from above (a fold that overhangs would be drawn twice; no sample grid has one).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..connectivity import offsets, ragged_arange, repeat_ids
from ..geometry import Geometry
from ..grid import Grid, T

UP = 0.5  # cos(60 degrees): the least |n_z| of a top face where the grid has no T tags


@dataclass(frozen=True)
class TopSurface:
    """The top faces of a 3-D grid (``faces``, the grid's; ``cells``, the cell under each) and
    a triangulation of them in plan view: the ``points`` (x, y, depth) are the faces' nodes,
    then each face's centre (the mean of its nodes); each face is a fan of ``triangles``
    (rows of point indices) from its centre over its edges (``triangle_face``: the index in
    ``faces`` of each). Lengths in the grid's length unit."""

    faces: np.ndarray
    cells: np.ndarray
    points: np.ndarray
    triangles: np.ndarray
    triangle_face: np.ndarray

    @property
    def depth_range(self) -> tuple[float, float]:
        """The shallowest and deepest depth of the top surface."""
        z = self.points[:, 2]
        return (float(z.min()), float(z.max())) if z.size else (0.0, 0.0)

    def plan_area(self) -> float:
        """The area of the top surface in plan view."""
        p = self.points[self.triangles]
        d1, d2 = p[:, 1, :2] - p[:, 0, :2], p[:, 2, :2] - p[:, 0, :2]
        return float(0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]).sum())

    def cell_size(self) -> float:
        """The grid's lateral cell size: the square root of the top's plan area per face."""
        return float(np.sqrt(self.plan_area() / max(self.faces.size, 1)))


def _columns(grid: Grid) -> tuple[np.ndarray, np.ndarray] | None:
    """Each cell's column and its layer (0 the top) where the grid has them, else None."""
    if grid.layering is not None:
        return grid.layering.column, grid.layering.layer
    if grid.cells.index_map is not None and grid.cart_dims is not None and len(grid.cart_dims) == 3:
        per_layer = int(grid.cart_dims[0]) * int(grid.cart_dims[1])
        return grid.cells.index_map % per_layer, grid.cells.index_map // per_layer
    return None


def top_faces(grid: Grid, geo: Geometry) -> tuple[np.ndarray, np.ndarray]:
    """The top faces of the 3-D ``grid`` (see the module's docstring) and the cell under each."""
    nb = grid.faces.neighbors
    faces = np.flatnonzero((nb < 0).any(axis=1))
    cells = nb[faces].max(axis=1)
    sign = np.where(nb[faces, 0] == cells, 1.0, -1.0)  # outward: the normal points out of cell 0
    nz = sign * geo.face_normals[faces, 2] / np.maximum(geo.face_areas[faces], np.finfo(float).tiny)
    if grid.cells.face_tag is not None:
        tagged = np.zeros(grid.num_faces, dtype=bool)
        tagged[grid.cells.faces[grid.cells.face_tag == T]] = True
        keep = (nz < 0) & tagged[faces]
    else:
        keep = nz < -UP
    faces, cells = faces[keep], cells[keep]
    columns = _columns(grid)
    if columns is not None:
        column, layer = columns
        order = np.lexsort((layer, column))
        first = np.ones(order.size, dtype=bool)
        first[1:] = column[order][1:] != column[order][:-1]
        shallowest = np.zeros(grid.num_cells, dtype=bool)
        shallowest[order[first]] = True
        keep = shallowest[cells]
        faces, cells = faces[keep], cells[keep]
    return faces, cells


def top_surface(grid: Grid, geo: Geometry) -> TopSurface:
    """The :class:`TopSurface` of the 3-D ``grid``."""
    faces, cells = top_faces(grid, geo)
    edges, owner = face_edges(grid, faces)
    used, local = np.unique(edges, return_inverse=True)
    local = local.reshape(edges.shape)
    xyz = grid.nodes.coords[used]
    counts = np.bincount(owner, minlength=faces.size)
    first = xyz[local[:, 0]]  # each face's nodes, once each
    centre = np.column_stack([np.bincount(owner, first[:, k], faces.size) for k in range(3)])
    centre /= np.maximum(counts, 1)[:, None]
    triangles = np.column_stack([used.size + owner, local])
    return TopSurface(faces, cells, np.vstack([xyz, centre]), triangles, owner)


def face_edges(grid: Grid, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The edges of ``faces`` (grid faces) as node pairs (m, 2), each face's in cyclic order,
    and the index in ``faces`` of each edge's face."""
    pos = grid.faces.node_pos
    counts = pos[faces + 1] - pos[faces]
    nodes = grid.faces.nodes[ragged_arange(pos[faces], counts)]
    starts = offsets(counts)
    nxt = np.arange(nodes.size) + 1
    nxt[starts[1:] - 1] = starts[:-1]
    return np.column_stack([nodes, nodes[nxt]]), repeat_ids(starts)


def fault_traces(grid: Grid, top: TopSurface) -> tuple[np.ndarray, np.ndarray]:
    """The fault traces along the top of the 3-D ``grid``: for every fault face (``faces.tag``
    > 0) of a cell under the top, its shallowest edge in plan view, as segments (n, 2, 2)
    ((x, y) of both ends) and their fault ids (n,). A fault face a column's top cell shares
    with a deeper cell across the fault (a throw) has its shallowest edge on the trace too."""
    under = np.zeros(grid.num_cells + 1, dtype=bool)
    under[top.cells] = True
    nb = grid.faces.neighbors
    faults = np.flatnonzero((grid.faces.tag > 0) & (under[nb[:, 0]] | under[nb[:, 1]]))
    if faults.size == 0:
        return np.zeros((0, 2, 2)), np.zeros(0, dtype=np.int64)
    edges, owner = face_edges(grid, faults)
    depth = grid.nodes.coords[edges, 2].mean(axis=1)
    order = np.lexsort((depth, owner))
    first = order[np.r_[True, owner[order][1:] != owner[order][:-1]]]
    segments = grid.nodes.coords[edges[first]][:, :, :2]
    return segments, grid.faces.tag[faults[owner[first]]].astype(np.int64)
