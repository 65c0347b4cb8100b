"""One registry of file formats, as meshio's: every format module registers, for each kind of
object it reads or writes, its file suffixes and its reader and writer; :func:`read` and
:func:`write` pick the format from the kind and the suffix of the path.

Kinds: ``grid`` (a gridlib grid: netCDF, VTU), ``geometry`` (a grid's geometry, netCDF),
``deck`` (a corner-point deck: GRDECL text, EGRID, ROFF), ``surface`` (one horizon on a regular
lattice: netCDF, IRAP binary ``.gri``/``.irapbin``, IRAP classic ASCII), ``points`` (scattered
picks: text), ``sticks`` (a fault's sticks: text), ``polygons`` (polylines: RMS/xtgeo text),
``well_path`` (a well's trajectory: text, CSV or RMS well files), ``cube`` (a property cube,
netCDF) and ``horizons`` (a horizons dataset, netCDF). IRAP classic ASCII, point, stick,
polygon and well path files have no fixed suffix: their formats claim every suffix (``*``)
that no other format of the kind claims.
A suffix no format of the kind reads (or writes) is one InputError naming the file.

gridlib's own formats are the table :data:`BUILTIN_FORMATS` below, their readers and writers
named as ``"module:function"`` and imported on first use: importing ``gridlib.io.netcdf`` (as
every workflow stage does) does not import the GRDECL, EGRID, IRAP or VTU modules and what
they need (``tests/test_layering.py`` holds those names to the layering of the import contract).
:func:`register_format` adds a format of one's own (or replaces one); :func:`formats` is the
table in use, a tuple that ``register_format`` replaces as a whole and never changes in place.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from importlib import import_module
from pathlib import Path
from typing import Any

from ..errors import InputError

ANY_SUFFIX = "*"


@dataclass(frozen=True)
class Format:
    """A file format for one kind of object: its name, suffixes (lower case, with the dot, or
    ``*``), and its reader ``reader(path, **options)`` and writer ``writer(path, obj, ...)``,
    each a function or the ``"module:function"`` that names it (imported by :meth:`function`)."""

    name: str
    kind: str
    suffixes: tuple[str, ...]
    reader: Callable[..., Any] | str | None = None
    writer: Callable[..., Any] | str | None = None

    def function(self, mode: str) -> Callable[..., Any]:
        """The reader (``mode="read"``) or writer (``"write"``), imported if named."""
        target = self.reader if mode == "read" else self.writer
        if isinstance(target, str):
            module, _, name = target.partition(":")
            target = getattr(import_module(module), name)
        if target is None:
            raise InputError(f"the {self.name} format cannot {mode} {self.kind} files")
        return target


_IO = "gridlib.io."
BUILTIN_FORMATS = (
    Format("netcdf", "grid", (".nc",), _IO + "netcdf:read_netcdf", _IO + "netcdf:write_netcdf"),
    Format("vtu", "grid", (".vtu",), None, _IO + "vtu:write_vtu"),
    Format(
        "netcdf",
        "geometry",
        (".nc",),
        _IO + "netcdf:read_geometry_netcdf",
        _IO + "netcdf:write_geometry_netcdf",
    ),
    Format(
        "grdecl",
        "deck",
        (".grdecl", ".data", ".inc", ".grd"),
        _IO + "grdecl:read_grdecl",
        _IO + "grdecl:write_grdecl",
    ),
    Format("bgrdecl", "deck", (".bgrdecl",), _IO + "grdecl:read_grdecl"),  # binary: read_grdecl tells
    Format("egrid", "deck", (".egrid", ".fegrid"), _IO + "egrid:read_egrid"),
    Format(
        "roff",
        "deck",
        (".roff", ".roffasc", ".roffbin", ".roff_asc"),  # roff.ROFF_SUFFIXES
        _IO + "roff:read_roff_deck",
        _IO + "roff:write_roff_grid",
    ),
    Format("netcdf", "surface", (".nc",), _IO + "horizon_files:read_surface_netcdf"),
    Format(
        "irap_binary",
        "surface",
        (".gri", ".irapbin"),
        _IO + "irap_binary:read_irap_binary_surface",
        _IO + "irap_binary:write_irap_binary",
    ),
    Format("irap", "surface", (ANY_SUFFIX,), _IO + "irap:read_irap_surface", _IO + "irap:write_irap"),
    Format("rms", "polygons", (ANY_SUFFIX,), _IO + "polygons:read_polygons", _IO + "polygons:write_polygons"),
    Format("text", "points", (ANY_SUFFIX,), _IO + "horizon_files:read_points"),
    Format("text", "sticks", (ANY_SUFFIX,), _IO + "fault_sticks:read_fault_sticks"),
    Format("text", "well_path", (ANY_SUFFIX,), _IO + "well_paths:read_well_path"),
    Format(
        "netcdf",
        "horizons",
        (".nc",),
        _IO + "horizon_files:read_horizons",
        _IO + "horizon_files:write_horizons",
    ),
    Format(
        "netcdf",
        "cube",
        (".nc",),
        _IO + "cube_files:read_property_cube",
        _IO + "cube_files:write_property_cube",
    ),
)
_formats: tuple[Format, ...] = BUILTIN_FORMATS  # replaced as a whole by register_format


def formats() -> tuple[Format, ...]:
    """The registered formats: gridlib's, then those :func:`register_format` added, in order."""
    return _formats


def register_format(
    name: str,
    kind: str,
    suffixes: Sequence[str],
    reader: Callable[..., Any] | str | None = None,
    writer: Callable[..., Any] | str | None = None,
) -> Format:
    """Register a format of one's own for ``read``/``write`` (replacing the format of the same
    name and kind, if any); ``reader``/``writer`` are functions or ``"module:function"``.

    The registered table is replaced by a new tuple in one assignment, so a ``read`` or
    ``write`` running meanwhile (in another thread) sees the old table or the new one whole."""
    global _formats
    fmt = Format(name, kind, tuple(s.lower() for s in suffixes), reader, writer)
    _formats = tuple(f for f in _formats if (f.name, f.kind) != (name, kind)) + (fmt,)
    return fmt


def _suffix(path: str | os.PathLike) -> str:
    return Path(path).suffix.lower()


def find_format(path: str | os.PathLike, kind: str, mode: str = "read") -> Format:
    """The format that reads (``mode="read"``) or writes ``kind`` from the suffix of ``path``.

    >>> find_format("a/b.GRDECL", "deck").name
    'grdecl'
    >>> find_format("b.xyz", "grid", "write")
    Traceback (most recent call last):
    ...
    gridlib.errors.InputError: b.xyz: unknown file type: cannot write '.xyz' files as grid (known: .nc, .vtu)
    """
    table = formats()
    able = [f for f in table if f.kind == kind and (f.reader if mode == "read" else f.writer)]
    suffix = _suffix(path)
    claimed = any(suffix in f.suffixes for f in table if f.kind == kind)
    for f in able:
        if suffix in f.suffixes or (not claimed and ANY_SUFFIX in f.suffixes):
            return f
    known = ", ".join(sorted({s for f in able for s in f.suffixes})) or "none"
    raise InputError(f"{path}: unknown file type: cannot {mode} '{suffix}' files as {kind} (known: {known})")


def kind_of(path: str | os.PathLike, kinds: Sequence[str]) -> str:
    """The first of ``kinds`` whose formats read the suffix of ``path`` (no ``*`` formats).

    >>> kind_of("SPE9.DATA", ("deck", "grid")), kind_of("grid.nc", ("deck", "grid"))
    ('deck', 'grid')
    """
    table = formats()
    suffix = _suffix(path)
    for kind in kinds:
        if any(f.kind == kind and f.reader and suffix in f.suffixes for f in table):
            return kind
    known = ", ".join(sorted({s for f in table if f.kind in kinds and f.reader for s in f.suffixes}))
    raise InputError(
        f"{path}: unknown file type: cannot read '{suffix}' files as {' or '.join(kinds)} (known: {known})"
    )


def read(path: str | os.PathLike, kind: str = "grid", **options: Any) -> Any:
    """The ``kind`` object in ``path``, read by the format its suffix names; ``options`` go to
    the reader (e.g. ``elevation=True`` for surfaces)."""
    return find_format(path, kind, "read").function("read")(path, **options)


def write(path: str | os.PathLike, obj: Any, *args: Any, kind: str = "grid", **options: Any) -> Any:
    """Write ``obj`` (a ``kind`` object) to ``path`` in the format its suffix names."""
    return find_format(path, kind, "write").function("write")(path, obj, *args, **options)
