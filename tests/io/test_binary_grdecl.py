"""Binary GRDECL (``.bgrdecl``, a deck's IMPORT): the keywords of a GRDECL as ECLIPSE's keyword
records, read into the same deck as the text, checked with the text's messages (the file and the
keyword's number in it), as RMS and xtgeo write them."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import resfo

from gridlib.cornerpoint.generators import simple_grdecl
from gridlib.io.grdecl import DeckError, read_grdecl, write_grdecl
from gridlib.io.grdecl.dimens import deck_dimensions
from gridlib.io.registry import read

SIXCELLS = Path(__file__).resolve().parents[1] / "data" / "decks" / "sixcells2"


def _deck():
    """A 3 x 2 x 2 deck with MAPAXES, ACTNUM and rock whose values are float32 numbers."""
    deck = simple_grdecl((3, 2, 2), phys_dims=(300.0, 200.0, 20.0))
    deck = replace(
        deck,
        coord=deck.coord.astype(np.float32).astype(np.float64),
        zcorn=(deck.zcorn + 1000.0).astype(np.float32).astype(np.float64),
        actnum=np.array([1, 1, 0, 1, 1, 1, 1, 1, 1, 1, 0, 1], np.int32),
        mapaxes=np.array([456000.0, 5930000.0, 456000.0, 5929000.0, 457000.0, 5929000.0]),
    )
    rock = {
        "PORO": np.linspace(0.1, 0.3, 12).astype(np.float32).astype(np.float64),
        "PERMX": np.arange(12, dtype=np.float64) * 10.0 + 5.0,
    }
    return deck, rock


def _binary(path: Path, deck, rock, extra=(), order=None) -> Path:
    records = [
        ("MAPAXES ", deck.mapaxes.astype(np.float32)),
        ("SPECGRID", np.array([*deck.cart_dims, 1], np.int32)),
        ("COORD   ", deck.coord.astype(np.float32)),
        ("ZCORN   ", deck.zcorn.astype(np.float32)),
        ("ACTNUM  ", deck.actnum.astype(np.int32)),
        *((f"{k:<8}", v.astype(np.float32)) for k, v in rock.items()),
        *extra,
    ]
    resfo.write(path, records if order is None else [records[i] for i in order])
    return path


def test_a_binary_grdecl_is_the_deck_its_text_is(tmp_path):
    deck, rock = _deck()
    text = read_grdecl(write_grdecl(tmp_path / "m.grdecl", deck, rock))
    binary = read_grdecl(_binary(tmp_path / "m.bgrdecl", deck, rock))
    assert binary.cart_dims == text.cart_dims == (3, 2, 2)
    for name in ("coord", "zcorn", "actnum", "mapaxes"):
        np.testing.assert_array_equal(getattr(binary, name), getattr(text, name), err_msg=name)
    assert sorted(binary.cell_data) == sorted(text.cell_data) == ["PERMX", "PORO"]
    for name, values in text.cell_data.items():
        np.testing.assert_array_equal(binary.cell_data[name], values, err_msg=name)
    assert deck_dimensions(tmp_path / "m.bgrdecl") == (3, 2, 2)
    np.testing.assert_array_equal(read(tmp_path / "m.bgrdecl", "deck").zcorn, text.zcorn)  # the suffix


def test_a_deck_imports_a_binary_grdecl(tmp_path):
    deck, _ = _deck()
    _binary(tmp_path / "GRID.BGRDECL", deck, {})
    (tmp_path / "M.DATA").write_text(
        "RUNSPEC\nDIMENS\n 3 2 2 /\nGRID\nIMPORT\n 'GRID.BGRDECL' /\n"
        "PORO\n 12*0.2 /\nMULTIPLY\n 'PORO' 0.5 /\n/\n"
    )
    read_in = read_grdecl(tmp_path / "M.DATA")
    np.testing.assert_array_equal(read_in.zcorn, deck.zcorn)
    np.testing.assert_array_equal(read_in.actnum, deck.actnum)
    np.testing.assert_array_equal(read_in.cell_data["PORO"], np.full(12, 0.1))


def test_rms_sixcells_binary_export_is_its_text_export():
    """RMS's text and binary exports of one grid (xtgeo-testdata's sixcells2, with MAPAXES; the
    binary has no MAPUNITS, GRIDUNIT or GDORIENT): the same corners, cells and MAPAXES."""
    text = read_grdecl(SIXCELLS / "sixcells2_hdr2.grdecl")
    binary = read_grdecl(SIXCELLS / "sixcells2_hdr2.bgrdecl")
    assert binary.cart_dims == text.cart_dims == (2, 1, 3)
    for name in ("coord", "zcorn", "actnum", "mapaxes"):
        np.testing.assert_array_equal(getattr(binary, name), getattr(text, name), err_msg=name)
    assert text.mapunits == "METRES" and binary.mapunits is None


@pytest.mark.parametrize(
    ("extra", "order", "message"),
    [
        ((("Zone    ", np.ones(12, np.int32)),), None, r"m.bgrdecl:keyword 8: unknown keyword 'Zone'"),
        ((), (0, 2, 1, 3, 4, 5, 6), r"m.bgrdecl:keyword 2: COORD: the grid dimensions are not known yet"),
        (
            (("NTG     ", np.ones(11, np.float32)),),
            None,
            r"m.bgrdecl:keyword 8: NTG: has 11 values, expected 12",
        ),
        (
            (("PERMY   ", np.full(12, np.nan, np.float32)),),
            None,
            r"m.bgrdecl:keyword 8: PERMY: 12 values are not finite numbers \(first nan\): cells \(1, 1, 1\)",
        ),
        ((("MAPUNITS", np.array([1.0], np.float32)),), None, None),  # not text: read as text, no error
    ],
)
def test_a_bad_binary_grdecl_names_the_file_and_the_keyword(tmp_path, extra, order, message):
    deck, rock = _deck()
    path = _binary(tmp_path / "m.bgrdecl", deck, rock, extra, order)
    if message is None:
        read_grdecl(path)
        return
    with pytest.raises(DeckError, match=message):
        read_grdecl(path)


def test_unknown_keywords_of_a_binary_grdecl_are_skipped_on_request(tmp_path):
    deck, rock = _deck()
    path = _binary(tmp_path / "m.bgrdecl", deck, rock, (("Zone    ", np.ones(12, np.int32)),))
    read_in = read_grdecl(path, unknown_keywords="skip")
    assert any("Zone (m.bgrdecl:keyword 8)" in note for note in read_in.notes)
    assert sorted(read_in.cell_data) == ["PERMX", "PORO"]


def test_a_damaged_binary_grdecl_is_one_error(tmp_path):
    deck, rock = _deck()
    data = _binary(tmp_path / "whole.bgrdecl", deck, rock).read_bytes()
    (tmp_path / "cut.bgrdecl").write_bytes(data[: len(data) // 2])
    with pytest.raises(DeckError, match=r"cut.bgrdecl: not a readable binary GRDECL file"):
        read_grdecl(tmp_path / "cut.bgrdecl")
