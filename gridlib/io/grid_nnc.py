"""The non-neighbour connections of ``grid.nc`` (and ``{case}.nc``): the ``nnc_*`` variables
over an ``nnc`` dimension, written beside the grid by :func:`gridlib.io.netcdf.write_netcdf`'s
``extra`` and read back as an :class:`~gridlib.pillars.nnc.NNC`.

``nnc_cells`` (the two cells, 0-based rows of the grid), ``nnc_global_cells`` (their linear
indices, i fastest), ``nnc_kind`` (0 fault, 1 pinch) and ``nnc_face`` (the connecting face,
-1 for pinch connections). A grid without an NNC list has none of them.
"""

from __future__ import annotations

import os

import numpy as np
import xarray as xr

from ..pillars.nnc import NNC
from .datasets import damaged
from .netcdf_parts import read_extra

NNC_VARS = ("nnc_cells", "nnc_global_cells", "nnc_kind", "nnc_face")


def nnc_variables(nnc: NNC | None) -> dict[str, xr.DataArray]:
    """The NNC list as variables over an ``nnc`` dimension (cells of the grid, 0-based)."""
    if nnc is None:
        return {}
    return {
        "nnc_cells": xr.DataArray(nnc.cells, dims=("nnc", "two"), attrs={"long_name": "cell pair"}),
        "nnc_global_cells": xr.DataArray(
            nnc.global_cells,
            dims=("nnc", "two"),
            attrs={"long_name": "linear index of the cells (i fastest)"},
        ),
        "nnc_kind": xr.DataArray(
            np.asarray(nnc.kind, dtype=np.int8), dims=("nnc",), attrs={"flag_meanings": "fault pinch"}
        ),
        "nnc_face": xr.DataArray(
            nnc.face, dims=("nnc",), attrs={"long_name": "connecting face, -1 for pinch"}
        ),
    }


def read_nnc(path: str | os.PathLike) -> NNC | None:
    """The NNC list of a grid file; None where it has none (no ``nnc_*`` variable); one
    InputError naming the file if it has some of them only, or is damaged."""
    extra = read_extra(path, NNC_VARS)
    if not extra:
        return None
    if len(extra) != len(NNC_VARS):
        missing = ", ".join(n for n in NNC_VARS if n not in extra)
        raise damaged(path, f"its NNC list is incomplete ({missing} missing)")
    if len({values.shape[0] for values in extra.values()}) > 1:
        raise damaged(path, "the variables of its NNC list differ in length")
    return NNC(extra["nnc_cells"], extra["nnc_global_cells"], extra["nnc_kind"], extra["nnc_face"])
