"""The deck syntax ECLIPSE allows and OPM Flow 2022.10 accepts, each form read by read_grdecl
and by Flow's dry run in the test: the same deck must give the same grid (dimensions, active
cells, pore volumes, every connection's transmissibility, within Flow's float32).

What Flow does, established with such decks (and opm-common 2022.10's Parser.cpp): text after
a record's '/' to the end of the line is a comment (a second record on that line is not read);
the rest of a keyword's line is ignored; records run over lines whatever their words; nested
INCLUDE paths are relative to the DATA file's directory; a keyword Flow does not know stops it.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest
from flow_tools import flow_connections, flow_executable, read_keywords, rest_of_deck, run_flow_dry

from gridlib.case import read_case_deck
from gridlib.config import load_case
from gridlib.cornerpoint.pore_volume import pore_volumes
from gridlib.errors import InputError
from gridlib.io.grdecl import DeckError, read_grdecl
from gridlib.transmissibility import deck_transmissibility

RUNSPEC = """RUNSPEC
DIMENS
 3 2 2 /
OIL
WATER
METRIC
TABDIMS
 1 1 20 20 /
EQLDIMS
 1 /
START
 1 'JAN' 2020 /
GRID
INIT
"""
# A 3 x 2 x 2 box grid, every cell's porosity and permeability different.
GEOMETRY = """DX
 12*100 /
DY
 12*50 /
DZ
 6*2 6*3 /
TOPS
 1000 1001 1002 1003 1004 1005 /
PERMX
 10 20 30 40 50 60 70 80 90 100 110 120 /
PERMY
 12*100 /
PERMZ
 12*10 /
"""
PORO = "PORO\n 0.10 0.11 0.12 0.13 0.14 0.15 0.16 0.17 0.18 0.19 0.20 0.21 /\n"


def write_deck(folder: Path, grid: str, runspec: str = RUNSPEC, files: dict[str, str] | None = None) -> Path:
    """CASE.DATA in ``folder``: RUNSPEC, GRID with the box grid and ``grid``, then PROPS to END;
    ``files`` are written beside it (paths relative to ``folder``)."""
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in (files or {}).items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text)
    deck = folder / "CASE.DATA"
    deck.write_text(runspec + GEOMETRY + grid + rest_of_deck(1000.0, 1010.0))
    return deck


def same_grid_as_flow(deck_path: Path, out: Path, **options):
    """read_grdecl's deck and Flow's dry run agree: dimensions, active cells, pore volumes (float32)
    and every connection's transmissibility (1e-6 relative). Returns the deck and Flow's INIT."""
    deck = read_grdecl(deck_path, **options)
    case = run_flow_dry(deck_path, out)
    egrid = read_keywords(Path(f"{case}.EGRID"))
    init = read_keywords(Path(f"{case}.INIT"))
    assert tuple(int(v) for v in egrid["GRIDHEAD"][1:4]) == deck.cart_dims
    flow_active = np.flatnonzero(egrid["ACTNUM"] > 0)
    np.testing.assert_array_equal(np.flatnonzero(deck.active), flow_active)
    np.testing.assert_allclose(pore_volumes(deck, flow_active), init["PORV"][flow_active], rtol=1e-6)
    ref = {pair: t for pair, t in flow_connections(case).items() if t > 0}
    c = deck_transmissibility(deck)
    ours = dict(zip(map(tuple, c.global_cells.tolist()), c.trans.tolist(), strict=True))
    assert set(ours) == set(ref)
    pairs = sorted(ref)
    np.testing.assert_allclose([ours[p] for p in pairs], [ref[p] for p in pairs], rtol=1e-6)
    return deck, init


def flow_refuses(deck_path: Path, out: Path) -> str:
    """Flow's dry run fails on the deck; its messages."""
    res = subprocess.run(
        [
            flow_executable(),
            "--enable-dry-run=true",
            "--threads-per-process=1",
            f"--output-dir={out}",
            str(deck_path),
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert res.returncode != 0
    return res.stdout + res.stderr


def test_records_over_lines_with_bare_words(tmp_path):
    grid = PORO + (
        "GDORIENT\nINC\nINC INC DOWN RIGHT\n/\n"  # the deck: five words over three lines
        "MULTZ\n12*1 /\nEQUALS\n 'MULTZ'\n 0.01\n 1 3 1 2\n 1 1\n/\n/\n"  # one record over five lines
    )
    deck, _ = same_grid_as_flow(write_deck(tmp_path, grid), tmp_path / "flow")
    np.testing.assert_array_equal(deck.cell_data["MULTZ"], [0.01] * 6 + [1.0] * 6)
    assert any("GDORIENT INC INC INC DOWN RIGHT" in n for n in deck.notes)


def test_text_after_a_slash_is_a_comment(tmp_path):
    grid = (
        "PORO\n 0.10 0.11 0.12 0.13 0.14 0.15 0.16 0.17 0.18 0.19 0.20 0.21 / porosity from the model\n"
        "MULTZ\n12*1 /\n"
        "EQUALS\n 'MULTZ' 0.01 1 3 1 2 1 1 / surface Mid_reek\n"
        " 'PORO' 0.3 1 1 1 1 1 1 / 'PORO' 0.4 2 2 1 1 1 1 /\n/\n"  # Flow reads only the first
    )
    deck, init = same_grid_as_flow(write_deck(tmp_path, grid), tmp_path / "flow")
    np.testing.assert_array_equal(deck.cell_data["PORO"][:3], [0.3, 0.11, 0.12])
    np.testing.assert_allclose(init["PORO"][:3], [0.3, 0.11, 0.12], rtol=1e-7)
    np.testing.assert_array_equal(deck.cell_data["MULTZ"], [0.01] * 6 + [1.0] * 6)


def test_comments_anywhere(tmp_path):
    grid = (
        "-- a comment line\nPORO -- a comment after the keyword\n"
        " -- a comment among the data\n"
        " 0.10 0.11 0.12 -- the first row\n 0.13 0.14 0.15--no blank before it\n"
        " 0.16 0.17 0.18 0.19 0.20 0.21 -- a / in a comment does not end the data\n/\n"
        "FAULTS -- fault names may hold '--' when quoted\n 'F--1' 1 1 1 2 1 2 X / the first fault\n/\n"
        "MULTFLT\n 'F--1' 0.1 / -- quarter\n/\n"
    )
    deck, _ = same_grid_as_flow(write_deck(tmp_path, grid), tmp_path / "flow")
    np.testing.assert_array_equal(deck.cell_data["PORO"], np.arange(10, 22) / 100)
    assert deck.multflt == {"F--1": 0.1}


def test_quoted_strings_with_blanks_and_slashes(tmp_path):
    files = {"a dir/the poro.inc": PORO}
    grid = (
        "INCLUDE\n 'a dir/the poro.inc' /\nFAULTS\n 'F /1' 1 1 1 2 1 2 'X' /\n/\nMULTFLT\n 'F /1' 0.1 /\n/\n"
    )
    deck, _ = same_grid_as_flow(write_deck(tmp_path, grid, files=files), tmp_path / "flow")
    assert [f.name for f in deck.faults] == ["F /1"] and deck.multflt == {"F /1": 0.1}


def test_repeat_counts_with_and_without_values(tmp_path):
    grid = (
        "PORO\n 6*0.1 6*0.2 /\nPORO\n 3* 3*0.15 6* /\n"  # n* leaves the values as they were
        "EQUALS\n PORO 0.3 2* 2 2 2* /\n/\n"  # defaulted box items: the whole grid
        "MULTIPLY\n PORO 2 1 1 1 1 1 1 /\n/\n"
    )
    deck, init = same_grid_as_flow(write_deck(tmp_path, grid), tmp_path / "flow")
    expected = [0.1, 0.1, 0.1, 0.3, 0.3, 0.3, 0.2, 0.2, 0.2, 0.3, 0.3, 0.3]
    expected[0] = 0.2
    np.testing.assert_allclose(deck.cell_data["PORO"], expected, rtol=1e-15)
    np.testing.assert_allclose(init["PORO"], expected, rtol=1e-7)


def test_lower_case_keywords(tmp_path):
    # Flow reads keywords in any case; the names inside EQUALS and MULTIPLY it wants in upper case.
    grid = "poro\n 12*0.1 /\nequals\n 'PORO' 0.2 1 1 1 1 1 1 /\n/\nMultiply\n PORO 2 2 2 1 1 1 1 /\n/\n"
    deck, _ = same_grid_as_flow(write_deck(tmp_path, grid), tmp_path / "flow")
    np.testing.assert_allclose(deck.cell_data["PORO"][:3], [0.2, 0.2, 0.1])


def test_keywords_without_data_and_the_rest_of_a_keyword_line(tmp_path):
    # ECHO/NOECHO/NEWTRAN take no '/'; the rest of a keyword's line is ignored (Flow reads PORO's
    # data from the next line), and a stray '/' between keywords is ignored as Flow does.
    grid = "NOECHO\nPORO 12*0.25 /\n 12*0.1 /\n/\nECHO\nNEWTRAN\nNTG\n 12*0.5 /\n"
    deck, _ = same_grid_as_flow(write_deck(tmp_path, grid), tmp_path / "flow")
    np.testing.assert_array_equal(deck.cell_data["PORO"], 0.1)
    assert any("text after the keyword on its line ignored" in n for n in deck.notes)
    assert any("a '/' where a keyword should be" in n for n in deck.notes)


def test_nested_include_is_relative_to_the_data_file(tmp_path):
    files = {
        "sub/a.inc": "INCLUDE\n 'b.inc' /\n",  # b.inc beside the DATA file, not sub/b.inc
        "sub/b.inc": "PORO\n 12*0.2 /\n",
        "b.inc": PORO,
    }
    deck, _ = same_grid_as_flow(
        write_deck(tmp_path, "INCLUDE\n 'sub/a.inc' /\n", files=files), tmp_path / "flow"
    )
    np.testing.assert_array_equal(deck.cell_data["PORO"], np.arange(10, 22) / 100)
    (tmp_path / "b.inc").unlink()  # only sub/b.inc: Flow and read_grdecl both refuse
    assert "No such file" in flow_refuses(tmp_path / "CASE.DATA", tmp_path / "flow2")
    with pytest.raises(DeckError, match=r"a.inc:2: INCLUDE: file 'b.inc' not found"):
        read_grdecl(tmp_path / "CASE.DATA")


def test_paths_aliases(tmp_path):
    runspec = RUNSPEC.replace("START", "PATHS\n 'INC' 'my dir' /\n 'K' 'perm' /\n/\nSTART")
    files = {"my dir/poro.inc": PORO, "perm/k.inc": "PERMX\n 12*50 /\n"}
    grid = "INCLUDE\n '$INC/poro.inc' /\nINCLUDE\n '$K/k.inc' /\n"
    deck, _ = same_grid_as_flow(write_deck(tmp_path, grid, runspec, files), tmp_path / "flow")
    np.testing.assert_array_equal(deck.cell_data["PERMX"], 50.0)
    bad = write_deck(tmp_path / "bad", "INCLUDE\n '$NONE/poro.inc' /\n", runspec, files)
    with pytest.raises(DeckError, match=r"CASE.DATA:\d+: INCLUDE: path alias \$NONE is not defined"):
        read_grdecl(bad)


def test_mapaxes_and_gridunit(tmp_path):
    grid = PORO + "MAPAXES\n 0.0 100.0\n 0.0 0.0 100.0 0.0 / over two lines\nGRIDUNIT\n METRES /\n"
    deck, _ = same_grid_as_flow(write_deck(tmp_path, grid), tmp_path / "flow")
    egrid = read_keywords(tmp_path / "flow" / "CASE.EGRID")
    np.testing.assert_array_equal(deck.mapaxes, egrid["MAPAXES"])
    assert deck.gridunit == "METRES" == egrid["GRIDUNIT"][0].decode().strip()


@pytest.mark.parametrize(
    ("units", "gridunit", "factor"),
    [
        ("METRIC", "FEET", 0.3048),
        ("METRIC", "CM", 0.01),
        ("FIELD", "METRES", 1 / 0.3048),
        ("FIELD", "FEET", 1.0),
    ],
)
def test_a_grid_in_another_length_unit_is_converted_as_flow_converts_it(tmp_path, units, gridunit, factor):
    """GRIDUNIT gives the grid's length unit: where it is not the deck's, COORD and ZCORN (here
    built from DX/DY/DZ/TOPS) are scaled to the deck's, as Flow does (before, the grid was read
    as if in the deck's unit: pore volumes and T of another size)."""
    runspec = RUNSPEC.replace("METRIC", units)
    plain = read_grdecl(write_deck(tmp_path / "plain", PORO, runspec))
    deck, _ = same_grid_as_flow(
        write_deck(tmp_path / "scaled", PORO + f"GRIDUNIT\n {gridunit} /\n", runspec), tmp_path / "flow"
    )
    np.testing.assert_array_equal(deck.zcorn, plain.zcorn * factor if factor != 1.0 else plain.zcorn)
    assert any(n.startswith(f"GRIDUNIT {gridunit} in a {units} deck") for n in deck.notes) == (factor != 1.0)


def test_an_unknown_gridunit_is_named(tmp_path):
    with pytest.raises(DeckError, match=r"CASE.DATA: GRIDUNIT: unknown length unit 'YARDS'"):
        read_grdecl(write_deck(tmp_path, PORO + "GRIDUNIT\n YARDS /\n"))


def test_commas_separate_items(tmp_path):
    grid = "PORO\n 12*0.1,\n/\nEQUALS\n 'PORO',0.2,1,1,1,1,1,1 /\n/\n"
    deck, _ = same_grid_as_flow(write_deck(tmp_path, grid), tmp_path / "flow")
    np.testing.assert_array_equal(deck.cell_data["PORO"][:2], [0.2, 0.1])


def test_props_and_regions_are_read_and_their_tables_skipped_by_shape(tmp_path):
    # Two saturation tables (TABDIMS item 1) without a closing empty record, ROCK (ended by the
    # next keyword); REGIONS' cell keywords are kept; MINPVFIL is a keyword only Flow knows.
    runspec = RUNSPEC.replace(" 1 1 20 20 /", " 2 1 20 20 /")
    rest = (
        "PROPS\nSWOF\n 0.0 0.0 1.0 0.0\n 1.0 1.0 0.0 0.0 /\n 0.0 0.0 1.0 0.0\n 1.0 1.0 0.0 0.0 /\n"
        "PVTW\n 200.0 1.0 3.0e-6 0.5 0.0 /\nPVDO\n 100.0 1.01 1.0\n 400.0 1.00 1.0 /\n"
        "DENSITY\n 800 1000 1 /\nROCK\n 200.0 1.0e-6 /\nSWL\n 12*0.1 /\n"
        "REGIONS\nSATNUM\n 6*1 6*2 /\nFIPNUM\n 1 2 3 4 5 6 7 8 9 10 11 12 /\n"
        "EQUALS\n FIPNUM 20 1 1 1 1 1 1 /\n/\n"
        "SOLUTION\nEQUIL\n 1000 200.0 1010 0 1000 0 /\nSCHEDULE\nTSTEP\n 1 /\nEND\n"
    )
    deck_path = tmp_path / "CASE.DATA"
    deck_path.write_text(runspec + GEOMETRY + PORO + "MINPVFIL\n 1e-9 /\n" + rest)
    deck, init = same_grid_as_flow(deck_path, tmp_path / "flow")
    np.testing.assert_array_equal(deck.cell_data["SATNUM"], init["SATNUM"])
    np.testing.assert_array_equal(deck.cell_data["FIPNUM"], init["FIPNUM"])
    assert deck.cell_data["FIPNUM"][0] == 20
    np.testing.assert_array_equal(deck.cell_data["SWL"], 0.1)
    assert any("SWOF" in n and "ROCK" in n and "MINPVFIL" in n for n in deck.notes)


def test_an_unknown_keyword_names_its_file_and_line(tmp_path):
    files = {"grid.inc": PORO + "ACTNUMX\n 11*1 0 /\n"}
    deck_path = write_deck(tmp_path, "INCLUDE\n 'grid.inc' /\n", files=files)
    assert "Unknown keyword: ACTNUMX" in flow_refuses(deck_path, tmp_path / "flow")
    with pytest.raises(DeckError, match=r"grid.inc:3: unknown keyword 'ACTNUMX'"):
        read_grdecl(deck_path)
    deck = read_grdecl(deck_path, unknown_keywords="skip")  # skipped: all 12 cells stay active
    assert deck.active.all() and any("ACTNUMX (grid.inc:3)" in n for n in deck.notes)
    # A misspelling that is not a keyword name at all: an error either way (Flow: "not formatted
    # as valid keyword"); before, 'ACT!NUM' was read and 12 cells were active instead of 11.
    (tmp_path / "grid.inc").write_text(PORO + "ACT!NUM\n 11*1 0 /\n")
    assert "not formatted as valid keyword" in flow_refuses(deck_path, tmp_path / "flow2")
    for option in ("error", "skip"):
        with pytest.raises(DeckError, match=r"grid.inc:3: expected a keyword, found 'ACT!NUM'"):
            read_grdecl(deck_path, unknown_keywords=option)


def test_deck_case_option_and_arrays(tmp_path):
    deck_path = write_deck(tmp_path, PORO + "FLUXNUM\n 6*1 6*2 /\nFOOBAR\n 1 2 3 /\n")
    deck_path.write_text(deck_path.read_text().replace("SOLUTION", "REGIONS\nSATNUM\n 12*1 /\nSOLUTION"))
    case_file = tmp_path / "case.yaml"
    case_file.write_text("name: case\ngrid: {type: deck, file: CASE.DATA}\n")
    # Refused when the case is read (its deck gives the rock), naming the case, the deck and the line
    with pytest.raises(InputError, match=r"case.yaml: grid.file: .*CASE.DATA:\d+: unknown keyword 'FOOBAR'"):
        load_case(case_file)
    case_file.write_text("name: case\ngrid: {type: deck, file: CASE.DATA, unknown_keywords: skip}\n")
    deck = read_case_deck(load_case(case_file))
    assert deck.cart_dims == (3, 2, 2) and any("FOOBAR" in n for n in deck.notes)
    # The case keeps the arrays a GRID section may hold; SATNUM (REGIONS only) is read_grdecl's.
    assert {"PORO", "FLUXNUM"} <= set(deck.cell_data) and "SATNUM" not in deck.cell_data
    assert any("PROPS/REGIONS arrays not used by the case: SATNUM" in n for n in deck.notes)
    assert "SATNUM" in read_grdecl(deck_path, unknown_keywords="skip").cell_data


REGIONS = """MULTNUM
 1 2 1 2 1 2 1 2 1 2 1 2 /
FLUXNUM
 1 1 2 2 3 3 1 1 2 2 3 3 /
OPERNUM
 2 2 2 1 1 1 2 2 2 1 1 1 /
"""


@pytest.mark.parametrize(
    "edits",
    [
        "EQUALREG\n PERMY 55 2 /\n PERMZ 7 3 F /\n/\n",
        "MULTIREG\n PERMX 3 1 M /\n PORO 1.5 2 O /\n/\nADDREG\n PERMY 10 1 F /\n/\n",
        "COPYREG\n PERMX PERMZ 2 M /\n/\n",
        "OPERATE\n NTG 1 3 1 1 1 1 MULTA PORO 2 0.1 /\n PERMX 1 3 2 2 2 2 MAXLIM PERMX 50 /\n/\n",
        "OPERATER\n PERMZ 1 MULTX PERMY 0.1 /\n PERMY 2 COPY PERMX 1* 1* FLUXNUM /\n/\n",
        "MULTREGP\n 1 0.5 F /\n 2 3.0 /\n 2 2.0 /\n/\n",
        "EDIT\nPORV\n 12*30 /\nOPERATE\n PORV 2 2 1 1 1 1 MULTX PORV 2.0 /\n/\n",
    ],
    ids=["equalreg", "multireg-addreg", "copyreg", "operate", "operater", "multregp", "operate-porv"],
)
def test_region_and_operate_edits_change_the_grid_as_flow_changes_it(tmp_path, edits):
    """EQUALREG, MULTIREG, ADDREG, COPYREG (region sets M, the default, F and O all different
    here), OPERATE, OPERATER and MULTREGP: Flow applies them to the arrays the grid's pore volumes
    and T come from; gridlib skipped them as keywords 'not needed for the grid' (T and pore
    volumes silently different)."""
    deck, _ = same_grid_as_flow(write_deck(tmp_path, PORO + REGIONS + edits), tmp_path / "flow")
    skipped = " ".join(note for note in deck.notes if "skipped keywords" in note)
    assert not any(k in skipped for k in ("REG", "OPERATE")), skipped


def test_operater_operates_in_the_decks_units(tmp_path):
    """OPERATER's POLY, PERMY + 2 PERMX^0.5 on FLUXNUM region 2, in mD as the manuals define it
    and OPM Flow does since 2023 (Flow 2022.10 applied OPERATER, not OPERATE, to its SI values:
    a permeability of 3.5e8 mD for 30 mD; the linear operations agree, the test above)."""
    edits = "OPERATER\n PERMY 2 POLY PERMX 2 0.5 FLUXNUM /\n/\n"
    deck = read_grdecl(write_deck(tmp_path, PORO + REGIONS + edits))
    permx = np.arange(10.0, 130.0, 10.0)
    expected = np.where(np.isin(np.arange(12), [2, 3, 8, 9]), 100.0 + 2.0 * np.sqrt(permx), 100.0)
    np.testing.assert_array_equal(deck.cell_data["PERMY"], expected)


def test_a_lone_star_is_one_defaulted_item(tmp_path):
    """'*' alone in a record is '1*' (Flow reads it so; gridlib took it for a value)."""
    grid = PORO + "EQUALS\n PERMX 50 2 2 * * 1 1 /\n/\nPINCH\n 0.5 * * TOPBOT /\n"
    deck, _ = same_grid_as_flow(write_deck(tmp_path, grid), tmp_path / "flow")
    np.testing.assert_array_equal(deck.cell_data["PERMX"][:6], [10, 50, 30, 40, 50, 60])


ROCK = "PERMX\n 12*100 /\nPERMY\n 12*100 /\nPERMZ\n 12*10 /\n" + PORO


def _box_deck(folder: Path, geometry: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    deck = folder / "CASE.DATA"
    deck.write_text(RUNSPEC + geometry + ROCK + rest_of_deck(1000.0, 1010.0))
    return deck


@pytest.mark.parametrize(
    "geometry",
    [
        "DX\n 6*100 /\nDY\n 6*50 /\nDZ\n 6*2 /\nTOPS\n 6*1000 /\n",  # the top layer only
        "DX\n 6*100 /\nDY\n 6*50 /\nDZ\n 6*2 3 /\nTOPS\n 6*1000 1002 1002 /\n",  # and part of the next
        "DX\n 12*100 /\nDY\n 12*50 /\nDZ\n 12*2 /\nTOPS\n 6*1000 1002.0000003 1001.9999998 4*1002 /\n",
    ],
    ids=["top-layer", "part-of-the-second", "tops-off-by-3e-7"],
)
def test_cartesian_keywords_for_the_upper_cells_only_and_rounded_tops(tmp_path, geometry):
    """DX/DY/DZ given for the top layer (or more) only: the cells below take the value of the cell
    above; TOPS: the bottom of the cell above; a TOPS within 1e-6 m of the bottom above is that
    bottom (printed TOPS rounded left a gap of 3e-7, which gridlib refused as overlapping
    layers, and Flow closes). As Flow does; gridlib refused the first two ("has 6 values")."""
    deck, _ = same_grid_as_flow(_box_deck(tmp_path, geometry), tmp_path / "flow")
    assert deck.cart_dims == (3, 2, 2)


def test_partial_tops_are_used_where_given(tmp_path):
    """TOPS for the top layer and one cell below, off the bottom of the cell above: that cell's
    top is the given one, as ECLIPSE (and OPM Flow since 2023) take it; Flow 2022.10 ignores
    TOPS below the top layer when it does not give all cells."""
    geometry = "DX\n 12*100 /\nDY\n 12*50 /\nDZ\n 12*2 /\nTOPS\n 6*1000 1005 /\n"
    deck = read_grdecl(_box_deck(tmp_path, geometry))
    top = deck.zcorn.reshape(4, 4, 6)[2]  # the second layer's top corners
    np.testing.assert_array_equal(top[:2, :2], 1005.0)  # cell (1, 1, 2), given
    np.testing.assert_array_equal(top[:2, 2:], 1002.0)  # cell (2, 1, 2), the bottom above


def test_mapaxes_with_a_seventh_value_reads_the_first_six(tmp_path):
    """Flow reads the first six values of a MAPAXES that has more (an OPM test deck has seven)."""
    grid = PORO + "MAPAXES\n 0.0 100.0 0.0 0.0 100.0 0.0 5.0 /\n"
    deck, _ = same_grid_as_flow(write_deck(tmp_path, grid), tmp_path / "flow")
    egrid = read_keywords(tmp_path / "flow" / "CASE.EGRID")
    np.testing.assert_array_equal(deck.mapaxes, egrid["MAPAXES"])
    assert any("MAPAXES: 7 values, the first 6 read" in n for n in deck.notes)
    with pytest.raises(DeckError, match=r"CASE.DATA:\d+: MAPAXES: has 5 values, expected 6"):
        read_grdecl(write_deck(tmp_path / "five", PORO + "MAPAXES\n 0 100 0 0 100 /\n"))
