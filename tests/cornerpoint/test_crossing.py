"""Pillars that cross are an error naming the deck and the cells; pillars that lean, converge or
make a concave cell are not."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from gridlib.cornerpoint.deck import Deck
from gridlib.cornerpoint.generators import simple_grdecl
from gridlib.cornerpoint.process import process_grdecl
from gridlib.errors import InputError

# Pillar (i, j) = (1, 1) (0-based) of a 3 x 2 x 2 deck of 100 m x 100 m x 10 m cells, vertical
# pillars from depth 0 to 20; its neighbour in +i stands at x = 200.
MOVED = 5


def _deck(dx_top: float, dx_bottom: float, mirrored: bool = False) -> Deck:
    """The deck with pillar MOVED's top and bottom points moved along x (and y mirrored: a
    left-handed deck)."""
    deck = simple_grdecl([3, 2, 2], undisturbed=True, flat=True, phys_dims=(300.0, 200.0, 20.0))
    coord = deck.coord.reshape(-1, 6).copy()
    coord[MOVED, 0] += dx_top
    coord[MOVED, 3] += dx_bottom
    if mirrored:
        coord[:, [1, 4]] *= -1.0
    return replace(deck, coord=coord.reshape(-1), source="X.GRDECL")


@pytest.mark.parametrize("mirrored", [False, True], ids=["right-handed", "left-handed"])
@pytest.mark.parametrize(
    ("dx_top", "dx_bottom", "cells"),
    [
        (0.0, 400.0, "4 cells .*: (2, 1, 1), (2, 2, 1), (2, 1, 2), (2, 2, 2) "),  # cross at depth 5
        (0.0, 150.0, "2 cells .*: (2, 1, 2), (2, 2, 2) "),  # at depth 13.3: the lower layer only
        (200.0, 200.0, "4 cells .*: (2, 1, 1), (2, 2, 1), (2, 1, 2), (2, 2, 2) "),  # above the model
        (-150.0, 0.0, "2 cells .*: (1, 1, 1), (1, 2, 1) "),  # past its -i neighbour, at depth 10
    ],
)
def test_crossing_pillars_are_an_error_naming_the_cells(dx_top, dx_bottom, cells, mirrored):
    message = r"X\.GRDECL: COORD: pillars cross: " + cells.replace("(", r"\(").replace(")", r"\)")
    with pytest.raises(InputError, match=message):
        process_grdecl(_deck(dx_top, dx_bottom, mirrored))


@pytest.mark.parametrize("mirrored", [False, True], ids=["right-handed", "left-handed"])
@pytest.mark.parametrize(
    ("dx_top", "dx_bottom"),
    [
        (0.0, 80.0),  # leans towards its neighbour, 20 m short of it at the base
        (60.0, -60.0),  # crosses its first position, not a neighbour
        (80.0, 80.0),
    ],
)
def test_leaning_pillars_are_fine(dx_top, dx_bottom, mirrored):
    r = process_grdecl(_deck(dx_top, dx_bottom, mirrored))
    assert r.grid.num_cells == 12 and (r.bulk_volumes > 0).all()
    total = 300.0 * 200.0 * 20.0  # the pillar moves inside the model: its volume is unchanged
    assert r.bulk_volumes.sum() == pytest.approx(total, rel=1e-12)


def test_a_concave_cell_is_fine():
    """Pillar (1, 1) moved to (160, 170): cell (1, 1) is concave (a dart) in plan view, its
    neighbours stay simple: the plan view is still a tiling, nothing overlaps."""
    deck = simple_grdecl([3, 2, 2], undisturbed=True, flat=True, phys_dims=(300.0, 200.0, 20.0))
    coord = deck.coord.reshape(-1, 6).copy()
    coord[MOVED, [0, 3]] = 160.0
    coord[MOVED, [1, 4]] = 170.0
    r = process_grdecl(replace(deck, coord=coord.reshape(-1)))
    assert r.grid.num_cells == 12 and (r.bulk_volumes > 0).all()
    assert r.bulk_volumes.sum() == pytest.approx(300.0 * 200.0 * 20.0, rel=1e-12)
    # cell (2, 2): (160, 170), (200, 100), (200, 200), (100, 200): 3500 m2 (shoelace) x 10 m
    assert np.isclose(r.bulk_volumes.min(), 35000.0, rtol=1e-12)


def test_a_deck_case_with_crossing_pillars_stops_naming_case_deck_and_cells(tmp_path):
    """As a ``deck`` case (accepted before, with overlapping cells and a Flow deck written), the
    grid stage stops with one InputError naming the case, the deck and the cells."""
    from gridlib.config import load_case
    from gridlib.io.grdecl import write_grdecl
    from gridlib.stages import stage_grid

    deck = _deck(0.0, 150.0)
    write_grdecl(tmp_path / "X.GRDECL", deck)
    case = tmp_path / "crossing.yaml"
    case.write_text("name: crossing\ngrid: {type: deck, file: X.GRDECL}\n")
    message = rf"{case}: grid: .*X\.GRDECL: COORD: pillars cross: 2 cells .*: \(2, 1, 2\), \(2, 2, 2\) "
    with pytest.raises(InputError, match=message):
        stage_grid(load_case(case), grid=tmp_path / "grid.nc", grdecl=tmp_path / "grid.grdecl")
    assert not (tmp_path / "grid.nc").exists()
