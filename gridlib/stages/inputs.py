"""The files most stages start from: a case's grid (``grid.nc``), its geometry
(``geometry.nc``) and, where given, its rock (``petrophysics.nc``), read and checked to
describe the same cells."""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

from ..cornerpoint.map_axes import MapAxes
from ..geometry import Geometry
from ..io.netcdf import GridDataset, read_geometry_netcdf, read_netcdf
from ..io.netcdf_parts import check_same_cells, read_attrs, stored_map_axes, stored_unit_system
from ..io.rock_file import read_rock
from ..units import UnitSystem


@dataclass(frozen=True)
class GridInputs:
    """A case's grid file as stored, its geometry, its rock (None without ``petrophysics``),
    the unit system of its files and where the grid lies on the map (a deck's MAPAXES; None:
    the grid's frame is the map's)."""

    stored: GridDataset
    geometry: Geometry
    rock: dict[str, np.ndarray] | None
    units: UnitSystem
    map_axes: MapAxes | None = None


def read_grid_inputs(
    grid: str | os.PathLike, geometry: str | os.PathLike, petrophysics: str | os.PathLike | None = None
) -> GridInputs:
    """Read ``grid``, ``geometry`` and ``petrophysics``; one InputError naming the file that is
    damaged, of an older gridlib, or of another grid (another number of cells)."""
    stored = read_netcdf(grid)
    geo = read_geometry_netcdf(geometry)
    counts = {geometry: geo.cell_volumes.size}
    rock = None
    if petrophysics is not None:
        rock = read_rock(petrophysics)
        counts[petrophysics] = rock["poro"].size
    check_same_cells(grid, stored.grid.num_cells, counts)
    attrs = read_attrs(grid)
    return GridInputs(stored, geo, rock, stored_unit_system(grid, attrs), stored_map_axes(grid, attrs))
