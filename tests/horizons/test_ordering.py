"""Horizon ordering (gridlib.horizons.ordering): crossings found and reported with their size,
repaired by erode or onlap, undefined nodes skipped."""

from __future__ import annotations

import numpy as np
import pytest

from gridlib import InputError, compute_geometry, horizons_to_grdecl, process_grdecl
from gridlib.horizons import (
    HorizonCrossingError,
    find_crossings,
    horizon_dataset,
    order_horizons,
    to_horizons,
)


def crossing_stack():
    x, y = np.linspace(0.0, 1000.0, 11), np.linspace(0.0, 500.0, 6)  # 100 m spacing
    X, _ = np.meshgrid(x, y)
    return x, y, np.stack([1000.0 + 0.02 * X, np.full_like(X, 1010.0)])  # cross where x > 500


def test_crossing_horizons_are_reported_with_their_size():
    x, y, H = crossing_stack()
    (c,) = find_crossings(H, x, y, ["top", "base"])
    # nodes x = 600..1000 in all 6 rows; tributary widths 4 x 100 + 50 m in x, 500 m in y
    assert (c.upper, c.lower, c.nodes, c.area, c.x, c.y, c.max_overlap) == (
        "top",
        "base",
        30,
        225000.0,
        600.0,
        0.0,
        pytest.approx(10.0, abs=1e-9),
    )
    with pytest.raises(HorizonCrossingError) as err:
        horizon_dataset(H, x, y, names=["top", "base"])
    msg = str(err.value)
    assert "horizons 'top' and 'base' cross at 30 nodes (225000 m2), first at (x, y) = (600, 0)" in msg
    assert "ordering to 'erode' or 'onlap'" in msg
    assert isinstance(err.value, InputError) and err.value.crossings == (c,)


def test_erode_and_onlap_repair_crossings():
    x, y, H = crossing_stack()
    cross = H[1] < H[0]
    eroded, notes = order_horizons(H, x, y, ordering="erode", names=["top", "base"])
    assert (np.diff(eroded, axis=0) >= 0).all()
    assert np.array_equal(eroded[0], H[0])  # the younger horizon cuts: top unchanged
    assert np.array_equal(eroded[1][cross], H[0][cross]) and np.array_equal(eroded[1][~cross], H[1][~cross])
    assert notes == ("ordering 'erode': horizon 'base' moved down to a horizon above it at 30 nodes",)
    onlapped, _ = order_horizons(H, x, y, ordering="onlap")
    assert (np.diff(onlapped, axis=0) >= 0).all()
    assert np.array_equal(onlapped[1], H[1])  # the older horizon wins: base unchanged
    assert np.array_equal(onlapped[0][cross], H[1][cross])
    ds = horizon_dataset(H, x, y, names=["top", "base"], ordering="erode")
    assert float((ds.depth.sel(horizon="base") - ds.depth.sel(horizon="top")).min()) == 0.0
    deck = horizons_to_grdecl(to_horizons(ds), layers=2)  # the corner-point builder takes it as it is
    cp = process_grdecl(deck)
    assert cp.grid.num_cells < 2 * 10 * 5  # the eroded half has zero thickness: collapsed cells removed
    assert (compute_geometry(cp.grid).cell_volumes > 0).all()


def test_undefined_nodes_are_skipped_by_the_ordering():
    x, y = np.array([0.0, 1.0]), np.array([0.0, 1.0])
    H = np.array([[[10.0, 10.0], [10.0, 10.0]], [[np.nan, 20.0], [20.0, 20.0]], [[5.0, 30.0], [30.0, 30.0]]])
    (c,) = find_crossings(H, x, y)
    assert (c.upper, c.lower, c.nodes) == ("horizon_0", "horizon_2", 1)  # against the nearest defined above
    fixed, _ = order_horizons(H, x, y, ordering="erode")
    assert np.isnan(fixed[1, 0, 0]) and fixed[2, 0, 0] == 10.0
