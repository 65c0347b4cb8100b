"""Corner nodes of a corner-point deck: masking, sanity checks, orientation, node ids.

Inactive cells are masked before anything else (their corners, often junk, are
never read). Active corners must be finite. z-up decks are negated to depth.
Every corner gets the id of its distinct depth on its pillar (ids grow with
depth along a pillar), computed one pillar row at a time.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..grid import FloatArray, IntArray
from ..stratigraphic.points import PillarPoints, points_on_pillars, unique_points_rows
from .deck import Deck


@dataclass(frozen=True, eq=False)
class CornerNodes:
    """Node ids of every cell corner and the nodes' coordinates.

    ``nodes[k, j, i, a + 2b + 4c]`` is the node of corner (a, b, c) of cell
    (i, j, k): a, b select the pillar (i + a, j + b), c the top (0) or bottom
    (1); -1 for inactive cells. ``kept`` marks active cells that are not
    collapsed on all four pillars.
    """

    nodes: IntArray  # (nz, ny, nx, 8)
    kept: np.ndarray  # (nz, ny, nx)
    points: PillarPoints
    xyz: FloatArray  # (n_nodes, 3), z is depth
    lines: FloatArray  # (n_pillars, 2, 3) pillars with z as depth
    left_handed: bool
    notes: tuple[str, ...]


def _cell(nx: int, ny: int, flat_corner: int) -> str:
    """1-based (i, j, k) of the cell owning a ZCORN entry of the (2nz, 2ny, 2nx) array."""
    kc, rest = divmod(flat_corner, 4 * nx * ny)
    jc, ic = divmod(rest, 2 * nx)
    return f"({ic // 2 + 1}, {jc // 2 + 1}, {kc // 2 + 1})"


def corner_nodes(deck: Deck, tolerance: float = 0.0) -> CornerNodes:
    src = deck.source
    nx, ny, nz = deck.cart_dims
    notes: list[str] = []
    active = deck.active.reshape(nz, ny, nx)
    if not active.any():
        raise InputError(f"{src}: no active cells (ACTNUM is all 0)")
    act2 = np.repeat(np.repeat(np.repeat(active, 2, axis=0), 2, axis=1), 2, axis=2)
    zc = deck.zcorn_array()
    with np.errstate(invalid="ignore"):
        bad = act2 & ~np.isfinite(zc)
    if bad.any():
        n_bad = len(np.unique(np.flatnonzero(bad.reshape(nz, 2, ny, 2, nx, 2).any(axis=(1, 3, 5)))))
        raise InputError(
            f"{src}: ZCORN: active cell {_cell(nx, ny, int(np.flatnonzero(bad)[0]))} has a non-finite "
            f"corner depth ({n_bad} active cells have NaN or infinite corners)"
        )
    z = np.where(act2, zc, np.nan)
    lines = deck.pillars().reshape(-1, 2, 3).copy()
    col_active = active.any(axis=0)
    pil_used = np.zeros((ny + 1, nx + 1), dtype=bool)
    for a in (0, 1):
        for b in (0, 1):
            pil_used[b : b + ny, a : a + nx] |= col_active
    if not np.isfinite(lines[pil_used.ravel()]).all():
        raise InputError(f"{src}: COORD: a pillar of an active cell is NaN or infinite")

    dz = z[1::2] - z[0::2]  # bottom minus top, per corner of every cell
    with np.errstate(invalid="ignore"):
        pos, neg = int((dz > 0).sum()), int((dz < 0).sum())
    if neg > pos:  # z grows upwards: make it depth
        z, dz = -z, -dz
        lines[:, :, 2] = -lines[:, :, 2]
        notes.append("z decreases with depth in this deck (z up): z was negated to depth")
    with np.errstate(invalid="ignore"):
        inverted = dz < 0
    if inverted.any():
        kc, jc, ic = np.unravel_index(int(np.flatnonzero(inverted)[0]), inverted.shape)
        raise InputError(
            f"{src}: ZCORN: cell ({ic // 2 + 1}, {jc // 2 + 1}, {kc + 1}) has a top corner "
            "below its bottom corner"
        )
    if tolerance < 0:
        raise InputError(f"process_grdecl: tolerance must be >= 0, got {tolerance}")

    # One row of candidate depths per pillar: the 2 x 2 corner columns around it.
    zp = np.full((2 * nz, 2 * ny + 2, 2 * nx + 2), np.nan)
    zp[:, 1:-1, 1:-1] = z
    rows = zp.reshape(2 * nz, ny + 1, 2, nx + 1, 2).transpose(1, 3, 0, 2, 4).reshape((ny + 1) * (nx + 1), -1)
    ids_rows, points = unique_points_rows(rows, tolerance)
    ids = ids_rows.reshape(ny + 1, nx + 1, 2 * nz, 2, 2).transpose(2, 0, 3, 1, 4).reshape(zp.shape)
    nodes = ids[:, 1:-1, 1:-1].reshape(nz, 2, ny, 2, nx, 2).transpose(0, 2, 4, 1, 3, 5).reshape(nz, ny, nx, 8)
    kept = active & ~(nodes[..., :4] == nodes[..., 4:]).all(axis=-1)
    xyz = points_on_pillars(lines, points.pillar, points.z)

    left = _left_handed(lines, active, nx, ny)
    if left:
        notes.append("the deck is left-handed in plan view: every face was reversed")
    return CornerNodes(np.ascontiguousarray(nodes), kept, points, xyz, lines, left, tuple(notes))


def _left_handed(lines: FloatArray, active: np.ndarray, nx: int, ny: int) -> bool:
    """Majority vote over active columns: does (i, j) turn clockwise in plan view?"""
    mid = lines.mean(axis=1)[:, :2].reshape(ny + 1, nx + 1, 2)
    ei = mid[:-1, 1:] - mid[:-1, :-1]
    ej = mid[1:, :-1] - mid[:-1, :-1]
    cross = (ei[..., 0] * ej[..., 1] - ei[..., 1] * ej[..., 0])[active.any(axis=0)]
    return bool((cross < 0).sum() > (cross > 0).sum())
