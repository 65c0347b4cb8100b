"""Depositional coordinates (x_r, y_r, w) of the cells of a grid: the pre-fault areal position
of each cell's column and the stratigraphic coordinate of its layer (see :mod:`gridlib.petrophysics`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..arrays import frozen_array
from ..errors import InputError
from ..geometry import compute_geometry
from ..grid import FloatArray, Grid, IntArray

__all__ = ["Depositional", "depositional_coordinates", "layer_index"]


@dataclass(frozen=True, eq=False)
class Depositional:
    """Depositional coordinates of the cells of a grid, as columns x layers.

    ``column_xy`` (ncol, 2): the pre-fault areal position of every column (m);
    ``w_edges`` (nl + 1,): the stratigraphic coordinate of the layer interfaces
    (m, 0 at the top, increasing downwards); ``column``, ``layer`` (nc,): each
    cell's column and layer. Rows of ``column_xy`` no cell uses may be NaN.
    """

    column_xy: FloatArray
    w_edges: FloatArray
    column: IntArray
    layer: IntArray

    def __post_init__(self) -> None:
        what = "depositional coordinates: "
        xy = frozen_array(self.column_xy, np.float64, what + "column_xy", 2, copy=True, error=InputError)
        w = frozen_array(self.w_edges, np.float64, what + "w_edges", 1, copy=True, error=InputError)
        col = frozen_array(self.column, np.int64, what + "column", 1, copy=True, error=InputError)
        lay = frozen_array(self.layer, np.int64, what + "layer", 1, copy=True, error=InputError)
        if xy.shape[1] != 2:
            raise InputError(f"depositional coordinates: column_xy must be (ncol, 2), got {xy.shape}")
        if w.size < 2 or not np.isfinite(w).all() or (np.diff(w) <= 0).any():
            raise InputError("depositional coordinates: w_edges must be finite and strictly increasing")
        if col.shape != lay.shape:
            raise InputError("depositional coordinates: column and layer must be 1-D of equal length")
        if col.size and (col.min() < 0 or col.max() >= xy.shape[0]):
            raise InputError(f"depositional coordinates: column ids must lie in [0, {xy.shape[0]})")
        if lay.size and (lay.min() < 0 or lay.max() >= w.size - 1):
            raise InputError(f"depositional coordinates: layer ids must lie in [0, {w.size - 1})")
        if col.size and not np.isfinite(xy[np.unique(col)]).all():
            raise InputError("depositional coordinates: a column holding cells has no finite (x, y)")
        for name, arr in (("column_xy", xy), ("w_edges", w), ("column", col), ("layer", lay)):
            object.__setattr__(self, name, arr)

    @property
    def num_cells(self) -> int:
        return self.column.size

    @property
    def num_layers(self) -> int:
        return self.w_edges.size - 1

    @property
    def layer_w(self) -> FloatArray:
        """w at the middle of every layer (m)."""
        return 0.5 * (self.w_edges[:-1] + self.w_edges[1:])

    @property
    def points(self) -> FloatArray:
        """(nc, 3) = x_r, y_r, w of every cell (m)."""
        xy = self.column_xy[self.column]
        return np.column_stack([xy, self.layer_w[self.layer]])


def _columns_layers(grid: Grid) -> tuple[IntArray, IntArray, int, int]:
    """Per cell its column and layer, the number of columns and of layers."""
    if grid.layering is not None:
        lay = grid.layering
        return lay.column, lay.layer, lay.areal.num_cells, lay.num_layers
    if grid.cart_dims is None:
        raise InputError(
            "depositional coordinates need a logically Cartesian grid (cart_dims and cells.index_map) or a "
            "layered grid (grid.layering); this grid has neither"
        )
    dims = tuple(grid.cart_dims)
    index = grid.cells.index_map
    if index is None:
        if int(np.prod(dims)) != grid.num_cells:
            raise InputError("depositional coordinates: the grid has cart_dims but no cells.index_map")
        index = np.arange(grid.num_cells)
    nxy = dims[0] * (dims[1] if len(dims) > 1 else 1)
    nl = dims[2] if len(dims) > 2 else 1
    return index % nxy, index // nxy, nxy, nl


def layer_index(grid: Grid) -> IntArray:
    """The layer of every cell (0 = top): ``index_map // (nx ny)`` of a logically Cartesian grid,
    ``layering.layer`` of a layered grid.

    >>> import gridlib as gl
    >>> layer_index(gl.cart_grid([2, 1, 3])).tolist()
    [0, 0, 1, 1, 2, 2]
    """
    return _columns_layers(grid)[1]


def depositional_coordinates(
    grid: Grid,
    *,
    dz_ref: float | ArrayLike | None = None,
    column_xy: ArrayLike | None = None,
    coord: ArrayLike | None = None,
    centroids: ArrayLike | None = None,
) -> Depositional:
    """The depositional coordinates (x_r, y_r, w) of the cells of ``grid`` (module docstring).

    Columns and layers: ``cells.index_map`` and ``cart_dims`` of a logically
    Cartesian grid (column = i + nx j, layer = k), or ``grid.layering``.

    The areal position of the columns, the first of:

    * ``column_xy`` (ncol, 2), given (m; e.g. restored positions);
    * a layered grid: the centroids of its areal cells;
    * ``coord``: the corner-point deck's COORD (``deck.coord``): the mean of the
      midpoints of a column's four pillars;
    * the mean (x, y) of the centroids of the column's cells (``centroids``
      (nc, 3), computed with ``compute_geometry`` if not given).

    ``dz_ref`` (m): the reference thickness of every layer (one number, or one
    per layer); default: the median depth difference between the centroids of
    vertically adjacent cells of a column (``centroids`` or computed), or 1 m
    for a single layer.

    >>> import gridlib as gl
    >>> u = depositional_coordinates(gl.cart_grid([2, 1, 2], [20.0, 10.0, 6.0]))
    >>> u.points.tolist()
    [[5.0, 5.0, 1.5], [15.0, 5.0, 1.5], [5.0, 5.0, 4.5], [15.0, 5.0, 4.5]]
    """
    column, layer, ncol, nl = _columns_layers(grid)
    cents = None if centroids is None else np.asarray(centroids, dtype=np.float64)
    if cents is not None and (cents.ndim != 2 or cents.shape[0] != grid.num_cells or cents.shape[1] < 2):
        raise InputError(f"centroids: expected ({grid.num_cells}, 3) cell centroids, got shape {cents.shape}")

    def centroids_() -> FloatArray:
        nonlocal cents
        if cents is None:
            cents = compute_geometry(grid).cell_centroids
        return cents

    if column_xy is not None:
        xy = np.asarray(column_xy, dtype=np.float64)
        if xy.shape != (ncol, 2):
            raise InputError(f"column_xy: expected ({ncol}, 2) column positions, got shape {xy.shape}")
    elif grid.layering is not None:
        xy = compute_geometry(grid.layering.areal).cell_centroids[:, :2]
    elif coord is not None:
        xy = _pillar_centres(coord, grid.cart_dims)
    else:
        c = centroids_()
        counts = np.bincount(column, minlength=ncol).astype(np.float64)
        with np.errstate(invalid="ignore", divide="ignore"):
            xy = np.column_stack(
                [np.bincount(column, c[:, 0], ncol) / counts, np.bincount(column, c[:, 1], ncol) / counts]
            )
    if dz_ref is None:
        dz = np.full(nl, _median_layer_step(column, layer, ncol, nl, centroids_) if nl > 1 else 1.0)
    else:
        dz = np.asarray(dz_ref, dtype=np.float64)
        if dz.ndim == 0:
            dz = np.full(nl, float(dz))
        if dz.shape != (nl,) or not np.isfinite(dz).all() or (dz <= 0).any():
            raise InputError(f"dz_ref: expected a positive thickness (m) or {nl} of them (one per layer)")
    return Depositional(xy, np.concatenate([[0.0], np.cumsum(dz)]), column, layer)


def _pillar_centres(coord: ArrayLike, cart_dims: tuple[int, ...] | None) -> FloatArray:
    if cart_dims is None or len(cart_dims) != 3:
        raise InputError("coord: pillars need a 3-D logically Cartesian grid (cart_dims nx, ny, nz)")
    nx, ny, _ = cart_dims
    c = np.asarray(coord, dtype=np.float64)
    if c.size != 6 * (nx + 1) * (ny + 1):
        raise InputError(f"coord: expected 6 (nx+1)(ny+1) = {6 * (nx + 1) * (ny + 1)} values, got {c.size}")
    p = c.reshape(ny + 1, nx + 1, 6)
    mid = 0.5 * (p[..., 0:2] + p[..., 3:5])
    col = 0.25 * (mid[:-1, :-1] + mid[:-1, 1:] + mid[1:, :-1] + mid[1:, 1:])  # (ny, nx, 2)
    return col.reshape(nx * ny, 2)


def _median_layer_step(column: IntArray, layer: IntArray, ncol: int, nl: int, centroids) -> float:
    """Median centroid depth difference of vertically adjacent cells of a column (m)."""
    key = column * nl + layer
    order = np.argsort(key, kind="stable")
    k = key[order]
    adjacent = np.flatnonzero(np.diff(k) == 1)
    adjacent = adjacent[(k[adjacent] // nl) == (k[adjacent + 1] // nl)]
    if adjacent.size == 0:
        return 1.0
    z = centroids()[:, 2] if centroids().shape[1] > 2 else np.zeros(column.size)
    step = z[order[adjacent + 1]] - z[order[adjacent]]
    step = step[step > 0]
    return float(np.median(step)) if step.size else 1.0
