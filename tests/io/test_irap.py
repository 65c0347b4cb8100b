"""IRAP classic ASCII surfaces (gridlib.io.irap): exact round trip, other writers' layout, bad input
named by file and line."""

from __future__ import annotations

import numpy as np
import pytest

from gridlib import InputError
from gridlib.horizons import Surface
from gridlib.io.irap import IRAP_UNDEFINED, read_irap, write_irap


def irap_surface():
    rng = np.random.default_rng(5)
    z = 1500.0 + rng.standard_normal((7, 9)) * 13.7
    z[0, 0] = z[3, 4] = z[6, 8] = np.nan
    return Surface(z, 456_789.123, 6_789_012.0625, 12.5, 25.0 / 3.0, rotation=30.0, name="top")


def test_irap_round_trip_is_exact(tmp_path):
    s = irap_surface()
    path = write_irap(tmp_path / "top.irap", s)
    text = path.read_text()
    assert text.startswith("-996 7 12.5 8.333333333333334\n456789.123 456889.123 6789012.0625 ")
    assert text.count(repr(IRAP_UNDEFINED)) == 3
    t = read_irap(path)
    assert np.array_equal(t.z, s.z, equal_nan=True)  # bit-identical, undefined nodes included
    assert (t.xori, t.yori, t.xinc, t.yinc, t.rotation, t.name) == (
        s.xori,
        s.yori,
        s.xinc,
        s.yinc,
        30.0,
        "top",
    )
    write_irap(tmp_path / "again.irap", t)
    assert (tmp_path / "again.irap").read_bytes() == path.read_bytes()


def test_irap_reads_other_writers_layout(tmp_path):
    f = tmp_path / "rms.irap"
    f.write_text(
        "-996   2   50.000000   25.000000\n 0.000000   100.000000   0.000000   25.000000\n"
        "3   0.000000   0.000000   0.000000\n0  0  0  0  0  0  0\n"
        "1000.000000  9999900.000000  1002.5\n 1003.0 1004.0\n 1005.0\n"
    )
    s = read_irap(f)
    assert s.z.tolist()[0][:1] == [1000.0] and np.isnan(s.z[0, 1])
    assert s.z[1].tolist() == [1003.0, 1004.0, 1005.0]
    assert s.sample(75.0, 25.0).item() == 1004.5
    assert read_irap(f, elevation=True).z[1, 0] == -1003.0


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("-995 2 1 1\n0 1 0 1\n2 0 0 0\n0 0 0 0 0 0 0\n1 2 3 4\n", r"bad\.irap:1: not an IRAP classic"),
        (
            "-996 2 1 1\n0 1 0 1\n2 0 0 0\n0 0 0 0 0 0 0\n1 2 3\n",
            r"2 x 2 nodes needs 4 values, the file has 3",
        ),
        ("-996 2 1 1\n0 1 0 1\n2 0 0 0\n0 0 0 0 0 0 0\n1 2\n3 x\n", r"bad\.irap:6: 'x' is not a number"),
        ("-996 2 0 1\n0 1 0 1\n2 0 0 0\n0 0 0 0 0 0 0\n1 2 3 4\n", r"bad\.irap:1: IRAP header: xinc must be"),
        ("-996 2 1 1\n0 1 0 1\n", r"the header needs 19 numbers"),
    ],
)
def test_irap_bad_input_names_the_file_and_line(tmp_path, text, message):
    f = tmp_path / "bad.irap"
    f.write_text(text)
    with pytest.raises(InputError, match=message):
        read_irap(f)
