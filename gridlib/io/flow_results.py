"""What OPM Flow wrote: summary vectors (SMSPEC/UNSMRY), the FIP report of the PRT file, and
cell states of the restart file (UNRST), read with resfo.

* :func:`read_summary`: every summary vector at every time step (``time``, days) and the
  report steps (``report``: the last time step of each); values are float32 in the file;
* :func:`read_fip_report`: the field's "Originally in place" and "Currently in place"
  lines of the PRT file's last FIP report (surface volumes, integers as Flow prints them);
* :func:`restart_steps`: every report step of the restart file (UNRST) with its time, unit
  system and solution arrays (PRESSURE, SWAT, SGAS, RS, ... as Flow wrote them), per active
  cell in Flow's order (ascending linear index), one step at a time; :func:`active_positions`
  puts them on the cells of a grid through ``cell_flow_index``.

Units: those of the deck (METRIC: sm3, sm3/day, bar; FIELD: stb, stb/day, psia).
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import resfo

from ..errors import InputError

__all__ = [
    "FlowSummary",
    "RestartStep",
    "active_positions",
    "read_fip_report",
    "read_summary",
    "restart_steps",
]


def _keywords(path: Path) -> list[tuple[str, object]]:
    if not path.is_file():
        raise InputError(f"{path}: not found (did OPM Flow run?)")
    try:
        return [(kw.strip(), value) for kw, value in resfo.read(path)]
    except Exception as exc:  # resfo's errors: a truncated or foreign file
        raise InputError(f"{path}: not readable as an ECLIPSE binary file ({exc})") from None


def _text(values) -> list[str]:
    return [(v.decode() if isinstance(v, bytes) else str(v)).strip() for v in np.asarray(values).tolist()]


@dataclass(frozen=True, eq=False)
class FlowSummary:
    """Summary vectors of a run: ``time`` (days, per time step), ``report`` (index of the last
    time step of every report step), ``units`` per vector and ``values``: (keyword, name)
    -> float64 array over the time steps; name is the well for W vectors, "" for F vectors."""

    time: np.ndarray
    report: np.ndarray
    values: dict[tuple[str, str], np.ndarray] = field(default_factory=dict)
    units: dict[tuple[str, str], str] = field(default_factory=dict)

    def __getitem__(self, key: str | tuple[str, str]) -> np.ndarray:
        k = (key, "") if isinstance(key, str) else key
        if k not in self.values:
            raise KeyError(f"no summary vector {k[0]}{' of ' + k[1] if k[1] else ''}")
        return self.values[k]

    @property
    def wells(self) -> list[str]:
        return sorted({name for kw, name in self.values if kw.startswith("W") and name})


def read_summary(case: str | os.PathLike) -> FlowSummary:
    """The summary of the run whose files are ``case``.SMSPEC and ``case``.UNSMRY."""
    base = Path(case)
    spec = dict(_keywords(base.with_name(base.name + ".SMSPEC")))
    keywords = _text(spec["KEYWORDS"])
    names = _text(spec.get("WGNAMES", spec.get("NAMES", [""] * len(keywords))))
    units = _text(spec.get("UNITS", [""] * len(keywords)))
    rows, report_rows = [], []
    for kw, value in _keywords(base.with_name(base.name + ".UNSMRY")):
        if kw == "SEQHDR" and rows:
            report_rows.append(len(rows) - 1)
        elif kw == "PARAMS":
            rows.append(np.asarray(value, dtype=np.float64))
    if rows:
        report_rows.append(len(rows) - 1)
    table = np.array(rows).reshape(len(rows), len(keywords))
    time = table[:, keywords.index("TIME")] if "TIME" in keywords else np.arange(len(rows), dtype=np.float64)
    values, unit = {}, {}
    for col, (kw, name) in enumerate(zip(keywords, names, strict=True)):
        key = (kw, "" if name.startswith(":+") or not kw.startswith("W") else name)
        values[key] = table[:, col]
        unit[key] = units[col]
    return FlowSummary(time, np.asarray(report_rows, dtype=np.int64), values, unit)


_FIP_LINE = re.compile(r":(Originally|Currently)\s+in place\s*:([^:]*):([^:]*):([^:]*):")
_BALANCE = re.compile(r"Balance\s+at\s+([0-9.eE+-]+)\s+Days")


def read_fip_report(prt: str | os.PathLike) -> dict[str, float | dict[str, float] | None]:
    """The field totals of the last FIP report in Flow's PRT file: {"days": its time,
    "original": {...}, "current": {...}}, each with "oil" (the total of liquid and
    vapour), "water" and "gas" (the total), surface volumes as Flow prints them (rounded
    to integers). Flow 2022.10 prints a report's tables (the field's, then every
    region's) before its "Balance at ... Days" banner, and takes as "Originally in place"
    the state after its first time step, not the initial one."""
    path = Path(prt)
    if not path.is_file():
        raise InputError(f"{path}: not found (did OPM Flow run?)")
    reports: list[dict] = []
    block: dict = {}
    for line in path.read_text(errors="replace").splitlines():
        b = _BALANCE.search(line)
        if b is not None:
            if {"original", "current"} <= set(block):
                reports.append({"days": float(b.group(1)), **block})
            block = {}
            continue
        m = _FIP_LINE.search(line)
        if m is None:
            continue
        oil, gas = m.group(2).split(), m.group(4).split()
        totals = {
            "oil": float(oil[-1]) if oil else 0.0,
            "water": float(m.group(3).split()[0]),
            "gas": float(gas[-1]) if gas else 0.0,
        }
        block.setdefault("original" if m.group(1) == "Originally" else "current", totals)  # the field's
    if {"original", "current"} <= set(block):
        reports.append({"days": None, **block})
    if not reports:
        raise InputError(f"{path}: no FIP report (Originally/Currently in place)")
    return reports[-1]


# INTEHEAD item 3 (index 2): the run's unit system; item 12 (index 11): the number of active cells
RESTART_UNITS = {1: "METRIC", 2: "FIELD", 3: "LAB", 4: "PVT-M"}
_INTEHEAD_UNITS, _INTEHEAD_NACTIVE = 2, 11


@dataclass(frozen=True, eq=False)
class RestartStep:
    """One report step of a restart file: ``step`` (its SEQNUM; 0 is the initial state),
    ``days`` since the start (DOUBHEAD item 1), ``units`` (the unit system of INTEHEAD: METRIC,
    FIELD, LAB or PVT-M) and ``cells``: every array of the step's solution section
    (STARTSOL ... ENDSOL) with one value per active cell, keyword -> float64 array in Flow's
    order of active cells, in file order (PRESSURE, SWAT, SGAS, RS, RV, ... as the run wrote)."""

    step: int
    days: float
    units: str
    cells: dict[str, np.ndarray]


def restart_steps(case: str | os.PathLike) -> Iterator[RestartStep]:
    """The report steps of ``case``.UNRST, one at a time (resfo's lazy reader: one step's
    arrays in memory). A file that is not a unified restart file is an InputError naming it."""
    path = Path(case).with_name(Path(case).name + ".UNRST")
    if not path.is_file():
        raise InputError(f"{path}: not found (did OPM Flow run?)")
    head: dict[str, np.ndarray] = {}
    cells: dict[str, np.ndarray] = {}
    solution = False
    try:
        for entry in resfo.lazy_read(path):
            keyword = entry.read_keyword().strip()
            if keyword in ("SEQNUM", "INTEHEAD", "DOUBHEAD"):
                if keyword == "SEQNUM" and head:
                    yield _restart_step(path, head, cells)
                    head, cells = {}, {}
                head[keyword] = np.asarray(entry.read_array())
            elif keyword in ("STARTSOL", "ENDSOL"):
                solution = keyword == "STARTSOL"
            elif (
                solution and "INTEHEAD" in head and entry.read_length() == head["INTEHEAD"][_INTEHEAD_NACTIVE]
            ):
                values = np.asarray(entry.read_array())
                if values.dtype.kind == "f":
                    cells[keyword] = values.astype(np.float64)
    except resfo.ResfoParsingError as exc:
        raise InputError(f"{path}: not readable as an ECLIPSE binary file ({exc})") from None
    if head:
        yield _restart_step(path, head, cells)


def _restart_step(path: Path, head: dict[str, np.ndarray], cells: dict[str, np.ndarray]) -> RestartStep:
    if not {"SEQNUM", "INTEHEAD", "DOUBHEAD"} <= set(head):
        raise InputError(f"{path}: a report step without SEQNUM, INTEHEAD and DOUBHEAD (not a restart file?)")
    units = RESTART_UNITS.get(int(head["INTEHEAD"][_INTEHEAD_UNITS]), "unknown")
    return RestartStep(int(head["SEQNUM"][0]), float(head["DOUBHEAD"][0]), units, cells)


def active_positions(egrid: str | os.PathLike, flow_index: np.ndarray) -> np.ndarray:
    """Where each grid cell (its 0-based linear Flow cell ``flow_index``) is in Flow's list of
    active cells (the order of INIT and restart arrays), from the EGRID's ACTNUM; raises
    InputError if Flow made one of them inactive."""
    keywords = dict(_keywords(Path(egrid)))
    head = np.asarray(keywords["GRIDHEAD"])
    total = int(head[1]) * int(head[2]) * int(head[3])
    actnum = np.asarray(keywords["ACTNUM"]) > 0 if "ACTNUM" in keywords else np.ones(total, dtype=bool)
    index = np.asarray(flow_index, dtype=np.int64)
    if index.size and (index.max() >= total or not actnum[index].all()):
        raise InputError(f"{egrid}: some cells of the grid are not active in Flow's grid")
    return np.cumsum(actnum)[index] - 1
