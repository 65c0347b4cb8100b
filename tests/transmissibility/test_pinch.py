"""Connections across removed layers (PINCH, MINPV) against OPM Flow's on decks the test
writes: random columns with zero-thickness and thin layers, inactive cells, cells below
MINPV, GAP/NOGAP, MULTZ options; and OPM's own five-cell PINCH/MINPV decks."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from flow_tools import PHASES, assert_same_connections, flow_connections, rest_of_deck, run_flow_dry

from gridlib.io.grdecl import read_grdecl
from gridlib.transmissibility import deck_transmissibility

DECKS = Path(__file__).parents[1] / "data" / "decks"
RUNSPEC = "METRIC\n" + PHASES
REST = rest_of_deck(0.5, 10.0)


def assert_same_as_flow(deck_path: Path, out: Path) -> dict:
    ref = flow_connections(run_flow_dry(deck_path, out))
    c = deck_transmissibility(read_grdecl(deck_path))
    ours = dict(zip(map(tuple, c.global_cells.tolist()), c.trans.tolist(), strict=True))
    assert_same_connections(ours, ref)
    return ours


def column_deck(rng, nx: int, ny: int, nz: int, options: str, minpv: float | None) -> str:
    """A corner-point deck of vertical pillars on a 10 m lattice with layers of random
    thickness: some zero (pinched out, per column), some thin, some inactive."""
    thick = rng.choice(
        [0.0, 0.0005, 0.05, 0.2, 1.0, 2.0], size=(nz, ny + 1, nx + 1), p=[0.2, 0.1, 0.15, 0.15, 0.2, 0.2]
    )
    thick[rng.random(nz) < 0.3, : ny // 2 + 1] = 0.0  # layers pinched out over part of the model
    depth = 1000.0 + np.concatenate(
        [np.zeros((1, ny + 1, nx + 1)), np.cumsum(thick, axis=0)]
    )  # at the pillars
    z = np.empty((2 * nz, 2 * ny, 2 * nx))
    for a, b in ((0, 0), (1, 0), (0, 1), (1, 1)):
        z[0::2, b::2, a::2] = depth[:-1, b : b + ny, a : a + nx]
        z[1::2, b::2, a::2] = depth[1:, b : b + ny, a : a + nx]
    coord = []
    for j in range(ny + 1):
        for i in range(nx + 1):
            coord += [10.0 * i, 10.0 * j, 900.0, 10.0 * i + 0.5 * j, 10.0 * j, 1100.0]
    n = nx * ny * nz
    act = (rng.random(n) > 0.15).astype(int)
    text = f"RUNSPEC\n{RUNSPEC}DIMENS\n {nx} {ny} {nz} /\nGRID\nINIT\n"
    text += "COORD\n" + " ".join(repr(float(v)) for v in coord) + " /\n"
    text += "ZCORN\n" + " ".join(repr(float(v)) for v in z.ravel()) + " /\n"
    text += "ACTNUM\n" + " ".join(map(str, act)) + " /\n"
    text += "PORO\n" + " ".join(f"{v:.3f}" for v in rng.uniform(0.1, 0.3, n)) + " /\n"
    for key in ("PERMX", "PERMY", "PERMZ"):
        text += f"{key}\n" + " ".join(f"{v:.3f}" for v in rng.uniform(10, 500, n)) + " /\n"
    text += "MULTZ\n" + " ".join(f"{v:.2f}" for v in rng.choice([1.0, 0.5, 0.1], n)) + " /\n"
    text += "MULTZ-\n" + " ".join(f"{v:.2f}" for v in rng.choice([1.0, 0.7], n)) + " /\n"
    if options:
        text += f"PINCH\n {options} /\n"
    if minpv is not None:
        text += f"MINPV\n {minpv} /\n"
    return text + REST


CASES = [
    ("", None),
    ("0.001 GAP 1* TOPBOT TOP", None),
    ("0.001 GAP 1* TOPBOT ALL", 15.0),
    ("0.1 NOGAP 1* TOPBOT TOP", 15.0),
    ("0.3 GAP 1* TOPBOT ALL", 15.0),
    ("", 15.0),
]


@pytest.mark.parametrize(("options", "minpv"), CASES)
def test_pinch_and_minpv_connections_equal_flows(tmp_path, options, minpv):
    rng = np.random.default_rng(len(options) * 7 + int(minpv or 0))
    deck = tmp_path / "COLUMNS.DATA"
    deck.write_text(column_deck(rng, 4, 3, 9, options, minpv))
    ours = assert_same_as_flow(deck, tmp_path / "out")
    layer = 4 * 3
    across = [p for p in ours if p[1] - p[0] > layer and (p[1] - p[0]) % layer == 0]
    if options or minpv:  # the cases do join cells across removed layers
        assert across, "no connection across removed layers: the case tests nothing"


@pytest.mark.parametrize(
    "name",
    ["FIVE", "FIVE_ACTNUM", "FIVE_PINCH", "FIVE_PINCH_NOGAP", "FIVE_PINCH_NOGAP2", "FIVE_PINCH_NOGAP3"],
)
def test_opm_five_cell_pinch_decks(tmp_path, name):
    """OPM's own PINCH/MINPV test columns (a 0.1 m cell below MINPV joined across with GAP
    and with NOGAP, two or three removed cells not joined with NOGAP), completed into
    decks Flow runs."""
    text = (DECKS / "pinch" / f"{name}.DATA").read_text()
    text = text.replace("\nGRID\n", "\nGRID\nINIT\n", 1).replace("RUNSPEC\n", "RUNSPEC\n" + RUNSPEC, 1)
    deck = tmp_path / f"{name}.DATA"
    deck.write_text(text + "\nEQUALS\n 'PERMX' 100 /\n 'PERMY' 100 /\n 'PERMZ' 100 /\n/\n" + REST)
    assert_same_as_flow(deck, tmp_path / "out")


def test_minpv_joins_the_cells_of_a_single_column(tmp_path):
    """A 1 x 1 x 3 column whose middle cell (0.1 m) is below MINPV: Flow joins the two others
    across it, and there is no face connection at all to compare with (gridlib used to fail
    with an IndexError there)."""
    deck = tmp_path / "COLUMN.DATA"
    deck.write_text(
        f"RUNSPEC\n{RUNSPEC}DIMENS\n 1 1 3 /\nGRID\nINIT\nDX\n 3*100 /\nDY\n 3*100 /\nDZ\n 2 0.1 2 /\n"
        "TOPS\n 2000 /\nPORO\n 3*0.25 /\nPERMX\n 3*100 /\nPERMY\n 3*100 /\nPERMZ\n 3*10 /\nMINPV\n 300 /\n"
        + REST
    )
    ours = assert_same_as_flow(deck, tmp_path / "out")
    assert list(ours) == [(0, 2)]
