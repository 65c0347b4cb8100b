"""The GRDECL reader's keyword loop (:func:`read_file`) and one handler per keyword it reads.

Each handler takes the reader's state, the source, the position of the keyword's data (the
line after the keyword's), the keyword and the INCLUDE depth, stores what the keyword says in
the state and returns the position after its data. INCLUDE reads the included file with
:func:`read_file` again, one level deeper. Keywords without a handler are looked up in the
:mod:`~gridlib.io.grdecl.vocabulary`: an array of one value per cell is kept, anything else is
skipped by its shape (:mod:`~gridlib.io.grdecl.shapes`); a name outside the vocabulary is an
error, or with ``unknown_keywords="skip"`` skipped to the next line that starts with a keyword.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from ... import reproducible
from ...cornerpoint.connection_keywords import TRAN_KEYWORDS, TranEdit
from ...cornerpoint.deck import FAULT_FACES, PINCH_DEFAULTS, FaultSegment
from ...memory import count_text, memory_shortfall
from ..connection_records import cell_pair_record, gridopts_record, multregt_record
from ..eclipse_text import (
    KEYWORD_NAME,
    MAX_KEYWORD_LENGTH,
    DeckError,
    Item,
    Numbers,
    Source,
    float_item,
    int_item,
    line_word,
    next_line,
    read_keyword,
    read_numbers,
    read_record,
    read_records,
    skip_blank,
)
from ..egrid import read_egrid
from .shapes import skip_data
from .state import ReaderState
from .values import MAX_LENGTH, check_cell_values, check_finite, check_not_negative
from .vocabulary import KeywordInfo, vocabulary

__all__ = ["SECTIONS", "UNITS", "UNKNOWN_KEYWORDS", "open_source", "read_file"]

UNITS = ("METRIC", "FIELD", "LAB", "PVT-M")
SECTIONS = ("RUNSPEC", "GRID", "EDIT", "PROPS", "REGIONS", "SOLUTION", "SUMMARY", "SCHEDULE", "OPTIMIZE")
_STOP_SECTIONS = ("SOLUTION", "SUMMARY", "SCHEDULE", "OPTIMIZE")
_CELL_SECTIONS = (None, "GRID", "EDIT", "PROPS", "REGIONS")  # None: a GRDECL file without sections
UNKNOWN_KEYWORDS = ("error", "skip")
# Cell keywords with a default value (used when EQUALS/ADD/... touch them before they are set).
_MULTIPLIER_KEYWORDS = frozenset(f"MULT{d}{s}" for d in "XYZ" for s in ("", "-"))
_DEFAULTS = {"ACTNUM": 1.0, "NTG": 1.0, "MULTPV": 1.0, "MULTNUM": 1.0}
_DEFAULTS |= dict.fromkeys(_MULTIPLIER_KEYWORDS, 1.0)
# Cell keywords we know (their count is checked); other arrays of one value per cell are kept too.
_CELL_KEYWORDS = frozenset(
    """ACTNUM PORO NTG PERMX PERMY PERMZ PERMXY PERMYZ PERMZX MULTX MULTY MULTZ MULTX- MULTY- MULTZ-
    MULTPV PORV DX DY DZ TOPS SATNUM FIPNUM EQLNUM PVTNUM IMBNUM ROCKNUM MINPVV SWATINIT
    DEPTH SWL SWCR SWU SGL SGCR SGU SOWCR SOGCR KRW KRO KRG PCW PCG MULTNUM FLUXNUM OPERNUM
    DIFFX DIFFY DIFFZ THCONR HEATCR""".split()
)
_MAX_INCLUDE_DEPTH = 32
# Bytes per cell a deck takes to read: ZCORN's eight float64 (64 B), as much again while its text
# is parsed, and four cell arrays (ACTNUM, PORO, PERMX, NTG: 32 B); COORD is small beside them.
READ_BYTES_PER_CELL = 160
_DATA_START = re.compile(rb"[\d+\-.*'/]")  # text after a keyword that looks like its data


class _KnownKeywords:
    """Names that start a keyword: the vocabulary's and those the reader handles."""

    def __contains__(self, name: object) -> bool:
        if not isinstance(name, str):
            return False
        known = vocabulary()
        return name in _HANDLERS or name in SECTIONS or name in known or name[:MAX_KEYWORD_LENGTH] in known


KNOWN_KEYWORDS = _KnownKeywords()


def open_source(path: Path) -> Source:
    """A deck file, read with the keywords that end a record written without its '/'."""
    return Source.open(path, KNOWN_KEYWORDS)


# Cartesian geometry keywords that may give the top layer only, or the upper layers (OPM Flow)
_TOP_DOWN_KEYWORDS = frozenset({"DX", "DY", "DZ", "TOPS"})
# GRID keywords whose cells left undefined take the value of their column's top cell (OPM Flow)
_FROM_TOP_LAYER = frozenset({"PORO", "PERMX", "PERMY", "PERMZ"})


def read_file(state: ReaderState, src: Source, depth: int) -> None:
    """Read the keywords of ``src`` into ``state`` (``depth``: how deep in INCLUDEs) up to the end
    of the file, ENDINC, END, or a section the reader stops at."""
    pos = 0
    while not state.stopped:
        line = read_keyword(src, pos)
        if line is None:
            return
        name, at, pos = line.name, line.at, line.data_start
        if name == "/":  # a stray '/': OPM Flow ignores it
            state.notes.append(f"{src.path.name}:{src.line(at)}: a '/' where a keyword should be: ignored")
            continue
        if name not in KNOWN_KEYWORDS or (len(name) > MAX_KEYWORD_LENGTH and name not in _HANDLERS):
            name, pos = _long_or_unknown(state, src, at, pos, name)
            if name is None:
                continue
        if _DATA_START.match(line.ignored) and name != "TITLE":
            state.notes.append(
                f"{src.path.name}:{src.line(at)}: {name}: text after the keyword on its line ignored "
                f"({line.ignored[:40].decode('latin-1')!r}; data start on the next line)"
            )
        if name in SECTIONS:
            state.section = name
            if name in _STOP_SECTIONS:
                state.stopped = True
                state.notes.append(
                    f"{src.path}:{src.line(at)}: stopped at {name}: later sections are not read"
                )
            continue
        if name == "END":
            state.stopped = True
            return
        if name == "ENDINC":
            return
        if name in UNITS:
            state.units = name
            continue
        handler = _HANDLERS.get(name)
        if handler is not None:
            pos = handler(state, src, pos, name, depth)
        elif name in _CELL_KEYWORDS:
            pos = _cell_array(state, src, pos, name)
        else:
            info = vocabulary().get(name)
            assert info is not None
            pos = _other_keyword(state, src, pos, info)


def _long_or_unknown(state: ReaderState, src: Source, at: int, pos: int, name: str) -> tuple[str | None, int]:
    """A name longer than 8 characters whose first 8 are a keyword is that keyword (as ECLIPSE and
    OPM Flow read it); any other name nobody knows is an error or, with unknown_keywords="skip",
    skipped up to the next line that starts with a word that could be a keyword."""
    where = f"{src.path.name}:{src.line(at)}"
    short = name[:MAX_KEYWORD_LENGTH]
    if len(name) > MAX_KEYWORD_LENGTH and short in KNOWN_KEYWORDS:
        state.notes.append(f"{where}: keyword {name} read as {short} (only 8 characters count)")
        return short, pos
    if state.unknown_keywords == "error":
        raise src.error(
            at,
            None,
            f"unknown keyword {name!r}: neither ECLIPSE nor OPM Flow knows it (misspelt?); "
            "read_grdecl(..., unknown_keywords='skip') (a deck case's grid.unknown_keywords: skip) "
            "skips such keywords",
        )
    state.unknown.setdefault(name, where)
    while True:  # as OPM Flow: lines up to one that starts with a name (known or not)
        word = line_word(src.data, pos)
        if word is None or KEYWORD_NAME.fullmatch(word):
            return None, skip_blank(src.data, pos)
        pos = next_line(src.data, skip_blank(src.data, pos))


def _other_keyword(state: ReaderState, src: Source, pos: int, info: KeywordInfo) -> int:
    """A keyword the reader has no handler for: an array of one value per cell (of the current
    BOX) in a section with cell data is kept; anything else is skipped by its shape."""
    name = info.name
    where = f"{src.path.name}:{src.line(pos)}"
    if info.shape.kind == "data" and state.section in _CELL_SECTIONS and state.dims is not None:
        try:
            numbers, end = read_numbers(src, pos, name, at_most=state.num_cells)
        except DeckError:
            numbers = None
        if numbers is not None and numbers.values.size == _box_size(state, state.box):
            store(state, src, pos, name, numbers, state.box, numbers.values.size)
            state.notes.append(f"{where}: {name} read as a cell keyword (one value per cell)")
            return end
    if info.shape.kind != "none":
        state.skipped.setdefault(name, where)
    return skip_data(state, src, pos, info)


# --- handlers ---------------------------------------------------------------------------------


def _need_dims(state: ReaderState, src: Source, pos: int, name: str) -> tuple[int, int, int]:
    if state.dims is None:
        raise src.error(
            pos, name, "the grid dimensions are not known yet (DIMENS or SPECGRID must come first)"
        )
    return state.dims


def _ints(src: Source, at: int, name: str, items: list[Item], n: int, what: str) -> list[int | None]:
    out = [int_item(src, at, name, v, what) for v in items[:n]]
    return out + [None] * (n - len(out))


def _dims_keyword(state, src, pos, name, depth):
    items, pos, at = read_record(src, pos, name)
    nx, ny, nz = _ints(src, at, name, items, 3, "dimensions")
    if None in (nx, ny, nz) or min(nx, ny, nz) < 1:
        raise src.error(at, name, f"needs three positive integers (NX NY NZ), got {items[:3]}")
    if name == "SPECGRID" and len(items) >= 5 and items[4] is not None and items[4].upper().startswith("T"):
        raise src.error(at, name, "radial (cylindrical) grids are not supported")
    dims = (nx, ny, nz)
    cells = nx * ny * nz
    refusal = memory_shortfall(cells * READ_BYTES_PER_CELL, f"{count_text(cells)} cells", "to read")
    if refusal is not None:
        raise src.error(at, name, f"{nx} {ny} {nz}: {refusal}")
    if state.dims is not None and state.dims != dims:
        raise src.error(at, name, f"dimensions {dims} differ from {state.dims} given earlier")
    state.dims = dims  # type: ignore[assignment]
    return pos


def _title(state, src, pos, name, depth):
    """TITLE: the line after the keyword's is free text (no '/')."""
    return next_line(src.data, next_line(src.data, pos))


def _coord(state, src, pos, name, depth):
    nx, ny, _ = _need_dims(state, src, pos, name)
    numbers, end = read_numbers(src, pos, name, expected=6 * (nx + 1) * (ny + 1))
    _no_defaults(src, end, name, numbers)
    finite_geometry(
        src, pos, name, numbers.values, 6, lambda p: f"pillar ({p % (nx + 1) + 1}, {p // (nx + 1) + 1})"
    )
    state.coord = numbers.values
    return end


def _zcorn(state, src, pos, name, depth):
    nx, ny, _ = _need_dims(state, src, pos, name)
    numbers, end = read_numbers(src, pos, name, expected=8 * state.num_cells)
    _no_defaults(src, end, name, numbers)
    finite_geometry(src, pos, name, numbers.values, 1, zcorn_corner_name(nx, ny))
    state.zcorn = numbers.values
    return end


def zcorn_corner_name(nx: int, ny: int):
    """The name of ZCORN's entry n in messages: a corner of the cell owning it (ZCORN is
    (2nz, 2ny, 2nx), i fastest)."""

    def corner_of(n: int) -> str:
        i2, j2, k2 = n % (2 * nx), n // (2 * nx) % (2 * ny), n // (4 * nx * ny)
        return f"a corner of cell ({i2 // 2 + 1}, {j2 // 2 + 1}, {k2 // 2 + 1})"

    return corner_of


def finite_geometry(src, pos, name, values, per_item, item_name) -> None:
    """COORD and ZCORN must be finite numbers of at most MAX_LENGTH in size; the first bad one
    named by ``item_name(index)``."""
    bad = np.flatnonzero(~(np.abs(values) <= MAX_LENGTH))
    if bad.size:
        raise src.error(
            pos,
            name,
            f"{bad.size} values are not finite numbers within +-{MAX_LENGTH:g} "
            f"(first {float(values[bad[0]])}, {item_name(int(bad[0]) // per_item)})",
        )


def _no_defaults(src, pos, name, numbers):
    if numbers.defaulted is not None:
        raise src.error(pos, name, "values cannot be defaulted (n*) here")


def _vector(state, src, pos, name, depth):
    nx, ny, nz = _need_dims(state, src, pos, name)
    n = {"DXV": nx, "DYV": ny, "DZV": nz, "DEPTHZ": (nx + 1) * (ny + 1)}[name]
    numbers, end = read_numbers(src, pos, name, expected=n)
    _no_defaults(src, end, name, numbers)
    values = numbers.values
    bad = np.flatnonzero(~(np.abs(values) <= MAX_LENGTH) | ((values < 0) & (name != "DEPTHZ")))
    if bad.size:
        what = f"not finite numbers within +-{MAX_LENGTH:g}"
        what += "" if name == "DEPTHZ" else " or negative (cell sizes)"
        raise src.error(
            pos, name, f"{bad.size} values are {what}: value {bad[0] + 1} is {float(values[bad[0]])}"
        )
    state.vectors[name] = values
    return end


def _box_cells(state: ReaderState, box: tuple[int, ...] | None) -> np.ndarray | slice:
    """Linear cell indices (i fastest) of a 0-based inclusive box, or all cells."""
    if box is None:
        return slice(None)
    nx, ny, _ = state.dims  # type: ignore[misc]
    i1, i2, j1, j2, k1, k2 = box
    k, j, i = np.meshgrid(np.arange(k1, k2 + 1), np.arange(j1, j2 + 1), np.arange(i1, i2 + 1), indexing="ij")
    return (i + nx * (j + ny * k)).ravel()


def _box_size(state: ReaderState, box: tuple[int, ...] | None) -> int:
    if box is None:
        return state.num_cells
    i1, i2, j1, j2, k1, k2 = box
    return (i2 - i1 + 1) * (j2 - j1 + 1) * (k2 - k1 + 1)


def _array(state: ReaderState, name: str) -> np.ndarray:
    if name not in state.arrays:
        state.arrays[name] = np.full(state.num_cells, _DEFAULTS.get(name, np.nan))
    return state.arrays[name]


def _cell_array(state, src, pos, name, depth=0):
    nx, ny, _ = _need_dims(state, src, pos, name)
    box = state.box
    expected = _box_size(state, box)
    if name in _TOP_DOWN_KEYWORDS and box is None:
        # as OPM Flow: the top layer at least; the cells below take DX/DY/DZ of the cell above
        # (filled here), TOPS the bottom of the cell above (filled with the geometry)
        numbers, end = read_numbers(src, pos, name, at_most=state.num_cells)
        given = numbers.values.size
        if given < nx * ny:
            raise src.error(
                skip_blank(src.data, pos),
                name,
                f"has {given} values, expected {state.num_cells} (or at least the top layer's {nx * ny})",
            )
        if given < state.num_cells and name != "TOPS":
            # each cell below the given ones takes the value of the given cell above it in its
            # column: the nearest one a whole number of layers up
            area = nx * ny
            below = np.arange(given, state.num_cells)
            full = np.concatenate(
                [numbers.values, numbers.values[below - area * ((below - given) // area + 1)]]
            )
            defaulted = numbers.defaulted
            if defaulted is not None:  # the filled cells are given (the values above them)
                defaulted = np.concatenate([defaulted, np.zeros(full.size - given, bool)])
            numbers = Numbers(full, defaulted)
            state.notes.append(
                f"{src.path.name}:{src.line(pos)}: {name}: {given} values for {state.num_cells} cells: the "
                "cells below take the value of the cell above (as OPM Flow)"
            )
        expected = numbers.values.size
    else:
        numbers, end = read_numbers(src, pos, name, expected=expected)
    if name == "PORV":
        if state.section is not None and state.section != "EDIT":
            state.notes.append(
                f"{src.path.name}:{src.line(pos)}: PORV in the {state.section} section ignored "
                "(OPM Flow 2022.10 reads the keyword only in EDIT; EQUALS, MULTIPLY... act anywhere)"
            )
            return end
        _start_porv(state)
    multiply = state.section == "EDIT" and name in _MULTIPLIER_KEYWORDS  # as OPM Flow: cumulative
    store(state, src, pos, name, numbers, box, expected, multiply)
    if name in _FROM_TOP_LAYER and state.section != "EDIT":
        _fill_from_top_layer(state, src, pos, name, box)
    return end


def _fill_from_top_layer(state: ReaderState, src: Source, at: int, name: str, box) -> None:
    """As OPM Flow: cells still undefined after a keyword that gave values in the top layer
    take the value it gave to the top cell of their column."""
    nx, ny, nz = state.dims  # type: ignore[misc]
    i1, i2, j1, j2, k1, _ = _full_box(state, box)
    values = state.arrays[name].reshape(nz, ny, nx)
    undefined = np.isnan(values)
    if k1 != 0 or not undefined.any():
        return
    top = np.full((ny, nx), np.nan)
    top[j1 : j2 + 1, i1 : i2 + 1] = values[0, j1 : j2 + 1, i1 : i2 + 1]
    fill = undefined & ~np.isnan(top)
    if fill.any():
        values[fill] = np.broadcast_to(top, values.shape)[fill]
        state.notes.append(
            f"{src.path.name}:{src.line(at)}: {name}: {int(fill.sum())} undefined cells below the top "
            "layer take the value of the top cell of their column (as OPM Flow)"
        )


def _start_porv(state: ReaderState) -> None:
    """The first PORV (keyword, or operation on it) fixes the pore volumes of the cells it
    leaves to Flow (NaN here): bulk volume x PORO x NTG x the MULTPV in force then, which
    becomes the deck's MULTPV (as in OPM Flow 2022.10, a later MULTPV changes nothing)."""
    if "PORV" not in state.arrays:
        state.porv_multpv = _array(state, "MULTPV").copy()
        _array(state, "PORV")


def _porv_operation(state, src, at, name, value, cells) -> None:
    """MULTIPLY, ADD, MINVALUE, MAXVALUE on PORV: on the values the deck gave, and (MULTIPLY
    only) on the pore volumes Flow computes, through their MULTPV."""
    porv = state.arrays["PORV"]
    computed = np.isnan(porv[cells])
    if name == "MULTIPLY":
        porv[cells] *= value
        state.porv_multpv[cells] *= value
        return
    if computed.any():
        raise src.error(
            at,
            name,
            f"PORV: {int(computed.sum())} cells of the box have no PORV yet (Flow computes theirs); "
            f"{name} on computed pore volumes is not supported (give PORV for them first)",
        )
    if name == "ADD":
        porv[cells] += value
    elif name == "MINVALUE":
        porv[cells] = np.maximum(porv[cells], value)
    else:  # MAXVALUE
        porv[cells] = np.minimum(porv[cells], value)


def store(state, src, at, name, numbers, box, expected, multiply=False):
    """Keyword ``name``'s ``numbers`` into the cells of ``box`` (or the first ``expected`` cells),
    checked (:func:`~gridlib.io.grdecl.values.check_cell_values`) before they are stored."""
    target = _array(state, name)
    cells = _box_cells(state, box) if expected == _box_size(state, box) else np.arange(expected)
    values = numbers.values
    if multiply:
        values = target[cells] * values
    given = None
    if numbers.defaulted is not None:  # n* leaves the values as they were
        values = np.where(numbers.defaulted, target[cells], values)
        given = ~numbers.defaulted
    check_cell_values(state, src, at, name, values, cells, given)
    target[cells] = values


def _full_box(state: ReaderState, box: tuple[int, ...] | None) -> tuple[int, int, int, int, int, int]:
    nx, ny, nz = state.dims  # type: ignore[misc]
    return tuple(box) if box is not None else (0, nx - 1, 0, ny - 1, 0, nz - 1)  # type: ignore[return-value]


def _tran_array(state, src, pos, name, depth):
    """TRANX, TRANY, TRANZ: values the simulator computes, replaced in the EDIT section."""
    _need_dims(state, src, pos, name)
    at = skip_blank(src.data, pos)
    numbers, end = read_numbers(src, pos, name, expected=_box_size(state, state.box))
    where = f"{src.path.name}:{src.line(at)}"
    if state.section != "EDIT":
        state.notes.append(f"{where}: {name} outside the EDIT section ignored (as OPM Flow does)")
        return end
    values = numbers.values
    if numbers.defaulted is not None:
        values = np.where(numbers.defaulted, np.nan, values)
    state.tran_edits.append(TranEdit(name, "SET", _full_box(state, state.box), values=values, source=where))
    return end


def _include(state, src, pos, name, depth):
    items, pos, at = read_record(src, pos, name)
    if not items or items[0] is None:
        raise src.error(at, name, "needs a file name")
    path = _resolve(state, src, at, name, items[0])
    if depth + 1 > _MAX_INCLUDE_DEPTH:
        raise src.error(at, name, f"includes nested more than {_MAX_INCLUDE_DEPTH} deep (a cycle?)")
    read_file(state, open_source(path), depth + 1)
    return pos


_PATH_ALIAS = re.compile(r"\$([A-Za-z0-9_-]+)")


def _resolve(state: ReaderState, src: Source, at: int, name: str, text: str) -> Path:
    """The file an INCLUDE (or GDFILE) names: ``$ALIAS`` replaced by its PATHS value, ``\\``
    read as ``/``, and a relative path taken from the directory of the deck that was opened
    (the DATA file), not of the including file: as ECLIPSE and OPM Flow do."""
    alias = _PATH_ALIAS.search(text)
    if alias is not None:
        if alias.group(1) not in state.paths:
            known = ", ".join(sorted(state.paths)) or "none"
            raise src.error(
                at, name, f"path alias ${alias.group(1)} is not defined by PATHS (defined: {known})"
            )
        text = text.replace(alias.group(0), state.paths[alias.group(1)])
    text = text.replace("\\", "/")
    path = Path(text)
    if not path.is_absolute():
        path = state.main.parent / path
    if not path.is_file():
        raise src.error(
            at, name, f"file {text!r} not found (looked for {path}: relative to the DATA file's directory)"
        )
    return path


def _paths(state, src, pos, name, depth):
    records, pos = read_records(src, pos, name)
    for items, _ in records:
        if len(items) >= 2 and items[0] and items[1]:
            state.paths[items[0]] = items[1]
    return pos


def _gdfile(state, src, pos, name, depth):
    items, pos, at = read_record(src, pos, name)
    if not items or items[0] is None:
        raise src.error(at, name, "needs a file name")
    path = _resolve(state, src, at, name, items[0])
    state.gdfile = read_egrid(path)
    if state.dims is None:
        state.dims = state.gdfile.cart_dims
    elif state.dims != state.gdfile.cart_dims:
        raise src.error(
            at, name, f"{path.name} has dimensions {state.gdfile.cart_dims}, the deck {state.dims}"
        )
    return pos


def _box(state, src, pos, name, depth):
    items, pos, at = read_record(src, pos, name)
    state.box = _read_box(state, src, at, name, items, None)
    return pos


def _read_box(state, src, at, name, items, default) -> tuple[int, ...] | None:
    """A 1-based inclusive box (six items, any defaulted) as a 0-based tuple, or None = all cells."""
    nx, ny, nz = _need_dims(state, src, at, name)
    values = _ints(src, at, name, items, 6, "box")
    if all(v is None for v in values):
        return default
    base = default if default is not None else (0, nx - 1, 0, ny - 1, 0, nz - 1)
    box = tuple(base[a] if v is None else v - 1 for a, v in enumerate(values))
    i1, i2, j1, j2, k1, k2 = box
    if not (0 <= i1 <= i2 < nx and 0 <= j1 <= j2 < ny and 0 <= k1 <= k2 < nz):
        shown = " ".join(str(b + 1) for b in box)
        raise src.error(at, name, f"box {shown} is not inside the {nx}x{ny}x{nz} grid")
    return box


def _endbox(state, src, pos, name, depth):
    state.box = None
    return pos


def _operator(state, src, pos, name, depth):
    """EQUALS, ADD, MULTIPLY, MINVALUE, MAXVALUE (name value box) and COPY (from to box)."""
    _need_dims(state, src, pos, name)
    records, pos = read_records(src, pos, name)
    for items, at in records:
        if len(items) < 2 or items[0] is None or items[1] is None:
            raise src.error(
                at, name, f"a record needs a keyword and a {'target' if name == 'COPY' else 'value'}"
            )
        target = items[0].upper()
        for keyword in (target, items[1].upper()) if name == "COPY" else (target,):
            if not is_cell_keyword(keyword):
                raise src.error(
                    at,
                    name,
                    f"{keyword!r} is not a keyword with one value per cell (OPM Flow refuses it too)",
                )
        box = _read_box(state, src, at, name, items[2:8], state.box)
        if target in TRAN_KEYWORDS or (name == "COPY" and items[1].upper() in TRAN_KEYWORDS):
            _tran_operation(state, src, at, name, items, box)
            continue
        if target == "PORV" or (name == "COPY" and items[1].upper() == "PORV"):
            _start_porv(state)
        cells = _box_cells(state, box)
        if target == "PORV" and name != "EQUALS" and name != "COPY":
            _porv_operation(state, src, at, name, _operand(src, at, name, items[1], target), cells)
            continue
        if name == "COPY":
            dest = items[1].upper()
            if target not in state.arrays and target not in _DEFAULTS:
                raise src.error(at, name, f"cannot copy {target}: it is not defined")
            _array(state, dest)[cells] = _array(state, target)[cells]
            continue
        value = _operand(src, at, name, items[1], target)
        if name == "EQUALS":
            check_cell_values(
                state, src, at, target, np.full(_box_size(state, box), value), cells, None, name
            )
            _array(state, target)[cells] = value
            continue
        if target not in state.arrays and target not in _DEFAULTS:
            raise src.error(at, name, f"{target} is not defined")
        arr = _array(state, target)
        if name == "ADD":
            arr[cells] += value
        elif name == "MULTIPLY":
            arr[cells] *= value
        elif name == "MINVALUE":
            arr[cells] = np.maximum(arr[cells], value)
        else:  # MAXVALUE
            arr[cells] = np.minimum(arr[cells], value)
        check_cell_values(state, src, at, target, arr[cells], cells, ~np.isnan(arr[cells]), name)
    return pos


# The region sets of EQUALREG, ADDREG, MULTIREG, COPYREG and MULTREGP (their item's first letter)
_REGION_SETS = {"M": "MULTNUM", "F": "FLUXNUM", "O": "OPERNUM"}
# OPERATE's and OPERATER's operations: the new value from the target's ``r``, the source's ``x``
# and the record's alpha ``a`` and beta ``b`` (as OPM Flow defines them, in the deck's units)
# (the transcendental ones from gridlib.reproducible: the same bits on every machine)
_OPERATIONS = {
    "MULTA": lambda r, x, a, b: a * x + b,
    "POLY": lambda r, x, a, b: r + a * reproducible.power(x, np.full_like(x, b)),
    "SLOG": lambda r, x, a, b: reproducible.power(np.full_like(x, 10.0), a + b * x),
    "LOG10": lambda r, x, a, b: reproducible.log10(x),
    "LOGE": lambda r, x, a, b: reproducible.log(x),
    "INV": lambda r, x, a, b: 1.0 / x,
    "MULTX": lambda r, x, a, b: a * x,
    "ADDX": lambda r, x, a, b: a + x,
    "COPY": lambda r, x, a, b: x,
    "MAXLIM": lambda r, x, a, b: np.minimum(a, x),
    "MINLIM": lambda r, x, a, b: np.maximum(a, x),
    "MULTP": lambda r, x, a, b: a * reproducible.power(x, np.full_like(x, b)),
    "ABS": lambda r, x, a, b: np.abs(x),
    "MULTIPLY": lambda r, x, a, b: r * x,
}


def _region_operator(state, src, pos, name, depth):
    """EQUALREG, ADDREG, MULTIREG (array value region set) and COPYREG (from to region set): as
    EQUALS, ADD, MULTIPLY and COPY on the cells of one region of a region set (M: MULTNUM; F:
    FLUXNUM; O: OPERNUM; defaulted: :func:`_default_region_set`; MULTNUM is 1 where the deck
    does not give it, FLUXNUM and OPERNUM must be given)."""
    _need_dims(state, src, pos, name)
    records, pos = read_records(src, pos, name)
    for items, at in records:
        if len(items) < 3 or items[0] is None or (name == "COPYREG" and items[1] is None):
            raise src.error(at, name, "a record needs an array, a value (or target) and a region number")
        target, second = items[0].upper(), items[1]
        arrays = (target, second.upper()) if name == "COPYREG" else (target,)
        _operated_arrays(src, at, name, arrays)
        cells = _region_cells(state, src, at, name, items[2], items[3] if len(items) > 3 else None)
        if name == "COPYREG":
            dest = second.upper()
            _defined(state, src, at, name, target, cells)
            if dest == "PORV":
                _start_porv(state)
            _array(state, dest)[cells] = state.arrays[target][cells]
            continue
        value = 0.0 if second is None else _operand(src, at, name, second, target)  # Flow's default 0
        if target == "PORV":
            _start_porv(state)
            if name != "EQUALREG":
                _porv_operation(state, src, at, "ADD" if name == "ADDREG" else "MULTIPLY", value, cells)
                continue
        if name == "EQUALREG":
            _array(state, target)[cells] = value
        else:
            _defined(state, src, at, name, target, cells)
            arr = state.arrays[target]
            arr[cells] = arr[cells] + value if name == "ADDREG" else arr[cells] * value
        values = _array(state, target)[cells]
        check_cell_values(state, src, at, target, values, cells, ~np.isnan(values), name)
    return pos


def _operate(state, src, pos, name, depth):
    """OPERATE (target box operation source alpha beta) and OPERATER (target region operation
    source alpha beta region-array, OPERNUM by default): the target's cells of the box or region
    set to the operation (:data:`_OPERATIONS`) of the source's values."""
    _need_dims(state, src, pos, name)
    records, pos = read_records(src, pos, name)
    operate = name == "OPERATE"
    for items, at in records:
        n_items = 11 if operate else 7
        items = items + [None] * (n_items - len(items))
        head = (items[0], items[7], items[8]) if operate else (items[0], items[1], items[2], items[3])
        if any(item is None for item in head):
            raise src.error(
                at,
                name,
                "a record needs a target, "
                + ("a box, " if operate else "a region, ")
                + "an operation and a source array",
            )
        target = items[0].upper()
        operation, source = (items[7], items[8]) if operate else (items[2], items[3])
        operation, source = operation.upper(), source.upper()
        if operation not in _OPERATIONS:
            raise src.error(at, name, f"unknown operation {operation!r} (one of {', '.join(_OPERATIONS)})")
        _operated_arrays(src, at, name, (target, source))
        alpha, beta = (
            float_item(src, at, name, item, "parameter") or 0.0  # defaulted: 0
            for item in ((items[9], items[10]) if operate else (items[4], items[5]))
        )
        if operate:
            cells = _box_cells(state, _read_box(state, src, at, name, items[1:7], state.box))
            cells = np.arange(state.num_cells)[cells]
        else:
            region = items[6].upper() if items[6] else "OPERNUM"
            cells = _region_cells(state, src, at, name, items[1], None, region)
        _defined(state, src, at, name, source, cells)
        if operation in ("MULTIPLY", "POLY"):
            _defined(state, src, at, name, target, cells)
        if target == "PORV":
            _start_porv(state)
        with np.errstate(all="ignore"):
            values = _OPERATIONS[operation](
                _array(state, target)[cells], state.arrays[source][cells], alpha, beta
            )
        check_cell_values(state, src, at, target, values, cells, None, name)
        _array(state, target)[cells] = values
    return pos


def _operated_arrays(src: Source, at: int, name: str, arrays) -> None:
    for keyword in arrays:
        if keyword in TRAN_KEYWORDS:
            raise src.error(at, name, f"{keyword} cannot be changed by {name} (OPM Flow refuses it too)")
        if not is_cell_keyword(keyword):
            raise src.error(at, name, f"{keyword!r} is not a keyword with one value per cell")


def _region_cells(state, src, at, name, number_item, set_item, region: str | None = None) -> np.ndarray:
    """The cells of region ``number_item`` of a region set: ``region`` (an array's name), else the
    set ``set_item`` names (M, F or O; defaulted: :func:`_default_region_set`)."""
    number = int_item(src, at, name, number_item, "region number")
    if number is None:
        raise src.error(at, name, "the region number cannot be defaulted")
    if region is None:
        region = _default_region_set(state) if set_item is None else _region_set(src, at, name, set_item)
    values = region_values(state.arrays, region, state.num_cells)
    if values is None:
        raise src.error(at, name, f"{region} is not defined (OPM Flow stops too)")
    return np.flatnonzero(values == number)


def _region_set(src: Source, at: int, name: str, item: str) -> str:
    """The region array a record's region set item names (its first letter: M, F or O)."""
    letter = item.strip().upper()[:1]
    if letter not in _REGION_SETS:
        raise src.error(at, name, f"region set {item!r} is not M, F or O (MULTNUM, FLUXNUM, OPERNUM)")
    return _REGION_SETS[letter]


def region_values(arrays: dict[str, np.ndarray], region: str, num_cells: int) -> np.ndarray | None:
    """The region array ``region`` of the deck's ``arrays``: MULTNUM is 1 where the deck does not
    give it; FLUXNUM and OPERNUM are None then (OPM Flow stops on a region of them)."""
    values = arrays.get(region)
    if values is None and region == "MULTNUM":
        return np.ones(num_cells)
    return values


def _default_region_set(state: ReaderState) -> str:
    """The region set of a record that names none: FLUXNUM, or MULTNUM where GRIDOPTS gives a
    number of MULTNUM regions (OPM Flow's rule; the manuals do not say)."""
    return "MULTNUM" if state.gridopts is not None and state.gridopts.nrmult > 0 else "FLUXNUM"


def _defined(state, src, at, name, keyword, cells) -> None:
    values = state.arrays.get(keyword)
    if values is None and keyword in _DEFAULTS:
        values = _array(state, keyword)
    if values is None or np.isnan(values[cells]).any():
        raise src.error(at, name, f"{keyword} is not defined in every cell it operates on")


def _multregp(state, src, pos, name, depth):
    """MULTREGP (region multiplier set): the pore volumes of a region's cells multiplied (the last
    record of a region counts, a region number of 0 or less is ignored, as Flow does)."""
    records, pos = read_records(src, pos, name)
    for items, at in records:
        number = int_item(src, at, name, items[0] if items else None, "region number")
        multiplier = float_item(src, at, name, items[1] if len(items) > 1 else None, "multiplier")
        if number is None or multiplier is None:
            raise src.error(at, name, "a record needs a region number and a multiplier")
        check_finite(src, at, name, multiplier, "multiplier")
        if number <= 0:
            continue
        region = _region_set(src, at, name, items[2] if len(items) > 2 and items[2] else "M")
        state.multregp[number] = (region, multiplier, f"{src.path.name}:{src.line(at)}")
    return pos


def _operand(src: Source, at: int, name: str, item: Item, target: str) -> float:
    value = float_item(src, at, name, item, target)
    if value is None:
        raise src.error(at, name, f"{target}: the value cannot be defaulted")
    check_finite(src, at, name, value, f"{target}: value")
    return value


def is_cell_keyword(name: str) -> bool:
    """Does ``name`` have one value per cell (what EQUALS, ADD, COPY, ... may act on)?"""
    if name in _CELL_KEYWORDS or name in _DEFAULTS or name in TRAN_KEYWORDS:
        return True
    info = vocabulary().get(name)
    return info is not None and info.shape.kind == "data"


def _tran_operation(state, src, at, name, items, box) -> None:
    """EQUALS/MULTIPLY/ADD/MINVALUE/MAXVALUE on TRANX/TRANY/TRANZ (EDIT only), or COPY."""
    where = f"{src.path.name}:{src.line(at)}"
    if name == "COPY":
        source, dest = items[0].upper(), items[1].upper()
        if source not in TRAN_KEYWORDS:  # as Flow: a copy from TRAN* is skipped, one into it fails
            raise src.error(at, name, f"cannot copy into {dest}: a transmissibility the simulator computes")
        state.notes.append(f"{where}: COPY {source} {dest} ignored (as OPM Flow 2022.10 does)")
        return
    keyword = items[0].upper()
    if state.section != "EDIT":
        if state.section == "GRID":
            raise src.error(at, name, f"{keyword} can only be modified in the EDIT section")
        state.notes.append(f"{where}: {name} {keyword} outside the EDIT section ignored")
        return
    value = float_item(src, at, name, items[1], keyword)
    if value is None or not np.isfinite(value):
        raise src.error(at, name, f"{keyword}: needs one finite value, got {items[1]!r}")
    state.tran_edits.append(TranEdit(keyword, name, _full_box(state, box), value=value, source=where))


def _multregt(state, src, pos, name, depth):
    records, pos = read_records(src, pos, name)
    state.multregt.extend(multregt_record(src, at, name, items) for items, at in records)
    return pos


def _gridopts(state, src, pos, name, depth):
    items, pos, at = read_record(src, pos, name)
    state.gridopts = gridopts_record(src, at, name, items)
    return pos


def _cell_pairs(state, src, pos, name, depth):
    """NNC (I1 J1 K1 I2 J2 K2 TRAN ...) and EDITNNC (... multiplier ...) records."""
    dims = _need_dims(state, src, pos, name)
    records, pos = read_records(src, pos, name)
    rows = state.cell_pairs.setdefault(name, [])
    unused = 0
    for items, at in records:
        g1, g2, value, extra = cell_pair_record(src, at, name, items, dims)
        default = 0.0 if name == "NNC" else 1.0
        rows.append((g1, g2, default if value is None else value, f"{src.path.name}:{src.line(at)}"))
        unused += extra
    if unused:
        state.notes.append(
            f"{src.path.name}:{src.line(records[0][1])}: {name}: items after item 7 are not used "
            f"({unused} records give some)"
        )
    return pos


def _faults(state, src, pos, name, depth):
    _need_dims(state, src, pos, name)
    records, pos = read_records(src, pos, name)
    state.faults.extend(_fault_segment(state, src, at, name, items) for items, at in records)
    return pos


def _fault_segment(state, src, at, name, items) -> FaultSegment:
    """One FAULTS record: name I1 I2 J1 J2 K1 K2 face (a box of the grid, a face X, Y, Z,
    X-, Y- or Z-; I, J, K accepted for X, Y, Z)."""
    if len(items) < 8 or items[0] is None or items[7] is None:
        raise src.error(at, name, "a record needs: name I1 I2 J1 J2 K1 K2 face")
    box = _read_box(state, src, at, name, items[1:7], None)
    face = items[7].upper().replace("I", "X").replace("J", "Y").replace("K", "Z")
    if face not in FAULT_FACES:
        raise src.error(
            at, name, f"face {items[7]!r} of fault {items[0]!r} is not one of X, Y, Z, X-, Y-, Z-"
        )
    assert box is not None
    i1, i2, j1, j2, k1, k2 = box
    return FaultSegment(items[0], i1, i2, j1, j2, k1, k2, face)


def _multflt(state, src, pos, name, depth):
    records, pos = read_records(src, pos, name)
    for items, at in records:
        if len(items) < 2 or items[0] is None:
            raise src.error(at, name, "a record needs: fault name and multiplier")
        value = float_item(src, at, name, items[1], "multiplier")
        check_not_negative(src, at, name, value, f"fault {items[0]!r}: multiplier")
        state.multflt[items[0]] = value
        state.multflt_sources[items[0]] = f"{src.path.name}:{src.line(at)}"
    return pos


def _mapaxes(state, src, pos, name, depth):
    """MAPAXES: six numbers; more are ignored with a note, as OPM Flow reads them."""
    numbers, end = read_numbers(src, pos, name, at_most=64)
    values = numbers.values
    if values.size < 6:
        raise src.error(pos, name, f"has {values.size} values, expected 6")
    if values.size > 6:
        state.notes.append(
            f"{src.path.name}:{src.line(pos)}: MAPAXES: {values.size} values, the first 6 read (as OPM Flow)"
        )
        values = values[:6]
    if not np.isfinite(values).all():
        raise src.error(pos, name, "needs six finite numbers (defaults or nan/inf given)")
    state.mapaxes = values
    return end


def _string_keyword(state, src, pos, name, depth):
    items, pos, _ = read_record(src, pos, name)
    text = " ".join(i for i in items if i)
    if name == "MAPUNITS":
        state.mapunits = text or None
    else:
        state.gridunit = items[0] if items and items[0] else None
    return pos


def _pinch(state, src, pos, name, depth):
    items, pos, at = read_record(src, pos, name)
    threshold = float_item(src, at, name, items[0] if items else None, "threshold")
    max_gap = float_item(src, at, name, items[2] if len(items) > 2 else None, "maximum gap")
    check_finite(src, at, name, threshold, "threshold thickness")
    check_finite(src, at, name, max_gap, "maximum gap")
    if threshold is not None and threshold < 0:
        state.notes.append(
            f"{src.path.name}:{src.line(at)}: PINCH: threshold thickness {threshold:g} is negative: no "
            "layer is thin enough to be pinched out (as OPM Flow reads it)"
        )
    state.pinch = (0.001 if threshold is None else threshold, 1e20 if max_gap is None else max_gap)
    chosen = []
    choices = (("GAP", "NOGAP"), ("TOPBOT", "ALL"), ("TOP", "ALL"))
    for item, allowed, default in zip((1, 3, 4), choices, PINCH_DEFAULTS, strict=True):
        value = items[item].upper() if len(items) > item and items[item] else default
        if value not in allowed:
            raise DeckError(
                f"{src.path}:{src.line(at)}: PINCH: item {item + 1} must be {' or '.join(allowed)}, "
                f"got {value!r}"
            )
        chosen.append(value)
    state.pinch_options = tuple(chosen)
    return pos


def _minpv(state, src, pos, name, depth):
    items, pos, at = read_record(src, pos, name)
    state.minpv = float_item(src, at, name, items[0] if items else None, "minimum pore volume")
    check_finite(src, at, name, state.minpv, "minimum pore volume")
    if state.minpv is not None and state.minpv < 0:
        state.notes.append(
            f"{src.path.name}:{src.line(at)}: {name} {state.minpv:g} is negative: no cell is removed "
            "(as OPM Flow reads it)"
        )
    return pos


def _skip_block(end_keyword: str, what: str):
    def handler(state, src, pos, name, depth):
        data = src.data
        search = pos
        while True:
            hit = data.find(end_keyword.encode(), search)
            if hit < 0:
                raise src.error(pos, name, f"no {end_keyword} closes it")
            line_start = data.rfind(b"\n", 0, hit) + 1
            if data[line_start:hit].strip() == b"":
                break
            search = hit + 1
        state.notes.append(f"{src.path.name}:{src.line(pos)}: {what} ({name} ... {end_keyword}) ignored")
        return hit + len(end_keyword)

    return handler


def _import(state, src, pos, name, depth):
    """IMPORT: the keywords of a binary GRDECL file (:mod:`~gridlib.io.grdecl.binary`; item 2
    says formatted or not, which the reader tells from the file itself)."""
    from .binary import read_binary_file  # the binary reader uses this module's checks

    items, pos, at = read_record(src, pos, name)
    if not items or items[0] is None:
        raise src.error(at, name, "needs a file name")
    read_binary_file(state, _resolve(state, src, at, name, items[0]))
    return pos


def _dual_porosity(state, src, pos, name, depth):
    """DUALPORO, DUALPERM: the deck's layers are two grids (the upper half of NZ the matrix, the
    lower half the fractures, joined cell by cell); refused rather than read as one grid whose
    fractures are layers below the matrix."""
    raise src.error(
        pos,
        name,
        "a dual-porosity deck (matrix and fracture cells, the lower half of the layers the fractures) "
        "is not read: gridlib reads single-porosity grids",
    )


def _numerical_aquifer(state, src, pos, name, depth):
    """AQUNUM, AQUCON: a numerical aquifer, which OPM Flow builds as cells of its own (each
    AQUNUM cell made active, with the pore volume of the aquifer's area x length x porosity,
    chained to the next and joined to the reservoir faces AQUCON names). gridlib's grid leaves
    them as the deck's ACTNUM has them: read past, with a note saying so (not among the keywords
    'not needed for the grid')."""
    where = f"{src.path.name}:{src.line(pos)}"
    if not any("the numerical aquifer is not built" in note for note in state.notes):
        state.notes.append(
            f"{where}: {name}: the numerical aquifer is not built (OPM Flow makes its AQUNUM cells "
            "active and joins them to the reservoir by AQUCON): its cells and connections are not "
            "in this grid"
        )
    return skip_data(state, src, pos, vocabulary().get(name))


def _single_record_note(state, src, pos, name, depth):
    items, pos, at = read_record(src, pos, name)
    state.notes.append(f"{src.path.name}:{src.line(at)}: {name} {' '.join(i or '*' for i in items)} ignored")
    return pos


_HANDLERS = {
    "DIMENS": _dims_keyword,
    "SPECGRID": _dims_keyword,
    "TITLE": _title,
    "COORD": _coord,
    "ZCORN": _zcorn,
    "DXV": _vector,
    "DYV": _vector,
    "DZV": _vector,
    "DEPTHZ": _vector,
    "INCLUDE": _include,
    "PATHS": _paths,
    "GDFILE": _gdfile,
    "BOX": _box,
    "ENDBOX": _endbox,
    "EQUALS": _operator,
    "COPY": _operator,
    "ADD": _operator,
    "MULTIPLY": _operator,
    "MINVALUE": _operator,
    "MAXVALUE": _operator,
    "FAULTS": _faults,
    "MULTFLT": _multflt,
    "MAPAXES": _mapaxes,
    "MAPUNITS": _string_keyword,
    "GRIDUNIT": _string_keyword,
    "PINCH": _pinch,
    "MINPV": _minpv,
    "MINPORV": _minpv,  # MINPV's other name (OPM Flow reads either)
    "SKIP": _skip_block("ENDSKIP", "skipped block"),
    "CARFIN": _skip_block("ENDFIN", "local grid refinement"),
    "RADFIN": _skip_block("ENDFIN", "local grid refinement"),
    "RADFIN4": _skip_block("ENDFIN", "local grid refinement"),
    "GDORIENT": _single_record_note,
    "IMPORT": _import,
    "DUALPORO": _dual_porosity,
    "EQUALREG": _region_operator,
    "ADDREG": _region_operator,
    "MULTIREG": _region_operator,
    "COPYREG": _region_operator,
    "OPERATE": _operate,
    "OPERATER": _operate,
    "MULTREGP": _multregp,
    "AQUNUM": _numerical_aquifer,
    "AQUCON": _numerical_aquifer,
    "DUALPERM": _dual_porosity,
    "COORDSYS": _single_record_note,
    "NNC": _cell_pairs,
    "EDITNNC": _cell_pairs,
    "MULTREGT": _multregt,
    "GRIDOPTS": _gridopts,
    "TRANX": _tran_array,
    "TRANY": _tran_array,
    "TRANZ": _tran_array,
}
