"""Fault stick files: the sticks of one fault, as geomodelling tools export them.

Two text formats, z being depth (m, positive down, e.g. RMS's ``Z_TVDSS``) in both:

* ``xyz_id``: rows ``x y z id`` (whitespace- or comma-separated), optionally under one header
  line of names (``X_UTME Y_UTMN Z_TVDSS POLY_ID``; the columns are taken in that order,
  whatever their names); a stick is a run of consecutive rows with one id;
* ``rms`` (the RMS/xtgeo polygon text): rows ``x y z``, every stick ended by the line
  ``999.0 999.0 999.0`` (the last one may be missing). Only a whole line of 999 ends a stick; a
  row with 999 in some of its columns only is an error (999 may be a real coordinate: use
  ``xyz_id`` for such files).

``#`` starts a comment in both. ``auto`` picks ``xyz_id`` for 4 columns and ``rms`` for 3.
The sticks come in file order, which must be their order along the fault's strike; a stick may
run down or up (it is turned to run down), but its depth must change monotonically.
"""

from __future__ import annotations

import os
from functools import partial
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..grid import FloatArray
from ..pillars.fault_surface import FaultSurface
from .text_table import check_widths, data_rows, is_number, read_lines, split_fields

__all__ = ["RMS_SEPARATOR", "STICK_FORMATS", "fault_surface_from_file", "read_fault_sticks", "rms_groups"]

STICK_FORMATS = ("auto", "rms", "xyz_id")
RMS_SEPARATOR = (999.0, 999.0, 999.0)  # the line that ends a stick or polygon in the rms format
_WIDTH = {"rms": 3, "xyz_id": 4}


def read_fault_sticks(path: str | os.PathLike, fmt: str = "auto") -> list[FloatArray]:
    """The sticks in ``path``: a list of (k >= 2, 3) arrays of x, y, z (m, z depth increasing
    down every stick), in file order. ``fmt``: ``auto`` (4 columns: ``xyz_id``, 3: ``rms``),
    ``rms`` or ``xyz_id`` (see the module docstring).

    Every problem is one :class:`~gridlib.errors.InputError` naming the file, the line and the
    stick (1-based, in file order), e.g. ``f2.xyz:14: stick 3: x, y and z must be finite``.
    Whether the sticks make a valid surface (none coincide or cross) is
    :func:`fault_surface_from_file`'s check.
    """
    p = Path(path)
    if fmt not in STICK_FORMATS:
        raise InputError(
            f"{p}: unknown fault stick format {fmt!r}; expected one of {', '.join(STICK_FORMATS)}"
        )
    table = data_rows(read_lines(p), split=partial(split_fields, semicolons=False))
    rows, numbers = table.rows, table.lines
    if not rows:
        raise InputError(f"{p}: no data lines (expected x y z [id] per line)")
    if fmt == "auto":
        fmt = {3: "rms", 4: "xyz_id"}.get(len(rows[0]), "")
        if not fmt:
            raise InputError(
                f"{p}:{numbers[0]}: expected 3 columns (x y z, the rms format) or 4 (x y z id, the "
                f"xyz_id format), found {len(rows[0])}"
            )
    width = _WIDTH[fmt]
    names = "x y z" if width == 3 else "x y z id"
    check_widths(p, rows, numbers, width, f" ({names}, the {fmt} format)")
    groups = rms_groups(p, rows, numbers) if fmt == "rms" else _id_sticks(p, rows, numbers)
    if len(groups) < 2:
        raise InputError(f"{p}: a fault needs at least 2 sticks, found {len(groups)}")
    return [_stick(p, number, group) for number, group in enumerate(groups, 1)]


def fault_surface_from_file(
    path: str | os.PathLike, fmt: str = "auto", name: str | None = None
) -> FaultSurface:
    """The :class:`~gridlib.pillars.fault_surface.FaultSurface` of the sticks in ``path``
    (:func:`read_fault_sticks`); sticks that coincide or cross are one InputError naming the
    file and the sticks."""
    return FaultSurface.from_sticks(read_fault_sticks(path, fmt), name=name, source=str(path))


def _numbers(
    p: Path, fields: list[str], number: int, stick: int, item: str = "stick"
) -> tuple[float, float, float]:
    """x, y, z of one row, finite."""
    values = []
    for column, field in zip("xyz", fields[:3], strict=True):
        if not is_number(field):
            raise InputError(f"{p}:{number}: {item} {stick}: {column}: {field!r} is not a number")
        values.append(float(field))
    if not np.isfinite(values).all():
        raise InputError(f"{p}:{number}: {item} {stick}: x, y and z must be finite")
    return values[0], values[1], values[2]


def rms_groups(
    p: Path, rows: list[list[str]], numbers: list[int], item: str = "stick"
) -> list[list[tuple[int, tuple[float, float, float]]]]:
    """The rows of the rms format (``x y z`` fields, 1-based line ``numbers``) up to each whole
    line of 999 (:data:`RMS_SEPARATOR`): per stick (or polygon: ``item`` names them in
    messages), its ``(line, (x, y, z))`` rows; empty groups dropped. A row with 999 in some
    columns only is an InputError."""
    groups: list[list[tuple]] = [[]]
    for fields, number in zip(rows, numbers, strict=True):
        xyz = _numbers(p, fields, number, len(groups), item)
        if xyz == RMS_SEPARATOR:
            if groups[-1]:
                groups.append([])
            continue
        if RMS_SEPARATOR[0] in xyz:
            raise InputError(
                f"{p}:{number}: {item} {len(groups)}: 999 in some columns only; in the rms format "
                f"only a whole line '999.0 999.0 999.0' ends a {item} (for 999 as a coordinate, "
                "use the xyz_id format)"
            )
        groups[-1].append((number, xyz))
    return [g for g in groups if g]


def _id_sticks(p: Path, rows: list[list[str]], numbers: list[int]) -> list[list[tuple]]:
    """Sticks of the xyz_id format: runs of consecutive rows with one id."""
    groups: list[list[tuple]] = []
    seen: dict[object, int] = {}
    current: object = None
    for fields, number in zip(rows, numbers, strict=True):
        ident = float(fields[3]) if is_number(fields[3]) else fields[3]
        if isinstance(ident, float) and not np.isfinite(ident):
            raise InputError(f"{p}:{number}: the stick id must be finite, got {fields[3]!r}")
        if not groups or ident != current:
            if ident in seen:
                raise InputError(
                    f"{p}:{number}: stick id {fields[3]} again, after other sticks (it is stick "
                    f"{seen[ident]}): the rows of a stick must be consecutive"
                )
            groups.append([])
            seen[ident] = len(groups)
            current = ident
        groups[-1].append((number, _numbers(p, fields, number, len(groups))))
    return groups


def _stick(p: Path, stick: int, group: list[tuple]) -> FloatArray:
    """One stick's rows as a (k, 3) array running down."""
    lines = [number for number, _ in group]
    where = f"{p}:{lines[0]}-{lines[-1]}" if len(lines) > 1 else f"{p}:{lines[0]}"
    if len(group) < 2:
        raise InputError(f"{where}: stick {stick} has 1 point; a stick needs at least 2")
    xyz = np.array([values for _, values in group])
    step = np.diff(xyz[:, 2])
    if np.all(step < 0):
        return xyz[::-1].copy()
    if not np.all(step > 0):
        k = int(np.flatnonzero(step <= 0)[0]) if step[0] > 0 else int(np.flatnonzero(step >= 0)[0])
        raise InputError(
            f"{p}:{lines[k + 1]}: stick {stick}: the depth must change monotonically along a stick "
            f"(z={xyz[k + 1, 2]:g} after z={xyz[k, 2]:g}; overturned faults are not supported)"
        )
    return xyz
