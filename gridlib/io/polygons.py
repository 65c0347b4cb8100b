"""Polygons and polylines as RMS/xtgeo text (xtgeo's ``xyz`` polygons format): write and read.

Format
------
Rows ``x y z``, one point each, every polyline ended by the line ``999.0 999.0 999.0``::

    1000.0 2000.0 1510.5
    1100.0 2050.0 1522.0
    999.0 999.0 999.0
    ...

This is the text RMS exports and imports for polygons and xtgeo reads and writes with
``fformat="xyz"`` (``Polygons``: columns ``X_UTME Y_UTMN Z_TVDSS``, a new ``POLY_ID`` after each
999 line), the same as the ``rms`` format of fault stick files (:mod:`gridlib.io.fault_sticks`,
whose row grouping :func:`read_polygons` reuses). z is depth, positive down (RMS's and xtgeo's
``Z_TVDSS``, true vertical depth below sea level), in the file's length unit (gridlib: metres).

Exactness
---------
Every number is written as Python's shortest repr that reads back to the same float64, so
``read_polygons(write_polygons(p))`` is bit for bit ``p``. xtgeo reads 999.0 in any column as
missing and drops that row: a point with a coordinate of exactly 999.0 cannot be stored in this
format, and writing one is an :class:`~gridlib.errors.InputError` (as is any non-finite value).

>>> import numpy as np, tempfile, os
>>> lines = [np.array([[0.0, 0.0, 1000.0], [10.0, 5.5, 1002.25]]), np.array([[3.0, 4.0, 999.5]])]
>>> path = write_polygons(os.path.join(tempfile.mkdtemp(), "f1.pol"), lines)
>>> print(open(path).read().strip())
0.0 0.0 1000.0
10.0 5.5 1002.25
999.0 999.0 999.0
3.0 4.0 999.5
999.0 999.0 999.0
>>> [p.tolist() for p in read_polygons(path)]
[[[0.0, 0.0, 1000.0], [10.0, 5.5, 1002.25]], [[3.0, 4.0, 999.5]]]
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from functools import partial
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..grid import FloatArray
from .atomic import atomic_path
from .fault_sticks import RMS_SEPARATOR, rms_groups
from .text_table import check_widths, data_rows, read_lines, split_fields

__all__ = ["POLYGON_FORMATS", "read_polygons", "write_polygons"]

POLYGON_FORMATS = ("rms",)
_SEPARATOR_LINE = " ".join(repr(v) for v in RMS_SEPARATOR)


def write_polygons(path: str | os.PathLike, polylines: Sequence[np.ndarray], *, fmt: str = "rms") -> Path:
    """Write ``polylines`` (each an (n >= 1, 3) array of x, y, z; z depth, positive down) as
    RMS/xtgeo polygon text, atomically; every polyline, the last too, ended by the 999 line.
    Returns ``path``. An empty polyline, a non-finite value or a coordinate of 999.0 is one
    :class:`~gridlib.errors.InputError` naming the file and the polyline (0-based)."""
    if fmt not in POLYGON_FORMATS:
        raise InputError(
            f"{path}: unknown polygon format {fmt!r}; expected one of {', '.join(POLYGON_FORMATS)}"
        )
    blocks = []
    for index, line in enumerate(polylines):
        xyz = np.asarray(line, dtype=np.float64)
        if xyz.ndim != 2 or xyz.shape[1] != 3 or xyz.shape[0] == 0:
            raise InputError(
                f"{path}: polyline {index}: expected an (n >= 1, 3) array of x, y, z, got shape {xyz.shape}"
            )
        if not np.isfinite(xyz).all():
            raise InputError(f"{path}: polyline {index}: x, y and z must be finite")
        if (xyz == RMS_SEPARATOR[0]).any():
            point = int(np.flatnonzero((xyz == RMS_SEPARATOR[0]).any(axis=1))[0])
            raise InputError(
                f"{path}: polyline {index}: point {point} has a coordinate of 999.0, the format's "
                "separator (xtgeo and RMS would drop or split there)"
            )
        words = [repr(v) for v in xyz.ravel().tolist()]
        rows = [" ".join(words[i : i + 3]) for i in range(0, len(words), 3)]
        blocks.append("\n".join([*rows, _SEPARATOR_LINE]))
    with atomic_path(path) as tmp:
        tmp.write_text("".join(block + "\n" for block in blocks), encoding="utf-8")
    return Path(path)


def read_polygons(path: str | os.PathLike, fmt: str = "rms") -> list[FloatArray]:
    """The polylines in an RMS/xtgeo polygon file: a list of (n >= 1, 3) arrays of x, y, z (z as
    in the file: depth, positive down), in file order; ``#`` starts a comment. Every problem is
    one :class:`~gridlib.errors.InputError` naming the file, the line and the polygon (1-based)."""
    p = Path(path)
    if fmt not in POLYGON_FORMATS:
        raise InputError(f"{p}: unknown polygon format {fmt!r}; expected one of {', '.join(POLYGON_FORMATS)}")
    table = data_rows(read_lines(p), split=partial(split_fields, semicolons=False))
    if not table.rows:
        raise InputError(f"{p}: no data lines (expected x y z per line, polygons ended by 999.0 999.0 999.0)")
    check_widths(p, table.rows, table.lines, 3, " (x, y, z, the rms polygon format)")
    groups = rms_groups(p, table.rows, table.lines, item="polygon")
    return [np.array([xyz for _, xyz in group]) for group in groups]
