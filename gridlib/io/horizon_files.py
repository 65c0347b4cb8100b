"""Horizon files: scattered picks (CSV or text), gridded surfaces in netCDF, ``horizons.nc``, and
the horizons stage's specifications that name them.

IRAP classic ASCII surfaces are :mod:`gridlib.io.irap`. The surfaces read here
are :class:`~gridlib.horizons.surface.Surface` s and the Dataset is
:func:`~gridlib.horizons.dataset.horizon_dataset`'s; :func:`build_horizons`
reads a case's horizon specifications (and their files) and hands them to
:func:`~gridlib.horizons.build.horizons_from_sources`. Units are metres; z is
depth, positive downwards, unless a reader is told ``elevation=True``.
"""

from __future__ import annotations

import copy
import json
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ..arrays import point_array
from ..errors import InputError
from ..grid import FloatArray
from ..horizons.build import SOURCES, HorizonSource, check_lattice, horizons_from_sources
from ..horizons.residuals import PickResiduals
from ..horizons.surface import Surface, regular_increment
from .datasets import damaged, load_artifact, load_dataset, save_dataset
from .registry import read
from .shared_reads import read_once
from .text_table import check_widths, data_rows, read_lines, strip_comment, to_numbers

__all__ = [
    "build_horizons",
    "load_horizon_source",
    "read_horizons",
    "read_pick_residuals",
    "read_points",
    "read_surface_netcdf",
    "write_horizons",
]

_POINT_KEYS = {
    "name",
    "points",
    "method",
    "extrapolation",
    "smoothing",
    "neighbors",
    "columns",
    "elevation",
    "null",
}
_SURFACE_KEYS = {"name", "surface", "method", "variable", "horizon", "elevation"}


def build_horizons(
    specs: Sequence[Mapping[str, Any]],
    x: ArrayLike,
    y: ArrayLike,
    *,
    ordering: str = "error",
    faults: Sequence[Any] = (),
    per_block: bool = False,
    fault_surfaces: Any = None,
    base_dir: str | os.PathLike = ".",
    attrs: Mapping[str, Any] | None = None,
) -> xr.Dataset:
    """The horizons Dataset of a list of horizon specifications, top first (the horizons stage).

    Each spec is a mapping with ``name`` and exactly one source:

    * ``points``: a file (CSV/text, :func:`read_points`; with ``columns``,
      ``elevation``, ``null``) or an (n, 3) array, interpolated with ``method``
      (default linear), ``extrapolation`` (default nan), ``smoothing``,
      ``neighbors``, per fault block of ``faults``;
    * ``surface``: an IRAP classic ASCII file (any suffix but ``.nc``) or a
      netCDF file (``variable``, ``horizon``), or a :class:`~gridlib.horizons.surface.Surface`, resampled
      with ``method`` ``linear`` (default) or ``nearest``; ``elevation``. A
      gridded surface is taken as it is (``faults`` do not apply): a throw in it
      stays within one of its cells;
    * ``plane``, ``dome`` or ``peaks``: the keyword arguments of :func:`~gridlib.horizons.plane`,
      :func:`~gridlib.horizons.dome` or :func:`~gridlib.horizons.peaks`.

    ``per_block`` (with ``faults``): the picks are of already-faulted surfaces. Each fault
    block then also gets its own surfaces over the whole lattice, from its own picks only,
    extended with each horizon's ``extrapolation`` (give ``trend`` or ``nearest``): the
    variable ``depth_by_block`` (fault_block, horizon, y, x), ordered per block, for
    :func:`~gridlib.horizons.by_block.horizons_to_grdecl_by_block`; ``depth`` is then each
    node's own block's value. Formulas and gridded surfaces are the same in every block.
    ``fault_surfaces`` (inclined faults): see
    :func:`~gridlib.horizons.build.horizons_from_sources`.

    Relative paths are relative to ``base_dir``. Errors name the spec, e.g.
    ``horizons[1] ('base'): method: unknown value 'spline'; expected one of ...``.

    >>> x, y = np.linspace(0.0, 400.0, 5), np.linspace(0.0, 200.0, 3)
    >>> top = {"name": "top", "plane": {"depth": 1000.0, "dip": 1.0, "azimuth": 90.0}}
    >>> base = {"name": "base", "dome": {"depth": 1010.0, "relief": 5.0, "radius": 300.0}}
    >>> ds = build_horizons([top, base], x, y)
    >>> ds.depth.shape, list(ds.horizon.values), list(ds.method.values)
    ((2, 3, 5), ['top', 'base'], ['plane', 'dome'])
    """
    if isinstance(specs, Mapping) or not isinstance(specs, Sequence) or not specs:
        raise InputError("horizons: expected a non-empty list of horizon specifications (top first)")
    xa, ya = check_lattice(x, y)
    base = Path(base_dir)
    loaded = [load_horizon_source(k, spec, base) for k, spec in enumerate(specs)]
    return horizons_from_sources(
        loaded,
        xa,
        ya,
        ordering=ordering,
        faults=faults,
        per_block=per_block,
        fault_surfaces=fault_surfaces,
        attrs=attrs,
    )


def load_horizon_source(k: int, spec: Any, base: Path) -> HorizonSource:
    """Spec ``k`` of the horizons stage checked, its file (if any) read (relative to ``base``)."""
    if not isinstance(spec, Mapping):
        raise InputError(f"horizons[{k}]: expected a mapping, got {type(spec).__name__}")
    name = spec.get("name")
    if not isinstance(name, str) or not name:
        raise InputError(f"horizons[{k}]: name: a non-empty string is required")
    label = f"horizons[{k}] ('{name}')"
    given = [s for s in SOURCES if s in spec]
    if len(given) != 1:
        raise InputError(f"{label}: give exactly one of {', '.join(SOURCES)} (got {given or 'none'})")
    kind = given[0]
    allowed = _POINT_KEYS if kind == "points" else _SURFACE_KEYS if kind == "surface" else {"name", kind}
    extra = set(spec) - allowed
    if extra:
        raise InputError(f"{label}: unknown keys {sorted(extra)} for {kind} (allowed: {sorted(allowed)})")
    src = spec[kind]
    if kind in ("plane", "dome", "peaks"):
        if not isinstance(src, Mapping):
            raise InputError(f"{label}: {kind}: expected a mapping of its parameters")
        return HorizonSource(name, label, kind, src, spec, f"{kind} {json.dumps(dict(src), sort_keys=True)}")
    if kind == "points":
        if isinstance(src, str | os.PathLike):
            path = base / src
            pts = read(
                path,
                kind="points",
                columns=spec.get("columns"),
                elevation=bool(spec.get("elevation", False)),
                null=spec.get("null"),
            )
            return HorizonSource(name, label, kind, pts, spec, str(path))
        pts = point_array(src, 3, f"{label}: points (a file name or an array)", min_points=0)
        return HorizonSource(name, label, kind, pts, spec, "points (array)")
    if isinstance(src, Surface):
        return HorizonSource(name, label, kind, src, spec, src.source or f"surface '{src.name}'")
    path = base / src
    elevation = bool(spec.get("elevation", False))
    surf = read(
        path, kind="surface", variable=spec.get("variable"), horizon=spec.get("horizon"), elevation=elevation
    )
    return HorizonSource(name, label, kind, surf, spec, str(path))


def read_points(
    path: str | os.PathLike,
    *,
    columns: Sequence[int] | Sequence[str] | None = None,
    elevation: bool = False,
    null: float | None = None,
) -> FloatArray:
    """Scattered picks ``(n, 3)`` = x, y, z (m) from a CSV or whitespace-separated text file.

    Lines are split at commas if the first data line has one (else at ``;`` if
    it has one, else at whitespace); empty lines and ``#`` comments are skipped.
    A first data line without any number is a header of column names.
    ``columns``: which columns are x, y and z (three 0-based indices, or three
    header names); by default a file must have exactly three. ``null``: rows
    whose z equals it are dropped (a no-data marker such as -999). ``elevation``:
    z is elevation (positive up) and is negated to depth.

    Every problem is an :class:`~gridlib.errors.InputError` naming the file and
    line, e.g. ``picks.csv:7: expected 3 columns (x, y, z), found 2``.
    """
    p = Path(path)
    lines = read_lines(p)
    first = next((line for line in map(strip_comment, lines) if line), "")
    sep = "," if "," in first else ";" if ";" in first else ""  # the first data line's
    table = data_rows(lines, split=lambda line: [f.strip() for f in line.split(sep)] if sep else line.split())
    rows, line_no = table.rows, table.lines
    header = None if table.header is None else [f.lower() for f in table.header]
    if not rows:
        raise InputError(f"{p}: no data lines (expected x, y, z per line)")
    width = len(header) if header is not None else len(rows[0])
    if columns is None:
        if width != 3:
            where = f"{p}:{table.header_line}" if header is not None else f"{p}:{line_no[0]}"
            raise InputError(
                f"{where}: expected 3 columns (x, y, z), found {width}; pass columns= to choose three"
            )
        cols = [0, 1, 2]
    else:
        cols = _point_columns(columns, header, width, p)
    check_widths(p, rows, line_no, width, " (x, y, z)" if width == 3 else "")
    picked = [[fields[c] for c in cols] for fields in rows]
    xyz = to_numbers(
        p, picked, line_no, ("x", "y", "z"), columns=cols, finite_hint=" (use null= for no-data markers)"
    )
    if null is not None:
        xyz = xyz[xyz[:, 2] != float(null)]
        if xyz.shape[0] == 0:
            raise InputError(f"{p}: every z equals the null value {null}")
    if elevation:
        xyz[:, 2] = -xyz[:, 2]
    return xyz


def _point_columns(columns: Sequence[Any], header: list[str] | None, width: int, p: Path) -> list[int]:
    cols = list(columns)
    if len(cols) != 3:
        raise InputError(f"{p}: columns must name three columns (x, y, z), got {columns!r}")
    out = []
    for c in cols:
        if isinstance(c, str):
            if header is None:
                raise InputError(f"{p}: columns names {c!r} but the file has no header line")
            if c.lower() not in header:
                raise InputError(f"{p}: no column {c!r} in the header ({', '.join(header)})")
            out.append(header.index(c.lower()))
        elif isinstance(c, int | np.integer) and not isinstance(c, bool) and 0 <= int(c) < width:
            out.append(int(c))
        else:
            raise InputError(f"{p}: columns: {c!r} is not a column index in [0, {width})")
    return out


def read_surface_netcdf(
    path: str | os.PathLike,
    *,
    variable: str | None = None,
    horizon: str | int | None = None,
    elevation: bool = False,
    name: str | None = None,
) -> Surface:
    """A :class:`~gridlib.horizons.surface.Surface` from a netCDF grid: a 2-D variable over (y, x)
    (the last dimension is x) with 1-D coordinate variables of those dimensions, regularly spaced
    (either direction).

    ``variable``: default ``depth``, else ``z``, else the only 2-D (or 3-D) variable. A
    variable with a ``horizon`` dimension (a ``horizons.nc``) needs ``horizon`` (a name or an
    index). ``elevation``: the values are elevations (positive up), negated to depths.
    """
    p = Path(path)
    ds = load_dataset(p)
    if variable is None:
        for candidate in ("depth", "z"):
            if candidate in ds.data_vars:
                variable = candidate
                break
        else:
            grids = [str(k) for k, v in ds.data_vars.items() if v.ndim >= 2]
            if len(grids) != 1:
                raise InputError(
                    f"{p}: which variable is the surface? pass variable= one of "
                    f"{', '.join(grids) or '(none)'}"
                )
            variable = grids[0]
    if variable not in ds.data_vars:
        raise InputError(f"{p}: no variable '{variable}' (has {', '.join(map(str, ds.data_vars)) or 'none'})")
    da = ds[variable]
    if "horizon" in da.dims:
        names = [str(v) for v in ds["horizon"].values] if "horizon" in ds.coords else []
        if horizon is None:
            raise InputError(f"{p}: '{variable}' holds several horizons; pass horizon= one of {names}")
        if isinstance(horizon, str):
            if horizon not in names:
                raise InputError(f"{p}: no horizon '{horizon}' (has {', '.join(names)})")
            da = da.isel(horizon=names.index(horizon))
        else:
            if not -da.sizes["horizon"] <= int(horizon) < da.sizes["horizon"]:
                raise InputError(
                    f"{p}: horizon index {horizon} out of range ({da.sizes['horizon']} horizons)"
                )
            da = da.isel(horizon=int(horizon))
        label_name = str(horizon) if isinstance(horizon, str) else names[int(horizon)] if names else ""
    else:
        label_name = ""
    if da.ndim != 2:
        raise InputError(f"{p}: '{variable}' must be 2-D (y, x), has dims {da.dims}")
    ydim, xdim = da.dims
    axes = []
    for dim in (xdim, ydim):
        if dim not in ds.coords and dim not in ds.variables:
            raise InputError(f"{p}: dimension '{dim}' of '{variable}' has no coordinate variable")
        a = np.asarray(ds[dim].values, dtype=np.float64)
        if a.ndim != 1 or not np.isfinite(a).all():
            raise InputError(f"{p}: coordinate '{dim}' must be a finite 1-D axis")
        axes.append(a)
    x, y = axes
    z = np.asarray(da.values, dtype=np.float64)
    if x.size > 1 and x[1] < x[0]:
        x, z = x[::-1], z[:, ::-1]
    if y.size > 1 and y[1] < y[0]:
        y, z = y[::-1], z[::-1, :]
    if elevation:
        z = -z
    label = name if name is not None else (label_name or p.stem)
    xinc = regular_increment(x, f"{p}: coordinate '{xdim}'")
    yinc = regular_increment(y, f"{p}: coordinate '{ydim}'")
    return Surface(z, float(x[0]), float(y[0]), xinc, yinc, name=label, source=str(p))


def write_horizons(path: str | os.PathLike, ds: xr.Dataset) -> Path:
    """Write a horizons Dataset (:func:`horizon_dataset`) as netCDF-4, atomically (``horizons.nc``)."""
    if "depth" not in ds or ds["depth"].dims != ("horizon", "y", "x"):
        raise InputError(f"{path}: write_horizons needs a Dataset with depth (horizon, y, x)")
    encoding = {"depth": {"_FillValue": np.nan}}
    if "block" in ds:
        encoding["block"] = {"_FillValue": None}
    return save_dataset(path, ds, encoding)


@read_once(copy.deepcopy)
def read_horizons(path: str | os.PathLike) -> xr.Dataset:
    """Read a ``horizons.nc`` written by :func:`write_horizons` (checked: depth (horizon, y, x))."""
    p = Path(path)
    ds = load_artifact(p)
    if "depth" not in ds or ds["depth"].dims != ("horizon", "y", "x"):
        raise damaged(p, "not a horizons file: it needs a variable depth over (horizon, y, x)")
    for key in ("x", "y", "horizon"):
        if key not in ds.coords:
            raise damaged(p, f"not a horizons file: coordinate '{key}' is missing")
    if ds["depth"].dtype.kind != "f":
        raise damaged(p, f"variable 'depth' has type {ds['depth'].dtype}, expected floats")
    return ds


PICK_VARIABLES = ("pick_horizon", "pick_x", "pick_y", "pick_depth", "pick_residual", "pick_block")


def read_pick_residuals(path: str | os.PathLike) -> tuple[PickResiduals, list[str]]:
    """The picks and residuals stored in a ``horizons.nc`` and the names of its horizons (top
    first); no picks (an empty :class:`PickResiduals`) where it has none (an older file, or no
    horizon given by points)."""
    ds = read_horizons(path)
    names = [str(h) for h in ds["horizon"].values]
    if "pick_residual" not in ds:
        empty = np.zeros(0)
        return PickResiduals(np.zeros(0, np.int32), empty, empty, empty, empty, np.zeros(0, np.int32)), names
    v = {key: ds[key].values for key in PICK_VARIABLES}
    surface = v["pick_depth"] - v["pick_residual"]
    residuals = PickResiduals(
        v["pick_horizon"].astype(np.int32),
        v["pick_x"],
        v["pick_y"],
        v["pick_depth"],
        surface,
        v["pick_block"],
    )
    return residuals, names
