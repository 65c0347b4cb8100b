"""Stage ``coarsen``: a partition of the cells and the coarse grid, with upscaled rock (``coarse.nc``).

``coarse.nc`` is a gridlib grid file of the blocks (cells = blocks, faces = the
fine faces between blocks, so it opens in ParaView like any grid) with the
block volumes (sums of the cells' polyhedral volumes), upscaled porosity, NTG
(averages weighted by bulk volume: ECLIPSE's for corner-point and deck grids, as the
simulator's pore volumes) and permeability (mD, the case's method) as cell data, and
the partition of the fine cells (``partition`` over ``fine_cell``).
"""

from __future__ import annotations

import os

import numpy as np

from ..case.partition import case_coarsening, case_partition
from ..coarsen import coarse_grid, upscale_ntg, upscale_permeability, upscale_porosity
from ..config import Case
from ..io.coarse_file import write_coarse
from ..io.netcdf import read_geometry_netcdf, read_netcdf
from ..io.netcdf_parts import read_extra, stored_unit_system
from ..io.rock_file import read_rock
from .common import log


def stage_coarsen(
    case: Case,
    *,
    grid: str | os.PathLike,
    geometry: str | os.PathLike,
    petrophysics: str | os.PathLike | None = None,
    coarse: str | os.PathLike,
) -> None:
    """Partition the grid of the files ``grid`` and ``geometry``, build the coarse grid, upscale
    the rock of ``petrophysics`` (where the case has rock); write ``coarse`` (``coarse.nc``)."""
    stored = read_netcdf(grid)
    mesh = stored.grid
    rock = read_rock(petrophysics) if petrophysics else None
    # METIS needs only the cell volumes: the rest of the geometry is read after it, so that the
    # two never meet at the peak of memory.
    coarsening = case_coarsening(case)
    uniform = coarsening.method == "uniform"
    geo = read_geometry_netcdf(geometry) if uniform else None
    volumes = geo.cell_volumes if geo is not None else read_extra(geometry, ("cell_volume",))["cell_volume"]
    partition = case_partition(case, mesh, rock, cell_volumes=volumes, geometry=geo)
    if geo is None:
        geo = read_geometry_netcdf(geometry)
    cg = coarse_grid(mesh, partition, geo)
    data = {"volume": cg.geometry.cell_volumes}
    if rock is not None:
        # Averages weighted by the volumes the simulator's pore volumes come from: a corner-point
        # cell's ECLIPSE bulk volume (positive where a deck's degenerate cell has a polyhedral
        # volume of zero or less), the polyhedral volume for every other grid.
        v = stored.cell_data.get("bulk_volume", geo.cell_volumes)
        data["poro"] = upscale_porosity(cg, rock["poro"], v)
        data["ntg"] = upscale_ntg(cg, rock["ntg"], v)
        method = coarsening.permeability
        if method == "harmonic-arithmetic" and cg.fine_ijk is None:
            method = "arithmetic"  # harmonic-arithmetic needs logical indices (see upscale_permeability)
            log.info("harmonic-arithmetic needs logical indices: arithmetic averages used")
        k = upscale_permeability(
            cg, np.column_stack([rock["permx"], rock["permy"], rock["permz"]]), v, method
        )
        data |= {"permx": k[:, 0], "permy": k[:, 1], "permz": k[:, 2]}
    write_coarse(coarse, cg, data, case.provenance(), stored_unit_system(grid, stored.attrs))
    log.info("wrote %s: %d blocks, %d coarse faces", coarse, cg.num_blocks, cg.faces.num)
