"""Well trajectory files (gridlib.io.well_paths): RMS well files, x y z [md] text and CSV with
named columns, read into WellPaths; and every error names the file and the line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gridlib import io
from gridlib.errors import InputError
from gridlib.io.well_paths import read_well_path
from gridlib.wells.survey import minimum_curvature

DEMO = Path(__file__).parents[1] / "data" / "wells" / "op_demo.w"


def write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_rms_well_file():
    path = read_well_path(DEMO)
    rows = np.loadtxt(DEMO, skiprows=7)
    assert path.name == "OP_DEMO" and path.xyz.shape == (41, 3)
    np.testing.assert_array_equal(path.xyz, rows[:, :3])
    md = rows[:, 4]
    md[20] = md[19] + np.linalg.norm(rows[20, :3] - rows[19, :3])  # MDepth -999: counted on
    # the x, y printed to 3 decimals make 7 of the 10 m steps along the arc (each 1.3e-4 longer
    # than its chord) up to 3e-4 shorter than their chords: those MDs are lengthened, no more
    np.testing.assert_allclose(path.md, md, rtol=0, atol=3e-4)
    assert np.count_nonzero(path.md != md) == 7 and (path.md >= md).all()
    chord = np.linalg.norm(np.diff(path.xyz, axis=0), axis=1)
    assert (np.diff(path.md) >= chord * (1 - 1e-12)).all()
    # the file is the survey's path, to its printed decimals
    survey_md = np.arange(0.0, 400.1, 10.0)
    survey = np.stack([survey_md, np.clip((survey_md - 100) * 0.1, 0, 45), np.full(41, 135.0)], axis=1)
    exact = minimum_curvature((461809.590, 5932990.360, -25.0), survey)
    np.testing.assert_allclose(path.xyz, exact.xyz, rtol=0, atol=5e-4)
    np.testing.assert_allclose(path.md, exact.md, rtol=0, atol=3e-4)


def test_rms_format_by_content_and_registry(tmp_path):
    other = write(tmp_path, "op_demo.txt", DEMO.read_text())
    assert read_well_path(other).name == "OP_DEMO"
    assert read_well_path(other, name="P9").name == "P9"
    via = io.read(other, kind="well_path")
    np.testing.assert_array_equal(via.md, read_well_path(DEMO).md)
    # a well without an MD log: MD from the first point, along the straight segments
    text = "1.0\nUnknown\nW 2 B 0.0 0.0\n1\nPoro UNK lin\n0 0 100 0.2\n0 0 110 -999\n3 4 110 0.25\n"
    plain = read_well_path(write(tmp_path, "w.w", text))
    assert plain.name == "W 2 B" and plain.md.tolist() == [0.0, 10.0, 15.0]


def test_text_and_csv_tables(tmp_path):
    xyz = write(
        tmp_path, "p1.xyz", "# a vertical then a horizontal leg\n0 0 1000\n0 0 1100  # heel\n\n30 40 1100\n"
    )
    path = read_well_path(xyz)
    assert path.name == "p1" and path.md.tolist() == [0.0, 100.0, 150.0]
    assert path.xyz.tolist() == [[0, 0, 1000], [0, 0, 1100], [30, 40, 1100]]
    with_md = read_well_path(
        write(tmp_path, "p2.txt", "x y z md\n0,0,1000,1200\n0,0,1100,1310\n30,40,1100,1360\n")
    )
    assert with_md.md.tolist() == [1200.0, 1310.0, 1360.0]
    csv = 'Name;"Northing";Easting;TVDSS;mdepth;GR\nA;0;0;1000;1200;50\nA;40;30;1100;1330;60\n'
    named = read_well_path(write(tmp_path, "p3.csv", csv))
    assert named.xyz.tolist() == [[0, 0, 1000], [30, 40, 1100]] and named.md.tolist() == [1200.0, 1330.0]
    chosen = read_well_path(
        write(tmp_path, "p4.csv", "E,N,Z_TVDSS,MD,MD2\n0,0,1000,1200,5\n30,40,1100,1330,200\n"),
        columns={"x": "e", "y": 1, "md": "MD2"},
    )
    assert chosen.xyz.tolist() == [[0, 0, 1000], [30, 40, 1100]] and chosen.md.tolist() == [5.0, 200.0]
    positions = read_well_path(
        write(tmp_path, "p5.txt", "7 0 0 1000\n7 0 0 1010\n"), columns={"x": 1, "y": 2, "z": 3}
    )
    assert positions.xyz.tolist() == [[0, 0, 1000], [0, 0, 1010]]


def test_md_short_of_the_straight_line_by_rounding_is_lengthened(tmp_path):
    """A straight vertical stretch printed to 2 decimals: a step 0.01 short of its straight line
    is rounding (each line's MD and point may be off by 0.005 + |(0.005, 0.005, 0.005)|, a step
    by twice that, 0.027): lengthened; the following MDs stay the file's. A step 0.1 short is an
    error, and so is one short by more than 1 % of its straight line whatever the decimals."""
    text = "x y z md\n0.00 0.00 1000.00 2000.00\n0.00 0.00 1010.01 2010.00\n0.00 0.00 1020.00 2020.00\n"
    path = read_well_path(write(tmp_path, "r.txt", text))
    assert path.md.tolist() == [2000.0, 2000.0 + 10.009999999999991, 2020.0]
    with pytest.raises(
        InputError, match=r"r2.txt: line 3: MD step 9.9 from line 2 is shorter than the straight"
    ):
        read_well_path(
            write(tmp_path, "r2.txt", "x y z md\n0.00 0.00 1000.00 2000.00\n0.00 0.00 1010.00 2009.90\n")
        )
    assert read_well_path(write(tmp_path, "r3.txt", "0 0 1000 2000\n0 0 1010 2009.9999\n")).length == 10.0
    with pytest.raises(InputError, match=r"r4.txt: line 2: MD step 9 from line 1 is shorter"):
        read_well_path(write(tmp_path, "r4.txt", "0 0 1000 2000\n0 0 1010 2009\n"))  # over 1 %: an error


@pytest.mark.parametrize(
    ("name", "text", "message"),
    [
        ("a.txt", "0 0 1000\n0 0 x1\n", "line 2: field 3 'x1' is not a number"),
        ("a.txt", "0 0 1000\n0 0\n", "line 2: expected 3 fields, found 2"),
        ("a.txt", "0 0 1000\n0 nan 1100\n", r"line 2: x, y, z must be finite, got \[0.0, nan, 1100.0\]"),
        (
            "a.txt",
            "0 0 1000 50\n0 0 1100 150\n0 0 1200 140\n",
            "line 3: MD 140 is not greater than line 2's MD 150",
        ),
        ("a.txt", "# only one\n0 0 1000\n", r"1 point \(line 2\); a well path needs at least 2"),
        ("a.txt", "0 0 1000\n0 0 1000\n", r"line 2: the same point as line 1 \(\[0.0, 0.0, 1000.0\]\)"),
        ("a.txt", "# nothing\n\n", r"no data lines \(expected x y z \[md\] per line\)"),
        (
            "a.txt",
            "1 2 3 4 5\n1 2 4 4 5\n",
            r"line 1: expected 3 columns \(x y z\) or 4 \(x y z md\), found 5",
        ),
        (
            "a.csv",
            "x,northing,gr\n0,0,1\n",
            r"line 1: no column for z \(named Z, TVD, TVDSS, Z_TVDSS, DEPTH\)",
        ),
        ("a.csv", "x,y,z,tvd\n0,0,1,1\n", "line 1: columns z and tvd both name z; choose one with columns"),
        ("a.w", "1.0\nx\nW 1 2\n1\nMD UNK lin\n0 0 -999 0\n", r"line 6: x, y or z is undefined \(-999\)"),
        ("a.w", "1.0\nx\nW\n0\n", "line 3: expected the well head 'name x y .rkb.', got 'W'"),
        ("a.w", "1.0\nx\nW 1 2\ntwo\n", "line 4: expected the number of logs, got 'two'"),
        ("a.w", "1.0\nx\nW 1 2\n2\nMD UNK lin\n", "2 logs declared on line 4, but the file ends at line 5"),
        ("a.w", "1.0\nx\nW 1 2\n1\n \n0 0 0 0\n", "line 5: expected a log 'name type ...', got ' '"),
        ("a.w", "1.0\nx\nW 1 2\n1\nMD UNK lin\n0 0 0 0\n0 0 5\n", "line 7: expected 4 fields, found 3"),
        (  # down and back up the same hole: its cells would be completed twice
            "a.xyz",
            "# x y z md\n0 0 0 0\n0 0 10 10\n0 0.01 0 20\n",
            r"line 3: the path turns back on itself \(by 179.94 degrees from line 2 through line 3 to",
        ),
    ],
)
def test_every_error_names_the_file_and_line(tmp_path, name, text, message):
    path = write(tmp_path, name, text)
    with pytest.raises(InputError, match=f"^{path}: {message}"):
        read_well_path(path)


def test_option_errors(tmp_path):
    path = write(tmp_path, "c.csv", "x,y,z\n0,0,0\n0,0,1\n")
    with pytest.raises(InputError, match=r"c.csv: columns: unknown key 'q' \(expected x, y, z, md\)"):
        read_well_path(path, columns={"q": "x"})
    with pytest.raises(InputError, match=r"c.csv: columns: md: no column 'mdx' \(the columns are x, y, z\)"):
        read_well_path(path, columns={"md": "mdx"})
    with pytest.raises(InputError, match=r"c.csv: columns: md: position 3 is not in 0..2"):
        read_well_path(path, columns={"md": 3})
    with pytest.raises(InputError, match=r"c.csv: columns: z is the same column as x \(0\)"):
        read_well_path(path, columns={"z": "x"})
    with pytest.raises(
        InputError, match=r"c\.csv: unknown well path format 'las'; expected one of auto, table, rms"
    ):
        read_well_path(path, format="las")
    with pytest.raises(InputError, match=r"nope\.w: no such file"):
        read_well_path(tmp_path / "nope.w")


def test_a_spreadsheets_byte_order_mark_is_not_part_of_the_first_name(tmp_path):
    """CSV from a spreadsheet ("CSV UTF-8") starts with a byte order mark: the header's first
    column is still X, and a survey's first station still a number."""
    from gridlib.io.survey_stations import read_survey_stations

    table = tmp_path / "p.csv"
    table.write_bytes("\ufeffX,Y,Z,MD\n0,0,1000,1000\n0,0,1100,1100\n".encode())
    path = read_well_path(table)
    assert path.xyz.tolist() == [[0.0, 0.0, 1000.0], [0.0, 0.0, 1100.0]] and path.md.tolist() == [1000, 1100]
    plain = tmp_path / "p.xyz"
    plain.write_bytes("\ufeff0 0 1000\n0 0 1100\n".encode())
    assert read_well_path(plain).md.tolist() == [0.0, 100.0]
    survey = tmp_path / "p.dev"
    survey.write_bytes("\ufeff1000 0 0\n1100 10 45\n".encode())
    assert read_survey_stations(survey).tolist() == [[1000.0, 0.0, 0.0], [1100.0, 10.0, 45.0]]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("MD INC AZI\n0 0 0\n# kick-off\n100 190 0\n", "4: inclination 190 is outside [0, 180] degrees"),
        ("0 0 0\n100 5 0\n100 6 0\n", "3: md 100 does not exceed the station before it (100); MD increases"),
        ("0 0 0\n100 5\n", "2: expected 3 columns (md, inclination, azimuth), found 2"),
        ("0 0 0\n100 n/a 0\n", "2: column 2 (inclination): 'n/a' is not a number"),
        ("0 0 0\n100 5 inf\n", "2: md, inclination and azimuth must be finite"),
    ],
)
def test_a_survey_files_errors_name_its_line(tmp_path, text, message):
    from gridlib.io.survey_stations import read_survey_stations

    path = write(tmp_path, "s.dev", text)
    with pytest.raises(InputError) as info:
        read_survey_stations(path)
    assert str(info.value).startswith(f"{path}:{message}")


def test_semicolon_separated_files_have_decimal_commas(tmp_path):
    """Spreadsheets in many locales write "0,5;1200,25": fields at semicolons, decimal commas."""
    from gridlib.io.survey_stations import read_survey_stations

    table = write(tmp_path, "p.csv", "X;Y;Z;MD\n0,5;0;1000;1000\n0,5;0;1100,25;1100,25\n")
    path = read_well_path(table)
    assert path.xyz.tolist() == [[0.5, 0.0, 1000.0], [0.5, 0.0, 1100.25]]
    assert path.md.tolist() == [1000.0, 1100.25]
    survey = write(tmp_path, "p.dev", "MD;INC;AZI\n1000;0;0\n1100,5;10,25;45\n")
    assert read_survey_stations(survey).tolist() == [[1000.0, 0.0, 0.0], [1100.5, 10.25, 45.0]]


RMS_HEAD = "1.0\nUnknown\nW1 100.0 200.0 25.0\n2\nMDepth UNK lin\nPerm\n"


def test_md_undefined_at_the_top_counts_back_from_the_first_given_one(tmp_path):
    """An MD log that starts below the file's first points (-999 above: a log measured from the
    reservoir down, as RMS exports some): those points' MDs are the first given MD less the
    straight distance to it, not a count from 0 (a 49.5 m MD step over 0.5 m of hole). A log
    given by its name alone ('Perm', no type) is read, as xtgeo reads it."""
    rows = "".join(
        f"100.0 200.0 {z:.1f} {md} 1\n" for z, md in [(0, -999), (0.5, -999), (1.0, 54.0), (1.5, -999)]
    )
    path = read_well_path(write(tmp_path, "w1.w", RMS_HEAD + rows))
    np.testing.assert_array_equal(path.md, [53.0, 53.5, 54.0, 54.5])


def test_a_file_of_several_wells_is_named_so(tmp_path):
    second = "1.0\nUnknown\nW2 300.0 400.0\n0\n300.0 400.0 0.0\n300.0 400.0 10.0\n"
    rows = "100.0 200.0 0.0 0.0 1\n100.0 200.0 10.0 10.0 1\n"
    with pytest.raises(InputError, match=r"w.w: line 9: a second well starts here .* one well"):
        read_well_path(write(tmp_path, "w.w", RMS_HEAD + rows + second))
