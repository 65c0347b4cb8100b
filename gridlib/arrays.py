"""Array arguments made safe to keep: converted, shape-checked and read-only, or one clear
error that names the argument.

Every frozen dataclass of gridlib adopts the arrays it is given through :func:`frozen_array`,
and every function that takes coordinates (a polygon's vertices, a fault trace, scattered
horizon picks, sample positions) checks them with :func:`point_array`, so that a wrong shape,
a string or a NaN fails at the argument's name, not deep inside numpy.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, DTypeLike, NDArray

from .errors import GridError, InputError

AXES = {1: "x", 2: "x, y", 3: "x, y, z"}  # the coordinate names of a point's columns


def frozen_array(
    value: ArrayLike,
    dtype: DTypeLike,
    name: str,
    ndim: int,
    *,
    copy: bool = False,
    error: type[ValueError] = GridError,
) -> NDArray:
    """``value`` as a read-only C-contiguous ``ndim``-D array of ``dtype``.

    The array is adopted without a copy when its dtype and layout already fit (so the caller's
    own array becomes read-only: the object that keeps it owns it from then on); ``copy=True``
    copies always. ``error`` (a :class:`~gridlib.errors.GridError` unless given) names ``name``.

    >>> a = frozen_array([1, 2, 3], np.int64, "cells.faces", 1)
    >>> a.tolist(), a.flags.writeable
    ([1, 2, 3], False)
    >>> frozen_array([[1, 2]], np.int64, "cells.faces", 1)
    Traceback (most recent call last):
    gridlib.errors.GridError: cells.faces: expected a 1-D array, got shape (1, 2)
    """
    try:
        arr = np.array(value, dtype=dtype, order="C") if copy else np.asarray(value, dtype, order="C")
    except (TypeError, ValueError) as exc:
        raise error(f"{name}: expected a {ndim}-D array of {np.dtype(dtype).name} ({exc})") from exc
    if arr.ndim != ndim:
        raise error(f"{name}: expected a {ndim}-D array, got shape {arr.shape}")
    arr.flags.writeable = False
    return arr


def point_array(
    value: ArrayLike,
    width: int,
    name: str,
    *,
    min_points: int = 1,
    point: str = "point",
    error: type[ValueError] = InputError,
) -> NDArray[np.float64]:
    """``value`` as an (n, ``width``) float64 array of finite coordinates, one point a row
    (x, y or x, y, z in metres, z depth), n >= ``min_points``.

    The error (an :class:`~gridlib.errors.InputError` unless given) starts with ``name`` and,
    for a NaN or infinite coordinate, names the first such row as ``point`` ("vertex", ...).

    >>> point_array([(0, 0), (1, 0)], 2, "domain").tolist()
    [[0.0, 0.0], [1.0, 0.0]]
    >>> point_array([(0, 0), (1, float("nan"))], 2, "domain", point="vertex")
    Traceback (most recent call last):
    gridlib.errors.InputError: domain: vertex 1 is not finite
    >>> point_array([0.0, 1.0, 2.0], 3, "top: points")
    Traceback (most recent call last):
    gridlib.errors.InputError: top: points: expected an (n >= 1, 3) array of x, y, z, got shape (3,)
    """
    rows = "n" if min_points == 0 else f"n >= {min_points}"
    expected = f"{name}: expected an ({rows}, {width}) array of {AXES.get(width, 'coordinates')}"
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise error(f"{expected}, got {value!r:.60} ({exc})") from exc
    if arr.ndim != 2 or arr.shape[1] != width or arr.shape[0] < min_points:
        raise error(f"{expected}, got shape {arr.shape}")
    finite = np.isfinite(arr).all(axis=1)
    if not finite.all():
        raise error(f"{name}: {point} {int(np.flatnonzero(~finite)[0])} is not finite")
    return arr
