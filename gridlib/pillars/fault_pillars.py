"""The pillars of an areal grid that conforms to inclined faults: in the fault surfaces on the
faults, blending back to vertical away from them (the 2.5D grids of the seed's Fig. 3.24).

The areal grid (a PEBI grid, or any polygons) has its edges along every fault's trace at the
*top* horizon tagged with the fault (``faces.tag`` t = ``faults[t - 1]``); the pillars are pinned
at the top horizon, so its cells are the areal cells there. Per areal node:

* a node on one fault's edges: the straight line in the fault surface through it, the ruling of
  the surface (linear between consecutive sticks at equal depth) through the point of the
  surface below or above the node; its drift interpolates the two neighbouring sticks' chord
  drifts between the model's top and base depths (mitred at trace kinks by the surface itself),
  so the fault faces of the extruded grid lie on the surface (exactly for straight sticks);
* a node on two faults' edges (a junction): the line where the two surfaces meet (through the
  points where their horizontal sections cross at the top and base depths); on three or more
  faults, the first two (a note);
* a node on the domain boundary keeps its pillar in the boundary's vertical plane (the horizons
  are known only inside): a fault node there follows the line where the fault surface meets
  that plane (a chord where the surface is twisted), another node slides along the boundary;
  a corner of the boundary stays vertical;
* along a fault's planar stretches (a dip fault's straight segments) its pillars also drift
  along strike, linearly between the lines where it meets other faults or the boundary, so
  that they agree with those lines (any line of the plane lies in it);
* a node of a well's cells (``vertical_cells``) stays vertical, as does every node farther
  than the relax distance R from every inclined fault's trace;
* every other node's drift is discrete-harmonic between those
  (:func:`~gridlib.pillars.inclined_lines.harmonic_drift`), pinned at the top horizon.

The relax distance defaults to :func:`~gridlib.pillars.inclined_lines.default_relax_distance`
(2 H cot(dip)); :func:`~gridlib.pillars.inclined_lines.first_crossing` then checks that every
column stays star-shaped around its site (followed down the column) over the depths its cells
can occupy (given the base horizon; else over the model's range).
Where a column folds, a default R is lengthened by half, up to three times (a note says so);
a given one is not: one InputError names the areal cell, the depth and the relax distance.

The throw needs nothing new: columns never straddle a fault surface, so the extrusion's
plan-view classification of the cells by their sites against the top trace is exact.

Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import GridError, InputError
from ..grid import FloatArray, Grid
from .column_inputs import ColumnCorners
from .fault_surface import FaultSurface
from .fault_traces import FaultTrace, nearest_on_trace
from .horizon_maps import DepthFunction
from .inclined_lines import (
    PillarLines,
    check_relax_distance,
    default_relax_distance,
    first_crossing,
    harmonic_drift,
    interior_drift,
)
from .pillar_depths import depth_on_pillars

__all__ = ["FaultPillars", "ModelDepths", "depth_range", "fault_pillars", "inclined"]


@dataclass(frozen=True, eq=False)
class FaultPillars:
    """What :func:`fault_pillars` returns: ``lines`` (one per areal node), the ``relax_distance``
    used (m), the model's depth range [``z_lo``, ``z_hi``] (m), ``notes``, and the lines that
    the cells' ``sites`` follow (``site_lines``, one per areal cell, None without sites)."""

    lines: PillarLines
    relax_distance: float
    z_lo: float
    z_hi: float
    notes: tuple[str, ...]
    site_lines: PillarLines | None = None

    def pillars(self) -> FloatArray:
        """(n, 2, 3) top and bottom points for :func:`~gridlib.pillars.extrude.extrude`."""
        return self.lines.as_pillars(self.z_lo, self.z_hi)

    def sites_at(self, column: np.ndarray, depth: np.ndarray) -> FloatArray:
        """(n, 2): where the site of areal cell ``column`` is at ``depth`` (m), per 3-D cell."""
        if self.site_lines is None:
            raise GridError("FaultPillars.sites_at: fault_pillars was given no sites")
        line = self.site_lines
        return line.point[column, :2] + (depth - line.point[column, 2])[:, None] * line.drift[column]


def inclined(faults: Sequence[FaultTrace]) -> bool:
    """Whether any fault has a surface that is not vertical."""
    return any(_surface(f) is not None for f in faults)


def _surface(trace: FaultTrace) -> FaultSurface | None:
    """The fault's surface if it is inclined, else None (a vertical fault)."""
    surface = trace.surface
    return None if surface is None or surface.is_vertical else surface


def fault_pillars(
    areal: Grid,
    faults: Sequence[FaultTrace],
    top: DepthFunction,
    z_lo: float,
    z_hi: float,
    *,
    vertical_cells: np.ndarray | None = None,
    relax_distance: float | None = None,
    thickness: float | None = None,
    base: DepthFunction | None = None,
    throw: float = 0.0,
    sites: FloatArray | None = None,
    who: str = "pillars",
) -> FaultPillars:
    """The pillars of ``areal`` (see the module docstring).

    ``faults``: the faults, ``faces.tag`` t of ``areal`` being ``faults[t - 1]``'s edges; a fault
    with a ``surface`` that is not vertical inclines its pillars. ``top``: the top horizon's
    depth at plan points, ``top(x, y)`` vectorised (NaN outside). ``z_lo`` < ``z_hi``: the depths
    (m) between which the model lies, throws included (the fault drifts are the chords of the
    sticks between them, and the no-crossing check covers them). ``vertical_cells``: areal
    cells whose nodes keep vertical pillars (wells). ``relax_distance``: R (m), default
    2 H s_max with ``thickness`` H the largest depth span one pillar carries (m; default
    z_hi - z_lo; in a dipping model much less). ``base``: the base horizon's depth function:
    then every column is checked over the depths its cells can occupy (where its pillars meet
    the top and the base, widened by ``throw``, m), not over [z_lo, z_hi].
    ``sites`` (n_cells, 2): a point inside every areal cell (the PEBI
    sites) to follow the columns down (:func:`~gridlib.pillars.inclined_lines.interior_drift`,
    pinned at the top horizon): ``FaultPillars.sites_at``. ``who`` begins the error messages.
    """
    if not z_hi > z_lo:
        raise InputError(f"{who}: the model's depth range is empty ({z_lo:g} to {z_hi:g} m)")
    xy = areal.nodes.coords[:, :2]
    nn = xy.shape[0]
    notes: list[str] = []
    surfaces = [_surface(f) for f in faults]
    drifts = [None if s is None else np.asarray(s.drift(z_lo, z_hi), dtype=np.float64) for s in surfaces]
    max_drift = max((float(np.hypot(*d.T).max()) for d in drifts if d is not None), default=0.0)
    if relax_distance is None:
        relax = default_relax_distance(z_hi - z_lo if thickness is None else thickness, max_drift)
    else:
        relax = check_relax_distance(relax_distance, who)
    with np.errstate(invalid="ignore"):
        pin = np.asarray(top(xy[:, 0].copy(), xy[:, 1].copy()), dtype=np.float64)
    pin = np.where(np.isfinite(pin), pin, z_lo)
    point = np.column_stack([xy, pin])
    corners = ColumnCorners.of(areal)
    tangent, corner = _boundary(areal)
    on_boundary = np.isfinite(tangent[:, 0]) | corner
    fault_of_node = _fault_nodes(areal, len(faults))

    special_point, special_drift = _meeting_lines(
        surfaces, faults, fault_of_node, xy, point, tangent, corner, z_lo, z_hi, notes, who
    )
    planar = [
        _planar(s, z_lo, z_hi, 2 if d is None else d.shape[0]) for s, d in zip(surfaces, drifts, strict=True)
    ]
    sources = [
        _strike_drift(f, surfaces[f], drifts[f], planar[f], fault_of_node, special_point, special_drift)
        for f in range(len(faults))
    ]

    fixed = np.zeros(nn, dtype=bool)
    if vertical_cells is not None and np.any(vertical_cells):
        fixed[corners.ring[np.asarray(vertical_cells, dtype=bool)[corners.owner]]] = True
    # The pillars on the faults, which the relax distance does not change.
    on_fault = np.zeros(nn, dtype=bool)
    fault_point, fault_drift = point.copy(), np.zeros((nn, 2))
    for f, surface in enumerate(surfaces):
        nodes = np.flatnonzero(fault_of_node[:, 0] == f)
        nodes = nodes[(fault_of_node[nodes, 1] < 0) & ~on_boundary[nodes]]
        on_fault[nodes] = True
        if surface is not None and nodes.size:
            fault_point[nodes], fault_drift[nodes] = _on_surface(
                surface, drifts[f], planar[f], sources[f], xy[nodes], pin[nodes]
            )
    for node in special_drift:
        on_fault[node] = True
        fault_point[node], fault_drift[node] = special_point[node], special_drift[node]
    if np.any(fixed & on_fault):
        notes.append(
            f"{int(np.count_nonzero(fixed & on_fault))} nodes of well cells lie on a fault and follow "
            "its surface, not the vertical"
        )

    edges = areal.faces.nodes.reshape(-1, 2)
    far, nearest = _nearest_inclined(xy, faults, surfaces)
    held = on_fault | fixed | corner
    slide = np.where((on_boundary & ~held)[:, None], tangent, np.nan)

    given = np.where(on_fault[:, None], fault_drift, 0.0)  # the faults' pillars; wells, corners: 0

    def lines_for(relax: float) -> PillarLines:
        drift = harmonic_drift(xy, edges, held | (far >= relax), given, slide)
        return PillarLines(np.where(on_fault[:, None], fault_point, point), drift)

    # The default relax distance is lengthened where the drift of several faults (or of faults,
    # wells and boundaries) folds a column with it: by half at a time, three times at most.
    tries = [relax] if relax_distance is not None else [relax * f for f in (1.0, 1.5, 2.25, 3.375)]
    inside = _column_points(areal, corners, sites)
    for relax in tries:
        lines = lines_for(relax)
        centres = _follow(lines, corners, xy, inside, top, z_lo)
        col_lo, col_hi = (
            (z_lo, z_hi) if base is None else _column_ranges(lines, corners, top, base, throw, z_lo, z_hi)
        )
        bad = first_crossing(lines, corners.pos, corners.ring, col_lo, col_hi, centres)
        if bad is None:
            break
    if bad is not None:
        x, y = lines.xy_at(np.full(nn, bad.depth))[bad.node]
        name = faults[int(nearest[bad.node])].name
        ring = corners.ring[corners.pos[bad.column] : corners.pos[bad.column + 1]]
        cause = (
            "a well's cells, which keep vertical pillars, are this close to the fault (move the well "
            "or give a larger relax_distance)"
            if fixed[ring].any()
            else "give a larger relax_distance"
        )
        raise InputError(
            f"{who}: the inclined pillars near fault '{name}' fold areal cell {bad.column} at depth "
            f"{bad.depth:g} m (its pillar through ({xy[bad.node, 0]:g}, {xy[bad.node, 1]:g}) on the top "
            f"horizon is at ({x:g}, {y:g}) there) with relax_distance {relax:g} m: {cause}"
        )
    if relax != tries[0]:
        notes.append(
            f"the default relax distance {tries[0]:g} m (2 H cot(dip)) was lengthened to {relax:g} m: "
            "with it, columns where faults meet (or near wells) would fold"
        )
    site_lines = None if sites is None else centres
    return FaultPillars(lines, relax, float(z_lo), float(z_hi), tuple(notes), site_lines)


def _column_points(areal: Grid, corners: ColumnCorners, sites: FloatArray | None) -> FloatArray:
    """A point inside every areal cell: its site, else the mean of its nodes (inside a convex
    cell)."""
    if sites is not None:
        return np.asarray(sites, dtype=np.float64)
    xy = areal.nodes.coords[:, :2]
    count = np.diff(corners.pos)
    return np.column_stack(
        [np.bincount(corners.owner, xy[corners.ring, d], minlength=count.size) / count for d in (0, 1)]
    )


def _follow(lines: PillarLines, corners: ColumnCorners, xy, points, top, z_lo: float) -> PillarLines:
    """The lines that ``points`` (one inside every column) follow down their columns, pinned at the
    top horizon (:func:`~gridlib.pillars.inclined_lines.interior_drift`)."""
    drift = interior_drift(lines, corners.pos, corners.ring, xy, points)
    with np.errstate(invalid="ignore"):
        pin = np.asarray(top(points[:, 0].copy(), points[:, 1].copy()), dtype=np.float64)
    return PillarLines(np.column_stack([points, np.where(np.isfinite(pin), pin, z_lo)]), drift)


@dataclass(frozen=True)
class ModelDepths:
    """Where a model lies in depth (m): from ``z_lo`` (the shallowest top less the largest throw)
    to ``z_hi`` (the deepest base plus it); ``thickness``, the largest depth span one pillar
    carries (the thickest top-to-base interval plus the throw); ``throw``, the largest throw."""

    z_lo: float
    z_hi: float
    thickness: float
    throw: float


def largest_throw(faults: Sequence[FaultTrace]) -> float:
    """The largest |throw| (m) of ``faults`` anywhere along them (a varying throw sampled at 101
    points along the trace); 0 without faults."""
    throw = 0.0
    for f in faults:
        values = f.throw(np.linspace(0.0, 1.0, 101)) if callable(f.throw) else f.throw
        throw = max(throw, float(np.max(np.abs(values))))
    return throw


def depth_range(
    top: DepthFunction, base: DepthFunction, xy: FloatArray, faults: Sequence[FaultTrace]
) -> ModelDepths:
    """The :class:`ModelDepths` of the horizons ``top`` and ``base`` at plan points ``xy`` (n, 2)
    with the throws of ``faults``."""
    with np.errstate(invalid="ignore"):
        z_top = np.asarray(top(xy[:, 0].copy(), xy[:, 1].copy()), dtype=np.float64)
        z_base = np.asarray(base(xy[:, 0].copy(), xy[:, 1].copy()), dtype=np.float64)
    throw = largest_throw(faults)
    return ModelDepths(
        float(np.nanmin(z_top)) - throw,
        float(np.nanmax(z_base)) + throw,
        float(np.nanmax(z_base - z_top)) + throw,
        throw,
    )


def _column_ranges(lines: PillarLines, corners: ColumnCorners, top, base, throw: float, z_lo, z_hi):
    """The depths (m) each column's cells can occupy: from the shallowest point where one of its
    pillars meets the top horizon (less the throw) to the deepest where one meets the base (plus
    it); where a pillar misses a horizon or the iteration does not settle, the model's range."""
    pillars = lines.as_pillars(z_lo, z_hi)
    ends = []
    for horizon, shift, fallback in ((top, -throw, z_lo), (base, throw, z_hi)):
        with np.errstate(invalid="ignore"):
            z = depth_on_pillars(horizon, pillars, "fault_pillars", unsettled="nan")
        ends.append(np.where(np.isfinite(z), z + shift, fallback))
    lo = np.full(corners.pos.size - 1, np.inf)
    hi = np.full(corners.pos.size - 1, -np.inf)
    np.minimum.at(lo, corners.owner, ends[0][corners.ring])
    np.maximum.at(hi, corners.owner, ends[1][corners.ring])
    return lo, hi


def _nearest_inclined(xy: FloatArray, faults, surfaces) -> tuple[FloatArray, np.ndarray]:
    """Per plan point: the distance (m) to the nearest inclined fault's trace at the top horizon
    (inf without one) and that fault's index."""
    far = np.full(xy.shape[0], np.inf)
    nearest = np.zeros(xy.shape[0], dtype=np.int64)
    for f, (trace, surface) in enumerate(zip(faults, surfaces, strict=True)):
        if surface is not None:
            ref = trace.points
            seg, t, _ = nearest_on_trace(xy, ref, False, False)
            d = np.hypot(*(xy - ref[seg] - t[:, None] * (ref[seg + 1] - ref[seg])).T)
            nearest[d < far] = f
            far = np.minimum(far, d)
    return far, nearest


def _meeting_lines(surfaces, faults, fault_of_node, xy, point, tangent, corner, z_lo, z_hi, notes, who):
    """The pillars (points and drifts, by node) where two faults meet (the line where their
    surfaces meet) and where a fault meets the domain boundary (the line where it meets the
    boundary's vertical plane); vertical at a corner of the boundary and between vertical faults.
    Notes (in place) what could not be honoured."""
    on_boundary = np.isfinite(tangent[:, 0]) | corner
    special = np.flatnonzero((fault_of_node[:, 0] >= 0) & ((fault_of_node[:, 1] >= 0) | on_boundary))
    points, drifts = {}, {}
    extent = float(np.ptp(xy, axis=0).max())
    many = 0
    for node in special.tolist():  # a few nodes: where traces meet or reach the boundary
        f, g = (int(v) for v in fault_of_node[node, :2])
        many += int(fault_of_node[node, 2] >= 0)
        if (surfaces[f] is None and (g < 0 or surfaces[g] is None)) or corner[node]:
            if corner[node] and surfaces[f] is not None:
                notes.append(
                    f"fault '{faults[f].name}' meets a corner of the domain at ({xy[node, 0]:g}, "
                    f"{xy[node, 1]:g}): the pillar there stays vertical, off the fault surface"
                )
            points[node], drifts[node] = point[node], np.zeros(2)
            continue
        points[node], drifts[node] = _meeting_line(
            surfaces, faults, f, g, xy[node], tangent[node], z_lo, z_hi, extent, who
        )
    if many:
        notes.append(f"{many} nodes where three or more faults meet follow the first two faults' surfaces")
    return points, drifts


def _strike_drift(f, surface, drift, planar, fault_of_node, special_point, special_drift):
    """Fault f's drift along strike (strike coordinates, drifts): its sticks', with the lines
    where it meets other faults or the boundary inserted on its planar stretches."""
    n_sticks = 2 if drift is None else drift.shape[0]
    at = [n for n in special_drift if f in fault_of_node[n, :2]]
    if surface is None or not at:
        return np.arange(float(n_sticks)), (np.zeros((n_sticks, 2)) if drift is None else drift)
    at_points = np.array([special_point[n] for n in at])
    seg, t, _ = _locate(at_points[:, :2], np.asarray(surface.section(at_points[:, 2]), dtype=np.float64))
    return _with_meetings(drift, planar, seg + t, np.array([special_drift[n] for n in at]))


def _meeting_line(surfaces, faults, f, g, node_xy, tangent, z_lo, z_hi, extent, who):
    """The line (a point (3,) and its drift (2,)) where fault f's surface meets fault g's
    (g >= 0) or the vertical plane of the domain boundary through the node (g < 0, along
    ``tangent``): through the crossings of their horizontal sections at z_lo and z_hi nearest the
    node."""
    first = _section_polyline(surfaces[f], faults[f])
    if g >= 0:
        second = _section_polyline(surfaces[g], faults[g])
    else:
        line = np.array([node_xy - 2.0 * extent * tangent, node_xy + 2.0 * extent * tangent])

        def second(z: float) -> FloatArray:
            return line

    ends = []
    for z in (z_lo, z_hi):
        p = _crossing(first(z), second(z), node_xy)
        if p is None:
            other = "the domain boundary" if g < 0 else f"fault '{faults[g].name}'"
            raise InputError(
                f"{who}: fault '{faults[f].name}' and {other} meet at ({node_xy[0]:g}, {node_xy[1]:g}) "
                f"on the top horizon but not at depth {z:g} m: the pillar there cannot lie in both"
            )
        if g < 0:  # along the boundary from the node: on its line to the last bit
            along = (p[0] - node_xy[0]) * tangent[0] + (p[1] - node_xy[1]) * tangent[1]
            p = node_xy + along * tangent
        ends.append(p)
    drift = (ends[1] - ends[0]) / (z_hi - z_lo)
    if g < 0:
        drift = (drift[0] * tangent[0] + drift[1] * tangent[1]) * tangent
    return np.array([*ends[0], z_lo]), drift


def _planar(surface, z_lo: float, z_hi: float, n: int) -> np.ndarray:
    """(n - 1,) whether the surface between each pair of consecutive sticks is planar (over the
    depth range; a vertical fault's everywhere): there any line of the plane lies in it, so the
    pillars along the trace may also drift along strike."""
    if surface is None:
        return np.ones(n - 1, dtype=bool)
    top, base = (np.asarray(surface.section(np.float64(z)), dtype=np.float64) for z in (z_lo, z_hi))
    p0 = np.column_stack([top[:-1], np.full(n - 1, z_lo)])
    e1 = np.column_stack([top[1:], np.full(n - 1, z_lo)]) - p0
    e2 = np.column_stack([base[:-1], np.full(n - 1, z_hi)]) - p0
    e3 = np.column_stack([base[1:], np.full(n - 1, z_hi)]) - p0
    volume = np.abs(np.einsum("ij,ij->i", np.cross(e1, e2), e3))
    size = np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1) * np.linalg.norm(e3, axis=1)
    return volume <= 1e-12 * size


def _with_meetings(drift: FloatArray, planar: np.ndarray, at: FloatArray, at_drift: FloatArray):
    """A fault's drift along strike: at the sticks (strike coordinate 0, 1, ..., their chord
    drifts ``drift`` (k, 2)) and at the points ``at`` (strike coordinates: segment + fraction)
    where it meets another fault or the boundary, the meeting line's drift, inserted on the
    planar stretches only (elsewhere only the rulings lie in the surface). Linear between them,
    the drift along a planar stretch stays in its plane. Returns (coordinates, drifts)."""
    sticks = np.arange(float(drift.shape[0]))
    seg = np.clip(np.floor(at).astype(np.int64), 0, planar.size - 1)
    keep = planar[seg] & (at > seg) & (at < seg + 1)
    coordinate = np.concatenate([sticks, at[keep]])
    values = np.concatenate([drift, at_drift[keep]])
    order = np.argsort(coordinate, kind="stable")
    return coordinate[order], values[order]


def _on_surface(surface, drift: FloatArray, planar, along_trace, xy: FloatArray, top_depth: FloatArray):
    """Points (n, 3) and drifts (n, 2) of the lines of ``surface`` through plan points ``xy``
    near its trace at the top horizon: the depth where the surface passes through the point,
    found from the top horizon's depth by Newton steps along the rulings (one step for a
    plane; where the vertical line through a point meets a twisted surface twice, the meeting
    nearest the top horizon); the drift that of the ruling there, interpolated between the two
    sticks' chord drifts, or where the surface is ``planar`` between the sticks the drift along
    strike ``along_trace`` ((strike coordinates, drifts), the meeting lines included)."""
    z = top_depth.copy()
    scale = 1e-12 * max(1.0, float(np.abs(xy).max()))
    rows = np.arange(xy.shape[0])
    for _ in range(50):
        sections = np.asarray(surface.section(z), dtype=np.float64)
        seg, t, q = _locate(xy, sections)
        ruling = (1.0 - t)[:, None] * drift[seg] + t[:, None] * drift[seg + 1]
        along = sections[rows, seg + 1] - sections[rows, seg]
        normal = np.column_stack([-along[:, 1], along[:, 0]]) / np.hypot(*along.T)[:, None]
        offset = ((xy - q) * normal).sum(axis=1)
        rate = (ruling * normal).sum(axis=1)
        step = np.where(np.abs(rate) > 1e-12, offset / np.where(rate == 0, 1.0, rate), 0.0)
        if not (np.abs(offset) > scale).any() or not step.any():
            break
        z = z + step
    coordinate, values = along_trace
    planar = planar[seg]
    if planar.any():
        at = seg + t
        in_plane = np.column_stack([np.interp(at, coordinate, values[:, d]) for d in (0, 1)])
        ruling = np.where(planar[:, None], in_plane, ruling)
    return np.column_stack([q, z]), ruling


def _locate(xy: FloatArray, polylines: FloatArray):
    """The nearest point of every polyline (n, k, 2) to its point xy (n, 2): segment, parameter
    in [0, 1] and the point. One pass per segment, vectorised over the points."""
    n, k, _ = polylines.shape
    best = np.full(n, np.inf)
    seg = np.zeros(n, dtype=np.int64)
    tt = np.zeros(n)
    for s in range(k - 1):
        a, d = polylines[:, s], polylines[:, s + 1] - polylines[:, s]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.clip(((xy - a) * d).sum(axis=1) / (d * d).sum(axis=1), 0.0, 1.0)
        t = np.nan_to_num(t)
        dist = ((a + t[:, None] * d - xy) ** 2).sum(axis=1)
        better = dist < best
        best[better], seg[better], tt[better] = dist[better], s, t[better]
    rows = np.arange(n)
    a, c = polylines[rows, seg], polylines[rows, seg + 1]
    return seg, tt, a + tt[:, None] * (c - a)


def _section_polyline(surface, trace: FaultTrace) -> Callable[[float], FloatArray]:
    """The fault's horizontal section at a depth: the surface's, or a vertical fault's trace."""
    if surface is None:
        return lambda z: trace.points
    return lambda z: np.asarray(surface.section(np.float64(z)), dtype=np.float64)


def _crossing(first: FloatArray, second: FloatArray, near: FloatArray) -> np.ndarray | None:
    """The crossing of two polylines (k, 2) nearest to ``near``, their end segments extended
    as rays; None if they do not cross."""
    a, d = first[:-1], np.diff(first, axis=0)
    b, e = second[:-1], np.diff(second, axis=0)
    A, D = a[:, None], d[:, None]
    B, E = b[None], e[None]
    denom = D[..., 0] * E[..., 1] - D[..., 1] * E[..., 0]
    rel = B - A
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (rel[..., 0] * E[..., 1] - rel[..., 1] * E[..., 0]) / denom
        t = (rel[..., 0] * D[..., 1] - rel[..., 1] * D[..., 0]) / denom
    ns, nt = d.shape[0], e.shape[0]
    lo_s = np.where(np.arange(ns) == 0, -np.inf, 0.0)[:, None]
    hi_s = np.where(np.arange(ns) == ns - 1, np.inf, 1.0)[:, None]
    lo_t = np.where(np.arange(nt) == 0, -np.inf, 0.0)[None]
    hi_t = np.where(np.arange(nt) == nt - 1, np.inf, 1.0)[None]
    ok = (denom != 0) & (s >= lo_s) & (s <= hi_s) & (t >= lo_t) & (t <= hi_t)
    if not ok.any():
        return None
    points = A + s[..., None] * D
    dist = np.where(ok, ((points - near) ** 2).sum(axis=-1), np.inf)
    i, j = np.unravel_index(int(np.argmin(dist)), dist.shape)
    return points[i, j]


def _fault_nodes(areal: Grid, n_faults: int) -> np.ndarray:
    """(n_nodes, 3): the (0-based) faults whose tagged edges a node is on, up to three, -1 for none,
    in fault order."""
    nn = areal.num_nodes
    tag = np.asarray(areal.faces.tag, dtype=np.int64)
    edges = np.flatnonzero((tag > 0) & (tag <= n_faults))
    en = areal.faces.nodes.reshape(-1, 2)[edges]
    node = en.ravel()
    fault = np.repeat(tag[edges] - 1, 2)
    pairs = np.unique(node * (n_faults + 1) + fault)  # one row per (node, fault), sorted
    node, fault = np.divmod(pairs, n_faults + 1)
    rank = np.arange(node.size) - np.searchsorted(node, node)
    out = np.full((nn, 3), -1, dtype=np.int64)
    keep = rank < 3
    out[node[keep], rank[keep]] = fault[keep]
    return out


def _boundary(areal: Grid) -> tuple[FloatArray, np.ndarray]:
    """Per node: the unit direction of the straight boundary it lies on (NaN off the boundary
    and at corners), and whether it is a corner of the boundary."""
    nn = areal.num_nodes
    xy = areal.nodes.coords[:, :2]
    b = np.flatnonzero((areal.faces.neighbors < 0).any(axis=1))
    en = areal.faces.nodes.reshape(-1, 2)[b]
    d = xy[en[:, 1]] - xy[en[:, 0]]
    d /= np.hypot(*d.T)[:, None]
    node = en.ravel()
    direction = np.repeat(d, 2, axis=0)
    order = np.argsort(node, kind="stable")
    node, direction = node[order], direction[order]
    first = np.r_[True, node[1:] != node[:-1]]
    start = np.flatnonzero(first)
    count = np.diff(np.r_[start, node.size])
    tangent = np.full((nn, 2), np.nan)
    corner = np.zeros(nn, dtype=bool)
    two = start[count == 2]
    d1, d2 = direction[two], direction[two + 1]
    straight = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) < 1e-9
    tangent[node[two[straight]]] = d1[straight]
    corner[node[two[~straight]]] = True
    corner[node[start[count != 2]]] = True
    return tangent, corner
