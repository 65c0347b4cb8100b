"""Vertical faults given by their trace in plan view: which cells move, and by how much.

Shared by both front ends of the pillar engine, so that one :class:`FaultTrace`
means the same on a corner-point deck (``horizons_to_grdecl``) and on an
extruded areal grid (``gridlib.pillars.extrude``):

* every cell (a column of the areal grid) is classified by its *centre*: the
  nearest point of the trace to the centre decides which side of the trace it
  lies on (at an interior vertex of the polyline, the side away from the turn);
  cells on the hanging-wall side are displaced;
* the corner of a displaced cell on pillar p moves down by ``throw(s_p)``,
  ``s_p`` being the normalised arc length of the pillar's nearest point on the
  trace, so two displaced cells sharing a pillar move it alike;
* an end point that is a *tip* (strictly inside the grid) ends the fault: cells
  whose centre's nearest trace point is the tip move by ``throw(s_p) -
  throw(tip)``; an end point that is not a tip is extended as a ray.

Units are metres; z is depth, positive downwards (a positive throw moves the
hanging wall down).
"""

from __future__ import annotations

import numbers
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..grid import FloatArray, IntArray
from .fault_surface import FaultSurface


@dataclass(frozen=True, eq=False)
class FaultTrace:
    """A fault given by its trace in plan view: vertical, unless it has a ``surface``.

    ``points``: the polyline, (n >= 2, 2) x, y in metres. ``throw`` (m): the
    vertical displacement of the hanging wall, positive downwards (deeper); a
    number, or a function of the normalised arc length ``s`` in [0, 1] along the
    polyline (0 at its first point) returning an array like ``s``, e.g.
    ``lambda s: 10 * (1 - s)`` for a fault dying out at its last point
    (values below 1e-12 times the largest are taken as 0, so round-off such as
    ``sin(pi)`` still gives an exact tip).
    ``side``: which side of the polyline, walked from its first point to its
    last, is the hanging wall, ``"left"`` or ``"right"`` as seen on a map with
    x to the right and y up. ``name``: the fault's name (default ``F1``, ``F2``,
    ... by position).
    ``surface``: None for a vertical fault (all of the above); for an inclined one its
    :class:`~gridlib.pillars.fault_surface.FaultSurface`, ``points`` being then the fault's
    trace on the top horizon, ``side`` its hanging wall and ``throw`` still the *vertical*
    displacement (the slip along the dip is ``throw / sin(dip)``, the heave ``throw / tan(dip)``).

    A trace should extend beyond the grid where the fault crosses it: an end
    point strictly inside the grid is a fault tip (see
    :func:`~gridlib.cornerpoint.between_horizons.horizons_to_grdecl` and
    :func:`~gridlib.pillars.extrude.extrude`), an end point on or outside
    it is not.

    >>> FaultTrace([(0.0, 0.0), (0.0, 100.0)], throw=5.0, name="F1").points.shape
    (2, 2)
    """

    points: NDArray[np.float64]
    throw: float | Callable[[NDArray[np.float64]], ArrayLike]
    name: str | None = None
    side: str = "right"
    surface: FaultSurface | None = None

    def __post_init__(self) -> None:
        label = "fault trace" if self.name is None else f"fault trace '{self.name}'"
        if self.name is not None and (not isinstance(self.name, str) or not self.name.strip()):
            raise InputError(f"{label}: name must be a non-empty string, got {self.name!r}")
        try:
            pts = np.array(self.points, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise InputError(f"{label}: points must be an (n, 2) array of x, y ({exc})") from exc
        if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2:
            raise InputError(f"{label}: points must be an (n >= 2, 2) array of x, y, got shape {pts.shape}")
        if not np.isfinite(pts).all():
            raise InputError(f"{label}: points must be finite")
        seg = np.hypot(*np.diff(pts, axis=0).T)
        if np.any(seg == 0):
            raise InputError(
                f"{label}: points {int(np.flatnonzero(seg == 0)[0])} and "
                f"{int(np.flatnonzero(seg == 0)[0]) + 1} coincide (zero-length segment)"
            )
        pts.flags.writeable = False
        object.__setattr__(self, "points", pts)
        if not callable(self.throw):
            if isinstance(self.throw, bool) or not isinstance(self.throw, numbers.Real):
                raise InputError(
                    f"{label}: throw must be a number (m) or a function of s in [0, 1], got {self.throw!r}"
                )
            if not np.isfinite(float(self.throw)):
                raise InputError(f"{label}: throw must be finite, got {self.throw!r}")
            object.__setattr__(self, "throw", float(self.throw))
        if self.side not in ("left", "right"):
            raise InputError(f"{label}: side must be 'left' or 'right', got {self.side!r}")
        if self.surface is not None and not isinstance(self.surface, FaultSurface):
            raise InputError(f"{label}: surface must be a FaultSurface or None, got {self.surface!r:.60}")


def nearest_on_trace(p: np.ndarray, verts: np.ndarray, open_start: bool, open_end: bool):
    """Nearest point of the polyline to every point ``p`` (m, 2): segment, parameter t on it
    (outside [0, 1] only on the rays that extend open ends) and the side value (> 0 = left)."""
    a, d = verts[:-1], np.diff(verts, axis=0)
    n_seg = d.shape[0]
    best = np.full(p.shape[0], np.inf)
    seg = np.zeros(p.shape[0], dtype=np.int64)
    tt = np.zeros(p.shape[0])
    px, py = np.ascontiguousarray(p[:, 0]), np.ascontiguousarray(p[:, 1])
    for k in range(n_seg):  # one pass per polyline segment, vectorised over the points
        t = ((px - a[k, 0]) * d[k, 0] + (py - a[k, 1]) * d[k, 1]) / (d[k, 0] * d[k, 0] + d[k, 1] * d[k, 1])
        lo = -np.inf if (k == 0 and open_start) else 0.0
        hi = np.inf if (k == n_seg - 1 and open_end) else 1.0
        t = np.clip(t, lo, hi)
        dist2 = _squared_offset(px, a[k, 0], t, d[k, 0])  # on x and y apart: contiguous and fast
        dist2 += _squared_offset(py, a[k, 1], t, d[k, 1])
        better = dist2 < best
        np.copyto(best, dist2, where=better)
        np.copyto(seg, k, where=better)
        np.copyto(tt, t, where=better)
    rel_x, rel_y = px - a[seg, 0], py - a[seg, 1]
    side = d[seg, 0] * rel_y - d[seg, 1] * rel_x
    # Nearest point at an interior vertex: the point lies on the outer side of the turn there.
    at_vertex = np.where((tt == 0) & (seg > 0), seg, np.where((tt == 1) & (seg < n_seg - 1), seg + 1, -1))
    v = at_vertex[at_vertex > 0]
    if v.size:
        turn = d[v - 1, 0] * d[v, 1] - d[v - 1, 1] * d[v, 0]
        side[at_vertex > 0] = np.where(turn != 0, -turn, side[at_vertex > 0])
    return seg, tt, side


def _squared_offset(x: np.ndarray, origin: float, t: np.ndarray, step: float) -> np.ndarray:
    """``(x - origin - t * step) ** 2`` elementwise, in place of one temporary."""
    out = x - origin
    out -= t * step
    out *= out
    return out


def fault_displacement(
    trace: FaultTrace,
    index: int,
    name: str,
    pillar_xy: FloatArray,
    centre_xy: FloatArray,
    corner_pillar: IntArray,
    corner_cell: IntArray,
    open_start: bool,
    open_end: bool,
) -> FloatArray:
    """Downward displacement (m) of every cell corner by one fault (see the module docstring).

    ``pillar_xy`` (n_pillars, 2) and ``centre_xy`` (n_cells, 2) are the plan-view
    positions of the pillars and of the cells' centres; ``corner_pillar`` and
    ``corner_cell`` (any shape, the same) give the pillar and the cell of every
    corner, and the result has their shape. ``open_start`` / ``open_end``: the
    first / last point of the trace is no tip (it lies on or outside the grid),
    so the end segment is extended as a ray. ``index`` and ``name`` only label
    errors (``fault 'name' (faults[index])``).

    >>> trace = FaultTrace([(1.0, -1.0), (1.0, 3.0)], throw=2.0)  # walking north: east is right
    >>> pillars = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    >>> centres = np.array([[0.5, 0.5], [1.5, 0.5]])
    >>> corner_pillar, corner_cell = np.array([[0, 1], [1, 2]]), np.array([[0, 0], [1, 1]])
    >>> fault_displacement(trace, 0, "F1", pillars, centres, corner_pillar, corner_cell, True, True).tolist()
    [[0.0, 0.0], [2.0, 2.0]]
    """
    t_pillar, t_start, t_end = pillar_throws(trace, index, name, pillar_xy, open_start, open_end)
    hanging, correction = _hanging(trace, trace.points, centre_xy, open_start, open_end, t_start, t_end)
    return np.where(hanging[corner_cell], t_pillar[corner_pillar] - correction[corner_cell], 0.0)


def pillar_throws(
    trace: FaultTrace, index: int, name: str, pillar_xy: FloatArray, open_start: bool, open_end: bool
) -> tuple[FloatArray, float, float]:
    """The throw (m) at every pillar (n_pillars,), ``throw(s_p)`` with ``s_p`` the normalised arc
    length of the pillar's nearest point on the trace, and the throws at the trace's first and last
    points; round-off zeros made exact (see :func:`fault_displacement` for the arguments)."""
    verts = trace.points
    seg_len = np.hypot(*np.diff(verts, axis=0).T)
    cum = np.concatenate([[0.0], np.cumsum(seg_len)])

    p_seg, p_t, _ = nearest_on_trace(pillar_xy, verts, open_start, open_end)
    s_pillar = np.clip((cum[p_seg] + p_t * seg_len[p_seg]) / cum[-1], 0.0, 1.0)

    s_all = np.concatenate([s_pillar, [0.0, 1.0]])
    label = f"fault '{name}' (faults[{index}])"
    if callable(trace.throw):
        try:
            values = np.asarray(trace.throw(s_all.copy()), dtype=np.float64)
            values = np.broadcast_to(values, s_all.shape).astype(np.float64)
        except Exception as exc:
            raise InputError(f"{label}: throw(s) failed for an array s in [0, 1]: {exc}") from exc
    else:
        values = np.full(s_all.shape, trace.throw)
    if not np.isfinite(values).all():
        raise InputError(f"{label}: throw(s) must be finite for s in [0, 1]")
    # Round-off zeros (3 * sin(pi) = 3.7e-16) are zeros: a tapered tip must match exactly.
    values = np.where(np.abs(values) <= 1e-12 * np.abs(values).max(), 0.0, values)
    return values[:-2], values[-2], values[-1]


def cell_displacement(
    trace: FaultTrace, centre_xy: FloatArray, open_start: bool, open_end: bool
) -> FloatArray | None:
    """The displacement (m) of every cell's corners by a fault of constant throw, one value per
    cell (n_cells,): what :func:`fault_displacement` gives every corner of the cell, without
    locating the pillars on the trace (the throw is the same at all of them). None when the
    throw is a function of the arc length (use :func:`fault_displacement`).

    >>> trace = FaultTrace([(1.0, -1.0), (1.0, 3.0)], throw=2.0)
    >>> cell_displacement(trace, np.array([[0.5, 0.5], [1.5, 0.5]]), True, True).tolist()
    [0.0, 2.0]
    """
    if callable(trace.throw):
        return None
    # fault_displacement's values at every pillar and at both ends, round-off zeros made exact.
    throw = 0.0 if trace.throw == 0.0 else float(trace.throw)
    hanging, correction = _hanging(trace, trace.points, centre_xy, open_start, open_end, throw, throw)
    return np.where(hanging, throw - correction, 0.0)


def _hanging(trace: FaultTrace, verts, centre_xy, open_start: bool, open_end: bool, t_start, t_end):
    """Which cells are on the hanging wall, and the throw their corners lose (that of the tip
    their centre is beyond, else 0)."""
    n_seg = verts.shape[0] - 1
    c_seg, c_t, c_side = nearest_on_trace(centre_xy, verts, open_start, open_end)
    beyond_start = (c_seg == 0) & (c_t <= 0) & (not open_start)
    beyond_end = (c_seg == n_seg - 1) & (c_t >= 1) & (not open_end)
    hanging = (c_side > 0) if trace.side == "left" else (c_side < 0)
    return hanging, np.where(beyond_start, t_start, np.where(beyond_end, t_end, 0.0))
