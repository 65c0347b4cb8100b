"""Layers that overlap on a pillar, as geomodelling exports carry them: the readers of ECLIPSE
files move them apart as OPM Flow reads ZCORN (a top above the bottom of the cell above moved
down to it, a bottom above its own top moved down to the top), with a note; the grid, its pore
volumes and T are then Flow's. Before, gridlib refused such a deck ("reaches below the top of
cell ... overlapping layers") that Flow runs."""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import numpy as np
from flow_tools import rest_of_deck
from real_decks import CHECKS_ALL, compare

from gridlib.cornerpoint.generators import simple_grdecl
from gridlib.cornerpoint.layer_overlaps import flow_zcorn
from gridlib.io.grdecl import read_grdecl, write_grdecl

SIXCELLS = Path(__file__).resolve().parents[1] / "data" / "decks" / "sixcells2"
RUNSPEC = "RUNSPEC\nDIMENS\n {} {} {} /\nMETRIC\nOIL\nWATER\nTABDIMS\n 1 1 20 20 /\nEQLDIMS\n 1 /\n"
RUNSPEC += "START\n 1 'JAN' 2020 /\nGRID\nINIT\n"


def _flow_deck(folder: Path, dims, grid_file: str, n: int, rest: str) -> Path:
    rock = f"PORO\n {n}*0.2 /\nPERMX\n {n}*100 /\nPERMY\n {n}*100 /\nPERMZ\n {n}*10 /\n"
    deck = folder / "CASE.DATA"
    deck.write_text(RUNSPEC.format(*dims) + rock + f"INCLUDE\n '{grid_file}' /\n" + rest)
    return deck


def test_rms_grid_with_overlapping_layers_reads_as_flow_reads_it(tmp_path):
    """xtgeo-testdata's sixcells2 with a layer reaching into the one below (an RMS export)."""
    shutil.copyfile(SIXCELLS / "sixcells2_described_zoverlap.grdecl", tmp_path / "g.grdecl")
    deck_path = _flow_deck(tmp_path, (2, 1, 3), "g.grdecl", 6, rest_of_deck(600.0, 900.0))
    deck = read_grdecl(deck_path)
    assert any(
        "corner depths of active cells moved down to remove overlapping layers" in n for n in deck.notes
    )
    comparison = compare("sixcells2_zoverlap", deck_path, tmp_path / "flow")
    for check in CHECKS_ALL:
        check(comparison)


def test_a_deck_with_overlaps_and_an_inverted_corner_is_flows_grid(tmp_path):
    """A 3 x 2 x 3 deck whose second layer's top reaches 0.3 m into the first and one of whose
    cells has a bottom corner above its top corner."""
    deck = simple_grdecl([3, 2, 3], 0.04, flat=True, phys_dims=(300.0, 200.0, 30.0))
    z = np.array(deck.zcorn).reshape(6, 4, 6)
    z[2] -= 0.3  # the second layer's top above the first layer's bottom
    z[5, 0, 0] = z[4, 0, 0] - 0.5  # cell (1, 1, 3): a bottom corner above its top corner
    write_grdecl(tmp_path / "g.grdecl", dataclasses.replace(deck, zcorn=z.ravel()))
    deck_path = _flow_deck(tmp_path, (3, 2, 3), "g.grdecl", 18, rest_of_deck(5.0, 25.0))
    assert read_grdecl(deck_path).notes[-1].startswith("25 corner depths of active cells moved down")
    comparison = compare("overlaps", deck_path, tmp_path / "flow")
    for check in CHECKS_ALL:
        check(comparison)
    up, moved = flow_zcorn(-z, np.ones((3, 2, 3), bool), -1)  # z up: the same rule, upwards
    down, _ = flow_zcorn(z, np.ones((3, 2, 3), bool), 1)
    np.testing.assert_array_equal(up, -down)
    assert moved == 25


def test_the_rule_ignores_inactive_cells_and_counts_what_moved():
    """Two columns of three cells: in the first the middle cell is inactive with a junk bottom
    (1e20), which does not move the cell below (Flow's would); the third cell's top, above the
    first cell's bottom, moves down to it. In the second the second cell's top overlaps."""
    z = np.zeros((6, 2, 4))
    z[:, :, :2] = np.array([0, 10, 8, 1e20, 9, 20])[:, None, None]
    z[:, :, 2:] = np.array([0, 10, 9, 20, 20, 30])[:, None, None]
    active = np.array([[[True, True]], [[False, True]], [[True, True]]])
    fixed, moved = flow_zcorn(z, active, 1)
    np.testing.assert_array_equal(fixed[:, 0, 0], [0, 10, 8, 1e20, 10, 20])
    np.testing.assert_array_equal(fixed[:, 0, 2], [0, 10, 10, 20, 20, 30])
    assert moved == 4 + 4  # four top corners in each column
    same, none = flow_zcorn(fixed, active, 1)
    assert none == 0 and same is fixed


def test_a_roff_grid_with_overlapping_layers_reads_as_its_grdecl_does(tmp_path):
    """The deck case of a ROFF grid writes a GRDECL for Flow, which Flow reads with the rule:
    read_roff_deck applies it too (read_roff_grid gives the file as it is)."""
    from gridlib.io.roff import read_roff_deck, read_roff_grid, write_roff_grid

    deck = simple_grdecl([3, 2, 3], 0.0, flat=True, phys_dims=(300.0, 200.0, 30.0))
    z = np.array(deck.zcorn).reshape(6, 4, 6)
    z[2] -= 0.25  # exact in float32, as ROFF stores it
    overlapping = dataclasses.replace(deck, zcorn=z.ravel())
    write_roff_grid(tmp_path / "g.roff", overlapping)
    np.testing.assert_array_equal(read_roff_grid(tmp_path / "g.roff").deck.zcorn, overlapping.zcorn)
    read_in = read_roff_deck(tmp_path / "g.roff")
    write_grdecl(tmp_path / "g.grdecl", overlapping)
    np.testing.assert_array_equal(read_in.zcorn, read_grdecl(tmp_path / "g.grdecl").zcorn)
    assert read_in.notes[-1].startswith("24 corner depths of active cells moved down")
