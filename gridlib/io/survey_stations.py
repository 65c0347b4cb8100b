"""Directional survey files: the stations of one well, as rows ``md inclination azimuth``.

Rows of three numbers, separated by whitespace, commas or semicolons (a line with a semicolon is
split at semicolons only, and a comma in it is a decimal mark, as spreadsheets write it in many
locales); empty lines and ``#`` comments
are skipped; a first data line without any number is a header of column names and is skipped (the
columns are taken in the order md, inclination, azimuth whatever their names). MD in the case's
length unit, strictly increasing; inclination in degrees from vertical in [0, 180] (0 straight down,
90 horizontal); azimuth in degrees clockwise from north (+y), any value (taken modulo 360). Every
problem is one :class:`~gridlib.errors.InputError` naming the file and the line, e.g. ``p2.dev:7:
column 2 (inclination): 'n/a' is not a number``.

>>> import tempfile, pathlib
>>> with tempfile.TemporaryDirectory() as d:
...     f = pathlib.Path(d, "p2.dev")
...     _ = f.write_text("MD INC AZI\\n1000 0 0\\n1100, 10, 45\\n")
...     read_survey_stations(f).tolist()
[[1000.0, 0.0, 0.0], [1100.0, 10.0, 45.0]]
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..grid import FloatArray
from ..wells.survey import station_problem
from .well_paths import is_number

COLUMNS = ("md", "inclination", "azimuth")
_SEPARATORS = re.compile(r"\s*[,;]\s*|\s+")  # "1, 2" and "1 2" alike; "1,,2" has an empty field


def _data_rows(p: Path) -> tuple[list[list[str]], list[int]]:
    """The data lines split into fields, with their 1-based line numbers (header skipped)."""
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    try:
        text = p.read_text(encoding="utf-8-sig")  # a spreadsheet's byte order mark is no text
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{p}: cannot read as text ({exc})") from None
    rows: list[list[str]] = []
    numbers: list[int] = []
    header = False
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        if ";" in line:  # a comma is then a decimal mark, as spreadsheets write in many locales
            fields = [f.strip().replace(",", ".") for f in line.split(";")]
        else:
            fields = _SEPARATORS.split(line)
        if not rows and not header and not any(is_number(f) for f in fields):
            header = True
            continue
        rows.append(fields)
        numbers.append(number)
    return rows, numbers


def read_survey_stations(path: str | os.PathLike) -> FloatArray:
    """The stations of the survey file ``path`` as an (m, 3) array of md, inclination and
    azimuth (module docstring); at least two stations."""
    p = Path(path)
    rows, numbers = _data_rows(p)
    if len(rows) < 2:
        raise InputError(
            f"{p}: {len(rows)} station(s); a survey needs at least 2 (md inclination azimuth per line)"
        )
    for fields, number in zip(rows, numbers, strict=True):
        if len(fields) != 3:
            raise InputError(
                f"{p}:{number}: expected 3 columns (md, inclination, azimuth), found {len(fields)}"
            )
    try:
        values = np.array(rows, dtype=np.float64)
    except ValueError:
        for fields, number in zip(rows, numbers, strict=True):
            for c, field in enumerate(fields):
                if not is_number(field):
                    raise InputError(
                        f"{p}:{number}: column {c + 1} ({COLUMNS[c]}): {field!r} is not a number"
                    ) from None
        raise
    bad = np.flatnonzero(~np.isfinite(values).all(axis=1))
    if bad.size:
        raise InputError(f"{p}:{numbers[bad[0]]}: md, inclination and azimuth must be finite")
    problem = station_problem(values)
    if problem is not None:
        raise InputError(f"{p}:{numbers[problem[0]]}: {problem[2]}")
    return values
