"""Floating-point results that are the same bits on every machine and for any number of threads.

gridlib promises that the same inputs and seed give bit-identical arrays whatever the
CPU, the BLAS library and its thread count. Two things in the numerical stack break
that promise, and this module replaces them where gridlib writes values:

**Matrix products.** BLAS (OpenBLAS, MKL) splits the sums of a product differently for
1 or 2 threads and uses different kernels on different CPUs (with or without fused
multiply-add), so ``a @ b`` differs in the last bits between machines. :func:`matmul`
splits both factors into slices of few significant bits (an Ozaki-type error-free
split): every product of two slices and every partial sum of a slice product is then
an exact floating-point number, so BLAS computes each slice product *exactly*, in any
order, with or without FMA, on any number of threads. The slice products are added in
a fixed order. The result is as accurate as an ordinary product (error about k u
max|a| max|b| per entry, k the inner dimension, u = 2**-53) and costs six BLAS products.

**Elementary functions.** numpy dispatches ``exp``, ``log``, ``power``, ``arctan2``,
``arccos`` and friends to SIMD implementations chosen by the CPU (AVX-512 machines use
different code from AVX2 or older ones), and the C library picks FMA variants by CPU:
results differ in the last bit. :func:`exp`, :func:`log`, :func:`log10`,
:func:`power`, :func:`arctan2`, :func:`arccos` and :func:`arcsin` here are built from
IEEE-754 basic operations only (+, -, *, /, sqrt, rint, frexp, ldexp: correctly
rounded or exact everywhere), so they give the same bits on every machine, within
about 1-2 units in the last place of the true value. ``np.sin``, ``np.cos``,
``np.sqrt`` and ``np.hypot`` are already the same on every dispatch level (a test
checks this with numpy's CPU features disabled), so gridlib uses them directly.

Everything else gridlib computes is elementwise IEEE arithmetic, or sums in a fixed
order (``np.add.reduce``, ``bincount``, ``cumsum``), which do not depend on the machine.

>>> import numpy as np
>>> a = np.arange(12.0).reshape(3, 4) / 7
>>> b = np.arange(8.0).reshape(4, 2) / 3
>>> bool(np.allclose(matmul(a, b), a @ b, rtol=1e-15))
True
>>> float(exp(1.0)), float(log(np.e))
(2.718281828459045, 1.0)
>>> float(arctan2(1.0, -1.0)) == 3 * np.pi / 4
True
"""

from __future__ import annotations

import decimal
import math
import threading

import numpy as np
from numpy.typing import ArrayLike

FloatArray = np.ndarray

# -------------------------------------------------------------------------- matrix products

SMALL_INNER = 8  # up to this inner dimension a product is summed term by term in numpy


def matmul(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """``a @ b`` for 2-D float arrays, bit-identical on every machine and thread count.

    Inner dimensions up to ``SMALL_INNER`` are summed term by term (k = 0, 1, ...);
    larger ones by the exact-slice method of the module docstring. Non-finite entries
    are refused (a ValueError): the exact split needs finite numbers. Many products with
    one right factor: :class:`RightFactor` (the same bits).
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    if a.ndim != 2 or b.ndim != 2 or a.shape[1] != b.shape[0]:
        raise ValueError(f"matmul: shapes {a.shape} and {b.shape} do not make a matrix product")
    if a.shape[1] == 0 or a.shape[0] == 0 or b.shape[1] == 0:
        return np.zeros((a.shape[0], b.shape[1]))
    return RightFactor(b).times(a)


class RightFactor:
    """The right factor ``b`` (k, n) of exact products ``a @ b`` (:func:`matmul`, the same
    bits): its slices computed once, and the temporaries of ``a``'s slices (four arrays the
    size of ``a``) kept per thread from one product to the next.

    A loop of products over blocks of rows (the random fields' sums) so allocates its
    temporaries once: allocated anew for every block, glibc may give their megabytes back to
    the kernel as they are freed (it trims its heap, depending on what the process allocated
    before), and the next block's touch faults every page in again, zeroed. Measured in a
    warm process without the pictures' allocations: a 5,000-cell variant's two fields (28
    blocks) took 88,000 page faults and 0.19 s of system time, more than the sums themselves.

    >>> b = np.arange(40.0).reshape(20, 2) / 3
    >>> a = np.arange(60.0).reshape(3, 20) / 7
    >>> product = RightFactor(b)
    >>> bool(np.array_equal(product.times(a), matmul(a, b)))
    True
    """

    def __init__(self, b: ArrayLike) -> None:
        b = np.asarray(b, dtype=np.float64)
        if b.ndim != 2:
            raise ValueError(f"matmul: the right factor must be 2-D, got shape {b.shape}")
        if not np.isfinite(b).all():
            raise ValueError("matmul: the factors must be finite")
        self.shape = b.shape
        k = b.shape[0]
        self._b = b
        # Slices of beta bits: a product of two slice entries has at most 2 beta bits and a sum
        # of k of them at most 2 beta + ceil(log2 k) <= 53, so every BLAS partial sum is exact.
        self._beta = (53 - int(np.ceil(np.log2(k)))) // 2 if k > SMALL_INNER else 0
        if k > SMALL_INNER and b.shape[1]:
            self._col_scale = _power_of_two_above(np.abs(b).max(axis=0))[None, :]
            self._sb = _slices(b * (1.0 / self._col_scale), self._beta)
        self._local = threading.local()

    def times(self, a: ArrayLike) -> FloatArray:
        """``a @ b`` (m, n), as :func:`matmul` (a ValueError where ``a`` is not finite)."""
        a = np.asarray(a, dtype=np.float64)
        k, n = self.shape
        if a.ndim != 2 or a.shape[1] != k:
            raise ValueError(f"matmul: shapes {a.shape} and {self.shape} do not make a matrix product")
        m = a.shape[0]
        if k == 0 or m == 0 or n == 0:
            return np.zeros((m, n))
        b = self._b
        if k <= SMALL_INNER:
            if not np.isfinite(a).all():
                raise ValueError("matmul: the factors must be finite")
            out = a[:, 0:1] * b[0]
            for j in range(1, k):
                out += a[:, j : j + 1] * b[j]
            return out
        rest, *sa = self._workspace(m)
        np.abs(a, out=rest)
        top = rest.max(axis=1)  # NaN where a row has one
        if not np.isfinite(top).all():
            raise ValueError("matmul: the factors must be finite")
        row_scale = _power_of_two_above(top)[:, None]
        np.multiply(a, 1.0 / row_scale, out=rest)
        for i, s in enumerate(sa, start=1):  # _slices, into the workspace
            up = 2.0 ** (i * self._beta)  # scaling by a power of two is exact
            np.multiply(rest, up, out=s)
            np.rint(s, out=s)
            s *= 1.0 / up
            if i < len(sa):
                rest -= s
        sb = self._sb
        # The products of slices i + j <= 4 (1-based) carry all but about 2**-(3 beta) of the
        # product; they are added from the smallest to the largest, in this fixed order.
        out = sa[2] @ sb[0]
        out += sa[1] @ sb[1]
        out += sa[0] @ sb[2]
        out += sa[1] @ sb[0]
        out += sa[0] @ sb[1]
        out += sa[0] @ sb[0]
        out *= row_scale
        out *= self._col_scale
        return out

    def _workspace(self, m: int) -> list[FloatArray]:
        """This thread's four (m, k) arrays: the rest of a row, its three slices."""
        k = self.shape[0]
        buffer = getattr(self._local, "buffer", None)
        if buffer is None or buffer.size < 4 * m * k:
            buffer = self._local.buffer = np.empty(4 * m * k)
        return [buffer[i * m * k : (i + 1) * m * k].reshape(m, k) for i in range(4)]


def _power_of_two_above(m: np.ndarray) -> np.ndarray:
    """The smallest power of two 2**e > m (1 where m is 0), elementwise."""
    _, e = np.frexp(m)
    return np.ldexp(1.0, e)


def _slices(x: np.ndarray, beta: int) -> list[np.ndarray]:
    """Three slices of x (|x| < 1): slice i holds the bits from 2**-(i-1)beta to 2**-i beta,
    rounded to the nearest multiple of 2**-(i beta); every step is exact."""
    out = []
    rest = x
    for i in range(1, 4):
        up = 2.0 ** (i * beta)  # scaling by a power of two is exact
        s = np.rint(rest * up)
        s *= 1.0 / up
        out.append(s)
        rest = rest - s
    return out


# -------------------------------------------------------------------------- exponential and logarithm


def _exp_table(bits: int) -> tuple[float, float, float, np.ndarray, np.ndarray]:
    """ln2 / N in two parts (the first with 36 significant bits, so k times it is exact for
    |k| < 2**17) and 2**(j/N), j = 0..N-1, as rounded value plus remainder; computed in
    40-digit decimal arithmetic, so the table is the same on every machine."""
    with decimal.localcontext() as ctx:
        ctx.prec = 40
        ln2 = decimal.Decimal(2).ln()
        step = ln2 / (1 << bits)
        hi = float(step)
        mant, e = math.frexp(hi)
        hi = math.ldexp(round(mant * 2**36), e - 36)
        lo = float(step - decimal.Decimal(hi))
        t = [(decimal.Decimal(j) * step).exp() for j in range(1 << bits)]
        t_hi = np.array([float(v) for v in t])
        t_lo = np.array([float(v - decimal.Decimal(float(v))) for v in t])
    return float((1 << bits) / ln2), hi, lo, t_hi, t_lo


EXP_TABLE_BITS = 6
_N_OVER_LN2, _STEP_HI, _STEP_LO, _EXP2_HI, _EXP2_LO = _exp_table(EXP_TABLE_BITS)
LN2_HI = 6.93147180369123816490e-01  # ln 2 in two parts; n * LN2_HI is exact for |n| < 2**20
LN2_LO = 1.90821492927058770002e-10
LN10 = 2.302585092994045684
EXP_MAX = 709.782712893383973096  # exp overflows above this
EXP_MIN = -745.13321910194110842  # and is 0 below this
_EXP_TAYLOR = (1.0 / 2.0, 1.0 / 6.0, 1.0 / 24.0, 1.0 / 120.0, 1.0 / 720.0)  # 1/k!, k = 2..6


ELEMENT_BLOCK = 1 << 14  # elements per block: the temporaries of a block stay in the CPU cache


def _blockwise(kernel, x: np.ndarray) -> FloatArray:
    """kernel applied to cache-sized blocks of x (any shape), the result shaped like x."""
    flat = np.ascontiguousarray(x, dtype=np.float64).reshape(-1)
    out = np.empty_like(flat)
    for s in range(0, flat.size, ELEMENT_BLOCK):
        out[s : s + ELEMENT_BLOCK] = kernel(flat[s : s + ELEMENT_BLOCK])
    out = out.reshape(np.shape(x))
    return out if out.ndim else out[()]


def _pow2(m: np.ndarray) -> np.ndarray:
    """2.0**m for integers -1022 <= m <= 1023, built from the bits (exact)."""
    return ((m + 1023) << 52).view(np.float64)


def _exp_kernel(x: np.ndarray) -> np.ndarray:
    finite = np.isfinite(x)
    all_finite = bool(finite.all())
    xc = np.clip(x if all_finite else np.where(finite, x, 0.0), EXP_MIN - 1.0, EXP_MAX + 1.0)
    k = np.rint(xc * _N_OVER_LN2)
    r = xc - k * _STEP_HI
    r -= k * _STEP_LO
    ki = k.astype(np.int64)
    j = ki & ((1 << EXP_TABLE_BITS) - 1)
    m = (ki - j) >> EXP_TABLE_BITS
    em1 = np.full_like(r, _EXP_TAYLOR[-1])
    for c in _EXP_TAYLOR[-2::-1]:
        em1 *= r
        em1 += c
    em1 *= r * r
    em1 += r  # e**r - 1 = r + r**2 (1/2 + r/6 + ...)
    t_hi = _EXP2_HI[j]
    em1 *= t_hi
    em1 += _EXP2_LO[j]
    em1 += t_hi  # 2**(j/64) e**r
    # times 2**m in two exact-or-once-rounded steps: 2**m1 keeps the product normal
    m1 = np.clip(m, -1000, 1000)
    with np.errstate(over="ignore", under="ignore"):
        em1 *= _pow2(m1)
        em1 *= _pow2(m - m1)
    out = np.where(xc > EXP_MAX, np.inf, np.where(xc < EXP_MIN, 0.0, em1))
    if not all_finite:
        out = np.where(finite, out, np.where(x == np.inf, np.inf, np.where(x == -np.inf, 0.0, np.nan)))
    return out


def exp(x: ArrayLike) -> FloatArray:
    """e**x, the same bits on every machine (within 0.51 ulp of the true value, so nearly
    always the correctly rounded value).

    x = (64 m + j) ln2/64 + r with |r| <= ln2/128 (ln2/64 in two parts), e**x =
    2**m 2**(j/64) e**r, 2**(j/64) from a table held as value plus remainder, e**r - 1 by
    its Taylor series to r**6.

    >>> exp([0.0, -np.inf, np.inf, 710.0]).tolist()
    [1.0, 0.0, inf, inf]
    """
    return _blockwise(_exp_kernel, np.asarray(x, dtype=np.float64))


# 2 / (2k + 1) for k = 1..11: 2 atanh(s) = 2 s + s R(s**2), R(z) = sum 2 z**k / (2k + 1)
_LOG_SERIES = tuple(2.0 / (2 * k + 1) for k in range(1, 12))
SQRT_HALF = 0.70710678118654752440


def _log_kernel(x: np.ndarray) -> np.ndarray:
    ok = np.isfinite(x) & (x > 0)
    all_ok = bool(ok.all())
    m, e = np.frexp(x if all_ok else np.where(ok, x, 1.0))  # m in [0.5, 1)
    low = m < SQRT_HALF
    m += m * low  # doubled where below sqrt(1/2): exact
    e = e.astype(np.float64)
    e -= low
    f = m
    f -= 1.0  # exact (Sterbenz)
    s = f / (2.0 + f)
    z = s * s
    rz = np.full_like(z, _LOG_SERIES[-1])
    for c in _LOG_SERIES[-2::-1]:
        rz *= z
        rz += c
    rz *= z
    hfsq = 0.5 * f
    hfsq *= f
    rz += hfsq
    rz *= s
    rz += e * LN2_LO
    np.subtract(hfsq, rz, out=rz)
    np.subtract(f, rz, out=rz)
    out = e * LN2_HI
    out += rz  # e ln2 + (f - (f**2/2 - (s (f**2/2 + R) + e ln2_lo)))
    if not all_ok:
        with np.errstate(invalid="ignore"):
            special = np.where(x == 0.0, -np.inf, np.where(x == np.inf, np.inf, np.nan))
        out = np.where(ok, out, special)
    return out


def log(x: ArrayLike) -> FloatArray:
    """Natural logarithm, the same bits on every machine (within about 1 ulp).

    x = m 2**e with m in [sqrt(1/2), sqrt(2)); log(m) = f - (f**2/2 - s (f**2/2 + R)),
    f = m - 1, s = f / (2 + f), R the atanh series in s**2.

    >>> log([1.0, 0.0, -1.0, np.inf]).tolist()
    [0.0, -inf, nan, inf]
    """
    return _blockwise(_log_kernel, np.asarray(x, dtype=np.float64))


def log10(x: ArrayLike) -> FloatArray:
    """Base-10 logarithm, log(x) / ln 10 (the same bits on every machine)."""
    return log(x) / LN10


SMALL_INTEGER_POWER = 64


def power(x: ArrayLike, y: ArrayLike) -> FloatArray:
    """x**y for x >= 0 (and for x < 0 with integer y), the same bits on every machine.

    Integer exponents up to ``SMALL_INTEGER_POWER`` by binary powering (repeated
    squaring); others as exp(y log x), whose relative error grows with |y log x| (about
    1e-14 for results near 1e±100), ample for sizes, ratios and growth factors.

    >>> power([2.0, 0.0, 0.0, -2.0, 4.0, 2.0], [3.0, 2.0, 0.0, 3.0, 0.5, -2.0]).tolist()
    [8.0, 0.0, 1.0, -8.0, 2.0, 0.25]
    """
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    x, y = np.broadcast_arrays(x, y)
    ax = np.abs(x)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        mag = exp(y * log(ax))
    integer_y = np.isfinite(y) & (np.rint(y) == y)
    small = integer_y & (np.abs(y) <= SMALL_INTEGER_POWER)
    if small.any():  # binary powering: exact for small results, a few roundings otherwise
        e = np.where(small, np.abs(y), 0.0).astype(np.int64)
        acc, base = np.ones_like(ax), ax.copy()
        with np.errstate(over="ignore", under="ignore"):
            while e.any():
                odd = (e & 1) == 1
                acc = np.where(odd, acc * base, acc)
                base = base * base
                e >>= 1
            with np.errstate(divide="ignore"):
                acc = np.where(y < 0, 1.0 / acc, acc)
        mag = np.where(small, acc, mag)
    odd_y = integer_y & (np.abs(np.fmod(y, 2.0)) == 1.0)
    out = np.where((x < 0) & odd_y, -mag, mag)
    out = np.where((x < 0) & ~integer_y, np.nan, out)
    out = np.where(y == 0.0, 1.0, out)
    out = np.where(x == 1.0, 1.0, out)
    out = np.asarray(out)
    return out if out.ndim else out[()]


# -------------------------------------------------------------------------- inverse trigonometry


def _decimal_atan(x: decimal.Decimal) -> decimal.Decimal:
    """atan(x) for 0 <= x <= 1/2 by its series, in the context's precision."""
    term, total, k = x, x, 0
    while abs(term) > decimal.Decimal(10) ** -45:
        k += 1
        term = -term * x * x
        total += term / (2 * k + 1)
    return total


def _two_parts(v: decimal.Decimal) -> tuple[float, float]:
    hi = float(v)
    return hi, float(v - decimal.Decimal(hi))


with decimal.localcontext() as _ctx:
    _ctx.prec = 50
    # Machin: pi/4 = 4 atan(1/5) - atan(1/239)
    _QUARTER_PI = 4 * _decimal_atan(decimal.Decimal(1) / 5) - _decimal_atan(decimal.Decimal(1) / 239)
    PI, PI_LO = _two_parts(4 * _QUARTER_PI)
    HALF_PI, HALF_PI_LO = _two_parts(2 * _QUARTER_PI)
    QUARTER_PI, QUARTER_PI_LO = _two_parts(_QUARTER_PI)
    ATAN_HALF, ATAN_HALF_LO = _two_parts(_decimal_atan(decimal.Decimal(1) / 2))
# (-1)**k / (2k + 1): atan(u) = u sum (-1)**k u**2k / (2k + 1) on |u| <= 7/16
_ATAN_SERIES = tuple((-1.0) ** k / (2 * k + 1) for k in range(25))


def _atan_unit(t: np.ndarray) -> np.ndarray:
    """atan(t) for 0 <= t <= 1: t itself below 7/16, else atan(1/2) + atan((2t - 1)/(2 + t))
    below 11/16, else pi/4 + atan((t - 1)/(t + 1)); the series on |u| <= 7/16."""
    mid = t >= 7.0 / 16.0
    high = t >= 11.0 / 16.0
    u = np.where(high, (t - 1.0) / (t + 1.0), np.where(mid, (2.0 * t - 1.0) / (2.0 + t), t))
    z = u * u
    p = np.full_like(z, _ATAN_SERIES[-1])
    for c in _ATAN_SERIES[-2::-1]:  # in place: the same operations, no temporaries
        p *= z
        p += c
    p *= u
    base_hi = np.where(high, QUARTER_PI, np.where(mid, ATAN_HALF, 0.0))
    base_lo = np.where(high, QUARTER_PI_LO, np.where(mid, ATAN_HALF_LO, 0.0))
    p += base_lo
    p += base_hi
    return p


def arctan2(y: ArrayLike, x: ArrayLike) -> FloatArray:
    """The angle of (x, y) in (-pi, pi], as ``np.arctan2``, the same bits on every machine.

    >>> arctan2([0.0, 1.0, 0.0, -1.0], [1.0, 0.0, -1.0, -1.0]).tolist() == [
    ...     0.0, np.pi / 2, np.pi, -3 * np.pi / 4]
    True
    """
    y = np.asarray(y, dtype=np.float64)
    x = np.asarray(x, dtype=np.float64)
    y, x = np.broadcast_arrays(y, x)
    shape = y.shape
    y, x = y.ravel(), x.ravel()  # at least 1-d: the steps below work in place
    ay, ax = np.abs(y), np.abs(x)
    both_inf = np.isinf(ay) & np.isinf(ax)
    if both_inf.any():  # (inf, inf) is the diagonal
        ay, ax = np.where(both_inf, 1.0, ay), np.where(both_inf, 1.0, ax)
    steep = ay > ax
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.minimum(ay, ax)  # the smaller over the larger: exact choices, as np.where would make
        t /= np.maximum(ay, ax)
    t[np.isnan(t)] = 0.0  # 0 / 0 (and NaN inputs, NaN again below)
    a = _atan_unit(t)
    np.subtract(HALF_PI, a - HALF_PI_LO, out=a, where=steep)  # angle in [0, pi/2] of (|x|, |y|)
    np.subtract(PI, a - PI_LO, out=a, where=np.signbit(x))
    np.copysign(a, y, out=a)
    a[np.isnan(x) | np.isnan(y)] = np.nan
    a = a.reshape(shape)
    return a if a.ndim else a[()]


def arcsin(x: ArrayLike) -> FloatArray:
    """asin(x) on [-1, 1] (nan outside), the same bits on every machine."""
    x = np.asarray(x, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        c = np.sqrt((1.0 - x) * (1.0 + x))
    return arctan2(x, c)


def arccos(x: ArrayLike) -> FloatArray:
    """acos(x) on [-1, 1] (nan outside), the same bits on every machine."""
    x = np.asarray(x, dtype=np.float64)
    with np.errstate(invalid="ignore"):
        s = np.sqrt((1.0 - x) * (1.0 + x))
    return arctan2(s, x)


# -------------------------------------------------------------------------- linear systems

LU_BLOCK = 64  # panel width of the blocked factorisation of large single systems


def solve(a: ArrayLike, b: ArrayLike) -> FloatArray:
    """x with a x = b, for a (..., n, n) and b (..., n): a batch of dense systems, the same
    bits on every machine and thread count (LAPACK's blocking and kernels differ).

    Gaussian elimination with partial pivoting (the first largest pivot), elementwise
    updates in a fixed order; a single large system (n > 4 ``LU_BLOCK``) is factorised
    in panels whose trailing updates go through :func:`matmul`. Raises
    ``np.linalg.LinAlgError`` on a zero pivot (a singular matrix).

    >>> solve([[2.0, 1.0], [1.0, 3.0]], [3.0, 5.0]).tolist()
    [0.8, 1.4]
    """
    a = np.array(a, dtype=np.float64)  # copies: eliminated in place
    b = np.asarray(b, dtype=np.float64)
    n = a.shape[-1]
    if a.ndim < 2 or a.shape[-2] != n or b.shape != a.shape[:-1]:
        raise ValueError(f"solve: shapes {a.shape} and {b.shape} are not square systems with one right side")
    aug = np.concatenate([a, b[..., None]], axis=-1)  # (..., n, n + 1)
    batch = aug.reshape(-1, n, n + 1)
    if batch.shape[0] == 1 and n > 4 * LU_BLOCK:
        _eliminate_blocked(batch[0])
    else:
        _eliminate(batch, 0, n, n + 1)
    return _back_substitute(batch).reshape(b.shape)


def _eliminate(aug: np.ndarray, k0: int, k1: int, c1: int) -> None:
    """Eliminate below the diagonal in columns k0..k1-1 of each (n, c) system of ``aug``,
    swapping whole rows and updating columns up to c1; the multipliers stay below the
    diagonal."""
    n = aug.shape[1]
    rows = np.arange(aug.shape[0])
    for k in range(k0, k1):
        p = k + np.argmax(np.abs(aug[:, k:, k]), axis=1)
        if np.any(aug[rows, p, k] == 0.0):
            raise np.linalg.LinAlgError("singular matrix")
        swap = p != k
        if swap.any():
            r = rows[swap]
            top = aug[r, k].copy()
            aug[r, k] = aug[r, p[swap]]
            aug[r, p[swap]] = top
        if k + 1 == n:
            break
        lower = aug[:, k + 1 :, k] / aug[:, k, k][:, None]
        aug[:, k + 1 :, k] = lower
        aug[:, k + 1 :, k + 1 : c1] -= lower[:, :, None] * aug[:, k, None, k + 1 : c1]


def _eliminate_blocked(aug: np.ndarray) -> None:
    """Right-looking blocked elimination of one (n, n + 1) system: panel, the panel's rows
    of U by forward substitution, then one trailing update by :func:`matmul`."""
    n = aug.shape[0]
    view = aug[None]
    for k0 in range(0, n, LU_BLOCK):
        k1 = min(k0 + LU_BLOCK, n)
        _eliminate(view, k0, k1, k1)  # the panel: pivots swap whole rows
        for k in range(k0, k1 - 1):  # U12 = L11^-1 A12 (unit lower L11)
            aug[k + 1 : k1, k1:] -= aug[k + 1 : k1, k, None] * aug[k, None, k1:]
        if k1 < n:
            aug[k1:, k1:] -= matmul(aug[k1:, k0:k1], aug[k0:k1, k1:])


def _back_substitute(aug: np.ndarray) -> np.ndarray:
    """x from the upper triangle and the last column of each eliminated system (column by column)."""
    n = aug.shape[1]
    y = aug[:, :, n].copy()
    x = np.empty_like(y)
    for k in range(n - 1, -1, -1):
        x[:, k] = y[:, k] / aug[:, k, k]
        y[:, :k] -= aug[:, :k, k] * x[:, k, None]
    return x
