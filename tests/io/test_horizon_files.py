"""Points files of horizon picks (gridlib.io.horizon_files.read_points): CSV and whitespace
columns, errors named by file and line."""

from __future__ import annotations

import pytest

from gridlib import InputError
from gridlib.io.horizon_files import read_points


def test_points_files(tmp_path):
    csv = tmp_path / "top.csv"
    csv.write_text("# picks\nX,Y,Z,well\n0,0,1000,A\n100,0,1010,B\n0,100,1000,C\n")
    pts = read_points(csv, columns=["x", "y", "z"])
    assert pts.tolist() == [[0.0, 0.0, 1000.0], [100.0, 0.0, 1010.0], [0.0, 100.0, 1000.0]]
    txt = tmp_path / "top.xyz"
    txt.write_text("0 0 -1000\n100 0 -1010   # comment\n\n0 100 -999\n5 5 -999.25\n")
    assert read_points(txt, elevation=True, null=-999.0)[:, 2].tolist() == [1000.0, 1010.0, 999.25]


@pytest.mark.parametrize(
    ("text", "kwargs", "message"),
    [
        ("0,0,1000\n1,2\n", {}, r"top\.csv:2: expected 3 columns \(x, y, z\), found 2"),
        ("x,y,z,w\n0,0,1000,1\n", {}, r"top\.csv:1: expected 3 columns \(x, y, z\), found 4; pass columns="),
        ("0,0,1000\n1,2,abc\n", {}, r"top\.csv:2: column 3 \(z\): 'abc' is not a number"),
        ("1,2,abc\n0,0,1000\n", {}, r"top\.csv:1: column 3 \(z\): 'abc' is not a number"),  # no header
        ("0,0,1000\n1,2,nan\n", {}, r"top\.csv:2: x, y and z must be finite"),
        ("# nothing\n", {}, r"top\.csv: no data lines"),
        ("x,y,z\n0,0,1\n", {"columns": ["x", "y", "depth"]}, r"top\.csv: no column 'depth' in the header"),
    ],
)
def test_points_file_errors_name_the_file_and_line(tmp_path, text, kwargs, message):
    f = tmp_path / "top.csv"
    f.write_text(text)
    with pytest.raises(InputError, match=message):
        read_points(f, **kwargs)
