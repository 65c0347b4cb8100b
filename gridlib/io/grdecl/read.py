"""``read_grdecl``: the keywords of a deck read into a :class:`~gridlib.cornerpoint.deck.Deck`.

The keywords are read by :mod:`gridlib.io.grdecl.keywords` into a
:class:`~gridlib.io.grdecl.state.ReaderState`; here the state is checked and
assembled into the deck, with COORD/ZCORN from GDFILE or, for a Cartesian
deck (DX/DY/DZ or DXV/DYV/DZV, TOPS or DEPTHZ), from
:func:`gridlib.cornerpoint.cartesian.cartesian_to_cornerpoint`.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ...cornerpoint.cartesian import cartesian_to_cornerpoint
from ...cornerpoint.connection_keywords import CellPairs
from ...cornerpoint.deck import Deck
from ...cornerpoint.layer_overlaps import without_layer_overlaps
from ...units import unit_system
from ..eclipse_text import DeckError
from .binary import is_binary_keyword_file, read_binary_file
from .keywords import UNKNOWN_KEYWORDS, open_source, read_file, region_values
from .state import ReaderState
from .values import normalised_actnum

__all__ = ["read_grdecl"]

_GEOMETRY_KEYWORDS = ("DX", "DY", "DZ", "TOPS")


def read_grdecl(path: str | os.PathLike, *, unknown_keywords: str = "error") -> Deck:
    """Read the grid of an ECLIPSE deck (GRDECL or DATA file, or a binary GRDECL:
    :mod:`~gridlib.io.grdecl.binary`).

    A keyword that neither ECLIPSE nor OPM Flow knows (outside the
    :mod:`~gridlib.io.grdecl.vocabulary`, e.g. a misspelt ``ACTNUMX``) stops the read with
    a :class:`DeckError` naming the file, line and keyword, as Flow does;
    ``unknown_keywords="skip"`` skips each such keyword up to the next line that starts with
    a keyword and lists them in ``Deck.notes``.

    >>> import tempfile, pathlib
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "box.grdecl"
    >>> _ = p.write_text("DIMENS\\n 2 1 1 /\\nDX\\n 2*10 /\\nDY\\n 2*5 /\\nDZ\\n 2*2 /\\nTOPS\\n 2*1000 /\\n")
    >>> deck = read_grdecl(p)
    >>> deck.cart_dims, float(deck.zcorn.min()), float(deck.zcorn.max())
    ((2, 1, 1), 1000.0, 1002.0)
    """
    main = Path(path)
    if not main.is_file():
        raise DeckError(f"{main}: no such file")
    if unknown_keywords not in UNKNOWN_KEYWORDS:
        raise DeckError(
            f"{main}: unknown_keywords must be one of {UNKNOWN_KEYWORDS}, not {unknown_keywords!r}"
        )
    state = ReaderState(main, unknown_keywords)
    if is_binary_keyword_file(main):
        read_binary_file(state, main)
    else:
        read_file(state, open_source(main), 0)
    return _deck(state)


def _deck(state: ReaderState) -> Deck:
    where = str(state.main)
    if state.dims is None:
        raise DeckError(f"{where}: no grid dimensions (DIMENS or SPECGRID)")
    nx, ny, nz = state.dims
    arrays = dict(state.arrays)
    notes = list(state.notes)
    coord, zcorn = state.coord, state.zcorn
    if (coord is None) != (zcorn is None):
        missing = "ZCORN" if zcorn is None else "COORD"
        raise DeckError(f"{where}: {missing} is missing (COORD and ZCORN come together)")
    if coord is None:
        if state.gdfile is not None:
            coord, zcorn = state.gdfile.coord, state.gdfile.zcorn
            if "ACTNUM" not in arrays and state.gdfile.actnum is not None:
                arrays["ACTNUM"] = state.gdfile.actnum.astype(np.float64)
            if state.mapaxes is None:
                state.mapaxes = state.gdfile.mapaxes
            notes.append(f"grid geometry from GDFILE {state.gdfile.source}")
        else:
            coord, zcorn = _cartesian_geometry(state, arrays, where)
            notes.append("COORD and ZCORN built from the Cartesian keywords (DX, DY, DZ, TOPS)")
    coord, zcorn = _in_deck_lengths(coord, zcorn, state, notes, where)
    for name in _GEOMETRY_KEYWORDS:
        arrays.pop(name, None)
    actnum = arrays.pop("ACTNUM", None)
    if actnum is not None:
        actnum = normalised_actnum(actnum)  # the values were checked as they were read (.values)
    if state.porv_multpv is not None:  # what multiplies the pore volumes Flow computes
        arrays["MULTPV"] = state.porv_multpv
    _apply_multregp(state, arrays, notes, where)
    for name, values in arrays.items():
        n_undefined = int(np.isnan(values).sum())
        if n_undefined and name == "PORV":
            notes.append(f"PORV (EDIT) given for {values.size - n_undefined} of {values.size} cells")
        elif n_undefined:
            notes.append(f"{name} is undefined in {n_undefined} of {values.size} cells (NaN)")
    if state.skipped:
        shown = ", ".join(f"{k} ({v})" for k, v in state.skipped.items())
        notes.append(f"skipped keywords not needed for the grid: {shown}")
    if state.unknown:
        shown = ", ".join(f"{k} ({v})" for k, v in state.unknown.items())
        notes.append(f"skipped keywords neither ECLIPSE nor OPM Flow knows (unknown_keywords=skip): {shown}")
    fault_names = {seg.name for seg in state.faults}
    for name, at in state.multflt_sources.items():
        if name not in fault_names:
            notes.append(f"{at}: MULTFLT of fault {name!r} ignored: FAULTS does not define it (Flow stops)")
    pairs = {}
    for keyword, rows in state.cell_pairs.items():
        g1, g2, values, sources = zip(*rows, strict=True) if rows else ((), (), (), ())
        pairs[keyword] = CellPairs(np.column_stack([g1, g2]).reshape(-1, 2), values, sources)
    deck = Deck(
        (nx, ny, nz),
        coord,
        zcorn,
        actnum,
        arrays,
        tuple(state.faults),
        dict(state.multflt),
        state.mapaxes,
        state.mapunits,
        state.gridunit,
        state.units,
        state.pinch,
        state.minpv,
        where,
        tuple(notes),
        pinch_options=state.pinch_options,
        nnc_keyword=pairs.get("NNC"),
        editnnc=pairs.get("EDITNNC"),
        multregt=tuple(state.multregt),
        gridopts=state.gridopts,
        tran_edits=tuple(state.tran_edits),
    )
    return without_layer_overlaps(deck)


def _apply_multregp(state: ReaderState, arrays: dict, notes: list[str], where: str) -> None:
    """MULTREGP's multipliers on the pore volumes of their regions' cells (the region arrays as
    the deck leaves them), through MULTPV."""
    if not state.multregp:
        return
    if "PORV" in arrays:
        first = next(iter(state.multregp.values()))[2]
        raise DeckError(f"{first}: MULTREGP: with PORV given (EDIT), not supported")
    multpv = arrays.setdefault("MULTPV", np.ones(state.num_cells))
    for number, (region, multiplier, at) in state.multregp.items():
        values = region_values(arrays, region, state.num_cells)
        if values is None:
            raise DeckError(f"{at}: MULTREGP: {region} is not defined (OPM Flow stops too)")
        cells = np.flatnonzero(values == number)
        multpv[cells] *= multiplier
        notes.append(
            f"{at}: MULTREGP: pore volumes of {cells.size} cells ({region} {number}) x {multiplier:g}"
        )


# GRIDUNIT's length units in metres
_GRID_UNIT_METRES = {"METRES": 1.0, "FEET": 0.3048, "CM": 0.01}


def _in_deck_lengths(coord, zcorn, state: ReaderState, notes: list[str], where: str):
    """COORD and ZCORN in the deck's length unit where GRIDUNIT gives the grid in another one
    (a METRIC deck's grid in FEET, say): scaled by the ratio of the two, as OPM Flow does
    (whatever GRIDUNIT's second item says); an unknown GRIDUNIT is an error."""
    if state.gridunit is None:
        return coord, zcorn
    name = state.gridunit.strip().upper()
    if name not in _GRID_UNIT_METRES:
        raise DeckError(f"{where}: GRIDUNIT: unknown length unit {state.gridunit!r} (METRES, FEET or CM)")
    system = unit_system(state.units)
    factor = _GRID_UNIT_METRES[name] / system.length
    if factor == 1.0:
        return coord, zcorn
    notes.append(
        f"GRIDUNIT {name} in a {system.name} deck: COORD and ZCORN converted to {system.unit('length')} "
        f"(x {factor:.10g}), as OPM Flow does"
    )
    return coord * factor, zcorn * factor


_TOPS_SNAP_METRES = 1e-6  # OPM Flow's tolerance


def _snapped_tops(tops: np.ndarray, dz: np.ndarray, units: str | None) -> np.ndarray:
    """TOPS (nz, ny, nx) as OPM Flow takes them: a top within 1e-6 m of the bottom of the cell
    above (TOPS + DZ there) is that bottom, so that the two cells touch (a deck's printed TOPS
    rounded otherwise leaves a gap of 1e-7 between them); layer by layer, from the top."""
    tops = tops.copy()
    tolerance = _TOPS_SNAP_METRES / unit_system(units).length
    for k in range(1, tops.shape[0]):
        bottom = tops[k - 1] + dz[k - 1]
        close = np.abs(tops[k] - bottom) < tolerance
        tops[k][close] = bottom[close]
    return tops


def _cartesian_geometry(state: ReaderState, arrays: dict, where: str) -> tuple[np.ndarray, np.ndarray]:
    """COORD/ZCORN of a block-centred grid from DX/DY/DZ (or DXV/DYV/DZV) and TOPS (or DEPTHZ).

    The keywords are checked and gathered here (a cell size per cell, the depths
    of the top layer's corners); TOPS below the first layer default to the
    bottom of the cell above, and the boxes become pillars and corner depths in
    :func:`~gridlib.cornerpoint.cartesian.cartesian_to_cornerpoint`.
    """
    nx, ny, nz = state.dims  # type: ignore[misc]
    shape = (nz, ny, nx)
    sizes = {}
    for axis, name in enumerate(("DX", "DY", "DZ")):
        vec = state.vectors.get(name + "V")
        if name in arrays:
            sizes[name] = arrays[name].reshape(shape)
        elif vec is not None:
            sizes[name] = np.broadcast_to(vec.reshape([-1 if a == 2 - axis else 1 for a in range(3)]), shape)
        else:
            raise DeckError(
                f"{where}: no grid geometry: COORD/ZCORN, GDFILE, or DX/DY/DZ with TOPS are needed"
            )
        if np.isnan(sizes[name]).any():
            raise DeckError(f"{where}: {name} is undefined in some cells")
        if np.any(sizes[name] < 0):
            raise DeckError(f"{where}: {name} has negative values")
    top = np.full((nz, ny, nx, 2, 2), np.nan)  # per cell: the depths of its 4 top corners
    if "TOPS" in arrays:
        tops = _snapped_tops(arrays["TOPS"].reshape(shape), sizes["DZ"], state.units)
        top[:] = tops[..., None, None]
    elif "DEPTHZ" in state.vectors:
        d = state.vectors["DEPTHZ"].reshape(ny + 1, nx + 1)
        top[0] = np.stack(
            [np.stack([d[:-1, :-1], d[:-1, 1:]], -1), np.stack([d[1:, :-1], d[1:, 1:]], -1)], -2
        )
    else:
        raise DeckError(f"{where}: TOPS (or DEPTHZ) is missing: the Cartesian grid has no depth")
    if np.isnan(top[0]).any():
        raise DeckError(f"{where}: TOPS is undefined for some cells of the top layer")
    return cartesian_to_cornerpoint(sizes["DX"], sizes["DY"], sizes["DZ"], top)
