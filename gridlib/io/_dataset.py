"""Open a netCDF file as a loaded xarray Dataset, or fail with one message naming the file."""

from __future__ import annotations

import os
from pathlib import Path

import xarray as xr

from ..errors import InputError


def load_dataset(path: str | os.PathLike) -> xr.Dataset:
    """The whole file in memory (the file is closed again); InputError if missing or unreadable."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    try:
        with xr.open_dataset(p, engine="netcdf4") as handle:
            return handle.load()
    except (OSError, ValueError) as exc:
        raise InputError(f"{p}: cannot read as netCDF ({exc})") from exc
