"""Which cells are active, and their pore volumes, as OPM Flow 2022.10 decides them.

Decks written here: 3 x 2 x 7 columns of flat cells (thick, thin and one collapsed),
the columns i = 3 thrown down by a fault (lateral connections across layers), PORO 0
inside a column, at its top and bottom and over five cells of a column; the same with
NTG 0, MULTPV 0 (GRID and EDIT), PORV in EDIT (whole, by BOX, MULTIPLY), MINPV, MINPVV
and every PINCH option. Each runs through Flow's dry run and must give the same active
cells, the same connections (T to 1e-6) and the same PORV (1e-6) as ours; and the deck
``write_grdecl`` writes of each pore-volume case gives Flow what the original gives it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from flow_tools import (
    PHASES,
    assert_same_connections,
    flow_connections,
    read_keywords,
    rest_of_deck,
    run_flow_dry,
)

from gridlib.cornerpoint.pore_volume import pore_volumes
from gridlib.cornerpoint.process import process_grdecl
from gridlib.errors import InputError
from gridlib.io.grdecl import read_grdecl, write_grdecl
from gridlib.transmissibility import deck_transmissibility

NX, NY, NZ = 3, 2, 7
N = NX * NY * NZ
# Layer thickness (m): thick, thin (below a 0.001 PINCH threshold), ...; the bulk volume is
# 100 m2 x thickness, so with PORO 0.2 MINPV 2 removes the 0.0005 m and 0.05 m layers.
LAYERS = np.array([1.0, 0.0005, 1.5, 0.2, 1.0, 0.05, 1.2])
THROW = 0.6  # of the columns i = 3 (1-based)
# PORO 0 (1-based i, j, k): inside column (1, 1) (one of them thin), at the top and the
# bottom of column (3, 2), over k = 2..6 of column (2, 1)
ZERO = [(1, 1, 4), (1, 1, 2), (3, 2, 1), (3, 2, 7)] + [(2, 1, k) for k in range(2, 7)]
COLLAPSED = (3, 1, 6)  # zero thickness: zero bulk volume


def cell(i: int, j: int, k: int) -> int:
    return (i - 1) + NX * ((j - 1) + NY * (k - 1))


def cells(ijk) -> list[int]:
    return [cell(*c) for c in ijk]


def array_text(name: str, values) -> str:
    return f"{name}\n" + " ".join(repr(float(v)) for v in np.asarray(values, float).ravel()) + " /\n"


def deck_text(grid: str = "", edit: str = "", poro=None, actnum=None) -> str:
    """The deck: geometry, rock, then ``grid`` (more GRID keywords) and ``edit`` (EDIT).
    ``poro``: PORO of every cell (default 0.2), or the text that gives it."""
    thick = np.broadcast_to(LAYERS[:, None, None], (NZ, NY, NX)).copy()
    i, j, k = COLLAPSED
    thick[k - 1, j - 1, i - 1] = 0.0
    top = 1000.0 + np.concatenate([np.zeros((1, NY, NX)), np.cumsum(thick, axis=0)])
    top[:, :, NX - 1] += THROW
    z = np.empty((2 * NZ, 2 * NY, 2 * NX))
    z[0::2] = np.repeat(np.repeat(top[:-1], 2, axis=1), 2, axis=2)
    z[1::2] = np.repeat(np.repeat(top[1:], 2, axis=1), 2, axis=2)
    coord = [
        v
        for jj in range(NY + 1)
        for ii in range(NX + 1)
        for v in (10 * ii, 10 * jj, 900, 10 * ii, 10 * jj, 1100)
    ]
    g = np.arange(N)
    text = "RUNSPEC\nMETRIC\n" + PHASES + f"DIMENS\n {NX} {NY} {NZ} /\nGRID\nINIT\n"
    text += array_text("COORD", coord) + array_text("ZCORN", z)
    if actnum is not None:
        text += "ACTNUM\n" + " ".join(map(str, actnum)) + " /\n"
    text += poro if isinstance(poro, str) else array_text("PORO", np.full(N, 0.2) if poro is None else poro)
    text += array_text("PERMX", 100 + 7 * g) + array_text("PERMY", 50 + 3 * g) + array_text("PERMZ", 10 + g)
    text += grid + ("EDIT\n" + edit if edit else "")
    return text + rest_of_deck(1000.5, 2000.0)


def poro_with_zeros() -> np.ndarray:
    poro = np.full(N, 0.2)
    poro[cells(ZERO)] = 0.0
    return poro


def zeros_of(keyword: str) -> str:
    values = np.ones(N)
    values[cells(ZERO)] = 0.0
    return array_text(keyword, values)


def porv_keyword() -> str:
    """PORV for every cell: 7.5, 0 on the cells ZERO, 1.0 (below MINPV 2) on two thick cells
    and on the collapsed one (Flow 2022.10 aborts on a collapsed cell at or above MINPV)."""
    values = np.full(N, 7.5)
    values[cells(ZERO)] = 0.0
    values[cells([(1, 2, 3), (3, 1, 5), COLLAPSED])] = 1.0
    return array_text("PORV", values)


def flow_run(text: str, work: Path) -> tuple[np.ndarray, dict, np.ndarray]:
    """Flow's active cells (linear indices), connections {(g1, g2): T} and PORV (per cell)."""
    work.mkdir(parents=True, exist_ok=True)
    deck = work / "ACTIVITY.DATA"
    deck.write_text(text)
    case = run_flow_dry(deck, work / "flow")
    active = np.flatnonzero(read_keywords(Path(f"{case}.EGRID"))["ACTNUM"] > 0)
    porv = read_keywords(Path(f"{case}.INIT"))["PORV"].astype(np.float64)
    return active, flow_connections(case), porv


def assert_same_as_flow(text: str, work: Path):
    """Our active cells, connections and pore volumes equal Flow's; returns ours."""
    flow_active, flow_conn, flow_porv = flow_run(text, work)
    deck = read_grdecl(work / "ACTIVITY.DATA")
    cp = process_grdecl(deck)
    index = cp.grid.cells.index_map
    assert index.tolist() == flow_active.tolist(), (
        sorted(set(index.tolist()) ^ set(flow_active.tolist())),
        cp.notes,
    )
    c = deck_transmissibility(deck, cp)
    ours = dict(zip(map(tuple, c.global_cells.tolist()), c.trans.tolist(), strict=True))
    assert_same_connections(ours, flow_conn)
    porv = pore_volumes(deck, index, cp.bulk_volumes)  # as the transmissibility stage
    np.testing.assert_allclose(porv, flow_porv[index], rtol=1e-6)
    return cp, ours


MINPV = "MINPV\n 2.0 /\n"
PINCHES = [
    "0.001 GAP 1* TOPBOT TOP",
    "0.3 GAP 1* ALL ALL",
    "0.1 NOGAP 1* TOPBOT TOP",
    "0.3 NOGAP 1* ALL TOP",
]


def pinch_id(options: str) -> str:
    return "_".join(v for v in options.split() if v != "1*")


CASES = {
    "poro0": "",
    "poro0_minpv": MINPV,
    "poro0_minpvv": "MINPVV\n" + " ".join(["2.0"] * (N // 2) + ["5.0"] * (N - N // 2)) + " /\n",
    "poro0_minporv_pinch": "MINPORV\n 2.0 /\nPINCH\n 0.3 /\n",
    **{f"poro0_pinch_{pinch_id(p)}": f"PINCH\n {p} /\n" for p in PINCHES},
    **{f"poro0_minpv_pinch_{pinch_id(p)}": MINPV + f"PINCH\n {p} /\n" for p in PINCHES},
}


@pytest.mark.parametrize("grid", CASES.values(), ids=CASES.keys())
def test_zero_porosity_cells_as_flow(grid, tmp_path):
    """PORO 0 cells are inactive and nothing bridges them; the collapsed cell (3, 1, 6) is
    bridged under MINPV (Flow counts it as removed by MINPV, not as of zero pore volume)."""
    cp, ours = assert_same_as_flow(deck_text(grid, poro=poro_with_zeros()), tmp_path)
    index = set(cp.grid.cells.index_map.tolist())
    assert not index & set(cells(ZERO)), "cells of zero pore volume must be inactive"
    assert any("zero pore volume" in note for note in cp.notes), cp.notes
    if "MIN" in grid:  # MINPV removes the 0.05 m cells of the columns with porosity
        assert cell(1, 2, 6) not in index
        assert any("below MIN" in note for note in cp.notes), cp.notes
        assert (cell(3, 1, 5), cell(3, 1, 7)) in ours  # across the collapsed cell
    # nothing joins the ends of column (2, 1) across its five PORO-0 cells
    assert (cell(2, 1, 1), cell(2, 1, 7)) not in ours


RULE_CASES = {
    "plain": "",
    "minpv_gap": MINPV + "PINCH\n 0.3 /\n",
    "minpv_nogap": MINPV + "PINCH\n 0.1 NOGAP /\n",
}


@pytest.mark.parametrize("grid", RULE_CASES.values(), ids=RULE_CASES.keys())
def test_flow_treats_zero_porosity_as_actnum_0(grid, tmp_path):
    """The rule itself, from Flow: PORO 0 gives exactly what ACTNUM 0 gives (cells, T, PORV)."""
    by_poro = flow_run(deck_text(grid, poro=poro_with_zeros()), tmp_path / "poro")
    actnum = np.ones(N, dtype=int)
    actnum[cells(ZERO)] = 0
    by_actnum = flow_run(deck_text(grid, actnum=actnum), tmp_path / "actnum")
    assert by_poro[0].tolist() == by_actnum[0].tolist()
    assert by_poro[1] == by_actnum[1]
    np.testing.assert_array_equal(by_poro[2], by_actnum[2])


PV_CASES = {
    "ntg0": (zeros_of("NTG") + MINPV + "PINCH\n 0.3 /\n", ""),
    "multpv0_grid": (zeros_of("MULTPV") + MINPV, ""),
    "multpv0_edit": ("MULTPV\n 42*0.5 /\n" + MINPV, zeros_of("MULTPV")),  # EDIT's MULTPV replaces GRID's
    # PORV in EDIT wins; 0 makes a cell inactive, 1 (below MINPV) removes it
    "porv_edit": (MINPV + "PINCH\n 0.1 NOGAP /\n", porv_keyword()),
    # PORV by BOX: the cells outside keep bulk x PORO x NTG x MULTPV, with the MULTPV of the
    # moment (the later one changes nothing); MULTIPLY PORV multiplies both kinds
    "porv_box": (
        "MULTPV\n 42*1.5 /\n" + MINPV,
        "BOX\n 1 3 1 1 1 7 /\nPORV\n 7*0 7*3.0 7*1.0 /\nENDBOX\nMULTPV\n 42*3.0 /\n"
        "MULTIPLY\n PORV 0.5 1 3 2 2 1 7 /\n PORV 4 1 1 1 1 5 5 /\n/\n",
    ),
    "porv_in_grid_ignored": ("PORV\n 42*0.0 /\n" + MINPV, ""),
    # ... but EQUALS and MULTIPLY on PORV act in GRID too (with the MULTPV of their moment)
    "porv_operations_in_grid": (
        "EQUALS\n PORV 5.0 1 1 1 1 1 1 /\n/\nMULTIPLY\n PORV 0.05 1 3 1 1 3 3 /\n/\n" + MINPV,
        "MULTPV\n 42*3.0 /\n",
    ),
}


@pytest.mark.parametrize(("grid", "edit"), PV_CASES.values(), ids=PV_CASES.keys())
def test_pore_volume_keywords_as_flow(grid, edit, tmp_path):
    assert_same_as_flow(deck_text(grid, edit), tmp_path)


@pytest.mark.parametrize(("grid", "edit"), PV_CASES.values(), ids=PV_CASES.keys())
def test_the_written_deck_keeps_the_pore_volumes(grid, edit, tmp_path):
    """write_grdecl of the deck read (its GRID part, then PORV in its EDIT part: Flow reads it
    nowhere else), INCLUDEd in GRID: Flow gives the original's active cells, T and PORV."""
    original = flow_run(deck_text(grid, edit), tmp_path / "original")
    write_grdecl(tmp_path / "written" / "GRID.INC", read_grdecl(tmp_path / "original" / "ACTIVITY.DATA"))
    text = "RUNSPEC\nMETRIC\n" + PHASES + f"DIMENS\n {NX} {NY} {NZ} /\nGRID\nINIT\nINCLUDE\n 'GRID.INC' /\n"
    written = flow_run(text + rest_of_deck(1000.5, 2000.0), tmp_path / "written")
    assert written[0].tolist() == original[0].tolist()
    assert_same_connections(written[1], original[1])
    np.testing.assert_allclose(written[2], original[2], rtol=1e-6)


PORO_CASES = {
    # cells PORO leaves undefined take the value of the top cell of their column
    "from_top_layer": ("BOX\n 1 3 1 2 1 4 /\nPORO\n 6*0.25 6*0.2 6*0.3 6*0.1 /\nENDBOX\n", 6),
    # ... if the keyword gave the top layer: else they have no pore volume (inactive)
    "top_layer_undefined": ("BOX\n 1 3 1 2 2 7 /\nPORO\n 36*0.2 /\nENDBOX\n", 0),
}


@pytest.mark.parametrize(("poro", "top_active"), PORO_CASES.values(), ids=PORO_CASES.keys())
def test_undefined_porosity_as_flow(poro, top_active, tmp_path):
    cp, _ = assert_same_as_flow(deck_text(MINPV, poro=poro), tmp_path)
    layer = cp.grid.cells.index_map // (NX * NY)
    assert (layer == 0).sum() == top_active and (layer == NZ - 1).sum() == NX * NY


def test_field_units_pore_volumes_in_reservoir_barrels(tmp_path):
    """FIELD: bulk volumes in ft3, pore volumes and MINPV in rb (5.614583 ft3): MINPV 2 rb
    removes the 0.2 ft layer (0.71 rb), which 2 ft3 would keep."""
    text = deck_text(MINPV + "PINCH\n 0.3 /\n", poro=poro_with_zeros()).replace("METRIC", "FIELD")
    cp, _ = assert_same_as_flow(text, tmp_path)
    assert cell(1, 2, 4) not in cp.grid.cells.index_map and cell(1, 2, 5) in cp.grid.cells.index_map


def test_negative_pore_volume_is_refused_with_the_cell(tmp_path):
    """Flow keeps a cell of negative pore volume active (PORV -10 in its INIT); we refuse it."""
    deck = tmp_path / "NEG.DATA"
    poro = np.full(N, 0.2)
    poro[cell(2, 2, 3)] = -0.1
    deck.write_text(deck_text(poro=poro))
    with pytest.raises(
        InputError, match=r"NEG.DATA: 1 active cells have a negative or infinite pore volume.*\(2, 2, 3\)"
    ):
        process_grdecl(read_grdecl(deck))


def test_grid_only_deck_keeps_actnum(tmp_path):
    """No PORO, no PORV: activity is ACTNUM (all cells but the collapsed one), no MINPV."""
    deck = tmp_path / "GRIDONLY.DATA"
    deck.write_text(deck_text(poro=""))
    cp = process_grdecl(read_grdecl(deck), minpv=2.0)
    assert cp.grid.num_cells == N - 1
    assert "MINPV not applied: the deck has no PORO (nor PORV)" in cp.notes


def test_partial_minpvv_is_refused(tmp_path):
    """Flow 2022.10 reads MINPVV's record as a whole-grid array: by BOX it reads past it."""
    deck = tmp_path / "MINPVV.DATA"
    deck.write_text(deck_text("BOX\n 1 1 1 1 3 3 /\nMINPVV\n 15.0 /\nENDBOX\n"))
    with pytest.raises(
        InputError, match=r"MINPVV: not given for every cell \(first missing: cell \(1, 1, 1\)\)"
    ):
        process_grdecl(read_grdecl(deck))
