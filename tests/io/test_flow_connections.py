"""io.flow_connections: the connection form's boxes and NNC text, exact arrays and bytes."""

from __future__ import annotations

import numpy as np

from gridlib.io.flow_connections import ConnectionGrid, box_corners, box_depths, nnc_text


def _column() -> ConnectionGrid:
    """One logical column of 3 cells holding grid cells at k = 0 and k = 2 whose 4 m boxes overlap."""
    return ConnectionGrid(
        dims=(1, 1, 3),
        index=np.array([0, 2]),
        porv=np.array([1.0, 1.0]),
        depth=np.array([10.0, 13.0]),
        thickness=np.array([4.0, 4.0]),
        poro=np.array([0.2, 0.2]),
        permeability=np.full((2, 3), 100.0),
        pairs=np.array([[0, 1]]),
        trans=np.array([0.5]),
        spacing=2.0,
    )


def test_boxes_shrink_about_their_centres_and_an_empty_cell_is_flat():
    tops, dz = box_depths(_column())
    assert tops.tolist() == [8.5, 11.5, 11.5]  # 3 m apart: each box 1.5 m either side of its centre
    assert dz.tolist() == [3.0, 0.0, 3.0]  # k = 1 has no grid cell: zero thickness
    coord, zcorn = box_corners(_column())
    assert coord.reshape(-1, 6).tolist() == [
        [0.0, 0.0, 8.5, 0.0, 0.0, 14.5],
        [2.0, 0.0, 8.5, 2.0, 0.0, 14.5],
        [0.0, 2.0, 8.5, 0.0, 2.0, 14.5],
        [2.0, 2.0, 8.5, 2.0, 2.0, 14.5],
    ]
    assert zcorn.tolist() == [8.5] * 4 + [11.5] * 4 + [11.5] * 8 + [11.5] * 4 + [14.5] * 4


def test_nnc_text_exact():
    text = b"".join(nnc_text(_column(), 0, "cP m3/(day bar)"))
    assert text == (
        b"-- Every connection of the grid, with gridlib's transmissibility (cP m3/(day bar)).\n"
        b"-- 1 connections; Flow adds each value to the 0 of the layout's own connection.\n\n"
        b"NNC\n-- I1 J1 K1 I2 J2 K2 TRAN\n"
        b" 1 1 1 1 1 3 0.5 /\n"
        b"/\n"
    )
