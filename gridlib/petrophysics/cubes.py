"""Property cubes: properties on a regular grid of cells, sampled at cell centroids or at
depositional coordinates (the files: :mod:`gridlib.io.cube_files`)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from ..arrays import point_array
from ..errors import InputError
from ..grid import FloatArray, IntArray
from .depositional import Depositional

__all__ = ["PropertyCube", "sample_cube"]


@dataclass(frozen=True, eq=False)
class PropertyCube:
    """Properties on a regular grid of cells: centres ``x`` (nx,), ``y`` (ny,), ``z`` (nz,)
    (m, increasing; z is depth) and ``values``: name -> (nz, ny, nx) array."""

    x: FloatArray
    y: FloatArray
    z: FloatArray
    values: Mapping[str, FloatArray] = field(default_factory=dict)
    source: str = ""

    def __post_init__(self) -> None:
        label = self.source or "property cube"
        axes = []
        for key in ("x", "y", "z"):
            a = np.array(getattr(self, key), dtype=np.float64)
            if a.ndim != 1 or a.size < 1 or not np.isfinite(a).all():
                raise InputError(f"{label}: coordinate {key} must be a finite 1-D axis")
            if a.size > 1:
                d = np.diff(a)
                inc = (a[-1] - a[0]) / (a.size - 1)
                if not (d > 0).all() or np.abs(d - inc).max() > 1e-6 * inc:
                    raise InputError(f"{label}: coordinate {key} must be increasing and regularly spaced")
            a.flags.writeable = False
            object.__setattr__(self, key, a)
            axes.append(a.size)
        shape = (axes[2], axes[1], axes[0])
        vals = {}
        for name, v in dict(self.values).items():
            arr = np.array(v, dtype=np.float64)
            if arr.shape != shape:
                raise InputError(f"{label}: '{name}' has shape {arr.shape}, expected (nz, ny, nx) = {shape}")
            arr.flags.writeable = False
            vals[str(name)] = arr
        if not vals:
            raise InputError(f"{label}: no property values")
        object.__setattr__(self, "values", vals)


def _spacing(a: FloatArray) -> float:
    return float((a[-1] - a[0]) / (a.size - 1)) if a.size > 1 else 1.0


def sample_cube(
    cube: PropertyCube,
    where: Depositional | ArrayLike,
    *,
    names: Sequence[str] | None = None,
    outside: str = "clip",
) -> dict[str, FloatArray]:
    """Values of the cube's cells at every position, by index (piecewise constant).

    ``where``: points (n, 3) (m, z depth; e.g. physical cell centroids): the
    cube cell containing each point; or :class:`Depositional` coordinates:
    (x_r, y_r) as points, and the layer's w normalised by the reference
    column's thickness onto the cube's depth range, k_cube = floor(w / W nz),
    so the cube's layers follow the grid's layers through every fault.
    ``outside``: ``"clip"`` (the nearest cell of the cube) or ``"nan"``.

    >>> cube = PropertyCube([5.0, 15.0], [5.0], [1.0, 3.0], {"poro": [[[0.1, 0.2]], [[0.3, 0.4]]]})
    >>> sample_cube(cube, [[4.0, 5.0, 2.5], [14.0, 5.0, 0.1]])["poro"].tolist()
    [0.3, 0.2]
    """
    if outside not in ("clip", "nan"):
        raise InputError(f"sample_cube: outside must be 'clip' or 'nan', got {outside!r}")
    chosen = list(cube.values) if names is None else list(names)
    missing = [n for n in chosen if n not in cube.values]
    if missing:
        raise InputError(
            f"sample_cube: no property {missing[0]!r} in the cube (has {', '.join(cube.values)})"
        )
    nz, ny, nx = len(cube.z), len(cube.y), len(cube.x)

    def index(coord: FloatArray, axis: FloatArray) -> tuple[IntArray, np.ndarray]:
        h = _spacing(axis)
        i = np.floor((coord - (axis[0] - h / 2)) / h)
        out = (i < 0) | (i > axis.size - 1)
        return np.clip(i, 0, axis.size - 1).astype(np.int64), out

    if isinstance(where, Depositional):
        xy = where.column_xy[where.column]
        i, out_i = index(xy[:, 0], cube.x)
        j, out_j = index(xy[:, 1], cube.y)
        frac = where.layer_w[where.layer] / where.w_edges[-1]
        k = np.minimum(np.floor(frac * nz).astype(np.int64), nz - 1)
        out = out_i | out_j
    else:
        pts = point_array(where, 3, "sample_cube: positions", min_points=0)
        i, out_i = index(pts[:, 0], cube.x)
        j, out_j = index(pts[:, 1], cube.y)
        k, out_k = index(pts[:, 2], cube.z)
        out = out_i | out_j | out_k
    flat = (k * ny + j) * nx + i
    result = {}
    for name in chosen:
        v = cube.values[name].ravel()[flat]
        if outside == "nan":
            v = np.where(out, np.nan, v)
        result[name] = v
    return result
