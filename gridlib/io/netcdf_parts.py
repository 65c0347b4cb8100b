"""Parts of a netCDF file read without the rest: some variables, one variable's length, the
global attributes; and the check that stage files read together describe the same cells."""

from __future__ import annotations

import copy
import json
import os
from typing import Any

import numpy as np

from ..cornerpoint.map_axes import MapAxes
from ..errors import InputError
from ..units import UnitSystem, unit_system
from .datasets import damaged, open_artifact, read_variable
from .shared_reads import read_once


def read_extra(path: str | os.PathLike, names: tuple[str, ...]) -> dict[str, np.ndarray]:
    """The variables ``names`` present in a gridlib netCDF file (missing ones are left out);
    one InputError naming the file if it is damaged (:func:`~gridlib.io.datasets.open_artifact`)."""
    with open_artifact(path) as ds:
        return {n: read_variable(ds, n, "biufUSO") for n in names if n in ds.variables}


def length_of(path: str | os.PathLike, name: str) -> int:
    """The first dimension's length of variable ``name`` of a gridlib netCDF file, without
    reading it (one InputError naming the file if the variable is missing or the file damaged)."""
    with open_artifact(path) as ds:
        if name not in ds.variables or not ds[name].ndim:
            raise damaged(path, f"variable '{name}' is missing")
        return int(ds[name].shape[0])


def check_same_cells(grid_nc: str | os.PathLike, num_cells: int, counts: dict[Any, int]) -> None:
    """Every stage file read beside ``grid_nc`` (keys of ``counts``: the file, or the file and
    variable) holds one value per cell of that grid; else an InputError naming both files."""
    for source, count in counts.items():
        if count != num_cells:
            raise InputError(
                f"{source}: {count} cells, but {grid_nc} has {num_cells} (stage files of different "
                "grids: build the case again)"
            )


@read_once(copy.deepcopy)
def read_attrs(path: str | os.PathLike) -> dict[str, Any]:
    """Global attributes of a netCDF file, JSON lists decoded."""
    with open_artifact(path) as ds:
        attrs = dict(ds.attrs)
    return {key: _json_or_text(value) for key, value in attrs.items()}


def stored_unit_system(path: str | os.PathLike, attrs: dict[str, Any]) -> UnitSystem:
    """The unit system of a stage file from its attributes ``attrs`` (its ``unit_system``);
    an InputError naming the file where it has none (a file of an older gridlib)."""
    if "unit_system" not in attrs:
        raise InputError(f"{path}: unit_system: attribute missing (written by an older gridlib: rebuild it)")
    try:
        return unit_system(str(attrs["unit_system"]))
    except InputError as exc:
        raise InputError(f"{path}: unit_system: {exc}") from None


def stored_map_axes(path: str | os.PathLike, attrs: dict[str, Any]) -> MapAxes | None:
    """Where the grid of a stage file lies on the map, from its attributes ``attrs`` (its
    ``map_axes``, a deck's MAPAXES; None: the grid's frame is the map's)."""
    if "map_axes" not in attrs:
        return None
    try:
        return MapAxes.of(attrs["map_axes"])
    except (TypeError, ValueError) as exc:
        raise InputError(f"{path}: map_axes: {exc}") from None


def _json_or_text(value: Any) -> Any:
    """A JSON list or mapping attribute decoded; any other value (text that merely starts with
    a bracket included) as it is."""
    if not (isinstance(value, str) and value[:1] in "[{"):
        return value
    try:
        return json.loads(value)
    except json.JSONDecodeError:
        return value
