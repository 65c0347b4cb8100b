"""Transmissibility multipliers of a deck: MULTX/Y/Z(-) and MULTFLT, as OPM Flow applies them.

Unitless factors on transmissibilities, applied after the harmonic mean and before
MULTREGT (:mod:`.region_multipliers`) and the EDIT section (:mod:`.edits`).

Flow keeps one multiplier array per face direction (X+ MULTX, X- MULTX-, Y+ MULTY,
Y- MULTY-, Z+ MULTZ, Z- MULTZ-; 1 where not given) and folds MULTFLT into them: every
cell listed under a fault's FAULTS records with face X has its X+ entry multiplied by
the fault's MULTFLT (the last MULTFLT given for a fault), and so on. A connection's
transmissibility is multiplied by each of its two cells' entries for the side of the
face that cell is on.
"""

from __future__ import annotations

import numpy as np

from ..cornerpoint.deck import Deck
from ..errors import InputError
from ..grid import B, E, N, S, T, W

# Rows of the multiplier array, by logical face tag of the cell's side: W X-, E X+, S Y-, N Y+, T Z-, B Z+
_KEYWORD_OF_TAG = {W: "MULTX-", E: "MULTX", S: "MULTY-", N: "MULTY", T: "MULTZ-", B: "MULTZ"}
_TAG_OF_FAULT_FACE = {"X": E, "X-": W, "Y": N, "Y-": S, "Z": B, "Z-": T}


def directional_multipliers(deck: Deck, notes: list[str]) -> dict[int, np.ndarray] | None:
    """The multiplier (nc,) of every cell for its side W, E, S, N, T or B (tag -> row), for
    the sides a keyword or MULTFLT sets (the others are 1), or None if all are 1."""
    present = [tag for tag, key in _KEYWORD_OF_TAG.items() if key in deck.cell_data]
    faulted = [seg for seg in deck.faults if deck.multflt.get(seg.name, 1.0) != 1.0]
    if not present and not faulted:
        _gridopts_notes(deck, [], notes)
        return None
    nx, ny, _ = deck.cart_dims
    mult = {}
    for tag in present:
        values = deck.cell_data[_KEYWORD_OF_TAG[tag]]
        if not np.isfinite(values).all() or (values < 0).any():
            raise InputError(f"{deck.source}: {_KEYWORD_OF_TAG[tag]}: multipliers must be finite and >= 0")
        mult[tag] = np.array(values, dtype=np.float64)
    if present:
        notes.append("multipliers applied: " + ", ".join(_KEYWORD_OF_TAG[t] for t in present))
    _gridopts_notes(deck, [_KEYWORD_OF_TAG[t] for t in present], notes)
    for seg in faulted:
        ranges = (np.arange(seg.i1, seg.i2 + 1), np.arange(seg.j1, seg.j2 + 1), np.arange(seg.k1, seg.k2 + 1))
        i, j, k = np.meshgrid(*ranges, indexing="ij")
        cells = (i + nx * (j + ny * k)).ravel()
        tag = _TAG_OF_FAULT_FACE[seg.face]
        if tag not in mult:
            mult[tag] = np.ones(deck.num_cells)
        np.multiply.at(mult[tag], cells, deck.multflt[seg.name])
    if faulted:
        names = sorted({seg.name for seg in faulted})
        notes.append(f"MULTFLT applied to the faces of {len(names)} faults: {', '.join(names)}")
    return mult


def side_multipliers(mult: dict[int, np.ndarray], tags: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """The multiplier of each of ``cells`` (linear ijk indices) for its side ``tags``, from
    :func:`directional_multipliers`' rows (1 for the sides it leaves out)."""
    out = np.ones(cells.size)
    for tag, row in mult.items():
        on = np.flatnonzero(tags == tag)
        out[on] = row[cells[on]]
    return out


def _gridopts_notes(deck: Deck, keywords: list[str], notes: list[str]) -> None:
    """GRIDOPTS items OPM Flow 2022.10 does not act on (nor gridlib): TRANMULT NO with
    MULTX-/MULTY-/MULTZ- given (they are applied all the same), NRPINC (PINCHNUM)."""
    options = deck.gridopts
    if options is None:
        return
    negative = [k for k in keywords if k.endswith("-")]
    if negative and not options.tranmult:
        notes.append(f"GRIDOPTS TRANMULT is NO, yet {', '.join(negative)} applied (as OPM Flow 2022.10)")
    if options.nrpinc > 0:
        notes.append(f"GRIDOPTS NRPINC {options.nrpinc}: PINCHNUM regions not used (nor by OPM Flow 2022.10)")
