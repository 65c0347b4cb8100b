"""io.connection_records: MULTREGT, GRIDOPTS, NNC and EDITNNC records, exact values and errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from gridlib.io.connection_records import cell_pair_record, gridopts_record, multregt_record
from gridlib.io.eclipse_text import DeckError, Source

SRC = Source(Path("deck.grdecl"), b"-- line 1\nRECORD\n")
AT = 10  # line 2


def test_multregt_record_defaults_and_every_region():
    r = multregt_record(SRC, AT, "MULTREGT", ["1", "-1", "0.5"])
    assert (r.region1, r.region2, r.multiplier, r.directions, r.nnc_option, r.region_set) == (
        1,
        None,
        0.5,
        "XYZ",
        "ALL",
        None,
    )
    assert r.source == "deck.grdecl:2"
    r = multregt_record(SRC, AT, "MULTREGT", [None, "2", "2D-1", "xy", "nnc", "m"])
    assert (r.region1, r.region2, r.multiplier, r.directions, r.nnc_option, r.region_set) == (
        None,
        2,
        0.2,
        "XY",
        "NNC",
        "M",
    )
    with pytest.raises(DeckError, match=r"deck\.grdecl:2: MULTREGT: a record needs a multiplier"):
        multregt_record(SRC, AT, "MULTREGT", ["1", "2"])
    with pytest.raises(DeckError, match="a record has 7 items, at most 6"):
        multregt_record(SRC, AT, "MULTREGT", ["1", "2", "1", "X", "ALL", "M", "extra"])


def test_gridopts_record():
    g = gridopts_record(SRC, AT, "GRIDOPTS", ["yes", "3"])
    assert (g.tranmult, g.nrmult, g.nrpinc) == (True, 3, 0)
    g = gridopts_record(SRC, AT, "GRIDOPTS", [])
    assert (g.tranmult, g.nrmult, g.nrpinc) == (False, 0, 0)
    with pytest.raises(DeckError, match="TRANMULT must be YES or NO, got 'maybe'"):
        gridopts_record(SRC, AT, "GRIDOPTS", ["maybe"])
    with pytest.raises(DeckError, match="NRMULT: 'x' is not an integer"):
        gridopts_record(SRC, AT, "GRIDOPTS", ["NO", "x"])


def test_cell_pair_records():
    dims = (3, 2, 2)
    # (1,1,1) -> 0, (3,2,2) -> 2 + 3 * (1 + 2 * 1) = 11
    assert cell_pair_record(SRC, AT, "NNC", ["1", "1", "1", "3", "2", "2", "0.75"], dims) == (
        0,
        11,
        0.75,
        False,
    )
    assert cell_pair_record(SRC, AT, "NNC", ["2", "1", "1", "2", "2", "1"], dims) == (1, 4, None, False)
    assert cell_pair_record(SRC, AT, "EDITNNC", ["1", "1", "1", "1", "1", "2", "2", "1"], dims) == (
        0,
        6,
        2.0,
        True,
    )
    with pytest.raises(DeckError, match=r"cell \(4, 1, 1\) is not inside the 3x2x2 grid"):
        cell_pair_record(SRC, AT, "NNC", ["4", "1", "1", "1", "1", "1", "1"], dims)
    with pytest.raises(DeckError, match=r"cell \(1, 1, 1\) is joined to itself"):
        cell_pair_record(SRC, AT, "NNC", ["1", "1", "1", "1", "1", "1", "1"], dims)
    with pytest.raises(DeckError, match="multiplier must be >= 0"):
        cell_pair_record(SRC, AT, "EDITNNC", ["1", "1", "1", "2", "1", "1", "-1"], dims)
