"""What OPM Flow 2022.10 does to the transmissibilities it has computed, in its order.

After the grid's connections have their transmissibility with MULTX/.../MULTFLT and
MULTREGT applied (one value per cell pair), Flow, and :func:`apply_deck_edits`:

1. makes a connection of transmissibility 0 for every NNC-keyword pair the grid does
   not connect (both cells in the grid);
2. replays the EDIT section's operations on TRANX, TRANY and TRANZ in deck order
   (SET = the keyword itself, EQUALS, MULTIPLY, ADD, MINVALUE = at least, MAXVALUE = at
   most), on logical neighbours only: TRANX of cell g is the connection (g, g + 1) if
   nx > 1, TRANY (g, g + nx) if ny > 1, TRANZ (g, g + nx ny); fault connections between
   such cells are edited, pinch-outs and other pairs are not;
3. applies EDITNNC: a record's multiplier multiplies the NNC keyword's values for the
   same pair if there are any (not the grid's own transmissibility of that pair),
   otherwise the grid's connection between the two cells, if there is one (else it is
   ignored, noted). Records with a multiplier of 1 or an inactive cell are skipped, and
   so are pairs Flow takes for neighbours: index difference 0, 1, nx or, **a quirk of
   2022.10**, ny (where nx ny is meant), so EDITNNC does multiply the vertical
   neighbour connections and skips pairs ny apart. **Another quirk**: Flow matches the
   sorted EDITNNC records against the sorted NNC records in one pass, so of several
   records for the NNC keyword's last pair (by index) only the first multiplies its
   value; the others multiply the grid's connection of that pair (records in deck
   order; Flow's unstable sort may order equal pairs otherwise beyond 16 records);
4. adds each NNC-keyword value (after EDITNNC) to its pair's transmissibility; no
   MULT*, MULTREGT or TRAN edit applies to that value (but EDIT TRAN operations do
   apply to a 0 connection the NNC keyword made between logical neighbours). Records
   with an inactive cell, or a cell the grid has removed (MINPV, collapsed), are
   skipped (noted);
5. sets every connection that is not between logical neighbours (index difference
   1, nx or nx ny) and has a transmissibility below 1e-6 deck units to 0.

Connections of transmissibility 0 are then left out (negative ones too, noted). All
values are in the deck's transmissibility unit (:mod:`gridlib.units`): NNC values and
the operands of EQUALS/ADD/MINVALUE/MAXVALUE as the deck gives them.
"""

from __future__ import annotations

import numpy as np

from ..cornerpoint.connection_keywords import CellPairs
from ..cornerpoint.deck import Deck
from ..grid import FloatArray, IntArray
from .connections import NEIGHBOR, OTHER

NNC_THRESHOLD = 1e-6  # deck units: non-neighbour connections below this are set to 0 (Flow)


def per_pair(
    cells: IntArray, trans: FloatArray, kind: np.ndarray, face: IntArray
) -> tuple[IntArray, FloatArray, np.ndarray, IntArray]:
    """One entry per cell pair (first < second), sorted by pair: faces between the same two
    cells added (parallel paths), the smallest kind and the first entry's face kept."""
    cells = np.sort(np.asarray(cells, dtype=np.int64).reshape(-1, 2), axis=1)
    order = np.argsort(_keys(cells[:, 0], cells[:, 1], int(cells.max(initial=0)) + 1), kind="stable")
    cells, trans, kind, face = cells[order], trans[order], kind[order], face[order]
    first = np.ones(order.size, dtype=bool)
    first[1:] = (cells[1:] != cells[:-1]).any(axis=1)
    if first.all():
        return cells, trans, kind, face
    group = np.cumsum(first) - 1
    starts = np.flatnonzero(first)
    total = np.bincount(group, trans, starts.size)
    kmin = np.full(starts.size, 127, dtype=np.int8)
    np.minimum.at(kmin, group, kind)
    return cells[starts], total, kmin, face[starts]


def logical_neighbors(g1: np.ndarray, g2: np.ndarray, dims: tuple[int, int, int]) -> np.ndarray:
    """Whether linear indices differ by 1, nx or nx ny (Flow's test for a neighbour pair)."""
    nx, ny, _ = dims
    step = np.abs(g2 - g1)
    return (step == 1) | (step == nx) | (step == nx * ny)


def _keys(lo: IntArray, hi: IntArray, n: int) -> IntArray:
    return np.asarray(lo, dtype=np.int64) * n + np.asarray(hi, dtype=np.int64)


def _ordered(pairs: IntArray) -> tuple[IntArray, IntArray]:
    return np.minimum(pairs[:, 0], pairs[:, 1]), np.maximum(pairs[:, 0], pairs[:, 1])


def _find(sorted_keys: IntArray, wanted: IntArray) -> tuple[IntArray, np.ndarray]:
    """Positions of ``wanted`` in ``sorted_keys`` and whether each is there."""
    if sorted_keys.size == 0:
        return np.zeros(wanted.size, dtype=np.int64), np.zeros(wanted.size, dtype=bool)
    at = np.minimum(np.searchsorted(sorted_keys, wanted), sorted_keys.size - 1)
    return at, sorted_keys[at] == wanted


def nnc_keyword_values(deck: Deck, notes: list[str]) -> tuple[IntArray, FloatArray, IntArray, FloatArray]:
    """Flow's input NNCs and EDITNNC: the NNC keyword's pairs (lo, hi linear indices,
    sorted) with their values after EDITNNC, and the EDITNNC multipliers left for the
    grid's own connections (pairs, product per pair)."""
    nc = deck.num_cells
    active = deck.active
    empty = CellPairs(np.zeros((0, 2), np.int64), np.zeros(0))
    nnc = deck.nnc_keyword or empty
    lo, hi = _ordered(nnc.cells)
    ok = active[lo] & active[hi]
    if not ok.all():
        notes.append(f"NNC: {int((~ok).sum())} records with an inactive cell ignored (as Flow)")
    order = np.argsort(_keys(lo[ok], hi[ok], nc), kind="stable")
    nnc_lo, nnc_hi, nnc_value = lo[ok][order], hi[ok][order], nnc.values[ok][order]

    edit = deck.editnnc or empty
    lo, hi = _ordered(edit.cells)
    mult = edit.values
    nx, ny, _ = deck.cart_dims
    diff = hi - lo
    wanted = mult != 1.0
    quirk = wanted & (diff == ny) & ~np.isin(ny, [1, nx])
    skipped = wanted & ~quirk & ~(active[lo] & active[hi] & ~np.isin(diff, [0, 1, nx]))
    if quirk.any():
        notes.append(
            f"EDITNNC: {int(quirk.sum())} records for cells ny = {ny} apart skipped "
            "(OPM Flow 2022.10 takes them for neighbours)"
        )
    if skipped.any():
        notes.append(f"EDITNNC: {int(skipped.sum())} records for neighbours or inactive cells skipped (Flow)")
    ok = wanted & ~quirk & ~skipped
    keys, mult = _keys(lo[ok], hi[ok], nc), mult[ok]
    order = np.argsort(keys, kind="stable")
    keys, mult = keys[order], mult[order]
    nnc_keys = _keys(nnc_lo, nnc_hi, nc)
    on_input = _find(nnc_keys, keys)[1]
    late = np.flatnonzero(on_input & (keys == nnc_keys[-1]))[1:] if nnc_keys.size else []
    if len(late):  # Flow's matching loop has passed the last NNC pair: the grid's connection
        on_input[late] = False
        notes.append(
            f"EDITNNC: {len(late)} further records for the NNC keyword's last pair multiply the "
            "grid's connection, not the NNC value (as OPM Flow 2022.10)"
        )
    at, hit = _find(nnc_keys, keys[on_input])
    factor = np.ones(nnc_keys.size)
    np.multiply.at(factor, at[hit], mult[on_input][hit])
    if on_input.any():
        notes.append(f"EDITNNC: {int(on_input.sum())} records multiply the NNC keyword's values")
    rest, inverse = np.unique(keys[~on_input], return_inverse=True)
    product = np.ones(rest.size)
    np.multiply.at(product, inverse, mult[~on_input])
    return (
        np.column_stack([nnc_lo, nnc_hi]),
        nnc_value * factor,
        np.column_stack([rest // nc, rest % nc]),
        product,
    )


def apply_deck_edits(
    deck: Deck,
    lo: IntArray,
    hi: IntArray,
    trans: FloatArray,
    kind: np.ndarray,
    face: IntArray,
    index_map: IntArray,
    notes: list[str],
    unit_label: str = "",
) -> tuple[IntArray, IntArray, FloatArray, np.ndarray, IntArray]:
    """Steps 1-5 above on the grid's connections: cells ``lo`` < ``hi`` of the processed grid
    (linear indices ``index_map``), one entry per face or pair. Returns the entries
    (per pair and sorted if the deck has NNC, EDITNNC or TRAN edits), cells still ordered."""
    trans = np.asarray(trans, dtype=np.float64)
    index_map = np.asarray(index_map, dtype=np.int64)
    if deck.nnc_keyword is not None or deck.editnnc is not None or deck.tran_edits:
        cells, trans, kind, face = _edited(
            deck, np.column_stack([lo, hi]), trans, kind, face, index_map, notes
        )
        lo, hi = cells[:, 0].copy(), cells[:, 1].copy()
    trans = _drop_small(deck, lo, hi, trans, kind, index_map, notes, unit_label)
    return lo, hi, trans, kind, face


def _edited(deck, cells, trans, kind, face, index_map, notes):
    """Steps 1-4, per pair."""
    cells, trans, kind, face = per_pair(cells, trans, kind, face)
    nc, n_cells = deck.num_cells, index_map.size
    cell_of = np.full(nc, -1, dtype=np.int64)
    cell_of[index_map] = np.arange(n_cells)

    nnc_pairs, nnc_values, edit_pairs, edit_mult = nnc_keyword_values(deck, notes)
    nnc_cells = np.sort(cell_of[nnc_pairs], axis=1)
    in_grid = nnc_cells[:, 0] >= 0
    if not in_grid.all():
        notes.append(f"NNC: {int((~in_grid).sum())} records with a cell the grid removed ignored (as Flow)")
    nnc_cells, nnc_values = nnc_cells[in_grid], nnc_values[in_grid]

    # 1. a connection of 0 for every NNC-keyword pair the grid does not join
    keys = _keys(cells[:, 0], cells[:, 1], n_cells)
    nnc_keys = _keys(nnc_cells[:, 0], nnc_cells[:, 1], n_cells)
    new = np.unique(nnc_keys[~_find(keys, nnc_keys)[1]])
    if new.size:
        at = np.searchsorted(keys, new)
        cells = np.insert(cells, at, np.column_stack([new // n_cells, new % n_cells]), axis=0)
        trans = np.insert(trans, at, 0.0)
        kind = np.insert(kind, at, OTHER)
        face = np.insert(face, at, -1)
        keys = np.insert(keys, at, new)
        notes.append(f"NNC: {new.size} connections the grid does not make added")
    lo, hi = _ordered(index_map[cells])

    # 2. EDIT TRANX/TRANY/TRANZ
    trans = apply_tran_edits(deck, lo, hi, trans, notes)

    # 3. EDITNNC on the grid's connections
    if edit_pairs.size:
        edit_cells = np.sort(cell_of[edit_pairs], axis=1)
        at, found = _find(keys, _keys(edit_cells[:, 0], edit_cells[:, 1], n_cells))
        found &= edit_cells[:, 0] >= 0
        trans = trans.copy()
        trans[at[found]] *= edit_mult[found]
        notes.append(f"EDITNNC: {int(found.sum())} connections multiplied")
        if not found.all():
            notes.append(f"EDITNNC: {int((~found).sum())} pairs the grid does not join ignored (Flow warns)")

    # 4. NNC values added
    if nnc_values.size:
        trans = trans.copy()
        np.add.at(trans, np.searchsorted(keys, nnc_keys), nnc_values)
        notes.append(f"NNC: {nnc_values.size} transmissibilities added")
    return cells, trans, kind, face


def _drop_small(deck, lo, hi, trans, kind, index_map, notes, unit_label):
    """Step 5: non-neighbour pairs whose total is below the threshold set to 0."""
    far = np.flatnonzero(kind != NEIGHBOR)  # NEIGHBOR entries are logical neighbours
    far = far[~logical_neighbors(index_map[lo[far]], index_map[hi[far]], deck.cart_dims)]
    if far.size:
        _, group = np.unique(_keys(lo[far], hi[far], index_map.size), return_inverse=True)
        total = np.bincount(group, trans[far])[group]  # per pair: its faces added
        small = far[(total < NNC_THRESHOLD) & (total != 0.0)]
        if small.size:
            label = f" {unit_label}" if unit_label else ""
            notes.append(
                f"{small.size} non-neighbour connections below {NNC_THRESHOLD:g}{label} were dropped "
                "(as OPM Flow does)"
            )
            trans = trans.copy()
            trans[small] = 0.0
    if (trans < 0).any():
        notes.append(f"{int((trans < 0).sum())} connections with a negative transmissibility left out")
    return trans


_AXIS_OF_KEYWORD = {"TRANX": 0, "TRANY": 1, "TRANZ": 2}


def apply_tran_edits(
    deck: Deck, lo: IntArray, hi: IntArray, trans: FloatArray, notes: list[str]
) -> FloatArray:
    """The EDIT section's TRANX/TRANY/TRANZ operations replayed on connections (lo, hi)."""
    if not deck.tran_edits:
        return trans
    nx, ny, _ = deck.cart_dims
    step = hi - lo
    axis = np.full(step.size, -1)
    axis[(step == nx * ny)] = 2  # Flow's if/else chain: X first, then Y, then Z
    axis[(step == nx) & (ny > 1)] = 1
    axis[(step == 1) & (nx > 1)] = 0
    trans = np.array(trans, dtype=np.float64)
    for keyword, ax in _AXIS_OF_KEYWORD.items():
        edits = [e for e in deck.tran_edits if e.keyword == keyword]
        if not edits:
            continue
        rows = np.flatnonzero(axis == ax)
        values = np.full(deck.num_cells, np.nan)  # per cell: its connection to the next cell along ax
        values[lo[rows]] = trans[rows]
        for edit in edits:
            cells = edit.cells(deck.cart_dims)
            current = values[cells]
            if edit.operation == "SET":
                given = ~np.isnan(edit.values)
                current = np.where(given, edit.values, current)
            elif edit.operation == "EQUALS":
                current = np.full(cells.size, edit.value)
            elif edit.operation == "MULTIPLY":
                current = current * edit.value
            elif edit.operation == "ADD":
                current = current + edit.value
            elif edit.operation == "MINVALUE":
                current = np.maximum(current, edit.value)
            else:  # MAXVALUE
                current = np.minimum(current, edit.value)
            values[cells] = current
        changed = values[lo[rows]] != trans[rows]
        trans[rows] = values[lo[rows]]
        sources = ", ".join(f"{e.operation} {e.source}".strip() for e in edits)
        notes.append(f"{keyword} edits ({sources}) changed {int(changed.sum())} connections")
    return trans
