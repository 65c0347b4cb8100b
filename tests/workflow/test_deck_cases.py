"""Decks that OPM Flow runs, as ``deck`` cases of the workflow: the Flow deck the workflow
writes gives Flow's own pore volumes and transmissibilities.

Two deck cases, every stage run as its Snakemake rule runs it (tests/deck_cases.py
run_as_the_workflow: the stage with its own log, in this process; the sample deck case spe9
goes through Snakemake itself in test_workflow.py):

* ``wedges``: thin wedges beside a fault, three of four corners of each collapsed, two of them
  with a polyhedral volume below zero (and positive ECLIPSE bulk volumes): kept, each named in
  the grid stage's notes and in summary.json;
* ``net_to_gross``: NTG up to 1.3 (ECLIPSE models carry NTG above 1): used as Flow uses it,
  with a note naming the cells.

For each, Flow's dry run of the deck the workflow writes (results/<case>/flow/<NAME>.DATA) and
of the original deck give the same PORV and T (1e-6), and so do gridlib's own
(transmissibility.nc).
"""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from deck_cases import run_as_the_workflow
from flow_tools import flow_connections, read_keywords, run_flow_dry
from wedge_decks import wedge_deck, write_data_deck

from gridlib.cell_names import ijk
from gridlib.cornerpoint.deck import Deck
from gridlib.cornerpoint.generators import simple_grdecl
from gridlib.io import read_geometry_netcdf, read_netcdf

ROCK_CASE = """petrophysics:
  porosity: {deck: PORO}
  permeability: {deck: PERMX}
  kv_kh: 0.1
"""


def _rock(n: int, seed: int, ntg: tuple[float, float] | None = None) -> dict[str, np.ndarray]:
    """PORO, PERMX, PERMY = PERMX, PERMZ = 0.1 PERMX (what the case's kv_kh makes) and NTG."""
    rng = np.random.default_rng(seed)
    permx = rng.uniform(50.0, 500.0, n)
    rock = {"PORO": rng.uniform(0.1, 0.3, n), "PERMX": permx, "PERMY": permx, "PERMZ": 0.1 * permx}
    if ntg is not None:
        rock["NTG"] = rng.uniform(*ntg, n)
    return rock


def _deeper(deck: Deck, by: float) -> Deck:
    """``deck`` moved ``by`` down (its pillars and corners)."""
    coord = deck.coord.reshape(-1, 6).copy()
    coord[:, [2, 5]] += by
    return replace(deck, coord=coord.reshape(-1), zcorn=deck.zcorn + by)


@pytest.fixture(scope="module")
def deck_cases(tmp_path_factory):
    """Both cases built as the workflow builds them; returns the scratch directory and the
    original decks."""
    work = tmp_path_factory.mktemp("deck_cases")
    config = work / "config"
    wedges = wedge_deck()
    originals = {"wedges": write_data_deck(config / "decks", "WEDGES", wedges, _rock(wedges.num_cells, 1))}
    ntg_deck = _deeper(simple_grdecl([4, 3, 3], 12.0, phys_dims=(400.0, 300.0, 30.0)), 1500.0)
    rock = _rock(ntg_deck.num_cells, 2, ntg=(0.8, 1.3))
    originals["net_to_gross"] = write_data_deck(config / "decks", "NTG", ntg_deck, rock)
    cases = []
    for name, deck in originals.items():
        case = config / f"{name}.yaml"
        extra = "  ntg: {deck: NTG}\n" if name == "net_to_gross" else ""
        case.write_text(f"name: {name}\ngrid: {{type: deck, file: decks/{deck.name}}}\n{ROCK_CASE}{extra}")
        cases.append(str(case))
    for case in cases:
        run_as_the_workflow(Path(case), work / "results")
    return work, originals


def _flow(deck: Path, out: Path) -> tuple[np.ndarray, dict[tuple[int, int], float]]:
    """Flow's PORV of every cell (0 inactive) and its connections {(g1, g2): T > 0}."""
    case = run_flow_dry(deck, out)
    porv = read_keywords(Path(f"{case}.INIT"))["PORV"].astype(np.float64)
    return porv, {pair: t for pair, t in flow_connections(case).items() if t > 0}


def _assert_same(got_porv, got_t, want_porv, want_t) -> None:
    np.testing.assert_allclose(got_porv, want_porv, rtol=1e-6, atol=0.0)
    assert set(got_t) == set(want_t), sorted(set(got_t) ^ set(want_t))[:5]
    pairs = list(want_t)
    np.testing.assert_allclose([got_t[p] for p in pairs], [want_t[p] for p in pairs], rtol=1e-6, atol=0.0)


@pytest.mark.parametrize("case", ["wedges", "net_to_gross"])
def test_the_written_deck_and_gridlib_give_flows_porv_and_t(deck_cases, case, tmp_path):
    work, originals = deck_cases
    folder = work / "results" / case
    want_porv, want_t = _flow(originals[case], tmp_path / "original")
    written = folder / "flow" / f"{case.upper()}.DATA"
    _assert_same(*_flow(written, tmp_path / "written"), want_porv, want_t)
    with xr.open_dataset(folder / "transmissibility.nc") as ds:  # gridlib's own
        index = ds["cell_flow_index"].values
        porv = np.zeros_like(want_porv)
        porv[index] = ds["porv"].values
        pairs = np.sort(index[ds["connection_cells"].values], axis=1)
        ours = dict(zip(map(tuple, pairs.tolist()), ds["trans"].values.tolist(), strict=True))
    _assert_same(porv, ours, want_porv, want_t)


def test_wedges_are_kept_and_each_named(deck_cases):
    work, _ = deck_cases
    folder = work / "results" / "wedges"
    grid = read_netcdf(folder / "grid.nc").grid
    volumes = read_geometry_netcdf(folder / "geometry.nc").cell_volumes
    bulk = read_netcdf(folder / "grid.nc").cell_data["bulk_volume"]
    degenerate = np.flatnonzero(volumes <= 0)  # the polyhedral volumes geometry.nc keeps
    assert degenerate.size == 2 and (bulk[degenerate] > 0).all()
    named = ijk(grid.cells.index_map[degenerate], grid.cart_dims).tolist()
    assert named == [[3, 7, 2], [3, 8, 2]]  # beside the fault (i = 2 | 3), in the pinched layer
    log = (work / "results" / "logs" / "wedges" / "grid.log").read_text().splitlines()
    note = [line for line in log if "non-positive polyhedral volume" in line]
    assert len(note) == 1 and "note: 2 cells" in note[0] and "(3, 7, 2), (3, 8, 2) (" in note[0], note
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["degenerate_cells"] == {
        "count": 2,
        "non_positive_volume": 2,
        "not_closed": 0,
        "cells": named,
    }
    assert summary["cells"] == grid.num_cells == 100  # every active cell kept (Flow: 100 active)


def test_ntg_above_one_is_a_note_naming_the_cells(deck_cases):
    work, originals = deck_cases
    logs = work / "results" / "logs" / "net_to_gross"
    noted = {
        stage: [line for line in (logs / f"{stage}.log").read_text().splitlines() if "NTG above 1" in line]
        for stage in ("petrophysics", "transmissibility")
    }
    assert len(noted["petrophysics"]) == 1 and noted["transmissibility"] == [], noted  # noted once, not twice
    lines = noted["petrophysics"]
    ntg = read_keywords(run_flow_dry(originals["net_to_gross"], work / "ntg_flow").with_suffix(".INIT"))[
        "NTG"
    ]
    assert f"{int((ntg > 1).sum())} cells have NTG above 1" in lines[0]
    summary = json.loads((work / "results" / "net_to_gross" / "summary.json").read_text())
    assert "degenerate_cells" not in summary
