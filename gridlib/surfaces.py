"""Horizons: depth surfaces from points, grids or formulas, per fault block, ordered, as a Dataset.

The horizons stage of a case (ALGORITHMS.md §4): every horizon becomes a depth
map on one areal lattice, the stack is checked or repaired so that depths never
decrease downwards, and the result is an :class:`xarray.Dataset` with dims
``(horizon, y, x)`` written as ``horizons.nc``. Each horizon of it is a
:class:`~gridlib.cornerpoint.horizons.Horizon` for ``horizons_to_grdecl``
(:func:`to_horizons`).

Conventions: x, y and z in metres; **z is depth, positive downwards**; NaN means
undefined (no data there). A lattice is given by its increasing 1-D axes ``x``
(nx,) and ``y`` (ny,) and maps are ``z[j, i]`` at ``(x[i], y[j])``.

Inputs
------
* scattered picks: :func:`read_points` (CSV or whitespace x y z text), then
  :func:`interpolate_points` (onto a lattice) or :func:`interpolate_points_at`
  (at any points, e.g. the areal nodes of a PEBI grid);
* gridded surfaces: :class:`Surface` (a regular, possibly rotated lattice), read
  from IRAP classic ASCII (:func:`gridlib.io.irap.read_irap`) or netCDF
  (:func:`read_surface_netcdf`) and resampled with :meth:`Surface.sample`;
* formulas: :func:`plane` (dip and azimuth), :func:`dome`, :func:`peaks`
  (MATLAB's, as in the MRST book's ``convertHorizonsToGrid`` example).

Interpolation of points (:func:`interpolate_points_at`)
-------------------------------------------------------
``method``: ``"linear"`` (Delaunay, C0; scipy's ``griddata`` linear),
``"cubic"`` (Clough-Tocher, C1), ``"rbf"`` (thin-plate spline with a
linear polynomial, scipy's ``RBFInterpolator``, optional ``smoothing``, local
``neighbors`` for large point sets) or ``"nearest"``. Planes are reproduced
exactly by ``linear`` and ``rbf`` (to round-off), data points by every method
with ``smoothing=0``. Before any of them, x and y are shifted to the points'
mean and divided by the larger side of their bounding box, so results
(``smoothing`` in particular) do not depend on the units or on UTM offsets.

Extrapolation policy, the same for every method: a node is *inside* when it
lies in the convex hull of the points used (of its fault block); outside,
``extrapolation`` decides:

* ``"nan"`` (default): undefined. ``horizons_to_grdecl`` makes cells with an
  undefined corner inactive, so the grid shrinks to where data are;
* ``"nearest"``: the interpolated value at the nearest point of the hull
  (constant along the outward normal, continuous at the hull);
* ``"trend"``: that value continued with the gradient of the least-squares
  plane through the points: z(p) = f(q) + g . (p - q), q the nearest hull
  point. Continuous at the hull and exact for planes.

The RBF's own extrapolation (which can be wild) is therefore never used.

Fault blocks
------------
With ``faults`` (polylines in plan view: (n, 2) arrays or
:class:`~gridlib.cornerpoint.horizons.FaultTrace`), the area (``extent``, by
default the bounding box of the points and the targets) is cut by the traces
into blocks (shapely's polygonize of the traces clipped to the area, their ends
extended by 1e-7 of its diagonal so that a trace ending on another one or on
the boundary closes a block); points and targets are classified by exact
point-in-polygon, and every block is interpolated from its own points only, so
a throw is never smeared across a trace. Points on a trace (within 1e-9 of the
diagonal) belong to no block and are not used; targets on a trace take the
block with the lowest id among those touching them (blocks are numbered by
their centroids, x then y); anything outside the area takes the nearest block.
A trace that ends inside the area without meeting another trace or the
boundary separates nothing (polygonize drops it): it is reported in ``notes``
and the throw is interpolated across it. Let traces run to or beyond the
lattice's edge, as for ``horizons_to_grdecl``.

Ordering
--------
:func:`order_horizons` (and :func:`horizon_dataset`): horizons are listed top
(youngest) first. Where a horizon is shallower than the nearest defined one
above it, the two *cross*. ``"error"`` raises :class:`HorizonCrossingError`
naming each crossing pair, its node count and area (the nodes' tributary
areas), its first node (lowest y, then x) and its largest overlap;
``"erode"`` (younger wins: z_k = max(z_k, z_j) for all j above, a top-down
running maximum) and ``"onlap"`` (older wins: z_k = min(z_k, z_j) for all j
below, a bottom-up running minimum) repair it, so that no thickness is
negative. Never by sorting, which moves volume between zones.
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike, NDArray

from .cornerpoint.horizons import FaultTrace, Horizon
from .errors import InputError
from .io._atomic import atomic_path

__all__ = [
    "EXTRAPOLATIONS",
    "METHODS",
    "ORDERINGS",
    "Crossing",
    "FaultBlocks",
    "HorizonCrossingError",
    "Surface",
    "build_horizons",
    "dome",
    "fault_blocks",
    "find_crossings",
    "horizon_dataset",
    "interpolate_points",
    "interpolate_points_at",
    "order_horizons",
    "peaks",
    "plane",
    "read_horizons",
    "read_points",
    "read_surface_netcdf",
    "to_horizons",
    "write_horizons",
]

METHODS = ("linear", "cubic", "rbf", "nearest")
EXTRAPOLATIONS = ("nan", "nearest", "trend")
ORDERINGS = ("error", "erode", "onlap")
RBF_GLOBAL_MAX = 2000  # beyond this many points (per block) the RBF is local by default
RBF_NEIGHBORS = 64  # ... with this many neighbours

FloatArray = NDArray[np.float64]


# --------------------------------------------------------------------------- gridded surfaces


@dataclass(frozen=True, eq=False)
class Surface:
    """A depth map on a regular lattice (m; z is depth, positive down; NaN = undefined).

    Node ``(i, j)`` lies at ``(xori + i xinc, yori + j yinc)`` in the lattice's
    own frame, which is rotated by ``rotation`` degrees counter-clockwise about
    the origin ``(xori, yori)`` (IRAP's convention); ``z[j, i]`` is its depth.
    ``name`` and ``source`` (a file name) are labels. The array is copied and
    made read-only.

    >>> z = [[1000.0, 1010.0, 1020.0], [1000.0, 1010.0, 1020.0]]
    >>> s = Surface.from_axes([0.0, 100.0, 200.0], [0.0, 50.0], z)
    >>> s.sample([50.0, 150.0, 250.0], [25.0, 25.0, 25.0]).tolist()  # bilinear; NaN outside the lattice
    [1005.0, 1015.0, nan]
    >>> s.to_horizon().z.shape
    (2, 3)
    """

    z: FloatArray
    xori: float
    yori: float
    xinc: float
    yinc: float
    rotation: float = 0.0
    name: str = ""
    source: str = ""

    def __post_init__(self) -> None:
        label = self._label()
        try:
            z = np.array(self.z, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise InputError(f"{label}: z is not an array of numbers ({exc})") from exc
        if z.ndim != 2 or z.size == 0:
            raise InputError(f"{label}: z must be a non-empty 2-D array (ny, nx), got shape {z.shape}")
        if np.isinf(z).any():
            raise InputError(f"{label}: z has infinite values (use NaN for undefined nodes)")
        z.flags.writeable = False
        object.__setattr__(self, "z", z)
        for key in ("xori", "yori", "xinc", "yinc", "rotation"):
            v = getattr(self, key)
            if isinstance(v, bool) or not isinstance(v, int | float | np.integer | np.floating):
                raise InputError(f"{label}: {key} must be a number, got {v!r}")
            v = float(v)
            if not math.isfinite(v) or (key in ("xinc", "yinc") and v <= 0):
                raise InputError(
                    f"{label}: {key} must be finite{' and positive' if 'inc' in key else ''}, got {v}"
                )
            object.__setattr__(self, key, v)

    def _label(self) -> str:
        return f"surface '{self.name}'" + (f" ({self.source})" if self.source else "")

    @classmethod
    def from_axes(cls, x: ArrayLike, y: ArrayLike, z: ArrayLike, name: str = "", source: str = "") -> Surface:
        """A surface on regular increasing axes ``x`` (nx,), ``y`` (ny,), ``z[j, i]`` (ny, nx)."""
        xa, ya = (np.asarray(a, dtype=np.float64) for a in (x, y))
        label = f"surface '{name}'"
        incs = []
        for key, a in (("x", xa), ("y", ya)):
            if a.ndim != 1 or a.size < 1 or not np.isfinite(a).all():
                raise InputError(f"{label}: {key} must be a finite 1-D axis")
            incs.append(_regular_increment(a, f"{label}: {key}"))
        return cls(z, float(xa[0]), float(ya[0]), incs[0], incs[1], name=name, source=source)

    @property
    def nx(self) -> int:
        return self.z.shape[1]

    @property
    def ny(self) -> int:
        return self.z.shape[0]

    @property
    def x(self) -> FloatArray:
        """The x axis of the lattice's own frame (world x when ``rotation`` is 0)."""
        return self.xori + np.arange(self.nx) * self.xinc

    @property
    def y(self) -> FloatArray:
        return self.yori + np.arange(self.ny) * self.yinc

    def node_coordinates(self) -> tuple[FloatArray, FloatArray]:
        """World coordinates ``X, Y`` (ny, nx) of the nodes."""
        u, v = np.meshgrid(np.arange(self.nx) * self.xinc, np.arange(self.ny) * self.yinc)
        c, s = _cos_sin(self.rotation)
        return self.xori + c * u - s * v, self.yori + s * u + c * v

    def to_horizon(self) -> Horizon:
        """The :class:`~gridlib.cornerpoint.horizons.Horizon` (axes and depths) of an unrotated surface."""
        if self.rotation != 0.0:
            raise InputError(
                f"{self._label()}: rotated by {self.rotation:g} degrees; resample it onto an axis-aligned "
                "lattice first (Surface.sample)"
            )
        return Horizon(self.x, self.y, self.z)

    def sample(self, xq: ArrayLike, yq: ArrayLike, method: str = "linear") -> FloatArray:
        """Depths at world points ``(xq, yq)`` (any matching shapes): bilinear (``"linear"``) or
        the nearest node (``"nearest"``); NaN outside the lattice and, bilinearly, wherever an
        undefined node has a non-zero weight. Points within 1e-9 node spacings of the edge count
        as inside."""
        if method not in ("linear", "nearest"):
            raise InputError(f"{self._label()}: sample: method must be 'linear' or 'nearest', got {method!r}")
        xq, yq = np.broadcast_arrays(np.asarray(xq, dtype=np.float64), np.asarray(yq, dtype=np.float64))
        c, s = _cos_sin(self.rotation)
        dx, dy = xq - self.xori, yq - self.yori
        u = (c * dx + s * dy) / self.xinc  # fractional node indices in the lattice frame
        v = (-s * dx + c * dy) / self.yinc
        tol = 1e-9
        inside = (u >= -tol) & (u <= self.nx - 1 + tol) & (v >= -tol) & (v <= self.ny - 1 + tol)
        out = np.full(xq.shape, np.nan)
        u, v = u[inside], v[inside]
        if method == "nearest":
            i = np.clip(np.rint(u), 0, self.nx - 1).astype(np.int64)
            j = np.clip(np.rint(v), 0, self.ny - 1).astype(np.int64)
            out[inside] = self.z[j, i]
            return out
        i0, t = _cell(u, self.nx)
        j0, r = _cell(v, self.ny)
        i1, j1 = np.minimum(i0 + 1, self.nx - 1), np.minimum(j0 + 1, self.ny - 1)
        val = np.zeros(u.shape)
        bad = np.zeros(u.shape, dtype=bool)
        for jj, ii, w in (
            (j0, i0, (1 - t) * (1 - r)),
            (j0, i1, t * (1 - r)),
            (j1, i0, (1 - t) * r),
            (j1, i1, t * r),
        ):
            zz = self.z[jj, ii]
            undefined = np.isnan(zz)
            bad |= undefined & (w > 0)
            val += np.where(undefined, 0.0, zz) * w
        out[inside] = np.where(bad, np.nan, val)
        return out


def _cos_sin(degrees: float) -> tuple[float, float]:
    if degrees == 0.0:
        return 1.0, 0.0
    a = math.radians(degrees)
    return math.cos(a), math.sin(a)


def _cell(u: FloatArray, n: int) -> tuple[NDArray[np.int64], FloatArray]:
    """Lower node and local coordinate in [0, 1] of fractional indices u in [0, n - 1]."""
    if n == 1:
        return np.zeros(u.shape, np.int64), np.zeros(u.shape)
    u = np.clip(u, 0.0, n - 1.0)
    i0 = np.minimum(np.floor(u).astype(np.int64), n - 2)
    return i0, u - i0


def _regular_increment(a: FloatArray, label: str) -> float:
    """The spacing of a regular increasing axis (1.0 for a single node)."""
    if a.size == 1:
        return 1.0
    d = np.diff(a)
    inc = (a[-1] - a[0]) / (a.size - 1)
    if not (d > 0).all():
        raise InputError(f"{label}: must be strictly increasing")
    if np.abs(d - inc).max() > 1e-6 * inc:
        raise InputError(f"{label}: is not regularly spaced (spacings {d.min():g} to {d.max():g})")
    return float(inc)


def read_surface_netcdf(
    path: str | os.PathLike,
    *,
    variable: str | None = None,
    horizon: str | int | None = None,
    elevation: bool = False,
    name: str | None = None,
) -> Surface:
    """A :class:`Surface` from a netCDF grid: a 2-D variable over (y, x) (the last dimension is x)
    with 1-D coordinate variables of those dimensions, regularly spaced (either direction).

    ``variable``: default ``depth``, else ``z``, else the only 2-D (or 3-D) variable. A
    variable with a ``horizon`` dimension (a ``horizons.nc``) needs ``horizon`` (a name or an
    index). ``elevation``: the values are elevations (positive up), negated to depths.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    try:
        with xr.open_dataset(p, engine="netcdf4") as handle:
            ds = handle.load()
    except (OSError, ValueError) as exc:
        raise InputError(f"{p}: cannot read as netCDF ({exc})") from exc
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
    xinc = _regular_increment(x, f"{p}: coordinate '{xdim}'")
    yinc = _regular_increment(y, f"{p}: coordinate '{ydim}'")
    return Surface(z, float(x[0]), float(y[0]), xinc, yinc, name=label, source=str(p))


# --------------------------------------------------------------------------- points


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
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{p}: cannot read as text ({exc})") from exc
    rows: list[list[str]] = []
    line_no: list[int] = []
    sep: str | None = None
    header: list[str] | None = None
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        if sep is None and not rows and header is None:
            sep = "," if "," in line else ";" if ";" in line else ""
        fields = [f.strip() for f in line.split(sep)] if sep else line.split()
        if not rows and header is None and not any(_is_number(f) for f in fields):
            header = [f.lower() for f in fields]
            header_line = number
            continue
        rows.append(fields)
        line_no.append(number)
    if not rows:
        raise InputError(f"{p}: no data lines (expected x, y, z per line)")
    width = len(header) if header is not None else len(rows[0])
    if columns is None:
        if width != 3:
            where = f"{p}:{header_line}" if header is not None else f"{p}:{line_no[0]}"
            raise InputError(
                f"{where}: expected 3 columns (x, y, z), found {width}; pass columns= to choose three"
            )
        cols = [0, 1, 2]
    else:
        cols = _point_columns(columns, header, width, p)
    for fields, number in zip(rows, line_no, strict=True):
        if len(fields) != width:
            raise InputError(
                f"{p}:{number}: expected {width} columns{' (x, y, z)' if width == 3 else ''}, "
                f"found {len(fields)}"
            )
    picked = [[fields[c] for c in cols] for fields in rows]
    try:
        xyz = np.array(picked, dtype=np.float64)
    except ValueError:
        for fields, number in zip(picked, line_no, strict=True):
            for k, f in enumerate(fields):
                if not _is_number(f):
                    raise InputError(
                        f"{p}:{number}: column {cols[k] + 1} ({'xyz'[k]}): {f!r} is not a number"
                    ) from None
        raise
    finite = np.isfinite(xyz).all(axis=1)
    if not finite.all():
        r = int(np.flatnonzero(~finite)[0])
        raise InputError(f"{p}:{line_no[r]}: x, y and z must be finite (use null= for no-data markers)")
    if null is not None:
        xyz = xyz[xyz[:, 2] != float(null)]
        if xyz.shape[0] == 0:
            raise InputError(f"{p}: every z equals the null value {null}")
    if elevation:
        xyz[:, 2] = -xyz[:, 2]
    return xyz


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


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


# --------------------------------------------------------------------------- formulas


def plane(
    x: ArrayLike,
    y: ArrayLike,
    *,
    depth: float,
    dip: float = 0.0,
    azimuth: float = 0.0,
    x0: float = 0.0,
    y0: float = 0.0,
) -> FloatArray:
    """A plane through depth ``depth`` (m) at ``(x0, y0)``, dipping ``dip`` degrees towards
    ``azimuth`` (degrees clockwise from north = +y; 90 = east = +x): depth increases along
    the azimuth, z = depth + tan(dip) ((x - x0) sin(azimuth) + (y - y0) cos(azimuth)).

    >>> plane([0.0, 100.0], [0.0, 0.0], depth=1000.0, dip=45.0, azimuth=90.0).round(9).tolist()
    [1000.0, 1100.0]
    """
    x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
    if not 0.0 <= dip < 90.0:
        raise InputError(f"plane: dip must be in [0, 90) degrees, got {dip!r}")
    a = math.radians(azimuth)
    g = math.tan(math.radians(dip))
    return depth + g * ((x - x0) * math.sin(a) + (y - y0) * math.cos(a))


def dome(
    x: ArrayLike,
    y: ArrayLike,
    *,
    depth: float,
    relief: float,
    radius: float,
    x0: float = 0.0,
    y0: float = 0.0,
) -> FloatArray:
    """A Gaussian dome: depth ``depth`` (m) at its crest ``(x0, y0)``, ``relief`` (m) deeper far
    from it, z = depth + relief (1 - exp(-r^2 / radius^2)), r the distance to the crest (m).

    >>> dome([0.0, 1e6], [0.0, 0.0], depth=1000.0, relief=50.0, radius=500.0).tolist()
    [1000.0, 1050.0]
    """
    if not radius > 0:
        raise InputError(f"dome: radius must be positive, got {radius!r}")
    x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
    r2 = ((x - x0) ** 2 + (y - y0) ** 2) / radius**2
    return depth + relief * (1.0 - np.exp(-r2))


def peaks(
    x: ArrayLike,
    y: ArrayLike,
    *,
    depth: float = 0.0,
    amplitude: float = 1.0,
    length: float = 1.0,
    x0: float = 0.0,
    y0: float = 0.0,
) -> FloatArray:
    """MATLAB's ``peaks`` as a depth map: z = depth + amplitude P(u, v), u = (x - x0) / length,
    v = (y - y0) / length, P(u, v) = 3 (1-u)^2 exp(-u^2 - (v+1)^2) - 10 (u/5 - u^3 - v^5)
    exp(-u^2 - v^2) - exp(-(u+1)^2 - v^2) / 3 (peaks(n) samples u, v in [-3, 3]).

    The MRST book's ``[y,x,z] = peaks(15); z = z+8`` names MATLAB's X axis y, so its top
    horizon is ``peaks(y, x, depth=8.0)`` at ``x, y = meshgrid(linspace(-3, 3, 15))``
    (z is depth, so the peaks point down).

    >>> round(float(peaks(0.0, 0.0)), 9)  # 8 / (3 e)
    0.981011843
    """
    if not length > 0:
        raise InputError(f"peaks: length must be positive, got {length!r}")
    u = (np.asarray(x, dtype=np.float64) - x0) / length
    v = (np.asarray(y, dtype=np.float64) - y0) / length
    p = (
        3.0 * (1.0 - u) ** 2 * np.exp(-(u**2) - (v + 1.0) ** 2)
        - 10.0 * (u / 5.0 - u**3 - v**5) * np.exp(-(u**2) - v**2)
        - np.exp(-((u + 1.0) ** 2) - v**2) / 3.0
    )
    return depth + amplitude * p


# --------------------------------------------------------------------------- fault blocks


@dataclass(frozen=True, eq=False)
class FaultBlocks:
    """The blocks into which fault traces cut a rectangle (see the module docstring).

    ``polygons``: the blocks (shapely polygons), block id = position;
    ``traces``: the traces as used (clipped shapely lines); ``tolerance``: the
    distance (m) within which a point lies on a trace; ``notes``: traces that
    separate nothing along part of their length.
    """

    polygons: tuple[Any, ...]
    traces: Any
    tolerance: float
    notes: tuple[str, ...]

    @property
    def num(self) -> int:
        return len(self.polygons)

    def classify(self, px: ArrayLike, py: ArrayLike, *, on_trace: str = "lowest") -> NDArray[np.int64]:
        """Block id of every point ``(px, py)`` (matching shapes). A point on a trace (touching
        several blocks) gets the lowest of their ids (``on_trace="lowest"``) or -1 (``"none"``);
        a point outside the rectangle gets the nearest block."""
        import shapely

        if on_trace not in ("lowest", "none"):
            raise InputError(f"FaultBlocks.classify: on_trace must be 'lowest' or 'none', got {on_trace!r}")
        px, py = np.broadcast_arrays(np.asarray(px, dtype=np.float64), np.asarray(py, dtype=np.float64))
        fx, fy = px.ravel(), py.ravel()
        ids = np.full(fx.size, -1, dtype=np.int64)
        for b, poly in enumerate(self.polygons):
            shapely.prepare(poly)
            todo = np.flatnonzero(ids < 0)
            if todo.size == 0:
                break
            inside = shapely.contains_xy(poly, fx[todo], fy[todo])
            ids[todo[inside]] = b
        rest = np.flatnonzero(ids < 0)
        if rest.size:  # on a trace, on the rectangle's edge, or outside it
            pts = shapely.points(fx[rest], fy[rest])
            dist = np.stack([shapely.distance(poly, pts) for poly in self.polygons])
            nearest = dist.argmin(axis=0)
            touching = (dist <= self.tolerance).sum(axis=0)
            on = touching >= 2
            first_touching = np.argmax(dist <= self.tolerance, axis=0)
            ids[rest] = np.where(on, first_touching if on_trace == "lowest" else -1, nearest)
        return ids.reshape(px.shape)


def _extent(*coords: ArrayLike) -> tuple[float, float, float, float]:
    """The bounding box (xmin, xmax, ymin, ymax) of x, y arrays given in pairs; a degenerate side is
    widened by 1e-9 of the other (or by 1 m)."""
    xs = np.concatenate([np.ravel(c) for c in coords[0::2]])
    ys = np.concatenate([np.ravel(c) for c in coords[1::2]])
    lo, hi = np.array([xs.min(), ys.min()]), np.array([xs.max(), ys.max()])
    pad = np.where(hi > lo, 0.0, 1e-9 * float((hi - lo).max()) or 1.0)
    return float(lo[0] - pad[0]), float(hi[0] + pad[0]), float(lo[1] - pad[1]), float(hi[1] + pad[1])


def _trace_points(f: Any, index: int) -> FloatArray:
    pts = getattr(f, "points", f)  # a FaultTrace, or anything with points, or the polyline itself
    try:
        arr = np.asarray(pts, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"faults[{index}]: not a polyline of (x, y) points ({exc})") from exc
    if arr.ndim != 2 or arr.shape[1] != 2 or arr.shape[0] < 2 or not np.isfinite(arr).all():
        raise InputError(
            f"faults[{index}]: a trace must be a finite (n >= 2, 2) array of x, y, got shape {arr.shape}"
        )
    return arr


def fault_blocks(faults: Sequence[Any], extent: Sequence[float]) -> FaultBlocks:
    """Cut the rectangle ``extent = (xmin, xmax, ymin, ymax)`` (m) by fault traces into blocks.

    ``faults``: polylines in plan view, (n, 2) arrays of x, y or
    :class:`~gridlib.cornerpoint.horizons.FaultTrace`. See the module docstring
    for the rules.

    >>> b = fault_blocks([[(500.0, -1.0), (500.0, 101.0)]], (0.0, 1000.0, 0.0, 100.0))
    >>> b.num, b.classify([100.0, 900.0, 500.0], [50.0, 50.0, 50.0]).tolist()
    (2, [0, 1, 0])
    """
    import shapely
    from shapely.ops import polygonize_full

    xmin, xmax, ymin, ymax = (float(v) for v in extent)
    if not (xmax > xmin and ymax > ymin):
        raise InputError(f"fault_blocks: the extent {tuple(extent)} is empty")
    box = shapely.box(xmin, ymin, xmax, ymax)
    diag = math.hypot(xmax - xmin, ymax - ymin)
    if isinstance(faults, FaultTrace) or (isinstance(faults, np.ndarray) and faults.ndim == 2):
        raise InputError("faults: expected a sequence of traces, got a single trace (wrap it in a list)")
    lines, clipped = [], []
    for k, f in enumerate(faults):
        pts = _trace_points(f, k)
        ext = pts.copy()  # overshoot both ends a little so that a trace that meets another one closes a block
        for end, nxt in ((0, 1), (-1, -2)):
            d = pts[end] - pts[nxt]
            n = math.hypot(*d)
            if n > 0:
                ext[end] = pts[end] + d / n * 1e-7 * diag
        line = shapely.LineString(ext)
        lines.append(line)
        clipped.append(line.intersection(box))
    noded = shapely.unary_union([box.boundary, *clipped])
    polys, cuts, dangles, _invalid = polygonize_full([noded])
    polygons = [g for g in shapely.get_parts(polys) if g.area > 0]
    if not polygons:  # no trace crosses the box: one block
        polygons = [box]
    polygons.sort(key=lambda g: (g.centroid.x, g.centroid.y))
    loose = shapely.union_all([dangles, cuts])
    notes = []
    for k, line in enumerate(clipped):
        if line.is_empty:
            notes.append(f"fault trace {k} lies outside the area and separates nothing")
            continue
        length = line.intersection(loose).length
        if length > 1e-6 * diag:
            notes.append(
                f"fault trace {k} separates no blocks along {length:.6g} m of its {line.length:.6g} m "
                "(it ends inside the area without meeting another trace or the boundary): the throw is "
                "interpolated across there"
            )
    return FaultBlocks(tuple(polygons), shapely.union_all(clipped), 1e-9 * diag, tuple(notes))


# --------------------------------------------------------------------------- interpolation


def _check_choice(value: Any, choices: Sequence[str], option: str) -> str:
    if not isinstance(value, str) or value not in choices:
        raise InputError(f"{option}: unknown value {value!r}; expected one of {', '.join(choices)}")
    return value


def interpolate_points(
    points: ArrayLike,
    x: ArrayLike,
    y: ArrayLike,
    *,
    method: str = "linear",
    extrapolation: str = "nan",
    smoothing: float = 0.0,
    neighbors: int | None = None,
    faults: Sequence[Any] = (),
    extent: Sequence[float] | None = None,
    name: str = "surface",
    notes: list[str] | None = None,
) -> FloatArray:
    """Interpolate scattered picks ``(n, 3)`` = x, y, z (m, z depth) onto the lattice of axes
    ``x`` (nx,), ``y`` (ny,): the depth map ``z[j, i]`` (ny, nx), NaN where undefined.

    See :func:`interpolate_points_at` for the options.

    >>> rng = np.random.default_rng(0)
    >>> xy = rng.uniform(0.0, 1000.0, (200, 2))
    >>> pts = np.column_stack([xy, plane(xy[:, 0], xy[:, 1], depth=1000.0, dip=5.0, azimuth=90.0)])
    >>> x, y = np.linspace(0.0, 1000.0, 11), np.linspace(0.0, 500.0, 6)
    >>> z = interpolate_points(pts, x, y, method="rbf", extrapolation="trend")
    >>> bool(np.abs(z - plane(*np.meshgrid(x, y), depth=1000.0, dip=5.0, azimuth=90.0)).max() < 1e-9)
    True
    """
    xa, ya = (np.asarray(a, dtype=np.float64) for a in (x, y))
    for key, a in (("x", xa), ("y", ya)):
        if a.ndim != 1 or a.size < 1 or not np.isfinite(a).all() or (np.diff(a) <= 0).any():
            raise InputError(f"{name}: the lattice axis {key} must be finite, 1-D and strictly increasing")
    X, Y = np.meshgrid(xa, ya)
    return interpolate_points_at(
        points,
        X,
        Y,
        method=method,
        extrapolation=extrapolation,
        smoothing=smoothing,
        neighbors=neighbors,
        faults=faults,
        extent=extent,
        name=name,
        notes=notes,
    )


def interpolate_points_at(
    points: ArrayLike,
    xq: ArrayLike,
    yq: ArrayLike,
    *,
    method: str = "linear",
    extrapolation: str = "nan",
    smoothing: float = 0.0,
    neighbors: int | None = None,
    faults: Sequence[Any] = (),
    extent: Sequence[float] | None = None,
    name: str = "surface",
    notes: list[str] | None = None,
) -> FloatArray:
    """Interpolate scattered picks ``(n, 3)`` = x, y, z (m, z depth) at the points ``(xq, yq)``
    (matching shapes); returns depths of that shape, NaN where undefined.

    ``method``: ``"linear"``, ``"cubic"``, ``"rbf"`` or ``"nearest"``;
    ``extrapolation``: ``"nan"``, ``"nearest"`` or ``"trend"`` (module docstring).
    ``smoothing`` (>= 0, ``rbf`` only): scipy's RBF smoothing on the
    non-dimensionalised coordinates; 0 interpolates. ``neighbors`` (``rbf``
    only): the number of nearest points of each local RBF; default: a global
    RBF up to 2000 points (per block), else 64 neighbours (the global solve is
    O(n^3)). ``faults``: traces (module docstring), each block interpolated
    from its own points; ``extent`` = (xmin, xmax, ymin, ymax), the area they
    cut into blocks (default: the bounding box of the points and the targets).
    ``name`` labels error messages; messages about blocks
    without data or traces that separate nothing are appended to ``notes``.

    A block with fewer than three non-collinear points gets no values (NaN);
    a result that is NaN everywhere is an :class:`~gridlib.errors.InputError`.
    """
    method = _check_choice(method, METHODS, f"{name}: method")
    extrapolation = _check_choice(extrapolation, EXTRAPOLATIONS, f"{name}: extrapolation")
    if isinstance(smoothing, bool) or not isinstance(smoothing, int | float) or not smoothing >= 0:
        raise InputError(f"{name}: smoothing must be a number >= 0, got {smoothing!r}")
    if smoothing and method != "rbf":
        raise InputError(f"{name}: smoothing applies to method 'rbf' only (method is {method!r})")
    if neighbors is not None:
        if method != "rbf":
            raise InputError(f"{name}: neighbors applies to method 'rbf' only (method is {method!r})")
        if isinstance(neighbors, bool) or not isinstance(neighbors, int | np.integer) or neighbors < 3:
            raise InputError(f"{name}: neighbors must be an integer >= 3, got {neighbors!r}")
    try:
        pts = np.asarray(points, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name}: points must be an (n, 3) array of x, y, z ({exc})") from exc
    if pts.ndim != 2 or pts.shape[1] != 3 or pts.shape[0] == 0:
        raise InputError(f"{name}: points must be an (n, 3) array of x, y, z, got shape {pts.shape}")
    if not np.isfinite(pts).all():
        raise InputError(f"{name}: points must be finite (drop undefined picks)")
    xq, yq = np.broadcast_arrays(np.asarray(xq, dtype=np.float64), np.asarray(yq, dtype=np.float64))
    if not (np.isfinite(xq).all() and np.isfinite(yq).all()):
        raise InputError(f"{name}: the target points must be finite")
    notes = [] if notes is None else notes
    qx, qy = xq.ravel(), yq.ravel()
    out = np.full(qx.size, np.nan)

    # Non-dimensional coordinates: shift to the points' mean, scale by the larger side of their box.
    centre = pts[:, :2].mean(axis=0)
    scale = float(np.ptp(pts[:, :2], axis=0).max()) or 1.0
    P = (pts[:, :2] - centre) / scale
    Q = (np.column_stack([qx, qy]) - centre) / scale

    if faults is None or len(faults) == 0:
        groups = [(np.arange(pts.shape[0]), np.arange(qx.size), f"{name}")]
    else:
        if extent is None:
            extent = _extent(pts[:, 0], pts[:, 1], qx, qy)
        blocks = fault_blocks(faults, extent)
        notes.extend(f"{name}: {n}" for n in blocks.notes)
        p_block = blocks.classify(pts[:, 0], pts[:, 1], on_trace="none")
        q_block = blocks.classify(qx, qy, on_trace="lowest")
        dropped = int((p_block < 0).sum())
        if dropped:
            notes.append(f"{name}: {dropped} points lie on a fault trace and were not used")
        groups = [
            (np.flatnonzero(p_block == b), np.flatnonzero(q_block == b), f"{name}: fault block {b}")
            for b in range(blocks.num)
        ]
    for p_idx, q_idx, label in groups:
        if q_idx.size == 0:
            continue
        out[q_idx] = _interpolate_group(
            P[p_idx],
            pts[p_idx, 2],
            Q[q_idx],
            method,
            extrapolation,
            float(smoothing),
            neighbors,
            label,
            notes,
        )
    if np.isnan(out).all():
        raise InputError(
            f"{name}: the interpolated surface is undefined (NaN) everywhere: the points do not cover the "
            f"targets (extrapolation={extrapolation!r}) or no block has three non-collinear points"
        )
    return out.reshape(xq.shape)


def _interpolate_group(
    P: FloatArray,
    z: FloatArray,
    Q: FloatArray,
    method: str,
    extrapolation: str,
    smoothing: float,
    neighbors: int | None,
    label: str,
    notes: list[str],
) -> FloatArray:
    """One block: points P (m, 2) with depths z at targets Q (q, 2), all non-dimensional."""
    from scipy.interpolate import (
        CloughTocher2DInterpolator,
        LinearNDInterpolator,
        NearestNDInterpolator,
        RBFInterpolator,
    )
    from scipy.spatial import ConvexHull, Delaunay, QhullError

    out = np.full(Q.shape[0], np.nan)
    if P.shape[0] < 3:
        notes.append(f"{label}: {P.shape[0]} points (needs 3 non-collinear); its targets are undefined")
        return out
    try:
        tri = Delaunay(P)
        hull = ConvexHull(P)
    except QhullError:
        notes.append(f"{label}: its {P.shape[0]} points are collinear; its targets are undefined")
        return out
    if method == "linear":
        f = LinearNDInterpolator(tri, z)
    elif method == "cubic":
        f = CloughTocher2DInterpolator(tri, z)
    elif method == "nearest":
        f = NearestNDInterpolator(P, z)
    else:
        n = P.shape[0]
        k = neighbors if neighbors is not None else (None if n <= RBF_GLOBAL_MAX else RBF_NEIGHBORS)
        if k is not None and k >= n:
            k = None
        if smoothing == 0 and np.unique(P, axis=0).shape[0] < n:
            counts = np.unique(P, axis=0, return_counts=True)[1]
            raise InputError(
                f"{label}: method 'rbf' with smoothing 0 needs distinct (x, y); {int((counts > 1).sum())} "
                "locations have several points (use smoothing > 0, or another method)"
            )
        try:
            f = RBFInterpolator(P, z, neighbors=k, smoothing=smoothing, kernel="thin_plate_spline", degree=1)
        except np.linalg.LinAlgError as exc:
            raise InputError(f"{label}: the RBF system is singular ({exc}); use smoothing > 0") from exc
    inside = tri.find_simplex(Q) >= 0
    if inside.any():
        out[inside] = f(Q[inside])
    outside = np.flatnonzero(~inside)
    if outside.size == 0 or extrapolation == "nan":
        return out
    import shapely

    ring = shapely.LinearRing(P[hull.vertices])
    lines = shapely.shortest_line(ring, shapely.points(Q[outside]))
    q = shapely.get_coordinates(lines)[0::2]  # the end on the hull
    fq = f(q)
    miss = np.isnan(fq)  # outside by round-off: retry just inside, then take the nearest point
    if miss.any():
        q[miss] += 1e-9 * (P[hull.vertices].mean(axis=0) - q[miss])
        fq[miss] = f(q[miss])
        miss = np.isnan(fq)
        if miss.any():
            fq[miss] = NearestNDInterpolator(P, z)(q[miss])
    if extrapolation == "trend":
        A = np.column_stack([np.ones(P.shape[0]), P])
        coef = np.linalg.lstsq(A, z, rcond=None)[0]
        fq = fq + (Q[outside] - q) @ coef[1:]
    out[outside] = fq
    return out


# --------------------------------------------------------------------------- ordering


@dataclass(frozen=True)
class Crossing:
    """Where horizon ``lower`` lies above horizon ``upper`` (the nearest defined one above it).

    ``nodes``: how many lattice nodes; ``area`` (m2): their tributary areas;
    ``x``, ``y``: the first such node (lowest y, then x); ``max_overlap`` (m):
    the largest ``z[upper] - z[lower]``.
    """

    upper: str
    lower: str
    nodes: int
    area: float
    x: float
    y: float
    max_overlap: float

    def __str__(self) -> str:
        return (
            f"horizons '{self.upper}' and '{self.lower}' cross at {self.nodes} nodes ({self.area:.6g} m2), "
            f"first at (x, y) = ({self.x:.6g}, {self.y:.6g}), by up to {self.max_overlap:.6g} m"
        )


class HorizonCrossingError(InputError):
    """Horizons cross and the ordering is ``"error"``; ``crossings`` lists where."""

    def __init__(self, message: str, crossings: Sequence[Crossing]) -> None:
        super().__init__(message)
        self.crossings = tuple(crossings)


def _tributary(a: FloatArray) -> FloatArray:
    """Length of axis a attributed to each node: half the spacing on either side."""
    if a.size == 1:
        return np.zeros(1)
    d = np.diff(a)
    return np.concatenate([[d[0] / 2], (d[:-1] + d[1:]) / 2, [d[-1] / 2]])


def _names(names: Sequence[str] | None, n: int) -> list[str]:
    if names is None:
        return [f"horizon_{k}" for k in range(n)]
    out = [str(v) for v in names]
    if len(out) != n:
        raise InputError(f"horizon names: {len(out)} names for {n} horizons")
    if len(set(out)) != n:
        raise InputError(f"horizon names must be distinct, got {out}")
    return out


def _stack(depth: ArrayLike, x: ArrayLike, y: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    H = np.asarray(depth, dtype=np.float64)
    xa, ya = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    if H.ndim != 3 or H.shape[1:] != (ya.size, xa.size):
        raise InputError(
            f"horizons: depth must have shape (horizons, len(y), len(x)) = (n, {ya.size}, {xa.size}), "
            f"got {H.shape}"
        )
    return H, xa, ya


def find_crossings(
    depth: ArrayLike, x: ArrayLike, y: ArrayLike, names: Sequence[str] | None = None
) -> list[Crossing]:
    """The crossings of a stack ``depth`` (horizons, ny, nx), top first, on axes ``x``, ``y`` (m).

    At every node each horizon is compared with the nearest *defined* horizon
    above it; equal depths (zero thickness) do not cross.

    >>> x, y = np.linspace(0.0, 1000.0, 11), np.linspace(0.0, 500.0, 6)
    >>> X, Y = np.meshgrid(x, y)
    >>> print(find_crossings([1000.0 + 0.02 * X, np.full_like(X, 1010.0)], x, y, ["top", "base"])[0])
    horizons 'top' and 'base' cross at 30 nodes (225000 m2), first at (x, y) = (600, 0), by up to 10 m
    """
    H, xa, ya = _stack(depth, x, y)
    label = _names(names, H.shape[0])
    defined = np.isfinite(H)
    idx = np.where(defined, np.arange(H.shape[0])[:, None, None], -1)
    last = np.maximum.accumulate(idx, axis=0)  # nearest defined horizon at or above
    area = _tributary(ya)[:, None] * _tributary(xa)[None, :]
    out = []
    for k in range(1, H.shape[0]):
        ref = last[k - 1]
        zref = np.take_along_axis(H, np.maximum(ref, 0)[None], axis=0)[0]
        with np.errstate(invalid="ignore"):
            bad = defined[k] & (ref >= 0) & (H[k] < zref)
        for j in np.unique(ref[bad]):
            m = bad & (ref == j)
            first = int(np.flatnonzero(m)[0])
            out.append(
                Crossing(
                    label[int(j)],
                    label[k],
                    int(m.sum()),
                    float(area[m].sum()),
                    float(xa[first % xa.size]),
                    float(ya[first // xa.size]),
                    float((zref - H[k])[m].max()),
                )
            )
    return out


def order_horizons(
    depth: ArrayLike,
    x: ArrayLike,
    y: ArrayLike,
    *,
    ordering: str = "error",
    names: Sequence[str] | None = None,
) -> tuple[FloatArray, tuple[str, ...]]:
    """Check or repair the order of a stack ``depth`` (horizons, ny, nx), top first (m, z depth).

    Returns the (repaired) stack and notes saying what moved. ``"error"``
    raises :class:`HorizonCrossingError`; ``"erode"`` and ``"onlap"`` repair
    (module docstring). Undefined (NaN) nodes stay undefined and are skipped.

    >>> x, y = np.linspace(0.0, 1000.0, 11), np.linspace(0.0, 500.0, 6)
    >>> X, _ = np.meshgrid(x, y)
    >>> H, notes = order_horizons([1000.0 + 0.02 * X, np.full_like(X, 1010.0)], x, y, ordering="erode")
    >>> float((H[1] - H[0]).min()), notes[0]
    (0.0, "ordering 'erode': horizon 'horizon_1' moved down to a horizon above it at 30 nodes")
    """
    ordering = _check_choice(ordering, ORDERINGS, "ordering")
    H, xa, ya = _stack(depth, x, y)
    label = _names(names, H.shape[0])
    crossings = find_crossings(H, xa, ya, label)
    if not crossings:
        return H.copy(), ()
    if ordering == "error":
        raise HorizonCrossingError(
            "horizons cross: "
            + "; ".join(map(str, crossings))
            + " (set ordering to 'erode' or 'onlap' to repair)",
            crossings,
        )
    defined = np.isfinite(H)
    if ordering == "erode":
        fixed = np.fmax.accumulate(H, axis=0)
    else:
        fixed = np.fmin.accumulate(H[::-1], axis=0)[::-1]
    fixed = np.where(defined, fixed, np.nan)
    notes = []
    for k in range(H.shape[0]):
        moved = int((defined[k] & (fixed[k] != H[k])).sum())
        if moved:
            where = "down to a horizon above" if ordering == "erode" else "up to a horizon below"
            notes.append(f"ordering '{ordering}': horizon '{label[k]}' moved {where} it at {moved} nodes")
    return fixed, tuple(notes)


# --------------------------------------------------------------------------- the Dataset


def horizon_dataset(
    depth: ArrayLike | Sequence[ArrayLike],
    x: ArrayLike,
    y: ArrayLike,
    *,
    names: Sequence[str] | None = None,
    ordering: str = "error",
    block: ArrayLike | None = None,
    sources: Sequence[str] | None = None,
    methods: Sequence[str] | None = None,
    notes: Sequence[str] = (),
    attrs: Mapping[str, Any] | None = None,
) -> xr.Dataset:
    """The horizons Dataset: ``depth`` (horizon, y, x) in m (z is depth, positive down, NaN =
    undefined), ordered by ``ordering``, with coordinates ``horizon`` (names, top first), ``x``,
    ``y`` (m), per-horizon ``source`` and ``method`` labels, an optional ``block`` (y, x) fault
    block id per node, and attributes: ``ordering``, ``notes`` (JSON list), ``gridlib_version``
    and ``attrs`` (provenance: case file hash, seed, ...).

    >>> x, y = np.linspace(0.0, 400.0, 5), np.linspace(0.0, 200.0, 3)
    >>> ds = horizon_dataset([np.full((3, 5), 1000.0), np.full((3, 5), 1020.0)], x, y, names=["top", "base"])
    >>> ds.depth.dims, ds.depth.attrs["units"], [h.z[0, 0] for h in to_horizons(ds)]
    (('horizon', 'y', 'x'), 'm', [np.float64(1000.0), np.float64(1020.0)])
    """
    from . import __version__

    H, xa, ya = _stack(np.asarray(depth, dtype=np.float64), x, y)
    if H.shape[0] < 1:
        raise InputError("horizons: the stack is empty")
    label = _names(names, H.shape[0])
    for k in range(H.shape[0]):
        if np.isnan(H[k]).all():
            raise InputError(f"horizon '{label[k]}': undefined (NaN) everywhere on the lattice")
        if np.isinf(H[k]).any():
            raise InputError(f"horizon '{label[k]}': has infinite depths (use NaN for undefined)")
    for key, a in (("x", xa), ("y", ya)):
        if a.ndim != 1 or not np.isfinite(a).all() or (np.diff(a) <= 0).any():
            raise InputError(f"horizons: the lattice axis {key} must be finite, 1-D and strictly increasing")
    H, order_notes = order_horizons(H, xa, ya, ordering=ordering, names=label)
    n = H.shape[0]
    src = ["" if s is None else str(s) for s in (sources or [""] * n)]
    met = ["" if s is None else str(s) for s in (methods or [""] * n)]
    if len(src) != n or len(met) != n:
        raise InputError(f"horizons: sources and methods need one entry per horizon ({n})")
    coords = {
        "horizon": ("horizon", np.array(label, dtype=object), {"long_name": "horizon, top (youngest) first"}),
        "y": ("y", ya, {"units": "m", "standard_name": "projection_y_coordinate", "axis": "Y"}),
        "x": ("x", xa, {"units": "m", "standard_name": "projection_x_coordinate", "axis": "X"}),
        "source": ("horizon", np.array(src, dtype=object), {"long_name": "input of each horizon"}),
        "method": ("horizon", np.array(met, dtype=object), {"long_name": "how each horizon was made"}),
    }
    data = {
        "depth": (
            ("horizon", "y", "x"),
            H,
            {"units": "m", "positive": "down", "long_name": "depth of the horizon (NaN = undefined)"},
        )
    }
    if block is not None:
        b = np.asarray(block)
        if b.shape != (ya.size, xa.size):
            raise InputError(f"horizons: block must have shape ({ya.size}, {xa.size}), got {b.shape}")
        data["block"] = (("y", "x"), b.astype(np.int32), {"long_name": "fault block of each node"})
    ds_attrs: dict[str, Any] = {
        "Conventions": "CF-1.11",
        "title": "gridlib horizons",
        "gridlib_version": __version__,
        "ordering": ordering,
        "notes": json.dumps([*notes, *order_notes]),
    }
    for key, value in (attrs or {}).items():
        if isinstance(value, bool) or value is None:
            value = json.dumps(value)
        elif not isinstance(value, str | int | float | np.integer | np.floating):
            value = json.dumps(value)
        ds_attrs[str(key)] = value
    return xr.Dataset(data, coords=coords, attrs=ds_attrs)


def write_horizons(path: str | os.PathLike, ds: xr.Dataset) -> Path:
    """Write a horizons Dataset (:func:`horizon_dataset`) as netCDF-4, atomically (``horizons.nc``)."""
    if "depth" not in ds or ds["depth"].dims != ("horizon", "y", "x"):
        raise InputError(f"{path}: write_horizons needs a Dataset with depth (horizon, y, x)")
    encoding = {"depth": {"_FillValue": np.nan}}
    if "block" in ds:
        encoding["block"] = {"_FillValue": None}
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine="netcdf4", format="NETCDF4", encoding=encoding)
    return Path(path)


def read_horizons(path: str | os.PathLike) -> xr.Dataset:
    """Read a ``horizons.nc`` written by :func:`write_horizons` (checked: depth (horizon, y, x))."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    try:
        with xr.open_dataset(p, engine="netcdf4") as handle:
            ds = handle.load()
    except (OSError, ValueError) as exc:
        raise InputError(f"{p}: cannot read as netCDF ({exc})") from exc
    if "depth" not in ds or ds["depth"].dims != ("horizon", "y", "x"):
        raise InputError(f"{p}: not a horizons file (needs a variable depth over (horizon, y, x))")
    for key in ("x", "y", "horizon"):
        if key not in ds.coords:
            raise InputError(f"{p}: not a horizons file (coordinate '{key}' is missing)")
    return ds


def to_horizons(ds: xr.Dataset) -> list[Horizon]:
    """Each horizon of the Dataset as a :class:`~gridlib.cornerpoint.horizons.Horizon` (x, y axes,
    z[j, i]), top first: the input of :func:`~gridlib.cornerpoint.horizons.horizons_to_grdecl`."""
    x, y = ds["x"].values, ds["y"].values
    return [Horizon(x, y, ds["depth"].values[k]) for k in range(ds.sizes["horizon"])]


# --------------------------------------------------------------------------- from a specification

_SOURCES = ("points", "surface", "plane", "dome", "peaks")
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
      netCDF file (``variable``, ``horizon``), or a :class:`Surface`, resampled
      with ``method`` ``linear`` (default) or ``nearest``; ``elevation``. A
      gridded surface is taken as it is (``faults`` do not apply): a throw in it
      stays within one of its cells;
    * ``plane``, ``dome`` or ``peaks``: the keyword arguments of :func:`plane`,
      :func:`dome` or :func:`peaks`.

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
    xa, ya = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    for key, a in (("x", xa), ("y", ya)):
        if a.ndim != 1 or a.size < 1 or not np.isfinite(a).all() or (np.diff(a) <= 0).any():
            raise InputError(f"horizons: the lattice axis {key} must be finite, 1-D and strictly increasing")
    X, Y = np.meshgrid(xa, ya)
    base = Path(base_dir)
    loaded = [_load_one(k, spec, base) for k, spec in enumerate(specs)]
    faulted = faults is not None and len(faults) > 0
    extent = None
    if faulted:  # one area for every horizon, so that all see the same blocks
        point_sets = [item.data for item in loaded if item.kind == "points"]
        extent = _extent(X, Y, *(c for pts in point_sets for c in (pts[:, 0], pts[:, 1])))
    depths, notes = [], []
    for item in loaded:
        try:
            depths.append(_make_one(item, X, Y, xa, ya, faults, extent, notes))
        except TypeError as exc:  # bad keyword arguments of a formula
            raise InputError(f"{item.label}: {item.kind}: {exc}") from exc
    block = fault_blocks(faults, extent).classify(X, Y) if faulted else None
    methods = [
        str(item.spec.get("method", "linear")) if item.kind == "points"
        else f"resampled ({item.spec.get('method', 'linear')})" if item.kind == "surface"
        else item.kind
        for item in loaded
    ]  # fmt: skip
    return horizon_dataset(
        np.stack(depths),
        xa,
        ya,
        names=[item.name for item in loaded],
        ordering=ordering,
        block=block,
        sources=[item.source for item in loaded],
        methods=methods,
        notes=notes,
        attrs=attrs,
    )


class _Loaded(NamedTuple):
    name: str
    label: str  # for messages: horizons[k] ('name')
    kind: str  # one of _SOURCES
    data: Any  # the points (n, 3), the Surface, or the formula's parameters
    spec: Mapping[str, Any]
    source: str


def _load_one(k: int, spec: Any, base: Path) -> _Loaded:
    """One spec checked, its file (if any) read."""
    if not isinstance(spec, Mapping):
        raise InputError(f"horizons[{k}]: expected a mapping, got {type(spec).__name__}")
    name = spec.get("name")
    if not isinstance(name, str) or not name:
        raise InputError(f"horizons[{k}]: name: a non-empty string is required")
    label = f"horizons[{k}] ('{name}')"
    given = [s for s in _SOURCES if s in spec]
    if len(given) != 1:
        raise InputError(f"{label}: give exactly one of {', '.join(_SOURCES)} (got {given or 'none'})")
    kind = given[0]
    allowed = _POINT_KEYS if kind == "points" else _SURFACE_KEYS if kind == "surface" else {"name", kind}
    extra = set(spec) - allowed
    if extra:
        raise InputError(f"{label}: unknown keys {sorted(extra)} for {kind} (allowed: {sorted(allowed)})")
    src = spec[kind]
    if kind in ("plane", "dome", "peaks"):
        if not isinstance(src, Mapping):
            raise InputError(f"{label}: {kind}: expected a mapping of its parameters")
        return _Loaded(name, label, kind, src, spec, f"{kind} {json.dumps(dict(src), sort_keys=True)}")
    if kind == "points":
        if isinstance(src, str | os.PathLike):
            path = base / src
            pts = read_points(
                path,
                columns=spec.get("columns"),
                elevation=bool(spec.get("elevation", False)),
                null=spec.get("null"),
            )
            return _Loaded(name, label, kind, pts, spec, str(path))
        try:
            pts = np.asarray(src, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise InputError(f"{label}: points: not a file name or an (n, 3) array ({exc})") from exc
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise InputError(f"{label}: points: expected an (n, 3) array of x, y, z, got shape {pts.shape}")
        return _Loaded(name, label, kind, pts, spec, "points (array)")
    if isinstance(src, Surface):
        return _Loaded(name, label, kind, src, spec, src.source or f"surface '{src.name}'")
    path = base / src
    elevation = bool(spec.get("elevation", False))
    if path.suffix.lower() == ".nc":
        surf = read_surface_netcdf(
            path, variable=spec.get("variable"), horizon=spec.get("horizon"), elevation=elevation
        )
    else:
        from .io.irap import read_irap

        surf = read_irap(path, elevation=elevation)
    return _Loaded(name, label, kind, surf, spec, str(path))


def _make_one(item: _Loaded, X, Y, xa, ya, faults, extent, notes: list[str]) -> FloatArray:
    spec, kind, data, label = item.spec, item.kind, item.data, item.label
    if kind in ("plane", "dome", "peaks"):
        fn = {"plane": plane, "dome": dome, "peaks": peaks}[kind]
        return fn(X, Y, **data)
    if kind == "points":
        return interpolate_points(
            data,
            xa,
            ya,
            method=spec.get("method", "linear"),
            extrapolation=spec.get("extrapolation", "nan"),
            smoothing=spec.get("smoothing", 0.0),
            neighbors=spec.get("neighbors"),
            faults=faults,
            extent=extent,
            name=label,
            notes=notes,
        )
    method = _check_choice(spec.get("method", "linear"), ("linear", "nearest"), f"{label}: method")
    z = data.sample(X, Y, method=method)
    if np.isnan(z).all():
        raise InputError(
            f"{label}: {data.source or 'the surface'} is undefined (NaN) everywhere on the lattice"
        )
    return z
