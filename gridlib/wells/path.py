"""A well's path: a polyline in space with the measured depth (MD) of each of its points.

Conventions (as the rest of gridlib): x east, y north, z depth (positive down), all in the
case's length unit; MD is the length along the hole from the well's reference (the rig floor or
the first point of a file), in the same unit. Between two points the path is the straight
segment joining them, and MD runs linearly along it: a point a fraction f along segment i has
MD ``md[i] + f (md[i+1] - md[i])``. A survey computed by minimum curvature
(:func:`gridlib.wells.survey.minimum_curvature`) is a path of circular arcs; it becomes a
``WellPath`` by its stations or by points along its arcs (its ``step``), and its MD steps are
then the arc lengths, a little longer than the chords.

The MD step between two points can thus be longer than the straight line between them, never
shorter: a path whose MD grows less than its length (up to a relative 1e-9) is refused.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..arrays import frozen_array, point_array
from ..errors import InputError
from ..grid import FloatArray

__all__ = ["MD_TOLERANCE", "WellPath", "check_path", "fill_md"]

MD_TOLERANCE = 1e-9  # relative: an MD step may be this much shorter than its straight line


def _where(name: str) -> str:
    return f"well path {name!r}" if name else "well path"


def _point(i: int) -> str:
    return f"point {i}"


def check_path(
    xyz: ArrayLike,
    md: ArrayLike,
    where: str,
    *,
    names: Callable[[int], str] = _point,
    slack: FloatArray | None = None,
) -> tuple[FloatArray, FloatArray]:
    """``xyz`` (n, 3) and ``md`` (n,) as float arrays, checked as a :class:`WellPath`'s: finite,
    n >= 2, MD strictly increasing, consecutive points distinct, and every MD step at least the
    straight distance between its two points (up to a relative :data:`MD_TOLERANCE`, and the
    absolute ``slack`` (n - 1,) of each step if given: a file reader's rounding).

    The first problem is one :class:`~gridlib.errors.InputError` starting with ``where`` and
    naming the point by ``names(i)`` (``point i``, 0-based, unless given; a file reader names
    lines), e.g. ``well path 'P1': point 3: MD 1205 is not greater than point 2's MD 1210``.
    """
    try:
        xyz = np.asarray(xyz, dtype=np.float64)
        md = np.asarray(md, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{where}: expected numbers for the points and their MD ({exc})") from exc
    if xyz.ndim != 2 or xyz.shape[1] != 3 or xyz.shape[0] < 2:
        raise InputError(f"{where}: expected an (n >= 2, 3) array of x, y, z, got shape {xyz.shape}")
    if md.shape != (xyz.shape[0],):
        raise InputError(f"{where}: md: expected {xyz.shape[0]} values (one per point), got shape {md.shape}")
    bad = np.flatnonzero(~np.isfinite(xyz).all(axis=1))
    if bad.size:
        raise InputError(
            f"{where}: {names(int(bad[0]))}: x, y and z must be finite, got {xyz[bad[0]].tolist()}"
        )
    bad = np.flatnonzero(~np.isfinite(md))
    if bad.size:
        raise InputError(f"{where}: {names(int(bad[0]))}: MD {md[bad[0]]} is not finite")
    step = np.diff(md)
    chord = np.linalg.norm(np.diff(xyz, axis=0), axis=1)
    checks = (
        (chord == 0, "the same point as {before} ({x})"),
        (step <= 0, "MD {md1:.10g} is not greater than {before}'s MD {md0:.10g}"),
        (
            step < chord * (1.0 - MD_TOLERANCE) - (0.0 if slack is None else slack),
            "MD step {step:.10g} from {before} is shorter than the straight line between them "
            "({chord:.10g}): measured depth cannot be shorter than the path",
        ),
    )
    for mask, message in checks:
        bad = np.flatnonzero(mask)
        if bad.size:
            i = int(bad[0])
            text = message.format(
                before=names(i), md0=md[i], md1=md[i + 1], step=step[i], chord=chord[i], x=xyz[i].tolist()
            )
            raise InputError(f"{where}: {names(i + 1)}: {text}")
    return xyz, md


def fill_md(xyz: FloatArray, md: FloatArray | None, start_md: float | None = None) -> FloatArray:
    """Measured depths for the points ``xyz`` (n, 3) where ``md`` (n,) is NaN or not given: the
    MD of the point before plus the straight distance between them; the first point's
    ``start_md`` where given, else before the first given MD that MD less the straight distance
    to it (a file whose MD log starts below its first points), and 0 with no MD given. A new
    array; the given MDs are kept as they are.

    >>> fill_md(np.array([(0, 0, 0), (0, 0, 10), (0, 3, 14)], float), np.array([5, np.nan, 40])).tolist()
    [5.0, 15.0, 40.0]
    >>> fill_md(np.array([(0, 0, 0), (0, 0, 10), (0, 3, 14)], float), np.array([np.nan, 50, np.nan])).tolist()
    [40.0, 50.0, 55.0]
    """
    chord = np.linalg.norm(np.diff(xyz, axis=0), axis=1)
    run = np.concatenate(([0.0], np.cumsum(chord)))  # the straight length up to each point
    if md is None:
        return (start_md or 0.0) + run
    md = np.array(md, dtype=np.float64)
    if start_md is not None and np.isnan(md[0]):
        md[0] = start_md
    missing = np.isnan(md)
    if missing.all():
        return run
    if missing.any():
        # each missing MD counts from the last given one; before any, back from the first
        given = np.where(missing, -1, np.arange(md.size))
        last = np.maximum.accumulate(given)
        last = np.where(last >= 0, last, int(np.flatnonzero(~missing)[0]))
        md[missing] = (md[last] + (run - run[last]))[missing]
    return md


@dataclass(frozen=True, eq=False)
class WellPath:
    """A well's path: points ``xyz`` (n >= 2, 3) (x, y, z depth) with their measured depths
    ``md`` (n,), strictly increasing; straight segments between consecutive points, which are
    distinct. Arrays are read-only; the constructor checks them (:func:`check_path`).

    >>> p = WellPath.from_points([(0, 0, 1000), (0, 0, 1100), (30, 40, 1100)], name="P1")
    >>> p.md.tolist(), p.length
    ([0.0, 100.0, 150.0], 150.0)
    >>> p.at([50.0, 125.0]).tolist()
    [[0.0, 0.0, 1050.0], [15.0, 20.0, 1100.0]]
    >>> p.between(90.0, 110.0).xyz.tolist()
    [[0.0, 0.0, 1090.0], [0.0, 0.0, 1100.0], [6.0, 8.0, 1100.0]]
    """

    xyz: FloatArray
    md: FloatArray
    name: str = ""

    def __post_init__(self) -> None:
        xyz, md = check_path(self.xyz, self.md, _where(self.name))
        object.__setattr__(self, "xyz", frozen_array(xyz, np.float64, "xyz", 2, error=InputError))
        object.__setattr__(self, "md", frozen_array(md, np.float64, "md", 1, error=InputError))

    @classmethod
    def from_points(
        cls,
        xyz: ArrayLike,
        md: ArrayLike | None = None,
        *,
        name: str = "",
        start_md: float | None = None,
        source: str = "",
    ) -> WellPath:
        """The path through ``xyz`` (n, 3). ``md`` (n,) may be omitted, or NaN at some points:
        a point without MD gets the MD of the point before it plus the straight distance between
        them (the first point: ``start_md``, else counted back from the first given MD, else 0;
        :func:`fill_md`). ``source`` starts the error messages (e.g. the file and key); the
        well's ``name`` does otherwise.

        >>> WellPath.from_points([(0, 0, 0), (0, 0, 10), (0, 3, 14)], [5, float("nan"), 40]).md.tolist()
        [5.0, 15.0, 40.0]
        """
        where = source or _where(name)
        xyz = point_array(xyz, 3, where, min_points=2)
        if md is not None:
            md = np.asarray(md, dtype=np.float64)
            if md.shape != (xyz.shape[0],):
                raise InputError(
                    f"{where}: md: expected {xyz.shape[0]} values (one per point), got shape {md.shape}"
                )
        md = fill_md(xyz, md, start_md)
        check_path(xyz, md, where)
        return cls(xyz, md, name)

    @property
    def length(self) -> float:
        """The path's length along the hole: ``md[-1] - md[0]``."""
        return float(self.md[-1] - self.md[0])

    @property
    def segments(self) -> tuple[FloatArray, FloatArray]:
        """The straight segments' start and end points, two (n - 1, 3) arrays (views)."""
        return self.xyz[:-1], self.xyz[1:]

    def _check_md(self, md: FloatArray, what: str) -> None:
        bad = np.flatnonzero(~((md >= self.md[0]) & (md <= self.md[-1])))
        if bad.size:
            raise InputError(
                f"{_where(self.name)}: {what} {md[bad[0]]:.10g} is outside the path's MD range "
                f"[{self.md[0]:.10g}, {self.md[-1]:.10g}]"
            )

    def at(self, md: ArrayLike) -> FloatArray:
        """The points (k, 3) at the measured depths ``md`` (k,), each linear along its segment;
        a path's own MD gives its point exactly. An MD outside ``[md[0], md[-1]]`` (or NaN) is an
        InputError."""
        m = np.atleast_1d(np.asarray(md, dtype=np.float64))
        if m.ndim != 1:
            raise InputError(f"{_where(self.name)}: at: expected a 1-D array of MD, got shape {m.shape}")
        self._check_md(m, "MD")
        seg = np.clip(np.searchsorted(self.md, m, side="right") - 1, 0, self.md.size - 2)
        m0, m1 = self.md[seg], self.md[seg + 1]
        f = ((m - m0) / (m1 - m0))[:, None]
        a, b = self.xyz[seg], self.xyz[seg + 1]
        out = a + f * (b - a)
        end = m == m1  # only the last point (side="right" puts every other vertex at f = 0)
        out[end] = b[end]
        return out

    def between(self, md_from: float, md_to: float) -> WellPath:
        """The part of the path with MD in ``[md_from, md_to]``: the points at both ends and
        the path's own points strictly between them. Both ends must be on the path and
        ``md_from < md_to`` (else an InputError); callers clip an interval to ``md[[0, -1]]``
        themselves when they mean to."""
        ends = np.array([md_from, md_to], dtype=np.float64)
        self._check_md(ends, "MD")
        if not ends[0] < ends[1]:
            raise InputError(
                f"{_where(self.name)}: between: MD {md_from:.10g} to {md_to:.10g} is not an interval"
            )
        inner = np.flatnonzero((self.md > ends[0]) & (self.md < ends[1]))
        tips = self.at(ends)
        xyz = np.concatenate([tips[:1], self.xyz[inner], tips[1:]])
        md = np.concatenate([ends[:1], self.md[inner], ends[1:]])
        # an end a rounding error away from a vertex can land on it: keep one of the two
        same = np.flatnonzero((xyz[1:] == xyz[:-1]).all(axis=1))
        if same.size:
            drop = np.where(same + 1 == md.size - 1, same, same + 1)  # keep the ends
            keep = np.ones(md.size, dtype=bool)
            keep[drop] = False
            xyz, md = xyz[keep], md[keep]
        return WellPath(xyz, md, self.name)
