"""A case's deviated and horizontal wells (``wells[k].trajectory``, ``.survey``, ``.branches``,
``.perforations``): their paths read from the case and the files it names, and what the schema
cannot check about them.

A well's path is its ``trajectory`` file (:func:`gridlib.io.well_paths.read_well_path`; MD from
the file, else the length along the points from 0) or its ``survey`` (stations in the case or in
a file, :mod:`gridlib.io.survey_stations`) joined by minimum curvature
(:func:`gridlib.wells.survey.minimum_curvature`) with points along the arcs at most
``survey.step`` apart in MD. Lengths, depths and MD are in the case's length unit (m; a FIELD
deck's ft), z depth.

A branch (a lateral) starts on its parent's path: the main path or an earlier branch, whichever
passes nearest its first point, which must lie within :data:`BRANCH_TOLERANCE` of it. Its MD
continues the parent's: a branch file without MD (its MD then starts at 0) gets the parent's MD
at that point added; a branch whose own MD starts elsewhere must start within the tolerance of
the parent's MD there. A branch holds its own hole only: one whose point
:data:`OVERLAP` along it still lies on its parent's path (within :data:`ON_PARENT`) runs along
that path (a lateral's file that repeats the parent's hole above the kick-off) and is refused, as
its cells would be completed twice. The tolerance is one length unit (1 m; 1 ft): wide enough for files
written to the centimetre and for a lateral read off a survey's arc where its parent's path is
the chord between survey points (the chord of a 30 m step on a 3 degree per 30 m build lies
0.2 m inside the arc), narrow enough to catch a branch given in the wrong file or the wrong
unit.

Perforations are MD intervals ``[from, to]`` of one path (the well's or a branch's), from < to,
inside the path's MD range and not overlapping one another; without any, the whole path is
open (the part inside the grid is what connects).

Files are read once per process and file state (path, modification time and size), as the
case's checks and its wells stage both need them.
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np

from ..errors import InputError
from .files import named_file
from .values import yaml_number

if TYPE_CHECKING:
    from ..wells.path import WellPath

BRANCH_TOLERANCE = 1.0  # the case's length unit: how far a branch may start from its parent's path
SURVEY_STEP = 10.0  # default largest MD step between a survey path's points along its arcs
OVERLAP = 30.0  # the case's length unit: a branch's point this far along it must be off its parent
ON_PARENT = 0.01  # the case's length unit: a point this near a path lies on it (a file's rounding)
MAX_SURVEY_POINTS = 1e6  # a survey path's points at most (a 10 km hole at a 1 cm step)
PATH_KEYS = ("trajectory", "survey")  # a deviated well is given by one of these
TRAJECTORY_ONLY = ("perforations", "radius", "skin", "branches")  # keys of those wells only


@dataclass(frozen=True, eq=False)
class WellPaths:
    """The paths of one deviated well: ``paths[0]`` its main path, then its branches in the
    order the case gives them; ``parents[b]`` the index in ``paths`` of the path that branch
    ``b`` (``paths[b + 1]``) starts on; ``perforations[p]`` the open MD intervals (k, 2) of
    ``paths[p]``, sorted (the whole path where the case gives none); ``keys[p]`` where the case
    gives each path (``wells[2]``, ``wells[2].branches[0]``)."""

    paths: tuple[WellPath, ...]
    parents: tuple[int, ...]
    perforations: tuple[np.ndarray, ...]
    keys: tuple[str, ...]


def is_deviated(well: Mapping[str, Any]) -> bool:
    """The well is given by a trajectory or a survey (not a point or a map path)."""
    return any(key in well for key in PATH_KEYS)


def well_paths(case_file: Path, well: Mapping[str, Any], key: str) -> WellPaths:
    """The paths of the deviated ``well`` (a validated case's ``wells[k]``, given at ``key``) of
    the case ``case_file``, checked (module docstring): one InputError ``"<key>...: message"``
    (the key as the case spells it) for the first problem."""
    name = str(well["name"])
    main = path_of(case_file, well, key, name)
    paths, parents, keys = [main], [], [key]
    for b, branch in enumerate(well.get("branches", [])):
        where = f"{key}.branches[{b}]"
        own = path_of(case_file, branch, where, str(branch.get("name", f"{name}:{b + 1}")))
        given = "trajectory" if "trajectory" in branch else "survey"
        parent, joined = _joined(own, paths, f"{where}.{given}", name)
        paths.append(joined)
        parents.append(parent)
        keys.append(where)
    specs = [well, *well.get("branches", [])]
    perforations = tuple(
        _perforations(spec.get("perforations"), path, where)
        for spec, path, where in zip(specs, paths, keys, strict=True)
    )
    return WellPaths(tuple(paths), tuple(parents), perforations, tuple(keys))


def path_of(case_file: Path, spec: Mapping[str, Any], key: str, name: str) -> WellPath:
    """The path of a well or branch ``spec`` (its ``trajectory`` or ``survey``) at ``key``."""
    if "trajectory" in spec:
        return _trajectory(case_file, spec["trajectory"], f"{key}.trajectory", name)
    return _survey(case_file, spec["survey"], f"{key}.survey", name)


def _trajectory(case_file: Path, spec: Any, key: str, name: str) -> WellPath:
    from ..wells.path import WellPath

    if isinstance(spec, str):
        spec = {"file": spec}
    else:
        key = f"{key}.file"
    file = named_file(case_file, spec["file"])
    if not file.is_file():
        _missing(key, spec["file"], file)
    columns = tuple(sorted((spec.get("columns") or {}).items()))
    stat = file.stat()
    try:
        path = _read_trajectory(file, stat.st_mtime_ns, stat.st_size, spec.get("format", "auto"), columns)
    except InputError as exc:
        raise InputError(f"{key}: {exc}") from None
    return WellPath(path.xyz, path.md, name)


@functools.lru_cache(maxsize=64)
def _read_trajectory(
    file: Path, mtime_ns: int, size: int, fmt: str, columns: tuple[tuple[str, str], ...]
) -> WellPath:
    from ..io.well_paths import read_well_path  # deferred: the workflow's parse imports config only

    return read_well_path(file, format=fmt, columns=dict(columns) or None)


def _survey(case_file: Path, spec: Mapping[str, Any], key: str, name: str) -> WellPath:
    from ..wells.survey import minimum_curvature

    if "file" in spec:
        file = named_file(case_file, spec["file"])
        if not file.is_file():
            _missing(f"{key}.file", spec["file"], file)
        stat = file.stat()
        try:
            stations = _read_stations(file, stat.st_mtime_ns, stat.st_size)
        except InputError as exc:
            raise InputError(f"{key}.file: {exc}") from None
        where = f"{key}.file"
    else:
        stations = np.asarray(spec["stations"], dtype=np.float64)
        _check_stations(stations, f"{key}.stations")
        where = f"{key}.stations"
    step = float(spec.get("step", SURVEY_STEP))
    points = float(np.ceil(np.diff(stations[:, 0]) / step).sum()) + 1.0
    if not points <= MAX_SURVEY_POINTS:
        md = stations[[0, -1], 0]
        raise InputError(
            f"{key}.step: {yaml_number(step)} makes {points:.3g} points along MD {yaml_number(md[0])} to "
            f"{yaml_number(md[1])} (at most {MAX_SURVEY_POINTS:.0e}); give a larger step"
        )
    try:
        return minimum_curvature(spec["head"], stations, name=name, step=step, source=where)
    except InputError as exc:
        text = str(exc)
        raise InputError(text if text.startswith(where) else f"{where}: {text}") from None


@functools.lru_cache(maxsize=64)
def _read_stations(file: Path, mtime_ns: int, size: int) -> np.ndarray:
    from ..io.survey_stations import read_survey_stations

    stations = read_survey_stations(file)
    stations.flags.writeable = False  # shared by every caller of the cache
    return stations


def _check_stations(stations: np.ndarray, key: str) -> None:
    """MD increasing and inclination in [0, 180] degrees, the first problem naming its station
    and column (``stations[3][0]``)."""
    from ..wells.survey import station_problem

    problem = station_problem(stations)
    if problem is not None:
        station, column, message = problem
        raise InputError(f"{key}[{station}][{column}]: {message}")


def _missing(key: str, given: str, looked: Path) -> NoReturn:
    raise InputError(f"{key}: file '{given}' not found (looked for {looked})")


def _joined(branch: WellPath, paths: Sequence[WellPath], key: str, well: str) -> tuple[int, WellPath]:
    """The path ``branch`` starts on (its index in ``paths``: the nearest to its first point)
    and the branch with its MD continuing that path's (module docstring)."""
    from ..wells.path import WellPath

    found = [closest_md(p, branch.xyz[0]) for p in paths]
    parent = int(np.argmin([distance for _, distance in found]))
    md, distance = found[parent]
    where = key
    at = ", ".join(yaml_number(v) for v in branch.xyz[0])
    if distance > BRANCH_TOLERANCE:
        raise InputError(
            f"{where}: branch '{branch.name}' starts at ({at}), {distance:.6g} from the nearest path of "
            f"well '{well}' (its main path or an earlier branch); a branch starts on its parent's path "
            f"(within {yaml_number(BRANCH_TOLERANCE)} in the case's length unit)"
        )
    if branch.length >= OVERLAP:  # a tangent sidetrack is metres off its parent by then
        _, off = closest_md(paths[parent], branch.at([branch.md[0] + OVERLAP])[0])
        if off <= ON_PARENT:
            raise InputError(
                f"{where}: branch '{branch.name}' runs along the path of its parent from its start at ({at}) "
                f"for {yaml_number(OVERLAP)} or more: give the branch's own hole only, from where it leaves "
                "its parent (its cells would be completed twice)"
            )
    if branch.md[0] == 0.0 and md != 0.0:  # no MD in the file: it counts on from the parent's
        return parent, WellPath(branch.xyz, branch.md + md, branch.name)
    if abs(branch.md[0] - md) > BRANCH_TOLERANCE:
        raise InputError(
            f"{where}: branch '{branch.name}' starts at MD {yaml_number(branch.md[0])}, but its parent's "
            f"path is at MD {md:.10g} there; give MD that continues the parent's (within "
            f"{yaml_number(BRANCH_TOLERANCE)}), or none"
        )
    return parent, branch


def closest_md(path: WellPath, point: np.ndarray) -> tuple[float, float]:
    """The MD of the point of ``path`` nearest ``point`` (3,), and its distance (linear along
    each straight segment; the first of equally near points)."""
    a, b = path.segments
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    near = a + t[:, None] * ab
    d = np.linalg.norm(near - point, axis=1)
    s = int(np.argmin(d))
    return float(path.md[s] + t[s] * (path.md[s + 1] - path.md[s])), float(d[s])


def _perforations(given: Sequence[Sequence[float]] | None, path: WellPath, key: str) -> np.ndarray:
    """The open intervals (k, 2) of ``path``, sorted by MD: ``given`` checked, else the whole path."""
    lo, hi = float(path.md[0]), float(path.md[-1])
    if not given:
        return np.array([[lo, hi]])
    for i, (a, b) in enumerate(given):
        if not a < b:
            raise InputError(
                f"{key}.perforations[{i}]: MD interval [{yaml_number(a)}, {yaml_number(b)}]: "
                f"{yaml_number(a)} is not below {yaml_number(b)}; give [from, to] with from < to"
            )
        if a < lo or b > hi:
            raise InputError(
                f"{key}.perforations[{i}]: MD interval [{yaml_number(a)}, {yaml_number(b)}] reaches "
                f"beyond the path of '{path.name}' (MD {lo:.10g} to {hi:.10g})"
            )

    def shown(i: int) -> str:
        return f"[{yaml_number(given[i][0])}, {yaml_number(given[i][1])}]"

    order = sorted(range(len(given)), key=lambda i: (given[i][0], given[i][1]))
    for a, b in itertools.pairwise(order):
        if given[b][0] < given[a][1]:
            first, second = sorted((a, b))
            raise InputError(
                f"{key}.perforations[{second}]: MD interval {shown(second)} overlaps "
                f"perforations[{first}] {shown(first)}; give each MD once"
            )
    return np.array([given[i] for i in order], dtype=np.float64)


def deviated_wells_problem(data: dict[str, Any], path: Path) -> str | None:
    """The first problem of the case's trajectory and survey wells (``"key: message"``), or
    None: keys that go with other wells, a 2-D grid, files, surveys, branches, perforations."""
    griddim3 = _is_3d(data["grid"])
    for k, well in enumerate(data.get("wells", [])):
        key, name = f"wells[{k}]", well["name"]
        if not is_deviated(well):
            wrong = next((w for w in TRAJECTORY_ONLY if w in well), None)
            if wrong is not None:
                kind = "a vertical well at a point" if "point" in well else "a map path"
                return (
                    f"{key}.{wrong}: well '{name}' is {kind}; {', '.join(TRAJECTORY_ONLY)} go with a "
                    "trajectory or survey well"
                )
            continue
        given = next(w for w in PATH_KEYS if w in well)
        if "rings" in well:
            return f"{key}.rings: rings go with a vertical well at a point; well '{name}' is a {given} well"
        if not griddim3:
            return f"{key}.{given}: well '{name}': a 2-D grid has no depth (give the grid a third axis)"
        try:
            well_paths(path, well, key)
        except InputError as exc:
            return str(exc)
    return None


def _is_3d(grid: Mapping[str, Any]) -> bool:
    if grid["type"] == "cartesian":
        return len(grid["dims"]) == 3
    if grid["type"] == "tensor":
        return "z" in grid
    return True
