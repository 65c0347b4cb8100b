"""Pillar directions near inclined faults on a corner-point lattice: the smoothstep drift field.

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
its orientation while 1.5 H cot(dip) / R < 1, so the default R = 2 H cot(dip)
(:func:`~gridlib.pillars.inclined_lines.default_relax_distance`) suffices for one fault; the
exact check that decides, for the corner-point and the PEBI pillars alike, is
:func:`~gridlib.pillars.inclined_lines.first_crossing`.

Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..grid import FloatArray, IntArray
from .fault_traces import FaultTrace, nearest_on_trace
from .horizon_maps import DepthFunction
from .pillar_depths import depth_on_pillars


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
