"""Horizon-pick residuals: how far each pick lies from the surface interpolated through it.

The residual of a pick is its depth minus the depth of its horizon's final surface (the one the
grid is built from: interpolated on the lattice, per fault block where the case asks for it,
and ordered) at the pick's (x, y), bilinear between the lattice nodes
(:func:`~gridlib.pillars.horizon_maps.interpolate_horizon`). Positive: the pick is deeper than
the surface. Where picks are interpolated per fault block, a pick is compared with its own
block's surface (``depth_by_block``), so a throw does not show as a residual next to a fault;
otherwise with the horizon's ``depth``, whose nodes take their own block's values, so a pick
within a lattice cell of a fault can show part of the throw. NaN where the surface is undefined
at the pick (outside the lattice, or an undefined node with a weight).

A linear interpolation (``method: linear``) honours its picks up to the lattice's bilinear
sampling; residuals then measure the lattice's resolution, the ordering's repairs (an eroded or
onlapped horizon no longer passes through its picks), smoothing, and picks dropped on a fault
trace. Units are the horizons' (metres, z depth positive down).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..grid import FloatArray
from ..pillars.horizon_maps import interpolate_horizon


@dataclass(frozen=True)
class PickResiduals:
    """The picks of every horizon given by points, one row per pick: ``horizon`` (int32, the
    index of its horizon in the stack, top first), ``x``, ``y``, ``depth`` (m, positive down),
    ``surface`` (the depth of the horizon's surface there, m; NaN where undefined) and ``block``
    (int32, the fault block whose surface it was compared with; -1: the horizon's ``depth``)."""

    horizon: NDArray[np.int32]
    x: FloatArray
    y: FloatArray
    depth: FloatArray
    surface: FloatArray
    block: NDArray[np.int32]

    @property
    def residual(self) -> FloatArray:
        """Pick depth minus surface depth (m; positive: the pick is deeper)."""
        return self.depth - self.surface

    @property
    def num(self) -> int:
        return int(self.horizon.size)


def pick_residuals(
    picks: Sequence[tuple[int, FloatArray, NDArray[np.int64] | None]],
    depth: FloatArray,
    xa: FloatArray,
    ya: FloatArray,
    depth_by_block: FloatArray | None = None,
) -> PickResiduals:
    """The residuals of ``picks``: per horizon given by points, ``(k, points, blocks)`` with
    ``k`` its index in ``depth`` (horizon, y, x) on the lattice ``xa``, ``ya``, ``points`` (n, 3)
    x, y, depth, and ``blocks`` the fault block of each pick (None: compare with ``depth[k]``;
    else with ``depth_by_block[block, k]``, (block, horizon, y, x)).

    >>> x, y = np.array([0.0, 100.0]), np.array([0.0, 100.0])
    >>> surface = np.array([[[1000.0, 1010.0], [1000.0, 1010.0]]])  # dips east, 0.1 m per m
    >>> r = pick_residuals([(0, np.array([[50.0, 50.0, 1007.0], [25.0, 80.0, 1001.5]]), None)], surface, x, y)
    >>> r.surface.tolist(), r.residual.tolist()
    ([1005.0, 1002.5], [2.0, -1.0])
    """
    rows = []
    for k, points, blocks in picks:
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        surface = np.full(pts.shape[0], np.nan)
        if blocks is None or depth_by_block is None:
            surface = interpolate_horizon(xa, ya, depth[k], pts[:, 0], pts[:, 1])
            block = np.full(pts.shape[0], -1, dtype=np.int32)
        else:
            block = np.asarray(blocks, dtype=np.int32)
            for b in np.unique(block[block >= 0]):  # a loop over fault blocks (a few)
                mine = np.flatnonzero(block == b)
                surface[mine] = interpolate_horizon(xa, ya, depth_by_block[b, k], pts[mine, 0], pts[mine, 1])
        rows.append((np.full(pts.shape[0], k, dtype=np.int32), pts, surface, block))
    if not rows:
        empty = np.zeros(0)
        return PickResiduals(np.zeros(0, np.int32), empty, empty, empty, empty, np.zeros(0, np.int32))
    horizon, pts, surface, block = (np.concatenate(parts) for parts in zip(*rows, strict=True))
    return PickResiduals(horizon, pts[:, 0], pts[:, 1], pts[:, 2], surface, block)


def residual_figures(residuals: PickResiduals, names: Sequence[str]) -> dict[str, dict[str, float | int]]:
    """Per horizon with picks (by name): ``picks`` (how many), ``rms`` and ``max_abs`` of their
    residuals (m) where the surface is defined (``undefined``: how many it is not at).

    >>> k, zero = np.zeros(3, np.int32), np.zeros(3)
    >>> r = PickResiduals(k, zero, zero, zero, np.array([1.0, -1.0, np.nan]), k - 1)
    >>> residual_figures(r, ["top"])
    {'top': {'picks': 3, 'rms': 1.0, 'max_abs': 1.0, 'undefined': 1}}
    """
    out: dict[str, dict[str, float | int]] = {}
    res = residuals.residual
    for k in np.unique(residuals.horizon):
        r = res[residuals.horizon == k]
        defined = r[np.isfinite(r)]
        rms = float(np.sqrt(np.mean(defined * defined))) if defined.size else float("nan")
        out[str(names[k])] = {
            "picks": int(r.size),
            "rms": rms,
            "max_abs": float(np.abs(defined).max()) if defined.size else float("nan"),
            "undefined": int(r.size - defined.size),
        }
    return out
