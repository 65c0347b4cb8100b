"""Interpolation of scattered picks (linear, cubic, thin-plate RBF, nearest) per fault block,
with one extrapolation policy."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..arrays import point_array
from ..errors import InputError
from ..grid import FloatArray
from ._constants import EXTRAPOLATIONS, METHODS, RBF_GLOBAL_MAX, RBF_NEIGHBORS, check_choice
from .blocks import bounding_box, fault_blocks
from .rbf import thin_plate_spline


def interpolate_points(
    points: ArrayLike, x: ArrayLike, y: ArrayLike, *, name: str = "surface", **options: Any
) -> FloatArray:
    """Interpolate scattered picks ``(n, 3)`` = x, y, z (m, z depth) onto the lattice of axes
    ``x`` (nx,), ``y`` (ny,): the depth map ``z[j, i]`` (ny, nx), NaN where undefined.

    ``name`` and the keyword ``options`` are those of :func:`interpolate_points_at`.

    >>> from gridlib.horizons import plane
    >>> rng = np.random.default_rng(0)
    >>> xy = rng.uniform(0.0, 1000.0, (200, 2))
    >>> pts = np.column_stack([xy, plane(xy[:, 0], xy[:, 1], depth=1000.0, dip=5.0, azimuth=90.0)])
    >>> x, y = np.linspace(0.0, 1000.0, 11), np.linspace(0.0, 500.0, 6)
    >>> z = interpolate_points(pts, x, y, method="rbf", extrapolation="trend")
    >>> bool(np.abs(z - plane(*np.meshgrid(x, y), depth=1000.0, dip=5.0, azimuth=90.0)).max() < 1e-9)
    True
    """
    xa, ya = (np.asarray(a, dtype=np.float64) for a in (x, y))
    for key, a in (("x", xa), ("y", ya)):
        if a.ndim != 1 or a.size < 1 or not np.isfinite(a).all() or (np.diff(a) <= 0).any():
            raise InputError(f"{name}: the lattice axis {key} must be finite, 1-D and strictly increasing")
    X, Y = np.meshgrid(xa, ya)
    return interpolate_points_at(points, X, Y, name=name, **options)


def interpolate_points_at(
    points: ArrayLike,
    xq: ArrayLike,
    yq: ArrayLike,
    *,
    method: str = "linear",
    extrapolation: str = "nan",
    smoothing: float = 0.0,
    neighbors: int | None = None,
    faults: Sequence[Any] = (),
    extent: Sequence[float] | None = None,
    name: str = "surface",
    notes: list[str] | None = None,
) -> FloatArray:
    """Interpolate scattered picks ``(n, 3)`` = x, y, z (m, z depth) at the points ``(xq, yq)``
    (matching shapes); returns depths of that shape, NaN where undefined.

    ``method``: ``"linear"``, ``"cubic"``, ``"rbf"`` or ``"nearest"``;
    ``extrapolation``: ``"nan"``, ``"nearest"`` or ``"trend"`` (module docstring).
    ``smoothing`` (>= 0, ``rbf`` only): the RBF smoothing (as scipy's) on the
    non-dimensionalised coordinates; 0 interpolates. ``neighbors`` (``rbf``
    only): the number of nearest points of each local RBF; default: a global
    RBF up to 2000 points (per block), else 64 neighbours (the global solve is
    O(n^3)). ``faults``: traces (module docstring), each block interpolated
    from its own points; ``extent`` = (xmin, xmax, ymin, ymax), the area they
    cut into blocks (default: the bounding box of the points and the targets).
    ``name`` labels error messages; messages about blocks
    without data or traces that separate nothing are appended to ``notes``.

    A block with fewer than three non-collinear points gets no values (NaN);
    a result that is NaN everywhere is an :class:`~gridlib.errors.InputError`.
    """
    method = check_choice(method, METHODS, f"{name}: method")
    extrapolation = check_choice(extrapolation, EXTRAPOLATIONS, f"{name}: extrapolation")
    if isinstance(smoothing, bool) or not isinstance(smoothing, int | float) or not smoothing >= 0:
        raise InputError(f"{name}: smoothing must be a number >= 0, got {smoothing!r}")
    if smoothing and method != "rbf":
        raise InputError(f"{name}: smoothing applies to method 'rbf' only (method is {method!r})")
    if neighbors is not None:
        if method != "rbf":
            raise InputError(f"{name}: neighbors applies to method 'rbf' only (method is {method!r})")
        if isinstance(neighbors, bool) or not isinstance(neighbors, int | np.integer) or neighbors < 3:
            raise InputError(f"{name}: neighbors must be an integer >= 3, got {neighbors!r}")
    pts = point_array(points, 3, f"{name}: points", point="pick")
    xq, yq = np.broadcast_arrays(np.asarray(xq, dtype=np.float64), np.asarray(yq, dtype=np.float64))
    if not (np.isfinite(xq).all() and np.isfinite(yq).all()):
        raise InputError(f"{name}: the target points must be finite")
    notes = [] if notes is None else notes
    qx, qy = xq.ravel(), yq.ravel()
    out = np.full(qx.size, np.nan)

    # Non-dimensional coordinates: shift to the points' mean, scale by the larger side of their box.
    centre = pts[:, :2].mean(axis=0)
    scale = float(np.ptp(pts[:, :2], axis=0).max()) or 1.0
    P = (pts[:, :2] - centre) / scale
    Q = (np.column_stack([qx, qy]) - centre) / scale

    if faults is None or len(faults) == 0:
        groups = [(np.arange(pts.shape[0]), np.arange(qx.size), f"{name}")]
    else:
        if extent is None:
            extent = bounding_box(pts[:, 0], pts[:, 1], qx, qy)
        blocks = fault_blocks(faults, extent)
        notes.extend(f"{name}: {n}" for n in blocks.notes)
        p_block = blocks.classify(pts[:, 0], pts[:, 1], pts[:, 2], on_trace="none")
        q_block = blocks.classify(qx, qy, on_trace="lowest")
        dropped = int((p_block < 0).sum())
        if dropped:
            notes.append(f"{name}: {dropped} points lie on a fault trace and were not used")
        groups = [
            (np.flatnonzero(p_block == b), np.flatnonzero(q_block == b), f"{name}: fault block {b}")
            for b in range(blocks.num)
        ]
    for p_idx, q_idx, label in groups:
        if q_idx.size == 0:
            continue
        out[q_idx] = _interpolate_group(
            P[p_idx],
            pts[p_idx, 2],
            Q[q_idx],
            method,
            extrapolation,
            float(smoothing),
            neighbors,
            label,
            notes,
        )
    if np.isnan(out).all():
        raise InputError(
            f"{name}: the interpolated surface is undefined (NaN) everywhere: the points do not cover the "
            f"targets (extrapolation={extrapolation!r}) or no block has three non-collinear points"
        )
    return out.reshape(xq.shape)


def _interpolate_group(
    P: FloatArray,
    z: FloatArray,
    Q: FloatArray,
    method: str,
    extrapolation: str,
    smoothing: float,
    neighbors: int | None,
    label: str,
    notes: list[str],
) -> FloatArray:
    """One block: points P (m, 2) with depths z at targets Q (q, 2), all non-dimensional."""
    from scipy.interpolate import (
        CloughTocher2DInterpolator,
        LinearNDInterpolator,
        NearestNDInterpolator,
    )
    from scipy.spatial import ConvexHull, QhullError

    out = np.full(Q.shape[0], np.nan)
    if P.shape[0] < 3:
        notes.append(f"{label}: {P.shape[0]} points (needs 3 non-collinear); its targets are undefined")
        return out
    try:
        tri = _delaunay(P)
        hull = ConvexHull(P)
    except QhullError:
        notes.append(f"{label}: its {P.shape[0]} points are collinear; its targets are undefined")
        return out
    if method == "linear":
        f = LinearNDInterpolator(tri, z)
    elif method == "cubic":
        f = CloughTocher2DInterpolator(tri, z)
    elif method == "nearest":
        f = NearestNDInterpolator(P, z)
    else:
        n = P.shape[0]
        k = neighbors if neighbors is not None else (None if n <= RBF_GLOBAL_MAX else RBF_NEIGHBORS)
        if k is not None and k >= n:
            k = None
        if smoothing == 0 and np.unique(P, axis=0).shape[0] < n:
            counts = np.unique(P, axis=0, return_counts=True)[1]
            raise InputError(
                f"{label}: method 'rbf' with smoothing 0 needs distinct (x, y); {int((counts > 1).sum())} "
                "locations have several points (use smoothing > 0, or another method)"
            )
        try:
            f = thin_plate_spline(P, z, smoothing=smoothing, neighbors=k)
        except np.linalg.LinAlgError as exc:
            raise InputError(f"{label}: the RBF system is singular ({exc}); use smoothing > 0") from exc
    inside = tri.find_simplex(Q) >= 0
    if inside.any():
        out[inside] = f(Q[inside])
    outside = np.flatnonzero(~inside)
    if outside.size == 0 or extrapolation == "nan":
        return out
    import shapely

    ring = shapely.LinearRing(P[hull.vertices])
    lines = shapely.shortest_line(ring, shapely.points(Q[outside]))
    q = shapely.get_coordinates(lines)[0::2]  # the end on the hull
    fq = f(q)
    miss = np.isnan(fq)  # outside by round-off: retry just inside, then take the nearest point
    if miss.any():
        q[miss] += 1e-9 * (P[hull.vertices].mean(axis=0) - q[miss])
        fq[miss] = f(q[miss])
        miss = np.isnan(fq)
        if miss.any():
            fq[miss] = NearestNDInterpolator(P, z)(q[miss])
    if extrapolation == "trend":
        gx, gy = _trend_gradient(P, z)
        d = Q[outside] - q
        fq = fq + (d[:, 0] * gx + d[:, 1] * gy)
    out[outside] = fq
    return out


def _trend_gradient(P: np.ndarray, z: np.ndarray) -> tuple[float, float]:
    """The slopes (dz/dx, dz/dy) of the least-squares plane through the points (x, y, z).

    Normal equations of the centred points, solved by Cramer's rule: fixed-order sums,
    no LAPACK, so the trend is the same bits on every machine. A degenerate set (all
    points on a line) has no plane: slopes 0.
    """
    d = P - P.mean(axis=0)
    dz = z - z.mean()
    sxx, syy, sxy = (
        float((d[:, 0] * d[:, 0]).sum()),
        float((d[:, 1] * d[:, 1]).sum()),
        float((d[:, 0] * d[:, 1]).sum()),
    )
    sxz, syz = float((d[:, 0] * dz).sum()), float((d[:, 1] * dz).sum())
    det = sxx * syy - sxy * sxy
    if not det > 1e-12 * max(sxx * syy, np.finfo(float).tiny):
        return 0.0, 0.0
    return (sxz * syy - syz * sxy) / det, (syz * sxx - sxz * sxy) / det


def _delaunay(P: np.ndarray) -> Any:
    """scipy's Delaunay triangulation of P (m, 2) with its barycentric transforms computed here.

    scipy computes them lazily with LAPACK, whose kernels round differently on different
    CPUs; its linear and Clough-Tocher interpolators and ``find_simplex`` use them. Here
    each triangle's 2 x 2 inverse is the explicit adjugate over the determinant, and a
    triangle whose 1-norm condition number exceeds 1 / (1000 eps) gets NaN, as in scipy.
    """
    from scipy.spatial import Delaunay

    tri = Delaunay(P)
    v = P[tri.simplices]  # (t, 3, 2)
    r = v[:, 2]
    a, b = v[:, 0, 0] - r[:, 0], v[:, 1, 0] - r[:, 0]  # T = [[a, b], [c, d]]: columns v_k - r
    c, d = v[:, 0, 1] - r[:, 1], v[:, 1, 1] - r[:, 1]
    det = a * d - b * c
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.stack([np.stack([d, -b], axis=-1), np.stack([-c, a], axis=-1)], axis=1) / det[:, None, None]
        norm = np.maximum(np.abs(a) + np.abs(c), np.abs(b) + np.abs(d))
        norm_inv = np.abs(inv).sum(axis=1).max(axis=1)
        singular = ~(norm * norm_inv <= 1.0 / (1000.0 * np.finfo(np.float64).eps))
    transform = np.empty((tri.nsimplex, 3, 2))
    transform[:, :2] = inv
    transform[:, 2] = r
    transform[singular] = np.nan
    tri._transform = transform  # scipy's cache of Delaunay.transform
    if tri.transform is not transform:  # pragma: no cover - scipy changed its internals
        raise RuntimeError("scipy.spatial.Delaunay no longer caches its transform in _transform")
    return tri
