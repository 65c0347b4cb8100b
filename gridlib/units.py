"""ECLIPSE unit systems (METRIC, FIELD, LAB, PVT-M) and their SI values.

Each unit is given by its value in SI units, with the constants OPM Flow uses, so that
quantities computed in SI and converted here agree with the simulator's to rounding:
1 ft = 0.3048 m, 1 stb = 0.158987294928 m3, 1 psi = 0.45359237 * 9.80665 / 0.0254**2 Pa,
1 atm = 101325 Pa, 1 bar = 1e5 Pa, 1 cP = 1e-3 Pa s, 1 day = 86400 s, 1 mD =
9.869232667160130e-16 m2. Permeabilities are in millidarcy in every system.

A transmissibility T (SI: m3) gives a flux q = T (1 / viscosity) (pressure difference);
in deck units METRIC cP m3 / (day bar), FIELD cP rb / (day psi), LAB cP cm3 / (h atm),
PVT-M cP m3 / (day atm). Converting K A / d from (mD, deck lengths) to deck units is a
multiplication by the "Darcy constant" (METRIC 0.0085270170, FIELD 0.0011271161, LAB 3.6,
PVT-M 0.00864; ECLIPSE's manual rounds them to 0.008527 and 0.001127).

>>> round(METRIC.darcy_constant, 10), round(FIELD.darcy_constant, 10), round(LAB.darcy_constant, 10)
(0.008527017, 0.0011271161, 3.6)
"""

from __future__ import annotations

from dataclasses import dataclass

from .errors import InputError

FOOT = 0.3048  # m
STB = 0.158987294928  # m3 (reservoir and stock-tank barrel alike)
PSI = 0.45359237 * 9.80665 / 0.0254**2  # Pa
ATM = 101325.0  # Pa
BAR = 1.0e5  # Pa
CENTIPOISE = 1.0e-3  # Pa s
DAY = 86400.0  # s
HOUR = 3600.0  # s
MILLIDARCY = 9.869232667160130e-16  # m2


@dataclass(frozen=True)
class UnitSystem:
    """An ECLIPSE unit system: SI values of its units and the names of the derived ones."""

    name: str
    length: float  # m
    volume: float  # m3 (reservoir volumes: pore volumes)
    pressure: float  # Pa
    time: float  # s
    transmissibility_label: str
    well_index_label: str

    @property
    def transmissibility(self) -> float:
        """One transmissibility unit in SI (m3): cP x volume / (time x pressure)."""
        return CENTIPOISE * self.volume / (self.time * self.pressure)

    @property
    def darcy_constant(self) -> float:
        """K A / d in mD and deck lengths times this is the transmissibility in deck units."""
        return MILLIDARCY * self.length / self.transmissibility


METRIC = UnitSystem("METRIC", 1.0, 1.0, BAR, DAY, "cP m3/(day bar)", "cP m3/(day bar)")
FIELD = UnitSystem("FIELD", FOOT, STB, PSI, DAY, "cP rb/(day psi)", "cP rb/(day psi)")
LAB = UnitSystem("LAB", 0.01, 1.0e-6, ATM, HOUR, "cP cm3/(h atm)", "cP cm3/(h atm)")
PVT_M = UnitSystem("PVT-M", 1.0, 1.0, ATM, DAY, "cP m3/(day atm)", "cP m3/(day atm)")
UNIT_SYSTEMS = {u.name: u for u in (METRIC, FIELD, LAB, PVT_M)}


def unit_system(name: str | None) -> UnitSystem:
    """The unit system of a deck's units keyword (None: ECLIPSE's default, METRIC)."""
    if name is None:
        return METRIC
    try:
        return UNIT_SYSTEMS[name.upper()]
    except KeyError:
        raise InputError(f"unknown unit system {name!r}; expected one of {', '.join(UNIT_SYSTEMS)}") from None
