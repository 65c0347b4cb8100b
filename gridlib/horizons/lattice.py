"""Gridded surfaces: a regular (optionally rotated) lattice of depths, read from netCDF."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..grid import FloatArray
from ..io._dataset import load_dataset
from ..stratigraphic.horizon_maps import Horizon


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
    xinc = _regular_increment(x, f"{p}: coordinate '{xdim}'")
    yinc = _regular_increment(y, f"{p}: coordinate '{ydim}'")
    return Surface(z, float(x[0]), float(y[0]), xinc, yinc, name=label, source=str(p))
