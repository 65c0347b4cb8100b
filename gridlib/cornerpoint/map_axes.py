"""A deck's MAPAXES: where the grid's own x, y (the frame its COORD is given in) lie on the map.

MAPAXES gives three map points, in ECLIPSE's order: a point on the grid's y axis, the grid's
origin, a point on its x axis. A grid point (x, y) lies on the map at ``origin + x ex + y ey``,
``ex`` and ``ey`` the unit vectors from the origin towards the axis points. That is the
convention of ECLIPSE, OPM Flow (which moves a well trajectory given on the map into the grid's
frame), xtgeo and ResInsight; RMS writes a GRDECL export in the grid's frame with MAPAXES and
its wells, surfaces and ROFF exports on the map. Depths are the same in both frames.

Axes along east and north, as RMS writes them, make both directions a translation: one
rounding per value, and a value moved to the map and back is the same float where the
translation is exact (whole numbers, or values with few decimals).

>>> axes = MapAxes.of([0.0, 101.0, 0.0, 100.0, 1.0, 100.0])  # origin (0, 100), axes east and north
>>> axes.to_map(np.array([[2.0, 3.0]]))
array([[  2., 103.]])
>>> axes.to_grid(np.array([[2.0, 103.0]]))
array([[2., 3.]])
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True, eq=False)
class MapAxes:
    """The grid's origin on the map and its x and y axes' unit vectors there, each (2,)."""

    origin: NDArray[np.float64]
    ex: NDArray[np.float64]
    ey: NDArray[np.float64]

    @classmethod
    def of(cls, mapaxes: Sequence[float] | NDArray[np.float64]) -> MapAxes:
        """From MAPAXES's six numbers (y-axis point, origin, x-axis point); ValueError where an
        axis point is the origin or the two axes are parallel (no frame)."""
        values = np.asarray(mapaxes, dtype=np.float64).ravel()
        if values.size != 6 or not np.isfinite(values).all():
            raise ValueError(f"MAPAXES needs six finite numbers, got {values.tolist()}")
        y_point, origin, x_point = values.reshape(3, 2)
        ex, ey = x_point - origin, y_point - origin
        lx, ly = float(np.hypot(*ex)), float(np.hypot(*ey))
        if lx == 0.0 or ly == 0.0:
            raise ValueError("MAPAXES: an axis point is the origin (no axis)")
        ex, ey = ex / lx, ey / ly
        if abs(float(ex[0] * ey[1] - ex[1] * ey[0])) < 1e-9:
            raise ValueError("MAPAXES: the x and y axes are parallel")
        return cls(origin, ex, ey)

    def to_map(self, xy: NDArray[np.float64]) -> NDArray[np.float64]:
        """Points (..., 2) of the grid's frame on the map."""
        xy = np.asarray(xy, dtype=np.float64)
        return self.origin + (xy[..., :1] * self.ex + xy[..., 1:2] * self.ey)

    def to_grid(self, xy: NDArray[np.float64]) -> NDArray[np.float64]:
        """Map points (..., 2) in the grid's frame (the inverse of :meth:`to_map`)."""
        d = np.asarray(xy, dtype=np.float64) - self.origin
        (a, c), (b, e) = self.ex, self.ey  # the columns of [ex ey]
        det = a * e - b * c
        x = (d[..., 0] * e - d[..., 1] * b) / det
        y = (d[..., 1] * a - d[..., 0] * c) / det
        return np.stack([x, y], axis=-1)

    def xyz_to_grid(self, xyz: NDArray[np.float64]) -> NDArray[np.float64]:
        """Points (n, 3) with x, y on the map (z depth) in the grid's frame."""
        out = np.array(xyz, dtype=np.float64)
        out[:, :2] = self.to_grid(out[:, :2])
        return out

    @property
    def is_identity(self) -> bool:
        """The grid's frame is the map's (origin 0, axes east and north)."""
        return bool(
            (self.origin == 0.0).all() and (self.ex == (1.0, 0.0)).all() and (self.ey == (0.0, 1.0)).all()
        )
