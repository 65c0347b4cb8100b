"""Horizons (gridlib.horizons): interpolation, fault blocks, surfaces, the Dataset and the stage
(ordering: test_ordering.py; IRAP and points files: tests/io/)."""

from __future__ import annotations

import numpy as np
import pytest

from gridlib import InputError, compute_geometry, horizons_to_grdecl, process_grdecl
from gridlib.cornerpoint import FaultTrace, Horizon
from gridlib.horizons import (
    Surface,
    fault_blocks,
    horizon_dataset,
    interpolate_points,
    interpolate_points_at,
    peaks,
    plane,
    to_horizons,
)
from gridlib.io.horizon_files import (
    build_horizons,
    read_horizons,
    read_surface_netcdf,
    write_horizons,
)
from gridlib.io.irap import write_irap

X_AXIS = np.linspace(0.0, 1000.0, 51)  # 20 m spacing
Y_AXIS = np.linspace(0.0, 800.0, 41)


def dipping(x, y):
    return plane(x, y, depth=1500.0, dip=3.0, azimuth=120.0, x0=500.0, y0=400.0)


def scattered(n=300, seed=1, lo=(0.0, 0.0), hi=(1000.0, 800.0)):
    xy = np.random.default_rng(seed).uniform(lo, hi, (n, 2))
    return np.column_stack([xy, dipping(xy[:, 0], xy[:, 1])])


# --------------------------------------------------------------------------- interpolation


@pytest.mark.parametrize("method", ["linear", "rbf"])
def test_plane_recovered_exactly_from_scattered_points(method):
    pts = scattered()
    X, Y = np.meshgrid(X_AXIS, Y_AXIS)
    z = interpolate_points(pts, X_AXIS, Y_AXIS, method=method)  # NaN outside the hull
    inside = np.isfinite(z)
    assert 0 < (~inside).sum() < 0.2 * z.size  # the hull of 300 random points misses the corners
    assert np.abs(z - dipping(X, Y))[inside].max() < 1e-9
    z = interpolate_points(pts, X_AXIS, Y_AXIS, method=method, extrapolation="trend")
    assert np.isfinite(z).all()
    assert np.abs(z - dipping(X, Y)).max() < 1e-9  # everywhere: the trend continues the plane


def test_local_rbf_and_utm_offsets_keep_planes_exact():
    pts = scattered(n=3000, seed=2)
    shift = np.array([456_789.0, 6_789_012.0, 0.0])  # UTM-sized coordinates
    X, Y = np.meshgrid(X_AXIS + shift[0], Y_AXIS + shift[1])
    z = interpolate_points(pts + shift, X_AXIS + shift[0], Y_AXIS + shift[1], method="rbf", neighbors=30)
    ok = np.isfinite(z)
    assert ok.sum() > 0.9 * z.size
    assert np.abs(z - dipping(X - shift[0], Y - shift[1]))[ok].max() < 1e-9


def test_interpolation_reproduces_the_data_points():
    rng = np.random.default_rng(3)
    xy = rng.uniform(-3.0, 3.0, (200, 2))
    z = peaks(xy[:, 0], xy[:, 1], depth=1000.0, amplitude=10.0)
    pts = np.column_stack([xy, z])
    for method in ("linear", "cubic", "rbf", "nearest"):
        got = interpolate_points_at(pts, xy[:, 0], xy[:, 1], method=method)
        assert np.abs(got - z).max() < 1e-8, method
    smooth = interpolate_points_at(pts, xy[:, 0], xy[:, 1], method="rbf", smoothing=1.0)
    assert np.abs(smooth - z).max() > 1e-3  # smoothing > 0 no longer interpolates


def test_extrapolation_nearest_is_continuous_at_the_hull():
    pts = np.array([[0.0, 0.0, 100.0], [10.0, 0.0, 110.0], [0.0, 10.0, 100.0], [10.0, 10.0, 110.0]])
    x, y = np.array([20.0, 30.0, -5.0]), np.array([5.0, 5.0, 5.0])
    assert interpolate_points_at(pts, x, y, extrapolation="nearest").tolist() == [110.0, 110.0, 100.0]
    trend = interpolate_points_at(pts, x, y, extrapolation="trend")
    assert np.allclose(trend, [120.0, 130.0, 95.0], rtol=0, atol=1e-9)
    with pytest.raises(InputError, match="undefined"):  # default: undefined outside the hull, here everywhere
        interpolate_points_at(pts, x, y)
    assert np.isnan(interpolate_points_at(pts, [5.0, 20.0], [5.0, 5.0])).tolist() == [False, True]


# --------------------------------------------------------------------------- faults


TRACE = np.array([(300.0, -50.0), (700.0, 850.0)])  # oblique, crossing the lattice from edge to edge
THROW = 25.0


def left_of_trace(x, y):
    d = TRACE[1] - TRACE[0]
    return d[0] * (y - TRACE[0, 1]) - d[1] * (x - TRACE[0, 0]) > 0


def faulted_points(n=800, seed=4):
    xy = np.random.default_rng(seed).uniform((0.0, 0.0), (1000.0, 800.0), (n, 2))
    z = dipping(xy[:, 0], xy[:, 1]) + np.where(left_of_trace(xy[:, 0], xy[:, 1]), 0.0, THROW)
    return np.column_stack([xy, z])


@pytest.mark.parametrize("method", ["linear", "rbf"])
def test_interpolation_per_fault_block_keeps_the_throw(method):
    pts = faulted_points()
    X, Y = np.meshgrid(X_AXIS, Y_AXIS)
    left = left_of_trace(X, Y)
    expected = dipping(X, Y) + np.where(left, 0.0, THROW)
    notes: list[str] = []
    z = interpolate_points(
        pts, X_AXIS, Y_AXIS, method=method, extrapolation="trend", faults=[TRACE], notes=notes
    )
    assert notes == []
    d = TRACE[1] - TRACE[0]
    dist = np.abs(d[0] * (Y - TRACE[0, 1]) - d[1] * (X - TRACE[0, 0])) / np.hypot(*d)  # m from the trace
    off = dist > 1e-6
    assert np.abs(z - expected)[off].max() < 1e-9  # every node off the trace: exactly its block's plane
    near = off & (dist < 20.0)  # the nodes next to the trace, on both sides
    assert near[left].sum() > 30 and near[~left].sum() > 30
    assert np.abs(z - expected)[near].max() < 1e-9
    assert np.abs(z[near & ~left] - dipping(X, Y)[near & ~left] - THROW).max() < 1e-9  # the full throw

    smeared = interpolate_points(pts, X_AXIS, Y_AXIS, method=method, extrapolation="trend")
    assert np.abs(smeared - expected)[near].max() > 5.0  # without the trace the throw is smeared


def test_fault_blocks_classify_and_report_dangling_traces():
    blocks = fault_blocks(
        [[(500.0, -1.0), (500.0, 101.0)], [(500.0, 50.0), (1001.0, 50.0)]], (0, 1000, 0, 100)
    )
    assert blocks.num == 3 and blocks.notes == ()
    ids = blocks.classify([100.0, 800.0, 800.0, 500.0, 500.0], [50.0, 20.0, 80.0, 20.0, 120.0])
    assert ids.tolist() == [0, 1, 2, 0, 0]  # on the trace: the lowest id; outside the box: the nearest
    assert blocks.classify([500.0], [20.0], on_trace="none").tolist() == [-1]

    tip = fault_blocks([[(500.0, -1.0), (500.0, 60.0)]], (0, 1000, 0, 100))  # ends inside: splits nothing
    assert tip.num == 1
    assert "fault trace 0 separates no blocks along" in tip.notes[0]

    with pytest.raises(InputError, match=r"faults\[0\]: a trace must be a finite"):
        fault_blocks([[(0.0, 0.0)]], (0, 1, 0, 1))


# --------------------------------------------------------------------------- surfaces


def test_surface_sampling_with_rotation():
    s = Surface([[0.0, 10.0], [0.0, 10.0]], 100.0, 200.0, 10.0, 10.0, rotation=90.0)  # local x is world +y
    X, Y = s.node_coordinates()
    assert np.allclose(X, [[100.0, 100.0], [90.0, 90.0]]) and np.allclose(Y, [[200.0, 210.0], [200.0, 210.0]])
    assert s.sample([100.0, 95.0, 110.0], [205.0, 202.0, 205.0]).round(12).tolist()[:2] == [5.0, 2.0]
    assert np.isnan(s.sample(110.0, 205.0))  # outside the rotated lattice
    with pytest.raises(InputError, match="rotated by 90 degrees"):
        s.to_horizon()


def test_bad_options_and_undefined_surfaces(tmp_path):
    pts = scattered(n=50)
    with pytest.raises(
        InputError, match=r"top: method: unknown value 'spline'; expected one of linear, cubic"
    ):
        interpolate_points(pts, X_AXIS, Y_AXIS, method="spline", name="top")
    with pytest.raises(InputError, match=r"extrapolation: unknown value 'linear'"):
        interpolate_points(pts, X_AXIS, Y_AXIS, extrapolation="linear")
    with pytest.raises(InputError, match=r"smoothing applies to method 'rbf' only"):
        interpolate_points(pts, X_AXIS, Y_AXIS, smoothing=1.0)
    with pytest.raises(InputError, match=r"horizons\[0\] \('top'\): method: unknown value 'kriging'"):
        build_horizons([{"name": "top", "points": pts, "method": "kriging"}], X_AXIS, Y_AXIS)
    with pytest.raises(InputError, match=r"horizons\[0\] \('top'\): unknown keys \['dip'\]"):
        build_horizons([{"name": "top", "points": pts, "dip": 3}], X_AXIS, Y_AXIS)
    with pytest.raises(InputError, match=r"horizon 'base': undefined \(NaN\) everywhere"):
        horizon_dataset(
            [np.zeros((41, 51)), np.full((41, 51), np.nan)], X_AXIS, Y_AXIS, names=["top", "base"]
        )
    far = pts + [5000.0, 0.0, 0.0]
    with pytest.raises(InputError, match=r"top: the interpolated surface is undefined \(NaN\) everywhere"):
        interpolate_points(far, X_AXIS, Y_AXIS, name="top")
    undefined = Surface(np.full((3, 3), np.nan), 0.0, 0.0, 500.0, 400.0)
    path = write_irap(tmp_path / "empty.irap", undefined)
    with pytest.raises(
        InputError, match=r"horizons\[0\] \('top'\): .*empty\.irap is undefined \(NaN\) everywhere"
    ):
        build_horizons([{"name": "top", "surface": str(path)}], X_AXIS, Y_AXIS)


# --------------------------------------------------------------------------- the Dataset and the stage


def test_build_horizons_from_files_and_formulas_round_trips(tmp_path):
    pts = faulted_points()
    np.savetxt(tmp_path / "top.xyz", pts)
    X, Y = np.meshgrid(X_AXIS, Y_AXIS)
    mid = Surface.from_axes(X_AXIS, Y_AXIS, dipping(X, Y) + 40.0, name="mid")
    write_irap(tmp_path / "mid.irap", mid)
    specs = [
        {"name": "top", "points": "top.xyz", "method": "rbf", "extrapolation": "trend"},
        {"name": "mid", "surface": "mid.irap"},
        {"name": "base", "plane": {"depth": 1600.0, "dip": 1.0, "azimuth": 45.0}},
    ]
    ds = build_horizons(
        specs, X_AXIS, Y_AXIS, ordering="error", faults=[TRACE], base_dir=tmp_path, attrs={"seed": 7}
    )
    assert ds.depth.dims == ("horizon", "y", "x") and ds.depth.shape == (3, 41, 51)
    assert list(ds.horizon.values) == ["top", "mid", "base"]
    assert list(ds.method.values) == ["rbf", "resampled (linear)", "plane"]
    assert ds.source.values[0].endswith("top.xyz") and ds.attrs["seed"] == 7
    assert ds.depth.attrs == {
        "units": "m",
        "positive": "down",
        "long_name": "depth of the horizon (NaN = undefined)",
    }
    left = left_of_trace(X, Y)
    d = TRACE[1] - TRACE[0]
    off = np.abs(d[0] * (Y - TRACE[0, 1]) - d[1] * (X - TRACE[0, 0])) > 1e-6  # nodes not on the trace
    assert np.array_equal(ds.block.values[off], np.where(left, 0, 1)[off])  # block 0 west of the trace
    top = ds.depth.sel(horizon="top").values
    expected = dipping(X, Y) + np.where(left, 0.0, THROW)
    assert np.abs(top - expected)[off].max() < 1e-9
    assert np.abs(ds.depth.sel(horizon="mid").values - (dipping(X, Y) + 40.0)).max() < 1e-9

    path = write_horizons(tmp_path / "horizons.nc", ds)
    back = read_horizons(path)
    assert np.array_equal(back.depth.values, ds.depth.values, equal_nan=True)
    assert np.array_equal(back.x.values, X_AXIS) and list(back.horizon.values) == ["top", "mid", "base"]
    assert back.attrs["ordering"] == "error" and "gridlib_version" in back.attrs
    hz = to_horizons(back)
    assert isinstance(hz[0], Horizon) and hz[2].z.shape == (41, 51)
    surf = read_surface_netcdf(path, horizon="base")
    assert surf.name == "base" and np.abs(surf.z - back.depth.values[2]).max() == 0.0
    with pytest.raises(
        InputError, match=r"holds several horizons; pass horizon= one of \['top', 'mid', 'base'\]"
    ):
        read_surface_netcdf(path)


def test_seed_peaks_example_through_horizons_to_grdecl():
    # MRST book §3.3.1: [y,x,z] = peaks(15); z = z+8; horizons z and z+8; 4 layers
    a = np.linspace(-3.0, 3.0, 15)
    X, Y = np.meshgrid(a, a)
    top = peaks(Y, X, depth=8.0)
    ds = horizon_dataset([top, top + 8.0], a, a, names=["top", "base"])
    cp = process_grdecl(horizons_to_grdecl(to_horizons(ds), layers=4))
    assert cp.grid.num_cells == 14 * 14 * 4
    vol = compute_geometry(cp.grid).cell_volumes.sum()
    assert vol == pytest.approx(36.0 * 8.0, rel=1e-12)  # 8 m everywhere over the 6 x 6 square
    assert float(peaks(1.5, -0.5)) == pytest.approx(
        3 * 0.25 * np.exp(-2.25 - 0.25) - 10 * (0.3 - 3.375 + 0.03125) * np.exp(-2.5) - np.exp(-6.5) / 3
    )


def test_faults_accept_fault_traces():
    pts = faulted_points()
    trace = FaultTrace(TRACE, throw=THROW)
    a = interpolate_points(pts, X_AXIS, Y_AXIS, faults=[trace])
    b = interpolate_points(pts, X_AXIS, Y_AXIS, faults=[TRACE])
    assert np.array_equal(a, b, equal_nan=True)


def test_picks_of_faulted_horizons_per_block_give_the_exact_throw():
    """Picks of two horizons already offset 30 m by a N-S fault (east side down). Interpolated per
    fault block and built with horizons_to_grdecl_by_block, the deck equals the one made from the
    pre-fault planes with a 30 m FaultTrace; interpolated across the trace, the offset is smeared."""
    from gridlib.horizons.by_block import block_horizons, horizons_to_grdecl_by_block

    rng = np.random.default_rng(3)
    xy = rng.uniform([0.0, 0.0], [1000.0, 500.0], (400, 2))
    xy = xy[np.abs(xy[:, 0] - 500.0) > 5.0]  # no pick on the trace itself

    def top(x, y):
        return 1000.0 + 0.02 * x + 0.01 * y

    east = np.where(xy[:, 0] > 500.0, 30.0, 0.0)
    specs = [
        {"name": "top", "points": np.column_stack([xy, top(*xy.T) + east]), "extrapolation": "trend"},
        {"name": "base", "points": np.column_stack([xy, top(*xy.T) + 40.0 + east]), "extrapolation": "trend"},
    ]
    x, y = np.linspace(0.0, 1000.0, 41), np.linspace(0.0, 500.0, 21)
    trace = [(500.0, -10.0), (500.0, 510.0)]
    ds = build_horizons(specs, x, y, faults=[trace], per_block=True)
    assert ds["depth_by_block"].dims == ("fault_block", "horizon", "y", "x") and ds.sizes["fault_block"] == 2
    stacks, blocks = block_horizons(ds)
    deck = horizons_to_grdecl_by_block(stacks, blocks, [20, 10], 4, [FaultTrace(trace, throw=0.0, name="F")])

    X, Y = np.meshgrid(x, y)
    planes = [Horizon(x, y, top(X, Y)), Horizon(x, y, top(X, Y) + 40.0)]
    want = horizons_to_grdecl(planes, [20, 10], 4, [FaultTrace(trace, throw=30.0, name="F")])
    np.testing.assert_allclose(deck.zcorn, want.zcorn, rtol=0, atol=1e-9)  # linear: planes are exact
    assert deck.faults == want.faults
    # the interpolated depths carry round-off (1e-13 m): merge points within 1e-6 m, or layers that
    # exactly touch across the fault would meet in slivers of 1e-10 m2
    got, ref = process_grdecl(deck, tolerance=1e-6), process_grdecl(want)
    assert got.grid.num_cells == 800 and got.nnc.num == ref.nnc.num > 0
    np.testing.assert_array_equal(np.sort(got.nnc.cells, axis=1), np.sort(ref.nnc.cells, axis=1))
    assert int((got.grid.faces.tag > 0).sum()) == int((ref.grid.faces.tag > 0).sum()) > 0
    volume = compute_geometry(got.grid).cell_volumes.sum()
    assert volume == pytest.approx(1000.0 * 500.0 * 40.0, rel=1e-12)

    smeared = build_horizons(specs, x, y)  # across the trace: the 30 m step spreads over cells
    plain = horizons_to_grdecl(to_horizons(smeared), [20, 10], 4)
    assert np.nanmax(np.abs(plain.zcorn - want.zcorn)) > 5.0


def test_per_block_surfaces_need_traces_and_picks_in_every_block():
    x, y = np.linspace(0.0, 1000.0, 11), np.linspace(0.0, 500.0, 6)
    pts = np.array(
        [[100.0, 100.0, 1000.0], [200.0, 400.0, 1001.0], [300.0, 200.0, 1002.0], [900.0, 100.0, 1003.0]]
    )
    spec = [
        {"name": "top", "points": pts, "extrapolation": "trend"},
        {"name": "base", "plane": {"depth": 1100.0}},
    ]
    with pytest.raises(InputError, match=r"per-fault-block surfaces need fault traces"):
        build_horizons(spec, x, y, per_block=True)
    with pytest.raises(InputError, match=r"horizons\[0\] \('top'\): fault block 1 has 1 pick\(s\)"):
        build_horizons(spec, x, y, faults=[[(500.0, -10.0), (500.0, 510.0)]], per_block=True)


def test_a_case_with_picks_of_faulted_horizons_keeps_the_throw(tmp_path):
    """The workflow's stages on a case whose picks hold a 20 m offset (horizons.per_fault_block):
    the fault faces are tagged F1, cells connect across it, and the volume is area x thickness."""
    import json

    from artifacts import run_case_without_pictures

    from gridlib.config import load_case

    rng = np.random.default_rng(5)
    xy = rng.uniform([0.0, 0.0], [1200.0, 800.0], (500, 2))
    xy = xy[np.abs(xy[:, 0] - 600.0) > 5.0]
    z = 1500.0 + 0.03 * xy[:, 0] + np.where(xy[:, 0] > 600.0, 20.0, 0.0)
    np.savetxt(tmp_path / "top.xyz", np.column_stack([xy, z]))
    np.savetxt(tmp_path / "base.xyz", np.column_stack([xy, z + 35.0]))
    (tmp_path / "picks.yaml").write_text(
        """name: picks
horizons:
  per_fault_block: true
  lattice: {x: {start: 0, stop: 1200, num: 49}, y: {start: 0, stop: 800, num: 33}}
  surfaces:
    - {name: top, points: top.xyz, extrapolation: trend}
    - {name: base, points: base.xyz, extrapolation: trend}
faults:
  - {name: F1, trace: [[600, -20], [600, 820]]}
grid: {type: cornerpoint, dims: [24, 16], layers: 5, tolerance: 1.0e-6}
"""
    )
    run_case_without_pictures(tmp_path / "picks.yaml", tmp_path / "out")
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["cells"] == 24 * 16 * 5 and summary["faults"] == ["F1"]
    assert summary["fault_faces"] > 0 and summary["nnc"] > 0
    assert summary["total_volume"] == pytest.approx(1200.0 * 800.0 * 35.0, rel=1e-9)
    bad = (
        (tmp_path / "picks.yaml")
        .read_text()
        .replace("trace: [[600, -20], [600, 820]]}", "trace: [[600, -20], [600, 820]], throw: 5}")
    )
    (tmp_path / "thrown.yaml").write_text(bad.replace("name: picks", "name: thrown"))
    with pytest.raises(InputError, match=r"thrown.yaml: faults\[0\].throw: with horizons.per_fault_block"):
        load_case(tmp_path / "thrown.yaml")
