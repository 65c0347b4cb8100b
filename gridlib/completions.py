"""The cells a vertical well crosses: where a simulator completes it.

A vertical well at plan-view point (x, y) crosses, top down:

* in a layered grid (pebi, layered; ``grid.layering``): every cell of the areal cell
  that contains the point;
* in a logically Cartesian 3-D grid (corner-point, deck, cartesian, tensor;
  ``cells.face_tag``): every cell whose top face (tag T), projected on the plane,
  contains the point -- the cells of its column for vertical pillars.

Point location is the crossing-number test, vectorised over every edge of every
polygon, with the half-open rule (an edge counts when exactly one of its ends lies
above the point, and the point lies strictly left of it): polygons that tile the plane
share out the points on their common edges and corners, so a well on a cell boundary
is in exactly one cell per layer. Cells are returned top down (by layer, or by the
depth of their top face). Coordinates in the grid's length unit; z is depth.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .connectivity import cell_node_cycles_2d, ragged_arange
from .errors import InputError
from .geometry import Geometry
from .grid import Grid, IntArray, T


def points_in_polygons(point: ArrayLike, pos: IntArray, nodes: IntArray, xy: np.ndarray) -> np.ndarray:
    """Which polygons contain ``point`` (x, y): polygon p has the nodes
    ``nodes[pos[p]:pos[p + 1]]`` in cyclic order, at ``xy`` (n, 2). Returns a boolean per
    polygon (half-open rule, module docstring).

    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.0], [2.0, 1.0]])
    >>> pos, nodes = np.array([0, 4, 8]), np.array([0, 1, 2, 3, 1, 4, 5, 2])
    >>> points_in_polygons([1.0, 0.5], pos, nodes, square).tolist()  # on the shared edge: one
    [False, True]
    """
    px, py = (float(v) for v in np.asarray(point, dtype=np.float64)[:2])
    counts = np.diff(pos)
    owner = np.repeat(np.arange(counts.size), counts)
    following = np.arange(nodes.size) + 1
    last = pos[1:] - 1
    following[last[counts > 0]] = pos[:-1][counts > 0]
    a, b = xy[nodes], xy[nodes[following]]
    straddles = (a[:, 1] > py) != (b[:, 1] > py)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_cross = a[:, 0] + (py - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    crossing = straddles & (px < x_cross)
    return np.bincount(owner, crossing, counts.size) % 2 == 1


def vertical_well_cells(grid: Grid, geometry: Geometry, point: ArrayLike) -> IntArray:
    """The cells (rows of ``grid``) a vertical well at ``point`` (x, y) crosses, top down;
    empty if it misses the grid. Raises InputError for grids without layers or logical
    faces (tetrahedral grids, say) and for 2-D grids."""
    if grid.griddim != 3:
        raise InputError("a vertical well needs a 3-D grid")
    if grid.layering is not None:
        areal = grid.layering.areal
        pos, nodes = cell_node_cycles_2d(areal)
        inside = np.flatnonzero(points_in_polygons(point, pos, nodes, areal.nodes.coords[:, :2]))
        if inside.size == 0:
            return np.zeros(0, dtype=np.int64)
        cells = np.flatnonzero(grid.layering.column == inside[0])
        return cells[np.argsort(grid.layering.layer[cells], kind="stable")]
    if grid.cells.face_tag is None:
        raise InputError("wells: locating a vertical well needs a layered or a logically Cartesian grid")
    top = np.flatnonzero(grid.cells.face_tag == T)
    owner = np.searchsorted(grid.cells.face_pos, top, side="right") - 1
    faces = grid.cells.faces[top]
    npos = grid.faces.node_pos
    counts = npos[faces + 1] - npos[faces]
    pos = np.concatenate([[0], np.cumsum(counts)])
    nodes = grid.faces.nodes[ragged_arange(npos[faces], counts)]
    inside = points_in_polygons(point, pos, nodes, grid.nodes.coords[:, :2])
    cells, first = np.unique(owner[inside], return_index=True)
    depth = geometry.face_centroids[faces[inside][first], 2]
    return cells[np.argsort(depth, kind="stable")]
