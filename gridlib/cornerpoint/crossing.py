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
Columns whose pillars cannot cross within the depths of their nodes are screened out first
(:func:`_safe_columns`: on the cornerpoint bench's 1e6-cell deck, every column), so the cost is
that of the columns where pillars lean by a fair part of a cell.
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


def _turns(ex: np.ndarray, ey: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """At each corner m of quadrilaterals with edges (ex, ey) (4, m) from corner m to m + 1: the
    turn (cross product of the edges arriving and leaving) and the two edges' lengths."""
    bx, by = np.roll(ex, 1, axis=0), np.roll(ey, 1, axis=0)
    return bx * ey - by * ex, np.hypot(bx, by), np.hypot(ex, ey)


def _safe_columns(cn: CornerNodes, sign: float) -> np.ndarray:
    """Columns (ny, nx) that no crossing can reach: along the depths of its nodes each pillar's
    (x, y) stays within a disc (about the midpoint of its first and last node: pillars are
    straight); if the quadrilateral of the four discs' centres turns the right way at every
    corner by more than any points in the discs could change it, no cell of the column turns
    the wrong way. Only the cells of other columns are looked at one by one."""
    _, nyp, nxp = cn.cells.shape
    ny, nx = nyp - 2, nxp - 2
    offset = cn.points.offset
    has = offset[1:] > offset[:-1]
    first, last = (
        cn.xyz[np.minimum(offset[:-1], offset[-1] - 1), :2],
        cn.xyz[np.maximum(offset[1:] - 1, 0), :2],
    )
    centre = 0.5 * (first + last)
    radius = np.where(has, 0.5 * np.hypot(*(last - first).T), np.inf).reshape(ny + 1, nx + 1)
    centre = centre.reshape(ny + 1, nx + 1, 2)
    corners = [(0, 0), (1, 0), (1, 1), (0, 1)]  # (a, b) around the column, as _CYCLE
    c = np.stack([centre[b : b + ny, a : a + nx] for a, b in corners])  # (4, ny, nx, 2)
    r = np.stack([radius[b : b + ny, a : a + nx] for a, b in corners])
    turn, before, after = _turns(
        np.roll(c[..., 0], -1, axis=0) - c[..., 0], np.roll(c[..., 1], -1, axis=0) - c[..., 1]
    )
    reach_before = np.roll(r, 1, axis=0) + r  # how far the edges' ends may move
    reach_after = r + np.roll(r, -1, axis=0)
    with np.errstate(invalid="ignore"):  # a pillar without nodes: an infinite reach, never safe
        margin = before * reach_after + reach_before * after + reach_before * reach_after
        return (sign * turn > margin).all(axis=0)


def crossing_cells(cn: CornerNodes) -> np.ndarray:
    """The kept cells of ``cn`` (numbered as ``cn.cells``) whose corners turn the wrong way at two
    or more corners of their top or bottom, in plan view (the pillars around them cross)."""
    sign = -1.0 if cn.left_handed else 1.0
    linear = np.flatnonzero(cn.kept & ~_safe_columns(cn, sign))  # the cells to look at, (k, j, i)
    _, nyp, nxp = cn.cells.shape
    k, rest = np.divmod(linear, (nyp - 2) * (nxp - 2))
    j, i = np.divmod(rest, nxp - 2)
    in_table = (k * nyp + j + 1) * nxp + i + 1  # on the padded layout of cn.table
    table = cn.table.reshape(8, -1)
    x, y = cn.xyz[:, 0], cn.xyz[:, 1]
    bad = np.zeros(in_table.size, dtype=bool)
    for start in range(0, in_table.size, _CHUNK):
        part = in_table[start : start + _CHUNK]
        for level in (0, 4):
            nodes = table[_CYCLE + level][:, part]  # (4, m) corners around the column
            ex = np.roll(x[nodes], -1, axis=0) - x[nodes]  # edge m -> m + 1
            ey = np.roll(y[nodes], -1, axis=0) - y[nodes]
            turn, before, after = _turns(ex, ey)
            wrong = sign * turn < -_RELATIVE * before * after  # the other way, beyond rounding
            bad[start : start + _CHUNK] |= np.count_nonzero(wrong, axis=0) >= 2
    return cn.cells[:, 1:-1, 1:-1].ravel()[linear[bad]]


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
