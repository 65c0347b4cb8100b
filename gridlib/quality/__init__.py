"""Per-cell quality measures of any grid (docs/quality.md).

xtgeo's set (``Grid.get_gridquality_properties``: the same names, definitions and units) for
the cells that are corner-point hexahedra, NaN for the others; and, for every grid, the
face-orientation errors of a two-point flux, the aspect ratio and the faces' non-planarity.

>>> from gridlib import cart_grid, compute_geometry
>>> g = cart_grid([2, 1, 1], [2.0, 1.0, 1.0])
>>> q = cell_quality(g, compute_geometry(g))
>>> [float(q[m][0]) for m in ("maxangle_sides", "orientation_error", "aspect_ratio", "twist")]
[90.0, 0.0, 1.0, 0.0]
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..cornerpoint.deck import Deck
from ..errors import GridError
from ..geometry import Geometry
from ..grid import FloatArray, Grid
from .cells import aspect_ratio, cell_face_nonplanarity, orientation_errors
from .corners import deck_corner_blocks, deck_faulted, grid_corners
from .hexahedra import NAMES, hexahedron_quality


@dataclass(frozen=True)
class Measure:
    """One per-cell quality quantity."""

    name: str  # xtgeo's name where xtgeo has it
    unit: str  # a quantity of gridlib.units ("angle": degrees; "dimensionless": flags, ratios)
    description: str
    hexahedral_only: bool  # NaN for cells that are not corner-point hexahedra


_A, _D = "angle", "dimensionless"
MEASURES: tuple[Measure, ...] = (
    Measure("minangle_topbase", _A, "smallest corner angle of the top and base faces", True),
    Measure("maxangle_topbase", _A, "largest corner angle of the top and base faces", True),
    Measure("minangle_topbase_proj", _A, "smallest corner angle of top and base in plan view", True),
    Measure("maxangle_topbase_proj", _A, "largest corner angle of top and base in plan view", True),
    Measure("minangle_sides", _A, "smallest corner angle of the four side faces", True),
    Measure("maxangle_sides", _A, "largest corner angle of the four side faces", True),
    Measure("collapsed", _D, "1 where the thickness on a pillar is below 1e-5", True),
    Measure("faulted", _D, "1 where a corner node is split by a fault", True),
    Measure("negative_thickness", _D, "1 where the bottom is above the top on a pillar", True),
    Measure("concave_proj", _D, "0 convex in plan view, else 1 + the corner inside the others", True),
    Measure("twist", _A, "turn of the base against the top about the cell's vertical axis", True),
    Measure("orientation_error", _A, "largest angle between face normal and centre line", False),
    Measure("k_orientation_error", _A, "largest angle between K n and the centre line", False),
    Measure("aspect_ratio", _D, "largest over smallest centroid-to-face distance", False),
    Measure("face_nonplanarity", _D, "largest node distance from a face's plane / sqrt(area)", False),
)
MEASURE = {m.name: m for m in MEASURES}
XTGEO_NAMES = tuple(m.name for m in MEASURES[:10])


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
    plain, k = orientation_errors(grid, geometry, centres, perm)
    out["orientation_error"] = plain
    if k is not None:
        out["k_orientation_error"] = k
    out["aspect_ratio"] = aspect_ratio(grid, geometry)
    out["face_nonplanarity"] = cell_face_nonplanarity(grid, geometry)
    return {m.name: out[m.name] for m in MEASURES if m.name in out}


def deck_quality(deck: Deck) -> dict[str, FloatArray]:
    """xtgeo's set (and ``twist``) for every cell of ``deck`` (active or not, i fastest), from
    each cell's own corners: the peer of xtgeo's ``get_gridquality_properties`` for decks
    gridlib would not grid (negative thickness, say)."""
    out = _blockwise(deck_corner_blocks(deck), deck.num_cells)
    out["faulted"] = deck_faulted(deck)
    return {m.name: out[m.name] for m in MEASURES if m.name in out}


def _blockwise(blocks: Iterable[tuple[slice, FloatArray]], n: int) -> dict[str, FloatArray]:
    """:func:`hexahedron_quality` of ``n`` cells whose corners come in blocks."""
    out = {name: np.full(n, np.nan) for name in NAMES}
    for part, corners in blocks:
        for name, values in hexahedron_quality(corners).items():
            out[name][part] = values
    return out


def _fault_cells(grid: Grid) -> FloatArray:
    on_fault = grid.faces.neighbors[grid.faces.tag > 0].ravel()
    flag = np.zeros(grid.num_cells)
    flag[on_fault[on_fault >= 0]] = 1.0
    return flag


__all__ = ["MEASURE", "MEASURES", "XTGEO_NAMES", "Measure", "cell_quality", "deck_quality"]
