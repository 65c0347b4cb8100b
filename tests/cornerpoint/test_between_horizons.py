"""horizons_to_grdecl: the seed's peaks examples (MRST book Figs. 3.18, 3.19), ordering repairs,
stair-stepped faults (straight, tapering to a tip, oblique, bent), input errors."""

from __future__ import annotations

import numpy as np
import pytest

import gridlib as gl
from gridlib.cornerpoint.between_horizons import FaultTrace, Horizon, horizons_to_grdecl
from gridlib.cornerpoint.deck import FaultSegment
from gridlib.cornerpoint.process import FAULT, process_grdecl


def peaks(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """MATLAB's peaks function."""
    return (
        3 * (1 - x) ** 2 * np.exp(-(x**2) - (y + 1) ** 2)
        - 10 * (x / 5 - x**3 - y**5) * np.exp(-(x**2) - y**2)
        - np.exp(-((x + 1) ** 2) - y**2) / 3
    )


# MATLAB's [y, x, z] = peaks(15): the first output (varying along columns) is named y.
PX, PY = np.meshgrid(np.linspace(-3, 3, 15), np.linspace(-3, 3, 15))
PEAKS_X, PEAKS_Y, PEAKS_Z = PY, PX, peaks(PX, PY) + 8

AXIS = np.linspace(0.0, 100.0, 11)  # 10 x 10 cells of 10 m


def flat(depth: float) -> Horizon:
    return Horizon(AXIS, AXIS, np.full((11, 11), depth))


def processed(deck):
    r = process_grdecl(deck)
    geo = gl.compute_geometry(r.grid)
    gl.check_grid(r.grid, geo)
    return r, geo


def cell_corners(deck) -> np.ndarray:
    """ZCORN as [k, j, i, c, b, a] (c = top/bottom, b, a = pillar offsets)."""
    nx, ny, nz = deck.cart_dims
    return deck.zcorn_array().reshape(nz, 2, ny, 2, nx, 2).transpose(0, 2, 4, 1, 3, 5)


# --------------------------------------------------------------------------- the seed


def test_seed_peaks_four_layers_volume_288():
    deck = horizons_to_grdecl(
        [{"x": PEAKS_X, "y": PEAKS_Y, "z": PEAKS_Z}, {"x": PEAKS_X, "y": PEAKS_Y, "z": PEAKS_Z + 8}], layers=4
    )
    assert deck.cart_dims == (14, 14, 4) and deck.source == "horizons_to_grdecl"
    r, geo = processed(deck)
    assert r.grid.num_cells == 14 * 14 * 4
    assert geo.cell_volumes.sum() == pytest.approx(288.0, rel=1e-12)
    assert r.bulk_volumes.sum() == pytest.approx(288.0, rel=1e-12)
    # Every layer is 2 m thick at every pillar; the top follows peaks at the horizon's nodes.
    zc = cell_corners(deck)
    np.testing.assert_allclose(zc[..., 1, :, :] - zc[..., 0, :, :], 2.0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(zc[0, :, :, 0, 0, 0], PEAKS_Z.T[:-1, :-1], rtol=0, atol=1e-12)
    # Pillars are vertical and span the depth range.
    p = deck.pillars()
    np.testing.assert_array_equal(p[:, :, 0, :2], p[:, :, 1, :2])
    assert p[0, 0, 0, 2] == pytest.approx(PEAKS_Z.min()) and p[0, 0, 1, 2] == pytest.approx(PEAKS_Z.max() + 8)


def test_meshgrid_ndgrid_1d_and_reversed_axes_give_the_same_deck():
    ref = horizons_to_grdecl([Horizon(PEAKS_X, PEAKS_Y, PEAKS_Z), Horizon(PEAKS_X, PEAKS_Y, PEAKS_Z + 8)])
    ax = np.linspace(-3, 3, 15)
    z = PEAKS_Z.T  # z[j, i] at (x[i], y[j])
    for top, base in (
        (Horizon(ax, ax, z), Horizon(ax, ax, z + 8)),
        (Horizon(PX, PY, z), Horizon(PX, PY, z + 8)),  # meshgrid layout
        (Horizon(ax[::-1], ax, z[:, ::-1]), Horizon(ax, ax[::-1], z[::-1] + 8)),
    ):
        deck = horizons_to_grdecl([top, base])
        np.testing.assert_allclose(deck.zcorn, ref.zcorn, rtol=0, atol=1e-12)
        np.testing.assert_allclose(deck.coord, ref.coord, rtol=0, atol=1e-12)


def test_seed_partially_overlapping_peaks_shrink_to_the_overlap():
    deck = horizons_to_grdecl(
        [Horizon(PEAKS_X, PEAKS_Y, PEAKS_Z), Horizon(PEAKS_X + 0.5, 2 * PEAKS_Y + 1, PEAKS_Z + 10)],
        dims=(30, 30),
        layers=3,
    )
    assert deck.cart_dims == (30, 30, 3)
    # Region [-3, 3.5] x [-5, 7]; overlap [-2.5, 3] x [-3, 3].
    px, py = np.linspace(-3, 3.5, 31), np.linspace(-5, 7, 31)
    xin = (px >= -2.5 - 1e-12) & (px <= 3 + 1e-12)
    yin = (py >= -3 - 1e-12) & (py <= 3 + 1e-12)
    column_inside = (yin[:-1] & yin[1:])[:, None] & (xin[:-1] & xin[1:])[None, :]
    active = deck.active.reshape(3, 30, 30)
    np.testing.assert_array_equal(active, np.broadcast_to(column_inside, (3, 30, 30)))
    assert int(active.sum()) == 24 * 15 * 3  # i = 3..26, j = 5..19
    r, _ = processed(deck)
    assert r.grid.num_cells == 1080
    # Inactive cells keep NaN corners where a horizon is undefined, never inf.
    assert np.isnan(deck.zcorn).any() and not np.isinf(deck.zcorn).any()


def test_partially_overlapping_planes_have_the_exact_volume():
    def plane(x, y, z0, a, b):
        return z0 + a * x + b * y

    h1 = Horizon(PEAKS_X, PEAKS_Y, plane(PEAKS_X, PEAKS_Y, 1000.0, 0.1, 0.05))
    x2, y2 = PEAKS_X + 0.5, 2 * PEAKS_Y + 1
    h2 = Horizon(x2, y2, plane(x2, y2, 1030.0, 0.2, -0.02))
    deck = horizons_to_grdecl([h1, h2], dims=(30, 30), layers=3)
    r, geo = processed(deck)
    x0, x1 = -3 + 3 * 6.5 / 30, -3 + 27 * 6.5 / 30  # the fully covered columns
    y0, y1 = -3.0, 3.0
    xc, yc = (x0 + x1) / 2, (y0 + y1) / 2
    expected = (x1 - x0) * (y1 - y0) * (30 + 0.1 * xc - 0.07 * yc)
    assert geo.cell_volumes.sum() == pytest.approx(expected, rel=1e-12)
    assert r.bulk_volumes.sum() == pytest.approx(expected, rel=1e-12)


def test_nan_nodes_deactivate_only_the_cells_they_weigh_on():
    z = np.full((15, 15), 100.0)
    z[7, 7] = np.nan
    ax = np.linspace(0, 14, 15)
    deck = horizons_to_grdecl([Horizon(ax, ax, z), Horizon(ax, ax, z * 0 + 110.0)], layers=2)
    inactive = ~deck.active.reshape(2, 14, 14)
    assert int(inactive.sum()) == 2 * 4
    assert inactive[:, 6:8, 6:8].all()
    # Twice as fine: the 9 pillars strictly inside the hole's support, 4 x 4 columns.
    deck = horizons_to_grdecl([Horizon(ax, ax, z), Horizon(ax, ax, z * 0 + 110.0)], dims=(28, 28))
    inactive = ~deck.active.reshape(28, 28)
    assert int(inactive.sum()) == 16 and inactive[12:16, 12:16].all()
    _, geo = processed(deck)
    assert geo.cell_volumes.sum() == pytest.approx(10.0 * (14 * 14 - 16 * 0.25), rel=1e-12)


def test_layers_per_zone_are_proportional():
    deck = horizons_to_grdecl([flat(1000.0), flat(1010.0), flat(1040.0)], layers=[2, 3])
    assert deck.cart_dims == (10, 10, 5)
    zc = cell_corners(deck)
    np.testing.assert_array_equal(zc[:, 0, 0, 0, 0, 0], [1000, 1005, 1010, 1020, 1030])
    np.testing.assert_array_equal(zc[:, 0, 0, 1, 0, 0], [1005, 1010, 1020, 1030, 1040])
    _, geo = processed(deck)
    assert geo.cell_volumes.sum() == pytest.approx(40.0 * 100 * 100, rel=1e-13)
    same = horizons_to_grdecl([flat(1000.0), flat(1010.0), flat(1040.0)], layers=(np.int64(2), 3.0))
    np.testing.assert_array_equal(same.zcorn, deck.zcorn)


# --------------------------------------------------------------------------- ordering


CROSSING = Horizon(AXIS, AXIS, np.broadcast_to(100.0 + 0.2 * (AXIS - 50.0), (11, 11)))  # 90 .. 110 m


def zone_volumes(deck, layers) -> np.ndarray:
    r, geo = processed(deck)
    nx, ny, _ = deck.cart_dims
    zone = np.repeat(np.arange(len(layers)), layers)[r.grid.cells.index_map // (nx * ny)]
    return np.bincount(zone, geo.cell_volumes, minlength=len(layers))


def test_crossing_horizons_are_an_error_by_default():
    with pytest.raises(
        gl.InputError,
        match=r"horizons 0 and 1 cross at 55 pillar nodes \(horizon 1 above horizon 0\), "
        r"first at \(x, y\) = \(0, 0\); pass ordering='erode' or 'onlap'",
    ):
        horizons_to_grdecl([flat(100.0), CROSSING, flat(150.0)])


def test_erode_clamps_the_younger_horizon_down():
    deck = horizons_to_grdecl([flat(100.0), CROSSING, flat(150.0)], layers=[2, 3], ordering="erode")
    zc = cell_corners(deck)
    assert np.all(zc[:, :, :, 1] >= zc[:, :, :, 0])  # non-negative thickness at every corner
    x = AXIS[np.arange(1, 21) // 2]  # x of every corner column
    np.testing.assert_array_equal(zc[0, 0, :, 0, 0, :].ravel(), 100.0)  # top unchanged
    np.testing.assert_allclose(zc[2, 0, :, 0, 0, :].ravel(), np.maximum(100.0, 100 + 0.2 * (x - 50)))
    np.testing.assert_array_equal(zc[4, 0, :, 1, 0, :].ravel(), 150.0)
    assert any("ordering='erode': horizon 1" in n and "55 pillar nodes" in n for n in deck.notes)
    np.testing.assert_allclose(zone_volumes(deck, [2, 3]), [25000.0, 475000.0], rtol=1e-12)


def test_onlap_clamps_the_older_horizon_up():
    deck = horizons_to_grdecl([flat(100.0), CROSSING, flat(150.0)], layers=[2, 3], ordering="onlap")
    zc = cell_corners(deck)
    assert np.all(zc[:, :, :, 1] >= zc[:, :, :, 0])
    x = AXIS[np.arange(1, 21) // 2]
    np.testing.assert_allclose(zc[0, 0, :, 0, 0, :].ravel(), np.minimum(100.0, 100 + 0.2 * (x - 50)))
    np.testing.assert_allclose(zc[2, 0, :, 0, 0, :].ravel(), 100 + 0.2 * (x - 50))  # h1 unchanged
    np.testing.assert_allclose(zone_volumes(deck, [2, 3]), [25000.0, 500000.0], rtol=1e-12)


def test_repairs_skip_undefined_horizons():
    mid = np.full((11, 11), 120.0)
    mid[5, 5] = np.nan
    bottom = np.full((11, 11), 150.0)
    bottom[5, 5] = 90.0  # above the top where the middle horizon is undefined
    hs = [flat(100.0), Horizon(AXIS, AXIS, mid), Horizon(AXIS, AXIS, bottom)]
    deck = horizons_to_grdecl(hs, ordering="erode")
    zc = cell_corners(deck)
    assert zc[1, 5, 5, 1, 0, 0] == 100.0  # the bottom clamped to the top, skipping the NaN
    assert np.isnan(zc[0, 5, 5, 1, 0, 0]) and np.isnan(zc[1, 5, 5, 0, 0, 0])  # middle stays undefined
    deck = horizons_to_grdecl(hs, ordering="onlap")
    assert cell_corners(deck)[0, 5, 5, 0, 0, 0] == 90.0  # the top clamped to the bottom


# --------------------------------------------------------------------------- faults


def fault_deck(faults, layers=4):
    return horizons_to_grdecl([flat(1000.0), flat(1020.0)], layers=layers, faults=faults)


def displacement(deck) -> np.ndarray:
    """Downward shift of every corner against the unfaulted layering: [k, j, i, c, b, a]."""
    nz = deck.cart_dims[2]
    ref = 1000.0 + 20.0 / nz * (np.arange(nz)[:, None] + np.arange(2)[None, :])
    return cell_corners(deck) - ref[:, None, None, :, None, None]


def test_straight_fault_with_constant_throw():
    fault = FaultTrace([(50.0, -10.0), (50.0, 110.0)], 2.0, "MAIN")  # walking north: east is right
    deck = fault_deck([fault])
    assert deck.faults == (FaultSegment("MAIN", 4, 4, 0, 9, 0, 3, "X"),)
    d = displacement(deck)
    np.testing.assert_array_equal(d[:, :, 5:], 2.0)
    np.testing.assert_array_equal(d[:, :, :5], 0.0)
    zc = deck.zcorn_array()  # pillar column i = 5: cell 4's corners (2i+1 = 9) and cell 5's (10)
    np.testing.assert_array_equal(zc[:, :, 10] - zc[:, :, 9], 2.0)
    r, geo = processed(deck)
    assert geo.cell_volumes.sum() == pytest.approx(20.0 * 100 * 100, rel=1e-13)
    assert r.fault_names[0] == "MAIN"
    # Per row: 4 same-layer overlaps, 3 next-layer overlaps, 2 pieces facing the void.
    assert int((r.grid.faces.tag == 1).sum()) == 10 * 9
    assert r.nnc.num == 10 * 3 and np.all(r.nnc.kind == FAULT)
    ki = np.array(np.unravel_index(r.nnc.global_cells, (4, 10, 10)))  # (k, j, i) x (n, 2)
    np.testing.assert_array_equal(ki[2, :, 0], 4)
    np.testing.assert_array_equal(ki[2, :, 1], 5)
    np.testing.assert_array_equal(ki[0, :, 0] - ki[0, :, 1], 1)  # west layer k meets east layer k - 1
    # The same fault walked southwards with the hanging wall on the left.
    back = fault_deck([FaultTrace([(50.0, 110.0), (50.0, -10.0)], 2.0, "MAIN", side="left")])
    np.testing.assert_array_equal(back.zcorn, deck.zcorn)
    assert back.faults == deck.faults


def test_fault_along_x_is_recorded_as_y_faces():
    deck = fault_deck([FaultTrace([(-10.0, 50.0), (110.0, 50.0)], 2.0)])  # walking east: south is right
    assert deck.faults == (FaultSegment("F1", 0, 9, 4, 4, 0, 3, "Y"),)
    d = displacement(deck)
    np.testing.assert_array_equal(d[:, :5], 2.0)
    np.testing.assert_array_equal(d[:, 5:], 0.0)
    r, _ = processed(deck)
    assert r.fault_names[0] == "F1" and int((r.grid.faces.tag == 1).sum()) == 90 and r.nnc.num == 30


def test_fault_tapering_to_a_tip_inside_the_grid():
    throw = lambda s: 4.0 * (1.0 - s)  # noqa: E731  (the trace runs from y = -10 to its tip at y = 52)
    deck = fault_deck([FaultTrace([(50.0, -10.0), (50.0, 52.0)], throw, "TIP")])
    d = displacement(deck)
    py = AXIS[np.arange(1, 21) // 2]  # y of the corner rows
    expected = 4.0 * (1 - np.clip((py + 10) / 62, 0, 1))
    expected[py > 52] = 0.0
    shift_east = d[0, :, 5:, 0]  # (j, i, b, a) top corners east of the fault
    np.testing.assert_allclose(shift_east, np.broadcast_to(expected.reshape(10, 1, 2, 1), (10, 5, 2, 2)))
    np.testing.assert_array_equal(d[:, :, :5], 0.0)  # the footwall never moves
    np.testing.assert_array_equal(d[:, 6:], 0.0)  # beyond the tip's cell row nothing moves
    # The cell row at the tip (j = 5, y in [50, 60]) moves only on its pillars before the tip.
    np.testing.assert_allclose(d[0, 5, 5:, 0, 0], 4 * 2 / 62)
    assert deck.faults == (FaultSegment("TIP", 4, 4, 0, 5, 0, 3, "X"),)
    r, geo = processed(deck)
    assert geo.cell_volumes.sum() == pytest.approx(20.0 * 100 * 100, rel=1e-13)
    tagged = np.flatnonzero(r.grid.faces.tag == 1)
    fy = gl.compute_geometry(r.grid).face_centroids[tagged, 1]
    assert tagged.size > 0 and fy.max() < 60.0  # no fault face beyond the tip's cell


def test_fault_with_both_tips_inside_moves_only_between_them():
    throw = lambda s: 3.0 * np.sin(np.pi * s)  # noqa: E731
    deck = fault_deck([FaultTrace([(50.0, 22.0), (50.0, 78.0)], throw, "LENS")])
    d = displacement(deck)
    py = AXIS[np.arange(1, 21) // 2]
    expected = 3.0 * np.sin(np.pi * np.clip((py - 22) / 56, 0, 1)).reshape(10, 1, 2, 1)
    np.testing.assert_allclose(d[0, :, 5:, 0], np.broadcast_to(expected, (10, 5, 2, 2)), atol=1e-15)
    np.testing.assert_array_equal(d[:, :2], 0.0)  # before the first tip (cell rows y < 20)
    np.testing.assert_array_equal(d[:, 8:], 0.0)  # after the last tip (cell rows y > 80)
    np.testing.assert_array_equal(d[:, :, :5], 0.0)
    assert deck.faults == (FaultSegment("LENS", 4, 4, 2, 7, 0, 3, "X"),)
    r, geo = processed(deck)
    assert geo.cell_volumes.sum() == pytest.approx(20.0 * 100 * 100, rel=1e-13)
    assert int((r.grid.faces.tag == 1).sum()) == 6 * 9 and r.nnc.num == 6 * 3  # cell rows 2..7


def test_constant_throw_ending_inside_ends_the_block_on_the_perpendicular():
    deck = fault_deck([FaultTrace([(50.0, -10.0), (50.0, 52.0)], 4.0, "BLOCK")])
    d = displacement(deck)
    np.testing.assert_array_equal(d[:, :5, 5:], 4.0)
    np.testing.assert_array_equal(d[:, 5:], 0.0)
    np.testing.assert_array_equal(d[:, :, :5], 0.0)
    assert deck.faults == (
        FaultSegment("BLOCK", 4, 4, 0, 4, 0, 3, "X"),
        FaultSegment("BLOCK", 5, 9, 4, 4, 0, 3, "Y"),
    )
    r, geo = processed(deck)
    assert geo.cell_volumes.sum() == pytest.approx(20.0 * 100 * 100, rel=1e-13)
    assert int((r.grid.faces.tag == 1).sum()) == 10 * 9


def test_oblique_fault_is_stair_stepped_by_cell_centres():
    deck = fault_deck([FaultTrace([(-10.0, -5.0), (110.0, 115.0)], 3.0, "DIAG")], layers=2)  # y = x + 5
    i, j = np.meshgrid(np.arange(10), np.arange(10))
    hanging = (5 + 10 * j) < (5 + 10 * i) + 5  # cell centre right of (below) the trace: j <= i
    d = displacement(deck)
    np.testing.assert_array_equal(
        d, np.broadcast_to(np.where(hanging, 3.0, 0.0)[None, :, :, None, None, None], d.shape)
    )
    assert len(deck.faults) == 18  # 9 steps: one +i face and one +j face each
    assert {(s.i1, s.j1, s.face) for s in deck.faults} == {(i, i + 1, "X") for i in range(9)} | {
        (i, i, "Y") for i in range(9)
    }
    r, geo = processed(deck)
    assert geo.cell_volumes.sum() == pytest.approx(20.0 * 100 * 100, rel=1e-13)
    # 18 edges x (2 same-layer overlaps + 1 next-layer overlap + 2 void pieces).
    assert int((r.grid.faces.tag == 1).sum()) == 18 * 5 and r.nnc.num == 18


def test_bent_trace_uses_the_outer_side_at_its_vertex():
    # A sharp apex at (50, 50); the hanging wall (right of the walk) is inside the wedge below it.
    verts = [(28.0, -10.0), (50.0, 50.0), (72.0, -10.0)]
    deck = fault_deck([FaultTrace(verts, 2.5, "WEDGE")], layers=1)
    cx, cy = np.meshgrid(5 + 10 * np.arange(10.0), 5 + 10 * np.arange(10.0))
    x1 = 28 + (cy + 10) * 22 / 60
    x2 = 72 - (cy + 10) * 22 / 60
    inside = (cx > x1) & (cx < x2) & (cy < 50)
    assert int(inside.sum()) == 4 + 2 + 2 + 2  # rows j = 0..3
    d = displacement(deck)
    np.testing.assert_array_equal(
        d, np.broadcast_to(np.where(inside, 2.5, 0.0)[None, :, :, None, None, None], d.shape)
    )
    # Cell (5, 5), centre (55, 55) above the apex: a naive side test on the first segment says "right".
    assert d[0, 5, 5].max() == 0.0
    processed(deck)


def test_two_faults_add_their_throws():
    faults = [
        FaultTrace([(50.0, -10.0), (50.0, 110.0)], 2.0, "NS"),  # east down 2 m
        FaultTrace([(-10.0, 50.0), (110.0, 50.0)], 3.0, "EW"),  # south down 3 m
    ]
    deck = fault_deck(faults)
    d = displacement(deck)[0, :, :, 0, 0, 0]
    np.testing.assert_array_equal(d[:5, :5], 3.0)
    np.testing.assert_array_equal(d[:5, 5:], 5.0)
    np.testing.assert_array_equal(d[5:, 5:], 2.0)
    np.testing.assert_array_equal(d[5:, :5], 0.0)
    assert [s.name for s in deck.faults] == ["NS", "EW"]
    r, geo = processed(deck)
    assert r.fault_names[:2] == ("NS", "EW")
    assert int((r.grid.faces.tag == 1).sum()) > 0 and int((r.grid.faces.tag == 2).sum()) > 0
    assert geo.cell_volumes.sum() == pytest.approx(20.0 * 100 * 100, rel=1e-13)


def test_fault_outside_the_grid_is_noted():
    deck = fault_deck([FaultTrace([(200.0, -10.0), (200.0, 110.0)], 2.0, "FAR")])
    assert deck.faults == () and any("'FAR' offsets no cell edge" in n for n in deck.notes)
    np.testing.assert_array_equal(displacement(deck), 0.0)  # the grid lies on its footwall side


# --------------------------------------------------------------------------- bad input


H0, H1 = flat(1000.0), flat(1020.0)


@pytest.mark.parametrize(
    ("horizons", "kwargs", "message"),
    [
        ([H0], {}, r"at least two horizons.*got 1"),
        ({"x": AXIS, "y": AXIS, "z": np.zeros((11, 11))}, {}, r"sequence of at least two horizons"),
        ([H0, {"x": AXIS, "y": AXIS}], {}, r"horizon 1: missing 'z'"),
        ([H0, object()], {}, r"horizon 1: object has no 'x'"),
        ([H0, {"x": AXIS, "y": AXIS[:5], "z": np.zeros((11, 11))}], {}, r"horizon 1: z has shape \(11, 11\)"),
        ([H0, {"x": AXIS[[0, 2, 1, 3]], "y": AXIS[:3], "z": np.zeros((3, 4))}], {}, r"horizon 1: x is not"),
        ([H0, {"x": AXIS, "y": AXIS, "z": np.full((11, 11), np.nan)}], {}, r"horizon 1: z is undefined"),
        ([H0, {"x": AXIS, "y": AXIS, "z": np.full((11, 11), np.inf)}], {}, r"horizon 1: z has infinite"),
        ([H0, {"x": AXIS, "y": AXIS, "z": np.zeros(11)}], {}, r"horizon 1: z must be a 2-D array"),
        ([H0, {"x": PX + 0.1 * PY, "y": PY, "z": PX}], {}, r"horizon 1: x and y are not a rectilinear mesh"),
        ([H0, {"x": PX, "y": PY, "z": np.zeros((3, 3))}], {}, r"horizon 1: x, y and z must have the same"),
        ([H0, H1], {"layers": 0}, r"layers must be a positive integer.*zone 0 has 0"),
        ([H0, H1], {"layers": 1.5}, r"layers must be a positive integer"),
        ([H0, H1], {"layers": True}, r"layers must be a positive integer"),
        ([H0, H1, H1], {"layers": [2]}, r"one per zone \(2 zones\), got 1 values"),
        ([H0, H1], {"dims": (0, 3)}, r"dims must be positive"),
        ([H0, H1], {"dims": (3,)}, r"dims must be two positive integers"),
        ([H0, H1], {"ordering": "sort"}, r"ordering must be one of error, erode, onlap"),
        ([H0, H1], {"faults": ["x"]}, r"faults\[0\]: expected a FaultTrace"),
        (
            [H0, H1],
            {
                "faults": [
                    FaultTrace([(0, 0), (1, 1)], 1.0),
                    FaultTrace([(0, 0), (1, 1)], lambda s: s / 0 * 0),
                ]
            },
            r"fault 'F2' \(faults\[1\]\): throw\(s\) must be finite",
        ),
        (
            [H0, H1],
            {"faults": [FaultTrace([(0, 0), (1, 1)], lambda s: s[:2], "BAD")]},
            r"fault 'BAD' \(faults\[0\]\): throw\(s\) failed",
        ),
    ],
)
def test_bad_input_is_a_clear_error(horizons, kwargs, message):
    with np.errstate(all="ignore"), pytest.raises(gl.InputError, match=message):
        horizons_to_grdecl(horizons, **kwargs)


def test_disjoint_horizons_are_a_clear_error():
    far = Horizon(AXIS + 500.0, AXIS, np.full((11, 11), 1020.0))
    with pytest.raises(gl.InputError, match=r"no common area"):
        horizons_to_grdecl([H0, far])


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (([(0.0, 0.0)], 1.0, "ONE"), r"fault trace 'ONE': points must be an \(n >= 2, 2\) array"),
        (([(0.0, 0.0), (0.0, 0.0), (1.0, 1.0)], 1.0, "DUP"), r"'DUP': points 0 and 1 coincide"),
        (([(0.0, 0.0), (np.nan, 1.0)], 1.0, "NAN"), r"'NAN': points must be finite"),
        (([(0.0, 0.0), (1.0, 1.0)], "big", "STR"), r"'STR': throw must be a number"),
        (([(0.0, 0.0), (1.0, 1.0)], np.inf, "INF"), r"'INF': throw must be finite"),
        (([(0.0, 0.0), (1.0, 1.0)], 1.0, ""), r"name must be a non-empty string"),
    ],
)
def test_bad_fault_trace_is_a_clear_error(args, message):
    with pytest.raises(gl.InputError, match=message):
        FaultTrace(*args)
    with pytest.raises(gl.InputError, match=r"side must be 'left' or 'right', got 'up'"):
        FaultTrace([(0.0, 0.0), (1.0, 1.0)], 1.0, "S", side="up")
