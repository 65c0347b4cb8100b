"""Fault blocks: the areas fault traces cut a region into, for per-block interpolation.

A point in plan view belongs to the block its position lies in. A point with a depth (a pick
of a horizon) is placed by the fault *surface* at its own depth where the fault is inclined
(a :class:`~gridlib.pillars.fault_traces.FaultTrace` with a ``surface``): a pick between the
trace (where the fault cuts the top horizon) and the surface's section at the pick's depth
lies on the other side of that fault than its plan position says, and goes to the block just
across the trace, so that a stair-stepped grid (cells placed by the surface at their depth)
and its picks agree.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..grid import FloatArray
from ..pillars.fault_traces import FaultTrace, nearest_on_trace
from ..pillars.horizon_maps import DepthFunction, interpolate_horizon


@dataclass(frozen=True, eq=False)
class FaultBlocks:
    """The blocks into which fault traces cut a rectangle (see the module docstring).

    ``polygons``: the blocks (shapely polygons), block id = position;
    ``traces``: the traces as used (clipped shapely lines); ``tolerance``: the
    distance (m) within which a point lies on a trace; ``notes``: traces that
    separate nothing along part of their length; ``lines`` and ``surfaces``: per
    trace its polyline (n, 2) and its inclined
    :class:`~gridlib.pillars.fault_surface.FaultSurface`, or None (vertical).
    """

    polygons: tuple[Any, ...]
    traces: Any
    tolerance: float
    notes: tuple[str, ...]
    lines: tuple[FloatArray, ...] = ()
    surfaces: tuple[Any, ...] = ()

    @property
    def num(self) -> int:
        return len(self.polygons)

    def classify(
        self, px: ArrayLike, py: ArrayLike, pz: ArrayLike | None = None, *, on_trace: str = "lowest"
    ) -> NDArray[np.int64]:
        """Block id of every point ``(px, py)`` (matching shapes). A point on a trace (touching
        several blocks) gets the lowest of their ids (``on_trace="lowest"``) or -1 (``"none"``);
        a point outside the rectangle gets the nearest block. ``pz``: the points' depths (m,
        positive down): a point on the other side of an inclined fault's surface at its depth
        than of its trace goes to the block just across the trace (see the module docstring)."""
        if on_trace not in ("lowest", "none"):
            raise InputError(f"FaultBlocks.classify: on_trace must be 'lowest' or 'none', got {on_trace!r}")
        if pz is None:
            px, py = np.broadcast_arrays(np.asarray(px, dtype=np.float64), np.asarray(py, dtype=np.float64))
            return self._in_plan(px.ravel(), py.ravel(), on_trace).reshape(px.shape)
        px, py, pz = np.broadcast_arrays(*(np.asarray(v, dtype=np.float64) for v in (px, py, pz)))
        fx, fy = self._across_surfaces(px.ravel(), py.ravel(), pz.ravel())
        return self._in_plan(fx, fy, on_trace).reshape(px.shape)

    def _across_surfaces(self, x: FloatArray, y: FloatArray, z: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The points, those on the other side of an inclined fault at their depth than in plan
        moved just across its trace (1000 tolerances beyond its nearest point), fault by fault."""
        x, y = x.copy(), y.copy()
        for line, surface in zip(self.lines, self.surfaces, strict=True):
            if surface is None or surface.is_vertical:
                continue
            seg, t, plan = nearest_on_trace(np.column_stack([x, y]), line, True, True)
            at_depth = surface.side_value(x, y, z)
            flip = np.flatnonzero((np.sign(at_depth) != np.sign(plan)) & (at_depth != 0))
            if flip.size == 0:
                continue
            d = np.diff(line, axis=0)[seg[flip]]
            left = np.column_stack([-d[:, 1], d[:, 0]]) / np.hypot(d[:, 0], d[:, 1])[:, None]
            foot = line[seg[flip]] + t[flip, None] * d
            across = foot + (np.sign(at_depth[flip]) * 1000.0 * self.tolerance)[:, None] * left
            x[flip], y[flip] = across[:, 0], across[:, 1]
        return x, y

    def _in_plan(self, fx: FloatArray, fy: FloatArray, on_trace: str) -> NDArray[np.int64]:
        import shapely

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
        return ids


def bounding_box(*coords: ArrayLike) -> tuple[float, float, float, float]:
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
    :class:`~gridlib.cornerpoint.between_horizons.FaultTrace` (those with an inclined
    ``surface`` classify points with a depth by it). See the module docstring for the rules.

    >>> b = fault_blocks([[(500.0, -1.0), (500.0, 101.0)]], (0.0, 1000.0, 0.0, 100.0))
    >>> b.num, b.classify([100.0, 900.0, 500.0], [50.0, 50.0, 50.0]).tolist()
    (2, [0, 1, 0])
    """
    import shapely
    from shapely.ops import polygonize_full

    xmin, xmax, ymin, ymax = (float(v) for v in extent)
    if not (xmax > xmin and ymax > ymin):
        raise InputError(f"fault_blocks: the extent x {xmin:g} to {xmax:g}, y {ymin:g} to {ymax:g} is empty")
    box = shapely.box(xmin, ymin, xmax, ymax)
    diag = math.hypot(xmax - xmin, ymax - ymin)
    if isinstance(faults, FaultTrace) or (isinstance(faults, np.ndarray) and faults.ndim == 2):
        raise InputError("faults: expected a sequence of traces, got a single trace (wrap it in a list)")
    lines, clipped, polylines = [], [], []
    for k, f in enumerate(faults):
        pts = _trace_points(f, k)
        polylines.append(pts)
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
    surfaces = tuple(getattr(f, "surface", None) for f in faults)
    return FaultBlocks(
        tuple(polygons), shapely.union_all(clipped), 1e-9 * diag, tuple(notes), tuple(polylines), surfaces
    )


def with_surfaces(blocks: FaultBlocks, faults: Sequence[Any]) -> FaultBlocks:
    """The same blocks (cut by the same traces), classifying points with a depth by the
    ``surface`` of the faults (FaultTraces, in the order the blocks were cut by)."""
    if len(faults) != len(blocks.lines):
        raise InputError(f"fault blocks: {len(faults)} faults for {len(blocks.lines)} traces")
    for k, (f, line) in enumerate(zip(faults, blocks.lines, strict=True)):
        if not np.array_equal(_trace_points(f, k), line):
            raise InputError(f"fault blocks: fault {k} does not follow the trace the blocks were cut by")
    return replace(blocks, surfaces=tuple(getattr(f, "surface", None) for f in faults))


def footwall_top(
    blocks: FaultBlocks, tops: FloatArray, xa: FloatArray, ya: FloatArray, faults: Sequence[FaultTrace]
) -> DepthFunction:
    """The depth function of every fault's footwall top horizon along its trace.

    ``tops``: (block, y, x) the top horizon of every block of ``blocks`` on the lattice of axes
    ``xa``, ``ya``; ``faults``: the traces the blocks were cut by, with their ``side`` (the
    hanging wall). At a point (x, y) (meant: on a trace) the function gives the top of the
    block just on the footwall side of the nearest trace there (NaN outside the lattice): the
    depth at which a fault given by its footwall cut-off meets the top horizon.
    """
    lines = [_trace_points(f, k) for k, f in enumerate(faults)]
    towards_footwall = [1.0 if f.side == "right" else -1.0 for f in faults]  # +1: the trace's left
    step = 1000.0 * blocks.tolerance

    def depth(x: ArrayLike, y: ArrayLike) -> FloatArray:
        px, py = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
        p = np.column_stack([px.ravel(), py.ravel()])
        best = np.full(p.shape[0], np.inf)
        probe = p.copy()
        for line, sign in zip(lines, towards_footwall, strict=True):
            seg, t, _ = nearest_on_trace(p, line, True, True)
            d = np.diff(line, axis=0)[seg]
            foot = line[seg] + t[:, None] * d
            dist = np.hypot(*(p - foot).T)
            left = np.column_stack([-d[:, 1], d[:, 0]]) / np.hypot(d[:, 0], d[:, 1])[:, None]
            nearer = dist < best
            best = np.where(nearer, dist, best)
            probe = np.where(nearer[:, None], foot + sign * step * left, probe)
        block = blocks.classify(probe[:, 0], probe[:, 1])
        values = np.stack([interpolate_horizon(xa, ya, top, p[:, 0], p[:, 1]) for top in tops])
        return values[block, np.arange(p.shape[0])].reshape(px.shape)

    return depth
