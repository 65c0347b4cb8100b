"""Scattered horizon picks: x y z text/CSV files."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..grid import FloatArray


def read_points(
    path: str | os.PathLike,
    *,
    columns: Sequence[int] | Sequence[str] | None = None,
    elevation: bool = False,
    null: float | None = None,
) -> FloatArray:
    """Scattered picks ``(n, 3)`` = x, y, z (m) from a CSV or whitespace-separated text file.

    Lines are split at commas if the first data line has one (else at ``;`` if
    it has one, else at whitespace); empty lines and ``#`` comments are skipped.
    A first data line without any number is a header of column names.
    ``columns``: which columns are x, y and z (three 0-based indices, or three
    header names); by default a file must have exactly three. ``null``: rows
    whose z equals it are dropped (a no-data marker such as -999). ``elevation``:
    z is elevation (positive up) and is negated to depth.

    Every problem is an :class:`~gridlib.errors.InputError` naming the file and
    line, e.g. ``picks.csv:7: expected 3 columns (x, y, z), found 2``.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{p}: cannot read as text ({exc})") from exc
    rows: list[list[str]] = []
    line_no: list[int] = []
    sep: str | None = None
    header: list[str] | None = None
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        if sep is None and not rows and header is None:
            sep = "," if "," in line else ";" if ";" in line else ""
        fields = [f.strip() for f in line.split(sep)] if sep else line.split()
        if not rows and header is None and not any(_is_number(f) for f in fields):
            header = [f.lower() for f in fields]
            header_line = number
            continue
        rows.append(fields)
        line_no.append(number)
    if not rows:
        raise InputError(f"{p}: no data lines (expected x, y, z per line)")
    width = len(header) if header is not None else len(rows[0])
    if columns is None:
        if width != 3:
            where = f"{p}:{header_line}" if header is not None else f"{p}:{line_no[0]}"
            raise InputError(
                f"{where}: expected 3 columns (x, y, z), found {width}; pass columns= to choose three"
            )
        cols = [0, 1, 2]
    else:
        cols = _point_columns(columns, header, width, p)
    for fields, number in zip(rows, line_no, strict=True):
        if len(fields) != width:
            raise InputError(
                f"{p}:{number}: expected {width} columns{' (x, y, z)' if width == 3 else ''}, "
                f"found {len(fields)}"
            )
    picked = [[fields[c] for c in cols] for fields in rows]
    try:
        xyz = np.array(picked, dtype=np.float64)
    except ValueError:
        for fields, number in zip(picked, line_no, strict=True):
            for k, f in enumerate(fields):
                if not _is_number(f):
                    raise InputError(
                        f"{p}:{number}: column {cols[k] + 1} ({'xyz'[k]}): {f!r} is not a number"
                    ) from None
        raise
    finite = np.isfinite(xyz).all(axis=1)
    if not finite.all():
        r = int(np.flatnonzero(~finite)[0])
        raise InputError(f"{p}:{line_no[r]}: x, y and z must be finite (use null= for no-data markers)")
    if null is not None:
        xyz = xyz[xyz[:, 2] != float(null)]
        if xyz.shape[0] == 0:
            raise InputError(f"{p}: every z equals the null value {null}")
    if elevation:
        xyz[:, 2] = -xyz[:, 2]
    return xyz


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def _point_columns(columns: Sequence[Any], header: list[str] | None, width: int, p: Path) -> list[int]:
    cols = list(columns)
    if len(cols) != 3:
        raise InputError(f"{p}: columns must name three columns (x, y, z), got {columns!r}")
    out = []
    for c in cols:
        if isinstance(c, str):
            if header is None:
                raise InputError(f"{p}: columns names {c!r} but the file has no header line")
            if c.lower() not in header:
                raise InputError(f"{p}: no column {c!r} in the header ({', '.join(header)})")
            out.append(header.index(c.lower()))
        elif isinstance(c, int | np.integer) and not isinstance(c, bool) and 0 <= int(c) < width:
            out.append(int(c))
        else:
            raise InputError(f"{p}: columns: {c!r} is not a column index in [0, {width})")
    return out
