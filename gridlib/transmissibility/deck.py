"""``deck_transmissibility``: the connections of a corner-point deck as OPM Flow computes them.

Order of operations (OPM Flow 2022.10, ECLIPSE's NEWTRAN):

1. half-transmissibilities and their harmonic mean (:mod:`.newtran`), NTG on I and J
   halves;
2. directional multipliers on the total: the multiplier of each cell for its own side
   of the face (MULTX of the cell on the -i side times MULTX- of the cell on the +i
   side, likewise Y and Z), by the face's logical direction, so fault connections are
   treated the same way; MULTFLT folded into those arrays for the faces listed under
   FAULTS (:mod:`.multipliers`);
3. non-neighbour connections (index difference not 1, nx or nx ny) below 1e-6 deck
   units are dropped, as Flow does.
"""

from __future__ import annotations

import numpy as np

from ..cornerpoint.deck import Deck
from ..cornerpoint.process import CornerPointGrid, process_grdecl
from ..errors import InputError
from ..grid import B, E, N, S, T, W
from ..units import unit_system
from .connections import FAULT, NEIGHBOR, PINCH, Connections, assemble
from .multipliers import directional_multipliers
from .newtran import (
    cell_and_face_centres,
    combine,
    half_transmissibilities,
    interior_half_faces,
    vector_areas,
)
from .pinch import minpv_connections

NNC_THRESHOLD = 1e-6  # deck units: non-neighbour connections below this are dropped (Flow)
_AXIS_OF_TAG = np.array([0, 0, 1, 1, 2, 2])  # W, E -> x; S, N -> y; T, B -> z
assert (W, E, S, N, T, B) == (0, 1, 2, 3, 4, 5)


def rock_arrays(deck: Deck) -> tuple[np.ndarray, np.ndarray]:
    """PERMX, PERMY, PERMZ (nc, 3) in mD and NTG (nc,) of every deck cell, checked.

    PERMY and PERMZ default to PERMX, NTG to 1 (as Flow). Raises naming the file and
    keyword: PERMX missing, a negative or non-finite permeability, NTG outside [0, 1].
    """
    data = deck.cell_data
    if "PERMX" not in data:
        raise InputError(f"{deck.source}: PERMX: the deck gives no permeability (PERMX is missing)")
    active = deck.active
    perm = np.stack([data.get(key, data["PERMX"]) for key in ("PERMX", "PERMY", "PERMZ")], axis=1)
    for d, key in enumerate(("PERMX", "PERMY", "PERMZ")):
        bad = active & ~(np.isfinite(perm[:, d]) & (perm[:, d] >= 0))
        if bad.any():
            cell = int(np.flatnonzero(bad)[0])
            raise InputError(
                f"{deck.source}: {key if key in data else 'PERMX'}: {int(bad.sum())} active cells have a "
                f"negative or undefined permeability (first: cell {_ijk(deck, cell)}, {perm[cell, d]!r})"
            )
    ntg = data.get("NTG", np.ones(deck.num_cells))
    bad = active & ~((ntg >= 0) & (ntg <= 1))
    if bad.any():
        cell = int(np.flatnonzero(bad)[0])
        raise InputError(
            f"{deck.source}: NTG: {int(bad.sum())} active cells have NTG outside [0, 1] "
            f"(first: cell {_ijk(deck, cell)}, {ntg[cell]!r})"
        )
    return perm, ntg


def _ijk(deck: Deck, g: int) -> str:
    nx, ny, _ = deck.cart_dims
    return f"({g % nx + 1}, {g // nx % ny + 1}, {g // (nx * ny) + 1})"


def logical_neighbors(g1: np.ndarray, g2: np.ndarray, dims: tuple[int, int, int]) -> np.ndarray:
    """Whether linear indices differ by 1, nx or nx ny (Flow's test for a neighbour pair)."""
    nx, ny, _ = dims
    step = np.abs(g2 - g1)
    return (step == 1) | (step == nx) | (step == nx * ny)


def deck_transmissibility(
    deck: Deck, cp: CornerPointGrid | None = None, *, pinch: bool | None = None
) -> Connections:
    """Every connection of a corner-point deck with Flow's transmissibility, in the deck's units.

    ``cp``: the deck already processed by :func:`~gridlib.cornerpoint.process_grdecl`
    (processed here otherwise; its MINPV applies). ``pinch``: whether PINCH is active
    (default: whether the deck has PINCH); connections across removed layers follow
    OPM Flow 2022.10 (:mod:`.pinch`) whatever ``cp`` was processed with.
    Connections are indexed by the processed grid's cells (``cells``) and by linear
    ijk index (``global_cells``). Units: those of the deck (METRIC cP m3/(day bar),
    FIELD cP rb/(day psi), ...).
    """
    if cp is None:
        cp = process_grdecl(deck)
    pinch_active = deck.pinch is not None if pinch is None else bool(pinch)
    units = unit_system(deck.units)
    grid = cp.grid
    glob = grid.cells.index_map
    perm, ntg = rock_arrays(deck)
    notes: list[str] = []
    dims = deck.cart_dims
    layer = dims[0] * dims[1]

    f, a, ta, b, tb = interior_half_faces(grid)
    centre, face_centre, bottom = cell_and_face_centres(deck, glob)
    area = vector_areas(grid, f)
    column = (ta >= T) & (tb >= T)  # one cell above the other
    across = column & (np.abs(glob[b] - glob[a]) > layer)  # across collapsed cells (PINCH)
    if across.any() and not pinch_active:
        keep = ~across
        f, a, ta, b, tb, area, column = (x[keep] for x in (f, a, ta, b, tb, area, column))
        notes.append(f"{int(across.sum())} connections across zero-thickness layers left out (no PINCH)")
    f, a, ta, b, tb, area, column = _with_minpv_connections(deck, glob, f, a, ta, b, tb, area, column, notes)
    upper = np.where(ta == B, a, b)
    area[column] = bottom[upper[column]]
    ga, gb = glob[a], glob[b]
    ha = half_transmissibilities(area, centre[a], face_centre[a, ta], perm[ga, _AXIS_OF_TAG[ta]])
    hb = half_transmissibilities(area, centre[b], face_centre[b, tb], perm[gb, _AXIS_OF_TAG[tb]])
    ha = np.where(ta < T, ha * ntg[ga], ha)
    hb = np.where(tb < T, hb * ntg[gb], hb)
    trans = combine(ha, hb, units)

    mult = directional_multipliers(deck, notes)
    if mult is not None:
        ma, mb = mult[ta, ga], mult[tb, gb]
        if pinch_active and deck.pinch_options[2] == "ALL":
            smallest = _smallest_multz(mult, ga, gb, ta, column, layer)
            ma = np.where(column & (ta == B), smallest, ma)
            mb = np.where(column & (tb == B), smallest, mb)
        trans = trans * ma * mb

    neighbor = logical_neighbors(ga, gb, dims)
    kind = np.where(neighbor, NEIGHBOR, np.where(column, PINCH, FAULT)).astype(np.int8)
    small = ~neighbor & (trans < NNC_THRESHOLD)
    if small.any():
        notes.append(
            f"{int(small.sum())} non-neighbour connections below {NNC_THRESHOLD:g} "
            f"{units.transmissibility_label} were dropped (as OPM Flow does)"
        )
        trans = np.where(small, 0.0, trans)
    return assemble(np.column_stack([a, b]), trans, kind, f, index_map=glob, units=units.name, notes=notes)


def _with_minpv_connections(deck, glob, f, a, ta, b, tb, area, column, notes):
    """The face connections with Flow's MINPV connections added (face -1, upper cell first,
    its bottom face to the lower cell's top), those already joined by a face left out."""
    pairs = minpv_connections(deck)
    if pairs.size == 0:
        return f, a, ta, b, tb, area, column
    cell_of = np.full(deck.num_cells, -1, dtype=np.int64)
    cell_of[glob] = np.arange(glob.size)
    up, low = cell_of[pairs[:, 0]], cell_of[pairs[:, 1]]
    ok = (up >= 0) & (low >= 0)
    n_cells = glob.size
    have = np.minimum(a, b) * n_cells + np.maximum(a, b)
    ok &= ~np.isin(np.minimum(up, low) * n_cells + np.maximum(up, low), have)
    up, low = up[ok], low[ok]
    if up.size:
        notes.append(f"{up.size} connections across cells removed by MINPV (as OPM Flow makes them)")
    n = up.size
    return (
        np.concatenate([f, np.full(n, -1)]),
        np.concatenate([a, up]),
        np.concatenate([ta, np.full(n, B)]),
        np.concatenate([b, low]),
        np.concatenate([tb, np.full(n, T)]),
        np.concatenate([area, np.zeros((n, 3))]),
        np.concatenate([column, np.ones(n, dtype=bool)]),
    )


def _smallest_multz(mult, ga, gb, ta, column, layer):
    """PINCH item 5 ALL: the Z+ multiplier of a connection between cells of one column is
    the smallest MULTZ from the upper cell down to the last cell above the lower one
    (instead of the upper cell's own); per connection (used where ``column``)."""
    up, low = np.where(ta == B, ga, gb), np.where(ta == B, gb, ga)
    best = mult[B, up].copy()
    span = np.where(column, (low - up) // layer, 0)
    for step in range(1, int(span.max(initial=0))):
        more = span > step
        best[more] = np.minimum(best[more], mult[B, up[more] + step * layer])
    return best
