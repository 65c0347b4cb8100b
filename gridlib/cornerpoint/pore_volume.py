"""Pore volumes and active cells of a corner-point deck, as OPM Flow 2022.10 decides them.

The rules (each one checked against Flow's dry run in
``tests/transmissibility/test_flow_activity.py``; ``docs/transmissibility.md``, "Which
cells are active: Flow's rules"):

1. **Pore volume** of a cell, in the deck's reservoir volume unit (METRIC rm3, FIELD rb,
   LAB rcc, PVT-M rm3): the PORV the EDIT section gives it, else bulk volume x PORO x
   NTG x MULTPV (bulk volume: :mod:`.volumes`, in the deck's length unit cubed, converted).
   Flow reads PORV only in EDIT (the reader ignores it in GRID and keeps NaN where the
   EDIT section leaves a cell to Flow), and the MULTPV of a cell is the one in force when
   the EDIT section first touches PORV (the reader stores that one).
2. **Zero pore volume**: an ACTNUM-active cell whose pore volume is 0 because PORO, NTG,
   MULTPV or its PORV is 0, or because PORO is undefined there (no PORV either: Flow's
   pore volume is then 0; Flow fills PORO below a keyword's top layer from it, as the
   reader does), is inactive, exactly as if ACTNUM were 0 there: no connection
   to it, none across it by MINPV or PINCH that an ACTNUM 0 cell would not give. A cell
   of zero bulk volume (collapsed on all four pillars) is not deactivated by this rule:
   the corner-point processing removes it, and under MINPV (its pore volume, 0, is below
   any threshold) it is a cell removed by MINPV, bridged like one. A negative pore volume
   stays active in Flow; gridlib refuses it (:class:`~gridlib.errors.InputError`).
3. **MINPV**: an active cell whose pore volume is below the threshold (strictly) is
   removed; MINPV or MINPORV give one threshold for every cell, MINPVV one per cell (used
   only without MINPV/MINPORV). Removed cells are bridged by Flow's MinpvProcessor
   (:mod:`gridlib.transmissibility.pinch`), unlike zero-pore-volume cells.

A deck without PORO and PORV (a grid-only GRDECL) has no pore volume: its activity is its
ACTNUM, and neither rule 2 nor MINPV applies.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..cell_names import ijk_text as cell_ijk_text
from ..errors import InputError
from ..grid import FloatArray, IntArray
from ..units import unit_system
from .corners import corner_points, depth_sign
from .deck import Deck
from .volumes import hexahedron_volumes

_CHUNK = 1 << 16  # cells whose corners are gathered at once


def has_pore_volume(deck: Deck) -> bool:
    """Whether the deck defines pore volumes (PORO or PORV)."""
    return "PORO" in deck.cell_data or "PORV" in deck.cell_data


def volume_unit(deck: Deck) -> float:
    """Reservoir volume units per cubed length unit of the deck (METRIC 1, FIELD ft3 -> rb)."""
    return unit_system(deck.units).volume_per_cubic_length


def pore_volume_factors(deck: Deck, cells: IntArray | slice = slice(None)) -> FloatArray:
    """PORO x NTG x MULTPV of ``cells``, what multiplies the bulk volume where the deck gives
    no PORV; 0 where PORO is undefined (NaN), as Flow's pore volume there."""
    data = deck.cell_data
    factor = data["PORO"][cells] if "PORO" in data else np.full(deck.num_cells, np.nan)[cells]
    for name in ("NTG", "MULTPV"):
        if name in data:
            factor = factor * data[name][cells]
    return np.where(np.isnan(factor), 0.0, factor)


def zero_pore_volume(deck: Deck) -> np.ndarray:
    """Per deck cell: ACTNUM-active cells whose pore volume is 0 whatever their bulk volume
    (PORV 0, or PORO x NTG x MULTPV 0 or undefined); no geometry needed."""
    if not has_pore_volume(deck):
        return np.zeros(deck.num_cells, dtype=bool)
    porv = deck.cell_data.get("PORV")
    factor = pore_volume_factors(deck)
    zero = factor == 0 if porv is None else np.where(np.isnan(porv), factor == 0, porv == 0)
    return zero & deck.active


def with_flow_activity(deck: Deck) -> Deck:
    """``deck`` with ACTNUM 0 where the pore volume is 0 whatever the geometry (rule 2);
    the same deck if there are none. A note says how many."""
    zero = zero_pore_volume(deck)
    if not zero.any():
        return deck
    note = f"{int(zero.sum())} ACTNUM-active cells have zero pore volume: inactive (as OPM Flow)"
    return replace(deck, actnum=(deck.active & ~zero).astype(np.int32), notes=(*deck.notes, note))


def bulk_volumes(deck: Deck, cells: IntArray) -> FloatArray:
    """|bulk volume| of ``cells`` (deck length unit cubed) from their corners (:mod:`.volumes`)."""
    cells = np.asarray(cells, dtype=np.int64)
    sign = depth_sign(deck)
    out = np.empty(cells.size)
    for start in range(0, cells.size, _CHUNK):
        part = cells[start : start + _CHUNK]
        pts = corner_points(deck, part, sign).reshape(-1, 3)
        table = np.arange(8 * part.size).reshape(part.size, 8).T
        out[start : start + _CHUNK] = np.abs(hexahedron_volumes(pts, table))
    return out


def pore_volumes(deck: Deck, cells: IntArray, bulk: FloatArray | None = None) -> FloatArray:
    """Flow's pore volume of ``cells`` (linear ijk indices), deck reservoir volume unit.

    ``bulk``: their bulk volumes (deck length unit cubed; computed from the corners if
    None). 0 where neither PORV nor PORO is defined.
    """
    cells = np.asarray(cells, dtype=np.int64)
    porv = deck.cell_data.get("PORV")
    computed = np.ones(cells.size, dtype=bool) if porv is None else np.isnan(porv[cells])
    pv = np.empty(cells.size)
    if porv is not None:
        pv[~computed] = porv[cells[~computed]]
    if computed.any():
        where = cells[computed]
        factor = pore_volume_factors(deck, where)
        volume = bulk_volumes(deck, where) if bulk is None else np.abs(np.asarray(bulk)[computed])
        pv[computed] = volume * factor * volume_unit(deck)
    return pv


def flow_pore_volumes(deck: Deck) -> tuple[np.ndarray, FloatArray]:
    """Per deck cell: Flow's activity before MINPV (ACTNUM, rule 2) and the pore volume (0
    where inactive; 0 too for active cells of zero bulk volume). Without PORO and PORV:
    ACTNUM, and NaN volumes."""
    active = deck.active & ~zero_pore_volume(deck)
    if not has_pore_volume(deck):
        return active, np.full(deck.num_cells, np.nan)
    cells = np.flatnonzero(active)
    pv = np.zeros(deck.num_cells)
    pv[cells] = pore_volumes(deck, cells)
    return active, pv


def minimum_pore_volumes(deck: Deck, minpv: float | None = None) -> FloatArray | None:
    """MINPV's threshold per deck cell (deck reservoir volume unit), or None without one.

    ``minpv``: one threshold for every cell instead of the deck's (0 turns MINPV off).
    The deck's: MINPV (or MINPORV), else MINPVV (per cell; all cells must be given).
    """
    if minpv is not None:
        if minpv < 0 or not np.isfinite(minpv):
            raise InputError(f"{deck.source}: minpv must be a finite value >= 0, got {minpv}")
        return np.full(deck.num_cells, float(minpv)) if minpv > 0 else None
    if deck.minpv is not None:
        return np.full(deck.num_cells, float(deck.minpv))
    per_cell = deck.cell_data.get("MINPVV")
    if per_cell is None:
        return None
    if np.isnan(per_cell).any():
        first = int(np.flatnonzero(np.isnan(per_cell))[0])
        raise InputError(
            f"{deck.source}: MINPVV: not given for every cell (first missing: cell "
            f"{ijk_text(deck, first)}); OPM Flow 2022.10 reads MINPVV only as a whole array"
        )
    return per_cell


def ijk_text(deck: Deck, g: int) -> str:
    """'(i, j, k)', 1-based, of the deck's linear cell index ``g``."""
    return cell_ijk_text(g, deck.cart_dims)
