"""The quality measures of a grid's cells (:data:`gridlib.quality.MEASURES`; docs/quality.md).

>>> from gridlib import cart_grid, compute_geometry
>>> g = cart_grid([2, 1, 1], [2.0, 1.0, 1.0])
>>> q = cell_quality(g, compute_geometry(g))
>>> [float(q[m][0]) for m in ("maxangle_sides", "orientation_error", "aspect_ratio", "twist")]
[90.0, 0.0, 1.0, 0.0]
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

import numpy as np
from numpy.typing import ArrayLike

from ..cornerpoint.deck import Deck
from ..errors import GridError
from ..geometry import Geometry
from ..grid import FloatArray, Grid
from ..threads import in_order
from . import MEASURES
from .cells import face_measures
from .corners import deck_corner_blocks, deck_faulted, grid_corners
from .hexahedra import MAX_THREADS, NAMES, hexahedron_quality, serial_hexahedron_quality


def cell_quality(
    grid: Grid,
    geometry: Geometry,
    *,
    perm: ArrayLike | None = None,
    centres: ArrayLike | None = None,
    deck: Deck | None = None,
) -> dict[str, FloatArray]:
    """Every measure of :data:`MEASURES` per cell of ``grid`` (float64; flags 0.0 / 1.0).

    ``perm`` (nc, 3): diagonal permeability along the axes (None: ``k_orientation_error`` is
    left out); ``centres`` (nc, d): the cell centres of the orientation angles (default: the
    centroids). ``deck``: the grid's corner-point deck (``grid.cells.index_map`` its linear
    cell indices), from which the hexahedral measures are taken as xtgeo takes them (each
    cell's own corners); without it they come from the grid's own hexahedral cells
    (:func:`~gridlib.quality.corners.grid_corners`) and ``faulted`` marks the cells with a
    face on a fault (``faces.tag > 0``).
    """
    if deck is not None:
        if grid.cells.index_map is None or grid.cart_dims != deck.cart_dims:
            raise GridError(
                f"cell_quality: the grid (cart_dims {grid.cart_dims}) is not a grid of the deck "
                f"{deck.source} ({deck.cart_dims})"
            )
        cells = grid.cells.index_map
        out = _blockwise(deck_corner_blocks(deck, cells), cells.size)
        faulted = deck_faulted(deck)[cells]
    else:
        out = hexahedron_quality(grid_corners(grid))
        faulted = _fault_cells(grid)
    out["faulted"] = np.where(np.isnan(out["minangle_topbase"]), np.nan, faulted)  # NaN: no hexahedron
    out |= face_measures(grid, geometry, centres, perm)
    return {m.name: out[m.name] for m in MEASURES if m.name in out}


def deck_quality(deck: Deck) -> dict[str, FloatArray]:
    """xtgeo's set (and ``twist``) for every cell of ``deck`` (active or not, i fastest), from
    each cell's own corners: the peer of xtgeo's ``get_gridquality_properties`` for decks
    gridlib would not grid (negative thickness, say)."""
    out = _blockwise(deck_corner_blocks(deck), deck.num_cells)
    out["faulted"] = deck_faulted(deck)
    return {m.name: out[m.name] for m in MEASURES if m.name in out}


def _blockwise(blocks: Iterable[tuple[slice, Callable[[], FloatArray]]], n: int) -> dict[str, FloatArray]:
    """:func:`hexahedron_quality` of ``n`` cells whose corners come in blocks (each block's
    slice and a function computing its corners), blocks on up to two threads."""
    out = {name: np.full(n, np.nan) for name in NAMES}

    def measured(part: slice, corners: Callable[[], FloatArray]):
        return part, serial_hexahedron_quality(corners())

    for part, values in in_order(measured, blocks, MAX_THREADS):
        for name, v in values.items():
            out[name][part] = v
    return out


def _fault_cells(grid: Grid) -> FloatArray:
    on_fault = grid.faces.neighbors[grid.faces.tag > 0].ravel()
    flag = np.zeros(grid.num_cells)
    flag[on_fault[on_fault >= 0]] = 1.0
    return flag


__all__ = ["cell_quality", "deck_quality"]
