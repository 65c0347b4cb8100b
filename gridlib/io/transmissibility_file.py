"""``transmissibility.nc``: what a two-point flux simulator needs of a case's grid.

Per connection (a pair of cells with a non-zero transmissibility; dimension ``connection``):
``connection_cells`` (the two cells, rows of ``grid.nc``, first < second), ``trans``,
``connection_kind`` (0 neighbor, 1 fault, 2 pinch, 3 other) and ``connection_face`` (the
face crossed, -1 for none). Per cell: ``porv``, the pore volume, and ``cell_flow_index``,
the cell's 0-based linear index (i fastest) in the logical box ``flow_dims`` (an attribute)
a simulator sees. Units: the attributes ``unit_system``, ``trans_units`` and ``porv_units``
(permeability in mD). ``{case}.nc`` holds the same variables.
"""

from __future__ import annotations

import os
from functools import partial
from typing import Any

import numpy as np
import xarray as xr

from ..transmissibility import KIND_NAMES, Connections
from ..units import UnitSystem
from .datasets import damaged, open_artifact, read_variable
from .deferred import Deferred, deferring
from .netcdf import deferred_data
from .quantities import label_units

CONNECTION_VARS = ("connection_cells", "trans", "connection_kind", "connection_face")
CELL_VARS = ("porv", "cell_flow_index")


def connections_dataset(
    conn: Connections,
    porv: np.ndarray,
    flow_index: np.ndarray,
    flow_dims: tuple[int, ...],
    system: UnitSystem,
) -> xr.Dataset:
    """The variables of ``transmissibility.nc`` (also written into ``{case}.nc``)."""
    data = {
        "connection_cells": xr.DataArray(
            conn.cells,
            dims=("connection", "two"),
            attrs={"long_name": "the two cells of the connection (0-based cells of grid.nc, first < second)"},
        ),
        "trans": xr.DataArray(
            conn.trans,
            dims=("connection",),
            attrs={"long_name": "transmissibility"},
        ),
        "connection_kind": xr.DataArray(
            np.asarray(conn.kind, dtype=np.int8),
            dims=("connection",),
            attrs={
                "flag_values": np.arange(len(KIND_NAMES), dtype=np.int8),
                "flag_meanings": " ".join(KIND_NAMES),
            },
        ),
        "connection_face": xr.DataArray(
            conn.face,
            dims=("connection",),
            attrs={"long_name": "face of grid.nc the connection crosses, -1 none"},
        ),
        "porv": xr.DataArray(
            np.asarray(porv, dtype=np.float64),
            dims=("cell",),
            attrs={"long_name": "pore volume at reservoir conditions"},
        ),
        "cell_flow_index": xr.DataArray(
            np.asarray(flow_index, dtype=np.int64),
            dims=("cell",),
            attrs={"long_name": "0-based linear index (i fastest) of the cell in the logical box flow_dims"},
        ),
    }
    label_units(data, system, griddim=3)  # T and porv are the same in 2-D
    counts = conn.counts()
    attrs: dict[str, Any] = {
        "unit_system": system.name,
        "trans_units": system.unit("transmissibility"),
        "porv_units": system.unit("porv"),
        "permeability_units": system.unit("permeability"),
        "flow_dims": np.asarray(flow_dims, dtype=np.int64),
        "num_connections": np.int64(conn.num),
        **{f"{kind}_connections": np.int64(n) for kind, n in counts.items()},
    }
    return xr.Dataset(data, attrs=attrs)


def read_transmissibility(
    path: str | os.PathLike, names: tuple[str, ...] = CONNECTION_VARS + CELL_VARS
) -> tuple[dict[str, xr.DataArray], dict[str, Any]]:
    """The variables ``names`` (default: all; loaded, with their attributes) and the global
    attributes of ``transmissibility.nc`` (or of a ``{case}.nc`` that holds them)."""
    with open_artifact(path) as ds:
        missing = [n for n in CONNECTION_VARS + CELL_VARS if n not in ds.variables]
        if missing:
            raise damaged(path, f"not a transmissibility file: {', '.join(missing)} missing")
        variables = {n: xr.DataArray(ds[n].variable.copy(data=read_variable(ds, n)), name=n) for n in names}
        return variables, dict(ds.attrs)


def deferred_connection_variables(path: str | os.PathLike) -> dict[str, xr.Variable]:
    """The :data:`CONNECTION_VARS` of ``transmissibility.nc`` as :func:`read_transmissibility`
    gives them (dimensions, attributes, encoding), each read from ``path`` only when it is
    written (:func:`~gridlib.io.netcdf.deferred_data`): a 1e7-cell grid's 3e7 connections,
    one variable in memory at a time; read at once where they are small
    (:func:`~gridlib.io.deferred.deferring`)."""
    with open_artifact(path) as ds:
        missing = [n for n in CONNECTION_VARS + CELL_VARS if n not in ds.variables]
        if missing:
            raise damaged(path, f"not a transmissibility file: {', '.join(missing)} missing")
        nbytes = sum(ds[name].size * ds[name].dtype.itemsize for name in CONNECTION_VARS)
        if not deferring(nbytes):
            return {
                name: xr.Variable(
                    ds[name].dims, read_variable(ds, name), dict(ds[name].attrs), dict(ds[name].encoding)
                )
                for name in CONNECTION_VARS
            }
        return {
            name: xr.Variable(
                ds[name].dims,
                deferred_data(
                    Deferred(
                        ds[name].shape, ds[name].dtype, partial(_read_one, path, name), f"{path}: {name}"
                    )
                ),
                dict(ds[name].attrs),
                dict(ds[name].encoding),
            )
            for name in CONNECTION_VARS
        }


def _read_one(path: str | os.PathLike, name: str) -> np.ndarray:
    return read_transmissibility(path, (name,))[0][name].values
