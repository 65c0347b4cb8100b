"""A case's ``simulation`` section: what its OPM Flow deck simulates, as frozen objects.

Quantities are in the case's unit system (METRIC: bar, m, sm3/day; a FIELD deck's: psia, ft,
stb/day). What the case leaves to the model is None here (the initial datum, pressure and
oil-water contact, a well's radius): the flow-deck stage (:mod:`gridlib.stages.flow_deck`)
derives it from the grid. A case without the section simulates nothing: the schema's
defaults (the oil-water preset), no wells, no report steps.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Literal

from ..config import Case, section_defaults


@dataclass(frozen=True)
class InitialState:
    """``simulation.initial``, the equilibrium (EQUIL), depths positive down; None: the
    model's (pressure hydrostatic, datum the top of the model, contact its base)."""

    pressure: float | None = None
    datum: float | None = None
    owc: float | None = None


@dataclass(frozen=True)
class SimulatedWell:
    """One of ``simulation.wells``: a vertical well of the case's ``wells`` at ``point``, or
    (``point`` None) a well with a trajectory or survey, whose connections (cells, factors,
    directions) are those of ``wells.nc`` and whose radius and skin are the case well's."""

    name: str
    kind: Literal["injector", "producer"]
    point: tuple[float, float] | None  # (x, y) of the case's well; None: a trajectory well
    rate: float | None  # surface rate (water injected, liquid produced), None: bhp controls
    bhp: float | None  # bottom-hole pressure: the control, or the limit of a rate
    radius: float | None  # None: 0.1 m in the case's length unit (vertical wells)
    skin: float
    key: str  # where the case gives it, for messages: "simulation.wells[k]"

    @property
    def has_trajectory(self) -> bool:
        """The well is completed along its path (``wells.nc``), not vertically at a point."""
        return self.point is None


@dataclass(frozen=True)
class CaseSimulation:
    """The ``simulation`` section: fluid preset, initial state, wells and report days."""

    fluid: Literal["oil-water", "water"]
    initial: InitialState
    wells: tuple[SimulatedWell, ...]
    report_days: tuple[float, ...]


def case_simulation(case: Case) -> CaseSimulation:
    """The case's ``simulation`` section (validated by :func:`gridlib.config.load_case`: every
    simulated well is one of the case's wells, at a point or with a trajectory or survey)."""
    spec: dict[str, Any] = case.data["simulation"] if case.has_simulation else section_defaults("simulation")
    initial = spec.get("initial", {})
    points = {w["name"]: w.get("point") for w in case.data.get("wells", [])}
    wells = tuple(
        SimulatedWell(
            name=w["name"],
            kind=w["type"],
            point=_point(points[w["name"]]),
            rate=_optional(w.get("rate")),
            bhp=_optional(w.get("bhp")),
            radius=_optional(w.get("radius")),
            skin=float(w.get("skin", 0.0)),
            key=f"simulation.wells[{k}]",
        )
        for k, w in enumerate(spec.get("wells", []))
    )
    return CaseSimulation(
        fluid=spec["fluid"],
        initial=InitialState(*(_optional(initial.get(k)) for k in ("pressure", "datum", "owc"))),
        wells=wells,
        report_days=tuple(float(d) for d in spec.get("report_days", ())),
    )


def _point(point: Any) -> tuple[float, float] | None:
    return None if point is None else (float(point[0]), float(point[1]))


def _optional(value: Any) -> float | None:
    return None if value is None else float(value)
