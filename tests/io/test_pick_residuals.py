"""Horizon-pick residuals (gridlib.horizons.residuals) against analytic planes, exact; their
storage in horizons.nc; and the residuals picture checked from its matplotlib objects."""

from __future__ import annotations

import numpy as np
import pytest

from gridlib.horizons.build import HorizonSource, horizons_from_sources
from gridlib.horizons.residuals import PickResiduals, pick_residuals, residual_figures
from gridlib.io.horizon_files import read_pick_residuals, write_horizons
from gridlib.io.pick_residuals import plot_pick_residuals, residuals_figure
from gridlib.io.picture_style import NORTH_ARROW, SCALE_BAR, fault_colour, named
from gridlib.pillars.fault_traces import FaultTrace

X, Y = np.linspace(0.0, 1000.0, 11), np.linspace(0.0, 500.0, 6)


def plane(x, y, depth=1000.0):
    """A plane dipping east and rising north: exact under bilinear interpolation."""
    return depth + 0.125 * x - 0.0625 * y


def picks(n: int, seed: int, offsets=None, depth=1000.0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    xy = rng.uniform([20.0, 20.0], [980.0, 480.0], (n, 2))
    z = plane(xy[:, 0], xy[:, 1], depth) + (0.0 if offsets is None else offsets)
    return np.column_stack([xy, z])


def test_residuals_are_the_picks_offsets_from_a_plane():
    offsets = np.array([1.5, -2.0, 0.0, 0.25, -0.75, 3.0])
    pts = picks(6, 1, offsets)
    outside = np.array([[1200.0, 100.0, 1100.0]])  # beyond the lattice: undefined
    surface = plane(*np.meshgrid(X, Y))[None]
    r = pick_residuals([(0, np.vstack([pts, outside]), None)], surface, X, Y)
    np.testing.assert_allclose(r.residual[:6], offsets, rtol=0, atol=1e-10)
    np.testing.assert_allclose(r.surface[:6], plane(pts[:, 0], pts[:, 1]), rtol=1e-15)
    assert np.isnan(r.residual[6]) and r.block.tolist() == [-1] * 7 and r.horizon.tolist() == [0] * 7
    figures = residual_figures(r, ["top"])["top"]
    assert figures["picks"] == 7 and figures["undefined"] == 1
    assert figures["rms"] == pytest.approx(np.sqrt(np.mean(offsets**2)), rel=1e-10)
    assert figures["max_abs"] == pytest.approx(3.0, rel=1e-12)


def test_a_pick_is_compared_with_its_own_fault_blocks_surface():
    by_block = np.stack([plane(*np.meshgrid(X, Y)), plane(*np.meshgrid(X, Y), depth=1025.0)])[:, None]
    pts = np.array(
        [[300.0, 200.0, plane(300.0, 200.0) + 1.0], [310.0, 200.0, plane(310.0, 200.0, 1025.0) - 2.0]]
    )
    r = pick_residuals([(0, pts, np.array([0, 1]))], by_block[0], X, Y, by_block)
    np.testing.assert_allclose(r.residual, [1.0, -2.0], rtol=0, atol=1e-10)
    assert r.block.tolist() == [0, 1]


def test_horizons_store_their_picks_residuals(tmp_path):
    """Picks on two planes 25 m apart across a N-S fault at x = 500, interpolated per fault
    block (linear: planes exact): every residual is 0; without per-block surfaces the picks
    next to the fault see part of the throw in the lattice cell it crosses."""
    top = picks(200, 2)
    top[top[:, 0] > 500.0, 2] += 25.0
    base = top + [0.0, 0.0, 40.0]
    sources = [
        HorizonSource(name, name, "points", pts, {"extrapolation": "trend"}, f"{name}.csv")
        for name, pts in (("top", top), ("base", base))
    ]
    fault = [FaultTrace([(500.0, -10.0), (500.0, 510.0)], throw=0.0, name="F1")]
    ds = horizons_from_sources(sources, X, Y, faults=fault, per_block=True)
    assert ds["pick_residual"].attrs["units"] == "m" and ds.sizes["pick"] == 400
    np.testing.assert_allclose(ds["pick_residual"].values, 0.0, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(ds["pick_horizon"].values, np.repeat([0, 1], 200))
    east = np.concatenate([top[:, 0], base[:, 0]]) > 500.0
    block = ds["pick_block"].values
    assert len(set(block[east])) == 1 and len(set(block[~east])) == 1 and block[east][0] != block[~east][0]
    # stored and read back: the same picks and residuals
    write_horizons(tmp_path / "horizons.nc", ds)
    back, names = read_pick_residuals(tmp_path / "horizons.nc")
    assert names == ["top", "base"]
    np.testing.assert_array_equal(back.depth, np.concatenate([top[:, 2], base[:, 2]]))
    np.testing.assert_array_equal(back.residual, ds["pick_residual"].values)
    # one surface for both blocks (no per-block surfaces): the throw shows next to the fault
    smeared = horizons_from_sources(sources, X, Y, faults=fault)
    near = np.abs(np.concatenate([top[:, 0], base[:, 0]]) - 500.0) < 100.0
    assert np.nanmax(np.abs(smeared["pick_residual"].values[near])) > 1.0
    np.testing.assert_allclose(smeared["pick_residual"].values[~near], 0.0, atol=1e-9)


@pytest.fixture(scope="module")
def residuals() -> PickResiduals:
    offsets = np.array([[2.0, -1.0, 0.5, -0.5], [0.25, 0.0, -4.0, 1.0]])
    pts = [picks(4, 3, offsets[0]), picks(4, 4, offsets[1], depth=1040.0)]
    surface = np.stack([plane(*np.meshgrid(X, Y)), plane(*np.meshgrid(X, Y), 1040.0)])
    return pick_residuals([(0, pts[0], None), (1, pts[1], None)], surface, X, Y)


def test_the_picture_shows_each_horizons_map_and_histogram(residuals):
    trace = np.array([[500.0, -10.0], [500.0, 510.0]])
    fig = residuals_figure(residuals, ["top", "base"], title="demo", length_unit="m", faults=[("F1", trace)])
    axes = np.array(fig.axes[:4]).reshape(2, 2)  # then the colour bars
    for row, name in enumerate(["top", "base"]):
        ax_map, ax_hist = axes[row]
        assert ax_map.get_xlabel() == "x (east) [m]" and ax_map.get_ylabel() == "y (north) [m]"
        (points,) = named(ax_map, "picks")
        mine = residuals.horizon == row
        np.testing.assert_array_equal(points.get_offsets(), np.column_stack([residuals.x, residuals.y])[mine])
        np.testing.assert_allclose(points.get_array(), residuals.residual[mine])
        assert points.cmap.name == "RdBu_r"
        assert (points.norm.vmin, points.norm.vmax) == pytest.approx(
            (-4.0, 4.0), abs=1e-9
        )  # symmetric, common
        assert points.colorbar.ax.get_ylabel() == "residual [m]"
        (line,) = named(ax_map, "fault F1")
        assert line.get_color() == fault_colour(1)
        assert len(named(ax_map, SCALE_BAR)) == 1 and len(named(ax_map, NORTH_ARROW)) == 1
        assert (
            ax_hist.get_xlabel() == "residual [m] (pick depth - surface depth)"
            and ax_hist.get_ylabel() == "picks"
        )
        assert sum(p.get_height() for p in ax_hist.patches) == 4
        f = residual_figures(residuals, ["top", "base"])[name]
        assert ax_hist.get_title() == f"{name}: 4 picks, RMS {f['rms']:.3g} m, max |r| {f['max_abs']:.3g} m"
    assert fig._suptitle.get_text() == "demo"
    assert residual_figures(residuals, ["top", "base"])["base"]["max_abs"] == pytest.approx(4.0, abs=1e-10)
    import matplotlib.pyplot as plt

    plt.close(fig)


def test_plot_writes_the_png_and_no_picks_is_an_error(residuals, tmp_path):
    plot_pick_residuals(tmp_path / "r.png", residuals, ["top", "base"])
    assert (tmp_path / "r.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    empty = pick_residuals([], np.zeros((1, Y.size, X.size)), X, Y)
    with pytest.raises(ValueError, match="no picks"):
        residuals_figure(empty, ["top"])


def test_summary_figures_of_the_residuals(residuals):
    from gridlib.stages.export import pick_residuals_summary

    got = pick_residuals_summary(residuals, ["top", "base"])["pick_residuals"]
    rms = np.sqrt(np.mean(np.square([[2.0, -1.0, 0.5, -0.5], [0.25, 0.0, -4.0, 1.0]]), axis=1))
    assert list(got) == ["top", "base"]
    for (name, f), r, largest in zip(got.items(), rms, (2.0, 4.0), strict=True):
        assert f["picks"] == 4 and f["undefined"] == 0, name
        assert f["rms"] == pytest.approx(r, rel=1e-10) and f["max_abs"] == pytest.approx(largest, rel=1e-10)
    assert pick_residuals_summary(pick_residuals([], np.zeros((1, 6, 11)), X, Y), ["top"]) == {}
