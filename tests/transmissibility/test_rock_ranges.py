"""Rock values as strict as OPM Flow 2022.10, no stricter: PORO and NTG above 1 are used as
Flow uses them (its dry run here), with a note naming the cells; negative and undefined values,
which Flow reads but computes nonsense from, are errors naming the keyword and the cells."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from flow_tools import flow_connections, read_keywords, run_flow_dry
from wedge_decks import write_data_deck

from gridlib.cornerpoint.generators import simple_grdecl
from gridlib.cornerpoint.process import process_grdecl
from gridlib.errors import InputError
from gridlib.io.grdecl import read_grdecl
from gridlib.transmissibility import deck_transmissibility


def _deck(tmp_path, **changes: tuple[int, float]):
    """A faulted 4 x 3 x 2 deck at 1500 m with PORO 0.2, PERMX 100, NTG 0.9, the values
    ``changes`` (keyword -> (cell, value)) set, as a DATA deck Flow runs."""
    deck = simple_grdecl([4, 3, 2], 8.0, phys_dims=(400.0, 300.0, 20.0))
    coord = deck.coord.reshape(-1, 6).copy()
    coord[:, [2, 5]] += 1500.0
    deck = replace(deck, coord=coord.reshape(-1), zcorn=deck.zcorn + 1500.0)
    n = deck.num_cells
    rock = {"PORO": np.full(n, 0.2), "PERMX": np.full(n, 100.0), "NTG": np.full(n, 0.9)}
    for key, (cell, value) in changes.items():
        rock[key][cell] = value
    return write_data_deck(tmp_path / "deck", "R", deck, rock)


def test_poro_and_ntg_above_one_give_flows_porv_and_t_with_a_note(tmp_path):
    path = _deck(tmp_path, PORO=(5, 1.5), NTG=(17, 1.2))  # cells (2, 2, 1) and (2, 2, 2)
    case = run_flow_dry(path, tmp_path / "flow")
    flow_porv = read_keywords(case.with_suffix(".INIT"))["PORV"].astype(np.float64)
    flow_t = {pair: t for pair, t in flow_connections(case).items() if t > 0}
    deck = read_grdecl(path)
    cp = process_grdecl(deck)
    conn = deck_transmissibility(deck, cp)
    ours = dict(zip(map(tuple, conn.global_cells.tolist()), conn.trans.tolist(), strict=True))
    assert set(ours) == set(flow_t)
    pairs = list(flow_t)
    np.testing.assert_allclose([ours[p] for p in pairs], [flow_t[p] for p in pairs], rtol=1e-6)
    index = cp.grid.cells.index_map
    porv = cp.bulk_volumes * deck.cell_data["PORO"][index] * deck.cell_data["NTG"][index]
    np.testing.assert_allclose(porv, flow_porv[index], rtol=1e-6)
    assert flow_porv[5] > cp.bulk_volumes[5]  # PORO 1.5: more pore volume than bulk volume
    (note,) = [n for n in conn.notes if "NTG above 1" in n]
    assert note.endswith(
        "1 cells have NTG above 1 (up to 1.2), used as given, as OPM Flow and ECLIPSE do: (2, 2, 2)"
    )


@pytest.mark.parametrize(
    ("key", "cell", "value", "message"),
    [
        ("PERMX", 5, -5.0, r"PERMX: 1 cells have a negative or undefined PERMX \(first -5\.0\): \(2, 2, 1\)"),
        # a negative NTG (or PORO) gives a negative pore volume, refused when the grid is processed
        (
            "NTG",
            23,
            -0.2,
            r"1 active cells have a negative or infinite pore volume \(first: cell \(4, 3, 2\), -3901\.8",
        ),
        (
            "PORO",
            23,
            np.inf,
            r"1 active cells have a negative or infinite pore volume \(first: cell \(4, 3, 2\), inf",
        ),
        (
            "PERMX",
            0,
            float("nan"),
            r"PERMX: 1 cells have a negative or undefined PERMX \(first nan\): \(1, 1, 1\)",
        ),
    ],
)
def test_negative_or_undefined_values_are_errors_naming_the_cells(tmp_path, key, cell, value, message):
    """Flow 2022.10 runs these (negative PORV or T; NaN T from 'nan' in a deck): gridlib refuses
    them. Set after reading: gridlib's GRDECL writer does not write NaN."""
    deck = read_grdecl(_deck(tmp_path))
    values = deck.cell_data[key].copy()
    values[cell] = value
    with pytest.raises(InputError, match=r"R\.DATA: " + message):
        deck_transmissibility(replace(deck, cell_data={**deck.cell_data, key: values}))
