"""Gridded surfaces: a regular (optionally rotated) lattice of depths (read by :mod:`gridlib.io.irap`
and :func:`gridlib.io.horizon_files.read_surface_netcdf`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..grid import FloatArray
from ..pillars.horizon_maps import Horizon


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
            incs.append(regular_increment(a, f"{label}: {key}"))
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
        """The :class:`~gridlib.cornerpoint.between_horizons.Horizon` (axes and depths) of an
        unrotated surface."""
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


def regular_increment(a: FloatArray, label: str) -> float:
    """The spacing of a regular increasing axis (1.0 for a single node); errors name ``label``."""
    if a.size == 1:
        return 1.0
    d = np.diff(a)
    inc = (a[-1] - a[0]) / (a.size - 1)
    if not (d > 0).all():
        raise InputError(f"{label}: must be strictly increasing")
    if np.abs(d - inc).max() > 1e-6 * inc:
        raise InputError(f"{label}: is not regularly spaced (spacings {d.min():g} to {d.max():g})")
    return float(inc)
