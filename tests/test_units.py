"""gridlib.units: one object per ECLIPSE unit system, found by its name where a file names it."""

import pytest

from gridlib.errors import InputError
from gridlib.fluids import deck_tables, water_gradient
from gridlib.units import FIELD, LAB, METRIC, PVT_M, UNIT_SYSTEMS, unit_system


def test_a_name_written_to_a_file_reads_back_as_the_same_object():
    for name, system in UNIT_SYSTEMS.items():
        assert system.name == name
        assert unit_system(name) is system
        assert unit_system(name.lower()) is system  # deck keywords are case-insensitive
        assert unit_system(system) is system
    assert unit_system(None) is METRIC  # ECLIPSE's default
    expected = "unknown unit system 'SI'; expected one of METRIC, FIELD, LAB, PVT-M"
    with pytest.raises(InputError, match=expected):
        unit_system("SI")


def test_darcy_constants_are_eclipses():
    # ECLIPSE technical description: 0.008527 (METRIC), 0.001127 (FIELD), 3.6 (LAB), 0.00864 (PVT-M)
    assert METRIC.darcy_constant == pytest.approx(0.008527, abs=5e-7)
    assert FIELD.darcy_constant == pytest.approx(0.001127, abs=5e-7)
    assert LAB.darcy_constant == pytest.approx(3.6, rel=1e-12)
    assert PVT_M.darcy_constant == pytest.approx(0.00864, rel=1e-12)


def test_field_conversions_are_the_textbook_ones():
    assert FIELD.volume_per_cubic_length == pytest.approx(1.0 / 5.614583333, rel=1e-9)  # 1 bbl = 5.6146 ft3
    assert FIELD.pressure_from_metric == pytest.approx(14.503773773, rel=1e-10)  # psi per bar
    assert FIELD.compressibility_from_metric * FIELD.pressure_from_metric == pytest.approx(1.0, rel=1e-15)
    assert 1000.0 * FIELD.density_from_metric == pytest.approx(62.427961, rel=1e-8)  # water, lb/ft3
    assert FIELD.length_from_metric == pytest.approx(1.0 / 0.3048, rel=1e-15)
    for quantity in ("pressure", "compressibility", "density", "length"):
        assert getattr(METRIC, f"{quantity}_from_metric") == 1.0
    assert METRIC.volume_per_cubic_length == 1.0 and PVT_M.volume_per_cubic_length == 1.0


def test_fluid_presets_in_field_units():
    # 1025 kg/m3 x 9.80665 m/s2 = 10051.8 Pa/m = 0.44437 psi/ft
    assert water_gradient(FIELD) == pytest.approx(1025.0 * 9.80665 * 0.3048 / 6894.757293168361, rel=1e-13)
    assert water_gradient(METRIC) == pytest.approx(1025.0 * 9.80665 / 1e5, rel=1e-15)  # 0.1005 bar/m
    # 1 kg/m3 = 0.0624279606 lb/ft3, to the ten digits the tables keep
    assert deck_tables("water", FIELD)["DENSITY"] == [[53.06376649, 63.98865959, 0.06242796058]]
    for system in (LAB, PVT_M):
        with pytest.raises(InputError, match=f"unit system {system.name}: the fluid presets are given for"):
            deck_tables("water", system)


def test_labels_of_each_system():
    labels = {
        name: (u.reservoir_volume_label, u.rate_label, u.pressure_label, u.transmissibility_label)
        for name, u in UNIT_SYSTEMS.items()
    }
    assert labels == {
        "METRIC": ("rm3", "sm3/day", "bar", "cP m3/(day bar)"),
        "FIELD": ("rb", "stb/day", "psia", "cP rb/(day psi)"),
        "LAB": ("rcc", "scc/h", "atm", "cP cm3/(h atm)"),
        "PVT-M": ("rm3", "sm3/day", "atm", "cP m3/(day atm)"),
    }
    assert {u.permeability_label for u in UNIT_SYSTEMS.values()} == {"mD"}
