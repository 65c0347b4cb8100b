"""Real public decks nobody here wrote, against OPM Flow 2022.10's dry run, run in the test.

For each deck (tests/data/decks/README.md: source, commit, licence), gridlib's
``read_grdecl`` -> ``process_grdecl`` -> ``deck_transmissibility`` and its pore volumes
(bulk volume x PORO x NTG x MULTPV in the deck's reservoir volume unit, as the
transmissibility stage computes them for a deck case) must give Flow's active cells, its
connection set, every T within 1e-6 relative (INIT stores float32) and every PORV within
1e-6 relative. Each of the four is its own test, so that a failure says which one differs
and by how much; T and PORV are compared on the pairs and cells both have.

* ``reek_rms``: Equinor's Reek model as it was run by ECLIPSE 2014.2 (res2df's test data):
  an RMS 10.1 export (MAPAXES, GDORIENT over two lines, a left-handed grid), FAULTS +
  MULTFLT, MULTIPLY PERMZ, EQUALS MULTZ with text after the record's '/', PINCH NOGAP,
  3 active cells with PORO 0. ECLIPSE's own EGRID of that run is compared too;
* ``emerald_hole*``: xtgeo-testdata's Emerald geomodel export (GDORIENT LEFT, a hole,
  PORO 0 in 5,389 of its 7,157 active cells) in a deck of ours, with and without PINCH and MINPV;
* ``spe10_model2``: SPE 10 model 2 as OPM ships it (60 x 220 x 85 = 1,122,000 cells by
  DX/DY/DZ/TOPS, FIELD units, OLDTRAN); its porosity and permeability files (tens of
  MB) are not vendored: the test writes a seeded stand-in of the same layout, with
  PORO 0 in 3% of the Ness cells (layers 36-85);
* ``spe9_minpv``: SPE 9's corner-point deck (FIELD) with MINPV 15000 rb.
"""

from __future__ import annotations

import lzma
import re
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from flow_tools import flow_connection_arrays, read_keywords, run_flow_dry

import gridlib.transmissibility.edits as edits
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.grdecl import read_grdecl
from gridlib.transmissibility import deck_transmissibility
from gridlib.units import unit_system

DECKS = Path(__file__).parents[1] / "data" / "decks"
REL = 1e-6  # Flow's INIT holds float32: 6e-8 relative


@dataclass(frozen=True)
class Computed:
    """Active cells (0-based linear, ascending), connections ((n, 2) linear pairs, first <
    second, sorted; T in deck units) and pore volumes per active cell (deck units)."""

    active: np.ndarray
    pairs: np.ndarray
    trans: np.ndarray
    porv: np.ndarray


@dataclass(frozen=True)
class Comparison:
    name: str
    deck: Path
    dims: tuple[int, int, int]
    flow: Computed
    gridlib_result: Computed | Exception

    def gridlib(self) -> Computed:
        """gridlib's result; its exception where gridlib failed (the test then fails with it)."""
        if isinstance(self.gridlib_result, Exception):
            raise self.gridlib_result
        return self.gridlib_result

    def ijk(self, g) -> list[tuple[int, int, int]]:
        nx, ny, _ = self.dims
        return [(int(v % nx) + 1, int(v // nx % ny) + 1, int(v // (nx * ny)) + 1) for v in np.atleast_1d(g)]


# --- the decks, laid out in a temporary folder --------------------------------------------------


def unpack(folder: str, dest: Path) -> Path:
    """Copy tests/data/decks/``folder`` to ``dest``, decompressing its .xz files."""
    src = DECKS / folder
    for path in sorted(src.rglob("*")):
        if path.is_dir():
            continue
        target = dest / path.relative_to(src)
        target.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix == ".xz":
            target.with_suffix("").write_bytes(lzma.decompress(path.read_bytes()))
        else:
            shutil.copyfile(path, target)
    return dest


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
    "emerald_hole_pinch": "PINCH\n 0.5 /\n",
    "emerald_hole_minpv": "MINPV\n 4000 /\n",
    "emerald_hole_pinch_nogap_minpv": "PINCH\n 0.5 NOGAP /\nMINPV\n 4000 /\n",
}


def emerald(work: Path, name: str) -> Path:
    root = unpack("emerald_hole", work)
    deck = root / "EMERALD_HOLE.DATA"
    text = re.sub(r"(?m)^INIT\s*$", "INIT\n" + EMERALD_OPTIONS[name].rstrip("\n"), deck.read_text(), count=1)
    out = root / f"{name.upper()}.DATA"
    out.write_text(text)
    return out


def spe10_model2(work: Path) -> Path:
    """SPE 10 model 2's deck with a seeded stand-in for its PHI and PERM include files:
    PORO uniform in [0.05, 0.35] (Tarbert, layers 1-35) or [0, 0.3] with 3% exact zeros
    (Ness); PERMX = PERMY lognormal, PERMZ 0.05-0.3 of PERMX (mD)."""
    root = unpack("spe10model2", work)
    nx, ny, nz = 60, 220, 85
    rng = np.random.default_rng(10)
    n = nx * ny * nz
    ness = np.repeat(np.arange(nz), nx * ny) >= 35
    poro = np.where(ness, rng.uniform(0.0, 0.3, n), rng.uniform(0.05, 0.35, n))
    poro[ness & (rng.random(n) < 0.03)] = 0.0
    permx = np.exp(rng.normal(np.where(ness, 1.0, 3.0), 2.0, n))
    permz = permx * rng.uniform(0.05, 0.3, n)
    _write_arrays(root / "SPE10MODEL2_PHI.INC", {"PORO": poro})
    _write_arrays(root / "SPE10MODEL2_PERM.INC", {"PERMX": permx, "PERMY": permx, "PERMZ": permz})
    return root / "SPE10_MODEL2.DATA"


def _write_arrays(path: Path, arrays: dict[str, np.ndarray]) -> None:
    with path.open("w") as f:
        for name, values in arrays.items():
            f.write(f"{name}\n")
            np.savetxt(f, values.reshape(-1, 6), fmt="%.6g")
            f.write("/\n")


def spe9_minpv(work: Path) -> Path:
    root = unpack("spe9", work)
    deck = root / "SPE9_CP.DATA"
    out = root / "SPE9_MINPV.DATA"
    out.write_text(re.sub(r"(?m)^GRID\s*$", "GRID\nMINPV\n 15000 /", deck.read_text(), count=1))
    return out


DECK_MAKERS = {
    "reek_rms": reek_rms,
    **{name: (lambda work, name=name: emerald(work, name)) for name in EMERALD_OPTIONS},
    "spe10_model2": spe10_model2,
    "spe9_minpv": spe9_minpv,
}


# --- what each computes ---------------------------------------------------------------------------


def flow_result(deck: Path, out: Path) -> tuple[Computed, tuple[int, int, int]]:
    case = run_flow_dry(deck, out)
    egrid = read_keywords(Path(f"{case}.EGRID"))
    init = read_keywords(Path(f"{case}.INIT"))
    dims = tuple(int(v) for v in egrid["GRIDHEAD"][1:4])
    active = np.flatnonzero(egrid["ACTNUM"] > 0)
    porv = init["PORV"].astype(np.float64)
    porv = porv[active] if porv.size == np.prod(dims) else porv
    pairs, trans = flow_connection_arrays(case)
    return Computed(active, pairs, trans, porv), dims


def gridlib_result(deck_path: Path) -> Computed:
    """Deck -> grid -> connections, and pore volumes as the transmissibility stage makes a
    deck case's: the deck's PORV where given, else bulk volume x PORO x NTG x MULTPV."""
    deck = read_grdecl(deck_path)
    cp = process_grdecl(deck)
    conn = deck_transmissibility(deck, cp)
    cells = cp.grid.cells.index_map
    data = deck.cell_data
    if "PORV" in data:
        porv = data["PORV"][cells]
    else:
        units = unit_system(deck.units)
        porv = cp.bulk_volumes * data["PORO"][cells] * units.length**3 / units.volume
        for name in ("NTG", "MULTPV"):
            porv = porv * data[name][cells] if name in data else porv
    order = np.lexsort((conn.global_cells[:, 1], conn.global_cells[:, 0]))
    return Computed(np.asarray(cells), conn.global_cells[order], conn.trans[order], np.asarray(porv))


@pytest.fixture(scope="module", params=list(DECK_MAKERS))
def comparison(request, tmp_path_factory) -> Comparison:
    name = request.param
    work = tmp_path_factory.mktemp(name)
    deck = DECK_MAKERS[name](work / "deck")
    if name.startswith("emerald"):  # the export's FACIES is no ECLIPSE keyword
        with pytest.MonkeyPatch.context() as mp:
            mp.setenv("OPM_ERRORS_IGNORE", "PARSE_UNKNOWN_KEYWORD")
            flow, dims = flow_result(deck, work / "flow")
    else:
        flow, dims = flow_result(deck, work / "flow")
    try:
        ours: Computed | Exception = gridlib_result(deck)
    except Exception as exc:  # reported by each test that needs it
        ours = exc
    return Comparison(name, deck, dims, flow, ours)


# --- the comparisons ------------------------------------------------------------------------------


def _difference(c: Comparison, only: np.ndarray, who: str) -> str:
    return f"{only.size:,d} only in {who} (first (i, j, k): {c.ijk(only[:3])})"


def test_active_cells_equal_flow(comparison):
    c, flow = comparison, comparison.flow
    ours = c.gridlib()
    if not np.array_equal(ours.active, flow.active):
        raise AssertionError(
            f"{c.name}: active cells: gridlib {ours.active.size:,d}, Flow {flow.active.size:,d}; "
            + _difference(c, ours.active[~_within(ours.active, flow.active)], "gridlib")
            + "; "
            + _difference(c, flow.active[~_within(flow.active, ours.active)], "Flow")
        )


def _within(values: np.ndarray, sorted_set: np.ndarray) -> np.ndarray:
    """Which of ``values`` are in the ascending ``sorted_set`` (np.isin without its sort)."""
    pos = np.minimum(np.searchsorted(sorted_set, values), max(sorted_set.size - 1, 0))
    return sorted_set[pos] == values if sorted_set.size else np.zeros(values.size, dtype=bool)


def _keys(pairs: np.ndarray, c: Comparison) -> np.ndarray:
    """One ascending int64 per pair (the pairs are sorted)."""
    return pairs[:, 0] * int(np.prod(c.dims)) + pairs[:, 1]


def test_connections_equal_flow(comparison):
    c, flow = comparison, comparison.flow
    ours = c.gridlib()
    ka, kb = _keys(ours.pairs, c), _keys(flow.pairs, c)
    if not np.array_equal(ka, kb):
        only_ours, only_flow = ours.pairs[~_within(ka, kb)], flow.pairs[~_within(kb, ka)]
        raise AssertionError(
            f"{c.name}: connections: gridlib {ka.size:,d}, Flow {kb.size:,d}; "
            f"{len(only_ours):,d} only in gridlib (first: {[c.ijk(p) for p in only_ours[:3]]}); "
            f"{len(only_flow):,d} only in Flow (first: {[c.ijk(p) for p in only_flow[:3]]})"
        )


def test_transmissibilities_equal_flow(comparison):
    """On the pairs both have (all of them, once the sets agree)."""
    c, flow = comparison, comparison.flow
    ours = c.gridlib()
    common, ia, ib = np.intersect1d(
        _keys(ours.pairs, c), _keys(flow.pairs, c), assume_unique=True, return_indices=True
    )
    assert common.size > 0.9 * flow.trans.size, (common.size, flow.trans.size)
    a, b = ours.trans[ia], flow.trans[ib]
    rel = np.abs(a - b) / np.abs(b)
    worst = int(np.argmax(rel))
    assert rel[worst] <= REL, (
        f"{c.name}: {int((rel > REL).sum()):,d} of {common.size:,d} T differ by more than {REL:g}; "
        f"worst {c.ijk(flow.pairs[ib[worst]])}: gridlib {a[worst]!r}, Flow {b[worst]!r}"
    )


def test_pore_volumes_equal_flow(comparison):
    """On the cells both have active (all of them, once the sets agree)."""
    c, flow = comparison, comparison.flow
    ours = c.gridlib()
    common, ia, ib = np.intersect1d(ours.active, flow.active, assume_unique=True, return_indices=True)
    assert common.size > 0.9 * flow.active.size, (common.size, flow.active.size)
    a, b = ours.porv[ia], flow.porv[ib]
    rel = np.abs(a - b) / np.abs(b)
    worst = int(np.argmax(rel))
    assert rel[worst] <= REL, (
        f"{c.name}: {int((rel > REL).sum()):,d} of {common.size:,d} pore volumes differ by more "
        f"than {REL:g}; worst {c.ijk(common[worst])}: gridlib {a[worst]!r}, Flow {b[worst]!r}"
    )


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
    cp = process_grdecl(deck)
    cells = cp.grid.cells.index_map
    assert cells.size == active.size and np.array_equal(cells, active), (
        cells.size,
        np.setdiff1d(cells, active),
        deck.cell_data["PORO"][np.setdiff1d(cells, active)],
    )


def test_reek_fault_connections_equal_eclipse_but_at_the_threshold(reek_eclipse, monkeypatch):
    """ECLIPSE's EGRID lists 3,286 non-neighbour pairs; gridlib (and Flow) find 3,288. They
    differ by six fault connections whose T (MULTFLT 0.001) lie within a factor 4 of the 1e-6
    below which Flow drops a non-neighbour connection: ECLIPSE keeps two just below it
    (8.5e-7 and 9.95e-7 by gridlib's T) and leaves out four just above (1.0e-6 to 3.3e-6)."""
    deck_path, egrid = reek_eclipse
    nx, ny = (int(v) for v in egrid["GRIDHEAD"][1:3])
    n1, n2 = egrid["NNC1"].astype(np.int64) - 1, egrid["NNC2"].astype(np.int64) - 1
    eclipse = set(zip(np.minimum(n1, n2).tolist(), np.maximum(n1, n2).tolist(), strict=True))
    assert len(eclipse) == 3_286
    deck = read_grdecl(deck_path)
    cp = process_grdecl(deck)
    monkeypatch.setattr(edits, "NNC_THRESHOLD", 0.0)  # every fault connection, however small
    conn = deck_transmissibility(deck, cp)
    g = conn.global_cells
    far = ~np.isin(g[:, 1] - g[:, 0], (1, nx, nx * ny))
    t_of = dict(zip(map(tuple, g[far].tolist()), conn.trans[far].tolist(), strict=True))
    ours = {p for p, t in t_of.items() if t >= 1e-6}
    assert len(ours) == 3_288
    only_eclipse, only_ours = sorted(eclipse - ours), sorted(ours - eclipse)
    assert len(only_eclipse) == 2 and len(only_ours) == 4, (only_eclipse, only_ours)
    assert all(5e-7 < t_of[p] < 1e-6 for p in only_eclipse), [t_of.get(p) for p in only_eclipse]
    assert all(1e-6 <= t_of[p] < 4e-6 for p in only_ours), [t_of[p] for p in only_ours]
