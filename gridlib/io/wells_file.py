"""``wells.nc``: a case's deviated and horizontal wells, their paths and their connections.

One file for every trajectory and survey well of the case (the ``wells`` stage), ragged over
the wells with offset arrays (``*_pos``: entries ``pos[w]`` to ``pos[w + 1]`` belong to item
``w``), as the grid's own ragged tables are stored:

* per well (dimension ``well``): ``well_name``, ``well_radius``, ``well_skin``;
  ``well_path_pos`` (``well + 1``) its paths, ``well_completion_pos`` (``well + 1``) its
  connections;
* per path (dimension ``path``; a well's main path first, then its branches in the case's
  order): ``path_name``, ``path_parent`` (the 0-based path of the same well a branch starts on;
  -1 for the main path), ``path_point_pos`` (``path + 1``) its points, ``path_perforation_pos``
  (``path + 1``) its open MD intervals;
* per point (dimension ``point``): ``path_xyz`` (x, y, z depth) and ``path_md``, MD increasing
  along each path;
* per perforation (dimension ``perforation``): ``perforation_md`` ([from, to], sorted);
* per connection (dimension ``completion``: one per connected cell of a well, branches merged,
  in MD order of first entry; :class:`~gridlib.wells.connections.WellConnections`):
  ``completion_cell`` (0-based row of ``grid.nc``), ``completion_ijk`` (1-based logical
  (i, j, k), as ECLIPSE and OPM Flow number cells; only for grids with logical indices),
  ``completion_entry_md``, ``completion_exit_md``, ``completion_entry``, ``completion_exit``
  (xyz), ``completion_length`` (the path's length in the cell), ``completion_axis_length``
  (its length along the cell's x, y and z axes), ``completion_factor`` (the connection factor)
  and ``completion_direction`` (0, 1, 2: x, y, z, the cell axis the path runs most along;
  COMPDAT's direction).

Units: the attribute ``unit_system`` (the grid's), and each variable's ``units`` from
:mod:`gridlib.io.quantities` (lengths in the length unit, factors in the transmissibility unit:
METRIC cP m3/(day bar)). A case without rock has no factors: ``completion_factor`` is NaN and
the attribute ``has_factors`` 0. The file carries checksums as every artifact
(:mod:`gridlib.io.datasets`).
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import xarray as xr

from ..cell_names import ijk
from ..connectivity import offsets
from ..units import UnitSystem
from ..wells.connections import WellConnections
from ..wells.path import WellPath
from .datasets import damaged, open_artifact, read_variable
from .netcdf import write_dataset
from .quantities import label_units

DIRECTIONS = "x y z"
_COMPLETION = (  # WellConnections field -> variable
    ("cell", "completion_cell"),
    ("entry_md", "completion_entry_md"),
    ("exit_md", "completion_exit_md"),
    ("entry", "completion_entry"),
    ("exit", "completion_exit"),
    ("length", "completion_length"),
    ("axis_length", "completion_axis_length"),
    ("factor", "completion_factor"),
    ("direction", "completion_direction"),
)


@dataclass(frozen=True, eq=False)
class WellRecord:
    """One well of ``wells.nc``: its ``name``, its ``paths`` (the main path, then its branches),
    its ``connections`` (one per connected cell, in MD order), and what made them: each
    branch's parent path (``parents[b]``: the index in ``paths`` of the path ``paths[b + 1]``
    starts on), each path's open MD intervals (``perforations[p]``, (k, 2)), the well's radius
    and skin (dimensionless). Lengths (points, MD, radius) in the file's length unit (m; a FIELD
    case's ft), z depth; factors in its transmissibility unit."""

    name: str
    paths: tuple[WellPath, ...]
    connections: WellConnections
    parents: tuple[int, ...] = ()
    perforations: tuple[np.ndarray, ...] = ()
    radius: float | None = None  # None: not recorded
    skin: float = 0.0


def wells_dataset(
    records: Sequence[WellRecord],
    units: UnitSystem,
    attrs: dict[str, Any],
    cart_dims: Sequence[int] | None = None,
    index_map: np.ndarray | None = None,
    has_factors: bool = True,
) -> xr.Dataset:
    """The Dataset of ``wells.nc`` (module docstring); ``cart_dims`` and ``index_map`` (the
    grid's) give the connections' (i, j, k)."""
    paths = [p for r in records for p in r.paths]
    perforations = [
        r.perforations[p] if r.perforations else np.array([[path.md[0], path.md[-1]]])
        for r in records
        for p, path in enumerate(r.paths)
    ]
    parents = [-1 if p == 0 else r.parents[p - 1] for r in records for p in range(len(r.paths))]
    conns = [r.connections for r in records]
    data: dict[str, xr.Variable] = {
        "well_name": xr.Variable("well", np.array([r.name for r in records], dtype=object)),
        "well_radius": xr.Variable(
            "well", np.array([np.nan if r.radius is None else r.radius for r in records], dtype=np.float64)
        ),
        "well_skin": xr.Variable("well", np.array([r.skin for r in records], dtype=np.float64)),
        "well_path_pos": xr.Variable("well_pos", offsets([len(r.paths) for r in records])),
        "well_completion_pos": xr.Variable("well_pos", offsets([c.cell.size for c in conns])),
        "path_name": xr.Variable("path", np.array([p.name for p in paths], dtype=object)),
        "path_parent": xr.Variable(
            "path", np.array(parents, dtype=np.int64), {"long_name": "path of the well it starts on, -1 none"}
        ),
        "path_point_pos": xr.Variable("path_pos", offsets([p.md.size for p in paths])),
        "path_perforation_pos": xr.Variable("path_pos", offsets([len(f) for f in perforations])),
        "path_xyz": xr.Variable(("point", "three"), _stack([p.xyz for p in paths], (0, 3))),
        "path_md": xr.Variable("point", _stack([p.md for p in paths], (0,))),
        "perforation_md": xr.Variable(("perforation", "two"), _stack(perforations, (0, 2))),
    }
    shapes = {"entry": (0, 3), "exit": (0, 3), "axis_length": (0, 3)}
    for field, name in _COMPLETION:
        values = _stack([np.asarray(getattr(c, field)) for c in conns], shapes.get(field, (0,)))
        dims = ("completion", "three") if values.ndim == 2 else ("completion",)
        data[name] = xr.Variable(dims, values)
    data["completion_cell"] = data["completion_cell"].astype(np.int64)
    data["completion_direction"] = xr.Variable(
        "completion",
        data["completion_direction"].values.astype(np.int8),
        {"flag_values": np.arange(3, dtype=np.int8), "flag_meanings": DIRECTIONS},
    )
    if cart_dims is not None and index_map is not None:
        cells = data["completion_cell"].values
        data["completion_ijk"] = xr.Variable(
            ("completion", "three"),
            ijk(np.asarray(index_map)[cells], cart_dims).astype(np.int64).reshape(-1, 3),
            {"long_name": "1-based logical (i, j, k) of the cell", "start_index": 1},
        )
    label_units(data, units, griddim=3)
    ds_attrs = {
        **attrs,
        "title": "gridlib wells",
        "unit_system": units.name,
        "has_factors": np.int32(has_factors),
    }
    return xr.Dataset(data, attrs=ds_attrs)


def _stack(arrays: Sequence[np.ndarray], empty: tuple[int, ...]) -> np.ndarray:
    return np.concatenate(arrays) if arrays else np.zeros(empty)


def write_wells(
    path: str | os.PathLike, records: Sequence[WellRecord], units: UnitSystem, **kwargs: Any
) -> None:
    """Write ``wells.nc`` (:func:`wells_dataset`'s arguments)."""
    write_dataset(path, wells_dataset(records, units, **kwargs))


def read_wells(path: str | os.PathLike) -> tuple[WellRecord, ...]:
    """The wells of ``wells.nc``, in the file's order: one InputError naming the file if it is
    damaged, incomplete or inconsistent (offsets that do not fit their tables)."""
    with open_artifact(path) as ds:
        v = {name: read_variable(ds, name, "biufUSO") for name in ds.variables}
    try:
        return _records(v)
    except (KeyError, ValueError, IndexError) as exc:
        raise damaged(path, f"its wells do not fit together ({type(exc).__name__}: {exc})") from None


def _ranges(pos: np.ndarray, total: int, what: str) -> list[slice]:
    pos = np.asarray(pos, dtype=np.int64)
    if pos.size == 0 or pos[0] != 0 or pos[-1] != total or (np.diff(pos) < 0).any():
        raise ValueError(f"{what} do not cover their {total} rows")
    return [slice(int(a), int(b)) for a, b in itertools.pairwise(pos)]


def _records(v: dict[str, np.ndarray]) -> tuple[WellRecord, ...]:
    names = [str(n) for n in v["well_name"]]
    point_of = _ranges(v["path_point_pos"], v["path_md"].size, "path_point_pos")
    perf_of = _ranges(v["path_perforation_pos"], v["perforation_md"].shape[0], "path_perforation_pos")
    paths = [
        WellPath(v["path_xyz"][s], v["path_md"][s], str(name))
        for s, name in zip(point_of, v["path_name"], strict=True)
    ]
    path_of = _ranges(v["well_path_pos"], len(paths), "well_path_pos")
    conn_of = _ranges(v["well_completion_pos"], v["completion_cell"].size, "well_completion_pos")
    records = []
    for w, name in enumerate(names):
        own = range(path_of[w].start, path_of[w].stop)
        connections = WellConnections(
            **{field: v[var][conn_of[w]] for field, var in _COMPLETION if field != "direction"},
            direction=v["completion_direction"][conn_of[w]].astype(np.int64),
        )
        records.append(
            WellRecord(
                name=name,
                paths=tuple(paths[p] for p in own),
                connections=connections,
                parents=tuple(int(v["path_parent"][p]) for p in own[1:]),
                perforations=tuple(v["perforation_md"][perf_of[p]] for p in own),
                radius=None if np.isnan(v["well_radius"][w]) else float(v["well_radius"][w]),
                skin=float(v["well_skin"][w]),
            )
        )
    return tuple(records)
