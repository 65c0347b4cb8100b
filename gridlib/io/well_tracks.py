"""The wells as the maps and sections draw them: a name and polylines (x, y, z depth) in the
case's length unit, from any kind of well the case has."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .wells_file import WellRecord


@dataclass(frozen=True)
class WellTrack:
    """A well to draw: its ``name``, its ``paths`` ((n, 3) polylines x, y, z depth: the main
    path first, then its branches), and ``vertical``: a vertical well at a point (a map draws
    it as a symbol, a section as a vertical line over the grid's depth range); ``plan_only``:
    a path known in plan view only (a PEBI grid's refining well), which sections leave out."""

    name: str
    paths: tuple[np.ndarray, ...]
    vertical: bool = False
    plan_only: bool = False

    @property
    def head(self) -> np.ndarray:
        """(x, y) of the well's main path's first point."""
        return self.paths[0][0, :2]


def vertical_track(name: str, point: Sequence[float], depths: tuple[float, float]) -> WellTrack:
    """A vertical well at ``point`` (x, y) from the depth ``depths[0]`` to ``depths[1]``."""
    x, y = float(point[0]), float(point[1])
    return WellTrack(name, (np.array([[x, y, depths[0]], [x, y, depths[1]]]),), vertical=True)


def plan_track(name: str, xy: np.ndarray, depth: float) -> WellTrack:
    """A well given by its path in plan view (a PEBI grid's refining well), at ``depth``."""
    xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
    return WellTrack(name, (np.column_stack([xy, np.full(xy.shape[0], depth)]),), plan_only=True)


def record_tracks(records: Sequence[WellRecord]) -> tuple[WellTrack, ...]:
    """The deviated wells of ``wells.nc`` (:func:`gridlib.io.wells_file.read_wells`)."""
    return tuple(WellTrack(r.name, tuple(np.asarray(p.xyz) for p in r.paths)) for r in records)
