"""Real public decks nobody here wrote, against OPM Flow 2022.10's dry run, run in the test.

Each deck (tests/data/decks/README.md: source, commit, licence) must give Flow's active
cells, connection set, T and pore volumes (tests/real_decks.py says how they are compared);
each of the four is its own test, so that a failure says which differs and by how much.

* ``reek_rms``: Equinor's Reek model as ECLIPSE 2014.2 ran it (res2df's test data): an
  RMS 10.1 export (MAPAXES, GDORIENT over two lines, a left-handed grid), FAULTS + MULTFLT,
  MULTIPLY PERMZ, EQUALS MULTZ with text after the record's '/', PINCH 0.4 NOGAP, 3 active
  cells with PORO 0. What ECLIPSE made of it is compared too: its EGRID's active cells and
  NNC pairs, and its PRT's pore volumes by FIPNUM region;
* ``emerald_hole*``: xtgeo-testdata's Emerald geomodel export (GDORIENT LEFT, a hole, PORO
  0 in 5,389 of its 7,157 active cells) in a deck of ours, with and without PINCH and MINPV;
* ``spe9_minpv``: SPE 9's corner-point deck (FIELD units) with MINPV 15000 rb;
* ``emerald_hole_case``: the Emerald deck as a workflow case (grid type deck, rock from the
  deck), through the grid, geometry, petrophysics and transmissibility stages.

The 1.1e6-cell SPE 10 model 2 is in test_real_decks_large.py (Flow's dry run alone takes
half a minute or more).
"""

from __future__ import annotations

import dataclasses
import re
from functools import partial
from pathlib import Path

import numpy as np
import pytest
from flow_tools import read_keywords
from real_decks import (
    case_result,
    check_active_cells,
    check_connections,
    check_pore_volumes,
    check_transmissibilities,
    compare,
    gridlib_result,
    unpack,
)

import gridlib.transmissibility.edits as edits
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.eclipse_text import Source, read_numbers
from gridlib.io.grdecl import read_grdecl
from gridlib.transmissibility import deck_transmissibility


def reek_rms(work: Path) -> Path:
    """Reek as ECLIPSE ran it. Flow 2022.10 refuses EQUIL item 9 (ECLIPSE's initialisation
    accuracy, 20 here): it is defaulted in the copy; the grid is untouched."""
    root = unpack("reek_rms", work)
    equil = root / "eclipse" / "include" / "solution" / "reek.equil"
    text, n = re.subn(r"(?m)^(\s*(?:\S+\s+){8})20(\s*/)", r"\g<1>1*\2", equil.read_text())
    assert n == 2, "reek.equil: its two EQUIL records were expected with item 9 = 20"
    equil.write_text(text)
    return root / "eclipse" / "model" / "2_R001_REEK-0.DATA"


EMERALD_OPTIONS = {
    "emerald_hole": "",
    "emerald_hole_pinch": "PINCH\n 0.5 /",
    "emerald_hole_minpv": "MINPV\n 4000 /",
    "emerald_hole_pinch_nogap_minpv": "PINCH\n 0.5 NOGAP /\nMINPV\n 4000 /",
}


def emerald(work: Path, name: str) -> Path:
    root = unpack("emerald_hole", work)
    text = (root / "EMERALD_HOLE.DATA").read_text()
    out = root / f"{name.upper()}.DATA"
    out.write_text(re.sub(r"(?m)^INIT\s*$", "INIT\n" + EMERALD_OPTIONS[name], text, count=1))
    return out


EMERALD_CASE = """name: emerald_hole
description: xtgeo-testdata's Emerald export as a deck case, its rock taken from the deck
grid: {type: deck, file: EMERALD_HOLE_CASE.DATA, unknown_keywords: skip}
petrophysics:
  porosity: {deck: PORO}
  permeability: {deck: PERMX}
  kv_kh: 0.1
"""


def emerald_case(work: Path) -> tuple[Path, Path]:
    """The Emerald deck with PERMY = PERMX (a case's rock has one horizontal permeability)
    and a case that takes its PORO and PERMX, PERMZ 0.1 PERMX as the deck does."""
    root = unpack("emerald_hole", work)
    text, n = re.subn(r"(?m)^ PERMY 0\.8 /\n", "", (root / "EMERALD_HOLE.DATA").read_text())
    assert n == 1
    (root / "EMERALD_HOLE_CASE.DATA").write_text(text)
    (root / "emerald_hole.yaml").write_text(EMERALD_CASE)
    return root / "EMERALD_HOLE_CASE.DATA", root / "emerald_hole.yaml"


def spe9_minpv(work: Path) -> Path:
    root = unpack("spe9", work)
    out = root / "SPE9_MINPV.DATA"
    text = (root / "SPE9_CP.DATA").read_text()
    out.write_text(re.sub(r"(?m)^GRID\s*$", "GRID\nMINPV\n 15000 /", text, count=1))
    return out


def sliver(work: Path) -> Path:
    """A 2 x 1 x 3 cut of OPM's MODEL2 (9_EDITNNC.EGRID) around a fault sliver of 1.7 mm: its
    faces are not quadrilaterals."""
    return unpack("sliver", work) / "SLIVER_MODEL2.DATA"


DECKS = {
    "reek_rms": reek_rms,
    "sliver_model2": sliver,
    **{name: (lambda work, name=name: emerald(work, name)) for name in EMERALD_OPTIONS},
    "spe9_minpv": spe9_minpv,
    "emerald_hole_case": emerald_case,  # through the workflow's stages (case_result)
}


@pytest.fixture(scope="module", params=list(DECKS))
def comparison(request, tmp_path_factory):
    name = request.param
    work = tmp_path_factory.mktemp(name)
    made = DECKS[name](work / "deck")
    deck, gridlib = made, None
    if isinstance(made, tuple):  # a deck and its case: gridlib's result is the workflow's
        deck, case = made
        gridlib = partial(case_result, case, (work / "case").resolve())
        (work / "case").mkdir()
    unknown = "error"
    with pytest.MonkeyPatch.context() as mp:
        if name.startswith("emerald"):  # the export's FACIES is no ECLIPSE keyword: both skip it
            mp.setenv("OPM_ERRORS_IGNORE", "PARSE_UNKNOWN_KEYWORD")
            unknown = "skip"
        return compare(name, deck, work / "flow", gridlib, unknown)


def test_active_cells_equal_flow(comparison):
    check_active_cells(comparison)


def test_connections_equal_flow(comparison):
    check_connections(comparison)


def test_transmissibilities_equal_flow(comparison):
    check_transmissibilities(comparison)


def test_pore_volumes_equal_flow(comparison):
    check_pore_volumes(comparison)


# --- Reek: what ECLIPSE 2014.2 itself made of the same deck --------------------------------------


@pytest.fixture(scope="module")
def reek_eclipse(tmp_path_factory) -> tuple[Path, dict[str, np.ndarray]]:
    deck = reek_rms(tmp_path_factory.mktemp("reek_eclipse"))
    return deck, read_keywords(deck.with_suffix(".EGRID"))


def test_reek_active_cells_equal_eclipse(reek_eclipse):
    """ECLIPSE made 35,817 of the 35,840 cells active: ACTNUM's 35,820 less the 3 with PORO 0."""
    deck_path, egrid = reek_eclipse
    active = np.flatnonzero(egrid["ACTNUM"] > 0)
    assert active.size == 35_817
    deck = read_grdecl(deck_path)
    cells = process_grdecl(deck).grid.cells.index_map
    extra = np.setdiff1d(cells, active)
    assert np.array_equal(cells, active), (cells.size, extra, deck.cell_data["PORO"][extra])


# ECLIPSE's PRT of that run (not vendored: 4 MB), the FIP report of 1 JAN 2000: "PORV=" of the
# field and of FIPNUM regions 1-6, rm3 "at reference conditions", printed to the unit
ECLIPSE_PORV = (399_077_425, 78_815_548, 79_432_248, 75_755_746, 74_878_274, 50_113_604, 40_082_005)


def test_reek_pore_volumes_equal_eclipse(reek_eclipse):
    """gridlib's pore volumes summed over the field and each FIPNUM region are ECLIPSE's to
    the cubic metre it prints (measured: 0.4 rm3 at most, 1e-8 relative)."""
    deck_path, _ = reek_eclipse
    ours = gridlib_result(deck_path)
    src = Source.open(deck_path.parents[1] / "include" / "regions" / "reek.fipnum")
    start = re.search(rb"(?m)^FIPNUM\s*$", src.data).end()
    fipnum, _ = read_numbers(src, start, "FIPNUM", expected=40 * 64 * 14)
    region = fipnum.values.astype(np.int64)[ours.active]
    totals = np.bincount(region, weights=ours.porv, minlength=len(ECLIPSE_PORV))
    totals[0] = ours.porv.sum()
    assert np.abs(totals - ECLIPSE_PORV).max() <= 0.5, totals - ECLIPSE_PORV


def test_reek_fault_connections_equal_eclipse_but_at_the_threshold(reek_eclipse, monkeypatch):
    """ECLIPSE's EGRID lists 3,286 non-neighbour pairs; gridlib (and Flow) find 3,288. They
    differ by six fault connections (MULTFLT 0.001) whose T lie within a factor 4 of the
    1e-6 below which Flow drops a non-neighbour connection: ECLIPSE keeps two just below it
    (8.5e-7 and 9.95e-7 by gridlib's T) and leaves out four just above (1.0e-6 to 3.3e-6)."""
    deck_path, egrid = reek_eclipse
    nx, ny = (int(v) for v in egrid["GRIDHEAD"][1:3])
    n1, n2 = egrid["NNC1"].astype(np.int64) - 1, egrid["NNC2"].astype(np.int64) - 1
    eclipse = set(zip(np.minimum(n1, n2).tolist(), np.maximum(n1, n2).tolist(), strict=True))
    assert len(eclipse) == 3_286
    deck = read_grdecl(deck_path)
    monkeypatch.setattr(edits, "NNC_THRESHOLD", 0.0)  # every fault connection, however small
    conn = deck_transmissibility(deck, process_grdecl(deck))
    g = conn.global_cells
    far = ~np.isin(g[:, 1] - g[:, 0], (1, nx, nx * ny))
    t_of = dict(zip(map(tuple, g[far].tolist()), conn.trans[far].tolist(), strict=True))
    ours = {p for p, t in t_of.items() if t >= 1e-6}
    assert len(ours) == 3_288
    only_eclipse, only_ours = sorted(eclipse - ours), sorted(ours - eclipse)
    assert len(only_eclipse) == 2 and len(only_ours) == 4, (only_eclipse, only_ours)
    assert all(5e-7 < t_of[p] < 1e-6 for p in only_eclipse), [t_of.get(p) for p in only_eclipse]
    assert all(1e-6 <= t_of[p] < 4e-6 for p in only_ours), [t_of[p] for p in only_ours]


def test_the_sliver_faces_transmissibility_does_not_depend_on_where_the_grid_lies(tmp_path):
    """The sliver deck moved by 2048 m east and north (exact in float64): every T the same
    within 1e-9, what float64 allows for a 1.7 mm face among coordinates of 2,500 m (eps x
    2500 / 1.7e-3 = 3e-10). A polygon's area summed from its absolute coordinates lost 2.3e-6 of
    the sliver's area to rounding (gridlib's T differed from Flow's by 2e-6, and moved with the
    grid)."""
    deck = read_grdecl(sliver(tmp_path))
    coord = deck.coord.reshape(-1, 3).copy()
    coord[:, :2] += 2048.0
    moved = dataclasses.replace(deck, coord=coord.ravel())
    a, b = deck_transmissibility(deck), deck_transmissibility(moved)
    np.testing.assert_array_equal(a.global_cells, b.global_cells)
    np.testing.assert_allclose(b.trans, a.trans, rtol=1e-9, atol=0)


def test_spe9_pore_volumes_and_transmissibilities_equal_eclipses(tmp_path):
    """SPE 9 as ECLIPSE 100 ran it (its EGRID and INIT, FIELD units): gridlib's pore volumes
    and TRANX/TRANY/TRANZ, from ECLIPSE's grid and the rock ECLIPSE wrote into its INIT, equal
    ECLIPSE's within 1e-6 (float32); every connection ECLIPSE gives T > 0 is gridlib's, and
    gridlib has no other. The simulator itself as the oracle, not only OPM Flow."""
    from gridlib.cornerpoint.pore_volume import pore_volumes
    from gridlib.io.egrid import read_egrid

    root = unpack("bench_spe9", tmp_path)
    init = read_keywords(root / "BENCH_SPE9.INIT")
    deck = read_egrid(root / "BENCH_SPE9.EGRID")
    nx, ny, nz = deck.cart_dims
    active = np.flatnonzero(deck.active)
    assert (nx, ny, nz) == (24, 25, 15) and active.size == int(init["INTEHEAD"][11]) == 9000
    rock = {}
    for key in ("PORO", "NTG", "PERMX", "PERMY", "PERMZ"):
        rock[key] = np.zeros(deck.num_cells)
        rock[key][active] = init[key]
    deck = dataclasses.replace(deck, cell_data=rock)
    cp = process_grdecl(deck)
    cells = np.asarray(cp.grid.cells.index_map)
    np.testing.assert_array_equal(cells, active)
    np.testing.assert_allclose(pore_volumes(deck, cells, cp.bulk_volumes), init["PORV"][cells], rtol=1e-6)
    conn = deck_transmissibility(deck, cp)
    pairs = np.sort(conn.global_cells, axis=1)
    position = np.full(deck.num_cells, -1)
    position[active] = np.arange(active.size)
    matched = 0
    for name, step in (("TRANX", 1), ("TRANY", nx), ("TRANZ", nx * ny)):
        ours = pairs[:, 1] - pairs[:, 0] == step
        eclipse = init[name].astype(np.float64)  # per active cell: T to its +I (+J, +K) neighbour
        np.testing.assert_allclose(
            conn.trans[ours], eclipse[position[pairs[ours, 0]]], rtol=1e-6, err_msg=name
        )
        assert np.count_nonzero(eclipse > 0) == np.count_nonzero(ours), name
        matched += np.count_nonzero(ours)
    assert matched == conn.trans.size == 25_665
