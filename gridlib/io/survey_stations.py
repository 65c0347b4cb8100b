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
from functools import partial
from pathlib import Path

from ..errors import InputError
from ..grid import FloatArray
from ..wells.survey import station_problem
from .text_table import check_widths, data_rows, read_lines, split_fields, to_numbers

COLUMNS = ("md", "inclination", "azimuth")


def read_survey_stations(path: str | os.PathLike) -> FloatArray:
    """The stations of the survey file ``path`` as an (m, 3) array of md, inclination and
    azimuth (module docstring); at least two stations."""
    p = Path(path)
    table = data_rows(read_lines(p), split=partial(split_fields, mixed=True))
    rows, numbers = table.rows, table.lines
    if len(rows) < 2:
        raise InputError(
            f"{p}: {len(rows)} station(s); a survey needs at least 2 (md inclination azimuth per line)"
        )
    check_widths(p, rows, numbers, 3, " (md, inclination, azimuth)")
    values = to_numbers(p, rows, numbers, COLUMNS)
    problem = station_problem(values)
    if problem is not None:
        raise InputError(f"{p}:{numbers[problem[0]]}: {problem[2]}")
    return values
