"""read_grdecl / write_grdecl / read_egrid: syntax, semantics, exact round trips, clear errors."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path

import numpy as np
import pytest

import gridlib as gl
from gridlib.cornerpoint.deck import Deck, FaultSegment
from gridlib.cornerpoint.generators import make_model3, simple_grdecl
from gridlib.cornerpoint.layer_overlaps import without_layer_overlaps
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.egrid import read_egrid
from gridlib.io.grdecl import DeckError, read_grdecl, write_grdecl

CUBE = """\
SPECGRID
 2 2 1 1 F /
COORD
 0 0 0  0 0 1   1 0 0  1 0 1   2 0 0  2 0 1
 0 1 0  0 1 1   1 1 0  1 1 1   2 1 0  2 1 1
 0 2 0  0 2 1   1 2 0  1 2 1   2 2 0  2 2 1 /
ZCORN
 16*0 16*1 /
"""


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def test_repeat_counts_comments_and_terminators(tmp_path):
    p = write(
        tmp_path / "a.grdecl",
        CUBE
        + """-- a comment with a / slash
PORO -- porosity, fraction (not m/s)
 2*0.25 -- inline comment / with slash
 0.1
 3.0E-1/
NTG
\t1\t1 2*0.5 /
""",
    )
    deck = read_grdecl(p)
    assert deck.cart_dims == (2, 2, 1)
    np.testing.assert_array_equal(deck.cell_data["PORO"], [0.25, 0.25, 0.1, 0.3])
    np.testing.assert_array_equal(deck.cell_data["NTG"], [1, 1, 0.5, 0.5])
    r = process_grdecl(deck)
    assert r.grid.num_cells == 4
    assert gl.compute_geometry(r.grid).cell_volumes.sum() == pytest.approx(4.0, abs=1e-14)


def test_crlf_fortran_exponents_and_lowercase(tmp_path):
    text = CUBE.replace("\n", "\r\n") + "poro\r\n 1.0D-1 2.5d-1 2*1D0 /\r\n"
    deck = read_grdecl(write(tmp_path / "b.grdecl", text))
    np.testing.assert_array_equal(deck.cell_data["PORO"], [0.1, 0.25, 1.0, 1.0])


def test_include_relative_to_the_data_file_and_paths(tmp_path):
    # As ECLIPSE and OPM Flow: a nested INCLUDE's path is relative to the DATA file's directory
    # (tests/io/test_deck_syntax.py checks it against Flow).
    write(tmp_path / "grid" / "geom.inc", CUBE + "INCLUDE\n 'grid/props/poro.inc' /\n")
    write(tmp_path / "grid" / "props" / "poro.inc", "PORO\n 4*0.2 /\n")
    write(tmp_path / "perm" / "k.inc", "PERMX\n 4*100 /\n")
    main = write(
        tmp_path / "CASE.DATA",
        "RUNSPEC\nTITLE\n  A TEST / WITH SLASH\nDIMENS\n 2 2 1 /\nMETRIC\nTABDIMS\n/\nGRID\n"
        "PATHS\n 'PERM' 'perm' /\n/\nINCLUDE\n 'grid/geom.inc' /\nINCLUDE\n '$PERM/k.inc' /\n"
        "PROPS\nPVTW\n garbage that is never read /\n",
    )
    deck = read_grdecl(main)
    assert deck.units == "METRIC"
    np.testing.assert_array_equal(deck.cell_data["PORO"], 0.2)
    np.testing.assert_array_equal(deck.cell_data["PERMX"], 100.0)
    assert any("TABDIMS" in n and "PVTW" in n for n in deck.notes)  # PROPS is read; its tables skipped


def test_equals_copy_multiply_add_with_box(tmp_path):
    p = write(
        tmp_path / "ops.grdecl",
        CUBE.replace(" 2 2 1 1 F", " 2 2 1 1 F").replace("16*0 16*1", "16*0 16*1")
        + """PERMX
 10 20 30 40 /
BOX
 1 1 1 2 1 1 /
PORO
 0.1 0.3 /
ENDBOX
EQUALS
 'PORO' 0.2 2 2 1* 1* /  -- the other column; the box defaults to the whole grid
 NTG 0.9 /
/
COPY
 PERMX PERMY /
 'PERMX' 'PERMZ' 1 2 1 1 1 1 /
/
MULTIPLY
 'PERMZ' 0.1 /
/
ADD
 PERMY 5 1 1 1 1 1 1 /
/
MAXVALUE
 PERMY 35 /
/
""",
    )
    deck = read_grdecl(p)
    d = deck.cell_data
    np.testing.assert_array_equal(d["PORO"], [0.1, 0.2, 0.3, 0.2])
    np.testing.assert_array_equal(d["NTG"], 0.9)
    np.testing.assert_array_equal(d["PERMY"], [15, 20, 30, 35])
    np.testing.assert_allclose(d["PERMZ"][:2], [1.0, 2.0], rtol=1e-15)
    assert np.isnan(d["PERMZ"][2:]).all()  # COPY only filled the box
    assert any("PERMZ is undefined in 2 of 4 cells" in n for n in deck.notes)


def test_defaulted_values_keep_what_was_there(tmp_path):
    p = write(tmp_path / "d.grdecl", CUBE + "PORO\n 4*0.2 /\nPORO\n 0.1 2* 0.4 /\n")
    np.testing.assert_array_equal(read_grdecl(p).cell_data["PORO"], [0.1, 0.2, 0.2, 0.4])


def test_cartesian_keywords_become_corner_point(tmp_path):
    """SPE1-like: DX/DY/DZ/TOPS, TOPS for the top layer only; volumes are boxes."""
    p = write(
        tmp_path / "cart.DATA",
        "RUNSPEC\nDIMENS\n 3 2 2 /\nFIELD\nGRID\nDX\n 12*100 /\nDY\n 6*50 6*50 /\n"
        "DZ\n 6*10 6*20 /\nTOPS\n 6*8000 /\nACTNUM\n 11*1 0 /\n",
    )
    deck = read_grdecl(p)
    assert deck.units == "FIELD"
    r = process_grdecl(deck)
    assert r.grid.num_cells == 11
    np.testing.assert_allclose(np.sort(r.bulk_volumes), [50000.0] * 6 + [100000.0] * 5, rtol=1e-15)
    z = deck.zcorn_array()
    assert z.min() == 8000 and z.max() == 8030


def test_dxv_dyv_dzv_depthz(tmp_path):
    p = write(
        tmp_path / "v.grdecl",
        "DIMENS\n 2 1 1 /\nDXV\n 1 3 /\nDYV\n 2 /\nDZV\n 4 /\nDEPTHZ\n 100 101 102 100 101 102 /\n",
    )
    r = process_grdecl(read_grdecl(p))
    np.testing.assert_allclose(r.bulk_volumes, [8.0, 24.0], rtol=1e-14)


def test_unknown_keywords_stop_the_read_or_are_skipped(tmp_path):
    text = (
        "NOECHO\nRPTGRID\n ALLNNC /\nFOOBAR\n 1 2 3 /\n  4 5 /\n/\n"
        + CUBE
        + "SWATINIT\n 1 2 3 4 /\nSOMEPROP\n 1 2 3 4 /\nNEWKW\nECHO\n"
    )
    p = write(tmp_path / "u.grdecl", text)
    with pytest.raises(DeckError, match=r"u.grdecl:4: unknown keyword 'FOOBAR'"):
        read_grdecl(p)
    deck = read_grdecl(p, unknown_keywords="skip")
    np.testing.assert_array_equal(deck.cell_data["SWATINIT"], [1, 2, 3, 4])  # known: kept
    assert "SOMEPROP" not in deck.cell_data
    skipped = next(n for n in deck.notes if n.startswith("skipped keywords not"))
    unknown = next(n for n in deck.notes if n.startswith("skipped keywords neither"))
    assert "RPTGRID (u.grdecl:2)" in skipped and "FOOBAR" not in skipped
    assert "FOOBAR (u.grdecl:4)" in unknown and "SOMEPROP (u.grdecl:" in unknown and "NEWKW" in unknown
    with pytest.raises(DeckError, match="unknown_keywords must be one of"):
        read_grdecl(p, unknown_keywords="ignore")


def test_faults_multflt_pinch_minpv_mapaxes(tmp_path):
    p = write(
        tmp_path / "f.grdecl",
        CUBE
        + """MAPUNITS
 'METRES  ' /
MAPAXES
 0.0 100.0 0.0 0.0 100.0 0.0 /
GRIDUNIT
 'METRES ' ' ' /
FAULTS
-- name  i1 i2 j1 j2 k1 k2 face
 'F1'   1  1  1  2  1  1  X /
 F2     1  2  2  2  1  1  J- /
/
MULTFLT
 'F1' 0.1 /
/
PINCH
 0.5 NOGAP 1* TOPBOT /
MINPV
 1e-3 /
""",
    )
    deck = read_grdecl(p)
    assert deck.faults == (
        FaultSegment("F1", 0, 0, 0, 1, 0, 0, "X"),
        FaultSegment("F2", 0, 1, 1, 1, 0, 0, "Y-"),
    )
    assert deck.multflt == {"F1": 0.1}
    assert deck.pinch == (0.5, 1e20) and deck.minpv == 1e-3
    assert deck.mapunits == "METRES" and deck.gridunit == "METRES"
    np.testing.assert_array_equal(deck.mapaxes, [0, 100, 0, 0, 100, 0])


def _assert_same_deck(a: Deck, b: Deck) -> None:
    assert a.cart_dims == b.cart_dims
    for name in ("coord", "zcorn"):
        np.testing.assert_array_equal(getattr(a, name).view(np.int64), getattr(b, name).view(np.int64))
    np.testing.assert_array_equal(a.active, b.active)
    assert sorted(a.cell_data) == sorted(b.cell_data)
    for k in a.cell_data:
        np.testing.assert_array_equal(a.cell_data[k].view(np.int64), b.cell_data[k].view(np.int64))
    assert a.faults == b.faults and a.multflt == b.multflt


def test_write_then_read_is_bit_identical(tmp_path):
    rng = np.random.default_rng(7)
    deck = make_model3([12, 9, 4])
    nc = deck.num_cells
    poro = rng.random(nc) * 0.3  # full 17-digit values
    poro[::5] = 0.2
    deck = dataclasses.replace(
        deck,
        zcorn=deck.zcorn + rng.standard_normal(deck.zcorn.size) * 1e-9,
        cell_data={"PORO": poro, "PERMX": np.exp(rng.standard_normal(nc) * 3), "SATNUM": np.ones(nc)},
        faults=(FaultSegment("A", 1, 3, 0, 8, 0, 3, "X"),),
        multflt={"A": 0.25},
    )
    # the noise makes layers overlap by 1e-9 where they touch, which the reader removes as
    # Flow does (test_layer_overlaps): the round trip is exact for a deck without overlaps
    deck = without_layer_overlaps(deck)
    back = read_grdecl(write_grdecl(tmp_path / "out.grdecl", deck))
    _assert_same_deck(deck, back)
    text = (tmp_path / "out.grdecl").read_text()
    assert max(len(line) for line in text.splitlines()) <= 132  # ECLIPSE's line length
    assert "2*" in text  # runs are compressed


def test_write_exact_text_of_a_tiny_deck(tmp_path):
    """Runs of bit-identical values become n*v (0.0 and -0.0 are not merged), integers are bare."""
    coord = np.array([[i, j, 0.0, i, j, 1.0] for j in (0, 1) for i in (0.0, 0.5, 1.0)]).ravel()
    zcorn = np.repeat([1000.0, 1000.0000000000001], 8)
    deck = Deck(
        (2, 1, 1),
        coord,
        zcorn,
        np.array([1, 0], np.int32),
        {"PORO": np.array([0.0, -0.0]), "SATNUM": np.array([3.0, 3.0])},
        faults=(FaultSegment("F", 0, 0, 0, 0, 0, 0, "X"),),
        multflt={"F": 0.5},
        mapaxes=np.array([0.0, 1.0, 0.0, 0.0, 1.0, 0.0]),
        source="tiny",
    )
    path = write_grdecl(tmp_path / "tiny.grdecl", deck)
    assert path.read_text() == (
        "-- written by gridlib from tiny\n\n"
        "SPECGRID\n 2 1 1 1 F /\n\n"
        "MAPAXES\n 0.0 1.0 0.0 0.0 1.0 0.0 /\n\n"
        "COORD\n"
        "5*0.0 1.0 0.5 2*0.0 0.5 0.0\n"
        "2*1.0 2*0.0 1.0 0.0 1.0 0.0\n"
        "1.0 2*0.0 2*1.0 0.5 1.0 0.0\n"
        "0.5 4*1.0 0.0 3*1.0\n"
        "/\n\n"
        "ZCORN\n8*1000.0 8*1000.0000000000001\n/\n\n"
        "ACTNUM\n1 0\n/\n\n"
        "PORO\n0.0 -0.0\n/\n\n"
        "SATNUM\n2*3\n/\n\n"
        "FAULTS\n 'F' 1 1 1 1 1 1 X /\n/\n\n"
        "MULTFLT\n 'F' 0.5 /\n/\n\n"
    )
    back = read_grdecl(path)
    _assert_same_deck(deck, back)
    np.testing.assert_array_equal(back.mapaxes, deck.mapaxes)


def test_write_round_trips_special_values_and_keeps_lines_short(tmp_path):
    rng = np.random.default_rng(3)
    deck = make_model3([6, 5, 4])
    nc = deck.num_cells
    special = np.array(
        [0.0, -0.0, 5e-324, -5e-324, 2.2250738585072014e-308, 2.225073858507201e-308,
         1.7976931348623157e308, -1.7976931348623157e308, 1e-300, -1.2345678901234567e-100,
         1e16, 9999999999999998.0, 1e-4, 9.999999999999999e-05, 0.1, 0.30000000000000004, 1 / 3,
         2.0**53, 2.0**53 + 2, 123456789.00000001, -7.0710678118654755],
    )  # fmt: skip
    arrays = {  # the names are cell keywords ECLIPSE knows (read_grdecl refuses others); any values
        "SWL": np.resize(special, nc),
        "SWCR": np.repeat(rng.choice(special, nc // 8 + 1), rng.integers(1, 30, nc // 8 + 1))[:nc],
        "SWU": np.repeat(special[[9, 8, 9, 6]], [nc - 3, 1, 1, 1]),
        "SGL": np.where(rng.random(nc) < 0.5, 0.0, -0.0),
        "KRW": rng.standard_normal(nc) * 10.0 ** rng.integers(-300, 300, nc),
        "KRO": rng.integers(0, 2**62, nc, dtype=np.int64).view(np.float64),  # NaN-free bit patterns
        "FIPNUM": np.repeat([1.0, 2.0, -0.0, 1e15], nc // 4),  # whole numbers: integers
    }
    coord = deck.coord.copy()
    coord[[3, 4, 10]] = np.nan  # NaN is written one by one ("n*nan" is not read)...
    with_nan = write_grdecl(tmp_path / "nan.grdecl", dataclasses.replace(deck, coord=coord))
    assert "nan" in with_nan.read_text() and "*nan" not in with_nan.read_text()
    with pytest.raises(DeckError, match=r"nan.grdecl:\d+: COORD: 3 values are not finite .*pillar \(1, 1\)"):
        read_grdecl(with_nan)  # ... and read back refused: a deck's numbers are finite
    deck = dataclasses.replace(deck, cell_data=arrays)
    path = write_grdecl(tmp_path / "special.grdecl", deck)
    back = read_grdecl(path)
    np.testing.assert_array_equal(back.coord.view(np.int64), deck.coord.view(np.int64))
    np.testing.assert_array_equal(back.zcorn.view(np.int64), deck.zcorn.view(np.int64))
    for name, values in arrays.items():
        expected = values + 0.0 if name == "FIPNUM" else values  # an integer keyword has no -0
        np.testing.assert_array_equal(
            back.cell_data[name].view(np.int64), expected.view(np.int64), err_msg=name
        )
    text = path.read_text()
    assert max(len(line) for line in text.splitlines()) <= 131  # ECLIPSE reads 132 characters a line
    assert f"{nc - 3}*-1.2345678901234567e-100" in text
    assert "FIPNUM\n30*1 30*2 30*0 30*1000000000000000\n/" in text


def test_write_keeps_undefined_values_undefined(tmp_path):
    """A deck that leaves cells without a value (PERMX given in a BOX, say) is written as it is:
    those cells defaulted (n*), undefined again when read (by Flow too). A deck case whose case
    gives its own permeability wrote its grid.grdecl that way; the writer used to refuse it."""
    deck = simple_grdecl([2, 2, 1])
    data = {"PERMX": np.array([10.0, np.nan, np.nan, 20.0]), "FIPNUM": np.array([np.nan, 1, 2, 2])}
    path = write_grdecl(tmp_path / "x.grdecl", dataclasses.replace(deck, cell_data=data))
    text = path.read_text()
    assert "PERMX\n10.0 2* 20.0\n/" in text and "FIPNUM\n1* 1 2*2\n/" in text
    back = read_grdecl(path)
    for name, values in data.items():
        np.testing.assert_array_equal(back.cell_data[name], values)


def test_read_egrid_of_eclipse_and_the_grdecl_agree(reek_dir):
    """REEK.EGRID (float32, written by ECLIPSE) and reek_sim_grid.grdecl (text) are one grid."""
    eg = read_egrid(reek_dir / "REEK.EGRID")
    txt = read_grdecl(reek_dir / "reek_sim_grid.grdecl")
    assert eg.cart_dims == txt.cart_dims == (40, 64, 14)
    np.testing.assert_array_equal(eg.active, txt.active)
    np.testing.assert_allclose(eg.zcorn, txt.zcorn, rtol=1e-7)
    assert eg.nnc.shape == (2874, 2)
    assert eg.mapunits == "METRES"


# --- errors ----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (CUBE + "PORO\n 0.1 0.2 0.3 /\n", r"x.grdecl:9: PORO: has 3 values, expected 4"),
        (CUBE + "PORO\n 0.1 0.2 abc 0.3 /\n", r"x.grdecl:10: PORO: 'abc' is not a number"),
        (
            CUBE + "PORO\n 0.1 0.2 0.3 0.4\nNTG\n 4*1 /\n",
            r"x.grdecl:11: PORO: 'NTG' is not a number \(is the '/'",
        ),
        (CUBE + "PORO\n 4*0.1\n", r"x.grdecl:9: PORO: the data has no terminating '/'"),
        (CUBE + "PORO\n 99999999999999*0.1 /\n", r"x.grdecl:9: PORO: has 99999999999999 values, expected 4"),
        (CUBE + "PORO\n 4*0.1 /\n 0.3\n", r"x.grdecl:11: expected a keyword, found '0.3'"),
        (CUBE + "IMPORT\n 'x.bin' /\n", r"x.grdecl:10: IMPORT: file 'x.bin' not found"),
        (CUBE + "INCLUDE\n 'nothere.inc' /\n", r"x.grdecl:10: INCLUDE: file 'nothere.inc' not found"),
        ("PORO\n 1 /\n", r"x.grdecl:1: PORO: the grid dimensions are not known yet"),
        ("SPECGRID\n 2 0 1 1 F /\n", r"x.grdecl:2: SPECGRID: needs three positive integers"),
        ("SPECGRID\n 2 2 1 1 T /\n", r"SPECGRID: radial .* not supported"),
        ("DIMENS\n 2 2 1 /\n", r"x.grdecl: no grid geometry"),
        (CUBE + "FAULTS\n 'F' 1 1 1 3 1 1 X /\n/\n", r"x.grdecl:10: FAULTS: box 1 1 1 3 1 1 is not inside"),
        (CUBE + "FAULTS\n 'F' 1 1 1 1 1 1 W /\n/\n", r"x.grdecl:10: FAULTS: face 'W' of fault 'F'"),
        (CUBE + "MULTIPLY\n 'PERMX' 2 /\n/\n", r"x.grdecl:10: MULTIPLY: PERMX is not defined"),
        (CUBE + "EQUALS\n 'PORO' x /\n/\n", r"x.grdecl:10: EQUALS: PORO: 'x' is not a number"),
        (
            CUBE + "ACTNUM\n 1 0 0.5 1 /\n",
            r"x.grdecl:9: ACTNUM: 1 values are not integers \(first 0.5\): cells \(1, 2, 1\)",
        ),
        (CUBE.replace("16*0 16*1", "16*0 15*1"), r"x.grdecl:7: ZCORN: has 31 values, expected 32"),
        (CUBE + "MAPUNITS\n 'METRES /\n", r"x.grdecl:10: MAPUNITS: a quoted string is not closed"),
        (CUBE + "EQUALREG\n PORO 0.2 1 X /\n/\n", r"x.grdecl:10: EQUALREG: region set 'X' is not M, F or O"),
        (CUBE + "EQUALREG\n PORO 0.2 1 /\n/\n", r"x.grdecl:10: EQUALREG: FLUXNUM is not defined"),
        (CUBE + "MULTREGP\n 1 0.5 O /\n/\n", r"x.grdecl:10: MULTREGP: OPERNUM is not defined"),
        (
            CUBE + "MULTIREG\n PERMX 2 1 M /\n/\n",
            r"x.grdecl:10: MULTIREG: PERMX is not defined in every cell",
        ),
        (CUBE + "OPERATE\n PORO 1 1 1 1 1 1 SQRT PORO /\n/\n", r"OPERATE: unknown operation 'SQRT'"),
        (CUBE + "OPERATER\n TRANX 1 MULTX PORO 2 /\n/\n", r"OPERATER: TRANX cannot be changed by OPERATER"),
        (CUBE + "COPYREG\n NOPE PORO 1 /\n/\n", r"COPYREG: 'NOPE' is not a keyword with one value per cell"),
    ],
)
def test_bad_decks_name_file_line_and_keyword(tmp_path, text, message):
    p = write(tmp_path / "x.grdecl", text)
    with pytest.raises(DeckError, match=message):
        read_grdecl(p)


def test_missing_file_and_binary_junk(tmp_path):
    with pytest.raises(DeckError, match="no such file"):
        read_grdecl(tmp_path / "none.grdecl")
    p = tmp_path / "junk.grdecl"
    p.write_bytes(b"\x00\x01\xff\xfe garbage")
    with pytest.raises(DeckError, match=r"junk.grdecl:1: expected a keyword, found '\\x00\\x01"):
        read_grdecl(p)
    with pytest.raises(DeckError, match="not a readable EGRID"):
        read_egrid(p)


def test_include_cycle_is_an_error(tmp_path):
    write(tmp_path / "a.inc", "INCLUDE\n 'b.inc' /\n")
    write(tmp_path / "b.inc", "INCLUDE\n 'a.inc' /\n")
    with pytest.raises(DeckError, match=re.escape("INCLUDE: includes nested more than 32 deep")):
        read_grdecl(tmp_path / "a.inc")


def test_undefined_corners_of_inactive_cells_are_written_finite(tmp_path):
    """horizons_to_grdecl leaves NaN in inactive cells; ECLIPSE cannot read NaN."""
    deck = make_model3([10, 8, 4])
    nx, ny, nz = deck.cart_dims
    z = deck.zcorn_array().copy()
    inactive = ~deck.active.reshape(nz, ny, nx)
    mask = np.repeat(np.repeat(np.repeat(inactive, 2, 0), 2, 1), 2, 2)
    z[mask] = np.nan
    holey = dataclasses.replace(deck, zcorn=z.ravel())
    back = read_grdecl(write_grdecl(tmp_path / "h.grdecl", holey))
    assert np.isfinite(back.zcorn).all()
    np.testing.assert_array_equal(back.zcorn[~mask.ravel()], deck.zcorn[~mask.ravel()])
    assert np.all(np.diff(back.zcorn_array(), axis=0) >= 0)  # order along every pillar kept
    a, b = process_grdecl(holey), process_grdecl(back)
    np.testing.assert_array_equal(a.bulk_volumes, b.bulk_volumes)
    bad = dataclasses.replace(deck, zcorn=np.where(mask.ravel(), deck.zcorn, np.nan))
    with pytest.raises(DeckError, match="active cells have undefined"):
        write_grdecl(tmp_path / "bad.grdecl", bad)


# The sha256 of write_grdecl's files of vendored decks, as written by the single-module writer
# (gridlib/io/grdecl.py at 934490c) before the reader and the writer were split and the value
# table was formatted in blocks: the split writer must give the same bytes.
WRITTEN_SHA256 = {
    "spe9/SPE9.GRDECL": "3ec1b491aa59e077ece8db94d32266902bcbbe5943d0ac3b11551d7f389f08c7",
    "reek/reek_sim_grid.grdecl": "ee989dad40e664ddf7c80a2a105dbf92394790b3440b50025c7bab408b528262",
}


@pytest.mark.parametrize("name", sorted(WRITTEN_SHA256))
def test_written_sample_decks_keep_their_bytes(tmp_path, decks_dir, name):
    import hashlib

    deck = dataclasses.replace(read_grdecl(decks_dir / name), source=name)  # the header names it
    path = write_grdecl(tmp_path / "out.grdecl", deck)
    assert hashlib.sha256(path.read_bytes()).hexdigest() == WRITTEN_SHA256[name]


def test_porv_is_read_in_edit_only_and_keeps_the_multpv_of_its_moment(tmp_path):
    """As OPM Flow 2022.10 reads them (tests/transmissibility/test_flow_activity.py runs Flow):
    the PORV keyword in GRID is ignored; in EDIT it sets its box (NaN elsewhere: Flow computes those);
    the computed cells keep the MULTPV in force when EDIT first touches PORV, times the
    MULTIPLY on PORV; MULTPV in EDIT replaces GRID's; MINPORV is MINPV."""
    text = CUBE.replace("SPECGRID", "GRID\nSPECGRID") + (
        "PORO\n 4*0.2 /\nMULTPV\n 4*0.5 /\nPORV\n 4*9 /\nMINPORV\n 0.25 /\n"
        "EDIT\nMULTPV\n 2 2 2 2 /\nBOX\n 1 1 1 1 1 1 /\nPORV\n 7 /\nENDBOX\n"
        "MULTPV\n 4*3 /\nMULTIPLY\n PORV 10 1 2 1 1 1 1 /\n/\nEQUALS\n PORV 1.5 2 2 2 2 1 1 /\n/\n"
    )
    deck = read_grdecl(write(tmp_path / "porv.data", text))
    np.testing.assert_array_equal(deck.cell_data["PORV"], [70, np.nan, np.nan, 1.5])
    np.testing.assert_array_equal(deck.cell_data["MULTPV"], [20, 20, 2, 2])
    assert deck.minpv == 0.25
    assert any("PORV in the GRID section ignored" in n for n in deck.notes)
    assert "PORV (EDIT) given for 2 of 4 cells" in deck.notes


@pytest.mark.parametrize("operation", ["ADD", "MINVALUE", "MAXVALUE"])
def test_porv_operations_flow_computes_are_refused_with_file_and_line(tmp_path, operation):
    text = CUBE.replace("SPECGRID", "GRID\nSPECGRID") + f"PORO\n 4*0.2 /\nEDIT\n{operation}\n PORV 1 /\n/\n"
    with pytest.raises(DeckError, match=rf"porv.data:\d+: {operation}.*4 cells of the box have no PORV"):
        read_grdecl(write(tmp_path / "porv.data", text))


def test_numpy_scalars_are_written_as_numbers(tmp_path):
    """A deck built in code may hold NumPy scalars: the text has their numbers, never a repr
    such as np.float64(0.5)."""
    deck = simple_grdecl([2, 1, 1])
    deck = dataclasses.replace(
        deck,
        faults=(FaultSegment("F", 0, 0, 0, 0, 0, 0, "X"),),
        multflt={"F": np.float64(0.5)},
        pinch=(np.float64(0.25), np.float64(1e20)),
        minpv=np.float64(3.0),
    )
    text = write_grdecl(tmp_path / "n.grdecl", deck).read_text()
    assert "np." not in text
    assert " 'F' 0.5 /" in text and "PINCH\n 0.25 GAP 1e+20 TOPBOT TOP /" in text and "MINPV\n 3.0 /" in text
    back = read_grdecl(tmp_path / "n.grdecl")
    assert back.multflt == {"F": 0.5} and back.pinch == (0.25, 1e20) and back.minpv == 3.0


@pytest.mark.parametrize("keyword", ["DUALPORO", "DUALPERM"])
def test_a_dual_porosity_deck_is_refused_not_read_as_one_grid(tmp_path, keyword):
    """DUALPORO/DUALPERM make the lower half of the layers fracture cells: read as one grid they
    would be layers below the matrix."""
    p = write(tmp_path / "x.DATA", f"RUNSPEC\nDIMENS\n 2 2 1 /\n{keyword}\nGRID\n" + CUBE)
    with pytest.raises(DeckError, match=rf"x.DATA:4: {keyword}: a dual-porosity deck .* is not read"):
        read_grdecl(p)


@pytest.mark.parametrize(
    ("filehead", "actnum", "kind"), [(1, 1, "DUALPORO"), (2, 1, "DUALPERM"), (0, 3, "ACTNUM")]
)
def test_a_dual_porosity_egrid_is_refused(tmp_path, filehead, actnum, kind):
    """ECLIPSE's EGRID of a dual-porosity run (FILEHEAD item 6; ACTNUM 2 and 3 for fracture cells)."""
    import resfo

    deck = simple_grdecl([2, 1, 1])
    head = np.zeros(100, np.int32)
    head[5] = filehead
    grid = np.zeros(100, np.int32)
    grid[:4] = (1, 2, 1, 1)
    resfo.write(
        tmp_path / "D.EGRID",
        [
            ("FILEHEAD", head),
            ("GRIDHEAD", grid),
            ("COORD   ", deck.coord.astype(np.float32)),
            ("ZCORN   ", deck.zcorn.astype(np.float32)),
            ("ACTNUM  ", np.array([1, actnum], np.int32)),
            ("ENDGRID ", np.zeros(0, np.int32)),
        ],
    )
    with pytest.raises(DeckError, match=rf"D.EGRID: a dual-porosity grid \({kind}.*\) is not read"):
        read_egrid(tmp_path / "D.EGRID")


def test_a_numerical_aquifer_is_named_as_not_built(tmp_path):
    """AQUNUM/AQUCON: Flow makes the aquifer's cells active and joins them to the reservoir;
    gridlib's grid does not, and says so (it listed them among keywords 'not needed for the
    grid')."""
    text = CUBE + "AQUNUM\n 1 1 1 1 1.0E5 1000 0.25 400 1* 1* 1 1 /\n/\nAQUCON\n 1 2 2 1 1 1 1 I- /\n/\n"
    deck = read_grdecl(write(tmp_path / "a.grdecl", text))
    aquifer = [n for n in deck.notes if "numerical aquifer is not built" in n]
    assert len(aquifer) == 1 and aquifer[0].startswith("a.grdecl:9: AQUNUM:")
    assert not any("AQU" in n for n in deck.notes if "not needed for the grid" in n)
