"""IRAP classic ASCII surfaces (RMS, Petrel and xtgeo's ``irap_ascii``): read and write, exactly.

Format
------
A header of 19 numbers on four lines, then the node values::

    -996  ny  xinc  yinc
    xori  xmax  yori  ymax
    nx  rotation  xrot  yrot
    0  0  0  0  0  0  0
    v(0,0) v(1,0) ... v(nx-1,0) v(0,1) ...      (six per line)

Values run i (x) fastest, from the origin row (j = 0, y = yori) up; 9999900.0
marks an undefined node (NaN in memory). ``rotation`` is in degrees,
counter-clockwise from the x axis, about the origin (xori, yori); ``xmax``
and ``ymax`` are xori + (nx - 1) xinc and yori + (ny - 1) yinc (the unrotated
extent). The reader goes by numbers, not lines, as the format's other readers
do; it checks the -996 code, the sizes and increments and the count of values,
and ignores ``xmax``, ``ymax``, ``xrot``, ``yrot`` (our rotation is always
about the origin, as RMS writes it).

Exactness
---------
:func:`write_irap` writes every number as Python's shortest repr that reads
back to the same float64, so ``read_irap(write_irap(s))`` has bit-identical
values and header, and writing that again gives the same bytes.

Units are those of the file (metres for gridlib); the values are read as they
are: depth (positive down) unless ``elevation=True`` negates them.

>>> import numpy as np, tempfile, os
>>> from gridlib.horizons.surface import Surface
>>> s = Surface(np.array([[1000.0, 1001.5, np.nan], [1002.0, 1003.0, 1004.25]]), 0.0, 0.0, 50.0, 25.0)
>>> path = os.path.join(tempfile.mkdtemp(), "top.irap")
>>> _ = write_irap(path, s)
>>> print(open(path).read().strip())
-996 2 50.0 25.0
0.0 100.0 0.0 25.0
3 0.0 0.0 0.0
0 0 0 0 0 0 0
1000.0 1001.5 9999900.0 1002.0 1003.0 1004.25
>>> t = read_irap(path)
>>> np.array_equal(t.z, s.z, equal_nan=True), (t.nx, t.ny, t.xinc, t.yinc)
(True, (3, 2, 50.0, 25.0))
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..horizons.surface import Surface
from .atomic import atomic_path
from .text_table import is_number

__all__ = ["IRAP_UNDEFINED", "is_number", "read_irap", "write_irap"]

IRAP_UNDEFINED = 9999900.0  # the format's null value; values >= it are undefined
_HEADER = 19
_PER_LINE = 6


def _line_of_token(text: str, index: int) -> int:
    """1-based line number of the ``index``-th whitespace-separated token of ``text``."""
    seen = 0
    for number, line in enumerate(text.splitlines(), start=1):
        n = len(line.split())
        if seen + n > index:
            return number
        seen += n
    return number if text else 1


def read_irap(path: str | os.PathLike, *, elevation: bool = False, name: str | None = None) -> Surface:
    """Read an IRAP classic ASCII surface into a :class:`~gridlib.horizons.surface.Surface`.

    ``elevation``: the file holds elevations (positive up), negated to depths.
    ``name``: the surface's name (default: the file's stem). Every problem is
    an :class:`~gridlib.errors.InputError` naming the file (and the line).
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    try:
        text = p.read_text(encoding="utf-8", errors="strict")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{p}: cannot read as IRAP classic ASCII text ({exc})") from exc
    tokens = text.split()
    if len(tokens) < _HEADER:
        raise InputError(
            f"{p}: not an IRAP classic ASCII surface: the header needs {_HEADER} numbers, "
            f"the file has {len(tokens)}"
        )
    try:
        head = [float(t) for t in tokens[:_HEADER]]
    except ValueError:
        bad = next(i for i, t in enumerate(tokens[:_HEADER]) if not is_number(t))
        raise InputError(
            f"{p}:{_line_of_token(text, bad)}: IRAP header: {tokens[bad]!r} is not a number"
        ) from None
    if head[0] != -996:
        raise InputError(
            f"{p}:1: not an IRAP classic ASCII surface (first number {tokens[0]}, expected -996)"
        )
    ny, xinc, yinc = head[1], head[2], head[3]
    xori, yori = head[4], head[6]
    nx, rotation = head[8], head[9]
    for what, v, line in (("ny", ny, 1), ("nx", nx, 3)):
        if not (math.isfinite(v) and v.is_integer() and v >= 1):
            raise InputError(f"{p}:{line}: IRAP header: {what} must be a positive integer, got {v!r}")
    for what, v, line in (("xinc", xinc, 1), ("yinc", yinc, 1)):
        if not (math.isfinite(v) and v > 0):
            raise InputError(f"{p}:{line}: IRAP header: {what} must be positive, got {v!r}")
    for what, v, line in (("xori", xori, 2), ("yori", yori, 2), ("rotation", rotation, 3)):
        if not math.isfinite(v):
            raise InputError(f"{p}:{line}: IRAP header: {what} must be finite, got {v!r}")
    nx_i, ny_i = int(nx), int(ny)
    body = tokens[_HEADER:]
    if len(body) != nx_i * ny_i:
        raise InputError(
            f"{p}: IRAP surface of {nx_i} x {ny_i} nodes needs {nx_i * ny_i} values, the file has {len(body)}"
        )
    try:
        values = np.array(body, dtype=np.float64)
    except ValueError:
        bad = next(i for i, t in enumerate(body) if not is_number(t))
        raise InputError(
            f"{p}:{_line_of_token(text, _HEADER + bad)}: {body[bad]!r} is not a number"
        ) from None
    finite = np.isfinite(values)
    if not finite.all():
        bad = int(np.flatnonzero(~finite)[0])
        raise InputError(
            f"{p}:{_line_of_token(text, _HEADER + bad)}: value {body[bad]!r} is not finite "
            f"(IRAP marks undefined nodes with {IRAP_UNDEFINED})"
        )
    values[values >= IRAP_UNDEFINED] = np.nan
    z = values.reshape(ny_i, nx_i)
    if elevation:
        z = -z
    return Surface(
        z, xori, yori, xinc, yinc, rotation=rotation, name=p.stem if name is None else name, source=str(p)
    )


def write_irap(path: str | os.PathLike, surface, *, elevation: bool = False) -> Path:
    """Write a :class:`~gridlib.horizons.surface.Surface` as IRAP classic ASCII, atomically.

    NaN nodes are written as 9999900.0; every number as its shortest exact
    repr, six values per line. ``elevation``: write elevations (negated
    depths). A defined value at or above 9999900 would read back as undefined
    and is an :class:`~gridlib.errors.InputError`.
    """
    z = np.asarray(surface.z, dtype=np.float64)
    if elevation:
        z = -z
    if np.isinf(z).any():
        raise InputError(f"{path}: write_irap: the surface has infinite values (use NaN for undefined)")
    if (z >= IRAP_UNDEFINED).any():
        raise InputError(
            f"{path}: write_irap: values >= {IRAP_UNDEFINED} would read back as undefined (the IRAP null)"
        )
    ny, nx = z.shape
    r = repr
    xori, yori, xinc, yinc = (float(v) for v in (surface.xori, surface.yori, surface.xinc, surface.yinc))
    rot = float(surface.rotation)
    xmax, ymax = xori + (nx - 1) * xinc, yori + (ny - 1) * yinc
    header = (
        f"-996 {ny} {r(xinc)} {r(yinc)}\n"
        f"{r(xori)} {r(xmax)} {r(yori)} {r(ymax)}\n"
        f"{nx} {r(rot)} {r(xori)} {r(yori)}\n"
        "0 0 0 0 0 0 0\n"
    )
    flat = np.where(np.isnan(z), IRAP_UNDEFINED, z).ravel()
    words = [r(v) for v in flat.tolist()]
    lines = [" ".join(words[i : i + _PER_LINE]) for i in range(0, len(words), _PER_LINE)]
    with atomic_path(path) as tmp:
        tmp.write_text(header + "\n".join(lines) + "\n", encoding="utf-8")
    return Path(path)


def read_irap_surface(
    path: str | os.PathLike,
    *,
    elevation: bool = False,
    name: str | None = None,
    variable: str | None = None,
    horizon: str | int | None = None,
) -> Surface:
    """:func:`read_irap` with the options of every surface reader (``kind="surface"``): an IRAP
    file holds one surface, so ``variable`` and ``horizon`` (which pick one of a netCDF file's)
    do not apply."""
    return read_irap(path, elevation=elevation, name=name)
