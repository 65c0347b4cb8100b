"""Fault stick files (gridlib.io.fault_sticks): both formats give the same sticks and the same
surface; every malformed file is one error naming the file, the line and the stick."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gridlib import io
from gridlib.errors import InputError
from gridlib.io.fault_sticks import fault_surface_from_file, read_fault_sticks

DATA = Path(__file__).parent.parent / "data" / "sticks"
F1 = [
    [(456000.0, 5930000.0, 1600.0), (456150.0, 5930010.0, 1850.0), (456260.0, 5930020.0, 2100.0)],
    [(456100.0, 5930500.0, 1620.0), (456250.0, 5930505.0, 1870.0), (456355.0, 5930512.0, 2110.0)],
    [(456250.0, 5931000.0, 1640.0), (456500.0, 5931010.0, 2080.0)],
    [(456300.0, 5931500.0, 1610.0), (456445.0, 5931498.0, 1850.0), (456560.0, 5931495.0, 2090.0)],
]


@pytest.mark.parametrize(
    ("name", "fmt"),
    [
        ("f1_sticks.xyz", "auto"),
        ("f1_sticks.csv", "xyz_id"),
        ("f1_sticks.pol", "auto"),
        ("f1_sticks.pol", "rms"),
    ],
)
def test_every_format_gives_the_sticks_running_down(name, fmt):
    sticks = read_fault_sticks(DATA / name, fmt)
    assert len(sticks) == 4
    for stick, expected in zip(sticks, F1, strict=True):
        np.testing.assert_array_equal(stick, np.array(expected))


def test_both_formats_give_the_same_surface():
    by_id = fault_surface_from_file(DATA / "f1_sticks.xyz", name="F1")
    rms = fault_surface_from_file(DATA / "f1_sticks.pol", "rms", name="F1")
    np.testing.assert_array_equal(by_id.levels, rms.levels)
    np.testing.assert_array_equal(by_id.points, rms.points)
    # The levels are every stick's depths; each stick passes through its own points.
    assert by_id.levels.tolist() == [1600, 1610, 1620, 1640, 1850, 1870, 2080, 2090, 2100, 2110]
    for k, stick in enumerate(F1):
        for x, y, z in stick:
            np.testing.assert_array_equal(by_id.section(z)[k], [x, y])
    assert by_id.dip_side() == "right" and by_id.source == str(DATA / "f1_sticks.xyz")
    np.testing.assert_array_equal(io.read(DATA / "f1_sticks.pol", kind="sticks", fmt="rms")[1], F1[1])


HEAD = "x y z\n"
GOOD_RMS = "0 0 1000\n10 0 1100\n999.0 999.0 999.0\n0 100 1000\n10 100 1100\n999.0 999.0 999.0\n"


@pytest.mark.parametrize(
    ("text", "fmt", "message"),
    [
        (
            "0 0 1000\n10 0 1100\n999.0 999.0 999.0\n",
            "auto",
            r"s\.pol: a fault needs at least 2 sticks, found 1",
        ),
        ("0 0 1000 1\n10 0 1100 1\n", "auto", "at least 2 sticks, found 1"),
        (GOOD_RMS + "5 200 1000\n999.0 999.0 999.0\n", "auto", r"s\.pol:7: stick 3 has 1 point"),
        (
            GOOD_RMS.replace("10 100 1100", "nan 100 1100"),
            "auto",
            r"s\.pol:5: stick 2: x, y and z must be finite",
        ),
        (
            GOOD_RMS.replace("10 100 1100", "10 100 one"),
            "auto",
            r"s\.pol:5: stick 2: z: 'one' is not a number",
        ),
        (
            GOOD_RMS.replace("10 100 1100", "999 100 1100"),
            "auto",
            r"s\.pol:5: stick 2: 999 in some columns only",
        ),
        (
            GOOD_RMS.replace("10 100 1100", "10 100 1100\n12 100 1050"),
            "rms",
            r"s\.pol:6: stick 2: the depth must change monotonically along a stick \(z=1050 after z=1100",
        ),
        (
            GOOD_RMS.replace("10 100 1100", "10 100 1100 4"),
            "auto",
            r"s\.pol:5: expected 3 columns \(x y z, the rms",
        ),
        (GOOD_RMS, "xyz_id", r"s\.pol:1: expected 4 columns \(x y z id, the xyz_id format\), found 3"),
        ("0 0 1000 1 5\n", "auto", r"s\.pol:1: expected 3 columns .* or 4 .* found 5"),
        (
            "0 0 1000 1\n1 0 1100 1\n0 9 1000 2\n1 9 1100 2\n2 0 1200 1\n",
            "auto",
            r"s\.pol:5: stick id 1 again, after other sticks \(it is stick 1\)",
        ),
        # Sticks 1 and 2 cross between 1000 and 1100 m: the surface's check names file and sticks.
        (
            "0 0 1000\n10 0 1100\n999 999 999\n0 100 1000\n10 -60 1100\n",
            "auto",
            r"fault 'F' \(sticks file .*s\.pol\): sticks 1 and 2 cross",
        ),
        ("# nothing\n", "auto", r"s\.pol: no data lines"),
        (GOOD_RMS, "roff", r"s\.pol: unknown fault stick format 'roff'"),
    ],
)
def test_malformed_files_give_one_error_naming_file_line_and_stick(tmp_path, text, fmt, message):
    path = tmp_path / "s.pol"
    path.write_text(text)
    with pytest.raises(InputError, match=message):
        fault_surface_from_file(path, fmt, name="F")


def test_missing_file():
    with pytest.raises(InputError, match=r"nowhere\.xyz: no such file"):
        read_fault_sticks("nowhere.xyz")
