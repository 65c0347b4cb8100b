"""Binary GRDECL: a GRDECL's keywords as ECLIPSE's keyword records (unformatted, or formatted),
the ``.bgrdecl`` of RMS and xtgeo and the file a deck's ``IMPORT`` names, read with ``resfo``
into the text reader's :class:`~gridlib.io.grdecl.state.ReaderState`.

Such a file holds whole arrays only (no BOX, EQUALS or records): the dimensions (SPECGRID or
DIMENS), MAPAXES, MAPUNITS, GRIDUNIT, COORD, ZCORN and cell arrays (ACTNUM, PORO, PERMX, ...;
one value per cell). Each is checked as its text form is (the same messages, naming the file
and the keyword's place in it, ``model.bgrdecl:keyword 4: PORO: ...``). A name neither ECLIPSE
nor OPM Flow knows (xtgeo writes its own parameters, ``Zone``, ``Region``) is an error, or with
``unknown_keywords="skip"`` skipped and noted, as in a text deck.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ...memory import count_text, memory_shortfall
from ..eclipse_text import DeckError, Numbers
from .keywords import (
    KNOWN_KEYWORDS,
    READ_BYTES_PER_CELL,
    UNITS,
    finite_geometry,
    is_cell_keyword,
    store,
    zcorn_corner_name,
)
from .state import ReaderState

__all__ = ["is_binary_keyword_file", "read_binary_file"]

# The start of an unformatted keyword file: the record length 16 (an 8-character name, the
# count and a 4-character type), big-endian as ECLIPSE writes it, or little-endian.
_MARKERS = (b"\x00\x00\x00\x10", b"\x10\x00\x00\x00")


def is_binary_keyword_file(path: Path) -> bool:
    """Does ``path`` start as an unformatted ECLIPSE keyword file (a printable 8-character name
    after the first record marker)?"""
    with open(path, "rb") as f:
        head = f.read(12)
    return len(head) == 12 and head[:4] in _MARKERS and all(32 <= b < 127 for b in head[4:12])


class BinaryRecord:
    """A keyword of a binary file, as the text reader's checks name their place: the file and
    the keyword's number in it (1 the first)."""

    def __init__(self, path: Path, number: int) -> None:
        self.path = path
        self.number = number

    def line(self, pos: int) -> str:
        return f"keyword {self.number}"

    def error(self, pos: int, keyword: str | None, message: str) -> DeckError:
        where = f"{self.path}:keyword {self.number}"
        return DeckError(f"{where}: {keyword}: {message}" if keyword else f"{where}: {message}")


def read_binary_file(state: ReaderState, path: Path) -> None:
    """The keywords of the binary keyword file ``path`` into ``state``."""
    import resfo

    form = resfo.Format.UNFORMATTED if is_binary_keyword_file(path) else resfo.Format.FORMATTED
    try:
        records = [(name.strip(), np.asarray(values)) for name, values in resfo.read(path, fileformat=form)]
    except (resfo.ResfoParsingError, OSError, ValueError, UnicodeDecodeError) as exc:
        raise DeckError(f"{path}: not a readable binary GRDECL file ({exc})") from None
    for number, (name, values) in enumerate(records, start=1):
        record = BinaryRecord(path, number)
        if name not in KNOWN_KEYWORDS:
            where = f"{path.name}:keyword {number}"
            if state.unknown_keywords == "error":
                raise record.error(
                    0,
                    None,
                    f"unknown keyword {name!r}: neither ECLIPSE nor OPM Flow knows it; "
                    "read_grdecl(..., unknown_keywords='skip') (a deck case's grid.unknown_keywords: "
                    "skip) skips such keywords",
                )
            state.unknown.setdefault(name, where)
            continue
        _keyword(state, record, name, values)


def _keyword(state: ReaderState, record: BinaryRecord, name: str, values: np.ndarray) -> None:
    """One whole array of a binary file into ``state``, checked as its text form is."""
    if name in ("SPECGRID", "DIMENS"):
        _dims(state, record, name, values)
    elif name == "MAPAXES":
        numbers = _floats(record, name, values, 6)
        if not np.isfinite(numbers).all():
            raise record.error(0, name, "needs six finite numbers (nan/inf given)")
        state.mapaxes = numbers
    elif name in ("MAPUNITS", "GRIDUNIT"):
        items = [v.decode("latin-1") if isinstance(v, bytes) else str(v) for v in values.ravel()]
        items = [i.strip() for i in items if i.strip()]
        if name == "MAPUNITS":
            state.mapunits = " ".join(items) or None
        else:
            state.gridunit = items[0] if items else None
    elif name in UNITS:
        state.units = name
    elif name in ("COORD", "ZCORN"):
        nx, ny, _ = _need_dims(state, record, name)
        expected = 6 * (nx + 1) * (ny + 1) if name == "COORD" else 8 * state.num_cells
        numbers = _floats(record, name, values, expected)
        if name == "COORD":
            finite_geometry(
                record, 0, name, numbers, 6, lambda p: f"pillar ({p % (nx + 1) + 1}, {p // (nx + 1) + 1})"
            )
            state.coord = numbers
        else:
            finite_geometry(record, 0, name, numbers, 1, zcorn_corner_name(nx, ny))
            state.zcorn = numbers
    elif is_cell_keyword(name):
        _need_dims(state, record, name)
        numbers = _floats(record, name, values, state.num_cells)
        store(state, record, 0, name, Numbers(numbers, None), None, state.num_cells)
    else:  # a keyword of a deck's other sections
        state.skipped.setdefault(name, f"{record.path.name}:keyword {record.number}")


def _dims(state: ReaderState, record: BinaryRecord, name: str, values: np.ndarray) -> None:
    if values.dtype.kind not in "iu" or values.size < 3 or int(values[:3].min()) < 1:
        raise record.error(0, name, f"needs three positive integers (NX NY NZ), got {values[:3].tolist()}")
    dims = tuple(int(v) for v in values[:3])
    cells = dims[0] * dims[1] * dims[2]
    refusal = memory_shortfall(cells * READ_BYTES_PER_CELL, f"{count_text(cells)} cells", "to read")
    if refusal is not None:
        raise record.error(0, name, f"{dims[0]} {dims[1]} {dims[2]}: {refusal}")
    if state.dims is not None and state.dims != dims:
        raise record.error(0, name, f"dimensions {dims} differ from {state.dims} given earlier")
    state.dims = dims  # type: ignore[assignment]


def _need_dims(state: ReaderState, record: BinaryRecord, name: str) -> tuple[int, int, int]:
    if state.dims is None:
        raise record.error(0, name, "the grid dimensions are not known yet (SPECGRID must come first)")
    return state.dims


def _floats(record: BinaryRecord, name: str, values: np.ndarray, expected: int) -> np.ndarray:
    """``values`` (numbers) as float64, ``expected`` of them."""
    if values.dtype.kind not in "iuf":
        raise record.error(0, name, f"expected numbers, found {values.dtype} values")
    if values.size != expected:
        raise record.error(0, name, f"has {values.size} values, expected {expected}")
    return values.astype(np.float64)
