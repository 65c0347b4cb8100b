"""Pillars that cross: a corner-point deck whose cells overlap their neighbours.

The four pillars of a column bound its cells in plan view. Where two pillars cross between
their top and bottom points, the cells below the crossing are turned inside out in plan view
and overlap the cells beside them: no volume, face or transmissibility computed from them
means anything, and no tolerance makes such a deck valid (unlike a thin wedge, whose geometry is
merely degenerate: :func:`gridlib.checks.check_deck_grid`). Since pillars are straight lines,
it is enough to look at each cell's top and bottom: its four corners there, in plan view,
must turn the way the deck's (i, j) frame turns (anticlockwise, or clockwise for a left-handed
deck) at every corner but at most one (a concave cell is fine; a cell whose corners are
reversed or form a bow tie is not). Corners on coincident pillars (no turn) are fine.
"""

from __future__ import annotations

import numpy as np

from ..cell_names import cell_names
from ..errors import InputError
from .corners import CornerNodes

_RELATIVE = 1e-9  # a turn below this fraction of its two edges' lengths' product is no turn
_CHUNK = 1 << 18  # cells per block: the gathered corners stay small

# Corner slots a + 2b (+ 4 at the bottom) in cyclic order around a column: (0, 0), (1, 0), (1, 1), (0, 1).
_CYCLE = np.array([0, 1, 3, 2])


def crossing_cells(cn: CornerNodes) -> np.ndarray:
    """The kept cells of ``cn`` (numbered as ``cn.cells``) whose corners turn the wrong way at two
    or more corners of their top or bottom, in plan view (the pillars around them cross)."""
    inner = cn.table[:, :, 1:-1, 1:-1][:, cn.kept]  # (8, n) node ids of the kept cells
    sign = -1.0 if cn.left_handed else 1.0
    bad = np.zeros(inner.shape[1], dtype=bool)
    for start in range(0, inner.shape[1], _CHUNK):
        part = inner[:, start : start + _CHUNK]
        for level in (0, 4):
            xy = cn.xyz[part[_CYCLE + level], :2]  # (4, m, 2) corners around the column
            edge = np.roll(xy, -1, axis=0) - xy  # edge from corner m to m + 1
            before = np.roll(edge, 1, axis=0)  # edge arriving at corner m
            turn = before[..., 0] * edge[..., 1] - before[..., 1] * edge[..., 0]
            scale = np.hypot(*before.transpose(2, 0, 1)) * np.hypot(*edge.transpose(2, 0, 1))
            wrong = sign * turn < -_RELATIVE * scale
            bad[start : start + _CHUNK] |= wrong.sum(axis=0) >= 2
    return np.flatnonzero(bad)


def check_pillars_do_not_cross(cn: CornerNodes, cart_dims: tuple[int, int, int], source: str) -> None:
    """Raise an InputError naming ``source`` and the first cells (i, j, k) if pillars cross
    (:func:`crossing_cells`)."""
    bad = crossing_cells(cn)
    if bad.size:
        linear = np.flatnonzero(cn.kept.ravel())[bad]  # kept cells are numbered in (k, j, i) order
        raise InputError(
            f"{source}: COORD: pillars cross: {bad.size} cells are turned inside out in plan view and "
            f"overlap their neighbours: {cell_names(np.arange(linear.size), linear, cart_dims)} "
            "(the pillars at their corners cross between their top and bottom points)"
        )
