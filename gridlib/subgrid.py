"""Cell subsets of a grid: ``remove_cells`` and ``extract_subgrid``.

Both keep the surviving cells in their original order and keep the original
orientation of every surviving face, so a face that loses one neighbour keeps
its -1 in the column where the removed cell was (as MRST's ``removeCells``).
Faces left with no cell and nodes left with no face are dropped.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .connectivity import offsets, ragged_arange, renumbering
from .errors import GridError
from .grid import Cells, Faces, Grid, IntArray, Nodes


@dataclass(frozen=True, eq=False)
class Subgrid:
    """A grid cut out of a parent, with maps back to the parent's indices."""

    grid: Grid
    cells: IntArray  # parent cell of each subgrid cell
    faces: IntArray  # parent face of each subgrid face
    nodes: IntArray  # parent node of each subgrid node


def cell_mask(grid: Grid, cells: ArrayLike, what: str) -> np.ndarray:
    """Boolean mask from a mask or a list of cell indices; errors name bad entries."""
    try:
        arr = np.asarray(cells)
    except ValueError as exc:
        raise GridError(f"{what}: cells must be a flat list of indices or a boolean mask") from exc
    nc = grid.num_cells
    if arr.dtype == object:
        raise GridError(f"{what}: cells must be a flat list of indices or a boolean mask")
    if arr.dtype == bool:
        if arr.shape != (nc,):
            raise GridError(f"{what}: boolean mask must have shape ({nc},), got {arr.shape}")
        return arr.copy()
    if arr.size == 0:
        return np.zeros(nc, dtype=bool)
    if not np.issubdtype(arr.dtype, np.integer):
        if (
            np.issubdtype(arr.dtype, np.floating)
            and np.all(np.isfinite(arr))
            and np.all(arr == np.round(arr))
        ):
            arr = arr.astype(np.int64)
        else:
            raise GridError(f"{what}: cells must be integer indices or a boolean mask")
    arr = arr.ravel().astype(np.int64)
    bad = (arr < 0) | (arr >= nc)
    if np.any(bad):
        raise GridError(
            f"{what}: unknown cell indices {arr[bad][:5].tolist()} (grid has {nc} cells, 0-based)"
        )
    mask = np.zeros(nc, dtype=bool)
    mask[arr] = True
    return mask


def _subset(grid: Grid, keep: np.ndarray, name: str) -> Subgrid:
    new_cell = renumbering(keep)
    nb = grid.faces.neighbors
    new_nb = np.where(nb >= 0, new_cell[np.maximum(nb, 0)], -1)
    keep_face = (new_nb >= 0).any(axis=1)
    new_face = renumbering(keep_face)

    # Half-faces of the kept cells, in the same order.
    fpos = grid.cells.face_pos
    kept_cells = np.flatnonzero(keep)
    counts = np.diff(fpos)[kept_cells]
    hf = ragged_arange(fpos[kept_cells], counts)
    cell_faces = new_face[grid.cells.faces[hf]]
    face_tag = None if grid.cells.face_tag is None else grid.cells.face_tag[hf]
    index_map = kept_cells if grid.cells.index_map is None else grid.cells.index_map[kept_cells]

    kept_faces = np.flatnonzero(keep_face)
    npos = grid.faces.node_pos
    ncount = np.diff(npos)[kept_faces]
    face_nodes = grid.faces.nodes[ragged_arange(npos[kept_faces], ncount)]
    used = np.zeros(grid.num_nodes, dtype=bool)
    used[face_nodes] = True
    new_node = renumbering(used)
    kept_nodes = np.flatnonzero(used)

    sub = grid.with_history(
        name,
        cells=Cells(offsets(counts), cell_faces, face_tag, index_map),
        faces=Faces(offsets(ncount), new_node[face_nodes], new_nb[keep_face], grid.faces.tag[keep_face]),
        nodes=Nodes(grid.nodes.coords[kept_nodes]),
        layering=None if grid.layering is None else grid.layering.subset(kept_cells),
    )
    return Subgrid(sub, kept_cells, kept_faces, kept_nodes)


def remove_cells(grid: Grid, cells: ArrayLike) -> Grid:
    """Grid without the given cells (indices or boolean mask).

    ``cells.index_map`` of the result maps every remaining cell to its index in
    the logical box (or, for grids without one, to its index in ``grid``).

    >>> from gridlib import cart_grid
    >>> g = remove_cells(cart_grid([3, 2]), [1])
    >>> g.num_cells, g.num_faces, g.num_nodes, g.cells.index_map.tolist()
    (5, 16, 12, [0, 2, 3, 4, 5])
    """
    drop = cell_mask(grid, cells, "remove_cells")
    if drop.all():
        raise GridError("remove_cells: removing every cell would leave an empty grid")
    return _subset(grid, ~drop, "remove_cells").grid


def extract_subgrid(grid: Grid, cells: ArrayLike) -> Subgrid:
    """The grid made of the given cells, with maps to the parent's cells, faces and nodes.

    Cells keep their parent order. Faces between a kept and a dropped cell
    become boundary faces.
    """
    keep = cell_mask(grid, cells, "extract_subgrid")
    if not keep.any():
        raise GridError("extract_subgrid: no cells selected")
    return _subset(grid, keep, "extract_subgrid")
