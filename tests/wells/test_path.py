"""WellPath: measured depths filled in, points at given MDs, sub-paths, and every check."""

from __future__ import annotations

import numpy as np
import pytest

from gridlib.errors import InputError
from gridlib.wells.path import WellPath

L_SHAPE = [[0.0, 0.0, 1000.0], [0.0, 0.0, 1100.0], [30.0, 40.0, 1100.0], [30.0, 40.0, 1160.0]]


def test_from_points_fills_md_from_the_straight_lengths():
    p = WellPath.from_points(L_SHAPE, name="P1", start_md=25.0)
    assert p.md.tolist() == [25.0, 125.0, 175.0, 235.0]
    assert p.length == 210.0 and p.name == "P1"
    assert not p.xyz.flags.writeable and not p.md.flags.writeable
    start, end = p.segments
    assert start.tolist() == L_SHAPE[:3] and end.tolist() == L_SHAPE[1:]
    # missing MDs count from the last given one; the first from start_md
    p = WellPath.from_points(L_SHAPE, [np.nan, 130.0, np.nan, np.nan], start_md=7.0)
    assert p.md.tolist() == [7.0, 130.0, 180.0, 240.0]
    # an MD longer than the straight line (a curved hole between two points) is fine
    assert WellPath.from_points(L_SHAPE, [0, 150, 260, 330]).length == 330.0


def test_at_is_linear_in_md_and_exact_at_the_points():
    p = WellPath.from_points(L_SHAPE, [0.0, 200.0, 300.0, 360.0])
    got = p.at([0.0, 50.0, 200.0, 250.0, 345.0, 360.0])
    want = [[0, 0, 1000], [0, 0, 1025], [0, 0, 1100], [15, 20, 1100], [30, 40, 1145], [30, 40, 1160]]
    assert got.tolist() == want
    assert p.at(300.0).tolist() == [[30.0, 40.0, 1100.0]]
    # the path's own MDs give its own points, bit for bit (also awkward decimals)
    q = WellPath.from_points(np.array(L_SHAPE) + 0.1, [0.3, 100.7, 151.1, 211.9])
    assert np.array_equal(q.at(q.md), q.xyz)


def test_between_cuts_the_path_at_both_ends():
    p = WellPath.from_points(L_SHAPE, name="P1")
    part = p.between(90.0, 170.0)
    assert part.xyz.tolist() == [[0, 0, 1090], [0, 0, 1100], [30, 40, 1100], [30, 40, 1120]]
    assert part.md.tolist() == [90.0, 100.0, 150.0, 170.0] and part.name == "P1"
    inside = p.between(110.0, 140.0)  # inside one segment
    assert inside.xyz.tolist() == [[6, 8, 1100], [24, 32, 1100]] and inside.md.tolist() == [110, 140]
    assert np.array_equal(p.between(0.0, 210.0).xyz, p.xyz)
    # an end a rounding error short of a vertex lands on it: the vertex is not repeated
    near = p.between(np.nextafter(100.0, 0.0), 150.0)
    assert near.md.size == 2 and near.xyz.tolist() == [[0, 0, 1100], [30, 40, 1100]]


@pytest.mark.parametrize(
    ("xyz", "md", "message"),
    [
        (L_SHAPE[:1], None, r"well path 'W': expected an \(n >= 2, 3\) array of x, y, z, got shape \(1, 3\)"),
        ([(0, 0, 0), (0, np.nan, 1)], None, "well path 'W': point 1 is not finite"),
        (L_SHAPE, [0, 100, np.inf, 300], "well path 'W': point 2: MD inf is not finite"),
        (L_SHAPE, [0, 100, 100, 300], "well path 'W': point 2: MD 100 is not greater than point 1's MD 100"),
        (L_SHAPE, [0, 100, 150], r"well path 'W': md: expected 4 values \(one per point\), got shape \(3,\)"),
        (
            [(0, 0, 0), (0, 0, 10), (0, 0, 10)],
            [0, 10, 20],
            r"well path 'W': point 2: the same point as point 1 \(\[0.0, 0.0, 10.0\]\)",
        ),
        (
            L_SHAPE,
            [0, 100, 149.9999, 300],
            r"well path 'W': point 2: MD step 49.9999 from point 1 is shorter than the straight line "
            r"between them \(50\)",
        ),
    ],
)
def test_every_check_names_the_point(xyz, md, message):
    with pytest.raises(InputError, match=f"^{message}"):
        WellPath.from_points(xyz, md, name="W")
    if md is not None and len(md) == len(xyz) and not np.isnan(md).any():
        with pytest.raises(InputError, match=f"^{message}"):
            WellPath(np.array(xyz, dtype=float), np.array(md, dtype=float), "W")


def test_md_within_a_relative_1e_9_of_the_straight_line_is_accepted():
    assert WellPath.from_points(L_SHAPE[:2], [0.0, 100.0 * (1 - 0.5e-9)]).length < 100.0
    with pytest.raises(InputError, match="point 1: MD step"):
        WellPath.from_points(L_SHAPE[:2], [0.0, 100.0 * (1 - 2e-9)])


def test_at_and_between_refuse_mds_off_the_path():
    p = WellPath.from_points(L_SHAPE, name="P1", source="x.yaml: wells[0]")
    with pytest.raises(
        InputError, match=r"^well path 'P1': MD 210.5 is outside the path's MD range \[0, 210\]"
    ):
        p.at([10.0, 210.5])
    with pytest.raises(InputError, match="MD nan is outside"):
        p.at(np.nan)
    with pytest.raises(InputError, match="MD -1 is outside"):
        p.between(-1.0, 5.0)
    with pytest.raises(InputError, match=r"^well path 'P1': between: MD 5 to 5 is not an interval"):
        p.between(5.0, 5.0)
    with pytest.raises(InputError, match=r"^x\.yaml: wells\[0\]: point 1 is not finite"):
        WellPath.from_points([(0, 0, 0), (np.nan, 0, 0)], source="x.yaml: wells[0]")
