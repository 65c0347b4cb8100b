"""deck_transmissibility with every multiplier and edit keyword, against OPM Flow 2022.10.

Flow's dry run on each deck (a few tenths of a second) gives its connections and
transmissibilities (tests/flow_tools.py); ours must be the same set, every value within
1e-6 relative (Flow writes float32). Decks: every vendored deck, random decks the test
writes (faulted corner-point, METRIC and FIELD, random PERMX/Y/Z, NTG, ACTNUM, every
MULT* keyword on random boxes, FAULTS + MULTFLT in GRID and EDIT, MULTREGT with every
option and region set, GRIDOPTS, the EDIT section's TRANX/TRANY/TRANZ operations, NNC
and EDITNNC), and decks made to show each of Flow 2022.10's MULTREGT rules. Then the
reader's records, values worked out by hand, and bad input.
"""

from __future__ import annotations

import re
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from flow_tools import flow_connections, rest_of_deck, run_flow_dry

from gridlib.cornerpoint.generators import simple_grdecl
from gridlib.cornerpoint.process import FAULT, process_grdecl
from gridlib.errors import InputError
from gridlib.io.grdecl import DeckError, read_grdecl, write_grdecl
from gridlib.transmissibility import NEIGHBOR, OTHER, deck_transmissibility
from gridlib.units import METRIC

DECKS = Path(__file__).parents[1] / "data" / "decks"


def flow_reference(deck_path: Path, out: Path) -> dict[tuple[int, int], float]:
    """Flow's connections {(g1, g2): T}. Only positive values: for an NNC-keyword pair whose
    total Flow has set to 0 (below 1e-6), its writer leaves out the keyword's value (below
    1e-6) but still writes the grid's part minus it, a negative number."""
    return {p: t for p, t in flow_connections(run_flow_dry(deck_path, out)).items() if t > 0}


def assert_same_as_flow(deck_path: Path, out: Path):
    """Ours equal Flow's: same pairs, values within 1e-6 relative (1e-11 absolute)."""
    ref = flow_reference(deck_path, out)
    c = deck_transmissibility(read_grdecl(deck_path))
    ours = dict(zip(map(tuple, c.global_cells.tolist()), c.trans.tolist(), strict=True))
    assert set(ours) == set(ref), (sorted(set(ours) - set(ref))[:5], sorted(set(ref) - set(ours))[:5])
    pairs = list(ref)
    a, b = np.array([ours[p] for p in pairs]), np.array([ref[p] for p in pairs])
    worst = int(np.argmax(np.abs(a - b) - 1e-6 * np.abs(b)))
    assert np.all(np.abs(a - b) <= 1e-6 * np.abs(b) + 1e-11), (pairs[worst], a[worst], b[worst])
    return c, ours


# --- the vendored decks ------------------------------------------------------------------------

VENDORED = [
    "spe1/SPE1CASE1.DATA",
    "spe1/SPE1CASE2_ACTNUM.DATA",
    "spe9/SPE9_CP.DATA",
    "spe10model1/SPE10_MODEL1_CP.DATA",
    "model5/2_WLIFT_MODEL5_NOINC.DATA",
    "reek/REEK_GRDECL.DATA",
]


def deck_with_init(relpath: str, work: Path) -> Path:
    """The vendored deck, with INIT added after GRID if it lacks it (Flow then writes its
    transmissibilities), its folder's other files linked next to it."""
    src = DECKS / relpath
    work.mkdir(parents=True)
    for entry in src.parent.iterdir():
        if entry != src:
            (work / entry.name).symlink_to(entry)
    text = src.read_text(errors="replace")
    if not re.search(r"^INIT\s*$", text, flags=re.M):
        text = re.sub(r"^GRID\s*$", "GRID\nINIT", text, count=1, flags=re.M)
    (work / src.name).write_text(text)
    return work / src.name


@pytest.mark.parametrize("relpath", VENDORED, ids=[Path(p).stem for p in VENDORED])
def test_vendored_decks_equal_flow(relpath, tmp_path):
    c, ours = assert_same_as_flow(deck_with_init(relpath, tmp_path / "deck"), tmp_path / "out")
    assert c.num == len(ours) > 0
    if relpath.startswith("model5"):
        # EDIT: MAXVALUE TRANZ 750000 caps 76 vertical connections (the deck's own comment)
        nx, ny, _ = (20, 30, 10)
        vertical = (c.global_cells[:, 1] - c.global_cells[:, 0]) == nx * ny
        assert int((c.trans[vertical] == 750000.0).sum()) == 76
        assert c.trans[vertical].max() == 750000.0
        assert any("TRANZ edits (MAXVALUE" in n and "changed 76 connections" in n for n in c.notes)


# --- random decks with every keyword -------------------------------------------------------------


def _box(rng, dims) -> tuple[int, ...]:
    lo = [int(rng.integers(0, d)) for d in dims]
    hi = [int(rng.integers(lo_, d)) for lo_, d in zip(lo, dims, strict=True)]
    return lo[0] + 1, hi[0] + 1, lo[1] + 1, hi[1] + 1, lo[2] + 1, hi[2] + 1


def _size(box) -> int:
    return (box[1] - box[0] + 1) * (box[3] - box[2] + 1) * (box[5] - box[4] + 1)


def _text(values) -> str:
    return " ".join(map(str, values))


def _ijk(g: int, dims) -> str:
    nx, ny, _ = dims
    return f"{g % nx + 1} {g // nx % ny + 1} {g // (nx * ny) + 1}"


def write_case(work: Path, deck, data, runspec=(), grid=(), edit=(), units="METRIC") -> Path:
    """CASE.DATA: an oil-water deck around grid.grdecl (``deck`` + ``data``) with the given
    RUNSPEC, GRID and EDIT keywords."""
    work.mkdir(parents=True, exist_ok=True)
    write_grdecl(work / "grid.grdecl", deck, data)
    nx, ny, nz = deck.cart_dims
    text = f"RUNSPEC\nDIMENS\n {nx} {ny} {nz} /\nOIL\nWATER\n{units}\n" + "\n".join(runspec)
    text += "\nTABDIMS\n 1 1 20 20 /\nEQLDIMS\n 1 /\nSTART\n 1 'JAN' 2020 /\nUNIFOUT\nGRID\nINIT\n"
    text += "INCLUDE\n 'grid.grdecl' /\n" + "\n".join(grid) + "\n"
    if edit:
        text += "EDIT\n" + "\n".join(edit) + "\n"
    text += rest_of_deck(float(deck.zcorn.min()), float(deck.zcorn.max()) + 1)
    (work / "CASE.DATA").write_text(text)
    return work / "CASE.DATA"


def pairs_apart(cells: np.ndarray, step: int, nx: int) -> np.ndarray:
    """The active cells g whose cell g + step is active too (in the same row for step 1)."""
    ok = np.isin(cells + step, cells)
    return cells[ok & (cells % nx < nx - 1)] if step == 1 else cells[ok]


def random_case(work: Path, seed: int) -> tuple[Path, tuple[int, int]]:
    """A faulted corner-point deck (MRST's simpleGrdecl with throw) using every multiplier
    and edit keyword on random boxes, cells and regions; and the pair of its NNC below 1e-6."""
    rng = np.random.default_rng(seed)
    dims = [(6, 5, 4), (8, 6, 5), (10, 8, 5), (8, 5, 3), (6, 6, 4), (10, 7, 4)][seed % 6]  # nx even: a fault
    units = "FIELD" if seed % 2 else "METRIC"
    nx, ny, nz = dims
    nc = nx * ny * nz
    scale = 1.0 / 0.3048 if units == "FIELD" else 1.0
    deck = simple_grdecl(dims, rng.uniform(3, 12) * scale, phys_dims=(600 * scale, 500 * scale, 40 * scale))
    active = (rng.random(nc) > 0.06).astype(np.int32)
    deck = replace(deck, actnum=active)
    g = np.arange(nc)
    i, j, k = g % nx, g // nx % ny, g // (nx * ny)
    data = {
        "PORO": rng.uniform(0.1, 0.3, nc),
        "PERMX": rng.lognormal(4, 1, nc),
        "PERMY": rng.lognormal(4, 1, nc),
        "PERMZ": rng.lognormal(2, 1, nc),
        "NTG": rng.uniform(0.3, 1, nc),
    }
    for name in ("FLUXNUM", "MULTNUM", "OPERNUM"):  # region boundaries across i, j and k
        ci, cj, ck = rng.integers(1, nx), rng.integers(1, ny), rng.integers(1, nz)
        data[name] = 1 + (i >= ci) + 2 * (j >= cj) * (rng.random() < 0.7) + (k >= ck) * (rng.random() < 0.5)
    runspec, grid, edit = [], [], []
    for name in ("MULTX", "MULTX-", "MULTY", "MULTY-", "MULTZ", "MULTZ-"):
        if rng.random() < 0.7:
            grid.append(f"EQUALS\n '{name}' {rng.uniform(0.0, 2.0):.4f} {_text(_box(rng, dims))} /\n/")
    box = _box(rng, dims)
    multz = _text(np.round(rng.uniform(0, 3, _size(box)), 4))
    grid.append(f"BOX\n {_text(box)} /\nMULTZ\n {multz} /\nENDBOX")
    fi = nx // 2  # the throw lies between columns fi and fi + 1 (1-based)
    faults = [f"'F1' {fi} {fi} 1 {ny} 1 {nz} X", f"'F2' 1 {nx} 2 2 1 {nz} Y", f"'F3' 1 2 1 {ny} 2 2 Z"]
    grid.append("FAULTS\n" + "".join(f" {f} /\n" for f in faults) + "/")
    grid.append(f"MULTFLT\n 'F1' {rng.uniform(0, 1):.4f} /\n 'F2' {rng.uniform(0, 1):.4f} /\n 'F3' 0.3 /\n/")
    if rng.random() < 0.5:
        runspec.append(f"GRIDOPTS\n 'YES' {int(rng.integers(0, 3))} /")
    records = []
    for _ in range(int(rng.integers(2, 6))):
        r1 = str(int(rng.integers(1, 5))) if rng.random() < 0.8 else "1*"
        r2 = str(int(rng.integers(1, 5))) if rng.random() < 0.8 else "-1"
        r2 = "1*" if r1 == r2 else r2
        directions = rng.choice(["X", "Y", "Z", "XY", "XZ", "YZ", "XYZ", "1*"])
        option = rng.choice(["ALL", "NNC", "NONNC", "1*"])
        region_set = rng.choice(["M", "F", "O", "1*"])
        records.append(f" {r1} {r2} {rng.uniform(0, 2):.4f} {directions} {option} {region_set} /")
    grid.append("MULTREGT\n" + "\n".join(records) + "\n/")

    edit.append(f"MULTFLT\n 'F1' {rng.uniform(0, 1):.4f} /\n/")  # replaces GRID's
    edit.append(f"MULTX\n {nc}*{rng.uniform(0.5, 1.5):.3f} /")  # multiplies GRID's MULTX
    edit.append(f"MULTREGT\n 1 2 {rng.uniform(0, 2):.4f} XYZ ALL F /\n/")
    scale_of = {"EQUALS": 50, "MULTIPLY": 3, "ADD": 5, "MINVALUE": 20, "MAXVALUE": 20}
    for keyword in ("TRANX", "TRANY", "TRANZ"):
        for op in rng.choice(list(scale_of), size=2, replace=False):
            value = rng.uniform(0.5, 1) * scale_of[op]
            edit.append(f"{op}\n {keyword} {value:.4f} {_text(_box(rng, dims))} /\n/")
        box = _box(rng, dims)
        values = [f"{v:.3f}" for v in rng.uniform(0.5, 30, _size(box))]
        if len(values) > 2:
            values[1] = "1*"  # leaves that cell's value as it is
        edit.append(f"BOX\n {_text(box)} /\n{keyword}\n {' '.join(values)} /\nENDBOX")

    cells = np.flatnonzero(active)
    nnc, editnnc = [], []
    for _ in range(6):  # new connections between random cells (not of one column)
        g1, g2 = rng.choice(cells, 2, replace=False)
        if g1 % (nx * ny) != g2 % (nx * ny):
            nnc.append(f" {_ijk(g1, dims)} {_ijk(g2, dims)} {rng.uniform(0.01, 10):.4f} /")
            if rng.random() < 0.5:
                editnnc.append(f" {_ijk(g2, dims)} {_ijk(g1, dims)} {rng.uniform(0, 3):.4f} /")
    first = int(rng.choice(cells[cells % nx == 0]))
    last = cells[(cells % nx == nx - 1) & ~np.isin(np.abs(cells - first), [1, nx, nx * ny])]
    tiny = tuple(sorted((first, int(rng.choice(last)))))  # not neighbours, even by index
    nnc.append(f" {_ijk(tiny[0], dims)} {_ijk(tiny[1], dims)} 4e-7 /")  # below 1e-6: dropped
    fault = process_grdecl(replace(deck, cell_data=data)).nnc
    fault = fault.global_cells[fault.kind == FAULT]
    p = fault[int(rng.integers(len(fault)))]  # on a fault connection: added to the grid's value
    nnc.append(f" {_ijk(p[0], dims)} {_ijk(p[1], dims)} {rng.uniform(0.1, 5):.4f} /")
    editnnc.append(f" {_ijk(p[0], dims)} {_ijk(p[1], dims)} {rng.uniform(0.1, 3):.4f} /")  # NNC value only
    for p in fault[rng.choice(len(fault), min(4, len(fault)), replace=False)]:
        editnnc.append(f" {_ijk(p[1], dims)} {_ijk(p[0], dims)} {rng.uniform(0, 3):.4f} /")
    for g in rng.choice(pairs_apart(cells, nx * ny, nx), 2, replace=False):  # vertical: EDITNNC applies
        editnnc.append(f" {_ijk(g, dims)} {_ijk(g + nx * ny, dims)} {rng.uniform(0, 3):.4f} /")
    g = int(rng.choice(pairs_apart(cells, ny, nx)))  # ny apart: EDITNNC skipped in Flow 2022.10
    nnc.append(f" {_ijk(g, dims)} {_ijk(g + ny, dims)} 2.5 /")
    editnnc.append(f" {_ijk(g, dims)} {_ijk(g + ny, dims)} 0.1 /")
    g = int(rng.choice(pairs_apart(cells, 1, nx)))  # an NNC on a logical neighbour, inside a TRANX edit
    nnc.append(f" {_ijk(g, dims)} {_ijk(g + 1, dims)} 1.5 /")
    ijk = _ijk(g, dims).split()
    edit.append(f"MULTIPLY\n TRANX 0.5 {ijk[0]} {ijk[0]} {ijk[1]} {ijk[1]} {ijk[2]} {ijk[2]} /\n/")
    grid.append("NNC\n" + "\n".join(nnc) + "\n/")
    edit.append("EDITNNC\n" + "\n".join(editnnc) + "\n/")
    return write_case(work, deck, data, runspec, grid, edit, units), tiny


@pytest.mark.parametrize("seed", range(6))
def test_random_decks_with_every_keyword_equal_flow(seed, tmp_path):
    path, tiny = random_case(tmp_path / "deck", seed)
    c, ours = assert_same_as_flow(path, tmp_path / "out")
    deck = read_grdecl(path)
    assert deck.units == ("FIELD" if seed % 2 else "METRIC")
    assert len(deck.tran_edits) >= 9 and deck.nnc_keyword.num >= 4 and deck.editnnc.num >= 5
    assert any(n.startswith("MULTREGT:") for n in c.notes)
    assert tiny not in ours and any("non-neighbour connections below 1e-06" in n for n in c.notes)
    assert OTHER in c.kind and NEIGHBOR in c.kind


# --- MULTREGT as Flow 2022.10 applies it ----------------------------------------------------------


def multregt_case(work: Path, dims: tuple[int, int, int], nrmult: int | None) -> Path:
    """Region boundaries by layer (FLUXNUM 1-4), by row (MULTNUM 5|6 at j = 1|2, 6|7 at
    j = 3|4) and by column (OPERNUM 8|9 at the fault, 9|10 at i = 5|6), so that:
    vertical pairs count as NNCs (NNC applies, NONNC does not); rows 3|4 are not "side by
    side" when ny != nz (Flow's j is g // nx % nz); (3, 4) of FLUXNUM is replaced by a
    MULTNUM record; fault connections crossing layers 1|3 and the OPERNUM boundary take
    FLUXNUM's multiplier only; defaulted sets follow the previous record, the first one
    FLUXNUM, or MULTNUM with GRIDOPTS NRMULT > 0; defaulted regions in EDIT."""
    rng = np.random.default_rng(7)
    nx, ny, nz = dims
    nc = nx * ny * nz
    deck = simple_grdecl(dims, 14.0, phys_dims=(800.0, 600.0, 40.0))
    g = np.arange(nc)
    i, j, k = g % nx, g // nx % ny, g // (nx * ny)
    data = {
        "PORO": rng.uniform(0.1, 0.3, nc),
        "PERMX": rng.lognormal(4, 1, nc),
        "PERMY": rng.lognormal(4, 1, nc),
        "PERMZ": rng.lognormal(2, 1, nc),
        "FLUXNUM": k + 1,
        "MULTNUM": 5 + (j >= 2) + (j >= 4),
        "OPERNUM": 8 + (i >= nx // 2) + (i >= nx // 2 + 2),
    }
    runspec = [] if nrmult is None else [f"GRIDOPTS\n 'NO' {nrmult} /"]
    grid = [
        """MULTREGT
 1 2 0.5 Z NNC 1* /
 2 3 0.25 XYZ NONNC F /
 6 7 0.3 Y NONNC M /
 5 6 0.35 XY NNC /
 8 9 0.7 XYZ ALL O /
 3 4 0.9 XYZ ALL F /
 4 3 0.2 XYZ ALL M /
 2 4 0.6 XYZ ALL 1* /
 1 3 0.55 X ALL F /
/"""
    ]
    return write_case(work, deck, data, runspec, grid, ["MULTREGT\n 1* 10 0.45 XYZ ALL O /\n/"])


@pytest.mark.parametrize(("dims", "nrmult"), [((8, 6, 4), None), ((8, 6, 4), 2), ((8, 8, 4), 0)])
def test_multregt_rules_of_flow(dims, nrmult, tmp_path):
    path = multregt_case(tmp_path / "deck", dims, nrmult)
    _, ours = assert_same_as_flow(path, tmp_path / "out")
    plain = deck_transmissibility(replace(read_grdecl(path), multregt=()))
    before = dict(zip(map(tuple, plain.global_cells.tolist()), plain.trans.tolist(), strict=True))
    factor = {p: ours[p] / before[p] for p in ours}
    nx, ny, nz = dims
    layer = nx * ny

    def at(i, j, k):
        return i + nx * (j + ny * k)

    # vertical, layers 1|2: "1 2 0.5 Z NNC" (FLUXNUM unless NRMULT > 0 makes MULTNUM the default)
    assert factor[(at(0, 0, 0), at(0, 0, 1))] == pytest.approx(1.0 if nrmult else 0.5)
    # vertical, layers 2|3: NONNC does not apply to a column; layers 3|4: replaced by MULTNUM's
    assert factor[(at(0, 0, 1), at(0, 0, 2))] == pytest.approx(1.0)
    assert factor[(at(0, 0, 2), at(0, 0, 3))] == pytest.approx(1.0)
    # rows 3|4 (MULTNUM 6|7) "NONNC": side by side by Flow's j only where (j + ny k) % nz is
    for kk in range(nz):
        side = abs((3 + ny * kk) % nz - (4 + ny * kk) % nz) == 1
        assert factor[(at(0, 3, kk), at(0, 4, kk))] == pytest.approx(0.3 if side else 1.0)
    # OPERNUM 9|10 (columns 5|6 of 8): the defaulted region of EDIT's record
    assert factor[(at(5, 0, 0), at(6, 0, 0))] == pytest.approx(0.45)
    # across the fault (OPERNUM 8|9 "ALL" 0.7), layers 1|3: FLUXNUM's record, the first set tried
    # that applies, wins (no product); layers 2|4: the record "2 4" (set M) left FLUXNUM without it
    across = [p for p in ours if p[1] - p[0] not in (1, nx, layer)]
    layers = [{p[0] // layer, p[1] // layer} for p in across]
    assert sum(kk == {0, 2} for kk in layers) > 0 and sum(kk == {1, 3} for kk in layers) > 0
    for p, kk in zip(across, layers, strict=True):
        if kk in ({0, 2}, {1, 3}):
            assert factor[p] == pytest.approx(0.55 if kk == {0, 2} else 0.7)


# --- values worked out by hand -----------------------------------------------------------------------

HAND_DECK = """RUNSPEC
DIMENS
 3 2 2 /
METRIC
GRID
DX
 12*10 /
DY
 12*20 /
DZ
 12*5 /
TOPS
 6*1000 /
PERMX
 12*100 /
PERMY
 12*100 /
PERMZ
 12*10 /
FLUXNUM
 1 2 2 1 2 2 1 2 2 1 2 2 /
MULTREGT
 1 2 0.5 X ALL F /
/
NNC
 1 1 1 3 2 2 0.7 /
 1 1 1 2 1 1 1.0 /
 3 2 1 3 2 2 0.3 /
/
EDIT
EQUALS
 TRANY 3.0 1 1 1 1 1 1 /
/
MULTIPLY
 TRANZ 2.0 /
/
EDITNNC
 3 2 2 1 1 1 2.0 /
 1 1 1 1 1 2 3.0 /
 1 1 1 3 2 1 4.0 /
 3 2 1 3 2 2 2.0 /
 3 2 2 3 2 1 5.0 /
/
"""


def test_every_step_by_hand(tmp_path):
    """3x2x2 boxes of 10 x 20 x 5 m, PERMX = PERMY = 100 mD, PERMZ = 10 mD: K A / d is 1000
    mD m along x, 250 along y, 400 along z, times METRIC's Darcy constant; Flow agrees."""
    (tmp_path / "HAND.DATA").write_text(HAND_DECK)
    deck = read_grdecl(tmp_path / "HAND.DATA")
    c = deck_transmissibility(deck)
    t = dict(zip(map(tuple, c.global_cells.tolist()), c.trans.tolist(), strict=True))
    tx, ty, tz = (v * METRIC.darcy_constant for v in (1000.0, 250.0, 400.0))
    assert t[(0, 1)] == pytest.approx(0.5 * tx + 1.0, rel=1e-12)  # MULTREGT, then the NNC value added
    assert t[(1, 2)] == pytest.approx(tx, rel=1e-12)
    assert t[(3, 4)] == pytest.approx(0.5 * tx, rel=1e-12)
    assert t[(0, 3)] == pytest.approx(3.0, rel=1e-12)  # EQUALS TRANY in cell (1, 1, 1)
    assert t[(1, 4)] == pytest.approx(ty, rel=1e-12)
    assert t[(0, 6)] == pytest.approx(2.0 * tz * 3.0, rel=1e-12)  # MULTIPLY TRANZ, EDITNNC on a neighbour
    assert t[(1, 7)] == pytest.approx(2.0 * tz, rel=1e-12)
    # the NNC keyword's last pair (by index): EDITNNC's first record multiplies its value, the
    # second one the grid's connection (Flow 2022.10's matching loop)
    assert t[(5, 11)] == pytest.approx(2.0 * tz * 5.0 + 0.3 * 2.0, rel=1e-12)
    assert t[(0, 11)] == pytest.approx(0.7 * 2.0, rel=1e-12)  # NNC, its value times EDITNNC
    assert c.counts() == {"neighbor": 8 + 6 + 6, "fault": 0, "pinch": 0, "other": 1}
    assert any("EDITNNC: 1 pairs the grid does not join ignored" in n for n in c.notes)  # (1,1,1)-(3,2,1)
    runspec = "RUNSPEC\nOIL\nWATER\nTABDIMS\n 1 1 20 20 /\nEQLDIMS\n 1 /\nSTART\n 1 'JAN' 2020 /\n"
    text = HAND_DECK.replace("RUNSPEC\n", runspec).replace("GRID\n", "GRID\nINIT\nPORO\n 12*0.2 /\n", 1)
    (tmp_path / "FLOW.DATA").write_text(text + rest_of_deck(1000.0, 1006.0))
    _, flow = assert_same_as_flow(tmp_path / "FLOW.DATA", tmp_path / "out")
    assert flow == pytest.approx(t, rel=1e-12)


# --- the reader's records ------------------------------------------------------------------------------


def _deck(tmp_path: Path, grid: str, edit: str = "", runspec: str = "") -> Path:
    text = f"RUNSPEC\nDIMENS\n 3 2 2 /\n{runspec}\nGRID\nDX\n 12*10 /\nDY\n 12*20 /\nDZ\n 12*5 /\n"
    text += f"TOPS\n 6*1000 /\nPERMX\n 12*100 /\n{grid}\n" + (f"EDIT\n{edit}\n" if edit else "")
    (tmp_path / "D.DATA").write_text(text)
    return tmp_path / "D.DATA"


def test_reader_keeps_records_in_deck_order(tmp_path):
    path = _deck(
        tmp_path,
        "FLUXNUM\n 12*1 /\nMULTNUM\n 6*1 6*2 /\nMULTREGT\n 1 2 0.5 /\n 1* -1 2 xz nnc m /\n/\n"
        "NNC\n 1 1 1 3 2 2 /\n 3 2 1 1 1 2 0.25 4* /\n/\nMULTX\n 12*0.5 /\nMULTFLT\n 'A' 0.1 /\n/\n"
        "FAULTS\n 'A' 1 1 1 2 1 2 X /\n/",
        "MULTX\n 6*2 6* /\nMULTFLT\n 'A' 0.3 /\n/\nBOX\n 1 2 1 1 1 1 /\nTRANX\n 2.5 1* /\nENDBOX\n"
        "MAXVALUE\n TRANZ 7 1 3 1 1 1 1 /\n TRANY 8 /\n/\nMULTREGT\n 2 1 0.1 Z NONNC /\n/\n"
        "EDITNNC\n 1 1 1 3 2 2 0.5 /\n/\nCOPY\n TRANX TRANY /\n/",
        "GRIDOPTS\n 'YES' 2 /",
    )
    deck = read_grdecl(path)
    assert deck.gridopts.tranmult and deck.gridopts.nrmult == 2 and deck.gridopts.nrpinc == 0
    assert [
        (r.region1, r.region2, r.multiplier, r.directions, r.nnc_option, r.region_set) for r in deck.multregt
    ] == [
        (1, 2, 0.5, "XYZ", "ALL", None),
        (None, None, 2.0, "XZ", "NNC", "M"),
        (2, 1, 0.1, "Z", "NONNC", None),
    ]
    assert [r.source for r in deck.multregt] == ["D.DATA:22", "D.DATA:23", "D.DATA:53"]
    np.testing.assert_array_equal(deck.nnc_keyword.cells, [[0, 11], [5, 6]])
    np.testing.assert_array_equal(deck.nnc_keyword.values, [0.0, 0.25])  # TRAN defaults to 0
    np.testing.assert_array_equal(deck.editnnc.cells, [[0, 11]])
    np.testing.assert_array_equal(deck.cell_data["MULTX"], [1.0] * 6 + [0.5] * 6)  # EDIT multiplies
    np.testing.assert_array_equal(deck.cell_data["MULTNUM"], [1] * 6 + [2] * 6)
    assert deck.multflt == {"A": 0.3}  # EDIT's replaces GRID's
    ops = [(e.keyword, e.operation, e.box, e.value) for e in deck.tran_edits]
    assert ops == [
        ("TRANX", "SET", (0, 1, 0, 0, 0, 0), None),
        ("TRANZ", "MAXVALUE", (0, 2, 0, 0, 0, 0), 7.0),
        ("TRANY", "MAXVALUE", (0, 2, 0, 1, 0, 1), 8.0),
    ]
    np.testing.assert_array_equal(deck.tran_edits[0].values, [2.5, np.nan])  # 1*: left as it is
    assert any("COPY TRANX TRANY ignored" in n for n in deck.notes)
    assert "TRANX" not in deck.cell_data and "TRANY" not in deck.cell_data


# --- bad input --------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("grid", "edit", "message"),
    [
        ("MULTREGT\n 1 2 0.5 XX /\n/", "", r"D\.DATA:17: MULTREGT: directions 'XX'"),
        ("MULTREGT\n 1 2 /\n/", "", r"D\.DATA:17: MULTREGT: a record needs a multiplier"),
        ("MULTREGT\n 1 2 0.5 X ALL Q /\n/", "", r"D\.DATA:17: MULTREGT: region set 'Q'"),
        ("MULTREGT\n 1 2 0.5 X SOME /\n/", "", r"D\.DATA:17: MULTREGT: NNC option 'SOME'"),
        ("MULTREGT\n 1 2 -0.5 /\n/", "", r"D\.DATA:17: MULTREGT: the multiplier must be"),
        ("MULTREGT\n 1 2 0.5 X ALL M 7 /\n/", "", r"D\.DATA:17: MULTREGT: a record has 7 items"),
        ("MULTREGT\n a 2 0.5 /\n/", "", r"D\.DATA:17: MULTREGT: region 1: 'a' is not an integer"),
        (
            "",
            "EDITNNC\n 1 1 1 4 2 2 0.5 /\n/",
            r"D\.DATA:19: EDITNNC: cell \(4, 2, 2\) is not inside the 3x2x2",
        ),
        ("", "EDITNNC\n 1 1 1 3 2 /\n/", r"D\.DATA:19: EDITNNC: a record needs six cell indices"),
        ("", "EDITNNC\n 1 1 1 3 2 2 -1 /\n/", r"D\.DATA:19: EDITNNC: multiplier must be >= 0"),
        ("", "EDITNNC\n 1 1 1 1.5 2 2 2 /\n/", r"D\.DATA:19: EDITNNC: cell index: '1.5' is not an integer"),
        ("NNC\n 1 1 1 1 1 1 2 /\n/", "", r"D\.DATA:17: NNC: cell \(1, 1, 1\) is joined to itself"),
        ("NNC\n 1 1 1 2 1 1 x /\n/", "", r"D\.DATA:17: NNC: transmissibility: 'x' is not a number"),
        ("MULTX\n 11*0.5 /", "", r"D\.DATA:16: MULTX: has 11 values, expected 12"),
        ("EQUALS\n TRANX 2 /\n/", "", r"D\.DATA:17: EQUALS: TRANX can only be modified in the EDIT section"),
        ("", "COPY\n PERMX TRANY /\n/", r"D\.DATA:19: COPY: cannot copy into TRANY"),
        ("", "MULTIPLY\n TRANZ 1* /\n/", r"D\.DATA:19: MULTIPLY: a record needs a keyword and a value"),
    ],
)
def test_malformed_records_name_file_line_and_keyword(tmp_path, grid, edit, message):
    with pytest.raises(DeckError, match=message):
        read_grdecl(_deck(tmp_path, grid, edit))


def test_bad_gridopts(tmp_path):
    with pytest.raises(DeckError, match=r"D\.DATA:5: GRIDOPTS: TRANMULT must be YES or NO"):
        read_grdecl(_deck(tmp_path, "", runspec="GRIDOPTS\n 'MAYBE' /"))


@pytest.mark.parametrize(
    ("grid", "message"),
    [
        ("PERMY\n 11*100 -1 /", r"D\.DATA: PERMY: 1 cells .* PERMY \(first -1\.0\): \(3, 2, 2\)"),
        ("NTG\n 5*1 -0.5 6*1 /", r"D\.DATA: NTG: 1 cells .* NTG \(first -0\.5\): \(3, 2, 1\)"),
        (
            "MULTY\n 3*1 -2 8*1 /",
            r"D\.DATA:\d+: MULTY: 1 values are negative \(first -2\): cells \(1, 2, 1\)",
        ),
        (
            "MULTREGT\n 1 2 0.5 X ALL O /\n/",
            r"D\.DATA:17: MULTREGT: region set OPERNUM is not given in the deck",
        ),
    ],
)
def test_bad_rock_and_multipliers_name_the_keyword(tmp_path, grid, message):
    path = _deck(tmp_path, grid)
    with pytest.raises(InputError, match=message):
        deck_transmissibility(read_grdecl(path))


def test_transmissibilities_beyond_any_float_name_the_deck_and_cells(tmp_path):
    """PERMX 1e300: finite values whose harmonic combination (t1 t2 / (t1 + t2), as Flow) is not."""
    path = _deck(tmp_path, "")
    path.write_text(path.read_text().replace("PERMX\n 12*100 /", "PERMX\n 12*1e300 /"))
    message = r"D\.DATA: 20 transmissibilities are beyond any float "
    message += r"\(first between cells \(1, 1, 1\) and \(2, 1, 1\)\)"
    with pytest.raises(InputError, match=message):
        deck_transmissibility(read_grdecl(path))


def test_missing_permeability_and_partial_regions(tmp_path):
    path = _deck(tmp_path, "")
    path.write_text(path.read_text().replace("PERMX\n 12*100 /\n", ""))
    with pytest.raises(InputError, match=r"D\.DATA: PERMX: the deck gives no permeability"):
        deck_transmissibility(read_grdecl(path))
    path = _deck(tmp_path, "EQUALS\n FLUXNUM 2 1 1 1 1 1 1 /\n/\nMULTREGT\n 1 2 0.5 /\n/")
    message = r"D\.DATA: FLUXNUM: 11 active cells have no region number .* D\.DATA:20: MULTREGT"
    with pytest.raises(InputError, match=message):
        deck_transmissibility(read_grdecl(path))
    with pytest.raises(DeckError, match=r"D\.DATA:16: FLUXNUM: has 11 values, expected 12"):
        read_grdecl(_deck(tmp_path, "FLUXNUM\n 11*1 /"))


def test_records_flow_refuses_are_noted(tmp_path):
    """MULTREGT within one region and NOAQUNNC stop Flow 2022.10; here they are noted
    (ignored, and applied as ALL), and so are a MULTFLT of a fault FAULTS does not define and
    GRIDOPTS items Flow does not act on (TRANMULT NO with MULTX-, NRPINC)."""
    grid = "FLUXNUM\n 6*1 6*2 /\nMULTREGT\n 1 1 0.5 /\n 1 2 0.25 Z NOAQUNNC F /\n/\nMULTFLT\n 'B' 2 /\n/"
    path = _deck(tmp_path, grid + "\nMULTX-\n 12*0.5 /", runspec="GRIDOPTS\n 'NO' 0 2 /")
    deck = read_grdecl(path)
    c = deck_transmissibility(deck)
    t = dict(zip(map(tuple, c.global_cells.tolist()), c.trans.tolist(), strict=True))
    tz = 4000.0 * METRIC.darcy_constant  # PERMZ = PERMX = 100 mD: K A / d = 100 * 200 / 5
    assert t[(0, 6)] == pytest.approx(0.25 * tz, rel=1e-12)
    assert any("MULTREGT within region 1 ignored" in n for n in c.notes)
    assert any("NOAQUNNC applied as ALL" in n for n in c.notes)
    assert any("MULTFLT of fault 'B' ignored" in n for n in deck.notes)
    assert t[(0, 1)] == pytest.approx(0.5 * 1000.0 * METRIC.darcy_constant, rel=1e-12)  # MULTX- of cell 2
    assert any("GRIDOPTS TRANMULT is NO, yet MULTX- applied" in n for n in c.notes)
    assert any("GRIDOPTS NRPINC 2: PINCHNUM regions not used" in n for n in c.notes)


def _fields(records) -> list[tuple]:
    return [(r.region1, r.region2, r.multiplier, r.directions, r.nnc_option, r.region_set) for r in records]


def test_write_grdecl_keeps_multregt_and_nnc(tmp_path):
    """MULTREGT and NNC go into the GRID part write_grdecl writes (exact values, deck order,
    defaulted items as 1*); EDITNNC into its EDIT part, which edit=False leaves out."""
    grid = "FLUXNUM\n 6*1 6*2 /\nMULTREGT\n 1 2 0.1 /\n 1* -3 0.25 YZ NONNC F /\n/\n"
    grid += "NNC\n 1 1 1 3 2 2 0.3 /\n/"
    deck = read_grdecl(_deck(tmp_path, grid, "EDITNNC\n 1 1 1 3 2 2 2 /\n/"))
    write_grdecl(tmp_path / "out.grdecl", deck)
    back = read_grdecl(tmp_path / "out.grdecl")
    assert _fields(back.multregt) == [(1, 2, 0.1, "XYZ", "ALL", None), (None, None, 0.25, "YZ", "NONNC", "F")]
    np.testing.assert_array_equal(back.nnc_keyword.cells, [[0, 11]])
    assert back.nnc_keyword.values.tolist() == [0.3]
    np.testing.assert_array_equal(back.editnnc.cells, [[0, 11]])
    assert back.editnnc.values.tolist() == [2.0]
    assert read_grdecl(write_grdecl(tmp_path / "grid_only.grdecl", deck, edit=False)).editnnc is None


@pytest.mark.parametrize("seed", [0, 1])
def test_same_bits_for_every_thread_count(seed, tmp_path, monkeypatch):
    """The connections are computed in blocks on the threads (faces, halves, multipliers, the
    sort's gathers): every array is the same, bit for bit, whatever the number of threads."""
    path, _ = random_case(tmp_path / "deck", seed)
    deck = read_grdecl(path)
    results = []
    for threads in ("1", "2", "3"):
        monkeypatch.setenv("GRIDLIB_NUM_THREADS", threads)
        for pinch in (False, True):
            c = deck_transmissibility(deck, pinch=pinch)
            results.append((threads, pinch, c))
    for threads, pinch, c in results[2:]:
        ref = results[pinch][2]  # one thread, the same PINCH
        assert c.notes == ref.notes, threads
        for name in ("cells", "global_cells", "trans", "kind", "face"):
            assert getattr(c, name).tobytes() == getattr(ref, name).tobytes(), (threads, pinch, name)
    assert results[0][2].num > 100
