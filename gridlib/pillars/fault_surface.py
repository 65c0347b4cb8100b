"""Inclined fault surfaces: a fault given by its dip or by fault sticks, as one ruled surface.

A fault surface is a list of *sticks* ordered along strike, every one a line (or a polyline)
running down the fault, resampled at one common set of depths, the *levels*. The surface is
straight between consecutive sticks at equal depth: its horizontal section at depth ``z`` is the
polyline through every stick's point at ``z`` (:meth:`FaultSurface.section`), and between two
sticks and two levels it is the ruled (bilinear) patch those four points span. A ruled patch, not
two triangles, so that straight lines running down the fault (pillars) can lie in it exactly.
Beyond the first and last level each stick goes on straight (its end interval extended), and
beyond the first and last stick the section goes on straight (its end segments extended), so the
surface covers any model.

A fault given by a dip (:meth:`FaultSurface.from_dip`) is a generated stick set: one straight
stick under every vertex of its trace on the top horizon. Units are metres and degrees; z is
depth, positive downwards.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..arrays import frozen_array, point_array
from ..errors import InputError
from ..grid import FloatArray, IntArray
from .horizon_maps import DepthFunction

_COINCIDENT = 1e-12  # two sticks closer than this (relative to the surface's extent) coincide
_PARALLEL = 1e-13  # sticks whose drifts differ by less (relative to their coordinates) are parallel
_PAIR_BUDGET = 1 << 20  # (depth, pair of strike segments) tests per block of the crossing check


@dataclass(frozen=True, eq=False)
class FaultSurface:
    """A fault surface made of sticks: straight between consecutive sticks at equal depth (a
    ruled surface), each stick piecewise linear in depth. z is depth (m, positive down).

    ``levels``: (m >= 2,) strictly increasing depths (m) at which every stick is sampled.
    ``points``: (m, n >= 2, 2) x, y (m) of stick s at depth ``levels[j]``; beyond the first and
    the last level every stick continues linearly (its end interval extended).
    ``name``: the fault's name, ``source``: the file the sticks came from; both only label errors.

    >>> s = FaultSurface.from_dip([(0.0, 0.0), (0.0, 100.0)], [1000.0, 1000.0], 45.0, "right")
    >>> s.section(1010.0).round(9).tolist()  # walking north, right is east: 10 m deeper, 10 m east
    [[10.0, 0.0], [10.0, 100.0]]
    >>> s.dip_side(), round(float(s.depth_at(5.0, 50.0)), 9)
    ('right', 1005.0)
    """

    levels: FloatArray
    points: FloatArray
    name: str | None = None
    source: str | None = None

    def __post_init__(self) -> None:
        label = _label(self.name, self.source)
        levels = frozen_array(self.levels, np.float64, f"{label}: levels", 1, copy=True, error=InputError)
        points = frozen_array(self.points, np.float64, f"{label}: points", 3, copy=True, error=InputError)
        if levels.size < 2 or not np.isfinite(levels).all() or np.any(np.diff(levels) <= 0):
            raise InputError(f"{label}: levels must be >= 2 finite, strictly increasing depths (m)")
        if points.shape[0] != levels.size or points.shape[1] < 2 or points.shape[2] != 2:
            raise InputError(
                f"{label}: points must be an ({levels.size}, n >= 2, 2) array of x, y "
                f"(one row per level), got shape {points.shape}"
            )
        if not np.isfinite(points).all():
            raise InputError(f"{label}: points must be finite")
        object.__setattr__(self, "levels", levels)
        object.__setattr__(self, "points", points)

    @classmethod
    def from_dip(
        cls,
        trace_xy: ArrayLike,
        top_depth: ArrayLike,
        dip_deg: ArrayLike,
        side: str,
        name: str | None = None,
    ) -> FaultSurface:
        """A fault given by its trace where it cuts the top horizon.

        ``trace_xy``: the trace's vertices (n >= 2, 2), m; ``top_depth``: the top horizon's
        depth at every vertex (n,), m; ``dip_deg``: the dip in degrees from horizontal, in
        (0, 90], a number or one per vertex; ``side``: ``"left"`` or ``"right"`` of the trace
        walked from its first vertex to its last, the side the fault dips towards (the hanging
        wall of a normal fault).

        Under every vertex v_k runs a straight stick ``x = v_k + (z - top_depth_k) * h_k``.
        On a straight trace, ``h_k = cot(dip_k) * n`` with ``n`` the horizontal unit normal of
        the trace towards ``side``: the dip is measured in the vertical plane normal to the map
        trace, so where the top horizon is not flat along the trace it is an *apparent* dip, and
        the fault is the plane through the trace (at the top's depths) dipping so in that plane.
        At an interior vertex the stick is the line where the planes of its two segments meet
        (the mitre: ``h = cot(dip) * (n_a + n_b) / (1 + n_a . n_b)`` under a flat top), so every
        straight segment of the trace keeps its own plane exactly. Dip 90 gives vertical sticks.
        """
        label = _label(name, None)
        verts = point_array(trace_xy, 2, f"{label}: trace", min_points=2, point="vertex")
        n = verts.shape[0]
        z0 = _per_vertex(top_depth, n, f"{label}: top horizon depth")
        dip = _per_vertex(dip_deg, n, f"{label}: dip")
        bad = (dip <= 0) | (dip > 90)
        if bad.any():
            raise InputError(
                f"{label}: dip must be in (0, 90] degrees, got {dip[bad][0]:g} at trace vertex "
                f"{int(np.flatnonzero(bad)[0]) + 1}"
            )
        if side not in ("left", "right"):
            raise InputError(f"{label}: side must be 'left' or 'right', got {side!r}")
        step = np.diff(verts, axis=0)
        length = np.hypot(step[:, 0], step[:, 1])
        if np.any(length == 0):
            k = int(np.flatnonzero(length == 0)[0]) + 1
            raise InputError(f"{label}: trace vertices {k} and {k + 1} coincide (zero-length segment)")
        along = step / length[:, None]
        towards = 1.0 if side == "left" else -1.0
        normal = towards * np.stack([-along[:, 1], along[:, 0]], axis=1)
        rad = np.radians(dip)
        cot = np.where(dip == 90, 0.0, np.cos(rad) / np.sin(rad))  # reproducible: no np.tan
        drift = _vertex_drift(along, normal, np.diff(z0) / length, cot)

        # Straight sticks: any two levels hold them exactly; these are well apart.
        top = float(z0.min())
        extent = float(np.ptp(verts, axis=0).max())
        levels = np.array([top, top + max(float(z0.max()) - top, extent, 1.0)])
        points = verts + (levels[:, None, None] - z0[None, :, None]) * drift[None]
        return cls(levels, points, name=name)

    @classmethod
    def from_sticks(
        cls, sticks: Sequence[ArrayLike], name: str | None = None, source: str | None = None
    ) -> FaultSurface:
        """A fault from its sticks: each a (k >= 2, 3) array of x, y, z rows (m, z depth
        increasing strictly down the stick), the sticks ordered along strike.

        Every stick is resampled at the union of all the sticks' depths (linear between its
        points, extended linearly beyond its ends). One :class:`~gridlib.errors.InputError`
        naming ``source`` and the stick (1-based) for: fewer than 2 sticks, a stick of fewer than
        2 points, a value that is not finite, a depth that does not increase down a stick, and
        two sticks that coincide or cross (at any level, or half-way between two, the
        horizontal section is not a simple polyline, or two consecutive sticks swap order).
        """
        label = _label(name, source)
        sticks = list(sticks)
        if len(sticks) < 2:
            raise InputError(f"{label}: a fault surface needs at least 2 sticks, got {len(sticks)}")
        arrays = [_stick_array(stick, number, label) for number, stick in enumerate(sticks, 1)]
        levels = np.unique(np.concatenate([stick[:, 2] for stick in arrays]))
        points = np.stack([_resample(stick, levels) for stick in arrays], axis=1)
        depths = np.sort(np.concatenate([levels, 0.5 * (levels[:-1] + levels[1:])]))
        _check_sections(depths, _sections(levels, points, depths), label)
        return cls(levels, points, name=name, source=source)

    @property
    def is_vertical(self) -> bool:
        """Every stick is vertical (no stick drifts with depth)."""
        return bool(np.all(self.points == self.points[:1]))

    def section(self, z: ArrayLike) -> FloatArray:
        """Every stick's x, y at depth ``z``: z (...,) m -> (..., n, 2) m."""
        return _sections(self.levels, self.points, np.asarray(z, dtype=np.float64))

    def drift(self, z_top: float, z_base: float) -> FloatArray:
        """(n, 2): the x, y change per metre of depth of every stick's chord between depths
        ``z_top`` and ``z_base`` (exact for straight sticks, whatever the depths); the stick's
        own slope there if the two depths are equal."""
        if z_top == z_base:
            j, _ = _interval(self.levels, np.asarray(float(z_top)))
            return (self.points[j + 1] - self.points[j]) / (self.levels[j + 1] - self.levels[j])
        return (self.section(z_base) - self.section(z_top)) / (float(z_base) - float(z_top))

    def side_value(self, x: ArrayLike, y: ArrayLike, z: ArrayLike) -> FloatArray:
        """Which side of the surface every point is on, at the point's own depth: > 0 on the
        left of the section at depth ``z`` walked from the first stick to the last, < 0 on its
        right, 0 on it: the cross product of the nearest segment of the section with the point
        from its start (m^2, |segment| times the distance). The sides of
        :func:`~gridlib.pillars.fault_traces.nearest_on_trace` (the nearest point of the section
        decides; nearest an interior stick, the side away from the turn; the end segments
        extended as rays). x, y, z broadcast together, m."""
        px, py, pz = (np.asarray(v, dtype=np.float64) for v in np.broadcast_arrays(x, y, z))
        shape = px.shape
        px, py = px.ravel(), py.ravel()
        j, w = _interval(self.levels, pz.ravel())
        n_seg = self.points.shape[1] - 1
        seg, tt, best = self._nearest(px, py, j, w, True, True)
        lower, step = self.points[:-1], np.diff(self.points, axis=0)  # as _nearest computes them
        ax, ay, bx, by = (lower[j, seg + s, c] + w * step[j, seg + s, c] for s in (0, 1) for c in (0, 1))
        side = (bx - ax) * (py - ay) - (by - ay) * (px - ax)
        # Nearest point at an interior stick: the point lies on the outer side of the turn there,
        # as far from it as the segment's cross product says elsewhere (|segment| * distance).
        vertex = np.where((tt == 0) & (seg > 0), seg, np.where((tt == 1) & (seg < n_seg - 1), seg + 1, -1))
        at = np.flatnonzero(vertex > 0)
        if at.size:
            v, jj, ww = vertex[at], j[at], w[at]
            before, here, after = (self._sticks_at(v + shift, jj, ww) for shift in (-1, 0, 1))
            d0, d1 = here - before, after - here
            turn = d0[:, 0] * d1[:, 1] - d0[:, 1] * d1[:, 0]
            segment = np.where((v == seg[at])[:, None], d1, d0)
            value = -np.sign(turn) * np.sqrt(best[at]) * np.hypot(segment[:, 0], segment[:, 1])
            side[at] = np.where(turn != 0, value, side[at])
        return side.reshape(shape)

    def nearest_on_section(
        self, x: ArrayLike, y: ArrayLike, z: ArrayLike, open_start: bool = True, open_end: bool = True
    ) -> tuple[IntArray, FloatArray]:
        """The nearest point of the surface's horizontal section at every point's own depth: its
        strike segment (0-based, between sticks ``seg`` and ``seg + 1``) and the fraction ``t``
        along it, as :func:`~gridlib.pillars.fault_traces.nearest_on_trace` gives them for a
        trace (t beyond [0, 1] on the first or last segment where that end is open: a ray).
        x, y, z broadcast together, m; returns arrays of their (flattened) size."""
        px, py, pz = (np.asarray(v, dtype=np.float64).ravel() for v in np.broadcast_arrays(x, y, z))
        j, w = _interval(self.levels, pz)
        seg, t, _ = self._nearest(px, py, j, w, open_start, open_end)
        return seg, t

    def _nearest(self, px, py, j: IntArray, w: FloatArray, open_start: bool, open_end: bool):
        """(segment, t, squared distance) of the nearest point of the section at depth interval
        ``j``, weight ``w`` of every point (px, py): one pass per strike segment."""
        n_seg = self.points.shape[1] - 1
        best = np.full(px.shape, np.inf)
        seg = np.zeros(px.shape, dtype=np.int64)
        tt = np.zeros(px.shape)
        lower, step = self.points[:-1], np.diff(self.points, axis=0)  # per level interval
        ax, ay = (lower[j, 0, c] + w * step[j, 0, c] for c in (0, 1))
        for k in range(n_seg):  # vectorised over the points
            bx, by = (lower[j, k + 1, c] + w * step[j, k + 1, c] for c in (0, 1))
            dx, dy = bx - ax, by - ay
            rx, ry = px - ax, py - ay
            length2 = dx * dx + dy * dy
            t = np.clip(
                (rx * dx + ry * dy) / length2,
                -np.inf if (k == 0 and open_start) else 0.0,
                np.inf if (k == n_seg - 1 and open_end) else 1.0,
            )
            dist2 = (rx - t * dx) ** 2 + (ry - t * dy) ** 2
            better = dist2 < best
            np.copyto(best, dist2, where=better)
            np.copyto(seg, k, where=better)
            np.copyto(tt, t, where=better)
            ax, ay = bx, by
        return seg, tt, best

    def depth_at(self, x: ArrayLike, y: ArrayLike) -> FloatArray:
        """The depth (m) where the vertical line through every (x, y) meets the surface: the
        shallowest such depth, NaN where the line does not meet it (beside a vertical surface,
        or along it). Solves, per ruled patch, the quadratic in depth that puts the point on
        the section's segment: one pass over the points per patch (sticks - 1) x (levels - 1),
        so meant for a grid's columns rather than its cells. x, y broadcast together, m."""
        px, py = (np.asarray(v, dtype=np.float64) for v in np.broadcast_arrays(x, y))
        shape = px.shape
        px, py = px.ravel(), py.ravel()
        levels, pts = self.levels, self.points
        n_lev, n_seg = levels.size - 1, pts.shape[1] - 1
        depth = np.full(px.shape, np.inf)
        eps = 1e-12
        for j in range(n_lev):  # one pass per ruled patch, vectorised over the points
            w_lo = -np.inf if j == 0 else -eps
            w_hi = np.inf if j == n_lev - 1 else 1.0 + eps
            for i in range(n_seg):
                t_lo = -np.inf if i == 0 else -eps
                t_hi = np.inf if i == n_seg - 1 else 1.0 + eps
                a0, a1, b0, b1 = pts[j, i], pts[j + 1, i], pts[j, i + 1], pts[j + 1, i + 1]
                d0, da = b0 - a0, a1 - a0
                dd = (b1 - a1) - d0
                if np.abs(dd).max() <= _PARALLEL * np.abs(pts[j : j + 2, i : i + 2]).max():
                    dd = np.zeros(2)  # parallel sticks (a plane): round-off must not curve it
                rx, ry = px - a0[0], py - a0[1]
                # cross(D(w), p - A(w)) = qa w^2 + qb w + qc, D(w) = d0 + w dd, A(w) = a0 + w da
                qa = -_cross(dd, da)
                qb = dd[0] * ry - dd[1] * rx - _cross(d0, da)
                qc = d0[0] * ry - d0[1] * rx
                roots = _quadratic_roots(qa, qb, qc)
                if np.isinf(w_lo) or np.isinf(w_hi):
                    # A patch extended beyond the first or last level: its far root belongs to the
                    # extension's curvature, not to the surface given; keep the nearer.
                    off = [np.where(np.isnan(r), np.inf, np.abs(r - 0.5)) for r in roots]
                    roots = (np.where(off[0] <= off[1], roots[0], roots[1]),)
                for w in roots:
                    ax, ay = a0[0] + w * da[0], a0[1] + w * da[1]
                    dx, dy = d0[0] + w * dd[0], d0[1] + w * dd[1]
                    with np.errstate(invalid="ignore", divide="ignore"):
                        t = ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy)
                    ok = (w >= w_lo) & (w <= w_hi)
                    ok &= (t >= t_lo) & (t <= t_hi)
                    z = levels[j] + w * (levels[j + 1] - levels[j])
                    np.minimum(depth, np.where(ok, z, np.inf), out=depth)
        return np.where(np.isfinite(depth), depth, np.nan).reshape(shape)

    def on_horizon(self, depth_fn: DepthFunction, missing: str = "error") -> tuple[FloatArray, FloatArray]:
        """Where every stick meets a horizon: ``depth_fn(x, y)`` gives the horizon's depth (m)
        at arrays of points (NaN outside it). Returns (xy (n, 2), z (n,)), m.

        Secant steps from the stick's first level (exact in one step for a plane horizon and a
        straight stick); a stick they do not settle is searched for its shallowest crossing
        over the levels' depth range widened by four times its span both ways, then bisected.
        A stick that does not meet the horizon (it lies beyond the horizon's defined area, say)
        is, with ``missing="error"``, one :class:`~gridlib.errors.InputError` naming the fault
        and the stick; with ``missing="nearest"`` it takes the depth where the nearest stick
        (in order along strike) that meets the horizon does (the horizon carried on flat along
        the fault), an error only if none does."""
        if missing not in ("error", "nearest"):
            raise ValueError(f"missing must be 'error' or 'nearest', got {missing!r}")
        n = self.points.shape[1]
        sticks = np.arange(n)

        def gap(z: FloatArray) -> FloatArray:  # horizon depth minus z, at every stick's point at z
            j, w = _interval(self.levels, z)  # z (..., n): one depth per stick, any leading shape
            xy = _lerp(self.points[j, sticks], self.points[j + 1, sticks], w[..., None])
            depth = depth_fn(xy[..., 0].ravel(), xy[..., 1].ravel())
            return np.asarray(depth, dtype=np.float64).reshape(z.shape) - z

        z_prev = np.full(n, self.levels[0])
        g_prev = gap(z_prev)
        z = z_prev + np.where(np.isfinite(g_prev), g_prev, 0.0)
        g = gap(z)
        for _ in range(60):
            settled = (g == 0) | ~np.isfinite(g)
            if settled.all():
                break
            with np.errstate(invalid="ignore", divide="ignore"):
                secant = z - g * (z - z_prev) / (g - g_prev)
            z_new = np.where(settled, z, np.where(np.isfinite(secant), secant, z + g))
            moved = z_new != z
            if not moved.any():
                break
            z_prev, g_prev = np.where(moved, z, z_prev), np.where(moved, g, g_prev)
            z = z_new
            g = np.where(moved, gap(z), g)
        tolerance = 1e-9 * np.maximum(1.0, np.abs(z))
        missed = ~(np.abs(g) <= tolerance)
        if missed.any():
            z = np.where(missed, self._bisect_horizon(gap), z)
        lost = np.isnan(z)
        if lost.any() and (missing == "error" or lost.all()):
            label = _label(self.name, self.source)
            raise InputError(
                f"{label}: stick {int(np.flatnonzero(lost)[0]) + 1} does not meet the horizon (the "
                "horizon is undefined or too steep where the fault reaches it)"
            )
        if lost.any():
            met = np.flatnonzero(~lost)
            z = z[met[np.argmin(np.abs(sticks[:, None] - met[None, :]), axis=1)]]
        j, w = _interval(self.levels, z)
        return self._sticks_at(sticks, j, w), z

    def check_sections(self, z_top: float, z_base: float) -> None:
        """One :class:`~gridlib.errors.InputError` naming the fault and the sticks if at some
        depth between ``z_top`` and ``z_base`` (m; a model's range) two sticks coincide or
        cross, as :meth:`from_sticks` checks within the sticks' own depths (at every level in
        the range and at eight depths in each interval between). For a fault from a dip: its
        section at a depth is its trace moved by the mitred drifts, which a sharp bend of the
        trace folds within a short depth."""
        inner = self.levels[(self.levels > z_top) & (self.levels < z_base)]
        knots = np.unique(np.concatenate([[float(z_top), float(z_base)], inner]))
        fractions = np.linspace(0.0, 1.0, 9)[:-1]
        depths = np.append((knots[:-1, None] + np.diff(knots)[:, None] * fractions).ravel(), knots[-1])
        _check_sections(depths, self.section(depths), _label(self.name, self.source))

    def dip_side(self) -> str:
        """``'left'`` or ``'right'``: the side of the section (walked from the first stick to
        the last) that the surface dips towards, i.e. the hanging wall of a normal fault.
        An :class:`~gridlib.errors.InputError` if the surface is vertical."""
        label = _label(self.name, self.source)
        top, base = self.points[0], self.points[-1]
        drift = (base - top) / (self.levels[-1] - self.levels[0])
        strike = np.diff(top, axis=0)
        mean_drift = 0.5 * (drift[:-1] + drift[1:])
        towards_left = float(np.sum(strike[:, 0] * mean_drift[:, 1] - strike[:, 1] * mean_drift[:, 0]))
        if self.is_vertical:
            raise InputError(f"{label}: the fault is vertical, it dips to neither side: give its side")
        if towards_left == 0:
            raise InputError(f"{label}: the fault dips along its strike, to neither side: give its side")
        return "left" if towards_left > 0 else "right"

    def _sticks_at(self, stick: IntArray, j: IntArray, w: FloatArray) -> FloatArray:
        """(N, 2): stick ``stick[p]`` at the depth given by interval ``j[p]`` and weight ``w[p]``."""
        return _lerp(self.points[j, stick], self.points[j + 1, stick], w[:, None])

    def _bisect_horizon(self, gap: Callable[[FloatArray], FloatArray]) -> FloatArray:
        """The shallowest depth where every stick crosses the horizon, by a scan and bisection
        (NaN for a stick that does not cross it within the scan)."""
        span = self.levels[-1] - self.levels[0]
        n = self.points.shape[1]
        scan = np.linspace(self.levels[0] - 4.0 * span, self.levels[-1] + 4.0 * span, 513)
        values = gap(np.repeat(scan[:, None], n, axis=1))  # (513, n), in one call of depth_fn
        with np.errstate(invalid="ignore"):
            product = values[:-1] * values[1:]
        sign_change = (product <= 0) & np.isfinite(product)
        found = sign_change.any(axis=0)
        first = np.argmax(sign_change, axis=0)
        lo, hi = scan[first], scan[first + 1]
        g_lo = values[first, np.arange(n)]
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            g_mid = gap(mid)
            same = np.sign(g_mid) == np.sign(g_lo)
            lo, g_lo = np.where(same, mid, lo), np.where(same, g_mid, g_lo)
            hi = np.where(same, hi, mid)
        return np.where(found, 0.5 * (lo + hi), np.nan)


def _label(name: str | None, source: str | None) -> str:
    """How errors name a fault surface."""
    if name is not None and source is not None:
        return f"fault '{name}' (sticks file {source})"
    if source is not None:
        return f"fault sticks file {source}"
    return "fault surface" if name is None else f"fault '{name}'"


def _per_vertex(value: ArrayLike, n: int, what: str) -> FloatArray:
    """A number or one finite value per trace vertex, as an (n,) array."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{what}: expected a number or {n} numbers ({exc})") from exc
    if arr.ndim > 1 or (arr.ndim == 1 and arr.size != n):
        raise InputError(f"{what}: expected a number or one per trace vertex ({n}), got shape {arr.shape}")
    arr = np.broadcast_to(arr, (n,)).copy()
    if not np.isfinite(arr).all():
        raise InputError(
            f"{what}: not finite at trace vertex {int(np.flatnonzero(~np.isfinite(arr))[0]) + 1}"
        )
    return arr


def _vertex_drift(along: FloatArray, normal: FloatArray, slope: FloatArray, cot: FloatArray) -> FloatArray:
    """(n, 2) horizontal drift (m per m of depth) of the stick under every trace vertex.

    Segment s of the trace (unit direction ``along[s]``, unit normal towards the dip
    ``normal[s]``, top depth rising ``slope[s]`` m per m along it) spans, with dip cot c at a
    vertex, the plane whose drift h satisfies ``(slope * c * along + normal) . h = c``. End
    vertices take ``c * normal``; an interior vertex the line where its two planes meet (the
    same when the two segments are collinear)."""
    n = along.shape[0] + 1
    drift = np.empty((n, 2))
    drift[0] = cot[0] * normal[0]
    drift[-1] = cot[-1] * normal[-1]
    if n > 2:
        c = cot[1:-1]
        row_a = (slope[:-1] * c)[:, None] * along[:-1] + normal[:-1]
        row_b = (slope[1:] * c)[:, None] * along[1:] + normal[1:]
        det = _cross(row_a.T, row_b.T)
        scale = np.hypot(*row_a.T) * np.hypot(*row_b.T)
        collinear = np.abs(det) <= 1e-12 * scale
        safe = np.where(collinear, 1.0, det)
        meet = (c / safe)[:, None] * np.stack([row_b[:, 1] - row_a[:, 1], row_a[:, 0] - row_b[:, 0]], axis=1)
        drift[1:-1] = np.where(collinear[:, None], c[:, None] * normal[:-1], meet)
    return drift


def _cross(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """The z component of the cross product of 2-D vectors given as (x, y) pairs."""
    return a[0] * b[1] - a[1] * b[0]


def _stick_array(stick: ArrayLike, number: int, label: str) -> FloatArray:
    """One stick as a checked (k >= 2, 3) array."""
    what = f"{label}: stick {number}"
    try:
        arr = np.asarray(stick, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{what}: expected a (k >= 2, 3) array of x, y, z ({exc})") from exc
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise InputError(f"{what}: expected a (k >= 2, 3) array of x, y, z, got shape {arr.shape}")
    if arr.shape[0] < 2:
        raise InputError(f"{what} has {arr.shape[0]} point(s); a stick needs at least 2")
    finite = np.isfinite(arr).all(axis=1)
    if not finite.all():
        raise InputError(f"{what}, point {int(np.flatnonzero(~finite)[0]) + 1}: not finite")
    rising = np.diff(arr[:, 2]) <= 0
    if rising.any():
        p = int(np.flatnonzero(rising)[0])
        raise InputError(
            f"{what}: depth must increase strictly down a stick (z is depth, overturned faults are "
            f"not supported), but point {p + 2} (z={arr[p + 1, 2]:g}) is not below point {p + 1} "
            f"(z={arr[p, 2]:g})"
        )
    return arr


def _interval(levels: FloatArray, z: np.ndarray) -> tuple[IntArray, FloatArray]:
    """The level interval of every depth (the end ones extended) and the weight of its lower
    end's successor: z = (1 - w) * levels[j] + w * levels[j + 1]."""
    j = np.clip(np.searchsorted(levels, z, side="right") - 1, 0, levels.size - 2)
    return j, (z - levels[j]) / (levels[j + 1] - levels[j])


def _sections(levels: FloatArray, points: FloatArray, z: np.ndarray) -> FloatArray:
    """Every stick at depth ``z`` (...,) -> (..., n, 2); exact at the levels."""
    j, w = _interval(levels, z)
    return _lerp(points[j], points[j + 1], w[..., None, None])


def _resample(stick: FloatArray, levels: FloatArray) -> FloatArray:
    """A stick's x, y at every level (m, 2): linear between its points, its end intervals
    extended beyond them; exact at its own points."""
    z = stick[:, 2]
    j = np.clip(np.searchsorted(z, levels, side="right") - 1, 0, z.size - 2)
    w = ((levels - z[j]) / (z[j + 1] - z[j]))[:, None]
    return _lerp(stick[j, :2], stick[j + 1, :2], w)


def _lerp(lower: FloatArray, upper: FloatArray, w: FloatArray) -> FloatArray:
    """``lower + w * (upper - lower)``, exactly ``lower`` at w = 0 and ``upper`` at w = 1, and
    exactly their value where the two are equal (a vertical stick stays where it is)."""
    return np.where(w == 1.0, upper, lower + w * (upper - lower))


def _check_sections(depths: FloatArray, sections: FloatArray, label: str) -> None:
    """The horizontal sections (K, n, 2) at increasing ``depths`` must be simple polylines and
    no two consecutive sticks may swap order between consecutive depths."""
    strike = np.diff(sections, axis=1)  # (K, n - 1, 2)
    length = np.hypot(strike[..., 0], strike[..., 1])
    extent = float(np.ptp(sections.reshape(-1, 2), axis=0).max())
    k, s = np.unravel_index(np.argmax(length <= _COINCIDENT * extent), length.shape)
    if length[k, s] <= _COINCIDENT * extent:
        raise InputError(f"{label}: sticks {s + 1} and {s + 2} coincide at depth {depths[k]:g} m")
    flipped = np.sum(strike[:-1] * strike[1:], axis=-1) <= 0
    if flipped.any():
        k, s = np.unravel_index(np.argmax(flipped), flipped.shape)
        raise InputError(
            f"{label}: sticks {s + 1} and {s + 2} cross (they swap order along strike between depths "
            f"{depths[k]:g} and {depths[k + 1]:g} m)"
        )
    turn = _cross(np.moveaxis(strike[:, :-1], -1, 0), np.moveaxis(strike[:, 1:], -1, 0))
    folded = (np.abs(turn) <= _COINCIDENT * length[:, :-1] * length[:, 1:]) & (
        np.sum(strike[:, :-1] * strike[:, 1:], axis=-1) < 0
    )
    if folded.any():
        k, s = np.unravel_index(np.argmax(folded), folded.shape)
        raise InputError(
            f"{label}: the surface folds back on itself at stick {s + 2} (sticks {s + 1} and "
            f"{s + 3} lie on the same side of it) at depth {depths[k]:g} m"
        )
    first, second = np.triu_indices(strike.shape[1], k=2)
    # Only pairs whose boxes (each segment's extent over every depth) overlap can meet.
    low = np.minimum(sections[:, :-1], sections[:, 1:]).min(axis=0)  # (n - 1, 2)
    high = np.maximum(sections[:, :-1], sections[:, 1:]).max(axis=0)
    near = np.all((low[first] <= high[second]) & (low[second] <= high[first]), axis=1)
    first, second = first[near], second[near]
    if first.size == 0:
        return
    step = max(1, _PAIR_BUDGET // first.size)
    for start in range(0, depths.size, step):  # depths in blocks: (depths x pairs) stays small
        block = sections[start : start + step]
        p, q = block[:, first], block[:, first + 1]  # (depths, pairs, 2)
        r, t = block[:, second], block[:, second + 1]
        crossing = _segments_meet(p, q, r, t)
        if crossing.any():
            k, pair = np.unravel_index(np.argmax(crossing), crossing.shape)
            a, b = int(first[pair]), int(second[pair])
            raise InputError(
                f"{label}: the surface between sticks {a + 1} and {a + 2} crosses the surface "
                f"between sticks {b + 1} and {b + 2} at depth {depths[start + k]:g} m"
            )


def _segments_meet(p: FloatArray, q: FloatArray, r: FloatArray, t: FloatArray) -> np.ndarray:
    """Whether segments p-q and r-t (arrays (..., 2)) touch or cross."""

    def orient(a, b, c):
        return np.sign(
            (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1])
            - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])
        )

    o1, o2, o3, o4 = orient(p, q, r), orient(p, q, t), orient(r, t, p), orient(r, t, q)
    proper = (o1 * o2 <= 0) & (o3 * o4 <= 0)
    # Collinear pairs meet only if their extents overlap.
    collinear = (o1 == 0) & (o2 == 0)
    lo = np.minimum(p, q)
    hi = np.maximum(p, q)
    overlap = np.all((np.maximum(r, t) >= lo) & (np.minimum(r, t) <= hi), axis=-1)
    return np.where(collinear, overlap, proper)


def _quadratic_roots(a: np.ndarray | float, b: FloatArray, c: FloatArray) -> tuple[FloatArray, FloatArray]:
    """The real roots of a w^2 + b w + c (elementwise; NaN where there is none), in the
    cancellation-free form: q = -(b + sign(b) sqrt(b^2 - 4ac)) / 2, roots q / a and c / q."""
    a = np.broadcast_to(np.asarray(a, dtype=np.float64), np.shape(b))
    with np.errstate(invalid="ignore", divide="ignore"):
        disc = b * b - 4.0 * a * c
        root = np.sqrt(np.where(disc >= 0, disc, np.nan))
        q = -0.5 * (b + np.copysign(root, b))
        first = np.where(a != 0, q / a, np.nan)
        second = np.where(q != 0, c / q, np.nan)
    return first, second
