"""Stage ``geometry``: cell volumes and centroids, face areas, normals and centroids (``geometry.nc``).

The volumes are the polyhedral volumes of the grid's cells (faces shared with the neighbours,
subdivided at faults), also for the degenerate cells a deck case keeps (see
:mod:`gridlib.stages.grid`): there they may be zero or negative. The simulator's volume of a
corner-point cell is its ECLIPSE bulk volume, ``bulk_volume`` in ``grid.nc``.
"""

from __future__ import annotations

import os
import time

from ..checks import check_deck_grid, check_grid
from ..config import load_case
from ..geometry import compute_geometry
from ..io.netcdf import read_netcdf, write_geometry_netcdf
from .common import log


def stage_geometry(
    case_file: str | os.PathLike, grid_nc: str | os.PathLike, geometry_out: str | os.PathLike
) -> None:
    """Compute and check the geometry of ``grid.nc``; write ``geometry.nc``."""
    case = load_case(case_file)
    grid = read_netcdf(grid_nc).grid
    t0 = time.perf_counter()
    geo = compute_geometry(grid)
    log.info("geometry of %d cells in %.2f s", grid.num_cells, time.perf_counter() - t0)
    if case.grid_type == "deck":  # degenerate cells kept, named by the grid stage
        degenerate = check_deck_grid(grid, geo)
        if len(degenerate):
            log.info("%d degenerate cells kept (see the grid stage's notes)", len(degenerate))
    else:
        check_grid(grid, geo)
    write_geometry_netcdf(geometry_out, geo, grid.griddim, case.provenance())
    log.info("wrote %s (total volume %.6g)", geometry_out, geo.cell_volumes.sum())
