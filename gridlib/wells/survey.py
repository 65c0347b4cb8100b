"""A directional survey turned into a well path by the minimum-curvature method.

A survey lists stations: measured depth (MD), inclination (degrees from vertical: 0 points
straight down, 90 is horizontal, 180 straight up) and azimuth (degrees clockwise from north,
+y: 90 is east, +x). The hole's unit direction at a station is

    t = (sin I sin A, sin I cos A, cos I)        (x east, y north, z depth down).

Minimum curvature joins two stations by the circular arc of length ``dMD = md2 - md1`` that
leaves the first along t1 and arrives along t2 (the industry standard; e.g. SPE-84246,
"Wellbore position calculations" by Sawaryn and Thorogood). Its dogleg angle beta is the angle
between t1 and t2, and the chord is

    p2 - p1 = dMD / 2 * RF * (t1 + t2),    RF = 2 / beta * tan(beta / 2),

RF the ratio factor (RF -> 1 as beta -> 0: a straight hole). Here beta is computed as
``2 atan2(|t2 - t1|, |t2 + t1|)``, accurate for every angle (the usual ``arccos`` of
``t1 . t2`` loses half the digits for small doglegs), and ``tan(beta / 2)`` as
``|t2 - t1| / |t2 + t1|``; RF is ``tan(h) / h`` with ``h = beta / 2``, and its Taylor series
``1 + h^2 / 3 + 2 h^4 / 15`` for ``h < 1e-3`` (error below 1e-19), so a straight interval gives
RF = 1 exactly. Two stations pointing in opposite directions (beta = 180 degrees) have no arc.

Minimum curvature is exact on a circular arc (a hole built or turned at a constant rate in one
plane); on other curves (a helix: a constant turn at fixed inclination off the horizontal) its
error shrinks with the square of the station spacing.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .. import reproducible as rp
from ..arrays import point_array
from ..connectivity import ragged_arange
from ..errors import InputError
from ..grid import FloatArray
from .path import WellPath

__all__ = ["direction", "minimum_curvature", "ratio_factor", "station_problem"]

SERIES_BELOW = 1e-3  # half doglegs (radians) below which RF is its Taylor series


def _sincos_degrees(degrees: FloatArray) -> tuple[FloatArray, FloatArray]:
    """sin and cos of angles in degrees, exact (0, 1 or -1) at multiples of 90 degrees."""
    degrees = np.fmod(degrees, 360.0)  # exact; keeps the quarter count small for any azimuth
    quarter = np.rint(degrees / 90.0)
    rest = np.deg2rad(degrees - 90.0 * quarter)  # in [-45, 45] degrees
    s, c = np.sin(rest), np.cos(rest)
    q = quarter.astype(np.int64) % 4
    sin = np.select([q == 0, q == 1, q == 2], [s, c, -s], -c)
    cos = np.select([q == 0, q == 1, q == 2], [c, -s, -c], s)
    return sin + 0.0, cos + 0.0  # + 0.0: no negative zeros


def direction(inclination: ArrayLike, azimuth: ArrayLike) -> FloatArray:
    """The unit directions (n, 3) of a hole at ``inclination`` (degrees from vertical, 0 down)
    and ``azimuth`` (degrees clockwise from north): ``(sin I sin A, sin I cos A, cos I)``, x east,
    y north, z down.

    >>> direction([0.0, 90.0, 90.0], [0.0, 90.0, 180.0]).tolist()
    [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]]
    """
    sin_i, cos_i = _sincos_degrees(np.asarray(inclination, dtype=np.float64))
    sin_a, cos_a = _sincos_degrees(np.asarray(azimuth, dtype=np.float64))
    return np.stack([sin_i * sin_a, sin_i * cos_a, cos_i], axis=-1)


def ratio_factor(half_angle: ArrayLike, tan_half: ArrayLike) -> FloatArray:
    """The minimum-curvature ratio factor ``RF = tan(h) / h`` of doglegs ``2 h`` (radians),
    given ``h`` and ``tan(h)``; its Taylor series below ``h = 1e-3``, so ``RF(0) = 1``.

    >>> ratio_factor([0.0, 1e-4, np.pi / 4], [0.0, 1.0000000033333334e-4, 1.0]).tolist()
    [1.0, 1.0000000033333334, 1.2732395447351628]
    """
    h = np.asarray(half_angle, dtype=np.float64)
    t = np.asarray(tan_half, dtype=np.float64)
    small = h < SERIES_BELOW
    h2 = h * h
    series = 1.0 + h2 * (1.0 / 3.0 + h2 * (2.0 / 15.0))
    return np.where(small, series, np.divide(t, h, out=np.ones_like(h), where=~small))


def station_problem(stations: FloatArray) -> tuple[int, int, str] | None:
    """The first problem of finite survey ``stations`` (m, 3) (md, inclination, azimuth), as
    (station, column, message), or None: an inclination outside [0, 180] degrees, an MD that
    does not exceed the one before (at one station, the inclination first). The callers name the
    station: a case's key, a file's line, a station number.

    >>> station_problem(np.array([[0.0, 0, 0], [10, 190, 0], [5, 0, 0]]))
    (1, 1, 'inclination 190 is outside [0, 180] degrees (0 is straight down, 90 horizontal)')
    """
    md, inc = stations[:, 0], stations[:, 1]
    bad_inc = (inc < 0) | (inc > 180)
    bad_md = np.r_[False, ~(md[1:] > md[:-1])]
    bad = np.flatnonzero(bad_inc | bad_md)
    if not bad.size:
        return None
    i = int(bad[0])
    if bad_inc[i]:
        return (
            i,
            1,
            f"inclination {inc[i]:.10g} is outside [0, 180] degrees (0 is straight down, 90 horizontal)",
        )
    before = f"the station before it ({md[i - 1]:.10g})"
    return i, 0, f"md {md[i]:.10g} does not exceed {before}; MD increases along the hole"


def _stations(stations: ArrayLike, where: str) -> tuple[FloatArray, FloatArray, FloatArray]:
    """MD, inclination and azimuth of a survey, checked; errors name the station (0-based)."""
    table = point_array(stations, 3, f"{where}: stations (md, inclination, azimuth)", min_points=2,
                        point="station")  # fmt: skip
    problem = station_problem(table)
    if problem is not None:
        raise InputError(f"{where}: station {problem[0]}: {problem[2]}")
    md, inc, azi = table.T
    return md, inc, azi


def minimum_curvature(
    head: ArrayLike,
    stations: ArrayLike,
    *,
    name: str = "",
    step: float | None = None,
    source: str = "",
) -> WellPath:
    """The path of a survey by minimum curvature (see the module docstring).

    ``head`` is the (x, y, depth) of the hole at the first station's MD; ``stations`` (m >= 2, 3)
    are rows of MD, inclination (degrees, 0 = straight down, in [0, 180]) and azimuth (degrees
    clockwise from north = +y, 90 = east = +x), MD strictly increasing. The path's points are the
    stations, and with ``step`` also points along each arc, evenly spaced in MD, at most ``step``
    apart (each placed on the arc exactly, by the same formula from the arc's start with the
    direction turned part of the way), so that the path's straight segments follow the arcs.
    ``source`` (e.g. the case file and key) starts the error messages; ``name`` names the path.

    >>> p = minimum_curvature((0.0, 0.0, 100.0), [(0, 0, 0), (100, 90, 90)], name="H1")
    >>> p.xyz.round(6).tolist()  # a quarter circle of radius 200 / pi, turning east
    [[0.0, 0.0, 100.0], [63.661977, 0.0, 163.661977]]
    """
    where = source or (f"survey of well {name!r}" if name else "survey")
    (p0,) = point_array([head], 3, f"{where}: head (x, y, depth)")
    md, inc, azi = _stations(stations, where)
    if step is not None and not (np.isfinite(step) and step > 0):
        raise InputError(f"{where}: step {step!r} must be a number > 0")
    t = direction(inc, azi)
    t1, t2 = t[:-1], t[1:]
    d = np.linalg.norm(t2 - t1, axis=1)  # 2 sin(beta / 2)
    s = np.linalg.norm(t2 + t1, axis=1)  # 2 cos(beta / 2)
    bad = np.flatnonzero(s == 0)
    if bad.size:
        i = int(bad[0])
        raise InputError(
            f"{where}: stations {i} and {i + 1} point in opposite directions (a dogleg of 180 degrees): "
            "no arc joins them"
        )
    half = rp.arctan2(d, s)  # beta / 2
    length = np.diff(md)
    chord = (0.5 * length * ratio_factor(half, d / s))[:, None] * (t1 + t2)
    xyz = np.concatenate([p0[None, :], p0 + np.cumsum(chord, axis=0)])
    if step is None:
        return WellPath(xyz, md, name)
    return _along_arcs(xyz, md, t1, t2, 2.0 * half, float(step), name)


def _along_arcs(
    xyz: FloatArray, md: FloatArray, t1: FloatArray, t2: FloatArray, beta: FloatArray, step: float, name: str
) -> WellPath:
    """The stations ``xyz`` with points along each arc (dogleg ``beta``, from ``t1`` to ``t2``)
    at most ``step`` apart in MD; a point at arc length ``u`` from its station, the direction
    there turned by ``theta = beta u / L`` towards t2, is ``p1 + u / 2 RF(theta) (t1 + t(theta))``."""
    length = np.diff(md)
    parts = np.maximum(np.ceil(length / step), 1.0).astype(np.int64)
    interval = np.repeat(np.arange(length.size), parts - 1)
    j = ragged_arange(np.ones(length.size, dtype=np.int64), parts - 1).astype(np.float64)
    fraction = j / parts[interval]
    u = length[interval] * fraction
    theta = beta[interval] * fraction
    # the unit normal of each arc's plane, from t1 towards t2 (zero on a straight interval)
    cos_beta = np.einsum("ij,ij->i", t1, t2)
    normal = t2 - cos_beta[:, None] * t1
    size = np.linalg.norm(normal, axis=1)
    normal = np.divide(normal, size[:, None], out=np.zeros_like(normal), where=size[:, None] > 0)
    a = t1[interval]
    turned = np.cos(theta)[:, None] * a + np.sin(theta)[:, None] * normal[interval]
    tan_half = np.sin(theta) / (1.0 + np.cos(theta))
    inner = xyz[interval] + (0.5 * u * ratio_factor(0.5 * theta, tan_half))[:, None] * (a + turned)
    first = np.concatenate([[0], np.cumsum(parts)])  # each station's row in the output
    out = np.empty((int(first[-1]) + 1, 3))
    out_md = np.empty(out.shape[0])
    out[first], out_md[first] = xyz, md
    rows = first[interval] + j.astype(np.int64)
    out[rows], out_md[rows] = inner, md[interval] + u
    return WellPath(out, out_md, name)
