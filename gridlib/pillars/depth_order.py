"""The depth order of a horizon stack: check it, or repair it by erosion or onlap.

Horizons are listed top (youngest) first and z is depth, positive downwards, so
a stack is in order where every horizon is at least as deep as the ones above
it. Where it is not, two horizons *cross*. A crossing is either an error or is
repaired, never by sorting (which would move volume from one zone to another):

* ``"erode"`` (the younger horizon wins): every horizon is clamped to at least
  the depth of all defined horizons above it, a top-down running maximum;
* ``"onlap"`` (the older horizon wins): every horizon is clamped to at most the
  depth of all defined horizons below it, a bottom-up running minimum.

Undefined (NaN) depths stay undefined and are skipped by both. :func:`repair_order`
is the one repair, used by the pillar front ends (:func:`order_depths`) and by
:func:`gridlib.horizons.order_horizons`, which find crossings each in their own
way and word their own messages.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..errors import InputError
from ..grid import FloatArray, IntArray

__all__ = ["ORDERINGS", "order_depths", "repair_order"]

ORDERINGS = ("error", "erode", "onlap")


def repair_order(H: FloatArray, ordering: str) -> tuple[FloatArray, IntArray]:
    """The stack ``H`` (n_horizons, ...) repaired by ``ordering`` (``"erode"`` or ``"onlap"``), and
    the number of defined nodes of each horizon that moved.

    >>> fixed, moved = repair_order(np.array([[10.0, 5.0], [8.0, np.nan], [9.0, 6.0]]), "erode")
    >>> fixed.tolist(), moved.tolist()
    ([[10.0, 5.0], [10.0, nan], [10.0, 6.0]], [0, 1, 1])
    >>> repair_order(np.array([[10.0, 5.0], [8.0, np.nan], [9.0, 6.0]]), "onlap")[0].tolist()
    [[8.0, 5.0], [8.0, nan], [9.0, 6.0]]
    """
    if ordering not in ("erode", "onlap"):
        raise ValueError(f"repair_order: ordering must be 'erode' or 'onlap', got {ordering!r}")
    defined = np.isfinite(H)
    if ordering == "erode":  # younger wins: top-down running maximum over the defined horizons
        fixed = np.fmax.accumulate(H, axis=0)
    else:  # onlap, older wins: bottom-up running minimum
        fixed = np.fmin.accumulate(H[::-1], axis=0)[::-1]
    fixed = np.where(defined, fixed, np.nan)
    changed = defined & (fixed != H)
    return fixed, changed.reshape(changed.shape[0], -1).sum(axis=1)


def order_depths(
    H: FloatArray,
    ordering: str,
    x: FloatArray,
    y: FloatArray,
    notes: list[str],
    who: str = "horizons_to_grdecl",
    where: str = "pillar nodes",
) -> FloatArray:
    """Check or repair the depth order of the horizons ``H`` (n_horizons, ...) at the pillars, whose
    plan-view positions are ``x``, ``y`` (``H[h]``'s shape).

    Two consecutive horizons cross where both are defined and the lower one is
    shallower. ``"error"`` raises an :class:`~gridlib.errors.InputError` naming
    every crossing pair, its number of points and the first one (x, y);
    ``"erode"`` and ``"onlap"`` repair (:func:`repair_order`) and append a note
    per horizon moved to ``notes``. ``who`` and ``where`` name the caller and the
    points in messages.

    >>> notes = []
    >>> order_depths(np.array([[10.0, 5.0], [8.0, 6.0]]), "erode", np.array([0.0, 1.0]), np.zeros(2), notes)
    array([[10.,  5.],
           [10.,  6.]])
    >>> notes
    ["ordering='erode': horizon 1 was moved to the horizon above it at 1 pillar nodes"]
    """
    if ordering == "error":
        defined = np.isfinite(H)
        with np.errstate(invalid="ignore"):
            crossing = defined[1:] & defined[:-1] & (H[1:] < H[:-1])
        if crossing.any():
            parts = "; ".join(_crossing_parts(crossing, x, y, where))
            raise InputError(f"{who}: {parts}; pass ordering='erode' or 'onlap' to repair")
        return H
    fixed, moved = repair_order(H, ordering)
    for h in np.flatnonzero(moved):
        notes.append(
            f"ordering='{ordering}': horizon {h} was moved to the "
            f"{'horizon above' if ordering == 'erode' else 'horizon below'} it at "
            f"{int(moved[h])} {where}"
        )
    return fixed


def _crossing_parts(crossing: np.ndarray, x: FloatArray, y: FloatArray, where: str) -> Sequence[str]:
    """One phrase per pair of consecutive horizons that cross (``crossing[h]``: where h + 1 lies
    above h)."""
    parts = []
    for h in np.flatnonzero(crossing.reshape(crossing.shape[0], -1).any(axis=1)):
        first = int(np.flatnonzero(crossing[h])[0])
        parts.append(
            f"horizons {h} and {h + 1} cross at {int(crossing[h].sum())} {where} "
            f"(horizon {h + 1} above horizon {h}), first at (x, y) = "
            f"({x.flat[first]:g}, {y.flat[first]:g})"
        )
    return parts
