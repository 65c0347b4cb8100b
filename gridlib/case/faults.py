"""A case's faults (``faults``) as gridlib objects: a fault's ``trace`` (or ``sticks``) and
``throw`` (a number, or ``{start, end}`` varying linearly along the trace) and ``side`` give a
:class:`~gridlib.pillars.fault_traces.FaultTrace`; an inclined fault (``dip`` below 90, or
sticks) also its :class:`~gridlib.pillars.fault_surface.FaultSurface`."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..config import Case
from ..config.files import fault_sticks
from ..errors import InputError
from ..grid import FloatArray
from ..pillars.fault_surface import FaultSurface
from ..pillars.fault_traces import FaultTrace
from ..pillars.horizon_maps import DepthFunction

_SAMPLES = 64  # intervals per trace segment at which the top horizon's defined area is looked for


def fault_traces(case: Case, top: DepthFunction | None = None) -> list[FaultTrace]:
    """The case's faults as FaultTraces (throw in m; 0 where none is given).

    A vertical fault (no ``dip``, or 90 all along; or vertical sticks, with the case's
    ``side``) is its trace, as ever (no ``surface``). An
    inclined one gets its ``surface``, built at the top horizon, whose depth function ``top``
    (``top(x, y)`` -> depth in m for arrays of points, NaN outside its defined area) it then
    needs (an InputError without it):

    * ``dip``: :meth:`FaultSurface.from_dip` of the trace at the top's depths. Where the trace
      leaves the top's defined area, a stick is added at the point where it leaves (found to
      round-off) and the vertices beyond take the top's depth extrapolated linearly along the
      trace (in arc length) from the last two defined vertices (between two defined stretches,
      interpolated): a straight trace on a planar top gives one exactly planar fault. With one
      defined point only, its depth is carried on flat. The trace (``points``) is the case's.
    * ``sticks``: ``points`` are where the sticks meet the top (:meth:`FaultSurface.on_horizon`;
      a stick beyond the top's defined area where the nearest stick that meets it does: the top
      carried on flat along the fault), ``side`` is the side they dip towards unless the case
      gives it.
    """
    traces = []
    for k, spec in enumerate(case.data.get("faults", [])):
        name = spec["name"]
        throw = _throw(spec["throw"])
        if "sticks" in spec:
            surface = fault_sticks(case.path, spec).surface
            if surface.is_vertical:  # a vertical fault, as if given by its trace
                points, side, surface = surface.section(surface.levels[0]), spec["side"], None
            else:
                top_fn = _top(top, case, k, name, "is given by sticks")
                points, _ = surface.on_horizon(top_fn, missing="nearest")
                side = spec.get("side") or surface.dip_side()
        else:
            points, side = spec["trace"], spec.get("side", "right")
            dip = spec.get("dip", 90)
            surface = None
            if not _vertical(dip):
                depth_fn = _top(top, case, k, name, "dips")
                surface = _dip_surface(np.asarray(points, dtype=np.float64), dip, side, name, depth_fn)
        traces.append(FaultTrace(points, throw=throw, name=name, side=side, surface=surface))
    return traces


def _throw(throw: Any) -> Any:
    """A number, or the linear function of the arc length s that ``{start, end}`` gives."""
    if isinstance(throw, dict):
        start, end = float(throw["start"]), float(throw["end"])
        return lambda s, a=start, b=end: a + (b - a) * np.asarray(s)
    return float(throw)


def _vertical(dip: Any) -> bool:
    if isinstance(dip, dict):
        return float(dip["start"]) == 90 and float(dip["end"]) == 90
    return float(dip) == 90


def _top(top: DepthFunction | None, case: Case, k: int, name: str, why: str) -> DepthFunction:
    if top is None:
        raise InputError(
            f"{case.path}: faults[{k}]: fault '{name}' {why}: its surface is placed at the top "
            "horizon, which fault_traces needs (top=)"
        )
    return top


def _dip_surface(trace: FloatArray, dip: Any, side: str, name: str, top: DepthFunction) -> FaultSurface:
    """The surface of a fault given by its trace and dip (see :func:`fault_traces`)."""
    vertices, s, depth = _trace_on_top(trace, top, name)
    if isinstance(dip, dict):
        dips = float(dip["start"]) + (float(dip["end"]) - float(dip["start"])) * s
    else:
        dips = float(dip)
    return FaultSurface.from_dip(vertices, depth, dips, side, name=name)


def _trace_on_top(
    trace: FloatArray, top: DepthFunction, name: str
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The trace's vertices with a vertex added wherever it enters or leaves the top's defined
    area, their normalised arc lengths, and the top's depth at each (beyond the area linear in
    arc length: :func:`_fill_along`)."""
    start, step = trace[:-1], np.diff(trace, axis=0)
    length = np.hypot(step[:, 0], step[:, 1])
    cum = np.concatenate([[0.0], np.cumsum(length)])

    def depth(seg: np.ndarray, t: np.ndarray) -> FloatArray:
        xy = start[seg] + t[:, None] * step[seg]
        return np.asarray(top(xy[:, 0], xy[:, 1]), dtype=np.float64).reshape(seg.shape)

    n_seg = step.shape[0]
    t = np.linspace(0.0, 1.0, _SAMPLES + 1)
    seg_grid, t_grid = np.repeat(np.arange(n_seg), t.size), np.tile(t, n_seg)
    defined = np.isfinite(depth(seg_grid, t_grid)).reshape(n_seg, t.size)
    if not defined.any():
        raise InputError(f"fault '{name}': its trace does not reach the top horizon's defined area")
    # Where the definedness changes between two samples, bisect to the boundary (its defined side).
    seg, j = np.nonzero(defined[:, 1:] != defined[:, :-1])
    lo, hi = t[j], t[j + 1]
    lo_defined = defined[seg, j]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        same = np.isfinite(depth(seg, mid)) == lo_defined
        lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
    t_edge = np.where(lo_defined, lo, hi)
    keep = (t_edge > 1e-9) & (t_edge < 1.0 - 1e-9)  # an edge at a vertex adds nothing
    seg, t_edge = seg[keep], t_edge[keep]

    all_seg = np.concatenate([np.arange(n_seg), [n_seg - 1], seg])
    all_t = np.concatenate([np.zeros(n_seg), [1.0], t_edge])
    order = np.lexsort((all_t, all_seg))
    all_seg, all_t = all_seg[order], all_t[order]
    original = np.concatenate([np.arange(n_seg + 1), np.full(seg.size, -1)])[order]
    vertices = np.where(
        (original >= 0)[:, None],
        trace[np.maximum(original, 0)],
        start[all_seg] + all_t[:, None] * step[all_seg],
    )
    s = (cum[all_seg] + all_t * length[all_seg]) / cum[-1]
    z = np.asarray(top(vertices[:, 0], vertices[:, 1]), dtype=np.float64).reshape(-1)
    return vertices, s, _fill_along(s, z)


def _fill_along(s: FloatArray, z: FloatArray) -> FloatArray:
    """The depths ``z`` at increasing arc lengths ``s`` with every NaN filled linearly in s:
    between defined values interpolated, beyond the first (last) two extrapolated from them, so
    a top that is linear along the trace stays so; flat with a single defined value.

    >>> _fill_along(np.linspace(0.0, 1.0, 5), np.array([np.nan, 10.0, np.nan, 12.0, np.nan])).tolist()
    [9.0, 10.0, 11.0, 12.0, 13.0]
    """
    at = np.flatnonzero(np.isfinite(z))
    filled = np.interp(s, s[at], z[at])  # flat beyond the ends
    if at.size >= 2:
        for end, inner, beyond in ((at[0], at[1], s < s[at[0]]), (at[-1], at[-2], s > s[at[-1]])):
            slope = (z[end] - z[inner]) / (s[end] - s[inner])
            filled = np.where(beyond, z[end] + (s - s[end]) * slope, filled)
    return np.where(np.isfinite(z), z, filled)
