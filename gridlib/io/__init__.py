"""File formats, one module per format behind one registry (as meshio's).

Every format module registers, for each kind of object it reads or writes, its suffixes and
its reader and writer (:mod:`gridlib.io.registry`); ``read(path, kind=...)`` and
``write(path, obj, kind=...)`` pick the format from the kind (default ``grid``) and the file
suffix, and an unknown suffix is one InputError naming the file:

* ``grid``: gridlib netCDF (``.nc``; :mod:`.netcdf`), VTU (``.vtu``, write; :mod:`.vtu`);
* ``geometry``: netCDF (``.nc``);
* ``deck``: GRDECL text and DATA decks (``.grdecl``, ``.data``, ``.inc``, ``.grd``;
  :mod:`.grdecl`), EGRID (``.egrid``, ``.fegrid``, read; :mod:`.egrid`);
* ``surface``: netCDF (``.nc``, read), IRAP classic ASCII (any other suffix; :mod:`.irap`);
* ``points``: CSV or whitespace-separated text (any suffix, read; :mod:`.horizon_files`);
* ``horizons``: horizons datasets (``.nc``; :mod:`.horizon_files`);
* ``cube``: property cubes (``.nc``; :mod:`.cubes`).

The per-format functions are also importable directly. OPM Flow decks, which are folders of
files rather than one file: :func:`write_flow_deck` (:mod:`gridlib.io.flow`); the fault faces
as VTK PolyData: :mod:`.vtp`; pictures: :mod:`.pictures`; every writer writes atomically
(:mod:`.atomic`).
"""

from __future__ import annotations

# Every format module, imported here so that each has registered its formats.
from . import cubes, egrid, grdecl, horizon_files, irap, netcdf, vtu  # noqa: F401
from .flow import write_flow_deck
from .netcdf import (
    GridDataset,
    grid_to_dataset,
    read_geometry_netcdf,
    read_netcdf,
    write_geometry_netcdf,
    write_netcdf,
)
from .registry import FORMATS, Format, find_format, kind_of, read, register_format, write
from .vtu import write_vtu

__all__ = [
    "FORMATS",
    "Format",
    "GridDataset",
    "find_format",
    "grid_to_dataset",
    "kind_of",
    "read",
    "read_geometry_netcdf",
    "read_netcdf",
    "register_format",
    "write",
    "write_flow_deck",
    "write_geometry_netcdf",
    "write_netcdf",
    "write_vtu",
]
