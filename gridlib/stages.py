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
import xarray as xr

from .build import build_grid
from .checks import check_grid
from .config import load_case
from .errors import InputError
from .geometry import Geometry, compute_geometry
from .io._atomic import atomic_path
from .io.netcdf import read_netcdf, write_netcdf
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
    write_geometry(geometry_out, geo, grid.griddim, case.provenance())
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
    geo = read_geometry(geometry_nc)
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


def write_geometry(path: str | os.PathLike, geo: Geometry, griddim: int, attrs: dict[str, Any]) -> None:
    """Geometry only (cells and faces dimensions), atomically, with units."""
    area_unit, vol_unit = ("m2", "m3") if griddim == 3 else ("m", "m2")
    ds = xr.Dataset(
        {
            "cell_volume": ("cell", geo.cell_volumes, {"units": vol_unit}),
            "cell_centroid": (("cell", "xyz"), geo.cell_centroids, {"units": "m"}),
            "face_area": ("face", geo.face_areas, {"units": area_unit}),
            "face_normal": (("face", "xyz"), geo.face_normals, {"units": area_unit}),
            "face_centroid": (("face", "xyz"), geo.face_centroids, {"units": "m"}),
        },
        attrs={
            **attrs,
            "gridlib_griddim": np.int32(griddim),
            "total_volume": float(geo.cell_volumes.sum()),
            "min_cell_volume": float(geo.cell_volumes.min()),
            "max_cell_volume": float(geo.cell_volumes.max()),
            "min_face_area": float(geo.face_areas.min()),
        },
    )
    if geo.cell_normals is not None:
        ds["cell_normal"] = (("cell", "xyz3"), geo.cell_normals, {"units": area_unit})
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4")


def read_geometry(path: str | os.PathLike) -> Geometry:
    """Read a file written by :func:`write_geometry`."""
    if not Path(path).is_file():
        raise InputError(f"{path}: no such file")
    with xr.open_dataset(path, engine="netcdf4") as ds:
        ds = ds.load()
    missing = [
        v
        for v in ("cell_volume", "cell_centroid", "face_area", "face_normal", "face_centroid")
        if v not in ds
    ]
    if missing:
        raise InputError(f"{path}: not a gridlib geometry file (missing {', '.join(missing)})")
    return Geometry(
        ds["cell_volume"].values,
        ds["cell_centroid"].values,
        ds["face_area"].values,
        ds["face_normal"].values,
        ds["face_centroid"].values,
        ds["cell_normal"].values if "cell_normal" in ds else None,
    )


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
