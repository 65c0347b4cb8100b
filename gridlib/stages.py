"""Workflow stages as plain functions: case file in, artifacts out.

Each stage reads its inputs, calls gridlib and writes its outputs atomically,
with the case's provenance (gridlib version, case file hash, seed) as
attributes. The Snakemake scripts in ``workflow/scripts`` are one-line
wrappers around these, so the same stages run from Python or a CLI.
"""

from __future__ import annotations

import logging
import os
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .build import build_grid
from .checks import check_grid
from .config import load_case
from .errors import InputError
from .geometry import compute_geometry
from .io.netcdf import read_geometry_netcdf, read_netcdf, write_geometry_netcdf, write_netcdf
from .io.vtu import write_vtu

log = logging.getLogger("gridlib.stages")


def stage_grid(case_file: str | os.PathLike, grid_out: str | os.PathLike) -> None:
    """Build the case's grid, check every invariant, write ``grid.nc``."""
    case = load_case(case_file)
    t0 = time.perf_counter()
    grid = build_grid(case)
    log.info("built %r in %.2f s", grid, time.perf_counter() - t0)
    check_grid(grid)
    write_netcdf(grid_out, grid, attrs=case.provenance())
    log.info("wrote %s", grid_out)


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


def stage_export(
    case_file: str | os.PathLike,
    grid_nc: str | os.PathLike,
    geometry_nc: str | os.PathLike,
    vtu_out: str | os.PathLike,
) -> None:
    """Write the case's grid with its geometry as cell data to ``{case}.vtu``."""
    load_case(case_file)
    grid = read_netcdf(grid_nc).grid
    geo = read_geometry_netcdf(geometry_nc)
    if geo.cell_volumes.size != grid.num_cells:
        raise InputError(f"{geometry_nc}: {geo.cell_volumes.size} cells, but {grid_nc} has {grid.num_cells}")
    cell_data: dict[str, np.ndarray] = {"volume": geo.cell_volumes, "centroid": geo.cell_centroids}
    if grid.cells.index_map is not None:
        cell_data["index_map"] = grid.cells.index_map
    if grid.layering is not None:
        cell_data["layer"] = grid.layering.layer
        cell_data["column"] = grid.layering.column
    write_vtu(vtu_out, grid, cell_data)
    log.info("wrote %s", vtu_out)


def run_logged(log_file: str | os.PathLike, stage: Callable[..., None], *args: Any) -> None:
    """Run a stage with gridlib's log (and any traceback) going to ``log_file``."""
    Path(log_file).parent.mkdir(parents=True, exist_ok=True)
    handler = logging.FileHandler(log_file, mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(name)s: %(message)s"))
    root = logging.getLogger("gridlib")
    root.addHandler(handler)
    root.setLevel(logging.INFO)
    try:
        stage(*args)
    except Exception as exc:
        root.error("%s failed: %s", stage.__name__, exc, exc_info=not isinstance(exc, ValueError))
        print(f"gridlib: {exc}", file=sys.stderr)
        raise
    finally:
        root.removeHandler(handler)
        handler.close()
