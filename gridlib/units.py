"""ECLIPSE unit systems (METRIC, FIELD, LAB, PVT-M): one :class:`UnitSystem` object each.

A unit system is passed between functions as the object; its ``name`` is written only
where it goes into a file (a netCDF attribute, a deck's units keyword) and read back,
through :func:`unit_system`, only where it comes out of one, or where a user names it
(the ``units`` argument of the public functions takes an object or its name).

Each unit is given by its value in SI units, with the constants OPM Flow uses, so that
quantities computed in SI and converted here agree with the simulator's to rounding:
1 ft = 0.3048 m, 1 stb = 0.158987294928 m3, 1 lb = 0.45359237 kg, 1 psi = 0.45359237 *
9.80665 / 0.0254**2 Pa, 1 atm = 101325 Pa, 1 bar = 1e5 Pa, 1 cP = 1e-3 Pa s, 1 day = 86400
s, 1 mD = 9.869232667160130e-16 m2. Permeabilities are in millidarcy and viscosities in
centipoise in every system.

A transmissibility T (SI: m3) gives a flux q = T (1 / viscosity) (pressure difference);
in deck units METRIC cP m3 / (day bar), FIELD cP rb / (day psi), LAB cP cm3 / (h atm),
PVT-M cP m3 / (day atm). Converting K A / d from (mD, deck lengths) to deck units is a
multiplication by the "Darcy constant" (METRIC 0.0085270170, FIELD 0.0011271161, LAB 3.6,
PVT-M 0.00864; ECLIPSE's manual rounds them to 0.008527 and 0.001127).

>>> round(METRIC.darcy_constant, 10), round(FIELD.darcy_constant, 10), round(LAB.darcy_constant, 10)
(0.008527017, 0.0011271161, 3.6)
>>> FIELD.reservoir_volume_label, round(FIELD.volume_per_cubic_length, 6)  # 1 ft3 in rb
('rb', 0.178108)
>>> round(FIELD.pressure_from_metric, 6)  # psi per bar
14.503774
"""

from __future__ import annotations

from dataclasses import dataclass

from .errors import InputError

FOOT = 0.3048  # m
STB = 0.158987294928  # m3 (reservoir and stock-tank barrel alike)
POUND = 0.45359237  # kg
PSI = POUND * 9.80665 / 0.0254**2  # Pa
ATM = 101325.0  # Pa
BAR = 1.0e5  # Pa
CENTIPOISE = 1.0e-3  # Pa s
DAY = 86400.0  # s
HOUR = 3600.0  # s
MILLIDARCY = 9.869232667160130e-16  # m2


# What a written value measures (its unit follows from the unit system, :meth:`UnitSystem.unit`):
# cell_measure and face_measure are a cell's volume and a face's area in 3-D, a cell's area and
# a face's length in 2-D; porv is a pore volume at reservoir conditions (Flow's rm3, rb, rcc);
# fraction (porosity, net-to-gross) and dimensionless (ratios, factors) are CF's units "1";
# rate is a surface rate, angle is in degrees in every system.
QUANTITIES = (
    "length",
    "area",
    "volume",
    "cell_measure",
    "face_measure",
    "porv",
    "pressure",
    "permeability",
    "transmissibility",
    "fraction",
    "dimensionless",
    "angle",
    "time",
    "rate",
)


@dataclass(frozen=True)
class UnitSystem:
    """An ECLIPSE unit system: the SI values of its units, the factors that convert into it,
    and the label of every quantity gridlib writes in it.

    ``volume`` is the unit of reservoir volumes (pore volumes) and of surface volumes
    alike (rm3 and sm3, rb and stb, rcc and scc): they differ in conditions, not size.
    """

    name: str  # the deck's units keyword
    length: float  # m
    volume: float  # m3
    pressure: float  # Pa
    time: float  # s
    mass: float  # kg
    length_label: str
    reservoir_volume_label: str  # pore volumes
    surface_volume_label: str
    rate_label: str  # surface rates
    pressure_label: str
    density_label: str
    transmissibility_label: str  # transmissibilities and well connection factors
    permeability_label: str = "mD"
    viscosity_label: str = "cP"
    time_label: str = "day"

    def unit(self, quantity: str, griddim: int = 3) -> str:
        """The label of a :data:`QUANTITIES` member in this system, as gridlib writes it into
        netCDF ``units`` attributes, table headers and axis labels; ``griddim`` sets what a
        cell and a face measure (3: volume and area; 2: area and length).

        >>> FIELD.unit("cell_measure"), FIELD.unit("face_measure", griddim=2), FIELD.unit("porv")
        ('ft3', 'ft', 'rb')
        """
        length = self.length_label
        measure = {"cell_measure": griddim, "face_measure": griddim - 1}
        labels = {
            "length": length,
            "area": f"{length}2",
            "volume": f"{length}3",
            "porv": self.reservoir_volume_label,
            "pressure": self.pressure_label,
            "permeability": self.permeability_label,
            "transmissibility": self.transmissibility_label,
            "fraction": "1",
            "dimensionless": "1",
            "angle": "degree",
            "time": self.time_label,
            "rate": self.rate_label,
        }
        if quantity in measure:
            power = measure[quantity]
            return length if power == 1 else f"{length}{power}"
        if quantity not in labels:
            raise ValueError(f"unknown quantity {quantity!r}; expected one of {', '.join(QUANTITIES)}")
        return labels[quantity]

    @property
    def transmissibility(self) -> float:
        """One transmissibility unit in SI (m3): cP x volume / (time x pressure)."""
        return CENTIPOISE * self.volume / (self.time * self.pressure)

    @property
    def darcy_constant(self) -> float:
        """K A / d in mD and deck lengths times this is the transmissibility in deck units."""
        return MILLIDARCY * self.length / self.transmissibility

    @property
    def volume_per_cubic_length(self) -> float:
        """Reservoir volume units per cubed length unit (METRIC 1, FIELD ft3 -> rb): a pore
        volume from a geometric one."""
        return self.length * self.length * self.length / self.volume

    # METRIC values into this system: multiply a METRIC value by these

    @property
    def pressure_from_metric(self) -> float:
        """bar -> the pressure unit."""
        return BAR / self.pressure

    @property
    def compressibility_from_metric(self) -> float:
        """1/bar -> 1/(the pressure unit)."""
        return self.pressure / BAR

    @property
    def density_from_metric(self) -> float:
        """kg/m3 -> the density unit."""
        return self.length * self.length * self.length / self.mass

    @property
    def length_from_metric(self) -> float:
        """m -> the length unit."""
        return 1.0 / self.length


METRIC = UnitSystem(
    "METRIC",
    length=1.0,
    volume=1.0,
    pressure=BAR,
    time=DAY,
    mass=1.0,
    length_label="m",
    reservoir_volume_label="rm3",
    surface_volume_label="sm3",
    rate_label="sm3/day",
    pressure_label="bar",
    density_label="kg/m3",
    transmissibility_label="cP m3/(day bar)",
)
FIELD = UnitSystem(
    "FIELD",
    length=FOOT,
    volume=STB,
    pressure=PSI,
    time=DAY,
    mass=POUND,
    length_label="ft",
    reservoir_volume_label="rb",
    surface_volume_label="stb",
    rate_label="stb/day",
    pressure_label="psia",
    density_label="lb/ft3",
    transmissibility_label="cP rb/(day psi)",
)
LAB = UnitSystem(
    "LAB",
    length=0.01,
    volume=1.0e-6,
    pressure=ATM,
    time=HOUR,
    mass=1.0e-3,
    length_label="cm",
    reservoir_volume_label="rcc",
    surface_volume_label="scc",
    rate_label="scc/h",
    pressure_label="atm",
    density_label="g/cm3",
    transmissibility_label="cP cm3/(h atm)",
    time_label="h",
)
PVT_M = UnitSystem(
    "PVT-M",
    length=1.0,
    volume=1.0,
    pressure=ATM,
    time=DAY,
    mass=1.0,
    length_label="m",
    reservoir_volume_label="rm3",
    surface_volume_label="sm3",
    rate_label="sm3/day",
    pressure_label="atm",
    density_label="kg/m3",
    transmissibility_label="cP m3/(day atm)",
)
UNIT_SYSTEMS = {u.name: u for u in (METRIC, FIELD, LAB, PVT_M)}


def unit_system(name: UnitSystem | str | None) -> UnitSystem:
    """The unit system ``name`` names: a deck's units keyword, a netCDF file's ``unit_system``
    attribute, a user's argument (None: ECLIPSE's default, METRIC; a UnitSystem: itself).

    >>> unit_system("field") is FIELD, unit_system(None) is METRIC, unit_system(LAB) is LAB
    (True, True, True)
    """
    if name is None:
        return METRIC
    if isinstance(name, UnitSystem):
        return name
    try:
        return UNIT_SYSTEMS[name.upper()]
    except KeyError:
        raise InputError(f"unknown unit system {name!r}; expected one of {', '.join(UNIT_SYSTEMS)}") from None
