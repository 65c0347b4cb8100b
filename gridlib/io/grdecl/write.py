"""``write_grdecl``: a :class:`~gridlib.cornerpoint.deck.Deck` written as a GRDECL file, exactly.

Arrays are written by :func:`gridlib.io.eclipse_text.keyword_text`, block by
block, straight into the file: the text of a 1e7-cell ZCORN is never held in
memory at once.
"""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path

import numpy as np

from ...cell_names import ijk
from ...cornerpoint.deck import Deck
from ..atomic import atomic_path
from ..eclipse_text import MAX_LINE, DeckError, keyword_text
from .edit import edit_section_text, has_edit_section

__all__ = ["write_edit_grdecl", "write_grdecl"]


def _finite_zcorn(deck: Deck) -> np.ndarray:
    """ZCORN with the undefined (NaN) corners of inactive cells filled, for simulators.

    Each undefined corner takes the depth of the nearest defined corner above
    it on its pillar (below it at the top), so the filled cells are collapsed
    and the order along the pillar is kept; a corner column with no defined
    depth takes the deck's shallowest depth.
    """
    z = deck.zcorn_array()
    undefined = np.isnan(z)
    if not undefined.any():
        return deck.zcorn
    nx, ny, nz = deck.cart_dims
    active = np.repeat(np.repeat(np.repeat(deck.active.reshape(nz, ny, nx), 2, 0), 2, 1), 2, 2)
    if np.any(undefined & active):
        raise DeckError(f"write_grdecl: {deck.source}: active cells have undefined (NaN) corner depths")
    if undefined.all():
        raise DeckError(f"write_grdecl: {deck.source}: ZCORN is undefined everywhere")
    rows = np.arange(z.shape[0])[:, None, None]
    above = np.maximum.accumulate(np.where(undefined, -1, rows), axis=0)
    below = np.minimum.accumulate(np.where(undefined, z.shape[0], rows)[::-1], axis=0)[::-1]
    source = np.where(above >= 0, above, below)
    filled = np.take_along_axis(z, np.minimum(source, z.shape[0] - 1), axis=0)
    filled = np.where(source < z.shape[0], filled, np.nanmin(z))
    return np.where(undefined, filled, z).ravel()


def _ijk_text(g: int, dims: tuple[int, int, int]) -> str:
    """1-based "I J K" of linear cell index ``g``."""
    return " ".join(str(int(v)) for v in ijk([g], dims)[0])


def write_grdecl(
    path: str | os.PathLike, deck: Deck, cell_data: dict | None = None, *, edit: bool = True
) -> Path:
    """Write ``deck`` (and extra per-cell ``cell_data``) as a GRDECL file, atomically.

    The file holds SPECGRID, MAPUNITS/MAPAXES/GRIDUNIT when known, COORD,
    ZCORN, ACTNUM, every cell keyword but PORV, FAULTS, MULTFLT, PINCH, MINPV,
    MULTREGT and NNC: what the GRID section of a DATA deck holds. Then, with
    ``edit`` and if the deck has any, the ``EDIT`` keyword and the deck's EDIT
    section (:mod:`~gridlib.io.grdecl.edit`: PORV, the TRANX/TRANY/TRANZ
    operations, EDITNNC), which OPM Flow reads nowhere else; the file, INCLUDEd at
    the end of the GRID section, then opens the EDIT section. With ``edit=False``
    it is a pure GRID include and :func:`write_edit_grdecl` writes the rest.
    Values are exact: ``read_grdecl`` gives back bit-identical arrays; the cells a keyword leaves
    undefined (NaN: the deck gave them no value) are written defaulted (``n*``), undefined again
    for OPM Flow and ``read_grdecl``. GRIDOPTS
    (RUNSPEC) is not written: MULTREGT records name their region set.
    """
    nx, ny, nz = deck.cart_dims
    if cell_data:
        extra = {
            name.upper(): np.asarray(values, dtype=np.float64).ravel() for name, values in cell_data.items()
        }
        for name, arr in extra.items():
            if arr.size != deck.num_cells:
                raise DeckError(f"write_grdecl: {name} has {arr.size} values, expected {deck.num_cells}")
        deck = replace(deck, cell_data={**deck.cell_data, **extra})
    data = {name: values for name, values in deck.cell_data.items() if name != "PORV"}  # PORV: EDIT only
    parts = [f"-- written by gridlib from {deck.source}", "", "SPECGRID", f" {nx} {ny} {nz} 1 F /", ""]
    if deck.mapunits:
        parts += ["MAPUNITS", f" '{deck.mapunits}' /", ""]
    if deck.mapaxes is not None:
        axes = [repr(float(v)) for v in deck.mapaxes]
        line = " " + " ".join(axes) + " /"
        if len(line) > MAX_LINE:  # three points, one a line
            line = "\n".join(" " + " ".join(axes[i : i + 2]) for i in range(0, len(axes), 2)) + " /"
        parts += ["MAPAXES", line, ""]
    if deck.gridunit:
        parts += ["GRIDUNIT", f" '{deck.gridunit}' /", ""]
    arrays: list[tuple[str, np.ndarray, bool]] = [("COORD", deck.coord, False)]
    arrays.append(("ZCORN", _finite_zcorn(deck), False))
    if deck.actnum is not None:
        arrays.append(("ACTNUM", deck.actnum, True))
    for name, values in data.items():
        defined = values[~np.isnan(values)]
        integer = bool(np.all(defined == np.round(defined))) and name.endswith("NUM")
        arrays.append((name, values, integer))
    tail: list[str] = []
    if deck.faults:
        tail.append("FAULTS")
        for seg in deck.faults:
            box = (seg.i1 + 1, seg.i2 + 1, seg.j1 + 1, seg.j2 + 1, seg.k1 + 1, seg.k2 + 1)
            tail.append(f" '{seg.name}' " + " ".join(map(str, box)) + f" {seg.face} /")
        tail += ["/", ""]
    if deck.multflt:
        tail.append("MULTFLT")
        tail += [f" '{name}' {float(value)!r} /" for name, value in deck.multflt.items()]
        tail += ["/", ""]
    if deck.pinch is not None:
        gap, pinchout, multz = deck.pinch_options
        tail += [
            "PINCH",
            f" {float(deck.pinch[0])!r} {gap} {float(deck.pinch[1])!r} {pinchout} {multz} /",
            "",
        ]
    if deck.minpv is not None:
        tail += ["MINPV", f" {float(deck.minpv)!r} /", ""]
    if deck.multregt:
        tail.append("MULTREGT")
        for r in deck.multregt:
            items = (
                r.region1,
                r.region2,
                repr(float(r.multiplier)),
                r.directions,
                r.nnc_option,
                r.region_set,
            )
            tail.append(" " + " ".join("1*" if v is None else str(v) for v in items) + " /")
        tail += ["/", ""]
    if deck.nnc_keyword is not None and deck.nnc_keyword.num:
        tail.append("NNC")
        records = zip(deck.nnc_keyword.cells.tolist(), deck.nnc_keyword.values.tolist(), strict=True)
        dims = deck.cart_dims
        tail += [f" {_ijk_text(g1, dims)} {_ijk_text(g2, dims)} {t!r} /" for (g1, g2), t in records]
        tail += ["/", ""]
    target = Path(path)
    with atomic_path(target) as tmp, open(tmp, "wb") as f:
        f.write(("\n".join(parts) + "\n").encode("ascii"))
        for name, values, integer in arrays:  # cells a keyword leaves undefined (NaN) stay so: n*
            for block in keyword_text(
                name, values, integer=integer, undefined=name not in ("COORD", "ZCORN")
            ):
                f.write(block)
        f.write(("\n".join(tail) + "\n").encode("ascii") if tail else b"")
        if edit and has_edit_section(deck):
            f.write(b"EDIT\n\n")
            for block in edit_section_text(deck):
                f.write(block)
    return target


def write_edit_grdecl(path: str | os.PathLike, deck: Deck) -> Path | None:
    """Write the contents of ``deck``'s EDIT section (:mod:`~gridlib.io.grdecl.edit`), to be
    INCLUDEd after the ``EDIT`` keyword of a DATA deck, atomically; None (and no file) if
    the deck has none."""
    if not has_edit_section(deck):
        return None
    target = Path(path)
    with atomic_path(target) as tmp, open(tmp, "wb") as f:
        f.write(f"-- written by gridlib from {deck.source}: its EDIT section\n\n".encode("ascii", "replace"))
        for block in edit_section_text(deck):
            f.write(block)
    return target
