"""Fluid presets of the decks gridlib writes for OPM Flow (``simulation.fluid`` of a case).

Two presets, good enough for a first look at a grid (does it run, where does the water
go, what do the wells see), not for a field study. Their tables are given here in
METRIC units (bar, m3, kg/m3, cP; volumes at surface conditions sm3, at reservoir
conditions rm3) and converted exactly to FIELD units (psia, stb/rb, lb/ft3) for decks in
FIELD units, with OPM's constants (the ``*_from_metric`` factors of :mod:`gridlib.units`).

``oil-water`` (phases OIL and WATER: a dead oil and water, no gas)

* **SWOF**: Corey curves, connate water Swc = 0.2, residual oil Sorw = 0.2, exponents
  2 and 2: krw = 0.4 x^2, kro = 0.9 (1 - x)^2 with x = (Sw - Swc) / (1 - Swc - Sorw),
  krw rising linearly from 0.4 to 1.0 between Sw = 0.8 and 1; no capillary pressure
  (a sharp oil-water contact);
* **PVDO**: dead oil of 2.0 cP and Bo = 1.12 rm3/sm3 at 200 bar, Bo falling by 0.008
  and the viscosity rising by 0.05 cP per 50 bar (compressibility about 1.4e-4 /bar),
  tabulated from 50 to 450 bar;
* **PVTW**: water Bw = 1.012 rm3/sm3 at 200 bar, compressibility 4.5e-5 /bar,
  0.45 cP;
* **DENSITY**: oil 850, water 1025 kg/sm3 (the gas value, 1.0, is not used);
* **ROCK**: pore compressibility 5e-5 /bar at 200 bar.

``water`` (phase WATER only: single-phase flow): PVTW, DENSITY and ROCK as above.

>>> from gridlib.units import FIELD, METRIC
>>> tables = deck_tables("oil-water", METRIC)
>>> tables["PVTW"]
[[200.0, 1.012, 4.5e-05, 0.45, 0.0]]
>>> round(deck_tables("water", FIELD)["ROCK"][0][0], 6)  # 200 bar in psia
2900.754755
"""

from __future__ import annotations

from .errors import InputError
from .units import BAR, FIELD, METRIC, UnitSystem

FLUIDS = ("oil-water", "water")
PRESET_UNIT_SYSTEMS = (METRIC, FIELD)  # the systems the presets are given in

# METRIC tables (see the module docstring)
_SWC, _SORW = 0.2, 0.2
_SW = [0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5, 0.55, 0.6, 0.65, 0.7, 0.75, 0.8, 1.0]


def _swof() -> list[list[float]]:
    rows = []
    span = 1.0 - _SWC - _SORW
    for sw in _SW:
        x = min((sw - _SWC) / span, 1.0)
        krw = 0.4 * x * x if sw <= 1.0 - _SORW else 0.4 + 0.6 * (sw - (1.0 - _SORW)) / _SORW
        kro = 0.9 * (1.0 - x) * (1.0 - x)
        rows.append([sw, round(krw, 6), round(kro, 6), 0.0])
    return rows


_PVDO = [[50.0 * k, round(1.144 - 0.008 * (k - 1), 4), round(1.85 + 0.05 * (k - 1), 4)] for k in range(1, 10)]
_PVTW = [[200.0, 1.012, 4.5e-5, 0.45, 0.0]]
_DENSITY = [[850.0, 1025.0, 1.0]]
_ROCK = [[200.0, 5.0e-5]]


def check_preset_units(units: UnitSystem) -> None:
    """An InputError unless the presets are given in ``units`` (METRIC or FIELD; decks in
    LAB or PVT-M units are not supported)."""
    if units not in PRESET_UNIT_SYSTEMS:
        raise InputError(f"unit system {units.name}: the fluid presets are given for METRIC and FIELD decks")


def deck_tables(fluid: str, units: UnitSystem = METRIC) -> dict[str, list[list[float]]]:
    """The PROPS tables of preset ``fluid`` in ``units``: keyword -> rows (one list per record
    row; SWOF, PVDO are one table each)."""
    if fluid not in FLUIDS:
        raise InputError(f"fluid: expected one of {', '.join(FLUIDS)}, got {fluid!r}")
    check_preset_units(units)

    def p(v: float) -> float:
        return _tidy(v * units.pressure_from_metric)

    def per_p(v: float) -> float:
        return _tidy(v * units.compressibility_from_metric)

    tables: dict[str, list[list[float]]] = {}
    if fluid == "oil-water":
        tables["SWOF"] = _swof()
        tables["PVDO"] = [[p(row[0]), row[1], row[2]] for row in _PVDO]
    tables["PVTW"] = [[p(r[0]), r[1], per_p(r[2]), r[3], r[4]] for r in _PVTW]
    tables["DENSITY"] = [[_tidy(v * units.density_from_metric) for v in _DENSITY[0]]]
    tables["ROCK"] = [[p(_ROCK[0][0]), per_p(_ROCK[0][1])]]
    return tables


def water_gradient(units: UnitSystem = METRIC) -> float:
    """Hydrostatic pressure gradient of the presets' water at surface density, pressure unit
    per length unit (METRIC 0.1005 bar/m)."""
    check_preset_units(units)
    return _DENSITY[0][1] * 9.80665 / BAR * units.pressure_from_metric / units.length_from_metric


def _tidy(value: float) -> float:
    """Ten significant digits: converted tables read like a person wrote them."""
    return float(f"{value:.10g}")
