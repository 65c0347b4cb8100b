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
from ..config import Case
from ..geometry import compute_geometry
from ..io.netcdf import read_netcdf, write_geometry_netcdf
from ..io.netcdf_parts import stored_unit_system
from .common import log


def stage_geometry(case: Case, *, grid: str | os.PathLike, geometry: str | os.PathLike) -> None:
    """Compute and check the geometry of the grid file ``grid``; write ``geometry``
    (``geometry.nc``)."""
    stored = read_netcdf(grid)
    mesh = stored.grid
    t0 = time.perf_counter()
    geo = compute_geometry(mesh)
    log.info("geometry of %d cells in %.2f s", mesh.num_cells, time.perf_counter() - t0)
    if case.grid_type == "deck":  # degenerate cells kept, named by the grid stage
        degenerate = check_deck_grid(mesh, geo)
        if len(degenerate):
            log.info("%d degenerate cells kept (see the grid stage's notes)", len(degenerate))
    else:
        check_grid(mesh, geo)
    units = stored_unit_system(grid, stored.attrs)  # the grid's: a FIELD deck's volumes are in ft3
    write_geometry_netcdf(geometry, geo, mesh.griddim, case.provenance(), units=units)
    log.info("wrote %s (total volume %.6g)", geometry, geo.cell_volumes.sum())
