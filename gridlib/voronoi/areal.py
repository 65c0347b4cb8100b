"""The areal path of a well trajectory inside the reservoir: what a PEBI grid refines along.

A trajectory is a 3-D polyline (x east, y north, z depth positive down, in the case's
length unit). The reservoir at the path lies between the top and the base horizon; the
parts of the path between them are found segment by segment, taking depth minus top and
base minus depth as linear along each segment (their signs at the path's points decide,
their zeros between the points are the crossings), and projected to plan view. Every
part becomes one polyline of :class:`~gridlib.voronoi.wells.Well`'s ``path``, or a point
where it is (nearly) vertical: a vertical part projects to one point, which gets one cell
(a site with its six side sites). Consecutive points that project onto each other (a
vertical stretch followed by a deviated one) are made one, and vertices within
``tolerance`` of the line through their neighbours are dropped (Douglas-Peucker), so a
straight horizontal stretch given by many survey points becomes one segment with sites at
equal steps: the stretch whose cells have their centroids on the path.

>>> import numpy as np
>>> xyz = np.array([[0.0, 0.0, 900.0], [0.0, 0.0, 1000.0], [50.0, 0.0, 1010.0], [300.0, 0.0, 1010.0]])
>>> [p.tolist() for p in areal_path(xyz, 1005.0, 1100.0)]
[[[25.0, 0.0], [300.0, 0.0]]]
>>> [p.tolist() for p in areal_path(xyz[:2], 950.0, 1100.0)]  # vertical: a point
[[[0.0, 0.0]]]
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import shapely
from numpy.typing import ArrayLike

from ..connectivity import ragged_arange
from ..errors import GridError

Depth = ArrayLike | Callable[[np.ndarray, np.ndarray], ArrayLike]


def areal_path(
    xyz: ArrayLike, top_depth: Depth, base_depth: Depth, *, tolerance: float = 0.0
) -> list[np.ndarray]:
    """The areal polylines ((k, 2) each, k = 1 a point) of the parts of ``xyz`` in the reservoir.

    ``xyz`` (n, 2 <= n): the trajectory's points (z depth, positive down), in measured-depth
    order. ``top_depth``, ``base_depth``: the depths of the reservoir's top and base at the
    points, as arrays (n,), scalars, or callables ``f(x, y) -> depths`` evaluated at the
    points; a point is inside where top <= z <= base. ``tolerance`` (length unit): vertices
    closer than this to the simplified polyline are dropped, and a part whose areal extent
    (the diagonal of its bounding box) is at most this becomes a point (the areal position
    half way along its 3-D length). Rounding-level noise (1e-9 of the path's extent) is
    always removed. Parts in path order; none if the path misses the reservoir. Touching a
    horizon at a single point is no part.
    """
    xyz = np.asarray(xyz, dtype=np.float64)
    if xyz.ndim != 2 or xyz.shape[1] != 3 or xyz.shape[0] < 2 or not np.isfinite(xyz).all():
        raise GridError(f"areal_path: xyz must be finite points (n, 3) with n >= 2, got shape {xyz.shape}")
    if not (np.isfinite(tolerance) and tolerance >= 0):
        raise GridError(f"areal_path: tolerance must be a length >= 0, got {tolerance!r}")
    top = _depths(top_depth, xyz, "top_depth")
    base = _depths(base_depth, xyz, "base_depth")
    lo, hi, used, inside = clip_segments(xyz[:, 2] - top, base - xyz[:, 2])
    seg = np.flatnonzero(used)
    if seg.size == 0:
        return []
    start = np.ones(seg.size, dtype=bool)  # a part goes on through an inside point
    start[1:] = ~((seg[1:] == seg[:-1] + 1) & inside[seg[1:]])
    d = xyz[seg + 1] - xyz[seg]
    count = 1 + start  # the first segment of a part gives its entry point too
    i = np.repeat(np.arange(seg.size), count)
    entry = start[i] & (ragged_arange(np.zeros(seg.size), count) == 0)
    t = np.where(entry, lo[seg][i], hi[seg][i])
    pts = xyz[seg][i] + t[:, None] * d[i]
    part = (np.cumsum(start) - 1)[i]
    extent = float(np.max(np.ptp(xyz, axis=0)))
    eps = 1e-9 * extent
    bounds = np.flatnonzero(np.diff(np.concatenate([[-1], part, [part[-1] + 1]])))
    out = []
    for k in range(bounds.size - 1):  # loop over the parts of one trajectory (a few)
        piece = _areal(pts[bounds[k] : bounds[k + 1]], max(tolerance, eps), eps)
        if piece is not None:
            out.append(piece)
    return out


def _depths(depth: Depth, xyz: np.ndarray, what: str) -> np.ndarray:
    """Depths (n,) at the points from an array, a scalar or a callable f(x, y)."""
    try:
        value = depth(xyz[:, 0], xyz[:, 1]) if callable(depth) else depth
        out = np.broadcast_to(np.asarray(value, dtype=np.float64), (xyz.shape[0],)).copy()
    except (TypeError, ValueError) as exc:
        raise GridError(f"areal_path: {what} must give one depth per point of the path ({exc})") from exc
    bad = ~np.isfinite(out)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise GridError(
            f"areal_path: {what} is not finite at point {k} ({xyz[k, 0]:.6g}, {xyz[k, 1]:.6g}) of the path"
        )
    return out


def clip_segments(
    below_top: np.ndarray, above_base: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The parts of a polyline's segments between two depths: given at its n points the depth
    below the top (``z - top``) and above the base (``base - z``), each linear along a segment,
    per segment the parameter interval [lo, hi] (0..1) where both are >= 0 ((n - 1,) each,
    exactly 0 and 1 at the points inside), which segments have one (lo < hi: a segment that
    only touches a horizon has none), and which points are inside (n,)."""
    inside = (below_top >= 0) & (above_base >= 0)
    m = below_top.size - 1
    lo, hi = np.zeros(m), np.ones(m)
    used = np.ones(m, dtype=bool)
    for f in (below_top, above_base):
        f0, df = f[:-1], np.diff(f)
        with np.errstate(divide="ignore", invalid="ignore"):
            root = np.where(df != 0, -f0 / np.where(df != 0, df, 1.0), 0.0)
        lo = np.where(df > 0, np.maximum(lo, root), lo)
        hi = np.where(df < 0, np.minimum(hi, root), hi)
        used &= ~((df == 0) & (f0 < 0))
    lo = np.where(inside[:-1], 0.0, np.clip(lo, 0.0, 1.0))  # exact ends at inside points
    hi = np.where(inside[1:], 1.0, np.clip(hi, 0.0, 1.0))
    used &= lo < hi
    return lo, hi, used, inside


def _areal(xyz: np.ndarray, tolerance: float, eps: float) -> np.ndarray | None:
    """One part in plan view: a simplified polyline, or a point when its areal extent is at
    most ``tolerance``; None when its 3-D length is at most ``eps``."""
    length = np.linalg.norm(np.diff(xyz, axis=0), axis=1)
    total = float(length.sum())
    if total <= eps:
        return None
    xy = xyz[:, :2]
    if float(np.hypot(*np.ptp(xy, axis=0))) <= tolerance:
        along = np.concatenate([[0.0], np.cumsum(length)])
        k = min(int(np.searchsorted(along, 0.5 * total, side="right")), xy.shape[0] - 1)
        t = (0.5 * total - along[k - 1]) / length[k - 1] if length[k - 1] > 0 else 0.0
        return (xy[k - 1] + t * (xy[k] - xy[k - 1]))[None, :]
    keep = np.concatenate([[True], np.hypot(*np.diff(xy, axis=0).T) > eps])
    if np.count_nonzero(keep) < 2:
        return xy[:1].copy()
    line = shapely.simplify(shapely.LineString(xy[keep]), tolerance, preserve_topology=False)
    return shapely.get_coordinates(line)
