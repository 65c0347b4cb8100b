"""A variant's responses (gridlib.io.flow_responses) from a summary built by hand: the values
the docs define, NaN written as null and read back, units in the run's system, a damaged
responses.json one InputError naming it. (The workflow test compares them with Flow's own
files: tests/workflow/test_study_simulation.py.)"""

from __future__ import annotations

import math

import numpy as np
import pytest

from gridlib.errors import InputError
from gridlib.io.flow_responses import (
    breakthrough_day,
    failed_responses,
    flow_responses,
    read_responses,
    write_responses,
)
from gridlib.io.flow_results import FlowSummary
from gridlib.units import FIELD, METRIC

TIME = np.array([1.0, 4.0, 30.0, 100.0, 150.0, 200.0])
REPORT = np.array([3, 5])  # report steps end at days 100 and 200


def _summary() -> FlowSummary:
    f32 = np.float32
    values = {
        ("FOPT", ""): np.array([10, 40, 300, 900, 1200, 1500], dtype=f32).astype(float),
        ("FOIP", ""): np.array([9990, 9960, 9700, 9100, 8800, 8500], dtype=f32).astype(float),
        ("FWPT", ""): np.array([0, 0, 0, 5, 50, 120], dtype=f32).astype(float),
        ("FWIT", ""): np.array([20, 80, 600, 2000, 3000, 4000], dtype=f32).astype(float),
        ("FPR", ""): np.array([200, 199, 198, 197, 196.5, 196.25], dtype=f32).astype(float),
        ("FOPR", ""): np.full(6, 10.0),
        ("FWPR", ""): np.full(6, 1.0),
        ("FWCT", ""): np.full(6, 0.1),
        ("WOPT", "P"): np.array([10, 40, 300, 900, 1200, 1500], dtype=f32).astype(float),
        ("WWPT", "P"): np.array([0, 0, 0, 5, 50, 120], dtype=f32).astype(float),
        ("WBHP", "P"): np.array([150, 150, 150, 150, 150, 149.5], dtype=f32).astype(float),
        ("WWCT", "P"): np.array([0.0, 0.001, 0.01, 0.0101, 0.2, 0.3]),  # exceeds 0.01 at day 100
        ("WOPR", "P"): np.full(6, 10.0),
        ("WWIT", "P"): np.zeros(6),
        ("WOPT", "I"): np.zeros(6),
        ("WWPT", "I"): np.zeros(6),
        ("WBHP", "I"): np.full(6, 250.0),
        ("WWCT", "I"): np.zeros(6),
        ("WOPR", "I"): np.zeros(6),
        ("WWIT", "I"): np.array([20, 80, 600, 2000, 3000, 4000], dtype=float),
    }
    return FlowSummary(TIME, REPORT, values)


def test_responses_as_the_docs_define_them():
    r = flow_responses(_summary(), METRIC, times=[100.0, 150.0], water_cut=0.01)
    assert r.status == "ok" and r.unit_system == "METRIC"
    assert r.scalars["FOPT"] == 1500 and r.scalars["FWIT"] == 4000 and r.scalars["FPR"] == 196.25
    assert r.scalars["FOIP0"] == 10000  # FOIP + FOPT after the first time step
    assert r.scalars["oil_recovery"] == 1500 / 10000
    assert r.scalars["FOPT@100"] == 900 and r.scalars["oil_recovery@100"] == 900 / 10000
    assert math.isnan(r.scalars["FOPT@150"])  # day 150 ends a time step, not a report step
    assert r.scalars["WBT:P"] == 100.0  # 0.01 is not above 0.01: the next step, not interpolated
    assert "WBT:I" not in r.scalars  # an injector has no breakthrough
    assert r.scalars["WBHP:P"] == 149.5 and r.scalars["WOPT:I"] == 0
    assert r.series["time"] == [100.0, 200.0] and r.series["FOPT"] == [900.0, 1500.0]
    assert r.series["WBHP:P"] == [150.0, 149.5]
    assert r.units["FOPT"] == "sm3" and r.units["FPR@100"] == "bar" and r.units["WBT:P"] == "day"
    assert r.units["FOPR"] == "sm3/day" and r.units["WWCT:P"] == "1" and r.units["oil_recovery"] == "1"
    field = flow_responses(_summary(), FIELD)
    assert field.units["FOPT"] == "stb" and field.units["FPR"] == "psia" and field.unit_system == "FIELD"


def test_breakthrough_is_the_first_time_above_the_threshold_or_nan():
    assert breakthrough_day(TIME, np.array([0, 0, 0.02, 0.5, 0, 0]), 0.01) == 30.0
    assert math.isnan(breakthrough_day(TIME, np.full(6, 0.01), 0.01))


def test_responses_json_reads_back_bit_for_bit_with_nan_as_null(tmp_path):
    r = flow_responses(_summary(), METRIC, times=[150.0])
    path = tmp_path / "responses.json"
    write_responses(path, r)
    assert '"FOPT@150": null' in path.read_text()
    back = read_responses(path)
    assert back.scalars.keys() == r.scalars.keys() and back.series == r.series and back.units == r.units
    assert all(
        a == b or (math.isnan(a) and math.isnan(b))
        for a, b in zip(back.scalars.values(), r.scalars.values(), strict=True)
    )
    failed = failed_responses("OPM Flow ended with status 1:\n  Error: no", METRIC, "simulation/X.PRT")
    write_responses(path, failed)
    back = read_responses(path)
    assert (back.status, back.reason, back.messages) == (
        "failed",
        "OPM Flow ended with status 1: Error: no",
        "simulation/X.PRT",
    )
    assert back.scalars == {} and back.series == {}


def test_a_damaged_responses_file_is_one_error_naming_it(tmp_path):
    path = tmp_path / "responses.json"
    path.write_text('{"status": "ok"')
    with pytest.raises(InputError, match=rf"^{path}: damaged or incomplete \(not JSON"):
        read_responses(path)
    path.write_text('{"status": "maybe"}')
    with pytest.raises(InputError, match="not a variant's responses"):
        read_responses(path)
