"""Ordering of a horizon stack: find crossings, or repair them by erosion or onlap."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..grid import FloatArray
from ..pillars.depth_order import ORDERINGS, repair_order
from ._constants import check_choice


@dataclass(frozen=True)
class Crossing:
    """Where horizon ``lower`` lies above horizon ``upper`` (the nearest defined one above it).

    ``nodes``: how many lattice nodes; ``area`` (m2): their tributary areas;
    ``x``, ``y``: the first such node (lowest y, then x); ``max_overlap`` (m):
    the largest ``z[upper] - z[lower]``.
    """

    upper: str
    lower: str
    nodes: int
    area: float
    x: float
    y: float
    max_overlap: float

    def __str__(self) -> str:
        return (
            f"horizons '{self.upper}' and '{self.lower}' cross at {self.nodes} nodes ({self.area:.6g} m2), "
            f"first at (x, y) = ({self.x:.6g}, {self.y:.6g}), by up to {self.max_overlap:.6g} m"
        )


class HorizonCrossingError(InputError):
    """Horizons cross and the ordering is ``"error"``; ``crossings`` lists where."""

    def __init__(self, message: str, crossings: Sequence[Crossing]) -> None:
        super().__init__(message)
        self.crossings = tuple(crossings)


def _tributary(a: FloatArray) -> FloatArray:
    """Length of axis a attributed to each node: half the spacing on either side."""
    if a.size == 1:
        return np.zeros(1)
    d = np.diff(a)
    return np.concatenate([[d[0] / 2], (d[:-1] + d[1:]) / 2, [d[-1] / 2]])


def horizon_names(names: Sequence[str] | None, n: int) -> list[str]:
    """The names of ``n`` horizons: ``names`` checked (distinct, one per horizon) or ``horizon_<k>``."""
    if names is None:
        return [f"horizon_{k}" for k in range(n)]
    out = [str(v) for v in names]
    if len(out) != n:
        raise InputError(f"horizon names: {len(out)} names for {n} horizons")
    if len(set(out)) != n:
        raise InputError(f"horizon names must be distinct, got {out}")
    return out


def depth_stack(depth: ArrayLike, x: ArrayLike, y: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
    """A stack of depth maps (horizons, len(y), len(x)) and its axes as float arrays, checked."""
    H = np.asarray(depth, dtype=np.float64)
    xa, ya = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    if H.ndim != 3 or H.shape[1:] != (ya.size, xa.size):
        raise InputError(
            f"horizons: depth must have shape (horizons, len(y), len(x)) = (n, {ya.size}, {xa.size}), "
            f"got {H.shape}"
        )
    return H, xa, ya


def find_crossings(
    depth: ArrayLike, x: ArrayLike, y: ArrayLike, names: Sequence[str] | None = None
) -> list[Crossing]:
    """The crossings of a stack ``depth`` (horizons, ny, nx), top first, on axes ``x``, ``y`` (m).

    At every node each horizon is compared with the nearest *defined* horizon
    above it; equal depths (zero thickness) do not cross.

    >>> x, y = np.linspace(0.0, 1000.0, 11), np.linspace(0.0, 500.0, 6)
    >>> X, Y = np.meshgrid(x, y)
    >>> print(find_crossings([1000.0 + 0.02 * X, np.full_like(X, 1010.0)], x, y, ["top", "base"])[0])
    horizons 'top' and 'base' cross at 30 nodes (225000 m2), first at (x, y) = (600, 0), by up to 10 m
    """
    H, xa, ya = depth_stack(depth, x, y)
    label = horizon_names(names, H.shape[0])
    defined = np.isfinite(H)
    idx = np.where(defined, np.arange(H.shape[0])[:, None, None], -1)
    last = np.maximum.accumulate(idx, axis=0)  # nearest defined horizon at or above
    area = _tributary(ya)[:, None] * _tributary(xa)[None, :]
    out = []
    for k in range(1, H.shape[0]):
        ref = last[k - 1]
        zref = np.take_along_axis(H, np.maximum(ref, 0)[None], axis=0)[0]
        with np.errstate(invalid="ignore"):
            bad = defined[k] & (ref >= 0) & (H[k] < zref)
        for j in np.unique(ref[bad]):
            m = bad & (ref == j)
            first = int(np.flatnonzero(m)[0])
            out.append(
                Crossing(
                    label[int(j)],
                    label[k],
                    int(m.sum()),
                    float(area[m].sum()),
                    float(xa[first % xa.size]),
                    float(ya[first // xa.size]),
                    float((zref - H[k])[m].max()),
                )
            )
    return out


def order_horizons(
    depth: ArrayLike,
    x: ArrayLike,
    y: ArrayLike,
    *,
    ordering: str = "error",
    names: Sequence[str] | None = None,
) -> tuple[FloatArray, tuple[str, ...]]:
    """Check or repair the order of a stack ``depth`` (horizons, ny, nx), top first (m, z depth).

    Returns the (repaired) stack and notes saying what moved. ``"error"``
    raises :class:`HorizonCrossingError`; ``"erode"`` and ``"onlap"`` repair
    (module docstring). Undefined (NaN) nodes stay undefined and are skipped.

    >>> x, y = np.linspace(0.0, 1000.0, 11), np.linspace(0.0, 500.0, 6)
    >>> X, _ = np.meshgrid(x, y)
    >>> H, notes = order_horizons([1000.0 + 0.02 * X, np.full_like(X, 1010.0)], x, y, ordering="erode")
    >>> float((H[1] - H[0]).min()), notes[0]
    (0.0, "ordering 'erode': horizon 'horizon_1' moved down to a horizon above it at 30 nodes")
    """
    ordering = check_choice(ordering, ORDERINGS, "ordering")
    H, xa, ya = depth_stack(depth, x, y)
    label = horizon_names(names, H.shape[0])
    crossings = find_crossings(H, xa, ya, label)
    if not crossings:
        return H.copy(), ()
    if ordering == "error":
        raise HorizonCrossingError(
            "horizons cross: "
            + "; ".join(map(str, crossings))
            + " (set ordering to 'erode' or 'onlap' to repair)",
            crossings,
        )
    fixed, moved_nodes = repair_order(H, ordering)
    notes = []
    for k in range(H.shape[0]):
        moved = int(moved_nodes[k])
        if moved:
            where = "down to a horizon above" if ordering == "erode" else "up to a horizon below"
            notes.append(f"ordering '{ordering}': horizon '{label[k]}' moved {where} it at {moved} nodes")
    return fixed, tuple(notes)
