"""Seeded stationary Gaussian random fields (gstools' randomisation method), summed fast in
depositional coordinates by factorising the modes into column and layer terms."""

from __future__ import annotations

import functools
import math
import numbers
import threading
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..grid import FloatArray
from ..reproducible import RightFactor, matmul
from ..threads import num_threads
from .depositional import Depositional
from .numbers import finite_number
from .variogram import Variogram

__all__ = ["gaussian_field"]

_CHUNK = 2048  # columns per block of the factorised summation on a lattice (_CHUNK // 32 x values)
# Columns per block of the factorised summation elsewhere: (128, 2 modes) temporaries stay in the
# CPU's caches, and the exact products (gridlib.reproducible.matmul) of such a block cost a third
# of those of 2048 columns, per column; a row's bits do not depend on the block it is in.
_COLUMNS = 128
_MAX_THREADS = 8  # blocks are summed by at most this many threads (each block alone: same result)


def gaussian_field(
    where: Depositional | ArrayLike,
    variogram: Variogram,
    *,
    seed: int,
    mean: float = 0.0,
    mode_no: int = 1000,
) -> FloatArray:
    """A Gaussian random field with ``variogram`` and ``mean`` at ``where``, seeded.

    ``where``: :class:`Depositional` coordinates (the fast factorised sum,
    module docstring) or points (n, d), d = 1..3 (m; gstools' own sum, cost
    proportional to n x mode_no). ``seed``: an integer; the same seed,
    variogram and positions give identical values. ``mode_no``: gstools'
    number of randomisation modes (accuracy against speed; default 1000).

    >>> v = Variogram("gaussian", var=4.0, len_scale=50.0)
    >>> points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [500.0, 0.0, 0.0]])  # m
    >>> f = gaussian_field(points, v, seed=1, mean=10.0)
    >>> f.shape, bool(abs(f[0] - f[1]) < 0.2)
    ((3,), True)
    """
    import gstools as gs

    if not isinstance(variogram, Variogram):
        raise InputError(f"variogram: expected a Variogram, got {type(variogram).__name__}")
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral):
        raise InputError(f"seed: expected an integer, got {seed!r}")
    if isinstance(mode_no, bool) or not isinstance(mode_no, numbers.Integral) or mode_no < 1:
        raise InputError(f"mode_no: expected a positive integer, got {mode_no!r}")
    mean = finite_number(mean, "mean")
    if isinstance(where, Depositional):
        modes = _modes(variogram, int(mode_no), int(seed))
        if where.num_cells == 0:
            return np.zeros(0)
        values = None if modes is None else _factorised(modes, where)
        if values is None:  # gstools changed its internals: sum the plain way
            srf = gs.SRF(variogram.covmodel(3), mode_no=int(mode_no), seed=int(seed))
            values = srf(where.points.T, mesh_type="unstructured")
        return mean + np.asarray(values, dtype=np.float64)
    try:
        pts = np.asarray(where, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(
            f"gaussian_field: positions must be Depositional or an (n, d) array ({exc})"
        ) from exc
    if pts.ndim == 1:
        pts = pts[:, None]
    if pts.ndim != 2 or not 1 <= pts.shape[1] <= 3:
        raise InputError(
            f"gaussian_field: positions must be an (n, d) array, d = 1..3, got shape {pts.shape}"
        )
    if not np.isfinite(pts).all():
        raise InputError("gaussian_field: positions must be finite")
    model = variogram.covmodel(pts.shape[1])
    srf = gs.SRF(model, mode_no=int(mode_no), seed=int(seed))
    if pts.shape[0] == 0:
        return np.zeros(0)
    return mean + np.asarray(srf(pts.T, mesh_type="unstructured"), dtype=np.float64)


@dataclass(frozen=True, eq=False)
class _Modes:
    """gstools' randomisation modes of a 3-D field: its covariance model, the wave vectors
    ``k`` (3, modes) and the normal weights ``z1``, ``z2`` (modes,), read-only."""

    model: Any
    k: FloatArray
    z1: FloatArray
    z2: FloatArray


@functools.lru_cache(maxsize=32)
def _modes(variogram: Variogram, mode_no: int, seed: int) -> _Modes | None:
    """The modes of gstools' 3-D field of ``variogram`` for ``seed`` (None where gstools keeps
    them elsewhere, or for a model with a nugget). Kept for the next field of the same
    variogram and seed (a study's variants share a few seeds): gstools draws the wave vectors
    of most models by Markov-chain sampling, 0.1 s for 1000 modes, more than the sum itself."""
    import gstools as gs

    model = variogram.covmodel(3)
    gen = gs.SRF(model, mode_no=mode_no, seed=seed).generator
    try:
        k, z1, z2 = gen._cov_sample, gen._z_1, gen._z_2  # gstools.field.generator.RandMeth's modes
        n_modes = gen.mode_no
    except AttributeError:
        return None
    if getattr(model, "nugget", 0.0) or k is None or np.shape(k) != (3, n_modes):
        return None
    arrays = [np.array(a, dtype=np.float64) for a in (k, z1, z2)]
    for a in arrays:
        a.flags.writeable = False
    return _Modes(model, *arrays)


def _factorised(modes: _Modes, u: Depositional) -> FloatArray:
    """gstools' randomisation-method sum at columns x layers, by the cos(a + b) identity.

    The field is sqrt(var / N) sum_m z1_m cos(k_m . T u) + z2_m sin(k_m . T u),
    T gstools' (linear) isometrisation. With K = T^t k, phase = K_xy . x_r + K_w w,
    so per column c and layer l: sum_m cos(a_cm) P_ml + sin(a_cm) Q_ml with
    P = z1 cos(b) + z2 sin(b), Q = z2 cos(b) - z1 sin(b), a_cm = K_xy,m . x_c,
    b_ml = K_w,m w_l: matrix products, by :func:`gridlib.reproducible.matmul` so that
    the field has the same bits for any BLAS, CPU and thread count.
    """
    model, k, z1, z2 = modes.model, modes.k, modes.z1, modes.z2
    n_modes = k.shape[1]
    T = _isometrization(model)
    K = matmul(T.T, k)  # (3, modes): phase = K . u
    used, col_pos = np.unique(u.column, return_inverse=True)
    xy = u.column_xy[used]
    b = np.outer(u.layer_w, K[2])  # (layers, modes)
    cb, sb = np.cos(b), np.sin(b)
    P = (z1 * cb + z2 * sb).T  # (modes, layers)
    Q = (z2 * cb - z1 * sb).T
    # Columns on a lattice (vertical pillars on a rectilinear mesh: cart_grid, horizons_to_grdecl,
    # make_model3) repeat few x and y values; then a = K_x x_i + K_y y_j splits once more, and
    # cos(a) P + sin(a) Q = cos(K_y y_j) R1_i + sin(K_y y_j) R2_i with R1 = cos(K_x x_i) P +
    # sin(K_x x_i) Q, R2 = cos(K_x x_i) Q - sin(K_x x_i) P: trigonometry of the distinct x and y
    # only, and batched matrix products over (x, y, layer).
    ux, ix = np.unique(xy[:, 0], return_inverse=True)
    uy, iy = np.unique(xy[:, 1], return_inverse=True)
    if ux.size * uy.size <= 2 * used.size and ux.size + uy.size < used.size:
        ax, ay = np.outer(ux, K[0]), np.outer(uy, K[1])
        cx, sx, cy, sy = np.cos(ax), np.sin(ax), np.cos(ay), np.sin(ay)
        G = np.empty((ux.size, uy.size, u.num_layers))
        CS = np.hstack([cy, sy])  # (len(uy), 2 modes)
        rows = max(1, _CHUNK // 32)
        for s in range(0, ux.size, rows):  # one large product per block
            c, sn = cx[s : s + rows, :, None], sx[s : s + rows, :, None]  # (rows, modes, 1)
            R = np.concatenate([c * P + sn * Q, c * Q - sn * P], axis=1)  # (rows, 2 modes, layers)
            n = R.shape[0]
            R = R.transpose(1, 0, 2).reshape(CS.shape[1], n * u.num_layers)
            G[s : s + n] = matmul(CS, R).reshape(uy.size, n, u.num_layers).transpose(1, 0, 2)
        F = G[ix.ravel(), iy.ravel()]
    else:
        F = np.empty((used.size, u.num_layers))
        phases, sums = RightFactor(K[:2]), RightFactor(np.vstack([P, Q]))
        local = threading.local()  # each thread's (columns, 2 modes) cos|sin, kept between blocks

        def block(s: int) -> None:
            a = phases.times(xy[s : s + _COLUMNS])  # (columns, modes)
            cs = getattr(local, "cs", None)
            if cs is None:
                cs = local.cs = np.empty((_COLUMNS, 2 * n_modes))
            cs = cs[: a.shape[0]]
            np.cos(a, out=cs[:, :n_modes])
            np.sin(a, out=cs[:, n_modes:])
            F[s : s + _COLUMNS] = sums.times(cs)

        _parallel(block, range(0, used.size, _COLUMNS))
    return math.sqrt(model.var / n_modes) * F[col_pos.ravel(), u.layer]


def _isometrization(model: Any) -> FloatArray:
    """gstools' isometrisation matrix of a 3-D model (``model.isometrize(np.eye(3))``), with
    its 3 x 3 products summed term by term instead of by BLAS (whose kernels round
    differently on different CPUs): diag(1, 1/anis) times the derotation, gstools'
    Givens rotations by the negated angles, in gstools' order and signs."""
    from gstools.tools.geometric import givens_rotation, rotation_planes

    angles = -np.asarray(model.angles, dtype=np.float64)
    derotate = np.eye(3)
    for i, (angle, plane) in enumerate(zip(angles, rotation_planes(3), strict=True)):
        derotate = matmul(derotate, givens_rotation(3, plane, (-1) ** i * angle))
    stretch = np.concatenate(([1.0], 1.0 / np.asarray(model.anis, dtype=np.float64)))
    return stretch[:, None] * derotate


def _parallel(fn: Any, starts: range) -> None:
    """fn(s) for every s, on a few threads (numpy releases the GIL in its loops and products);
    every block writes its own rows, so the result does not depend on the number of threads."""
    workers = num_threads(min(len(starts), _MAX_THREADS))
    if workers > 1:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(workers) as pool:
            list(pool.map(fn, starts))
    else:
        for s in starts:
            fn(s)
