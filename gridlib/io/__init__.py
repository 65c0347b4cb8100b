"""File formats, one module per format behind one registry (as meshio).

``write(path, grid, ...)`` and ``read(path)`` pick the format from the file
suffix; the per-format functions are also importable directly. OPM Flow decks, which
are folders of files rather than one grid file: :func:`write_flow_deck`
(:mod:`gridlib.io.flow`).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path

from ..errors import InputError
from .flow import write_flow_deck
from .netcdf import (
    GridDataset,
    grid_to_dataset,
    read_geometry_netcdf,
    read_netcdf,
    write_geometry_netcdf,
    write_netcdf,
)
from .vtu import write_vtu

WRITERS: dict[str, Callable[..., Path]] = {".nc": write_netcdf, ".vtu": write_vtu}
READERS: dict[str, Callable[..., GridDataset]] = {".nc": read_netcdf}


def _suffix(path: str | os.PathLike, table: dict, what: str) -> str:
    suffix = Path(path).suffix.lower()
    if suffix not in table:
        raise InputError(f"{path}: cannot {what} '{suffix}' files; known: {', '.join(sorted(table))}")
    return suffix


def write(path: str | os.PathLike, grid, *args, **kwargs) -> Path:
    """Write ``grid`` in the format given by the suffix of ``path``."""
    return WRITERS[_suffix(path, WRITERS, "write")](path, grid, *args, **kwargs)


def read(path: str | os.PathLike) -> GridDataset:
    """Read a grid file in the format given by its suffix."""
    return READERS[_suffix(path, READERS, "read")](path)


__all__ = [
    "READERS",
    "WRITERS",
    "GridDataset",
    "grid_to_dataset",
    "read",
    "read_geometry_netcdf",
    "read_netcdf",
    "write",
    "write_flow_deck",
    "write_geometry_netcdf",
    "write_netcdf",
    "write_vtu",
]
