"""Real decks written by others, against what OPM Flow computes for them (flow_reference.npz).

Per deck: the active cells are Flow's, every active cell's bulk volume equals
Flow's PORV / (PORO * NTG * MULTPV) to 1e-6 relative (Flow writes float32), the
processed grid passes check_grid, and Reek's fault connections include every
pair ECLIPSE itself wrote into REEK.EGRID.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import gridlib as gl
from gridlib.cornerpoint.process import FAULT, process_grdecl
from gridlib.io.egrid import read_egrid
from gridlib.io.grdecl import read_grdecl

DECKS = [
    ("SPE9_CP", "spe9/SPE9_CP.DATA", "FIELD"),
    ("SPE10_MODEL1_CP", "spe10model1/SPE10_MODEL1_CP.DATA", "FIELD"),
    ("SPE1CASE1", "spe1/SPE1CASE1.DATA", "FIELD"),
    ("SPE1CASE2_ACTNUM", "spe1/SPE1CASE2_ACTNUM.DATA", "FIELD"),
    ("2_WLIFT_MODEL5_NOINC", "model5/2_WLIFT_MODEL5_NOINC.DATA", "METRIC"),
    ("REEK_GRDECL", "reek/REEK_GRDECL.DATA", "METRIC"),  # the text files
    ("REEK_FLOWWRAP", "reek/REEK_FLOWWRAP.DATA", "METRIC"),  # GDFILE: ECLIPSE's REEK.EGRID
] + [  # OPM's PINCH/MINPV decks: five stacked cells, some thin, MINPV 0.5 makes them inactive
    (name, f"pinch/{name}.DATA", None)
    for name in (
        "FIVE",
        "FIVE_ACTNUM",
        "FIVE_PINCH",
        "FIVE_PINCH_NOGAP",
        "FIVE_PINCH_NOGAP2",
        "FIVE_PINCH_NOGAP3",
    )
]


@pytest.fixture(scope="module")
def processed(decks_dir):
    cache = {}

    def get(relpath):
        if relpath not in cache:
            deck = read_grdecl(decks_dir / relpath)
            cache[relpath] = (deck, process_grdecl(deck))
        return cache[relpath]

    return get


@pytest.mark.parametrize(("name", "relpath", "units"), DECKS, ids=[d[0] for d in DECKS])
def test_active_cells_and_bulk_volumes_match_flow(processed, flow_reference, name, relpath, units):
    deck, r = processed(relpath)
    assert deck.units == units
    active = flow_reference[f"{name}_active"]
    np.testing.assert_array_equal(r.grid.cells.index_map, active)  # same cells, same order
    bulk = flow_reference[f"{name}_bulk"]
    np.testing.assert_allclose(r.bulk_volumes, bulk, rtol=1e-6)
    geo = gl.compute_geometry(r.grid)
    gl.check_grid(r.grid, geo)
    # The watertight polyhedra hold the same total volume (cells differ only where warped
    # faces are shared across faults: see gridlib.cornerpoint.volumes).
    assert geo.cell_volumes.sum() == pytest.approx(bulk.sum(), rel=1e-5)


def test_minpv_can_be_turned_off(decks_dir):
    deck = read_grdecl(decks_dir / "pinch" / "FIVE_PINCH_NOGAP3.DATA")
    assert deck.minpv == 0.5
    r = process_grdecl(deck)
    assert r.grid.cells.index_map.tolist() == [0, 4]  # thicknesses 1, 0.1, 0.3, 0.4, 2.2 m; PORO 1
    assert "3 cells with a pore volume below MINPV 0.5 were made inactive" in r.notes
    assert process_grdecl(deck, minpv=0).grid.num_cells == 5
    assert process_grdecl(deck, minpv=0.35).grid.cells.index_map.tolist() == [0, 3, 4]


def test_reference_totals_are_the_readme_figures(flow_reference):
    """The decks' README quotes Flow's sums (in rb or m3); our reference holds the same."""
    rb = 1728 / 9702
    assert flow_reference["SPE9_CP_bulk"].sum() * rb == pytest.approx(3.452794e9, rel=1e-6)
    assert flow_reference["SPE1CASE1_bulk"].sum() * rb == pytest.approx(1.781076e9, rel=1e-6)
    assert flow_reference["REEK_FLOWWRAP_bulk"].sum() == pytest.approx(2.939631e9, rel=1e-6)


def test_reek_egrid_read_directly_matches_flow(reek_dir, flow_reference):
    r = process_grdecl(read_egrid(reek_dir / "REEK.EGRID"))
    np.testing.assert_array_equal(r.grid.cells.index_map, flow_reference["REEK_FLOWWRAP_active"])
    np.testing.assert_allclose(r.bulk_volumes, flow_reference["REEK_FLOWWRAP_bulk"], rtol=1e-6)


@pytest.mark.parametrize("relpath", ["reek/REEK_GRDECL.DATA", "reek/REEK_FLOWWRAP.DATA"])
def test_reek_fault_connections_include_eclipses(processed, reek_dir, flow_reference, relpath):
    _, r = processed(relpath)
    eclipse = read_egrid(reek_dir / "REEK.EGRID").nnc
    assert eclipse.shape == (2874, 2)
    ours = np.sort(r.nnc.global_cells, axis=1)
    ours_set = set(map(tuple, ours.tolist()))
    assert set(map(tuple, np.sort(eclipse, axis=1).tolist())) <= ours_set
    # Flow finds 70 more (tiny overlaps); so do we: exactly Flow's 2944 pairs.
    assert ours_set == set(map(tuple, flow_reference["REEK_FLOWWRAP_nnc"].tolist()))
    assert np.all(r.nnc.kind == FAULT)


def test_reek_named_faults_tag_faces(processed):
    _, r = processed("reek/REEK_GRDECL.DATA")
    assert r.fault_names[:2] == ("F1", "F2")
    tags = r.grid.faces.tag
    assert np.any(tags == 1) and np.any(tags == 2)


@pytest.mark.parametrize(("sx", "sy", "sz"), [(-1, 1, 1), (1, -1, 1), (1, 1, -1)])
def test_reek_mirrored_and_z_up_give_the_same_volumes(reek_dir, sx, sy, sz):
    deck = read_egrid(reek_dir / "REEK.EGRID")
    ref = process_grdecl(deck)
    c = deck.coord.reshape(-1, 6) * [sx, sy, sz, sx, sy, sz]
    flipped = process_grdecl(dataclasses.replace(deck, coord=c.ravel(), zcorn=deck.zcorn * sz))
    geo = gl.compute_geometry(flipped.grid)
    gl.check_grid(flipped.grid, geo)
    np.testing.assert_allclose(np.sort(flipped.bulk_volumes), np.sort(ref.bulk_volumes), rtol=1e-12)
    np.testing.assert_allclose(
        np.sort(geo.cell_volumes), np.sort(gl.compute_geometry(ref.grid).cell_volumes), rtol=1e-10
    )
    assert flipped.nnc.num == ref.nnc.num


def test_seed_deck_written_by_mrst(decks_dir):
    """The seed's simpleGrdecl([4,2,3], .12, 'flat', true), as MRST wrote it."""
    r = process_grdecl(read_grdecl(decks_dir / "seed" / "simple_grdecl_4x2x3_flat_drop012.grdecl"))
    g = r.grid
    assert (g.num_cells, g.num_faces, g.num_nodes) == (24, 106, 72)
    fault = g.faces.tag > 0
    inner = (g.faces.neighbors >= 0).all(axis=1)
    assert (int(fault.sum()), int((fault & inner).sum()), int((fault & ~inner).sum())) == (14, 10, 4)
    assert int((g.cells.num_faces == 7).sum()) == 12
    assert gl.compute_geometry(g).cell_volumes.sum() == pytest.approx(0.494, abs=1e-12)


def test_deck_case_whose_deck_leaves_permx_undefined_writes_its_grid(tmp_path):
    """Issue 24: a deck giving PERMX to a BOX of the top layer only left the other columns
    undefined, and the grid stage's grid.grdecl refused them ('write_grdecl: PERMX has undefined
    (NaN) values') although the case gives its own permeability; they are written defaulted."""
    from gridlib.config import load_case
    from gridlib.stages import stage_grid

    (tmp_path / "box.DATA").write_text(
        "RUNSPEC\nDIMENS\n 3 2 2 /\nMETRIC\nGRID\nDX\n 12*100 /\nDY\n 12*100 /\nDZ\n 12*10 /\n"
        "TOPS\n 6*2000 /\nPORO\n 12*0.25 /\nBOX\n 1 2 1 2 1 1 /\nPERMX\n 4*100 /\nENDBOX\n"
    )
    case = tmp_path / "box.yaml"
    case.write_text(
        "name: box\ngrid: {type: deck, file: box.DATA}\n"
        "petrophysics: {porosity: {constant: 0.2}, permeability: {constant: 50}}\n"
    )
    stage_grid(load_case(case), grid=tmp_path / "grid.nc", grdecl=tmp_path / "grid.grdecl")
    assert "PERMX\n2*100.0 1* 2*100.0 1* 2*100.0 1*\n2*100.0 1*\n/" in (tmp_path / "grid.grdecl").read_text()
    back = read_grdecl(tmp_path / "grid.grdecl")
    np.testing.assert_array_equal(back.cell_data["PERMX"], np.tile([100.0, 100.0, np.nan], 4))
