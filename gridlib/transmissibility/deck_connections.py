"""``deck_transmissibility``: the connections of a corner-point deck as OPM Flow computes them.

Order of operations (OPM Flow 2022.10, ECLIPSE's NEWTRAN), all in the deck's unit system
(lengths in deck units, permeability in mD, T in METRIC cP m3/(day bar), FIELD cP
rb/(day psi), ...; :mod:`gridlib.units`):

1. half-transmissibilities and their harmonic mean (:mod:`.newtran`), NTG on I and J
   halves; connections across removed layers (:mod:`.pinch`);
2. directional multipliers on the total: the multiplier of each cell for its own side
   of the face (MULTX of the cell on the -i side times MULTX- of the cell on the +i
   side, likewise Y and Z), by the face's logical direction, so fault connections are
   treated the same way; MULTFLT folded into those arrays for the faces listed under
   FAULTS (:mod:`.multipliers`); PINCH item 5 ALL: the smallest MULTZ down a column;
3. MULTREGT, the region multiplier of each connection (:mod:`.region_multipliers`);
4. from here per cell pair (:mod:`.edits`): a 0 connection for each NNC-keyword pair
   the grid does not make; the EDIT section's TRANX/TRANY/TRANZ operations in deck
   order on logical neighbours; EDITNNC; the NNC keyword's values added;
5. non-neighbour connections (index difference not 1, nx or nx ny) below 1e-6 deck
   units are dropped, as Flow does.

What a deck uses that is not honoured is said in ``Connections.notes``.
"""

from __future__ import annotations

from functools import partial

import numpy as np

from ..cell_names import cell_names, ijk_text
from ..cornerpoint.deck import Deck
from ..cornerpoint.pore_volume import with_flow_activity
from ..cornerpoint.process import CornerPointGrid, process_grdecl
from ..errors import InputError
from ..grid import B, E, N, S, T, W
from ..pages import without_huge_pages
from ..petrophysics.ranges import FRACTIONS, check_rock_values
from ..threads import concurrently
from ..units import unit_system
from .connections import FAULT, NEIGHBOR, PINCH, Connections, assemble_ordered
from .edits import apply_deck_edits, logical_neighbors
from .multipliers import directional_multipliers, side_multipliers
from .newtran import NeighbourPairs, RawConnections, newtran_connections
from .region_multipliers import region_multipliers

assert (W, E, S, N, T, B) == (0, 1, 2, 3, 4, 5)
_BLOCKS = 32  # blocks of connections finished side by side on the threads (each writes its own rows)


def rock_arrays(deck: Deck, notes: list[str] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """PERMX, PERMY, PERMZ (nc, 3) in mD and NTG (nc,) of every deck cell, checked on the
    active cells as strictly as OPM Flow (:mod:`gridlib.petrophysics.ranges`).

    PERMY and PERMZ default to PERMX, NTG to 1 (as Flow). Raises an InputError naming the
    file, keyword and cells (i, j, k): PERMX missing, a negative or non-finite permeability or
    NTG. NTG above 1 is used as Flow uses it, with a note (appended to ``notes``).
    """
    perm, ntg = rock_columns(deck, notes)
    return np.stack(perm, axis=1), ntg


def rock_columns(deck: Deck, notes: list[str] | None = None) -> tuple[list[np.ndarray], np.ndarray]:
    """:func:`rock_arrays` with PERMX, PERMY, PERMZ as three (nc,) arrays (the deck's own)."""
    data = deck.cell_data
    if "PERMX" not in data:
        raise InputError(f"{deck.source}: PERMX: the deck gives no permeability (PERMX is missing)")
    perm = [np.asarray(data.get(key, data["PERMX"]), dtype=np.float64) for key in ("PERMX", "PERMY", "PERMZ")]
    ntg = np.asarray(data["NTG"], dtype=np.float64) if "NTG" in data else np.ones(deck.num_cells)
    given = [key for key in ("PERMX", "PERMY", "PERMZ", "NTG") if key in data]
    if all(_plainly_valid(key, data[key]) for key in given):
        return perm, ntg  # every cell's values pass: so do the active cells', without a note
    active = np.flatnonzero(deck.active)
    values = {key: data[key][active] for key in given}
    found = check_rock_values(values, deck.source, lambda pos: cell_names(pos, active, deck.cart_dims))
    if notes is not None:
        notes.extend(found)
    return perm, ntg


def _plainly_valid(key: str, values: np.ndarray) -> bool:
    """Whether every value of ``values`` (all cells) is finite, >= 0 and, for NTG, at most 1:
    :func:`check_rock_values` would find nothing (two reductions, no temporaries)."""
    low, high = values.min(initial=np.inf), values.max(initial=0.0)  # NaN: neither comparison holds
    return bool(low >= 0.0 and (high <= 1.0 if key in FRACTIONS else high < np.inf))


def deck_transmissibility(
    deck: Deck, cp: CornerPointGrid | None = None, *, pinch: bool | None = None
) -> Connections:
    """Every connection of a corner-point deck with Flow's transmissibility, in the deck's units.

    ``cp``: the deck already processed by :func:`~gridlib.cornerpoint.process_grdecl`
    (processed here otherwise; its MINPV applies). ``pinch``: whether PINCH is active
    (default: whether the deck has PINCH); connections across removed layers follow
    OPM Flow 2022.10 (:mod:`.pinch`) whatever ``cp`` was processed with.
    Cells whose pore volume is 0 are inactive, as in Flow (:mod:`gridlib.cornerpoint.pore_volume`).
    Connections are indexed by the processed grid's cells (``cells``) and by linear
    ijk index (``global_cells``). Units: those of the deck (METRIC cP m3/(day bar),
    FIELD cP rb/(day psi), ...).
    """
    deck = with_flow_activity(deck)  # cells of zero pore volume are inactive, as ACTNUM 0
    if cp is None:
        cp = process_grdecl(deck)
    with without_huge_pages():  # hundreds of MB of fresh temporaries (gridlib.pages)
        return _connections(deck, cp, pinch)


def _connections(deck: Deck, cp: CornerPointGrid, pinch: bool | None) -> Connections:
    """:func:`deck_transmissibility` of a deck whose zero pore volume cells are inactive."""
    pinch_active = deck.pinch is not None if pinch is None else bool(pinch)
    units = unit_system(deck.units)
    grid = cp.grid
    glob = grid.cells.index_map
    notes: list[str] = []
    perm, ntg = rock_columns(deck, notes)
    dims = deck.cart_dims
    layer = dims[0] * dims[1]

    parts = newtran_connections(deck, grid, perm, ntg, units, pinch_active, notes)
    del perm, ntg  # from here on, every array is dropped once used: this is the peak of memory
    mult = directional_multipliers(deck, notes)
    smallest_multz = pinch_active and deck.pinch_options[2] == "ALL"
    regions = bool(deck.multregt)
    n = sum(part.trans.size for part in parts)
    lo, hi = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64)
    trans = np.empty(n)
    kind = np.empty(n, dtype=np.int8)
    f = np.empty(n, dtype=np.int64)
    ga, gb, axis = (np.empty(n, dtype=np.int64) for _ in range(3)) if regions else (None, None, None)

    def finish(part: NeighbourPairs | RawConnections, rows: slice, out: slice) -> None:
        """Rows ``rows`` of ``part`` into rows ``out`` of the connection list: the ordered
        pair, the transmissibility with the directional multipliers, the kind, the face."""
        a, b = part.cells(rows)
        t = part.trans[rows]
        neighbours = isinstance(part, NeighbourPairs)
        if neighbours:
            g1 = part.lower[rows]
            g2 = g1 + part.stride
            n, plus = g1.size, 2 * part.axis + 1  # the lower cell's side: E, N or B
            ta, tb = np.full(n, plus, dtype=np.int8), np.full(n, plus - 1, dtype=np.int8)
            column = np.full(n, part.axis == 2)
        else:
            g1, g2, ta, tb, column = (
                part.ga[rows],
                part.gb[rows],
                part.ta[rows],
                part.tb[rows],
                part.column[rows],
            )
        if mult is not None and neighbours and not smallest_multz:
            for m, g in ((mult.get(plus), g1), (mult.get(plus - 1), g2)):
                if m is not None:  # a side without a multiplier is x 1: skipped
                    t = t * m[g]
        elif mult is not None:
            ma, mb = side_multipliers(mult, ta, g1), side_multipliers(mult, tb, g2)
            if smallest_multz:
                smallest = _smallest_multz(mult, g1, g2, ta, column, layer)
                ma = np.where(column & (ta == B), smallest, ma)
                mb = np.where(column & (tb == B), smallest, mb)
            t = t * ma * mb
        trans[out] = t
        if neighbours:
            kind[out] = NEIGHBOR
            lo[out], hi[out] = a, b  # a < b: the grid numbers cells in linear index order
        else:
            k = kind[out]
            k[...] = FAULT
            k[column] = PINCH
            k[logical_neighbors(g1, g2, dims)] = NEIGHBOR
            np.minimum(a, b, out=lo[out])  # ordered as the connection list is (first < second)
            np.maximum(a, b, out=hi[out])
        f[out] = part.face[rows]
        if regions:
            ga[out], gb[out], axis[out] = g1, g2, ta // 2  # tag // 2 = axis

    concurrently(*(partial(finish, *block) for block in _blocks(parts, _BLOCKS)))
    del parts
    if regions:
        trans *= region_multipliers(deck, ga, gb, axis, notes)  # MULTREGT
        del ga, gb, axis
    # EDIT TRANX/Y/Z, EDITNNC, NNC keyword, small non-neighbours (.edits)
    lo, hi, trans, kind, f = apply_deck_edits(
        deck, lo, hi, trans, kind, f, glob, notes, units.transmissibility_label
    )
    _check_finite(deck, trans, lo, hi, glob)
    return assemble_ordered(lo, hi, trans, kind, f, index_map=glob, units=units, notes=notes)


def _blocks(
    parts: list[NeighbourPairs | RawConnections], count: int
) -> list[tuple[NeighbourPairs | RawConnections, slice, slice]]:
    """The rows of ``parts`` in about ``count`` blocks of similar size: (part, its rows, their
    rows in the parts one after the other)."""
    total = sum(part.trans.size for part in parts)
    size = max(1, -(-total // count))
    blocks, at = [], 0
    for part in parts:
        n = part.trans.size
        for start in range(0, n, size):
            stop = min(start + size, n)
            blocks.append((part, slice(start, stop), slice(at + start, at + stop)))
        at += n
    return blocks


def _check_finite(deck: Deck, trans: np.ndarray, lo: np.ndarray, hi: np.ndarray, glob: np.ndarray) -> None:
    """Transmissibilities beyond float64 (a PERMX or multiplier of 1e300) are the deck's doing:
    one InputError naming the deck and the first connection's cells (``glob`` of ``lo``, ``hi``)."""
    bad = np.flatnonzero(~np.isfinite(trans))
    if bad.size:
        a, b = (ijk_text(int(glob[c[bad[0]]]), deck.cart_dims) for c in (lo, hi))
        raise InputError(
            f"{deck.source}: {bad.size} transmissibilities are beyond any float (first between cells "
            f"{a} and {b}): check the permeabilities and multipliers there"
        )


def _smallest_multz(mult, ga, gb, ta, column, layer):
    """PINCH item 5 ALL: the Z+ multiplier of a connection between cells of one column is
    the smallest MULTZ from the upper cell down to the last cell above the lower one
    (instead of the upper cell's own); per connection (used where ``column``)."""
    up, low = np.where(ta == B, ga, gb), np.where(ta == B, gb, ga)
    if B not in mult:  # no MULTZ: 1 everywhere
        return np.ones(up.size)
    multz = mult[B]
    best = multz[up]
    span = np.where(column, (low - up) // layer, 0)
    for step in range(1, int(span.max(initial=0))):
        more = span > step
        best[more] = np.minimum(best[more], multz[up[more] + step * layer])
    return best
