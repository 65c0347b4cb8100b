"""Straight inclined pillars that follow inclined faults and relax back to vertical away from them.

One concept serves corner-point lattices and 2.5D (PEBI) grids alike: every pillar is a
straight line, given by one of its points (x, y, depth) and its *drift* (dx/dz, dy/dz): the
horizontal metres it moves per metre of depth. A pillar in a fault surface takes the drift
of the surface's ruling; the other pillars take a drift that blends back to vertical:

* :func:`taper`: the weight w(d) = smoothstep(1 - d / R) of a fault's drift at plan
  distance d from its trace, 1 on the trace, 0 from the *relax distance* R on, with zero
  slope at both ends;
* :func:`relaxed_drift`: the drift field of several faults, each trace's own drift
  (interpolated along strike between its vertices) weighted by the taper; where several
  faults reach a point, the drift that moves it across each fault as that fault asks
  (least squares), so that near a junction the field is the junction line's drift;
* :func:`default_relax_distance`: R = 2 H s_max (H the depth range of the model, s_max the
  largest fault drift, cot(dip) for a dip fault). The map X0 -> X0 + dz s(X0) preserves
  orientation while dz |grad s| < 1, and the taper's slope is at most 1.5 s_max / R: this R
  keeps H |grad s| at 0.75;
* :func:`first_crossing`: the exact test that no column of the grid inverts or folds at
  any depth of the model (a sufficient bound is no proof for the taper of several faults,
  wells and boundaries together).

The test: at depth z every pillar is at P(z) = a + z s, linear in z, so the signed area of
the triangle (P_{c-1}, P_c, P_{c+1}) at every corner c of a column is a quadratic in z. If
none is negative over the depth range, every column's horizontal section is a convex,
positively oriented polygon at every depth: no two pillars of a column cross and no
column inverts (its cells then have positive volumes when their layers are in depth order).
Corners whose three pillars are collinear (nodes along a straight fault trace, whose
pillars lie in one plane, or along a straight domain boundary) stay collinear: the section
may turn the wrong way there by no more than round-off, 1e-9 radians.

Columns are given as node cycles (``pos``/``ring``, as
:class:`~gridlib.pillars.column_inputs.ColumnCorners`: corner-point cells have four, PEBI
cells as many as their polygon). Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..grid import FloatArray, IntArray
from .fault_traces import nearest_on_trace

__all__ = [
    "Crossing",
    "PillarLines",
    "default_relax_distance",
    "first_crossing",
    "relaxed_drift",
    "taper",
]

# How firmly relaxed_drift makes a point near a fault move across it as the fault does, beside 1
# for keeping to the faults' mean drift: STIFFNESS w^POWER (3 on a trace). Chosen on junctions
# of two planar faults (dips 45-70 degrees, meeting at 80-100 degrees) as the setting that
# folds no column at the smallest relax distance.
STIFFNESS = 3.0
POWER = 2

# The section of a column may turn the wrong way at a corner by this much (radians) without
# folding: collinear pillars (one fault plane, one boundary edge) stay collinear up to round-off.
COLLINEAR_TOLERANCE = 1e-9


@dataclass(frozen=True, eq=False)
class PillarLines:
    """Straight pillars, one per node: ``point`` (n, 3) a point of each (x, y, depth, m) and
    ``drift`` (n, 2) its horizontal displacement per metre of depth (0 = vertical)."""

    point: FloatArray
    drift: FloatArray

    def xy_at(self, z: ArrayLike) -> FloatArray:
        """(n, 2): where every pillar is at depth ``z`` (a number or one depth per pillar)."""
        dz = np.asarray(z, dtype=np.float64) - self.point[:, 2]
        return self.point[:, :2] + dz[:, None] * self.drift

    def as_pillars(self, z_top: float, z_bottom: float) -> FloatArray:
        """(n, 2, 3): the top and bottom points of every pillar at depths ``z_top`` < ``z_bottom``,
        as :func:`~gridlib.pillars.extrude.extrude` and COORD take them. A pillar of drift 0 keeps
        its x, y exactly."""
        n = self.point.shape[0]
        out = np.empty((n, 2, 3))
        for k, z in enumerate((z_top, z_bottom)):
            out[:, k, :2] = self.xy_at(z)
            out[:, k, 2] = z
        return out


def taper(distance: ArrayLike, relax: float) -> FloatArray:
    """w = smoothstep(1 - d / R): 1 at distance 0, 0 from ``relax`` on, slope 0 at both ends and
    at most 1.5 / R in between."""
    t = np.clip(1.0 - np.asarray(distance, dtype=np.float64) / relax, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def default_relax_distance(depth_range: float, max_drift: float) -> float:
    """R = 2 H s_max (m): ``depth_range`` H the depth span of the model, ``max_drift`` the largest
    horizontal drift of a fault (cot(dip) for a dip fault). 0 when no fault is inclined."""
    return 2.0 * float(depth_range) * float(max_drift)


def relaxed_drift(
    points: FloatArray, traces: Sequence[tuple[FloatArray, FloatArray, np.ndarray]], relax: float
) -> FloatArray:
    """The drift (n, 2) at plan ``points`` (n, 2) of the faults ``traces``: per fault its trace's
    vertices (k, 2), the drift of the fault at each (k, 2), interpolated linearly along every
    segment, and whether the fault is planar along each segment (k - 1,) (its pillars may then
    also drift along strike, e.g. towards a junction's).

    Fault f offers at a point its drift s_f at the nearest trace point, the trace's horizontal
    unit normal n_f there and the weight w_f = :func:`taper` (distance, ``relax``) (past a
    trace's ends the distance is to its end point, so the drift also dies out beyond a tip).
    The drift is the blend s_mean = sum w_f s_f / max(1, sum w_f), corrected so that it moves
    the point across every fault nearby as that fault asks: s minimises
    |s - s_mean|^2 + sum_f K w_f^2 (s . n_f - w_f s_f . n_f)^2 (K = ``STIFFNESS``; where a fault is
    not planar, the component along it is held alike). One fault:
    s = w_f s_f exactly. Where two faults meet, s tends to their common drift, the one of the
    line where the surfaces meet (the junction pillars'), so the columns there shear little; a
    fault far away (small w_f) hardly constrains it. A vertical fault (drift 0) pulls the
    points near it back to vertical."""
    n = points.shape[0]
    m = np.zeros((n, 2, 2))
    m[:, 0, 0] = m[:, 1, 1] = 1.0
    rhs = np.zeros((n, 2))
    mean = np.zeros((n, 2))
    weight = np.zeros(n)
    if relax <= 0:
        return mean
    for verts, drift, planar in traces:
        seg, t, _ = nearest_on_trace(points, verts, False, False)
        near = verts[seg] + t[:, None] * (verts[seg + 1] - verts[seg])
        w = taper(np.hypot(*(points - near).T), relax)
        s = (1.0 - t)[:, None] * drift[seg] + t[:, None] * drift[seg + 1]
        along = np.diff(verts, axis=0)[seg]
        normal = np.column_stack([-along[:, 1], along[:, 0]]) / np.hypot(*along.T)[:, None]
        stiffness = STIFFNESS * w**POWER
        # across the fault; where it is not planar its pillars cannot drift along it either
        held = normal[:, :, None] * normal[:, None, :] + (~np.asarray(planar)[seg])[:, None, None] * (
            np.eye(2) - normal[:, :, None] * normal[:, None, :]
        )
        m += stiffness[:, None, None] * held
        rhs += (stiffness * w)[:, None] * np.einsum("nij,nj->ni", held, s)
        mean += w[:, None] * s
        weight += w
    rhs += mean / np.maximum(weight, 1.0)[:, None]
    det = m[:, 0, 0] * m[:, 1, 1] - m[:, 0, 1] * m[:, 1, 0]
    out = np.empty((n, 2))
    out[:, 0] = (m[:, 1, 1] * rhs[:, 0] - m[:, 0, 1] * rhs[:, 1]) / det
    out[:, 1] = (m[:, 0, 0] * rhs[:, 1] - m[:, 1, 0] * rhs[:, 0]) / det
    return out


@dataclass(frozen=True)
class Crossing:
    """The first column (0-based) whose section turns the wrong way, at which corner (its node)
    and depth (m), and by how much (the sine of the wrong turn)."""

    column: int
    node: int
    depth: float
    turn: float


def first_crossing(
    lines: PillarLines, pos: IntArray, ring: IntArray, z_lo: float, z_hi: float
) -> Crossing | None:
    """The exact no-crossing test (module docstring) of the columns ``pos``/``ring`` (node cycles,
    all walked the same way round, as the cells of an areal grid: the way is that of their total
    area at mid depth) over depths [``z_lo``, ``z_hi``]; None when every column stays convex and
    oriented that way at every depth. Vectorised over all corners."""
    n_corner = ring.size
    owner = np.repeat(np.arange(pos.size - 1), np.diff(pos))
    nxt = np.arange(1, n_corner + 1)
    nxt[pos[1:] - 1] = pos[:-1]
    prv = np.arange(-1, n_corner - 1)
    prv[pos[:-1]] = pos[1:] - 1
    z_mid = 0.5 * (z_lo + z_hi)
    # Positions at mid depth, relative to the column's first node (no digits lost at UTM sizes),
    # and depths relative to mid depth: P = a + zeta s with zeta in [-h, h].
    xy = lines.xy_at(z_mid)
    a = xy[ring] - xy[ring[pos[:-1]]][owner]
    s = lines.drift[ring]
    u, du = a - a[prv], s - s[prv]
    v, dv = a[nxt] - a, s[nxt] - s
    c0 = _cross(u, v)
    c1 = _cross(u, dv) + _cross(du, v)
    c2 = _cross(du, dv)
    sign = -1.0 if _cross(a, a[nxt]).sum() < 0 else 1.0  # the grid's orientation: its total area
    h = 0.5 * (z_hi - z_lo)
    candidates = [np.full(n_corner, -h), np.full(n_corner, h)]
    with np.errstate(divide="ignore", invalid="ignore"):
        vertex = np.where(c2 != 0, -c1 / (2.0 * c2), -h)
    candidates.append(np.clip(vertex, -h, h))
    worst_turn = np.full(n_corner, np.inf)
    worst_zeta = np.zeros(n_corner)
    for zeta in candidates:
        area = sign * (c0 + zeta * (c1 + zeta * c2))
        lengths = np.hypot(*(u + zeta[:, None] * du).T) * np.hypot(*(v + zeta[:, None] * dv).T)
        with np.errstate(divide="ignore", invalid="ignore"):
            turn = np.where(lengths > 0, area / lengths, -1.0)  # a vanishing edge folds the column
        lower = turn < worst_turn
        worst_turn[lower] = turn[lower]
        worst_zeta[lower] = zeta[lower]
    bad = np.flatnonzero(worst_turn < -COLLINEAR_TOLERANCE)
    if bad.size == 0:
        return None
    q = int(bad[np.argmin(owner[bad])])
    return Crossing(int(owner[q]), int(ring[q]), float(z_mid + worst_zeta[q]), float(worst_turn[q]))


def interior_drift(
    lines: PillarLines, pos: IntArray, ring: IntArray, node_xy: FloatArray, points: FloatArray
) -> FloatArray:
    """The drift (n_columns, 2) of one point inside every column that moves with it: ``points``
    (n_columns, 2) inside the convex polygons of the nodes ``node_xy`` (``pos``/``ring``) take the
    pillars' drifts averaged with their Wachspress coordinates there (generalised barycentric
    coordinates, positive inside a convex polygon). A point so moved stays inside its column's
    section at every depth where the section is convex (the PEBI sites as cell centres)."""
    owner = np.repeat(np.arange(pos.size - 1), np.diff(pos))
    nxt = np.arange(1, ring.size + 1)
    nxt[pos[1:] - 1] = pos[:-1]
    prv = np.arange(-1, ring.size - 1)
    prv[pos[:-1]] = pos[1:] - 1
    v = node_xy[ring] - points[owner]  # relative to the point: no digits lost at UTM sizes
    corner_area = _cross(v - v[prv], v[nxt] - v)
    before, after = _cross(v[prv], v), _cross(v, v[nxt])
    with np.errstate(divide="ignore", invalid="ignore"):
        w = corner_area / (before * after)
    w = np.where(np.isfinite(w), w, 0.0)
    total = np.bincount(owner, w, minlength=pos.size - 1)
    out = np.empty((pos.size - 1, 2))
    for d in (0, 1):
        out[:, d] = np.bincount(owner, w * lines.drift[ring, d], minlength=pos.size - 1) / total
    return out


def _cross(p: FloatArray, q: FloatArray) -> FloatArray:
    return p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]


def check_relax_distance(relax: float, who: str) -> float:
    """``relax`` as a float, or one InputError naming ``who`` if it is not a positive length."""
    try:
        value = float(relax)
    except (TypeError, ValueError):
        raise InputError(f"{who}: relax_distance must be a length in metres, got {relax!r}") from None
    if not np.isfinite(value) or value <= 0:
        raise InputError(f"{who}: relax_distance must be a positive length in metres, got {relax!r}")
    return value
