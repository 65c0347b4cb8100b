"""cornerpoint.cartesian: COORD and ZCORN of block-centred (DX/DY/DZ/TOPS) grids, exact arrays."""

from __future__ import annotations

import numpy as np

from gridlib.cornerpoint.cartesian import cartesian_to_cornerpoint
from gridlib.io.grdecl import read_grdecl


def _two_by_one_by_two():
    """nx=2, ny=1, nz=2; DX changes with depth (inclined middle pillars); tops of layer 1 undefined."""
    dx = np.array([[[1.0, 3.0]], [[2.0, 2.0]]])
    dy = np.full((2, 1, 2), 4.0)
    dz = np.array([[[1.0, 2.0]], [[3.0, 3.0]]])
    top = np.full((2, 1, 2, 2, 2), np.nan)
    top[0] = np.array([100.0, 101.0])[None, :, None, None]
    return dx, dy, dz, top


EXPECTED_COORD = [
    [0.0, 0.0, 100.0, 0.0, 0.0, 106.0],
    [1.0, 0.0, 100.0, 2.0, 0.0, 106.0],
    [4.0, 0.0, 100.0, 4.0, 0.0, 106.0],
    [0.0, 4.0, 100.0, 0.0, 4.0, 106.0],
    [1.0, 4.0, 100.0, 2.0, 4.0, 106.0],
    [4.0, 4.0, 100.0, 4.0, 4.0, 106.0],
]
EXPECTED_ZCORN = (
    [100.0, 100.0, 101.0, 101.0] * 2  # layer 0, top corners (rows j-, j+ of the column)
    + [101.0, 101.0, 103.0, 103.0] * 2  # layer 0, bottom
    + [101.0, 101.0, 103.0, 103.0] * 2  # layer 1, top: the bottom of layer 0
    + [104.0, 104.0, 106.0, 106.0] * 2  # layer 1, bottom
)


def test_boxes_become_pillars_and_corner_depths():
    coord, zcorn = cartesian_to_cornerpoint(*_two_by_one_by_two())
    assert coord.reshape(-1, 6).tolist() == EXPECTED_COORD
    assert zcorn.tolist() == EXPECTED_ZCORN


def test_the_deck_reader_gives_the_same_arrays(tmp_path):
    p = tmp_path / "boxes.grdecl"
    p.write_text("DIMENS\n 2 1 2 /\nDX\n 1 3 2 2 /\nDY\n 4*4 /\nDZ\n 1 2 3 3 /\nTOPS\n 100 101 /\n")
    deck = read_grdecl(p)
    assert deck.coord.reshape(-1, 6).tolist() == EXPECTED_COORD
    assert deck.zcorn.tolist() == EXPECTED_ZCORN


def test_tilted_top_corners_and_a_flat_grid():
    one = np.ones((1, 1, 1))
    top = np.array([10.0, 11.0, 12.0, 13.0]).reshape(1, 1, 1, 2, 2)  # (j, i) corners
    coord, zcorn = cartesian_to_cornerpoint(5.0 * one, 2.0 * one, 2.0 * one, top)
    assert zcorn.tolist() == [10.0, 11.0, 12.0, 13.0, 12.0, 13.0, 14.0, 15.0]
    assert coord.reshape(-1, 6).tolist() == [
        [0.0, 0.0, 10.0, 0.0, 0.0, 15.0],
        [5.0, 0.0, 10.0, 5.0, 0.0, 15.0],
        [0.0, 2.0, 10.0, 0.0, 2.0, 15.0],
        [5.0, 2.0, 10.0, 5.0, 2.0, 15.0],
    ]
    coord, zcorn = cartesian_to_cornerpoint(one, one, 0.0 * one, np.full((1, 1, 1, 2, 2), 7.0))
    assert zcorn.tolist() == [7.0] * 8
    assert coord.reshape(-1, 6)[:, [2, 5]].tolist() == [[7.0, 8.0]] * 4  # pillars 1 long when flat
