"""Vertical wells on a fault (mid-trace, at a tip, where two or three faults meet) and next to it:
the well has no site of its own, one fault cell is its, on the side ``fault_side`` says or the
nearer one, with a note; the grid keeps every PEBI invariant. And the last-resort error names the
case keys that would fix the layout."""

from __future__ import annotations

import numpy as np
import pytest
from pebi_invariants import check_pebi

import gridlib as gl
from gridlib.case.wells import pebi_wells
from gridlib.config import load_case
from gridlib.voronoi import Fault, Rings, Well, fault_layout, pebi_grid
from gridlib.voronoi.pebi_result import FAULT

H = 10.0
DOMAIN = np.array([(0.0, 0.0), (100.0, 0.0), (100.0, 100.0), (0.0, 100.0)])
ONE = [Fault([(10, 20), (90, 70)])]  # through (50, 45), direction (0.848, 0.530)
TIP = [Fault([(10, 20), (70, 60)])]
CROSS = [Fault([(10, 20), (90, 80)]), Fault([(10, 80), (90, 20)])]  # cross at (50, 50)
SPLAY = [Fault([(50, 50), (90, 60)]), Fault([(50, 50), (20, 90)]), Fault([(50, 50), (30, 10)])]
RINGS = Rings(inner=0.5, outer=8.0)


def _build(faults, well: Well):
    pg = pebi_grid(DOMAIN, H, faults, [well])
    check_pebi({"domain": DOMAIN, "offset": np.zeros(2), "faults": faults, "wells": [well]}, pg, h=H)
    return pg


def _cell(pg) -> int:
    (cell,) = np.flatnonzero(pg.cell_well == 1)  # one cell, a fault cell
    assert pg.site_kind[cell] == FAULT
    return int(cell)


def _side(site: np.ndarray, a, b) -> float:
    """+ left, - right of the segment a -> b."""
    t = np.subtract(b, a)
    rel = site - np.asarray(a, dtype=float)
    return float(t[0] * rel[1] - t[1] * rel[0])


def _slack(pg, cell: int, p) -> float:
    """How much farther (m) ``p`` is from the cell's site than from the nearest site: 0 when ``p``
    lies in the cell or on its boundary (the cells are the sites' Voronoi regions)."""
    d = np.hypot(*(pg.sites - np.asarray(p, dtype=float)).T)
    return float(d[cell] - d.min())


NOTE = (
    "well 'W1' (wells[0]) {where}: it has no site of its own (it would lie in the fault's circles); "
    "its cell is the fault cell {side} {fault} (as drawn), site at {at}: {why}"
)
DEFAULT = "both sides are equally near, the left is the default (fault_side chooses)"


def _at(xy: np.ndarray) -> str:
    """A point as the messages write it: to the millimetre."""
    return "(" + ", ".join(f"{v:.3f}".rstrip("0").rstrip(".") for v in xy) + ")"


def _note(where: str, side: str, site, why: str, rings) -> str:
    """The note of well 'W1' (wells[0]) given a fault cell ``side`` ("left"/"right") of fault
    'F1' (faults[0]), its site at ``site``, for the reason ``why``; with ``rings``, that they
    are not built."""
    note = NOTE.format(where=where, side=f"{side} of", fault="fault 'F1' (faults[0])", at=_at(site), why=why)
    return note + ("; its rings are not built" if rings else "")


@pytest.mark.parametrize("rings", [None, RINGS], ids=["no_rings", "rings"])
@pytest.mark.parametrize("side", [None, "left", "right"])
def test_a_well_on_a_trace_gets_the_fault_cell_on_its_side(side, rings):
    """Exactly on the trace: the well's point lies on the fault face between its cell and the
    cell across; the cell is left of the trace by default, else the side asked for."""
    pg = _build(ONE, Well((50, 45), rings=rings, fault_side=side))
    cell = _cell(pg)
    sign = -1.0 if side == "right" else 1.0
    assert sign * _side(pg.sites[cell], (10, 20), (90, 70)) > 0
    assert _slack(pg, cell, (50, 45)) == pytest.approx(0.0, abs=1e-9 * H)
    # its site and its mirror across the trace are the fault pair of the step holding the well
    mirror = pg.sites[cell] - 2 * _side(pg.sites[cell], (10, 20), (90, 70)) / np.hypot(80, 50) * np.array(
        [-50, 80]
    ) / np.hypot(80, 50)
    assert np.hypot(*(pg.sites - mirror).T).min() == pytest.approx(0.0, abs=1e-9 * H)
    why = DEFAULT if side is None else f"as its fault_side ({side!r}) says"
    assert _note("lies on fault 'F1' (faults[0])", side or "left", pg.sites[cell], why, rings) in pg.notes
    assert not any("refined locally" in n for n in pg.notes)  # no refinement for the well


@pytest.mark.parametrize("side", [None, "left", "right"])
def test_a_well_next_to_a_trace_takes_the_nearer_fault_cell_or_the_side_asked(side):
    """1.89 m right of the trace (a fifth of a cell): the nearer fault site is right of it, and
    the well lies inside that cell; ``fault_side`` may ask for the cell across."""
    p = (51.0, 43.4)  # right of the trace
    dist = abs(_side(np.array(p), (10, 20), (90, 70))) / np.hypot(80, 50)
    pg = (
        _build(ONE, Well(p, fault_side=side))
        if side != "left"
        else pebi_grid(DOMAIN, H, ONE, [Well(p, fault_side=side)])
    )
    cell = _cell(pg)
    want = "left" if side == "left" else "right"
    assert (_side(pg.sites[cell], (10, 20), (90, 70)) > 0) == (want == "left")
    if want == "right":
        assert _slack(pg, cell, p) == 0.0  # inside its cell
    else:
        assert _slack(pg, cell, p) > 0.1  # across the trace from it, as asked
    why = (
        "its site is the fault site nearest the well (fault_side chooses a side)"
        if side is None
        else f"as its fault_side ({side!r}) says"
    )
    where = f"lies {dist:.3g} m from fault 'F1' (faults[0]), closer than the fault's cells are wide"
    assert _note(where, want, pg.sites[cell], why, None) in pg.notes
    assert f"{dist:.3g}" == "1.89"


@pytest.mark.parametrize("rings", [None, RINGS], ids=["no_rings", "rings"])
def test_a_well_at_a_faults_tip(rings):
    """At the free end: the well lies on the corner its cell shares with the tip site's cell
    and the cell across; by default the left one of the last step."""
    pg = _build(TIP, Well((70, 60), rings=rings))
    cell = _cell(pg)
    assert _side(pg.sites[cell], (10, 20), (70, 60)) > 0
    assert _slack(pg, cell, (70, 60)) == pytest.approx(0.0, abs=1e-9 * H)
    # the last step's pair: the site is behind the tip, the tip site straight ahead
    along = np.dot(pg.sites[cell] - (70, 60), (60, 40))
    assert along < 0
    assert (
        _note("lies at the end of fault 'F1' (faults[0])", "left", pg.sites[cell], DEFAULT, rings) in pg.notes
    )
    right = _build(TIP, Well((70, 60), rings=rings, fault_side="right"))
    assert _side(right.sites[_cell(right)], (10, 20), (70, 60)) < 0


@pytest.mark.parametrize("rings", [None, RINGS], ids=["no_rings", "rings"])
@pytest.mark.parametrize(("faults", "names"), [(CROSS, "two"), (SPLAY, "three")], ids=["cross", "splay"])
def test_a_well_where_faults_meet(faults, names, rings):
    """At the crossing of two faults and at the node of a splay of three: the well lies on the
    node, a corner of its cell; the cell is left of the first fault, the one farther along it."""
    node = (50.0, 50.0)
    pg = _build(faults, Well(node, rings=rings))
    cell = _cell(pg)
    a, b = faults[0].points[0], faults[0].points[-1]
    assert _side(pg.sites[cell], a, b) > 0
    assert _slack(pg, cell, node) == pytest.approx(0.0, abs=1e-9 * H)
    # of the node's cells left of F1, the one farther along F1
    d = np.hypot(*(pg.sites - node).T)
    ring = np.flatnonzero(np.abs(d - d[cell]) <= 1e-9 * H)
    left = ring[[_side(pg.sites[k], a, b) > 1e-9 for k in ring]]
    assert np.dot(pg.sites[cell] - node, b - a) == pytest.approx(max(np.dot(pg.sites[left] - node, b - a)))
    meet = (
        "fault 'F1' (faults[0]) and fault 'F2' (faults[1])"
        if names == "two"
        else "fault 'F1' (faults[0]), fault 'F2' (faults[1]) and fault 'F3' (faults[2])"
    )
    assert _note(f"lies where {meet} meet", "left", pg.sites[cell], DEFAULT, rings) in pg.notes
    right = _build(faults, Well(node, rings=rings, fault_side="right"))
    assert _side(right.sites[_cell(right)], a, b) < 0


def test_two_wells_on_one_fault_cell_take_two_cells():
    """Two wells on the trace 5.2 m apart (about half a fault step) each get a fault cell of their own."""
    wells = [Well((50, 45)), Well((50 + 5.2 * 0.848, 45 + 5.2 * 0.53))]
    pg = pebi_grid(DOMAIN, H, ONE, wells)
    c1, c2 = np.flatnonzero(pg.cell_well == 1), np.flatnonzero(pg.cell_well == 2)
    assert c1.size == c2.size == 1 and c1[0] != c2[0]
    assert pg.site_kind[c1[0]] == pg.site_kind[c2[0]] == FAULT


PEBI_CASE = """name: on_fault
horizons:
  lattice: {x: {start: 0, stop: 1000, num: 11}, y: {start: 0, stop: 800, num: 9}}
  surfaces:
    - {name: top, plane: {depth: 1000}}
    - {name: base, plane: {depth: 1040}}
grid:
  type: pebi
  domain: {rectangle: [0, 0, 1000, 800]}
  cell_size: 100
  layers: 2
faults:
  - {name: F1, trace: [[500, -50], [500, 850]]}
wells:
  - {name: INJ, point: [500, 400], fault_side: SIDE}
"""


def test_a_case_file_chooses_the_side(tmp_path):
    """``fault_side`` in a case file reaches the grid: the well INJ on the N-S fault F1 (walked
    north) gets the fault cell east of it for ``right``; a bad value is refused naming the file
    and the key."""
    path = tmp_path / "on_fault.yaml"
    path.write_text(PEBI_CASE.replace("SIDE", "right"))
    case = load_case(path)
    (well,) = pebi_wells(case)
    assert well.fault_side == "right"
    fault = Fault(case.data["faults"][0]["trace"], "F1")
    pg = pebi_grid(((0, 0), (1000, 800)), 100.0, [fault], [well])
    gl.check_grid(pg.grid)
    cell = _cell(pg)
    assert pg.sites[cell, 0] > 500.0 and _slack(pg, cell, (500, 400)) == pytest.approx(0.0, abs=1e-7)
    assert any(n.startswith("well 'INJ' (wells[0]) lies on fault 'F1' (faults[0])") for n in pg.notes)
    path.write_text(PEBI_CASE.replace("SIDE", "east"))
    with pytest.raises(gl.InputError) as info:
        load_case(path)
    assert str(info.value) == f"{path}: wells[0].fault_side: 'east' is not one of ['left', 'right']"


def test_the_grid_stage_builds_a_case_with_a_well_where_two_faults_cross(tmp_path):
    """Through the workflow's stages: INJ (with rings) where the throwing fault F1 (walked north)
    crosses F2, ``fault_side: right``: its cell in each layer is the fault cell east of F1, the
    one farther north (along F1); the other wells keep their own cells."""
    import xarray as xr

    from gridlib.stages.grid import stage_grid
    from gridlib.stages.horizons import stage_horizons

    text = PEBI_CASE.replace("SIDE", "right, rings: {inner: 2, outer: 40}")
    f1 = "  - {name: F1, trace: [[500, -50], [500, 850]]}\n"
    f2 = "  - {name: F2, trace: [[100, 100], [900, 700]]}\n"
    text = text.replace(f1, f1.replace("]]}", "]], throw: 10}") + f2)
    path = tmp_path / "on_fault.yaml"
    path.write_text(text + "  - {name: P1, point: [300, 500]}\n")
    case = load_case(path)
    stage_horizons(case, horizons=tmp_path / "h.nc")
    stage_grid(case, grid=tmp_path / "g.nc", horizons=tmp_path / "h.nc")
    with xr.open_dataset(tmp_path / "g.nc") as ds:
        well, site, layer = ds["well"].values, ds["site"].values, ds["layer"].values
    assert np.bincount(well).tolist()[1:] == [2, 2]  # one cell per layer each
    inj = site[well == 1]
    assert sorted(layer[well == 1].tolist()) == [0, 1] and np.all(inj == inj[0])
    assert inj[0, 0] > 500.0 and inj[0, 1] > 400.0  # east of F1, north of the crossing
    assert np.all(site[well == 2] == [300.0, 500.0])


def test_a_library_well_with_a_bad_side_is_refused():
    with pytest.raises(
        gl.GridError, match=r"well 'P' \(wells\[0\]\): fault_side must be 'left', 'right' or None"
    ):
        pebi_grid(DOMAIN, H, ONE, [Well((50, 45), "P", fault_side="east")])
    with pytest.raises(gl.GridError, match=r"well 'P' \(wells\[0\]\): fault_side applies to a vertical well"):
        pebi_grid(DOMAIN, H, ONE, [Well(path=[(20, 60), (60, 90)], name="P", fault_side="left")])


def test_parallel_faults_a_sixtieth_of_a_cell_apart_build():
    """Two parallel faults 0.16 m apart with 10 m cells (just above the smallest feature honoured,
    1/64 of the cell size): the local refinement goes on while it makes fault steps smaller, and
    the grid builds with both traces honoured."""
    faults = [Fault([(10, 50), (90, 50)]), Fault([(10, 50.16), (90, 50.16)])]
    pg = pebi_grid(DOMAIN, H, faults)
    check_pebi({"domain": DOMAIN, "offset": np.zeros(2), "faults": faults, "wells": []}, pg, h=H)
    assert "fault spacing refined locally 7 time(s) to keep the empty-circle condition" in pg.notes


def test_the_last_resort_error_names_the_faults_the_place_and_cell_size(monkeypatch):
    """Where the refinement cannot help (forced here: it changes nothing), the error names both
    faults, the place, the fault step reached and cell_size, and no internal setting."""
    monkeypatch.setattr(fault_layout.FaultLayout, "refined", lambda self, requests: self)
    faults = [Fault([(10, 10), (40, 10)], "A"), Fault([(10, 10.3), (40, 10.3)], "B")]
    with pytest.raises(gl.GridError) as info:
        pebi_grid(((0, 0), (50, 20)), H, faults)
    message = str(info.value)
    assert message.startswith(
        "fault 'A' (faults[0]) and fault 'B' (faults[1]): no conforming PEBI sites near ("
    )
    assert (
        ": even with fault cells of 10 m there (refined locally from the cell size, 10 m) a site " in message
    )
    assert message.endswith("widen the angle or the separation of the traces, or give a smaller cell_size")
    assert "refinements" not in message and "times" not in message
