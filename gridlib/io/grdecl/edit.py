"""The EDIT section a :class:`~gridlib.cornerpoint.deck.Deck` holds, as ECLIPSE text.

What OPM Flow 2022.10 reads only in EDIT, written so that Flow (and ``read_grdecl``)
reading the text after an ``EDIT`` keyword get the deck's values back exactly:

* PORV where the deck's EDIT section gives it (``cell_data["PORV"]``; NaN, the cells
  whose pore volume Flow computes, stay unset): the whole array when every cell has
  one, else one BOX per run of given cells along i. Flow computes the others from the
  GRID part, whose MULTPV is the one in force when the deck first set PORV;
* the operations on TRANX, TRANY and TRANZ in deck order (``tran_edits``), each with
  its box: the keyword itself (``n*`` where the deck defaulted values), EQUALS,
  MULTIPLY, ADD, MINVALUE, MAXVALUE;
* EDITNNC, its records in deck order.

The EDIT section's MULT* arrays are not here: the reader has multiplied them into the
GRID values (``cell_data``), which the GRID part carries.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from ...cell_names import ijk
from ...cornerpoint.connection_keywords import Box, TranEdit
from ...cornerpoint.deck import Deck
from ..eclipse_text import format_values, keyword_text

__all__ = ["edit_section_contents", "edit_section_text", "has_edit_section"]


def edit_section_contents(deck: Deck) -> list[str]:
    """What ``deck``'s EDIT section holds that Flow reads nowhere else, in words (empty: none)."""
    porv = deck.cell_data.get("PORV")
    given = 0 if porv is None else int((~np.isnan(porv)).sum())
    out = [f"PORV of {given} cells"] if given else []
    out += [f"{len(deck.tran_edits)} TRANX/TRANY/TRANZ operations"] if deck.tran_edits else []
    if deck.editnnc is not None and deck.editnnc.num:
        out.append(f"EDITNNC ({deck.editnnc.num} records)")
    return out


def has_edit_section(deck: Deck) -> bool:
    """Whether ``deck`` holds anything Flow reads only in the EDIT section."""
    return bool(edit_section_contents(deck))


def edit_section_text(deck: Deck) -> Iterator[bytes]:
    """The contents of ``deck``'s EDIT section (without the ``EDIT`` keyword), in blocks."""
    porv = deck.cell_data.get("PORV")
    if porv is not None:
        yield from _porv_text(porv, deck.cart_dims)
    for edit in deck.tran_edits:
        yield _tran_edit_text(edit)
    if deck.editnnc is not None and deck.editnnc.num:
        yield _editnnc_text(deck)


def _box_text(box: Box) -> str:
    """'I1 I2 J1 J2 K1 K2', 1-based, of a 0-based inclusive box."""
    return " ".join(str(b + 1) for b in box)


def _porv_text(porv: np.ndarray, dims: tuple[int, int, int]) -> Iterator[bytes]:
    given = ~np.isnan(porv)
    if given.all():
        yield from keyword_text(
            "PORV", porv, "pore volumes given in the EDIT section (the deck's reservoir volume unit)"
        )
        return
    if not given.any():
        return
    nx, ny, _ = dims
    cells = np.flatnonzero(given)
    # runs of given cells along i: a new run where a cell does not follow the previous one in its row
    new_run = np.ones(cells.size, dtype=bool)
    new_run[1:] = (np.diff(cells) != 1) | (cells[1:] % nx == 0)
    starts = np.flatnonzero(new_run)
    ends = np.append(starts[1:], cells.size) - 1
    yield b"-- PORV (reservoir volume unit) of the cells the EDIT section gives; Flow computes the rest\n"
    for first, last in zip(starts.tolist(), ends.tolist(), strict=True):
        g1, g2 = int(cells[first]), int(cells[last])
        i, j, k = g1 % nx, g1 // nx % ny, g1 // (nx * ny)
        box = (i, g2 % nx, j, j, k, k)
        yield f"BOX\n {_box_text(box)} /\n".encode("ascii")
        yield from keyword_text("PORV", porv[g1 : g2 + 1])
        yield b"ENDBOX\n\n"


def _tran_edit_text(edit: TranEdit) -> bytes:
    where = f"-- {edit.source}\n" if edit.source else ""
    if edit.operation != "SET":
        record = f" '{edit.keyword}' {edit.value!r} {_box_text(edit.box)} /"
        return f"{where}{edit.operation}\n{record}\n/\n\n".encode("ascii", "replace")
    values = edit.values
    defaulted = np.isnan(values)
    starts = np.flatnonzero(np.diff(defaulted, prepend=~defaulted[0]))  # runs of given / defaulted values
    ends = np.append(starts[1:], values.size)
    parts: list[bytes] = []
    for start, end in zip(starts.tolist(), ends.tolist(), strict=True):
        if defaulted[start]:
            parts.append(f"{end - start}*\n".encode("ascii"))  # n*: left as Flow computed it
        else:
            parts.extend(format_values(values[start:end]))
    head = f"{where}BOX\n {_box_text(edit.box)} /\n{edit.keyword}\n".encode("ascii", "replace")
    return head + b"".join(parts) + b"/\nENDBOX\n\n"


def _editnnc_text(deck: Deck) -> bytes:
    cells = deck.editnnc.cells
    rows = np.hstack([ijk(cells[:, 0], deck.cart_dims), ijk(cells[:, 1], deck.cart_dims)]).tolist()
    lines = [
        " " + " ".join(map(str, row)) + f" {m!r} /"
        for row, m in zip(rows, deck.editnnc.values.tolist(), strict=True)
    ]
    text = ["EDITNNC", "-- I1 J1 K1 I2 J2 K2 transmissibility multiplier", *lines, "/", "", ""]
    return "\n".join(text).encode("ascii")
