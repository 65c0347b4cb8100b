"""File formats, one module per format behind one registry (as meshio's).

The registry (:mod:`gridlib.io.registry`) lists, for each kind of object, the formats that read
or write it: their suffixes and their reader and writer; ``read(path, kind=...)`` and
``write(path, obj, kind=...)`` pick the format from the kind (default ``grid``) and the file
suffix, and an unknown suffix is one InputError naming the file:

* ``grid``: gridlib netCDF (``.nc``; :mod:`.netcdf`), VTU (``.vtu``, write; :mod:`.vtu`);
* ``geometry``: netCDF (``.nc``);
* ``deck``: GRDECL text and DATA decks (``.grdecl``, ``.data``, ``.inc``, ``.grd``;
  :mod:`.grdecl`), EGRID (``.egrid``, ``.fegrid``, read; :mod:`.egrid`);
* ``surface``: netCDF (``.nc``, read), IRAP classic ASCII (any other suffix; :mod:`.irap`);
* ``points``: CSV or whitespace-separated text (any suffix, read; :mod:`.horizon_files`);
* ``sticks``: a fault's sticks, ``x y z id`` rows or RMS polygon text (any suffix, read;
  :mod:`.fault_sticks`);
* ``well_path``: a well's trajectory, ``x y z [md]`` text or CSV with named columns, or an RMS
  well file (any suffix, read; :mod:`.well_paths`);
* ``horizons``: horizons datasets (``.nc``; :mod:`.horizon_files`);
* ``cube``: property cubes (``.nc``; :mod:`.cube_files`).

The stage files of a case's results folder, one module each: ``grid.nc`` and ``geometry.nc``
(:mod:`.netcdf`; the grid's NNC list :mod:`.grid_nnc`), ``horizons.nc`` (:mod:`.horizon_files`),
``petrophysics.nc`` (:mod:`.rock_file`), ``coarse.nc`` (:mod:`.coarse_file`),
``transmissibility.nc`` (:mod:`.transmissibility_file`); parts of any of them read alone, and
the check that files read together describe one grid: :mod:`.netcdf_parts`; the table of every
case's summary, ``summary.csv``: :mod:`.summary_table`. Every netCDF file is written with
checksums and every stage file read through :func:`.datasets.open_artifact`: a damaged one is
one InputError naming it (:func:`.datasets.damaged`).

The per-format functions are also importable directly. OPM Flow decks, which are folders of
files rather than one file: :func:`write_flow_deck` (:mod:`gridlib.io.flow`); the fault faces
as VTK PolyData: :mod:`.vtp`; pictures: :mod:`.pictures`; every writer writes atomically
(:mod:`.atomic`). A format module is imported when it is first used (by ``read``/``write`` or a
name below), so importing one format does not cost the others' imports.
"""

from __future__ import annotations

from .._lazy import lazy_exports

# The public names, each imported on first use from the module that defines it.
_EXPORTS: dict[str, str] = {
    "Format": ".registry",
    "find_format": ".registry",
    "formats": ".registry",
    "kind_of": ".registry",
    "read": ".registry",
    "register_format": ".registry",
    "write": ".registry",
    "write_flow_deck": ".flow",
    "GridDataset": ".netcdf",
    "grid_to_dataset": ".netcdf",
    "read_geometry_netcdf": ".netcdf",
    "read_netcdf": ".netcdf",
    "write_geometry_netcdf": ".netcdf",
    "write_netcdf": ".netcdf",
    "write_vtu": ".vtu",
}

__all__ = sorted(_EXPORTS)

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
