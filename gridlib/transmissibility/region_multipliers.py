"""MULTREGT: transmissibility multipliers between regions, as OPM Flow 2022.10 applies them.

A MULTREGT record ``r1 r2 m directions option set`` multiplies by m the connections
between a cell of region r1 and a cell of region r2 (either way round) of the region
array FLUXNUM (set F), MULTNUM (M) or OPERNUM (O), for connections whose face is along
one of ``directions``. Flow applies it to every connection the grid makes (logical
neighbours, faults, pinch-outs; not to NNC-keyword connections), after MULTX/.../
MULTFLT and before the EDIT section, as follows (MULTREGTScanner, 2022.10):

* a defaulted or negative region number stands for every region value of the active
  cells; a record between a region and itself is skipped;
* a defaulted region set is the previous record's, and for the first record FLUXNUM,
  or MULTNUM when GRIDOPTS NRMULT > 0 (ECLIPSE's documented default is M);
* records are keys by region pair: a later record for the same pair, in either order
  and **whatever its region set**, replaces the earlier one; multipliers never
  multiply each other;
* for a connection between cells g1 < g2 (linear indices), each region set that has
  a record is tried in alphabetical order (FLUXNUM, MULTNUM, OPERNUM) and the first
  record that applies gives the multiplier (1 if none does). A record applies if its
  directions contain the face's axis and its option allows the connection: ALL
  always, NNC only if the two cells are not "side by side", NONNC only if they are;
* "side by side" is |di| + |dj| = 1 with i = g % nx and, **a quirk of 2022.10**,
  j = (g // nx) % nz (nz, not ny: right only when ny = nz). So, **second quirk**, two
  cells of one column (di = dj = 0) are never side by side: vertical connections count
  as NNCs (NNC applies to them, NONNC does not).

NOAQUNNC (Flow 2022.10 refuses it) is applied as ALL, which it is without numerical
aquifers; a record between a region and itself (Flow refuses it) is ignored; both
are noted. A region set without its array in the deck is an error, as in Flow.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..cornerpoint.connection_keywords import REGION_SETS, MultregtRecord
from ..cornerpoint.deck import Deck
from ..errors import InputError
from ..grid import IntArray

_AXES = "XYZ"


def resolved_region_sets(deck: Deck) -> list[str]:
    """The region array (FLUXNUM, MULTNUM, OPERNUM) each MULTREGT record uses, in order."""
    previous = "MULTNUM" if deck.gridopts is not None and deck.gridopts.nrmult > 0 else "FLUXNUM"
    names = []
    for record in deck.multregt:
        if record.region_set is not None:
            previous = REGION_SETS[record.region_set]
        names.append(previous)
    return names


def with_explicit_region_sets(deck: Deck) -> Deck:
    """``deck`` with every MULTREGT record naming its region set (:func:`resolved_region_sets`),
    so that it means the same without GRIDOPTS (whose NRMULT changes the default), e.g. written
    into a GRID include of another deck."""
    if not deck.multregt or all(r.region_set is not None for r in deck.multregt):
        return deck
    letter = {name: key for key, name in REGION_SETS.items()}
    records = tuple(
        replace(r, region_set=letter[name])
        for r, name in zip(deck.multregt, resolved_region_sets(deck), strict=True)
    )
    return replace(deck, multregt=records)


def _region_values(deck: Deck, name: str, record: MultregtRecord) -> np.ndarray:
    """The region array as int64 (0 in inactive cells), checked on the active cells."""
    values = deck.cell_data.get(name)
    where = f"{record.source}: MULTREGT" if record.source else "MULTREGT"
    if values is None:
        raise InputError(
            f"{where}: region set {name} is not given in the deck ({deck.source}: RUNSPEC, GRID and EDIT "
            "are read; OPM Flow stops too if the deck has none)"
        )
    active = deck.active
    bad = active & ~(np.isfinite(values) & (values >= 0) & (values == np.floor(values)))
    if bad.any():
        raise InputError(
            f"{deck.source}: {name}: {int(bad.sum())} active cells have no region number "
            f"(undefined or not a non-negative integer), needed by {where}"
        )
    return np.where(active, values, 0).astype(np.int64)


def region_multipliers(
    deck: Deck, g1: IntArray, g2: IntArray, axis: IntArray, notes: list[str]
) -> np.ndarray | None:
    """MULTREGT's multiplier of each connection between cells ``g1`` and ``g2`` (linear
    indices) across a face along ``axis`` (0, 1, 2 = X, Y, Z); None without MULTREGT."""
    if not deck.multregt:
        return None
    g1, g2 = np.asarray(g1, dtype=np.int64), np.asarray(g2, dtype=np.int64)
    lo, hi = np.minimum(g1, g2), np.maximum(g1, g2)
    names = resolved_region_sets(deck)
    regions = {}
    for record, name in zip(deck.multregt, names, strict=True):
        if name not in regions:
            regions[name] = _region_values(deck, name, record)
    # Pair -> record: later records replace earlier ones for a pair, across region sets.
    by_pair: dict[tuple[int, int], int] = {}
    for index, (record, name) in enumerate(zip(deck.multregt, names, strict=True)):
        if record.region1 is not None and record.region1 == record.region2:
            notes.append(f"{record.source}: MULTREGT within region {record.region1} ignored (Flow stops)")
            continue
        present = np.unique(regions[name][deck.active]).tolist()
        sources = present if record.region1 is None else [record.region1]
        targets = present if record.region2 is None else [record.region2]
        for s in sources:
            for t in targets:
                if s != t:
                    by_pair[(s, t)] = by_pair[(t, s)] = index
    if any(r.nnc_option == "NOAQUNNC" for r in deck.multregt):
        notes.append("MULTREGT option NOAQUNNC applied as ALL (no numerical aquifers; Flow 2022.10 stops)")

    nx, _, nz = deck.cart_dims
    di = np.abs(lo % nx - hi % nx)
    dj = np.abs((lo // nx) % nz - (hi // nx) % nz)  # sic: % nz, as Flow 2022.10
    side_by_side = ((di == 0) & (dj == 1)) | ((di == 1) & (dj == 0))
    axis = np.asarray(axis, dtype=np.int64)
    along = np.array([[a in r.directions for a in _AXES] for r in deck.multregt])  # (records, 3)
    option = np.array([r.nnc_option for r in deck.multregt])
    factor = np.array([r.multiplier for r in deck.multregt])
    mult = np.ones(lo.size)
    pending = np.ones(lo.size, dtype=bool)
    for name in sorted(set(names)):  # Flow's std::map order
        entries = [(pair, index) for pair, index in by_pair.items() if names[index] == name]
        if not entries:
            continue
        region = regions[name]
        r1, r2 = region[lo], region[hi]
        base = int(max(region.max(), max(max(p) for p, _ in entries))) + 1
        keys = np.array([s * base + t for (s, t), _ in entries], dtype=np.int64)
        record_of = np.array([index for _, index in entries], dtype=np.int64)
        order = np.argsort(keys)
        keys, record_of = keys[order], record_of[order]
        wanted = r1 * base + r2
        at = np.minimum(np.searchsorted(keys, wanted), keys.size - 1)
        found = pending & (keys[at] == wanted)
        rec = record_of[at]
        applies = found & along[rec, axis]
        applies &= ~((option[rec] == "NNC") & side_by_side) & ~((option[rec] == "NONNC") & ~side_by_side)
        mult[applies] = factor[rec[applies]]
        pending &= ~applies
    sources = ", ".join(r.source for r in deck.multregt if r.source)
    count = int((~pending).sum())
    notes.append(f"MULTREGT: {len(deck.multregt)} records ({sources}) applied to {count} connections")
    return mult
