"""Stage ``geometry``: cell volumes and centroids, face areas, normals and centroids (``geometry.nc``)."""

from __future__ import annotations

import os
import time

from ..checks import check_grid
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
    check_grid(grid, geo)
    write_geometry_netcdf(geometry_out, geo, grid.griddim, case.provenance())
    log.info("wrote %s (total volume %.6g)", geometry_out, geo.cell_volumes.sum())
