"""A deck case keeps its deck's EDIT section through the stages.

The faulted anisotropic deck of ``deck_cases`` (``test_deck_rock``'s) with an NNC keyword record in GRID and
an EDIT section that gives PORV by BOX (over cells with a MULTPV), multiplies TRANX in a
box, sets TRANY (``1*`` leaving a value as Flow computes it), multiplies MULTX- again
(Flow: the EDIT array multiplies the GRID one) and multiplies, by EDITNNC, a fault
connection and the NNC keyword's value. Flow's dry run of the case's written deck must
equal its dry run of the original (active cells, connections and T, pore volumes, 1e-6
relative: INIT is float32), and so must ``transmissibility.nc`` and ``grid.grdecl`` included
as it is in a deck's GRID section.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from deck_cases import (
    DIMS,
    GRID_KEYWORDS,
    assert_close,
    assert_stage_file_equals_flow,
    build,
    write_case,
    write_deck,
)
from flow_tools import flow_connections, read_keywords, run_flow_dry

from gridlib.io.grdecl import read_grdecl, write_edit_grdecl, write_grdecl
from gridlib.io.transmissibility_file import read_transmissibility

ROCK_KEYWORDS = ("PORO", "PERMX", "PERMY", "PERMZ", "NTG", "FLUXNUM", "MULTNUM")
PORV_BOX = (2, 3, 2, 4, 1, 2)  # 1-based I1 I2 J1 J2 K1 K2
PORV_VALUES = 1000.0 + 37.5 * np.arange(12)  # rm3, i fastest over the box
NNC_PAIR = ((1, 1, 1), (6, 5, 4))
FAULT_PAIR = ((3, 2, 2), (4, 2, 1))  # across the fault (throw 12 m, layers 10 m)

GRID_WITH_NNC = (
    GRID_KEYWORDS
    + "EQUALS\n 'MULTPV' 1.5 1 6 1 5 1 2 /\n/\n"  # on the PORV box too: there PORV wins
    + "NNC\n {} {} {} {} {} {} 0.7 /\n/\n".format(*NNC_PAIR[0], *NNC_PAIR[1])
)
EDIT = (
    "EDIT\nBOX\n {} {} {} {} {} {} /\n".format(*PORV_BOX)
    + "PORV\n "
    + " ".join(map(repr, PORV_VALUES.tolist()))
    + " /\nENDBOX\n"
    "MULTIPLY\n 'TRANX' 0.5 1 3 1 5 1 4 /\n/\n"
    "BOX\n 1 3 1 1 1 1 /\nTRANY\n 2.5 1* 7.25 /\nENDBOX\n"
    "BOX\n 2 2 1 5 2 2 /\nMULTX-\n 5*3.0 /\nENDBOX\n"
    "EDITNNC\n"
    " {} {} {} {} {} {} 0.25 /\n".format(*FAULT_PAIR[0], *FAULT_PAIR[1])
    + " {} {} {} {} {} {} 2.0 /\n".format(*NNC_PAIR[0], *NNC_PAIR[1])
    + "/\n"
)


def edited_deck(folder: Path) -> Path:
    """ANISO.DATA with the NNC keyword in GRID and the EDIT section above."""
    deck = write_deck(folder, ROCK_KEYWORDS, GRID_WITH_NNC)
    text = deck.read_text()
    assert text.count("PROPS\n") == 1
    deck.write_text(text.replace("PROPS\n", EDIT + "PROPS\n"))
    return deck


def linear(ijk: tuple[int, int, int]) -> int:
    nx, ny, _ = DIMS
    i, j, k = ijk
    return (i - 1) + nx * ((j - 1) + ny * (k - 1))


def porv_box_cells() -> np.ndarray:
    i1, i2, j1, j2, k1, k2 = PORV_BOX
    return np.array(
        [linear((i, j, k)) for k in range(k1, k2 + 1) for j in range(j1, j2 + 1) for i in range(i1, i2 + 1)]
    )


@pytest.fixture(scope="module")
def original(tmp_path_factory) -> tuple[Path, Path]:
    """The original deck and Flow's dry run of it."""
    folder = tmp_path_factory.mktemp("edit")
    deck = edited_deck(folder / "deck")
    return deck, run_flow_dry(deck, folder / "flow_original")


def test_the_edit_section_round_trips(original, tmp_path):
    """grid.grdecl's EDIT part, and the EDIT include alone, read back as the deck's."""
    deck = read_grdecl(original[0])
    assert deck.tran_edits and deck.editnnc.num == 2 and deck.nnc_keyword.num == 1
    back = read_grdecl(write_grdecl(tmp_path / "grid.grdecl", deck))
    np.testing.assert_array_equal(back.cell_data["PORV"], deck.cell_data["PORV"])  # NaN where Flow computes
    for name in ("MULTPV", "MULTX-", "PORO"):
        np.testing.assert_array_equal(back.cell_data[name], deck.cell_data[name])
    assert [(e.keyword, e.operation, e.box, e.value) for e in back.tran_edits] == [
        (e.keyword, e.operation, e.box, e.value) for e in deck.tran_edits
    ]
    np.testing.assert_array_equal(back.tran_edits[1].values, [2.5, np.nan, 7.25])
    for name in ("editnnc", "nnc_keyword"):
        np.testing.assert_array_equal(getattr(back, name).cells, getattr(deck, name).cells)
        np.testing.assert_array_equal(getattr(back, name).values, getattr(deck, name).values)

    grid_only = read_grdecl(write_grdecl(tmp_path / "g.grdecl", deck, edit=False))
    assert "PORV" not in grid_only.cell_data and not grid_only.tran_edits and grid_only.editnnc is None
    edit_text = write_edit_grdecl(tmp_path / "e.inc", deck).read_text()
    lines = edit_text.splitlines()
    assert lines.count("PORV") == 6 and lines.count("BOX") == 7  # a box per run along i, and TRANY's
    assert "EDITNNC" in lines and "MULTX-" not in lines  # the EDIT MULTX- is in the GRID part's MULTX-
    assert write_edit_grdecl(tmp_path / "none.inc", grid_only) is None


def test_deck_case_gives_flow_the_original_decks_edit_section(original, tmp_path, caplog):
    """No petrophysics section: Flow on the written deck computes what it computes on the
    original, and transmissibility.nc holds the same."""
    deck, ref_case = original
    case = write_case(deck.parent, "edited")
    with caplog.at_level("INFO", logger="gridlib.stages"):
        paths = build(case, tmp_path / "out", flow_deck=True)
    assert (
        "ends with the deck's EDIT section (PORV of 12 cells, 2 TRANX/TRANY/TRANZ operations, " in caplog.text
    )
    assert (paths["flow_deck"].parent / "EDITED_EDIT.INC").is_file()
    new_case = run_flow_dry(paths["flow_deck"], tmp_path / "flow_written")

    ref_egrid, new_egrid = read_keywords(Path(f"{ref_case}.EGRID")), read_keywords(Path(f"{new_case}.EGRID"))
    np.testing.assert_array_equal(new_egrid["ACTNUM"], ref_egrid["ACTNUM"])
    ref, new = flow_connections(ref_case), flow_connections(new_case)
    assert_close(new, ref, "Flow on the written deck")
    ref_init, new_init = read_keywords(Path(f"{ref_case}.INIT")), read_keywords(Path(f"{new_case}.INIT"))
    assert np.all(np.abs(new_init["PORV"] - ref_init["PORV"]) <= 1e-6 * ref_init["PORV"])

    # the EDIT section acted in Flow: PORV as given, the EDITNNC'd NNC value, TRANX halved
    box = porv_box_cells()
    assert np.allclose(ref_init["PORV"][box], PORV_VALUES, rtol=1e-6)
    nnc = tuple(sorted(map(linear, NNC_PAIR)))
    assert ref[nnc] == pytest.approx(1.4, rel=1e-6)

    _, attrs = assert_stage_file_equals_flow(paths["transmissibility"], ref, ref_init["PORV"])
    assert "the PORV of the deck's EDIT section in 12 of 120 grid cells" in attrs["notes"]

    # grid.grdecl itself, INCLUDEd in GRID, opens the EDIT section: Flow reads it as the deck
    data = paths["flow_deck"].read_text()
    edit_include = "EDIT\n\nINCLUDE\n 'EDITED_EDIT.INC' /\n"
    assert data.count(edit_include) == 1 and data.count("'EDITED_GRID.INC'") == 1
    data = data.replace(edit_include, "").replace("'EDITED_GRID.INC'", "'../grid.grdecl'")
    by_hand = paths["flow_deck"].with_name("BY_HAND.DATA")
    by_hand.write_text(data)
    hand_case = run_flow_dry(by_hand, tmp_path / "flow_by_hand")
    assert_close(flow_connections(hand_case), ref, "Flow on grid.grdecl")
    hand_porv = read_keywords(Path(f"{hand_case}.INIT"))["PORV"]
    assert np.all(np.abs(hand_porv - ref_init["PORV"]) <= 1e-6 * ref_init["PORV"])


def test_a_case_porosity_leaves_the_decks_porv(original, tmp_path, caplog):
    """A case's porosity replaces PORO, not the deck's EDIT PORV (Flow's rule): the PORV cells keep
    their pore volume, the others follow the case; a note says so; Flow agrees on the written deck."""
    deck, ref_case = original
    case = write_case(deck.parent, "porous", {"porosity": {"constant": 0.3}})
    with caplog.at_level("INFO", logger="gridlib.stages"):
        paths = build(case, tmp_path / "out", flow_deck=True)
    assert "petrophysics.porosity leaves the pore volume of those 12 cells as the deck's PORV" in caplog.text
    new_case = run_flow_dry(paths["flow_deck"], tmp_path / "flow_written")
    new_init = read_keywords(Path(f"{new_case}.INIT"))
    ref_init = read_keywords(Path(f"{ref_case}.INIT"))

    variables, _ = read_transmissibility(paths["transmissibility"])
    glob = variables["cell_flow_index"].values
    porv = variables["porv"].values
    flow_porv = new_init["PORV"][glob].astype(np.float64)
    assert np.all(np.abs(porv - flow_porv) <= 1e-6 * flow_porv)
    box = np.isin(glob, porv_box_cells())
    np.testing.assert_array_equal(porv[box], PORV_VALUES)  # box cells in grid order: i fastest
    with xr.open_dataset(paths["petrophysics"]) as ds:
        poro = ds["poro"].values
    assert np.all(poro == 0.3)
    ratio = flow_porv[~box] / ref_init["PORV"][glob][~box]  # the rest: the case's porosity
    deck_poro = read_grdecl(deck).cell_data["PORO"][glob][~box]
    assert np.allclose(ratio, 0.3 / deck_poro, rtol=1e-6)
