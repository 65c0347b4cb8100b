"""Thin-plate spline interpolation of scattered picks, the same bits on every machine.

The interpolant of scipy's ``RBFInterpolator(kernel="thin_plate_spline", degree=1)``:

    f(x) = sum_j w_j phi(|x - p_j|) + c_0 + c_1 x + c_2 y,   phi(r) = r**2 log r,

with (K + s I) w + P c = z and P^t w = 0 (K_ij = phi(|p_i - p_j|), P the rows
(1, x_j, y_j) in coordinates centred and scaled on the picks, s the ``smoothing``).
Globally (every pick in one system), or locally (``neighbors``): the value at x is
that of the spline through the ``neighbors`` picks nearest to x, as scipy does. The
systems are solved by :func:`gridlib.reproducible.solve` and the sums run in a fixed
order, so the surface does not depend on BLAS, LAPACK, the CPU or the thread count
(scipy's solve and products do).

>>> import numpy as np
>>> p = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [0.5, 0.3]])
>>> f = thin_plate_spline(p, 2.0 + 3.0 * p[:, 0] - p[:, 1])  # a plane is reproduced
>>> np.round(f(np.array([[0.25, 0.75], [2.0, 2.0]])), 12).tolist()
[2.0, 6.0]
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.spatial import cKDTree

from ..reproducible import log, solve

EVAL_ENTRIES = 1 << 21  # kernel entries per evaluation block (16 MiB)
SYSTEM_ENTRIES = 1 << 22  # matrix entries per batch of local systems (32 MiB)


def _phi(r2: np.ndarray) -> np.ndarray:
    """r**2 log r from r**2 (0 at r = 0)."""
    safe = np.where(r2 > 0.0, r2, 1.0)
    return 0.5 * r2 * log(safe)


def _frame(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centre and half-range of points (..., m, 2) along m (half-range 1 where flat)."""
    lo, hi = points.min(axis=-2), points.max(axis=-2)
    half = (hi - lo) / 2.0
    return (hi + lo) / 2.0, np.where(half > 0.0, half, 1.0)


def _squared_distances(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """|a_i - b_j|**2 for a (..., m, 2) and b (..., n, 2): (..., m, n)."""
    dx = a[..., :, None, 0] - b[..., None, :, 0]
    dy = a[..., :, None, 1] - b[..., None, :, 1]
    return dx * dx + dy * dy


def _systems(points: np.ndarray, values: np.ndarray, smoothing: np.ndarray):
    """The coefficients (w, c, centre, half) of the splines through each set of points (..., m, 2)."""
    m = points.shape[-2]
    centre, half = _frame(points)
    scaled = (points - centre[..., None, :]) / half[..., None, :]
    lhs = np.zeros((*points.shape[:-2], m + 3, m + 3))
    lhs[..., :m, :m] = _phi(_squared_distances(points, points))
    idx = np.arange(m)
    lhs[..., idx, idx] += smoothing
    lhs[..., :m, m] = 1.0
    lhs[..., :m, m + 1 :] = scaled
    lhs[..., m, :m] = 1.0
    lhs[..., m + 1 :, :m] = np.swapaxes(scaled, -1, -2)
    rhs = np.zeros((*points.shape[:-2], m + 3))
    rhs[..., :m] = values
    coef = solve(lhs, rhs)
    return coef[..., :m], coef[..., m:], centre, half


def _evaluate(x: np.ndarray, points: np.ndarray, w: np.ndarray, c: np.ndarray, centre, half) -> np.ndarray:
    """Spline values at x (..., 2) for splines of points (..., m, 2) (broadcast over ...)."""
    d2 = _squared_distances(x[..., None, :], points)[..., 0, :]  # (..., m)
    s = (x - centre) / half
    poly = c[..., 0] + (c[..., 1] * s[..., 0] + c[..., 2] * s[..., 1])
    return (w * _phi(d2)).sum(axis=-1) + poly


def thin_plate_spline(
    points: np.ndarray, values: np.ndarray, *, smoothing: float = 0.0, neighbors: int | None = None
) -> Callable[[np.ndarray], np.ndarray]:
    """The thin-plate spline (with a linear trend) through ``values`` at ``points`` (n, 2),
    as a function of query points (q, 2). ``smoothing`` >= 0 on the kernel diagonal (0
    interpolates); ``neighbors``: use only that many nearest picks per query point (None:
    all). Raises ``np.linalg.LinAlgError`` if a system is singular (coincident picks
    without smoothing).
    """
    P = np.ascontiguousarray(points, dtype=np.float64)
    z = np.asarray(values, dtype=np.float64)
    n = P.shape[0]
    if neighbors is None or neighbors >= n:
        w, c, centre, half = _systems(P, z, np.full(n, float(smoothing)))

        def global_spline(q: np.ndarray) -> np.ndarray:
            q = np.asarray(q, dtype=np.float64).reshape(-1, 2)
            out = np.empty(q.shape[0])
            step = max(1, EVAL_ENTRIES // max(n, 1))
            for s in range(0, q.shape[0], step):
                out[s : s + step] = _evaluate(q[s : s + step], P[None], w, c, centre, half)
            return out

        return global_spline

    k = int(neighbors)
    tree = cKDTree(P)

    def local_spline(q: np.ndarray) -> np.ndarray:
        q = np.asarray(q, dtype=np.float64).reshape(-1, 2)
        if q.shape[0] == 0:
            return np.zeros(0)
        _, idx = tree.query(q, k)
        idx = np.sort(idx.reshape(q.shape[0], k), axis=1)
        sets, which = np.unique(idx, axis=0, return_inverse=True)
        which = which.ravel()
        out = np.empty(q.shape[0])
        order = np.argsort(which, kind="stable")
        bounds = np.searchsorted(which[order], np.arange(sets.shape[0] + 1))
        batch = max(1, SYSTEM_ENTRIES // (k + 3) ** 2)
        for s in range(0, sets.shape[0], batch):
            chunk = sets[s : s + batch]
            w, c, centre, half = _systems(P[chunk], z[chunk], np.full(k, float(smoothing)))
            targets = order[bounds[s] : bounds[s + chunk.shape[0]]]
            local = which[targets] - s
            pts = P[chunk][local]
            out[targets] = _evaluate(q[targets], pts, w[local], c[local], centre[local], half[local])
        return out

    return local_spline
