"""Gridded horizons: depth maps on rectilinear meshes, checked and interpolated bilinearly.

A :class:`Horizon` is the input both pillar front ends accept for a surface
(``horizons_to_grdecl`` and ``extrude``); :func:`check_horizon` brings it to
increasing 1-D axes and ``z[j, i]``, :func:`interpolate_horizon` evaluates
it anywhere, NaN where it is undefined, and :func:`depth_function` makes it the
function ``f(x, y)`` that places pillars and fault surfaces. Units are metres; z is
depth, positive downwards.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError

__all__ = ["DepthFunction", "Horizon", "check_horizon", "depth_function", "interpolate_horizon"]

# A surface z = f(x, y): depth (m) at arrays of plan points, NaN where it is undefined.
DepthFunction = Callable[[np.ndarray, np.ndarray], ArrayLike]


@dataclass(frozen=True, eq=False)
class Horizon:
    """A depth map on a rectilinear mesh (m; z is depth, positive down, NaN = undefined).

    ``x`` and ``y`` are either the 1-D axes (then ``z[j, i]`` is the depth at
    ``(x[i], y[j])``) or 2-D meshgrid arrays of ``z``'s shape, with x varying
    along one axis and y along the other (MATLAB's ``meshgrid``/``peaks`` or
    ``ndgrid`` layout). The arrays are copied; they are checked by
    :func:`~gridlib.cornerpoint.between_horizons.horizons_to_grdecl`, which can name the horizon at fault.
    """

    x: NDArray[np.float64]
    y: NDArray[np.float64]
    z: NDArray[np.float64]

    def __post_init__(self) -> None:
        for name in ("x", "y", "z"):
            try:
                arr = np.array(getattr(self, name), dtype=np.float64)
            except (TypeError, ValueError) as exc:
                raise InputError(f"Horizon: {name} is not an array of numbers ({exc})") from exc
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)


def check_horizon(hz: Any, h: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One gridded horizon (a :class:`Horizon`, a mapping or an object with ``x``, ``y``, ``z``)
    as an increasing x axis (nx,), an increasing y axis (ny,) and depths z[j, i] (ny, nx);
    errors name it ``horizon {h}``."""
    arrays = {}
    for key in ("x", "y", "z"):
        try:
            arrays[key] = np.asarray(_field(hz, key, h), dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise InputError(f"horizon {h}: {key} is not an array of numbers ({exc})") from exc
    x, y, z = arrays["x"], arrays["y"], arrays["z"]
    if z.ndim != 2 or min(z.shape) < 2:
        raise InputError(f"horizon {h}: z must be a 2-D array of at least 2 x 2 nodes, got shape {z.shape}")
    if x.ndim != y.ndim or x.ndim not in (1, 2):
        raise InputError(
            f"horizon {h}: x and y must both be 1-D axes or both 2-D mesh arrays, "
            f"got shapes {x.shape} and {y.shape}"
        )
    if not (np.isfinite(x).all() and np.isfinite(y).all()):
        raise InputError(f"horizon {h}: x and y must be finite")
    if x.ndim == 1:
        if z.shape != (y.size, x.size):
            raise InputError(
                f"horizon {h}: z has shape {z.shape}, expected (len(y), len(x)) = ({y.size}, {x.size})"
            )
        xa, ya = x, y
    else:
        if x.shape != z.shape or y.shape != z.shape:
            raise InputError(
                f"horizon {h}: x, y and z must have the same shape, got {x.shape}, {y.shape} and {z.shape}"
            )
        tol = 1e-10 * max(1.0, float(np.abs(x).max()), float(np.abs(y).max()))

        def const(a: np.ndarray, axis: int, tol: float = tol) -> bool:
            ref = a[:1, :] if axis == 0 else a[:, :1]
            return bool(np.all(np.abs(a - ref) <= tol))

        if const(x, 0) and const(y, 1) and not const(x, 1):  # meshgrid layout: x along columns
            xa, ya = x[0], y[:, 0]
        elif const(x, 1) and const(y, 0) and not const(x, 0):  # ndgrid layout: x along rows
            xa, ya, z = x[:, 0], y[0], z.T
        else:
            raise InputError(
                f"horizon {h}: x and y are not a rectilinear mesh (x must be constant along one "
                "axis and y along the other, as meshgrid gives)"
            )
    xa, flip_x = _axis(xa, "x", h)
    ya, flip_y = _axis(ya, "y", h)
    if flip_x:
        z = z[:, ::-1]
    if flip_y:
        z = z[::-1, :]
    if np.isinf(z).any():
        raise InputError(f"horizon {h}: z has infinite values (use NaN for undefined depths)")
    if np.isnan(z).all():
        raise InputError(f"horizon {h}: z is undefined (NaN) everywhere")
    return np.ascontiguousarray(xa), np.ascontiguousarray(ya), np.ascontiguousarray(z)


def depth_function(horizon: Any, index: int = 0, *, clamped: bool = False) -> DepthFunction:
    """A gridded horizon (as :func:`check_horizon` takes it; errors name it ``horizon {index}``)
    as the depth function ``f(x, y)`` (m, arrays of any shape): bilinear, NaN outside its box and
    where it is undefined. ``clamped``: every point is first clamped into the box, so the
    horizon's edge values carry on beyond it (where fault sticks outside the grid meet it).

    >>> f = depth_function(Horizon([0.0, 10.0], [0.0, 10.0], [[100.0, 110.0], [100.0, 110.0]]))
    >>> f(np.array([5.0, 20.0]), np.array([5.0, 5.0])).tolist()
    [105.0, nan]
    """
    xa, ya, z = check_horizon(horizon, index)

    def f(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
        if clamped:
            x, y = np.clip(x, xa[0], xa[-1]), np.clip(y, ya[0], ya[-1])
        return interpolate_horizon(xa, ya, z, x, y)

    return f


def _field(h: Any, key: str, index: int) -> Any:
    if isinstance(h, Mapping):
        if key not in h:
            raise InputError(f"horizon {index}: missing '{key}' (a horizon needs x, y and z)")
        return h[key]
    if not hasattr(h, key):
        raise InputError(
            f"horizon {index}: {type(h).__name__} has no '{key}' (a horizon needs x, y and z: "
            "a Horizon or a mapping)"
        )
    return getattr(h, key)


def _axis(a: np.ndarray, name: str, index: int) -> tuple[np.ndarray, bool]:
    """A strictly monotone axis as increasing, and whether it was reversed."""
    d = np.diff(a)
    if np.all(d > 0):
        return a, False
    if np.all(d < 0):
        return a[::-1], True
    raise InputError(f"horizon {index}: {name} is not strictly monotone (values must increase or decrease)")


def interpolate_horizon(xa: np.ndarray, ya: np.ndarray, z: np.ndarray, qx: np.ndarray, qy: np.ndarray):
    """Bilinear depths of the horizon (``check_horizon``'s axes and z) at the points (qx, qy), any
    shape; NaN outside its box (round-off at the box edges counts as inside) and wherever one of
    its NaN nodes has a non-zero weight."""
    from scipy.interpolate import RegularGridInterpolator  # slow to import (0.5 s): only when used

    undefined = np.isnan(z)
    values = np.stack([np.where(undefined, 0.0, z), undefined.astype(np.float64)], axis=-1)
    interp = RegularGridInterpolator((ya, xa), values, method="linear", bounds_error=False, fill_value=np.nan)

    def snap(p: np.ndarray, a: np.ndarray) -> np.ndarray:  # round-off at the box edges counts as inside
        tol = 1e-10 * (a[-1] - a[0])
        p = np.where((p < a[0]) & (p >= a[0] - tol), a[0], p)
        return np.where((p > a[-1]) & (p <= a[-1] + tol), a[-1], p)

    out = interp(np.stack([snap(qy, ya), snap(qx, xa)], axis=-1))
    return np.where(out[..., 1] > 0, np.nan, out[..., 0])
