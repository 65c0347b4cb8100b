"""IRAP/RMS binary surfaces (``.gri``, xtgeo's ``irap_binary``): read and write.

Format
------
Big-endian Fortran unformatted sequential records: every record is its length in bytes
(int32), its bytes, and the length again. Three header records, then the values::

    [32]  -996 (int32)  ny (int32)  xori xmax yori ymax xinc yinc (float32)  [32]
    [16]  nx (int32)  rotation xrot yrot (float32)                           [16]
    [28]  seven int32 zeros                                                   [28]
    [4 m] m float32 values                                                    [4 m]   (repeated)

Values run i (x) fastest, from the origin row (j = 0) up, as in IRAP classic ASCII
(:mod:`gridlib.io.irap`); RMS and xtgeo write one record per row (``m = nx``), the reader takes
records of any length. ``rotation`` is in degrees counter-clockwise from the x axis about
(xori, yori); ``xmax``/``ymax`` are the unrotated extent, ``xrot``/``yrot`` the rotation origin
(written as xori, yori; both ignored on reading, as by xtgeo). Bytes after the last value
record are ignored (ResInsight appends a text footer of metadata there). A negative ``yinc`` means rows
run the other way (xtgeo's ``yflip = -1``): the reader turns such a lattice to a positive
``yinc`` with the rows reversed and the origin moved to the old last row, the same nodes.
These facts are from xtgeo's reader and writer (``xtgeo.surface``, LGPL; read, not copied)
and Equinor's ``surfio``.

Undefined nodes
---------------
The writer writes 1e30 (float32 ``1.0000000150474662e30``) for NaN, as xtgeo and surfio do
(xtgeo reads values >= 1e30 as undefined). The reader takes values >= 9999900.0 as undefined:
1e30 and also the classic ASCII null 9999900.0, which some writers put in binary files. A
defined depth at or above 9999900.0 (or beyond float32's range) is an
:class:`~gridlib.errors.InputError` on writing.

Precision
---------
Everything is float32, the header too. Values are rounded to the nearest float32 (relative
error <= 2**-24, e.g. <= 0.06 mm at 1000 m depth); ``write(read(f))`` gives ``f``'s bytes back
and ``read(write(s))`` gives ``s.z.astype(float32)`` exactly. The header is float32 as well:
an origin in UTM coordinates is rounded to the float32 spacing there (0.03 m at 5e5 m east,
0.5 m at 6.7e6 m north), so write the lattice origin where it is representable (a multiple of
the spacing, e.g. of 0.5 m north of 4.2e6 m) when metres matter; xtgeo and RMS have the same
limit with this format. Lengths are the file's (gridlib: metres).

Depth or elevation
------------------
Values are written as they are in the :class:`~gridlib.horizons.surface.Surface`: depth,
positive down, which is what RMS (its depth domain, ``TVDSS``) and xtgeo (``Z_TVDSS``
positive down) hold for depth surfaces. ``elevation=True`` negates on reading and writing, for
files of elevations (positive up).

>>> import numpy as np, tempfile, os
>>> from gridlib.horizons.surface import Surface
>>> s = Surface(np.array([[1000.0, 1001.5, np.nan], [1002.0, 1003.0, 1004.25]]), 0.0, 0.0, 50.0, 25.0)
>>> path = write_irap_binary(os.path.join(tempfile.mkdtemp(), "top.gri"), s)
>>> t = read_irap_binary(path)
>>> t.z.tolist(), (t.nx, t.ny, t.xinc, t.yinc, t.rotation)
([[1000.0, 1001.5, nan], [1002.0, 1003.0, 1004.25]], (3, 2, 50.0, 25.0, 0.0))
>>> os.path.getsize(path)  # 100 header bytes + 2 rows of (4 + 3 * 4 + 4)
140
"""

from __future__ import annotations

import math
import os
import struct
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..horizons.surface import Surface
from .atomic import atomic_path
from .irap import IRAP_UNDEFINED

__all__ = ["IRAP_BINARY_UNDEFINED", "read_irap_binary", "read_irap_binary_surface", "write_irap_binary"]

IRAP_BINARY_UNDEFINED = 1e30  # the null written for undefined nodes (xtgeo's, surfio's)
_ID = -996
_HEADER = struct.Struct(">3i6f3i3f2i7ii")  # the three header records with their markers
_HEADER_BYTES = _HEADER.size  # 100
_FLOAT32_MAX = float(np.finfo(np.float32).max)


def read_irap_binary(path: str | os.PathLike, *, elevation: bool = False, name: str | None = None) -> Surface:
    """Read an IRAP/RMS binary surface into a :class:`~gridlib.horizons.surface.Surface`
    (float32 values widened exactly to float64; undefined nodes NaN; see the module docstring).

    ``elevation``: the file holds elevations (positive up), negated to depths. ``name``: the
    surface's name (default: the file's stem). A file that is not this format, or is cut short,
    is one :class:`~gridlib.errors.InputError` naming the file and the byte offset.
    """
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: no such file")
    try:
        buf = p.read_bytes()
    except OSError as exc:
        raise InputError(f"{p}: cannot read ({exc})") from exc
    if len(buf) < _HEADER_BYTES:
        raise InputError(
            f"{p}: not an IRAP binary surface: {len(buf)} bytes, the header alone has {_HEADER_BYTES}"
        )
    head = _HEADER.unpack_from(buf)
    markers = (head[0], head[9], head[10], head[15], head[16], head[24])
    if markers != (32, 32, 16, 16, 28, 28) or head[1] != _ID:
        raise InputError(
            f"{p}: not an IRAP binary surface (big-endian records of 32, 16 and 28 bytes starting "
            f"with -996 expected; found record markers {markers[::2]} and id {head[1]})"
        )
    ny, xori, yori, xinc, yinc = head[2], head[3], head[5], head[7], head[8]
    nx, rotation = head[11], head[12]
    if nx < 1 or ny < 1:
        raise InputError(f"{p}: IRAP binary header: nx and ny must be positive, got {nx} x {ny}")
    for key, v, ok, need in (
        ("xori", xori, True, "finite"),
        ("yori", yori, True, "finite"),
        ("rotation", rotation, True, "finite"),
        ("xinc", xinc, xinc > 0, "finite and positive"),
        ("yinc", yinc, yinc != 0, "finite and non-zero"),
    ):
        if not (math.isfinite(v) and ok):
            raise InputError(f"{p}: IRAP binary header: {key} must be {need}, got {v!r}")
    values = _values(p, buf, nx * ny)
    values[values >= IRAP_UNDEFINED] = np.nan
    z = values.reshape(ny, nx)
    if yinc < 0:  # rows run the other way: the same nodes from the other end, yinc positive
        z = z[::-1]
        a = math.radians(rotation)
        c, s = math.cos(a), math.sin(a)
        along = (ny - 1) * yinc  # negative: the old last row lies at this offset along v
        xori, yori, yinc = xori - s * along, yori + c * along, -yinc
    if elevation:
        z = -z
    return Surface(
        z, xori, yori, xinc, yinc, rotation=rotation, name=p.stem if name is None else name, source=str(p)
    )


def _values(p: Path, buf: bytes, count: int) -> np.ndarray:
    """The ``count`` float32 values of the value records after the header, as float64."""
    body = memoryview(buf)[_HEADER_BYTES:]
    first = struct.unpack_from(">i", body)[0] if len(body) >= 4 else 0
    need = (
        count * 4 // first * (first + 8) if first > 0 and first % 4 == 0 and (4 * count) % first == 0 else 0
    )
    if need and len(body) >= need:
        # records of one length (as RMS and xtgeo write them): one vectorised view
        rec = np.frombuffer(body[:need], dtype=">i4").reshape(-1, first // 4 + 2)
        if (rec[:, 0] == first).all() and (rec[:, -1] == first).all():
            return rec[:, 1:-1].view(">f4").astype(np.float64).ravel()
    parts, offset, got = [], 0, 0
    while offset < len(body) and got < count:  # other record lengths: one step per record
        where = _HEADER_BYTES + offset
        if offset + 4 > len(body):
            raise InputError(f"{p}: byte {where}: IRAP binary record cut short")
        size = struct.unpack_from(">i", body, offset)[0]
        end = offset + 4 + size
        if size < 0 or size % 4 or end + 4 > len(body) or struct.unpack_from(">i", body, end)[0] != size:
            raise InputError(
                f"{p}: byte {where}: bad IRAP binary record (length {size}, not matched at its end)"
            )
        parts.append(np.frombuffer(body[offset + 4 : end], dtype=">f4"))
        got += size // 4
        offset = end + 4
    values = np.concatenate(parts).astype(np.float64) if parts else np.zeros(0)
    if values.size != count:
        raise InputError(f"{p}: IRAP binary surface of {count} nodes has {values.size} values")
    return values


def write_irap_binary(path: str | os.PathLike, surface: Surface, *, elevation: bool = False) -> Path:
    """Write a :class:`~gridlib.horizons.surface.Surface` as IRAP/RMS binary, atomically.

    One record per row of ``nx`` values (as RMS and xtgeo write), NaN as 1e30, every number
    rounded to float32 (see the module docstring). ``elevation``: write elevations (negated
    depths). A defined value at or above 9999900.0 (it would read back as undefined) or
    beyond float32's range is an :class:`~gridlib.errors.InputError`. Returns ``path``.
    """
    z = np.asarray(surface.z, dtype=np.float64)
    if elevation:
        z = -z
    defined = ~np.isnan(z)
    if (np.abs(z[defined]) > _FLOAT32_MAX).any() or (z[defined] >= IRAP_UNDEFINED).any():
        raise InputError(
            f"{path}: write_irap_binary: values must lie below {IRAP_UNDEFINED} (the IRAP null) and within "
            "float32's range"
        )
    ny, nx = z.shape
    xori, yori, xinc, yinc, rot = (
        float(v) for v in (surface.xori, surface.yori, surface.xinc, surface.yinc, surface.rotation)
    )
    header = _HEADER.pack(
        32, _ID, ny, xori, xori + (nx - 1) * xinc, yori, yori + (ny - 1) * yinc, xinc, yinc, 32,
        16, nx, rot, xori, yori, 16,
        28, *(0,) * 7, 28,
    )  # fmt: skip
    rows = np.empty((ny, nx + 2), dtype=">i4")
    rows[:, 0] = rows[:, -1] = 4 * nx
    rows[:, 1:-1] = np.where(defined, z, IRAP_BINARY_UNDEFINED).astype(">f4").view(">i4")
    with atomic_path(path) as tmp:
        tmp.write_bytes(header + rows.tobytes())
    return Path(path)


def read_irap_binary_surface(
    path: str | os.PathLike,
    *,
    elevation: bool = False,
    name: str | None = None,
    variable: str | None = None,
    horizon: str | int | None = None,
) -> Surface:
    """:func:`read_irap_binary` with the options of every surface reader (``kind="surface"``):
    the file holds one surface, so ``variable`` and ``horizon`` do not apply."""
    return read_irap_binary(path, elevation=elevation, name=name)
