"""A simulated variant's responses (``results/<study>/<variant>/simulation/responses.json``):
what a study tabulates of one OPM Flow run, computed from its summary (:func:`read_summary`).

Names are ECLIPSE summary keys as ERT and FMU write them, in the run's unit system (METRIC:
sm3, bar, day; FIELD: stb, psia, day). Scalars:

* at the end of the run: ``FOPT``, ``FWPT`` (oil and water produced), ``FWIT`` (water
  injected), ``FPR`` (the field's pore-volume weighted pressure);
* ``FOIP0``: the variant's own initial oil in place. Flow's summary starts at the end of the
  first time step (there is no day-0 row), so it is ``FOIP + FOPT`` there: oil neither enters
  nor changes phase in a dead-oil (oil-water) model, so what was in place at day 0 is what is
  in place after the first step plus what the step produced. Computed in float64 from the
  file's float32 values;
* ``oil_recovery``: ``FOPT / FOIP0`` (fraction; NaN where FOIP0 is 0);
* per well ``W``: ``WOPT:W``, ``WWPT:W`` (cumulative oil and water produced), ``WBHP:W``
  (final bottom-hole pressure); for a producer (a well that injected nothing: WWIT 0)
  ``WBT:W``, its water breakthrough day: the first summary time (the end of a time step of
  Flow's, not interpolated between steps) at which its water cut WWCT exceeds the study's
  threshold (``responses.water_cut``, a fraction of the liquid rate); NaN if it never does;
* at each chosen day ``t`` (a report day; written as an integer where it is one):
  ``FOPT@t``, ``FWPT@t``, ``FPR@t``, ``oil_recovery@t``; NaN where the run has no report step
  at ``t``.

Series (``series``): ``time`` (days) and the field's ``FOPR``, ``FWPR``, ``FWCT``, ``FPR``,
``FOPT``, ``FWPT`` and each well's ``WOPR:W``, ``WWCT:W``, ``WBHP:W`` at the end of every
report step (the summary's report rows: one time axis shared by variants with the same
report days; the file holds every time step).

Values are the summary's float32 numbers as float64, written with ``repr`` (JSON), so they
read back bit for bit; NaN is written as ``null`` and read back as NaN. A failed run has
status ``failed``, Flow's reason (one line), the path of its message file (PRT) and no
scalars or series (the study's table gives them NaN).
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..units import UnitSystem
from .atomic import atomic_path
from .datasets import damaged, read_json_artifact
from .flow_results import FlowSummary

FIELD_AT_END = ("FOPT", "FWPT", "FWIT", "FPR")
FIELD_AT_TIMES = ("FOPT", "FWPT", "FPR", "oil_recovery")
WELL_AT_END = ("WOPT", "WWPT", "WBHP")
FIELD_SERIES = ("FOPR", "FWPR", "FWCT", "FPR", "FOPT", "FWPT")
WELL_SERIES = ("WOPR", "WWCT", "WBHP")
# What each response measures (gridlib.units quantities; "surface_volume": sm3 or stb).
QUANTITIES = {
    "FOPT": "surface_volume",
    "FWPT": "surface_volume",
    "FWIT": "surface_volume",
    "FOIP0": "surface_volume",
    "FPR": "pressure",
    "oil_recovery": "fraction",
    "WOPT": "surface_volume",
    "WWPT": "surface_volume",
    "WBHP": "pressure",
    "WBT": "time",
    "FOPR": "rate",
    "FWPR": "rate",
    "FWCT": "fraction",
    "WOPR": "rate",
    "WWCT": "fraction",
    "time": "time",
}
STATUSES = ("ok", "failed")


def response_quantity(name: str) -> str:
    """What response ``name`` measures: ``WBHP:PROD`` -> pressure, ``FOPT@365`` -> surface_volume."""
    return QUANTITIES[name.split("@", 1)[0].split(":", 1)[0]]


def response_unit(name: str, system: UnitSystem) -> str:
    """The unit of response ``name`` in ``system``: ``FOPT`` -> sm3 (METRIC), stb (FIELD)."""
    quantity = response_quantity(name)
    return system.surface_volume_label if quantity == "surface_volume" else system.unit(quantity)


def day_text(day: float) -> str:
    """A day in a response's name: ``365`` (an integer where it is one), ``182.5``."""
    return str(int(day)) if float(day).is_integer() else repr(float(day))


@dataclass(frozen=True)
class Responses:
    """One variant's responses (the content of responses.json; see the module's docstring):
    ``scalars`` and ``series`` name -> value(s), ``units`` name -> unit, ``messages`` the path
    of Flow's PRT file relative to the variant's folder."""

    status: str
    unit_system: str
    reason: str | None = None
    messages: str | None = None
    units: dict[str, str] = field(default_factory=dict)
    scalars: dict[str, float] = field(default_factory=dict)
    series: dict[str, list[float]] = field(default_factory=dict)

    def as_json(self) -> dict[str, Any]:
        return {
            "status": self.status,
            "reason": self.reason,
            "messages": self.messages,
            "unit_system": self.unit_system,
            "units": self.units,
            "scalars": {k: _json_number(v) for k, v in self.scalars.items()},
            "series": {k: [_json_number(v) for v in vs] for k, vs in self.series.items()},
        }


def _json_number(value: float) -> float | None:
    return None if math.isnan(value) else float(value)


def _at(summary: FlowSummary, day: float) -> int | None:
    """The row of the summary's report step ending at ``day``, or None."""
    rows = summary.report[np.isclose(summary.time[summary.report], day, rtol=0.0, atol=1e-6)]
    return int(rows[0]) if rows.size else None


def _is_injector(summary: FlowSummary, well: str) -> bool:
    injected = summary.values.get(("WWIT", well))
    return injected is not None and bool(injected[-1] > 0)


def breakthrough_day(time: np.ndarray, water_cut: np.ndarray, threshold: float) -> float:
    """The first of ``time`` (days) at which ``water_cut`` exceeds ``threshold`` (no
    interpolation between the summary's time steps); NaN if it never does."""
    above = np.flatnonzero(np.asarray(water_cut) > threshold)
    return float(time[above[0]]) if above.size else math.nan


def initial_oil_in_place(summary: FlowSummary) -> float:
    """The run's initial oil in place (FOIP0 of the module docstring): FOIP + FOPT at the first
    summary time, float64 from the file's float32 values."""
    return float(summary["FOIP"][0]) + float(summary["FOPT"][0])


def flow_responses(
    summary: FlowSummary,
    system: UnitSystem,
    times: Sequence[float] = (),
    water_cut: float = 0.01,
    messages: str | None = None,
) -> Responses:
    """The responses of a run that reached its end (see the module's docstring), in ``system``
    (the deck's unit system); ``times``: the days of the ``@`` responses; ``water_cut``: the
    breakthrough threshold; ``messages``: the PRT file's path to record. A vector the study
    needs that the summary lacks is a KeyError naming it."""
    scalars: dict[str, float] = {k: float(summary[k][-1]) for k in FIELD_AT_END}
    initial = initial_oil_in_place(summary)
    scalars["FOIP0"] = initial

    def recovery(produced: float) -> float:
        return produced / initial if initial > 0 else math.nan

    scalars["oil_recovery"] = recovery(scalars["FOPT"])
    for day in times:
        row = _at(summary, day)
        for k in FIELD_AT_TIMES:
            if row is None:
                value = math.nan
            elif k == "oil_recovery":
                value = recovery(float(summary["FOPT"][row]))
            else:
                value = float(summary[k][row])
            scalars[f"{k}@{day_text(day)}"] = value
    for well in summary.wells:
        for k in WELL_AT_END:
            scalars[f"{k}:{well}"] = float(summary[(k, well)][-1])
        if not _is_injector(summary, well):
            scalars[f"WBT:{well}"] = breakthrough_day(summary.time, summary[("WWCT", well)], water_cut)
    rows = summary.report
    series: dict[str, list[float]] = {"time": summary.time[rows].tolist()}
    series |= {k: summary[k][rows].tolist() for k in FIELD_SERIES}
    for well in summary.wells:
        series |= {f"{k}:{well}": summary[(k, well)][rows].tolist() for k in WELL_SERIES}
    units = {name: response_unit(name, system) for name in [*scalars, *series]}
    return Responses("ok", system.name, None, messages, units, scalars, series)


def failed_responses(reason: str, system: UnitSystem, messages: str | None = None) -> Responses:
    """The responses of a run that failed for ``reason`` (one line): none, status failed."""
    return Responses("failed", system.name, " ".join(reason.split()), messages)


def write_responses(path: str | os.PathLike, responses: Responses) -> None:
    """``responses`` as JSON at ``path``, atomically."""
    text = json.dumps(responses.as_json(), indent=1, allow_nan=False) + "\n"
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")


def read_responses(path: str | os.PathLike) -> Responses:
    """A responses.json read back (null values as NaN); one InputError naming the file where
    it is missing, not JSON or not a variant's responses (:func:`~gridlib.io.datasets.damaged`)."""
    doc = read_json_artifact(path)
    keys = {"status", "reason", "messages", "unit_system", "units", "scalars", "series"}
    if not isinstance(doc, dict) or not keys <= set(doc) or doc["status"] not in STATUSES:
        raise damaged(path, "not a variant's responses (status, reason, messages, units, scalars, series)")
    return Responses(
        status=doc["status"],
        unit_system=doc["unit_system"],
        reason=doc["reason"],
        messages=doc["messages"],
        units=dict(doc["units"]),
        scalars={k: _number(v) for k, v in doc["scalars"].items()},
        series={k: [_number(v) for v in vs] for k, vs in doc["series"].items()},
    )


def _number(value: Any) -> float:
    return math.nan if value is None else float(value)


def response_units(responses: Sequence[Responses]) -> dict[str, Mapping[str, list[str]]]:
    """Each response's units over the variants, each with the unit systems it applies to (as
    :func:`gridlib.io.summary_table.column_units`: one unit where the variants share a system)."""
    out: dict[str, dict[str, list[str]]] = {}
    for r in responses:
        for name, unit in r.units.items():
            systems = out.setdefault(name, {}).setdefault(unit, [])
            if r.unit_system not in systems:
                systems.append(r.unit_system)
    return out
