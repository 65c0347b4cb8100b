"""Property cube files: a :class:`~gridlib.petrophysics.cubes.PropertyCube` as netCDF-4 (3-D
variables over (z, y, x) with coordinate variables of the cell centres); kind ``cube`` in the
registry."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from ..errors import InputError
from ..petrophysics.cubes import PropertyCube
from .datasets import load_dataset, save_dataset


def read_property_cube(path: str | os.PathLike, variables: Sequence[str] | None = None) -> PropertyCube:
    """A :class:`PropertyCube` from netCDF: 3-D variables over (z, y, x) (x last) with regular 1-D
    coordinate variables of cell centres (m). A vertical coordinate with ``positive = "up"`` is
    an elevation and is negated to depth. ``variables``: which (default: every 3-D variable)."""

    p = Path(path)
    ds = load_dataset(p)
    names = [str(k) for k, v in ds.data_vars.items() if v.ndim == 3] if variables is None else list(variables)
    if not names:
        raise InputError(f"{p}: no 3-D variable (z, y, x) in the file")
    dims = None
    for name in names:
        if name not in ds.data_vars:
            raise InputError(f"{p}: no variable '{name}' (has {', '.join(map(str, ds.data_vars))})")
        if ds[name].ndim != 3:
            raise InputError(f"{p}: '{name}' must be 3-D (z, y, x), has dims {ds[name].dims}")
        if dims is None:
            dims = ds[name].dims
        elif ds[name].dims != dims:
            raise InputError(f"{p}: '{name}' has dims {ds[name].dims}, the others {dims}")
    assert dims is not None
    axes = {}
    for dim in dims:
        if dim not in ds.variables:
            raise InputError(f"{p}: dimension '{dim}' has no coordinate variable")
        axes[dim] = np.asarray(ds[dim].values, dtype=np.float64)
    zdim, ydim, xdim = dims
    flips = []
    zc = axes[zdim]
    if str(ds[zdim].attrs.get("positive", "down")).lower() == "up":
        zc = -zc
    x, y = axes[xdim], axes[ydim]
    values = {}
    for name in names:
        v = np.asarray(ds[name].values, dtype=np.float64)
        for axis, a in ((0, zc), (1, y), (2, x)):
            if a.size > 1 and a[1] < a[0]:
                v = np.flip(v, axis=axis)
        values[name] = v
    for a in (zc, y, x):
        flips.append(a[::-1] if a.size > 1 and a[1] < a[0] else a)
    zc, y, x = flips
    return PropertyCube(x, y, zc, values, source=str(p))


def write_property_cube(
    path: str | os.PathLike, cube: PropertyCube, attrs: Mapping[str, Any] | None = None
) -> Path:
    """Write a :class:`PropertyCube` as netCDF-4 (z, y, x), atomically."""
    coords = {
        "z": ("z", cube.z, {"units": "m", "positive": "down", "long_name": "depth of the cell centres"}),
        "y": ("y", cube.y, {"units": "m", "standard_name": "projection_y_coordinate"}),
        "x": ("x", cube.x, {"units": "m", "standard_name": "projection_x_coordinate"}),
    }
    data = {name: (("z", "y", "x"), v) for name, v in cube.values.items()}
    ds = xr.Dataset(data, coords=coords, attrs={"title": "gridlib property cube", **dict(attrs or {})})
    return save_dataset(path, ds)
