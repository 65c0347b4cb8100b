"""Text tables of numbers: the mechanics the point, stick, survey and well path readers share.

A table file is read as text (``utf-8-sig``: a spreadsheet's byte order mark is no text);
``#`` starts a comment; empty lines are skipped; each line is split into fields by the
reader's own ``split`` (whitespace, commas, semicolons with decimal commas: the readers differ
there on purpose); a first data line without any number is a header of column names. Rows keep
their 1-based line numbers, so every problem is one :class:`~gridlib.errors.InputError` naming
the file and the line, e.g. ``picks.csv:7: column 3 (z): 'n/a' is not a number``.

This module imports only numpy and :mod:`gridlib.errors`: a case's checks read wells and
fault sticks without loading the horizons' modules.

>>> table = data_rows(["X Y # names", "", "1, 2", "3, 4"], split=lambda s: s.replace(",", " ").split())
>>> table.header, table.header_line, table.rows, table.lines
(['X', 'Y'], 1, [['1', '2'], ['3', '4']], [3, 4])
>>> to_numbers("p.csv", table.rows, table.lines, ("x", "y")).tolist()
[[1.0, 2.0], [3.0, 4.0]]
"""

from __future__ import annotations

import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

from ..errors import InputError

__all__ = [
    "TextTable",
    "check_widths",
    "data_rows",
    "first_non_number",
    "is_number",
    "read_lines",
    "split_fields",
    "strip_comment",
    "to_numbers",
]


@dataclass(frozen=True)
class TextTable:
    """A file's data: the header's names (or None) and its 1-based line (0 without one), the
    rows of fields and their 1-based line numbers."""

    header: list[str] | None
    header_line: int
    rows: list[list[str]]
    lines: list[int]


def is_number(token: str) -> bool:
    """Whether a text token reads as a float (``"1e3"``, ``"-0.5"``, ``"nan"``; not ``"x"``).

    >>> is_number("1e3"), is_number("x")
    (True, False)
    """
    try:
        float(token)
    except ValueError:
        return False
    return True


def read_lines(p: Path) -> list[str]:
    """The lines of the text file ``p``; a missing or unreadable file is an InputError."""
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    try:
        text = p.read_text(encoding="utf-8-sig")  # a spreadsheet's byte order mark is no text
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{p}: cannot read as text ({exc})") from None
    return text.splitlines()


def strip_comment(raw: str) -> str:
    """A line without its ``#`` comment and surrounding blanks."""
    return raw.split("#", 1)[0].strip()


_COMMAS_OR_BLANKS = re.compile(r"\s*,\s*|\s+")  # "1, 2" and "1 2" alike; "1,,2" has an empty field


def split_fields(
    line: str, *, semicolons: bool = True, quotes: bool = False, mixed: bool = False
) -> list[str]:
    """A line's fields: with ``semicolons``, at semicolons if it has one (a comma there is a
    decimal mark, as spreadsheets write in many locales: ``0,5`` is 0.5); else at commas if it
    has one; else at whitespace. ``mixed``: commas and whitespace both separate on one line
    (``1, 2 3``). ``quotes``: quotes around a field are dropped.

    >>> split_fields("1;0,5"), split_fields("1, 2 3", mixed=True), split_fields("'a', 2", quotes=True)
    (['1', '0.5'], ['1', '2', '3'], ['a', '2'])
    """
    quote = "\"'" if quotes else ""
    if semicolons and ";" in line:
        return [f.strip().strip(quote).replace(",", ".") for f in line.split(";")]
    if mixed:
        return _COMMAS_OR_BLANKS.split(line)
    if "," in line:
        return [f.strip().strip(quote) for f in line.split(",")]
    return line.split()


def data_rows(lines: Sequence[str], *, split: Callable[[str], list[str]]) -> TextTable:
    """The data lines of ``lines`` split into fields by ``split`` (comments and empty lines
    skipped), with their 1-based line numbers; a first data line without any number is the
    header. No rows is not an error here (the readers say what they expected)."""
    rows: list[list[str]] = []
    numbers: list[int] = []
    header: list[str] | None = None
    header_line = 0
    for number, raw in enumerate(lines, start=1):
        line = strip_comment(raw)
        if not line:
            continue
        fields = split(line)
        if not rows and header is None and not any(is_number(f) for f in fields):
            header, header_line = fields, number
            continue
        rows.append(fields)
        numbers.append(number)
    return TextTable(header, header_line, rows, numbers)


def check_widths(p: Path, rows: list[list[str]], lines: list[int], width: int, label: str = "") -> None:
    """Every row has ``width`` fields, else ``<file>:<line>: expected <width> columns<label>,
    found <n>`` for the first that has not (``label`` e.g. ``" (x, y, z)"``)."""
    for fields, number in zip(rows, lines, strict=True):
        if len(fields) != width:
            raise InputError(f"{p}:{number}: expected {width} columns{label}, found {len(fields)}")


def first_non_number(
    rows: list[list[str]], lines: list[int], columns: Sequence[int] | None = None
) -> tuple[int, int, str]:
    """The first field (in row order, then in ``columns`` order; default all) that is not a
    number, as (line number, 0-based column, field). Called after a failed conversion, so one
    exists."""
    for fields, number in zip(rows, lines, strict=True):
        for column in range(len(fields)) if columns is None else columns:
            if not is_number(fields[column]):
                return number, column, fields[column]
    raise ValueError("every field is a number")


def _listed(names: Sequence[str]) -> str:
    """``"x, y and z"``."""
    return f"{', '.join(names[:-1])} and {names[-1]}" if len(names) > 1 else "".join(names)


def to_numbers(
    p: Path,
    rows: list[list[str]],
    lines: list[int],
    names: Sequence[str],
    *,
    columns: Sequence[int] | None = None,
    finite_hint: str = "",
) -> npt.NDArray[np.float64]:
    """Rows of fields (all of one width, :func:`check_widths`) as an (n, k) float64 array.

    ``names``: the k columns' names; ``columns``: their 1-based-in-messages positions in the
    file when the rows were picked from wider ones (default 0..k-1). A field that is not a
    number is ``<file>:<line>: column <c> (<name>): '<field>' is not a number``; a non-finite
    value ``<file>:<line>: x, y and z must be finite<finite_hint>``.
    """
    try:
        values = np.array(rows, dtype=np.float64).reshape(len(rows), len(names))
    except ValueError:
        number, k, field = first_non_number(rows, lines)
        column = k if columns is None else columns[k]
        raise InputError(
            f"{p}:{number}: column {column + 1} ({names[k]}): {field!r} is not a number"
        ) from None
    bad = np.flatnonzero(~np.isfinite(values).all(axis=1))
    if bad.size:
        raise InputError(f"{p}:{lines[bad[0]]}: {_listed(names)} must be finite{finite_hint}")
    return values
