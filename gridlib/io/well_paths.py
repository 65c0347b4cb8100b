"""Well trajectory files: a well's path as points x, y, z (z depth, positive down) with or
without measured depths, read into a :class:`~gridlib.wells.path.WellPath`.

Two formats:

* ``table``: plain text or CSV, one point a line, fields split at semicolons on lines that
  have one (a comma there is a decimal mark, as spreadsheets write it in many locales), else at
  commas on lines that have one, else at whitespace; ``#`` starts a comment; empty lines are skipped.
  A first line without any number is a header of column names. With a header, the columns are
  found by their names (case-insensitive): x ``X``, ``EASTING``, ``X_UTME``; y ``Y``,
  ``NORTHING``, ``Y_UTMN``; z ``Z``, ``TVD``, ``TVDSS``, ``Z_TVDSS``, ``DEPTH``; MD ``MD``,
  ``MDEPTH``, ``M_DEPTH`` (optional); other columns are ignored. Without a header the columns
  are ``x y z`` or ``x y z md``.
* ``rms``: the RMS well format (as xtgeo reads and writes it): line 1 a version (``1.0``),
  line 2 a free text (the well type), line 3 ``name x y [rkb]`` (the well head; the name may
  hold spaces), line 4 the number of logs, then one line per log (``name type ...``: ``DISC``
  with code/name pairs, or ``CONT``/``UNK`` with a scale such as ``lin``; a name alone is a log
  without a type, as xtgeo reads it), then one row per point, ``x y z`` and a value per log;
  -999 is an undefined value. The MD is the log named ``MD``, ``MDEPTH`` or ``M_DEPTH`` if there
  is one (an undefined MD counts on from the point before; above the first defined one, back
  from it; :func:`~gridlib.wells.path.fill_md`); the well's name is line 3's. A file of several
  wells (xtgeo's stacked files) is an error naming the line where the second starts.

``columns`` maps any of ``x``, ``y``, ``z``, ``md`` to a column's name or 0-based position
(for an ``rms`` file the names are ``X_UTME``, ``Y_UTMN``, ``Z_TVDSS`` and the logs'). Without
an MD column, MD is the length along the straight segments from the first point (MD 0 there).
A file's numbers are rounded to the decimals printed, so an MD step along a straight stretch
can come out a little shorter than the straight line between its points: a step short by no
more than the rounding of its four numbers allows (half a unit of each one's last decimal; at
most 1 % of the straight line) is lengthened to the straight line (each MD becomes the larger of
its own and the one before plus the straight distance, so the MDs after a lengthened step stay
the file's as soon as the file's MD is ahead again), a step shorter than that is an error. A
path that turns back on itself at a point (by more than 170 degrees: lines out of order, or two
wells in one file) is an error too.
Every problem is one :class:`~gridlib.errors.InputError` naming the file and the line, e.g.
``data/p2.w: line 17: MD 1205 is not greater than line 16's MD 1210``.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from functools import partial
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..grid import FloatArray
from ..reproducible import arctan2
from ..wells.path import WellPath, check_path, fill_md
from .text_table import TextTable, data_rows, first_non_number, is_number, read_lines, split_fields

__all__ = ["COLUMN_NAMES", "RMS_UNDEFINED", "WELL_PATH_FORMATS", "read_well_path"]

WELL_PATH_FORMATS = ("auto", "table", "rms")
COLUMN_NAMES = {
    "x": ("x", "easting", "x_utme"),
    "y": ("y", "northing", "y_utmn"),
    "z": ("z", "tvd", "tvdss", "z_tvdss", "depth"),
    "md": ("md", "mdepth", "m_depth"),
}
RMS_UNDEFINED = -999.0
RMS_SUFFIXES = (".w", ".rmswell")
_RMS_COORDINATES = ["X_UTME", "Y_UTMN", "Z_TVDSS"]


def read_well_path(
    path: str | os.PathLike,
    *,
    format: str = "auto",
    name: str | None = None,
    columns: Mapping[str, str | int] | None = None,
) -> WellPath:
    """The well path in ``path`` (see the module docstring for the formats).

    ``format``: ``auto`` (``rms`` for the suffixes ``.w`` and ``.rmswell`` or a file that starts
    like one: a version alone on line 1 and the number of logs alone on line 4; else ``table``),
    ``table`` or ``rms``. ``name``: the path's name (default: an RMS file's well name, else the
    file's stem). ``columns``: which columns are x, y, z and md (names or 0-based positions).
    """
    p = Path(path)
    if format not in WELL_PATH_FORMATS:
        raise InputError(
            f"{p}: unknown well path format {format!r}; expected one of {', '.join(WELL_PATH_FORMATS)}"
        )
    lines = read_lines(p)
    if format == "auto":
        format = "rms" if p.suffix.lower() in RMS_SUFFIXES or _looks_rms(lines) else "table"
    if format == "rms":
        well, table = _rms_table(p, lines)
        undefined: float | None = RMS_UNDEFINED
    else:
        well, table, undefined = "", _text_table(p, lines), None
    width = len(table.header) if table.header is not None else len(table.rows[0])
    cols = _columns(p, table, width, columns)
    used = [cols[role] for role in COLUMN_NAMES if role in cols]
    values, text = _numbers(p, table, width, used)
    bad = np.flatnonzero(~np.isfinite(values).all(axis=1))
    if bad.size:
        used = ", ".join(role for role in COLUMN_NAMES if role in cols)
        raise InputError(
            f"{p}: line {table.lines[bad[0]]}: {used} must be finite, got {values[bad[0]].tolist()}"
        )
    xyz = values[:, :3]
    md = values[:, 3].copy() if "md" in cols else None
    if undefined is not None:
        bad = np.flatnonzero((xyz == undefined).any(axis=1))
        if bad.size:
            raise InputError(f"{p}: line {table.lines[bad[0]]}: x, y or z is undefined ({undefined:g})")
        if md is not None:
            md[md == undefined] = np.nan  # counted on from the point before
    if xyz.shape[0] < 2:
        raise InputError(f"{p}: {xyz.shape[0]} point (line {table.lines[0]}); a well path needs at least 2")
    slack = None
    if md is not None:
        half = _half_units(text)  # each value's rounding
        half[np.isnan(md), 3] = 0.0  # an undefined MD is counted on exactly
        per_row = half[:, 3] + np.linalg.norm(half[:, :3], axis=1)
        chord = np.linalg.norm(np.diff(xyz, axis=0), axis=1)
        slack = np.minimum(per_row[:-1] + per_row[1:], SLACK_LIMIT * chord)
    md = fill_md(xyz, md)
    xyz, md = check_path(xyz, md, str(p), names=lambda i: f"line {table.lines[i]}", slack=slack)
    _check_turns(p, xyz, table.lines)
    chord = np.linalg.norm(np.diff(xyz, axis=0), axis=1)
    if slack is not None and (np.diff(md) < chord).any():
        # steps short of the straight line by the file's rounding are lengthened to it
        run = np.concatenate(([0.0], np.cumsum(chord)))
        md = np.maximum(md, run + np.maximum.accumulate(md - run))
    return WellPath(xyz, md, name if name is not None else (well or p.stem))


TURN_BACK = 170.0  # degrees: a path turning by more at one of its points goes back along itself


def _check_turns(p: Path, xyz: FloatArray, lines: list[int]) -> None:
    """No point where the path turns back on itself (by more than :data:`TURN_BACK` degrees):
    a hole cannot, and the cells along both legs would be completed twice (lines out of order,
    or two wells in one file)."""
    u, v = np.diff(xyz[:-1], axis=0), np.diff(xyz[1:], axis=0)
    cross = np.linalg.norm(np.cross(u, v), axis=1)
    angle = np.rad2deg(arctan2(cross, np.einsum("ij,ij->i", u, v)))
    bad = np.flatnonzero(angle > TURN_BACK)
    if bad.size:
        i = int(bad[0])
        raise InputError(
            f"{p}: line {lines[i + 1]}: the path turns back on itself (by {angle[i]:.5g} degrees from line "
            f"{lines[i]} through line {lines[i + 1]} to line {lines[i + 2]}): a hole cannot; are its lines "
            "in order, and of one well?"
        )


SLACK_LIMIT = 0.01  # rounding lengthens an MD step by at most this fraction of its straight line
HALF_UNIT = np.array([0.5 / 10**k for k in range(20)])  # half a unit of the k-th decimal


def _half_units(fields: np.ndarray) -> FloatArray:
    """Half a unit of the last decimal printed of each text number (``"12.05"``: 0.005): the
    largest rounding error of the value; 0 for numbers with an exponent (``1.2e3``)."""
    dot = np.char.find(fields, ".")
    decimals = np.where(dot >= 0, np.char.str_len(fields) - dot - 1, 0)
    half = HALF_UNIT[np.clip(decimals, 0, HALF_UNIT.size - 1)]
    half[np.char.find(np.char.lower(fields), "e") >= 0] = 0.0
    return half


def _looks_rms(lines: list[str]) -> bool:
    """Whether the file starts as an RMS well file: a number alone on line 1 and an integer
    alone on line 4."""
    if len(lines) < 4:
        return False
    first, fourth = lines[0].split(), lines[3].split()
    return len(first) == 1 and is_number(first[0]) and len(fourth) == 1 and fourth[0].isdigit()


def _text_table(p: Path, lines: list[str]) -> TextTable:
    """The rows of a table file (comments and empty lines skipped, an optional header)."""
    table = data_rows(lines, split=partial(split_fields, quotes=True))
    if not table.rows:
        raise InputError(f"{p}: no data lines (expected x y z [md] per line)")
    return table


def _rms_table(p: Path, lines: list[str]) -> tuple[str, TextTable]:
    """The well name and the rows of an RMS well file; the header names are the coordinates'
    and the logs'."""
    if len(lines) < 4:
        raise InputError(f"{p}: an RMS well file starts with 4 header lines (version, type, name x y, logs)")
    head = lines[2].split()
    if len(head) < 3 or not (is_number(head[-1]) and is_number(head[-2])):
        raise InputError(f"{p}: line 3: expected the well head 'name x y [rkb]', got {lines[2].strip()!r}")
    numeric = len(head) >= 4 and is_number(head[-3])  # name x y rkb
    well = " ".join(head[: -3 if numeric else -2])
    count = lines[3].strip()
    if not count.isdigit():
        raise InputError(f"{p}: line 4: expected the number of logs, got {count!r}")
    logs = int(count)
    if len(lines) < 4 + logs:
        raise InputError(f"{p}: {logs} logs declared on line 4, but the file ends at line {len(lines)}")
    names = list(_RMS_COORDINATES)
    for number in range(5, 5 + logs):
        fields = lines[number - 1].split()
        if not fields:  # a name alone is a log without a type (xtgeo reads it as UNK lin)
            raise InputError(f"{p}: line {number}: expected a log 'name type ...', got {lines[number - 1]!r}")
        names.append(fields[0])
    rows, numbers = [], []
    for number in range(5 + logs, len(lines) + 1):
        fields = lines[number - 1].split()
        if len(fields) == 1 and number < len(lines) and _starts_with_text(lines[number]):
            raise InputError(
                f"{p}: line {number}: a second well starts here (a version line, then "
                f"'{lines[number].strip()}'): an RMS well file holds one well (xtgeo's stacked files "
                "hold several: split them)"
            )
        if fields:
            rows.append(fields)
            numbers.append(number)
    if not rows:
        raise InputError(f"{p}: no data lines after the {logs} logs (expected x y z and the logs per line)")
    return well, TextTable(names, 4, rows, numbers)


def _starts_with_text(line: str) -> bool:
    """Does ``line`` start with a word that is not a number (a well type, after a version line)?"""
    fields = line.split()
    return bool(fields) and not is_number(fields[0])


def _columns(
    p: Path, table: TextTable, width: int, columns: Mapping[str, str | int] | None
) -> dict[str, int]:
    """The 0-based positions of x, y, z and (if any) md."""
    given = dict(columns or {})
    unknown = sorted(set(given) - set(COLUMN_NAMES))
    if unknown:
        raise InputError(f"{p}: columns: unknown key {unknown[0]!r} (expected x, y, z, md)")
    lower = [h.lower() for h in table.header] if table.header is not None else None
    where = f"{p}: line {table.header_line}" if table.header is not None else f"{p}: line {table.lines[0]}"
    cols: dict[str, int] = {}
    for role, value in given.items():
        if isinstance(value, int) and not isinstance(value, bool):
            if not 0 <= value < width:
                raise InputError(f"{p}: columns: {role}: position {value} is not in 0..{width - 1}")
            cols[role] = value
        elif lower is not None and isinstance(value, str) and value.lower() in lower:
            cols[role] = lower.index(value.lower())
        else:
            have = f"the columns are {', '.join(table.header)}" if table.header else "the file has no header"
            raise InputError(f"{p}: columns: {role}: no column {value!r} ({have})")
    for role, known in COLUMN_NAMES.items():
        if role in cols:
            continue
        if lower is None:
            if width not in (3, 4):
                raise InputError(
                    f"{where}: expected 3 columns (x y z) or 4 (x y z md), found {width}; "
                    "add a header line or choose them with columns"
                )
            position = list(COLUMN_NAMES).index(role)
            if (role != "md" or width == 4) and position not in cols.values():
                cols[role] = position
            continue
        found = [i for i, h in enumerate(lower) if h in known]
        if len(found) > 1:
            both = " and ".join(table.header[i] for i in found)
            raise InputError(f"{where}: columns {both} both name {role}; choose one with columns")
        if found:
            cols[role] = found[0]
        elif role != "md":
            raise InputError(
                f"{where}: no column for {role} (named {', '.join(n.upper() for n in known)}) among "
                f"{', '.join(table.header)}; name it so or choose it with columns"
            )
    seen: dict[int, str] = {}
    for role in COLUMN_NAMES:
        if role in cols and cols[role] in seen:
            raise InputError(f"{p}: columns: {role} is the same column as {seen[cols[role]]} ({cols[role]})")
        if role in cols:
            seen[cols[role]] = role
    return cols


def _numbers(p: Path, table: TextTable, width: int, used: list[int]) -> tuple[FloatArray, np.ndarray]:
    """The ``used`` columns of the rows as an (n, k) float array, and as their text; a row of
    another width or a used field that is not a number is one error naming its line."""
    for fields, number in zip(table.rows, table.lines, strict=True):
        if len(fields) != width:
            raise InputError(f"{p}: line {number}: expected {width} fields, found {len(fields)}")
    text = np.array(table.rows)[:, used]
    try:
        values = text.astype(np.float64)
    except ValueError:
        number, column, field = first_non_number(table.rows, table.lines, used)
        raise InputError(f"{p}: line {number}: field {column + 1} {field!r} is not a number") from None
    return values, text
