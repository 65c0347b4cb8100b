"""``coarse.nc``: a coarse grid and the partition it comes from.

A gridlib grid file (:mod:`gridlib.io.netcdf`) of the blocks (cells = blocks, faces = the
fine faces between blocks, so it opens in ParaView like any grid) with the coarsen stage's
cell data (``volume``; where the case has rock the upscaled ``poro``, ``ntg``, ``permx``,
``permy``, ``permz``), the ``partition`` of the fine cells (the block of each, over
``fine_cell``) and the attributes ``num_blocks``, ``coarse_faces`` and ``unit_system`` (that of
the fine grid: ``volume`` in m3, ft3 or cm3, see :mod:`gridlib.io.quantities`).
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any

import numpy as np
import xarray as xr

from .datasets import open_artifact, read_variable
from .netcdf import write_netcdf

if TYPE_CHECKING:
    from ..coarsen import CoarseGrid
    from ..units import UnitSystem


def write_coarse(
    path: str | os.PathLike,
    cg: CoarseGrid,
    cell_data: dict[str, np.ndarray],
    attrs: dict[str, Any],
    units: UnitSystem,
) -> None:
    """``coarse.nc``: the blocks of ``cg`` with ``cell_data`` (one value per block), the partition
    of the fine cells and ``attrs`` (the case's provenance); ``units``: the fine grid's unit
    system."""
    extra = {
        "partition": xr.DataArray(
            cg.partition, dims=("fine_cell",), attrs={"long_name": "block of each fine cell"}
        )
    }
    attrs = {**attrs, "num_blocks": int(cg.num_blocks), "coarse_faces": int(cg.faces.num)}
    write_netcdf(path, cg.grid, cell_data=cell_data, extra=extra, attrs=attrs, units=units)


def read_partition(path: str | os.PathLike) -> np.ndarray:
    """The block of every fine cell (``partition`` of ``coarse.nc``); one InputError naming the
    file if it is damaged or incomplete."""
    with open_artifact(path) as ds:
        return read_variable(ds, "partition", "iu", 1)
