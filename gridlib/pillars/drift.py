"""Pillar directions near inclined faults: the drift field and the no-crossing check.

A straight pillar is a point ``p`` at depth ``zp`` and a *drift* ``s`` (horizontal metres
per metre of depth): it passes through ``p + (z - zp) s`` at depth z. Near an inclined
fault the pillars lean with the fault and relax back to vertical away from it
(Petrel-style pillar gridding; the MRST book's ``simpleGrdecl``, Fig. 3.16):

* a pillar on a fault is a *ruling* of its surface (:class:`FaultRulings`): the straight
  line through the surface that joins the same strike position on every stick, so the
  pillar lies in the surface at every depth;
* any other pillar takes the drift of each fault's nearest ruling weighted by
  ``smoothstep(1 - d / R)`` (d the plan distance to the fault's trace at the top horizon,
  R the relax distance); near several faults, their weighted mean times the largest weight.

With the taper's steepest slope 1.5 / R, the map x -> x + dz s(x) over a depth range H keeps
its orientation while 1.5 H cot(dip) / R < 1: :func:`relax_bound` is R = 2 H cot(dip), the
default. :func:`min_corner_areas` is the exact check that decides: for every column of pillars
and every corner, the signed area of the triangle (previous, this, next corner) is a quadratic
in depth; its minimum over the column's depth range must be positive, which makes every
horizontal section of the column strictly convex and counter-clockwise, so no pillars cross and
no cell inverts.

Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..grid import FloatArray, IntArray
from .fault_traces import FaultTrace, nearest_on_trace
from .pillar_depths import DepthFunction, depth_on_pillars


@dataclass(frozen=True, eq=False)
class FaultRulings:
    """A fault surface as its rulings through the sticks, where they meet the top horizon.

    ``anchors`` (n >= 2, 2): x, y where stick k meets the top horizon (the fault's trace there),
    ``depth`` (n,): the depth there (m), ``drift`` (n, 2): stick k's horizontal change per metre
    of depth. Between sticks k and k + 1 the ruling at fraction t joins the points at t of both
    sticks at equal depth, so its anchor, depth and drift are the linear interpolations at t:
    the surface is linear between consecutive sticks at equal depth. All zero drift: a vertical
    fault. ``name`` labels errors.
    """

    name: str
    anchors: FloatArray
    depth: FloatArray
    drift: FloatArray

    @property
    def max_drift(self) -> float:
        """The largest drift of a stick, cot of the smallest dip."""
        return float(np.hypot(*self.drift.T).max())

    def ruling(self, seg: IntArray, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Anchor (m, 2), depth (m,) and drift (m, 2) of the rulings at fraction ``t`` of segments
        ``seg`` (t outside [0, 1] extrapolates the end segments)."""
        w = t[:, None]
        a = self.anchors[seg] * (1 - w) + self.anchors[seg + 1] * w
        z = self.depth[seg] * (1 - t) + self.depth[seg + 1] * t
        s = self.drift[seg] * (1 - w) + self.drift[seg + 1] * w
        return a, z, s


def fault_rulings(
    trace: FaultTrace,
    name: str,
    top: DepthFunction,
    z_range: tuple[float, float],
    tolerance: float = np.inf,
) -> tuple[FaultRulings, float]:
    """The rulings of ``trace``'s surface where they meet the top horizon ``top(x, y)`` (defined
    everywhere, e.g. clamped to its box), and how far (m, horizontally) the sticks stray from the
    straight chords that stand for them over ``z_range`` (the model's depths): 0 for straight
    sticks; a listric (bent) stick cannot be followed by a straight pillar. No surface: a
    vertical fault on the trace.

    A plane meets a curved top horizon (a dome) along a curve, not along the chord between its
    sticks' anchors: rulings are inserted between sticks (exactly, the surface being linear
    between them at equal depth) until the anchors' polyline is within ``tolerance`` (m) of the
    trace at the top horizon at every segment's midpoint. Otherwise the lattice line on the chord
    would sit off the trace and its pillars, pinned at the chord's depth, would cross their
    neighbours pinned at the top horizon. A flat or planar top needs no insertion."""
    surface = trace.surface
    if surface is None:
        anchors = np.array(trace.points, dtype=np.float64)
        return FaultRulings(name, anchors, top(anchors[:, 0], anchors[:, 1]), np.zeros_like(anchors)), 0.0
    z_lo, z_hi = z_range
    start = surface.section(z_lo)
    drift = surface.drift(z_lo, z_hi)
    inside = (surface.levels > z_lo) & (surface.levels < z_hi)
    chord = start[None] + (surface.levels[inside] - z_lo)[:, None, None] * drift[None]
    stray = float(np.hypot(*(surface.points[inside] - chord).T).max(initial=0.0))
    anchors, depth = _anchors(start, drift, z_lo, top, name)
    for _ in range(30):  # each round halves the segments still off the trace
        mid_start, mid_drift = 0.5 * (start[:-1] + start[1:]), 0.5 * (drift[:-1] + drift[1:])
        mid_anchor, mid_depth = _anchors(mid_start, mid_drift, z_lo, top, name)
        split = np.flatnonzero(np.hypot(*(mid_anchor - 0.5 * (anchors[:-1] + anchors[1:])).T) > tolerance)
        if split.size == 0:
            break
        start = np.insert(start, split + 1, mid_start[split], axis=0)
        drift = np.insert(drift, split + 1, mid_drift[split], axis=0)
        anchors = np.insert(anchors, split + 1, mid_anchor[split], axis=0)
        depth = np.insert(depth, split + 1, mid_depth[split])
    return FaultRulings(name, anchors, depth, drift), stray


def _anchors(
    start: FloatArray, drift: FloatArray, z_lo: float, top: DepthFunction, name: str
) -> tuple[FloatArray, FloatArray]:
    """Where the rulings through ``start`` (n, 2) at depth ``z_lo`` with ``drift`` meet the top."""
    lines = np.stack(
        [
            np.column_stack([start, np.full(len(start), z_lo)]),
            np.column_stack([start + drift, np.full(len(start), z_lo + 1.0)]),
        ],
        axis=1,
    )
    depth = depth_on_pillars(top, lines, f"fault '{name}': where its sticks meet the top horizon")
    if not np.isfinite(depth).all():
        k = int(np.flatnonzero(~np.isfinite(depth))[0])
        raise InputError(
            f"fault '{name}': stick {k + 1} does not meet the top horizon (it is undefined there)"
        )
    return start + (depth - z_lo)[:, None] * drift, depth


def relax_bound(thickness: float, max_drift: float) -> float:
    """The default relax distance R = 2 H cot(dip) (m): ``thickness`` H the largest depth range a
    pillar carries, ``max_drift`` cot of the smallest dip. Twice the heave over the model, so the
    smoothstep taper (slope at most 1.5 / R) keeps every column's orientation."""
    return 2.0 * float(thickness) * float(max_drift)


def blended_drift(xy: FloatArray, faults: list[FaultRulings], relax: float) -> FloatArray:
    """Drift (n, 2) of pillars through the points ``xy`` (n, 2) at the top horizon that lie on no
    fault: the mean of the faults' nearest rulings' drifts weighted by ``w = smoothstep(1 - d /
    relax)``, d the plan distance to the fault's trace (so it also tapers beyond a tip), times the
    largest w: near one fault its drift times w, and two faults' drifts never add up."""
    total = np.zeros_like(xy)
    weight = np.zeros(xy.shape[0])
    strongest = np.zeros(xy.shape[0])
    if relax <= 0:
        return total
    for fault in faults:
        if fault.max_drift == 0.0:
            continue
        seg, t, _ = nearest_on_trace(xy, fault.anchors, False, False)
        near, _, s = fault.ruling(seg, t)
        d = np.hypot(*(xy - near).T)
        w = smoothstep(1.0 - d / relax)
        total += w[:, None] * s
        weight += w
        np.maximum(strongest, w, out=strongest)
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(weight[:, None] > 0, total / weight[:, None], 0.0)
    return mean * strongest[:, None]


def smoothstep(u: FloatArray) -> FloatArray:
    """3u^2 - 2u^3 of u clipped to [0, 1]: 0 -> 0, 1 -> 1, flat at both ends."""
    u = np.clip(u, 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


def min_corner_areas(
    q: FloatArray, s: FloatArray, triples: IntArray, z_lo: FloatArray, z_hi: FloatArray
) -> FloatArray:
    """Smallest doubled signed area of every corner triangle over a depth range.

    Pillar n passes through ``q[n] + z s[n]`` (z relative to any common reference depth).
    ``triples`` (m, 3): the previous, this and next corner of a column's ring (counter-clockwise
    seen from above, x east, y north); ``z_lo``, ``z_hi`` (m,): the depth range (same reference)
    the column's cells occupy. The area is a quadratic a + b z + c z^2 in z; its minimum over
    [z_lo, z_hi] is at an end or at the vertex. All positive: no pillar crosses another and no
    column inverts anywhere in that range.

    >>> q = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    >>> s = np.array([[0.0, 0.0], [-0.5, 0.0], [0.0, 0.0]])  # the second pillar leans west
    >>> min_corner_areas(q, s, np.array([[2, 0, 1]]), np.array([0.0]), np.array([1.0])).tolist()
    [0.5]
    """
    p0, p1, p2 = q[triples[:, 0]], q[triples[:, 1]], q[triples[:, 2]]
    d0, d1, d2 = s[triples[:, 0]], s[triples[:, 1]], s[triples[:, 2]]
    u0, u1 = p2 - p1, d2 - d1  # this -> next
    v0, v1 = p0 - p1, d0 - d1  # this -> previous
    a = _cross(u0, v0)
    b = _cross(u0, v1) + _cross(u1, v0)
    c = _cross(u1, v1)

    def area(z: FloatArray) -> FloatArray:
        return a + z * (b + z * c)

    lo, hi = area(z_lo), area(z_hi)
    with np.errstate(divide="ignore", invalid="ignore"):
        vertex = np.where(c > 0, -b / (2 * c), z_lo)
    inside = (c > 0) & (vertex > z_lo) & (vertex < z_hi)
    return np.minimum(np.minimum(lo, hi), np.where(inside, area(np.where(inside, vertex, z_lo)), np.inf))


def _cross(u: FloatArray, v: FloatArray) -> FloatArray:
    return u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]


def check_columns(
    q: FloatArray,
    s: FloatArray,
    triples: IntArray,
    column: IntArray,
    z_lo: FloatArray,
    z_hi: FloatArray,
    column_label,
    nearest_fault,
    relax: float,
    bound: float,
) -> None:
    """:func:`min_corner_areas` of every corner positive, else one :class:`InputError` naming the
    first failing column (``column_label(c)``, e.g. ``"(i, j) = (3, 5)"``), the fault nearest to it
    (``nearest_fault(c)``) and the relax distance, suggesting a larger one."""
    area = min_corner_areas(q, s, triples, z_lo, z_hi)
    bad = ~(area > 0)
    if not bad.any():
        return
    first = int(column[np.flatnonzero(bad)[0]])
    n_bad = np.unique(column[bad]).size
    raise InputError(
        f"fault_geometry pillars: the pillars near fault '{nearest_fault(first)}' cross or invert "
        f"{n_bad} columns, first column {column_label(first)}: its pillars lean too differently over "
        f"its depth range; increase relax_distance (now {relax:g} m; the bound 2 H cot(dip) is "
        f"{bound:g} m) or use fault_geometry: stair_steps"
    )
