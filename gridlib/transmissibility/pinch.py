"""Vertical connections across removed layers, as OPM Flow 2022.10 makes them.

Two mechanisms join the active cells above and below cells that are not in the grid:

* **PINCH**: cells of zero thickness (inactive, or active but collapsed) lie between
  two active cells whose bottom and top faces therefore coincide. The processed grid
  has that face; Flow connects across it only when the deck has PINCH. A removed layer
  of any non-zero thickness leaves a gap and no connection: Flow 2022.10 reads PINCH's
  threshold and maximum gap but does not use them here (ECLIPSE connects across
  inactive layers thinner than the threshold), nor its item 4 (TOPBOT/ALL).
* **MINPV** (also without PINCH): each active cell whose pore volume is below MINPV
  is removed column by column from the top, and an NNC joins the cell above it to the
  cell below it, skipping inactive cells not thicker than the PINCH threshold (0
  without PINCH). With GAP (the default) runs of removed cells are skipped as well;
  with NOGAP only removed cells thinner than the threshold are. The pair is connected
  only if both ends are active and above MINPV. This follows Flow's MinpvProcessor,
  including two details of 2022.10: the search upwards for the cell above stops at
  layer 1 (never reaching layer 0), and the search downwards judges "thin" by the
  thickness of the cell above.

Cells of zero pore volume (PORO, NTG, MULTPV or PORV 0) are inactive cells here, exactly
as ACTNUM 0 ones (:mod:`gridlib.cornerpoint.pore_volume`); MINPV's threshold may be one
per cell (MINPVV), and the search below compares with the removed cell's own threshold.

Such a connection's transmissibility is the ordinary harmonic mean of the PERMZ halves
of its two cells (no NTG), to their own bottom and top face centres, through the upper
cell's bottom face; the removed cells add no resistance. Its Z multiplier is MULTZ of
the upper cell (PINCH item 5 TOP) or the smallest MULTZ from the upper cell down to the
last cell before the lower one (ALL), times MULTZ- of the lower cell.
"""

from __future__ import annotations

import numpy as np

from ..cornerpoint.deck import Deck
from ..cornerpoint.pore_volume import flow_pore_volumes, has_pore_volume, minimum_pore_volumes
from ..grid import IntArray


def cell_thickness(deck: Deck, cells: IntArray) -> np.ndarray:
    """Mean depth of the 4 bottom corners minus that of the 4 top corners (Flow's thickness)."""
    nx, ny, _ = deck.cart_dims
    g = np.asarray(cells, dtype=np.int64)
    i, j, k = g % nx, (g // nx) % ny, g // (nx * ny)
    zc = deck.zcorn_array()
    top = (zc[2 * k, 2 * j, 2 * i] + zc[2 * k, 2 * j, 2 * i + 1]) + (
        zc[2 * k, 2 * j + 1, 2 * i] + zc[2 * k, 2 * j + 1, 2 * i + 1]
    )
    bottom = (zc[2 * k + 1, 2 * j, 2 * i] + zc[2 * k + 1, 2 * j, 2 * i + 1]) + (
        zc[2 * k + 1, 2 * j + 1, 2 * i] + zc[2 * k + 1, 2 * j + 1, 2 * i + 1]
    )
    return np.abs(bottom - top) / 4.0


def minpv_connections(deck: Deck, minpv: float | None = None) -> IntArray:
    """The (n, 2) linear cell pairs (upper, lower) Flow joins across cells removed by MINPV.

    Activity and pore volumes are Flow's (:func:`~gridlib.cornerpoint.pore_volume.flow_pore_volumes`:
    cells of zero pore volume count as inactive); ``minpv`` overrides the deck's threshold
    (MINPV, MINPORV or the per-cell MINPVV)."""
    threshold = minimum_pore_volumes(deck, minpv)
    if threshold is None or not has_pore_volume(deck):
        return np.zeros((0, 2), dtype=np.int64)
    nx, ny, nz = deck.cart_dims
    ncol = nx * ny
    flow_active, pv_all = flow_pore_volumes(deck)
    active = flow_active.reshape(nz, ncol)
    removed = (active & (pv_all.reshape(nz, ncol) < threshold.reshape(nz, ncol))).ravel()
    cols = np.unique(np.flatnonzero(removed) % ncol)
    if cols.size == 0:
        return np.zeros((0, 2), dtype=np.int64)
    ids = np.arange(nz)[:, None] * ncol + cols[None, :]  # (nz, m) cells of the affected columns
    act = active[:, cols]
    pv = pv_all[ids]
    limit = threshold[ids]
    thick = cell_thickness(deck, ids.ravel()).reshape(ids.shape)
    ztol = float(deck.pinch[0]) if deck.pinch is not None else 0.0
    nogap = deck.pinch is not None and deck.pinch_options[0] == "NOGAP"
    small = pv < limit
    significant = pv > limit
    inactive = ~act
    # next k' >= k of a predicate along each column (nz where none)
    skip_below = ~(inactive & (thick <= ztol))
    found_broad = (act & (significant | nogap)) | inactive  # the search below, when "broad"
    found_thin = act & significant  # ... when not
    next_kept, next_broad, next_thin = (_next_true(p) for p in (skip_below, found_broad, found_thin))
    broad = thick > ztol
    found_above = (act & (significant | (nogap & broad))) | (inactive & broad)
    prev_above = _prev_true(found_above)

    pairs = []
    for kk in range(1, nz):  # a removed cell in layer 0 makes no connection
        col = np.flatnonzero(act[kk] & small[kk])
        if col.size == 0 or kk + 1 == nz:
            continue
        kb = next_kept[kk + 1, col]
        col, kb = col[kb < nz], kb[kb < nz]
        ka = np.full(col.size, kk - 1)
        thin_a = thick[kk - 1, col] < ztol
        search_a = (inactive[kk - 1, col] & thin_a) | (
            act[kk - 1, col] & small[kk - 1, col] & (~nogap | thin_a)
        )
        if kk - 2 >= 1:
            hit = prev_above[kk - 2, col]
            ka = np.where(search_a, np.where(hit >= 1, hit, 1), ka)
        thin_b = thick[kb, col] < ztol
        small_b = pv[kb, col] < limit[kk, col]  # the removed cell's threshold (as Flow)
        search_b = (inactive[kb, col] & thin_b) | (act[kb, col] & small_b & (~nogap | thin_b))
        start = kb + 1
        can = search_b & (start < nz)
        start_c = np.minimum(start, nz - 1)
        hit_b = np.where(thick[ka, col] > ztol, next_broad[start_c, col], next_thin[start_c, col])
        kb = np.where(can, np.where(hit_b < nz, hit_b, nz - 1), kb)
        ok = act[ka, col] & act[kb, col] & significant[ka, col] & significant[kb, col]
        pairs.append(np.column_stack([ids[ka[ok], col[ok]], ids[kb[ok], col[ok]]]))
    if not pairs:
        return np.zeros((0, 2), dtype=np.int64)
    return np.unique(np.concatenate(pairs), axis=0)


def _next_true(p: np.ndarray) -> np.ndarray:
    """(nz, m): the first k' >= k with p[k'] true in each column, nz where none."""
    nz = p.shape[0]
    out = np.full(p.shape, nz, dtype=np.int64)
    nxt = np.full(p.shape[1], nz, dtype=np.int64)
    for k in range(nz - 1, -1, -1):
        nxt = np.where(p[k], k, nxt)
        out[k] = nxt
    return out


def _prev_true(p: np.ndarray) -> np.ndarray:
    """(nz, m): the last k' <= k with p[k'] true in each column, -1 where none."""
    out = np.full(p.shape, -1, dtype=np.int64)
    prv = np.full(p.shape[1], -1, dtype=np.int64)
    for k in range(p.shape[0]):
        prv = np.where(p[k], k, prv)
        out[k] = prv
    return out
