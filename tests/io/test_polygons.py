"""RMS/xtgeo polygon text (gridlib.io.polygons) against xtgeo 4.27: xtgeo reads ours with equal
coordinates and polygon ids, we read xtgeo's, exact round trip, bad input named."""

from __future__ import annotations

import numpy as np
import pytest
import xtgeo

from gridlib import InputError, io
from gridlib.io.polygons import read_polygons, write_polygons

# xtgeo 4.27's polygon reader calls pandas with inplace=True, which pandas 3.1 deprecates
pytestmark = pytest.mark.filterwarnings("ignore:The inplace keyword:Warning")


def polylines() -> list[np.ndarray]:
    """Three polylines of awkward float64 values (UTM-sized x, y; depths positive down)."""
    rng = np.random.default_rng(3)
    base = np.array([456_789.123456789, 6_789_012.987654321, 1_523.456789])
    return [base + rng.standard_normal((n, 3)) * [100.0, 100.0, 10.0] for n in (4, 1, 7)]


def test_xtgeo_reads_ours_with_equal_values(tmp_path):
    lines = polylines()
    path = write_polygons(tmp_path / "faults.pol", lines)
    p = xtgeo.polygons_from_file(path, fformat="xyz")
    df = p.get_dataframe()
    assert p.zname == "Z_TVDSS"  # xtgeo's name: depth below sea level, positive down
    assert df["POLY_ID"].tolist() == [0] * 4 + [1] + [2] * 7
    np.testing.assert_array_equal(df[["X_UTME", "Y_UTMN", "Z_TVDSS"]].to_numpy(), np.vstack(lines))


def test_we_read_xtgeos_file_equal(tmp_path):
    lines = polylines()
    stacked = np.vstack(lines)
    ids = np.repeat(np.arange(3), [len(a) for a in lines])
    xtgeo.Polygons(np.column_stack([stacked, ids])).to_file(tmp_path / "xt.pol", fformat="xyz")
    back = read_polygons(tmp_path / "xt.pol")
    assert len(back) == 3
    for ours, theirs in zip(back, lines, strict=True):
        np.testing.assert_array_equal(ours, theirs)
    write_polygons(tmp_path / "ours.pol", back)
    assert (tmp_path / "ours.pol").read_text() == (tmp_path / "xt.pol").read_text()


def test_registry_and_exact_round_trip(tmp_path):
    lines = polylines()
    io.write(tmp_path / "f.xyz", lines, kind="polygons")
    back = io.read(tmp_path / "f.xyz", kind="polygons")
    for ours, theirs in zip(back, lines, strict=True):
        np.testing.assert_array_equal(ours, theirs)


@pytest.mark.parametrize(
    ("polys", "message"),
    [
        ([np.zeros((0, 3))], r"p\.pol: polyline 0: expected an \(n >= 1, 3\) array"),
        ([np.ones((2, 3)), np.array([[1.0, np.nan, 2.0]])], r"p\.pol: polyline 1: x, y and z must be finite"),
        (
            [np.array([[1.0, 2.0, 3.0], [4.0, 999.0, 5.0]])],
            r"p\.pol: polyline 0: point 1 has a coordinate of 999\.0",
        ),
    ],
)
def test_bad_polylines_are_refused(tmp_path, polys, message):
    with pytest.raises(InputError, match=message):
        write_polygons(tmp_path / "p.pol", polys)
    assert not (tmp_path / "p.pol").exists()


def test_bad_files_name_the_line(tmp_path):
    f = tmp_path / "p.pol"
    f.write_text("1 2 3\n4 5 6\n999.0 999.0 999.0\n7 8 x\n")
    with pytest.raises(InputError, match=r"p\.pol:4: polygon 2: z: 'x' is not a number"):
        read_polygons(f)
    f.write_text("1 2 3\n4 999 6\n")
    with pytest.raises(InputError, match=r"p\.pol:2: polygon 1: 999 in some columns only"):
        read_polygons(f)
