"""ECLIPSE GRDECL / DATA decks: ``read_grdecl`` (text in, :class:`Deck` out) and ``write_grdecl``.

``read_grdecl`` reads what a grid needs from a GRDECL include file or a full
DATA deck (RUNSPEC, GRID and EDIT sections; it stops at PROPS):

* dimensions: DIMENS, SPECGRID; units: METRIC, FIELD, LAB, PVT-M; MAPAXES,
  MAPUNITS, GRIDUNIT;
* geometry: COORD + ZCORN, or the Cartesian keywords DX/DY/DZ (or DXV/DYV/DZV)
  with TOPS (or DEPTHZ), turned into COORD/ZCORN, or GDFILE (an EGRID);
* ACTNUM, PORO, NTG, PERMX/Y/Z and any other numeric cell keyword (one value
  per cell, or per cell of the current BOX);
* FAULTS, MULTFLT, PINCH, MINPV;
* INCLUDE (relative to the including file; PATHS aliases), BOX/ENDBOX, and
  EQUALS, COPY, ADD, MULTIPLY, MINVALUE, MAXVALUE;
* what modifies connections, kept as records to be replayed in the simulator's
  order (:mod:`gridlib.cornerpoint.connection_keywords`): MULTREGT (GRID and EDIT,
  deck order), GRIDOPTS, NNC, EDITNNC, and the EDIT section's TRANX/TRANY/TRANZ (the
  keywords, with BOX, and EQUALS, MULTIPLY, ADD, MINVALUE, MAXVALUE on them, in deck
  order). As OPM Flow 2022.10 reads them: MULTX/MULTX-/MULTY/... arrays in the EDIT
  section multiply the values from GRID; MULTFLT in GRID or EDIT sets a fault's
  multiplier (the last one counts); COPY from TRANX/TRANY/TRANZ is ignored (noted),
  COPY into them and operations on them in the GRID section are errors, TRANX arrays
  outside EDIT are ignored (noted); MULTNUM defaults to 1, FLUXNUM and OPERNUM have
  no default;
* repeat counts (``3*0.2``; ``5*`` leaves five values unchanged), comments,
  ``/`` terminators. Keywords it does not know are skipped and listed in
  ``Deck.notes``.

Numbers are parsed in bulk (see :mod:`gridlib.io.eclipse_text`): a 1e6-cell
deck reads in about a second. Every error names the file, the line and the
keyword (:class:`DeckError`, an :class:`~gridlib.errors.InputError`).

``write_grdecl`` writes a deck that ECLIPSE, OPM Flow and ``read_grdecl`` read;
floats are written with the shortest text that reads back to the same float64
(Python's ``repr``) and runs of bit-identical values as ``n*v``, so a written
and re-read deck has bit-identical arrays. Each distinct value is formatted
once (``repr``, most of the time taken) and the text is assembled in NumPy,
in lines of at most 131 characters (ECLIPSE reads 132).

Lengths are in the deck's units (metres for METRIC, feet for FIELD); z is
depth, positive down, as the deck gives it.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from ..cornerpoint.connection_keywords import TRAN_KEYWORDS, CellPairs, GridOptions, MultregtRecord, TranEdit
from ..cornerpoint.deck import FAULT_FACES, PINCH_DEFAULTS, Deck, FaultSegment
from ._atomic import atomic_path
from .connection_records import cell_pair_record, gridopts_record, multregt_record
from .eclipse_text import (
    DeckError,
    Item,
    Source,
    looks_like_keyword_line,
    read_keyword,
    read_numbers,
    read_record,
    read_records,
    skip_blank,
    skip_unknown,
)

__all__ = ["DeckError", "read_grdecl", "write_grdecl"]

UNITS = ("METRIC", "FIELD", "LAB", "PVT-M")
SECTIONS = ("RUNSPEC", "GRID", "EDIT", "PROPS", "REGIONS", "SOLUTION", "SUMMARY", "SCHEDULE", "OPTIMIZE")
_STOP_SECTIONS = ("PROPS", "REGIONS", "SOLUTION", "SUMMARY", "SCHEDULE", "OPTIMIZE")
_NO_DATA = frozenset(
    """ECHO NOECHO INIT NONNC NEWTRAN OLDTRAN UNIFOUT UNIFIN FMTOUT FMTIN MULTOUT MULTIN NOSIM
    NOINSPEC NORSSPEC IMPES FULLIMP OIL WATER GAS DISGAS VAPOIL BRINE SOLVENT POLYMER TEMP THERMAL
    CO2STORE H2STORE MONITOR NOMONITO NOWARN WARN NOGGF NOCASC DUALPORO DUALPERM SKIP100 SKIP300
    ENDSKIP""".split()
)
# Cell keywords with a default value (used when EQUALS/ADD/... touch them before they are set).
_MULTIPLIER_KEYWORDS = frozenset(f"MULT{d}{s}" for d in "XYZ" for s in ("", "-"))
_DEFAULTS = {"ACTNUM": 1.0, "NTG": 1.0, "MULTPV": 1.0, "MULTNUM": 1.0}
_DEFAULTS |= dict.fromkeys(_MULTIPLIER_KEYWORDS, 1.0)
# Cell keywords we know; others with one value per cell are kept too.
_CELL_KEYWORDS = frozenset(
    """ACTNUM PORO NTG PERMX PERMY PERMZ PERMXY PERMYZ PERMZX MULTX MULTY MULTZ MULTX- MULTY- MULTZ-
    MULTPV PORV DX DY DZ TOPS SATNUM FIPNUM EQLNUM PVTNUM IMBNUM ROCKNUM MINPVV SWATINIT
    DEPTH SWL SWCR SWU SGL SGCR SGU SOWCR SOGCR KRW KRO KRG PCW PCG MULTNUM FLUXNUM OPERNUM
    DIFFX DIFFY DIFFZ THCONR HEATCR PRESSURE SWAT SGAS RS RV""".split()
)
_GEOMETRY_KEYWORDS = ("DX", "DY", "DZ", "TOPS")
_MAX_INCLUDE_DEPTH = 32


@dataclass
class _State:
    """Everything read so far, across INCLUDEd files."""

    main: Path
    dims: tuple[int, int, int] | None = None
    arrays: dict[str, np.ndarray] = field(default_factory=dict)
    coord: np.ndarray | None = None
    zcorn: np.ndarray | None = None
    vectors: dict[str, np.ndarray] = field(default_factory=dict)  # DXV, DYV, DZV, DEPTHZ
    box: tuple[int, int, int, int, int, int] | None = None  # 0-based inclusive
    faults: list[FaultSegment] = field(default_factory=list)
    multflt: dict[str, float] = field(default_factory=dict)
    mapaxes: np.ndarray | None = None
    mapunits: str | None = None
    gridunit: str | None = None
    units: str | None = None
    pinch: tuple[float, ...] | None = None
    pinch_options: tuple[str, ...] = PINCH_DEFAULTS
    minpv: float | None = None
    multregt: list[MultregtRecord] = field(default_factory=list)
    gridopts: GridOptions | None = None
    tran_edits: list[TranEdit] = field(default_factory=list)
    cell_pairs: dict[str, list[tuple[int, int, float, str]]] = field(default_factory=dict)  # NNC, EDITNNC
    multflt_sources: dict[str, str] = field(default_factory=dict)  # fault -> where its MULTFLT was set
    gdfile: Deck | None = None
    paths: dict[str, str] = field(default_factory=dict)
    section: str | None = None
    stopped: bool = False
    notes: list[str] = field(default_factory=list)
    skipped: dict[str, str] = field(default_factory=dict)  # keyword -> where first seen

    @property
    def num_cells(self) -> int:
        assert self.dims is not None
        return self.dims[0] * self.dims[1] * self.dims[2]


def read_grdecl(path: str | os.PathLike) -> Deck:
    """Read the grid of an ECLIPSE deck (GRDECL or DATA file).

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
    state = _State(main)
    _read_file(state, Source.open(main), 0)
    return _deck(state)


def _read_file(state: _State, src: Source, depth: int) -> None:
    pos = 0
    while not state.stopped:
        found = read_keyword(src, pos)
        if found is None:
            return
        name, pos = found
        at = pos
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
        if name in _NO_DATA:
            continue
        handler = _HANDLERS.get(name)
        if handler is not None:
            pos = handler(state, src, pos, name, depth)
        elif name in _CELL_KEYWORDS:
            pos = _cell_array(state, src, pos, name)
        else:
            pos = _unknown(state, src, pos, name)


# --- handlers ---------------------------------------------------------------------------------


def _need_dims(state: _State, src: Source, pos: int, name: str) -> tuple[int, int, int]:
    if state.dims is None:
        raise src.error(
            pos, name, "the grid dimensions are not known yet (DIMENS or SPECGRID must come first)"
        )
    return state.dims


def _ints(src: Source, at: int, name: str, items: list[Item], n: int, what: str) -> list[int | None]:
    out: list[int | None] = []
    for v in items[:n]:
        if v is None:
            out.append(None)
            continue
        try:
            out.append(int(v))
        except ValueError:
            raise src.error(at, name, f"{what}: {v!r} is not an integer") from None
    return out + [None] * (n - len(out))


def _float_item(src: Source, at: int, name: str, value: Item, what: str) -> float | None:
    if value is None:
        return None
    try:
        return float(value.replace("D", "E").replace("d", "e"))
    except ValueError:
        raise src.error(at, name, f"{what}: {value!r} is not a number") from None


def _dims_keyword(state, src, pos, name, depth):
    items, pos, at = read_record(src, pos, name)
    nx, ny, nz = _ints(src, at, name, items, 3, "dimensions")
    if None in (nx, ny, nz) or min(nx, ny, nz) < 1:
        raise src.error(at, name, f"needs three positive integers (NX NY NZ), got {items[:3]}")
    if name == "SPECGRID" and len(items) >= 5 and items[4] is not None and items[4].upper().startswith("T"):
        raise src.error(at, name, "radial (cylindrical) grids are not supported")
    dims = (nx, ny, nz)
    if state.dims is not None and state.dims != dims:
        raise src.error(at, name, f"dimensions {dims} differ from {state.dims} given earlier")
    state.dims = dims  # type: ignore[assignment]
    return pos


def _title(state, src, pos, name, depth):
    """TITLE: the next line is free text (no '/')."""
    data = src.data
    line_end = data.find(b"\n", pos)
    if line_end < 0:
        return len(data)
    if data[pos:line_end].strip():  # the title is on the keyword's own line
        return line_end + 1
    title_end = data.find(b"\n", line_end + 1)
    return len(data) if title_end < 0 else title_end + 1


def _coord(state, src, pos, name, depth):
    nx, ny, _ = _need_dims(state, src, pos, name)
    numbers, pos = read_numbers(src, pos, name, expected=6 * (nx + 1) * (ny + 1))
    _no_defaults(src, pos, name, numbers)
    state.coord = numbers.values
    return pos


def _zcorn(state, src, pos, name, depth):
    _need_dims(state, src, pos, name)
    numbers, pos = read_numbers(src, pos, name, expected=8 * state.num_cells)
    _no_defaults(src, pos, name, numbers)
    state.zcorn = numbers.values
    return pos


def _no_defaults(src, pos, name, numbers):
    if numbers.defaulted is not None:
        raise src.error(pos, name, "values cannot be defaulted (n*) here")


def _vector(state, src, pos, name, depth):
    nx, ny, nz = _need_dims(state, src, pos, name)
    n = {"DXV": nx, "DYV": ny, "DZV": nz, "DEPTHZ": (nx + 1) * (ny + 1)}[name]
    numbers, pos = read_numbers(src, pos, name, expected=n)
    _no_defaults(src, pos, name, numbers)
    state.vectors[name] = numbers.values
    return pos


def _box_cells(state: _State, box: tuple[int, ...] | None) -> np.ndarray | slice:
    """Linear cell indices (i fastest) of a 0-based inclusive box, or all cells."""
    if box is None:
        return slice(None)
    nx, ny, _ = state.dims  # type: ignore[misc]
    i1, i2, j1, j2, k1, k2 = box
    k, j, i = np.meshgrid(np.arange(k1, k2 + 1), np.arange(j1, j2 + 1), np.arange(i1, i2 + 1), indexing="ij")
    return (i + nx * (j + ny * k)).ravel()


def _box_size(state: _State, box: tuple[int, ...] | None) -> int:
    if box is None:
        return state.num_cells
    i1, i2, j1, j2, k1, k2 = box
    return (i2 - i1 + 1) * (j2 - j1 + 1) * (k2 - k1 + 1)


def _array(state: _State, name: str) -> np.ndarray:
    if name not in state.arrays:
        state.arrays[name] = np.full(state.num_cells, _DEFAULTS.get(name, np.nan))
    return state.arrays[name]


def _cell_array(state, src, pos, name, depth=0):
    nx, ny, _ = _need_dims(state, src, pos, name)
    box = state.box
    expected = _box_size(state, box)
    if name == "TOPS" and box is None:
        numbers, end = read_numbers(src, pos, name, at_most=state.num_cells)
        if numbers.values.size not in (nx * ny, state.num_cells):
            raise src.error(
                skip_blank(src.data, pos),
                name,
                f"has {numbers.values.size} values, expected {nx * ny} (top layer) or {state.num_cells}",
            )
        expected = numbers.values.size
    else:
        numbers, end = read_numbers(src, pos, name, expected=expected)
    multiply = state.section == "EDIT" and name in _MULTIPLIER_KEYWORDS  # as OPM Flow: cumulative
    _store(state, name, numbers, box, expected, multiply)
    return end


def _store(state, name, numbers, box, expected, multiply=False):
    target = _array(state, name)
    cells = _box_cells(state, box) if expected == _box_size(state, box) else np.arange(expected)
    values = numbers.values
    if multiply:
        values = target[cells] * values
    if numbers.defaulted is not None:  # n* leaves the values as they were
        values = np.where(numbers.defaulted, target[cells], values)
    target[cells] = values


def _full_box(state: _State, box: tuple[int, ...] | None) -> tuple[int, int, int, int, int, int]:
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


def _unknown(state, src, pos, name):
    """A keyword we do not know: keep it if it is one number per cell, else skip it."""
    where = f"{src.path.name}:{src.line(pos)}"
    if looks_like_keyword_line(src.data, pos):
        state.skipped.setdefault(name, where)
        return pos
    if state.section not in ("RUNSPEC",) and state.dims is not None:
        start = pos
        try:
            numbers, end = read_numbers(src, pos, name, at_most=state.num_cells)
        except DeckError:
            numbers = None
        if numbers is not None and numbers.values.size == _box_size(state, state.box):
            _store(state, name, numbers, state.box, numbers.values.size)
            state.notes.append(f"{where}: {name} read as a cell keyword (one value per cell)")
            return end
        pos = start
    state.skipped.setdefault(name, where)
    return skip_unknown(src, pos, name)


def _include(state, src, pos, name, depth):
    items, pos, at = read_record(src, pos, name)
    if not items or items[0] is None:
        raise src.error(at, name, "needs a file name")
    path = _resolve(state, src, at, name, items[0])
    if depth + 1 > _MAX_INCLUDE_DEPTH:
        raise src.error(at, name, f"includes nested more than {_MAX_INCLUDE_DEPTH} deep (a cycle?)")
    _read_file(state, Source.open(path), depth + 1)
    return pos


def _resolve(state: _State, src: Source, at: int, name: str, text: str) -> Path:
    for alias, value in state.paths.items():
        text = text.replace(f"${alias}", value)
    path = Path(text)
    if not path.is_absolute():
        path = src.path.parent / path
    if not path.is_file():
        raise src.error(at, name, f"file {text!r} not found (looked for {path})")
    return path


def _paths(state, src, pos, name, depth):
    records, pos = read_records(src, pos, name)
    for items, _ in records:
        if len(items) >= 2 and items[0] and items[1]:
            state.paths[items[0]] = items[1]
    return pos


def _gdfile(state, src, pos, name, depth):
    from .egrid import read_egrid

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
        box = _read_box(state, src, at, name, items[2:8], state.box)
        if target in TRAN_KEYWORDS or (name == "COPY" and items[1].upper() in TRAN_KEYWORDS):
            _tran_operation(state, src, at, name, items, box)
            continue
        cells = _box_cells(state, box)
        if name == "COPY":
            dest = items[1].upper()
            if target not in state.arrays and target not in _DEFAULTS:
                raise src.error(at, name, f"cannot copy {target}: it is not defined")
            _array(state, dest)[cells] = _array(state, target)[cells]
            continue
        value = _float_item(src, at, name, items[1], target)
        if name == "EQUALS":
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
    return pos


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
    value = _float_item(src, at, name, items[1], keyword)
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
    for items, at in records:
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
        state.faults.append(FaultSegment(items[0], i1, i2, j1, j2, k1, k2, face))
    return pos


def _multflt(state, src, pos, name, depth):
    records, pos = read_records(src, pos, name)
    for items, at in records:
        if len(items) < 2 or items[0] is None:
            raise src.error(at, name, "a record needs: fault name and multiplier")
        state.multflt[items[0]] = _float_item(src, at, name, items[1], "multiplier")
        state.multflt_sources[items[0]] = f"{src.path.name}:{src.line(at)}"
    return pos


def _mapaxes(state, src, pos, name, depth):
    numbers, pos = read_numbers(src, pos, name, expected=6)
    state.mapaxes = numbers.values
    return pos


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
    threshold = _float_item(src, at, name, items[0] if items else None, "threshold")
    max_gap = _float_item(src, at, name, items[2] if len(items) > 2 else None, "maximum gap")
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
    state.minpv = _float_item(src, at, name, items[0] if items else None, "minimum pore volume")
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
    "SKIP": _skip_block("ENDSKIP", "skipped block"),
    "CARFIN": _skip_block("ENDFIN", "local grid refinement"),
    "RADFIN": _skip_block("ENDFIN", "local grid refinement"),
    "RADFIN4": _skip_block("ENDFIN", "local grid refinement"),
    "GDORIENT": _single_record_note,
    "COORDSYS": _single_record_note,
    "NNC": _cell_pairs,
    "EDITNNC": _cell_pairs,
    "MULTREGT": _multregt,
    "GRIDOPTS": _gridopts,
    "TRANX": _tran_array,
    "TRANY": _tran_array,
    "TRANZ": _tran_array,
}


# --- assembling the deck --------------------------------------------------------------------


def _deck(state: _State) -> Deck:
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
    for name in _GEOMETRY_KEYWORDS:
        arrays.pop(name, None)
    actnum = arrays.pop("ACTNUM", None)
    if actnum is not None:
        undefined = np.isnan(actnum)
        if undefined.any():
            actnum = np.where(undefined, 1.0, actnum)
        if np.any((actnum < 0) | (actnum != np.floor(actnum))):
            raise DeckError(f"{where}: ACTNUM values must be non-negative integers")
    for name, values in arrays.items():
        n_undefined = int(np.isnan(values).sum())
        if n_undefined:
            notes.append(f"{name} is undefined in {n_undefined} of {values.size} cells (NaN)")
    if state.skipped:
        shown = ", ".join(f"{k} ({v})" for k, v in state.skipped.items())
        notes.append(f"skipped keywords not needed for the grid: {shown}")
    fault_names = {seg.name for seg in state.faults}
    for name, at in state.multflt_sources.items():
        if name not in fault_names:
            notes.append(f"{at}: MULTFLT of fault {name!r} ignored: FAULTS does not define it (Flow stops)")
    pairs = {}
    for keyword, rows in state.cell_pairs.items():
        g1, g2, values, sources = zip(*rows, strict=True) if rows else ((), (), (), ())
        pairs[keyword] = CellPairs(np.column_stack([g1, g2]).reshape(-1, 2), values, sources)
    return Deck(
        (nx, ny, nz),
        coord,
        zcorn,
        None if actnum is None else actnum.astype(np.int32),
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


def _cartesian_geometry(state: _State, arrays: dict, where: str) -> tuple[np.ndarray, np.ndarray]:
    """COORD/ZCORN of a block-centred grid from DX/DY/DZ (or DXV/DYV/DZV) and TOPS (or DEPTHZ).

    Cells are boxes: each cell's four top corners lie at its TOPS, its bottom
    at TOPS + DZ; TOPS below the first layer default to the bottom of the cell
    above. Pillar positions are the running sums of DX along i (DY along j),
    from the top layer for the pillar's top point and from the bottom layer for
    its bottom point (as OPM), so the pillars are vertical when DX and DY do not
    vary with depth.
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
    dx, dy, dz = sizes["DX"], sizes["DY"], sizes["DZ"]
    top = np.full((nz, ny, nx, 2, 2), np.nan)  # per cell: the depths of its 4 top corners
    if "TOPS" in arrays:
        tops = arrays["TOPS"].reshape(shape)
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
    for k in range(1, nz):  # a loop over layers, vectorised over each layer
        top[k] = np.where(np.isnan(top[k]), top[k - 1] + dz[k - 1][..., None, None], top[k])
    bottom = top + dz[..., None, None]
    z = np.stack([top, bottom], axis=1)  # (nz, 2, ny, nx, 2b, 2a)
    zcorn = z.transpose(0, 1, 2, 4, 3, 5).reshape(2 * nz, 2 * ny, 2 * nx).ravel()

    def pillar_positions(d: np.ndarray, along: int) -> np.ndarray:
        """Running sums of cell sizes along i (along=1) or j (along=0) of one layer, per pillar."""
        run = np.cumsum(d, axis=along)
        run = np.concatenate([np.zeros_like(np.take(run, [0], axis=along)), run], axis=along)
        other = 1 - along
        return np.concatenate([run, np.take(run, [-1], axis=other)], axis=other)

    x_top, x_bot = pillar_positions(dx[0], 1), pillar_positions(dx[-1], 1)
    y_top, y_bot = pillar_positions(dy[0], 0), pillar_positions(dy[-1], 0)
    z_top, z_bot = float(zcorn.min()), float(zcorn.max())
    if z_bot == z_top:
        z_bot = z_top + 1.0
    coord = np.stack(
        [x_top, y_top, np.full_like(x_top, z_top), x_bot, y_bot, np.full_like(x_top, z_bot)], axis=-1
    )
    return coord.ravel(), zcorn


# --- writing --------------------------------------------------------------------------------

_VALUES_PER_LINE = 6
_MAX_LINE = 131  # ECLIPSE reads 132 characters a line; stay below
_CHUNK_RUNS = 1 << 16  # runs formatted per block: a few MiB of scratch, whatever the array size
_DIRECT_COUNTS = 1 << 16  # runs up to this long index the prefix table by their length
_SPACE, _NEWLINE = ord(" "), ord("\n")


def _text_table(values: list, integer: bool) -> np.ndarray:
    """Fixed-width ASCII table (one row per value, NUL-padded) of ``repr`` (or ``%d``) of each value.

    ``repr`` of a float is the shortest text that reads back to the same
    float64. One ``%`` formatting of all values, then a vectorised split,
    costs less than a Python string per value.
    """
    if not values:
        return np.zeros((0, 1), np.uint8)
    text = np.frombuffer(
        (("%d\n" if integer else "%r\n") * len(values) % tuple(values)).encode("ascii"), np.uint8
    )
    ends = np.flatnonzero(text == _NEWLINE)
    lengths = np.diff(ends, prepend=-1) - 1
    table = np.zeros((len(values), int(lengths.max())), np.uint8)
    table[np.arange(table.shape[1]) < lengths[:, None]] = text[text != _NEWLINE]
    return table


def _format_values(values: np.ndarray, integer: bool = False) -> Iterator[bytes]:
    """Round-trip exact ASCII text of an array, in blocks: runs of equal values as ``n*v``.

    Runs are of bit-identical values (so ``-0.0`` next to ``0.0`` stays
    itself; with ``integer`` they are equal values), and a NaN is never
    repeated. Each distinct value and each distinct repeat count is formatted
    once; the tokens are gathered from those tables as fixed-width byte rows,
    with a space or line break after each, and the NUL padding dropped. At
    most ``_VALUES_PER_LINE`` tokens go on a line, fewer when the longest
    token would make a line longer than ``_MAX_LINE``. The text ends with a
    line break.
    """
    v = np.ascontiguousarray(values).ravel()
    if v.size == 0:
        yield b"\n"
        return
    floating = v.dtype.kind == "f"
    if floating:
        v = v.astype(np.float64, copy=False)
        key = (v + 0.0 if integer else v).view(np.uint64)  # integer: -0.0 is 0
    else:
        key = v.astype(np.int64, copy=False)
    same = key[1:] == key[:-1]
    if floating and not integer:
        same &= ~np.isnan(v[1:])  # the reader does not take "n*nan"
    starts = np.flatnonzero(np.concatenate([[True], ~same]))
    counts = np.diff(starts, append=v.size)
    codes, distinct = pd.factorize(key[starts], sort=False)
    distinct = np.asarray(distinct)
    value_table = _text_table((distinct.view(np.float64) if floating else distinct).tolist(), integer)
    if counts.max() <= _DIRECT_COUNTS:  # the usual case: a prefix for every count up to the longest run
        count_codes, distinct_counts = counts, range(int(counts.max()) + 1)
    else:
        count_codes, distinct_counts = pd.factorize(counts, sort=False)
    prefixes = [f"{n}*" if n > 1 else "" for n in list(distinct_counts)]
    width = max(1, *map(len, prefixes))
    prefix_table = np.array(prefixes, dtype=f"S{width}").view(np.uint8).reshape(len(prefixes), width)
    widest = int(((prefix_table != 0).sum(1)[count_codes] + (value_table != 0).sum(1)[codes]).max())
    per_line = max(1, min(_VALUES_PER_LINE, (_MAX_LINE + 1) // (widest + 1)))
    wp, wv = prefix_table.shape[1], value_table.shape[1]
    chunk = _CHUNK_RUNS - _CHUNK_RUNS % per_line  # whole lines per block
    block = np.empty((chunk, wp + wv + 1), np.uint8)
    for lo in range(0, starts.size, chunk):
        hi = min(lo + chunk, starts.size)
        rows = block[: hi - lo]
        # The codes are in range; mode="clip" lets take write into the strided columns unbuffered.
        np.take(prefix_table, count_codes[lo:hi], axis=0, out=rows[:, :wp], mode="clip")
        np.take(value_table, codes[lo:hi], axis=0, out=rows[:, wp:-1], mode="clip")
        rows[:, -1] = _SPACE
        rows[per_line - 1 :: per_line, -1] = _NEWLINE
        if hi == starts.size:
            rows[-1, -1] = _NEWLINE
        yield rows[rows != 0].tobytes()


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


def _ijk_text(g: int, nx: int, ny: int) -> str:
    """1-based "I J K" of linear cell index ``g``."""
    return f"{g % nx + 1} {g // nx % ny + 1} {g // (nx * ny) + 1}"


def write_grdecl(path: str | os.PathLike, deck: Deck, cell_data: dict | None = None) -> Path:
    """Write ``deck`` (and extra per-cell ``cell_data``) as a GRDECL file, atomically.

    The file holds SPECGRID, MAPUNITS/MAPAXES/GRIDUNIT when known, COORD,
    ZCORN, ACTNUM, every cell keyword, FAULTS, MULTFLT, PINCH, MINPV, MULTREGT
    and NNC; it can be INCLUDEd in the GRID section of a DATA deck. Values are
    exact: ``read_grdecl`` gives back bit-identical arrays. GRIDOPTS (RUNSPEC),
    EDITNNC and the TRANX/TRANY/TRANZ operations (EDIT) belong to other sections
    and are not written.
    """
    nx, ny, nz = deck.cart_dims
    data = dict(deck.cell_data)
    for name, values in (cell_data or {}).items():
        arr = np.asarray(values, dtype=np.float64).ravel()
        if arr.size != deck.num_cells:
            raise DeckError(f"write_grdecl: {name} has {arr.size} values, expected {deck.num_cells}")
        data[name.upper()] = arr
    parts = [f"-- written by gridlib from {deck.source}", "", "SPECGRID", f" {nx} {ny} {nz} 1 F /", ""]
    if deck.mapunits:
        parts += ["MAPUNITS", f" '{deck.mapunits}' /", ""]
    if deck.mapaxes is not None:
        axes = [repr(float(v)) for v in deck.mapaxes]
        line = " " + " ".join(axes) + " /"
        if len(line) > _MAX_LINE:  # three points, one a line
            line = "\n".join(" " + " ".join(axes[i : i + 2]) for i in range(0, len(axes), 2)) + " /"
        parts += ["MAPAXES", line, ""]
    if deck.gridunit:
        parts += ["GRIDUNIT", f" '{deck.gridunit}' /", ""]
    arrays: list[tuple[str, np.ndarray, bool]] = [("COORD", deck.coord, False)]
    arrays.append(("ZCORN", _finite_zcorn(deck), False))
    if deck.actnum is not None:
        arrays.append(("ACTNUM", deck.actnum, True))
    for name, values in data.items():
        if np.isnan(values).any():
            raise DeckError(f"write_grdecl: {name} has undefined (NaN) values; ECLIPSE cannot read them")
        integer = bool(np.all(values == np.round(values))) and name.endswith("NUM")
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
        tail += [f" '{name}' {value!r} /" for name, value in deck.multflt.items()]
        tail += ["/", ""]
    if deck.pinch is not None:
        gap, pinchout, multz = deck.pinch_options
        tail += ["PINCH", f" {deck.pinch[0]!r} {gap} {deck.pinch[1]!r} {pinchout} {multz} /", ""]
    if deck.minpv is not None:
        tail += ["MINPV", f" {deck.minpv!r} /", ""]
    if deck.multregt:
        tail.append("MULTREGT")
        for r in deck.multregt:
            items = (r.region1, r.region2, repr(r.multiplier), r.directions, r.nnc_option, r.region_set)
            tail.append(" " + " ".join("1*" if v is None else str(v) for v in items) + " /")
        tail += ["/", ""]
    if deck.nnc_keyword is not None and deck.nnc_keyword.num:
        tail.append("NNC")
        records = zip(deck.nnc_keyword.cells.tolist(), deck.nnc_keyword.values.tolist(), strict=True)
        tail += [f" {_ijk_text(g1, nx, ny)} {_ijk_text(g2, nx, ny)} {t!r} /" for (g1, g2), t in records]
        tail += ["/", ""]
    target = Path(path)
    with atomic_path(target) as tmp, open(tmp, "wb") as f:
        f.write(("\n".join(parts) + "\n").encode("ascii"))
        for name, values, integer in arrays:
            f.write(f"{name}\n".encode("ascii"))
            for block in _format_values(values, integer):
                f.write(block)
            f.write(b"/\n\n")
        f.write(("\n".join(tail) + "\n").encode("ascii") if tail else b"")
    return target
