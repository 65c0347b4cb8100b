"""The keyword vocabulary (facts from OPM opm-common 2022.10's keyword definitions) and skipping
a keyword's data by its shape, one test per shape."""

from __future__ import annotations

from pathlib import Path

import pytest

from gridlib.io.eclipse_text import DeckError
from gridlib.io.grdecl.keywords import open_source
from gridlib.io.grdecl.make_vocabulary import shape
from gridlib.io.grdecl.shapes import skip_data
from gridlib.io.grdecl.state import ReaderState
from gridlib.io.grdecl.vocabulary import Shape, vocabulary


def test_vocabulary_facts():
    v = vocabulary()
    assert len(v.names) > 1000
    assert v.get("GDORIENT").shape == Shape("records", 1)
    assert v.get("SWOF").shape.count_from == ("TABDIMS", 1, 1, 0, 1)  # NTSFUN, default 1
    assert v.get("PVTO").shape == Shape("tables", count_from=("TABDIMS", 2, 1, 0, 1))  # NTPVT
    assert v.get("PVTWSALT").shape.count_from == ("TABDIMS", 2, 1, 0, 2)  # two records per table
    assert v.get("ROCK").shape.kind == "open"
    assert v.get("EQUALS").shape.kind == "list" and "REGIONS" in v.get("EQUALS").sections
    assert v.get("ECHO").shape.kind == "none" and v.get("TABDIMS").shape == Shape("records", 1)
    assert v.get("ACTNUM").shape.kind == "data" and v.get("ACTNUM").sections == {"GRID"}
    assert v.get("SATNUM").sections == {"REGIONS"} and v.get("MULTX-").shape.kind == "data"
    assert v.get("BRINE").shape == Shape("records", 1, 0)
    assert v.get("TVDPXYZ").name == "TVDPXYZ"  # a family of names (TVDP.+)
    assert v.get("ACTNUMX") is None and "ACTNUMX" not in v and "FIPZONE" in v


def skipped_to(tmp_path: Path, text: str, name: str, state: ReaderState | None = None) -> str:
    """The text left after skipping keyword ``name``'s data (its keyword line is the first line)."""
    path = tmp_path / "x.inc"
    path.write_text(text)
    src = open_source(path)
    state = state or ReaderState(path)
    pos = skip_data(state, src, src.data.index(b"\n"), vocabulary().get(name))
    return src.data[pos:].decode().strip()


@pytest.mark.parametrize(
    ("name", "data"),
    [
        ("ECHO", ""),
        ("MAPAXES", " 1 2 3\n 4 5 6 / text\n"),
        ("GDORIENT", "INC\nINC INC DOWN RIGHT\n/\n"),
        ("EQUALS", " 'PORO' 0.1 / one\n PERMX 2 1 1 1 1 1 1 /\n/\n"),
        ("SWOF", " 0 0 1 0\n 1 1 0 0 /\n"),  # TABDIMS absent: its default, one table
        ("PVTO", " 1 100 1.1 1\n 200 1.0 1.1 /\n 2 150 1.2 1 /\n/\n"),  # one table, ended by '/'
        ("ROCK", " 200 1e-6 /\n 210 2e-6 /\n"),  # up to the next keyword
        ("MPFNNC", " 1 1 1 2 2 2 0.5 /\n/\n 1 1 1 1.0 /\n/\n/\n"),  # two empty records in a row
        ("DYNAMICR", " IF (FOO) THEN / \n ENDIF\nENDDYN\n"),
        ("BRINE", ""),  # up to one record, none here: a keyword follows
    ],
)
def test_skip_by_shape(tmp_path, name, data):
    assert skipped_to(tmp_path, f"{name}\n{data}PORO\n", name) == "PORO"


def test_records_counted_by_a_runspec_item(tmp_path):
    state = ReaderState(tmp_path / "x.inc")
    assert skipped_to(tmp_path, "TABDIMS\n 2 1 /\n", "TABDIMS", state) == ""
    assert state.size_records["TABDIMS"] == ["2", "1"]
    text = "SWOF\n 0 0 1 0\n 1 1 0 0 /\n 0 0 1 0 / second table\nPORO\n"
    assert skipped_to(tmp_path, text, "SWOF", state) == "PORO"
    state.size_records["TABDIMS"] = ["x"]
    with pytest.raises(DeckError, match="TABDIMS: item 1: 'x' is not an integer"):
        skipped_to(tmp_path, text, "SWOF", state)


def test_a_table_count_without_a_default_names_its_keyword(tmp_path):
    with pytest.raises(DeckError, match=r"x.inc:\d+: DISPERSE: its number of records is item 0 of DISPDIMS"):
        skipped_to(tmp_path, "DISPERSE\n 1 2 /\n/\n", "DISPERSE")


def test_make_vocabulary_shapes_follow_opm_size_rules():
    definitions = {
        "TABDIMS": {"name": "TABDIMS", "items": [{"name": "NTSFUN", "default": 1}, {"name": "NTPVT"}]}
    }
    cases = [
        ({"size": 0}, "none"),
        ({"size": 1, "items": []}, "records:1"),
        ({"size": 1, "min_size": 0, "items": []}, "records:1:0"),
        ({"size": "UNKNOWN", "items": []}, "open"),
        ({"size": {"keyword": "TABDIMS", "item": "NTSFUN"}, "items": []}, "sized:TABDIMS:1:1:0:1"),
        ({"size": {"keyword": "TABDIMS", "item": "NTPVT", "shift": 1}, "items": []}, "sized:TABDIMS:2:-:1:1"),
        (
            {"size": {"keyword": "TABDIMS", "item": "NTPVT"}, "alternating_records": [[], []]},
            "sized:TABDIMS:2:-:0:2",
        ),
        ({"num_tables": {"keyword": "TABDIMS", "item": "NTPVT"}, "items": []}, "tables:TABDIMS:2:-"),
        ({"records_set": [[], []]}, "sets"),
        ({"code": {"end": "ENDDYN"}}, "code:ENDDYN"),
        ({"data": {"value_type": "DOUBLE"}}, "data"),
        ({"items": []}, "list"),
        ({"records": [[], []]}, "list"),  # no size: slash-terminated, as opm-common reads it
        ({}, "none"),
    ]
    for spec, code in cases:
        assert shape(spec, definitions) == code, spec
        Shape.parse(code)  # every code the generator writes, the reader reads
