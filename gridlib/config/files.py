"""Files a case names: where they are, and what a deck or a fault's sticks file gives, read as
cheaply as possible."""

from __future__ import annotations

import functools
import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

if TYPE_CHECKING:
    from ..pillars.fault_surface import FaultSurface


def named_file(case_file: Path, name: str | os.PathLike) -> Path:
    """A file a case names: ``name`` relative to the case file's folder (or absolute), its ``..``
    resolved by the path's text, not by the file system: a study's variant is checked before its
    folder results/<study>/<variant>/ exists, and names its base case's files from there.

    >>> named_file(Path("results/sweep/fine_r0/fine_r0.yaml"), "../../../config/cases/top.csv").as_posix()
    'config/cases/top.csv'
    """
    return Path(os.path.normpath(Path(case_file).parent / name))


def deck_cell_keywords(path: Path, unknown_keywords: str = "error") -> frozenset[str]:
    """The cell keywords (PORO, PERMX, MULTZ, ...) the deck file ``path`` gives; a text deck is
    read with ``unknown_keywords`` (a deck case's ``grid.unknown_keywords``)."""
    p = path.resolve()
    stat = p.stat()
    return _deck_cell_keywords(p, stat.st_mtime_ns, stat.st_size, unknown_keywords)


def case_deck_keywords(case_file: Path, grid: Mapping[str, Any]) -> frozenset[str]:
    """The cell keywords a deck case's grid has: its deck file's (``grid.file``, relative to
    ``case_file``) and those its ``grid.parameters`` give (ROFF files, read by the grid stage)."""
    given = deck_cell_keywords(named_file(case_file, grid["file"]), grid["unknown_keywords"])
    return given | frozenset(grid.get("parameters") or {})


@functools.lru_cache(maxsize=8)
def _deck_cell_keywords(path: Path, mtime_ns: int, size: int, unknown_keywords: str) -> frozenset[str]:
    # Cached per process on the file's identity: every stage and every variant of a study loads
    # the case again. (An INCLUDEd file edited in the same process is not seen: runs are new
    # processes.)
    from ..io.registry import find_format, read  # deferred: the workflow's parse imports config only

    options = {"unknown_keywords": unknown_keywords} if find_format(path, "deck").name == "grdecl" else {}
    return frozenset(read(path, kind="deck", **options).cell_data)


class FaultSticks(NamedTuple):
    """A case's fault given by sticks: its surface and, in plan view, the shallowest point of
    every stick (x, y, m), the polyline the case's checks take for its trace."""

    surface: FaultSurface
    tops: tuple[tuple[float, float], ...]


def fault_sticks(case_file: Path, fault: Mapping[str, Any]) -> FaultSticks:
    """The sticks file a case's fault names (``fault["sticks"]``, relative to ``case_file``), read
    with its ``sticks_format`` and made a surface named after the fault: an InputError naming the
    file, the line and the stick where it cannot be. Cached per process on the file's identity."""
    path = named_file(case_file, fault["sticks"])
    stat = path.stat()
    fmt = fault.get("sticks_format", "auto")
    return _fault_sticks(path, stat.st_mtime_ns, stat.st_size, fmt, fault["name"])


@functools.lru_cache(maxsize=32)
def _fault_sticks(path: Path, mtime_ns: int, size: int, fmt: str, name: str) -> FaultSticks:
    from ..io.fault_sticks import read_fault_sticks  # deferred, as above
    from ..pillars.fault_surface import FaultSurface as Surface

    sticks = read_fault_sticks(path, fmt)
    surface = Surface.from_sticks(sticks, name=name, source=str(path))
    return FaultSticks(surface, tuple((float(s[0, 0]), float(s[0, 1])) for s in sticks))


def pebi_outline(domain: Any) -> Any:
    """A pebi grid's ``domain`` (validated: ``{rectangle: [xmin, ymin, xmax, ymax]}`` or a
    polygon ``[[x, y], ...]``) as a shapely polygon in plan view (m)."""
    import shapely

    return shapely.box(*domain["rectangle"]) if isinstance(domain, dict) else shapely.Polygon(domain)


def fault_plan_trace(case_file: Path, fault: Mapping[str, Any]) -> list[list[float]]:
    """A case's fault in plan view, for the checks that place it against the model's area: its
    ``trace``, or its sticks' shallowest points (:class:`FaultSticks`)."""
    if "trace" in fault:
        return [list(p) for p in fault["trace"]]
    return [list(p) for p in fault_sticks(case_file, fault).tops]
