"""The study pictures' data, read back from the figure objects (gridlib.io.study_pictures):
a 2 x 3 x 2 study (two keys, two realisations) with known values; each line's points are the
table's values for its combination of the other key, no spread segment joins realisations of
different combinations, every axis has its unit and no offset text; the profiles and the
tornado equal what the table gives by hand. No Flow: the tables are built here, after the
study.nc contract (docs/studies.md)."""

from __future__ import annotations

import json
import re

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr

from gridlib.io import study_pictures as sp

THROWS = [0, 40]  # m
SIZES = [50, 100, 200]  # m
REALISATIONS = [0, 1]
DAYS = np.array([0.0, 100.0, 200.0, 365.0])
KEYS = ["faults.0.throw", "grid.cell_size"]
NAME = r"throw-(\d+)_cell_size-(\d+)_r(\d+)"  # a variant's name


def _value(t: int, c: int, r: int) -> float:
    """A figure of variant (throw t, cell size c, realisation r), distinct per variant."""
    return 0.30 + 0.001 * t - 0.0002 * c + 0.01 * r


def _study(simulated: bool = True, failed: tuple[int, int, int] | None = None, combine: str = "product"):
    """study.nc of the 2 x 3 x 2 study: cells, pore_volume (~1e7 m3: a power of ten in the
    label), and when ``simulated`` the responses and series; ``failed`` (t, c, r) NaN."""
    shape = (len(THROWS), len(SIZES), len(REALISATIONS))
    t, c, r = np.meshgrid(THROWS, SIZES, REALISATIONS, indexing="ij")
    names = np.vectorize(lambda a, b, k: f"throw-{a}_cell_size-{b}_r{k}")(t, c, r).astype(object)
    dims = [*KEYS, "realisation"]
    ds = xr.Dataset(
        {
            "variant": (dims, names.astype(str)),
            "cells": (dims, (1_000_000 // c + 10 * t + r).astype(float)),
            "pore_volume": (dims, 1.5e7 + 1e5 * t + 1e4 * r - 10.0 * c, {"units": "m3"}),
        },
        coords={
            "faults.0.throw": ("faults.0.throw", THROWS, {"units": "m"}),
            "grid.cell_size": ("grid.cell_size", SIZES, {"units": "m"}),
            "realisation": REALISATIONS,
        },
        attrs={"study": "sweep", "combine": combine, "varied_keys": json.dumps(KEYS)},
    )
    if simulated:
        recovery = _value(t, c, r)
        status = np.full(shape, "ok", dtype=object)
        ds["oil_recovery"] = (dims, recovery, {"units": "1"})
        ds["FOPT"] = (dims, 2.0e6 * recovery, {"units": "sm3"})
        ds["FWPT"] = (dims, 1.0e5 * (1 + r) + 10.0 * t, {"units": "sm3"})
        ds["FPR"] = (dims, 250.0 - 0.1 * t - 0.01 * c, {"units": "bar"})
        ds["WBT:PROD"] = (dims, 100.0 + c + t - 5.0 * r, {"units": "day"})
        series = recovery[..., None] * DAYS / 365.0  # (throw, size, realisation, time)
        ds = ds.assign_coords(time=("time", DAYS, {"units": "day"}))
        ds["FOPR"] = ([*dims, "time"], 1000.0 * series, {"units": "sm3/day"})
        ds["FWCT"] = ([*dims, "time"], series, {"units": "1"})
        ds["FPR_series"] = ([*dims, "time"], 250.0 - series * 10.0, {"units": "bar"})
        if failed:
            at = tuple(v.index(x) for v, x in zip((THROWS, SIZES, REALISATIONS), failed, strict=True))
            status[at] = "failed"
            for name in ("oil_recovery", "FOPT", "FWPT", "FPR", "WBT:PROD", "FOPR", "FWCT", "FPR_series"):
                ds[name].values[at] = np.nan
        ds["simulation"] = (dims, status.astype(str))
    return ds


def _table(ds, figure: str) -> dict[tuple[int, int, int], float]:
    """(throw, size, realisation) -> value of ``figure``: the table the picture must show."""
    return {
        (t, c, r): float(ds[figure].sel({KEYS[0]: t, KEYS[1]: c, "realisation": r}))
        for t in THROWS
        for c in SIZES
        for r in REALISATIONS
    }


def _panels(fig, figures, keys=KEYS):
    axes = [a for a in fig.axes if a.get_xlabel()]
    assert len(axes) == len(figures) * len(keys)
    return {(f, k): axes[i * len(keys) + j] for i, f in enumerate(figures) for j, k in enumerate(keys)}


def _of(ax, gid):
    return [a for a in [*ax.lines, *ax.collections] if a.get_gid() == gid]


@pytest.fixture(scope="module")
def simulated():
    ds = _study(failed=(40, 100, 1))
    fig = sp.study_figure(ds)
    fig.canvas.draw()
    yield ds, fig
    plt.close(fig)


def _check_lines(ds, fig, figures, skip_failed):
    panels = _panels(fig, figures)
    for (figure, key), ax in panels.items():
        table = _table(ds, figure)
        other = KEYS[1] if key == KEYS[0] else KEYS[0]
        other_values = SIZES if key == KEYS[0] else THROWS
        values = THROWS if key == KEYS[0] else SIZES
        means = _of(ax, sp.MEAN)
        points = _of(ax, sp.REALISATIONS)
        spreads = _of(ax, sp.SPREAD)
        assert len(means) == len(points) == len(spreads) == len(other_values)
        for n, ov in enumerate(other_values):  # lines in order of the other key's values
            unit = "m"
            assert means[n].get_label() == f"{other} = {ov} {unit}"

            def at(v, ov=ov, key=key, table=table):
                t, c = (v, ov) if key == KEYS[0] else (ov, v)
                ys = [table[(t, c, r)] for r in REALISATIONS]
                if skip_failed and (t, c) == (40, 100):
                    ys = ys[:1]  # realisation 1 failed
                return ys

            x, y = means[n].get_xydata().T
            assert x.tolist() == [float(v) for v in values]
            assert y.tolist() == [float(np.mean(at(v))) for v in values]
            want = sorted((float(v), yy) for v in values for yy in at(v))
            assert sorted(map(tuple, points[n].get_xydata().tolist())) == want
            # each segment: one value of the key, from min to max of THIS combination's realisations
            segments = spreads[n].get_segments()
            assert len(segments) == len(values)
            for seg, v in zip(segments, values, strict=True):
                (x0, y0), (x1, y1) = seg
                assert x0 == x1 == float(v)
                assert (y0, y1) == (min(at(v)), max(at(v)))
        # every point inside the panel (visible), no offset text on either axis
        (x0, x1), (y0, y1) = sorted(ax.get_xlim()), sorted(ax.get_ylim())
        for line in points:
            x, y = line.get_xydata().T
            assert np.all((x0 < x) & (x < x1)) and np.all((y0 < y) & (y < y1))
        assert ax.xaxis.get_offset_text().get_text() == ""
        assert ax.yaxis.get_offset_text().get_text() == ""


def test_each_line_is_its_combination_and_no_spread_spans_another_key(simulated):
    ds, fig = simulated
    figures = ["oil_recovery", "FOPT", "FWPT", "FPR", "WBT:PROD"]
    assert sp.chosen_figures(ds) == figures
    _check_lines(ds, fig, figures, skip_failed=True)


def test_the_bug_of_issue_28_bars_spanning_the_other_key_is_gone():
    """The old picture drew one bar per throw over every cell size: cells 4,668 to 11,706 at
    one throw. Now a bar never reaches beyond one (throw, cell size) combination."""
    ds = _study(simulated=False)
    fig = sp.study_figure(ds)
    try:
        panels = _panels(fig, ["cells", "pore_volume"])
        for ax in (panels[("cells", KEYS[0])], panels[("pore_volume", KEYS[0])]):
            for spread in _of(ax, sp.SPREAD):
                for (_x0, y0), (_x1, y1) in spread.get_segments():
                    assert y1 - y0 <= 1e4  # realisations differ by 1 (cells) and 1e4 m3
        _check_lines(ds, fig, ["cells", "pore_volume"], skip_failed=False)
    finally:
        plt.close(fig)


def test_axes_carry_units_and_the_power_of_ten_is_in_the_label(simulated):
    _, fig = simulated
    panels = _panels(fig, ["oil_recovery", "FOPT", "FWPT", "FPR", "WBT:PROD"])
    assert {ax.get_xlabel() for ax in panels.values()} == {"faults.0.throw [m]", "grid.cell_size [m]"}
    assert panels[("oil_recovery", KEYS[0])].get_ylabel() == "oil recovery [fraction]"
    assert panels[("FOPT", KEYS[0])].get_ylabel() == "FOPT [10³ sm3]"
    assert panels[("FWPT", KEYS[0])].get_ylabel() == "FWPT [10³ sm3]"
    assert panels[("FPR", KEYS[0])].get_ylabel() == "FPR [bar]"
    assert panels[("WBT:PROD", KEYS[0])].get_ylabel() == "WBT:PROD [day]"
    assert [t.get_text() for t in panels[("FPR", KEYS[0])].get_xticklabels()] == ["0", "40"]
    assert [t.get_text() for t in panels[("FPR", KEYS[1])].get_xticklabels()] == ["50", "100", "200"]
    ax = panels[("FOPT", KEYS[0])]
    ticks = ax.yaxis.get_major_locator()()
    labels = [ax.yaxis.get_major_formatter()(v, 0) for v in ticks]
    assert labels == [f"{v / 1e3:g}" for v in ticks]
    grid = sp.study_figure(_study(simulated=False))
    try:
        pv = _panels(grid, ["cells", "pore_volume"])[("pore_volume", KEYS[1])]
        assert pv.get_ylabel() == "pore volume [10⁶ m3]"
        assert _panels(grid, ["cells", "pore_volume"])[("cells", KEYS[1])].get_ylabel() == "cells"
    finally:
        plt.close(grid)


def test_failed_variants_are_marked_not_drawn_as_zero(simulated):
    _, fig = simulated
    panels = _panels(fig, ["oil_recovery", "FOPT", "FWPT", "FPR", "WBT:PROD"])
    for (_figure, key), ax in panels.items():
        (cross,) = _of(ax, sp.FAILED)
        assert cross.get_xdata().tolist() == [40 if key == KEYS[0] else 100]
        for line in _of(ax, sp.REALISATIONS):
            assert np.all(np.asarray(line.get_ydata()) > 0)


def test_zipped_study_draws_one_line():
    ds = _study(simulated=False, combine="zip")
    # a zipped study has the diagonal only; the other combinations are "" variants
    keep = np.zeros((2, 3, 2), bool)
    keep[0, 0, :] = keep[1, 1, :] = True
    ds["variant"] = ds["variant"].where(keep, "")
    fig = sp.study_figure(ds)
    try:
        ax = _panels(fig, ["cells", "pore_volume"])[("cells", KEYS[0])]
        (mean,) = _of(ax, sp.MEAN)
        table = _table(ds, "cells")
        want = [np.mean([table[(t, c, r)] for r in REALISATIONS]) for t, c in ((0, 50), (40, 100))]
        assert mean.get_ydata().tolist() == want
    finally:
        plt.close(fig)


def test_profiles_are_each_variants_series_coloured_by_its_value():
    ds = _study(failed=(0, 200, 0))
    fig = sp.profiles_figure(ds)
    try:
        fig.canvas.draw()
        axes = [a for a in fig.axes if a.get_xlabel()]
        assert len(axes) == 2 * 3  # a row per key, a column per profile
        assert [a.get_ylabel() for a in axes[:3]] == ["FOPR [sm3/day]", "FWCT [fraction]", "FPR [bar]"]
        assert {a.get_xlabel() for a in axes} == {"time [day]"}
        for row, key in enumerate(KEYS):
            values = THROWS if row == 0 else SIZES
            colours = {}
            for col, name in enumerate(("FOPR", "FWCT", "FPR_series")):
                ax = axes[3 * row + col]
                lines = [ln for ln in ax.lines if ln.get_gid()]
                assert len(lines) == 11  # 12 variants, one failed
                assert "throw-0_cell_size-200_r0" not in {ln.get_gid() for ln in lines}
                (note,) = [t for t in ax.texts if t.get_gid() == sp.FAILED]
                assert note.get_text() == "1 failed variant left out"
                for ln in lines:
                    t, c, r = map(int, re.fullmatch(NAME, ln.get_gid()).groups())
                    at = {KEYS[0]: t, KEYS[1]: c, "realisation": r}
                    assert ln.get_xdata().tolist() == DAYS.tolist()
                    assert ln.get_ydata().tolist() == ds[name].sel(at).values.tolist()
                    value = t if row == 0 else c
                    colours.setdefault(value, tuple(ln.get_color()))
                    assert tuple(ln.get_color()) == colours[value]
            assert len(set(colours.values())) == len(values)
            legend = axes[3 * row + 2].get_legend()
            assert legend.get_title().get_text() == key
            assert [t.get_text() for t in legend.get_texts()] == [f"{v} m" for v in values]
    finally:
        plt.close(fig)


def test_tornado_is_the_swing_of_the_mean_between_lowest_and_highest_values():
    ds = _study(failed=(40, 100, 1))

    def mean(t, c):
        ys = [_value(t, c, r) for r in REALISATIONS if (t, c, r) != (40, 100, 1)]
        return sum(ys) / len(ys)

    # middle values: throw 0 (lower middle of 2 values), cell size 100
    swings = {s.key: s for s in sp.tornado_swings(ds)}
    throw, size = swings[KEYS[0]], swings[KEYS[1]]
    assert (throw.low, throw.high, size.low, size.high) == (0, 40, 50, 200)
    assert throw.base == size.base == mean(0, 100)
    assert throw.low_mean == mean(0, 100) and throw.high_mean == mean(40, 100)  # (40, 100) one realisation
    assert size.low_mean == mean(0, 50) and size.high_mean == mean(0, 200)
    assert [s.key for s in sp.tornado_swings(ds)] == [KEYS[0], KEYS[1]]  # 0.04 > 0.03
    fig = sp.tornado_figure(ds)
    try:
        (ax,) = fig.axes
        low = [p for p in ax.patches if p.get_gid() == sp.TORNADO_LOW]
        high = [p for p in ax.patches if p.get_gid() == sp.TORNADO_HIGH]
        # largest swing on top (y = 1): throw; cell size below (y = 0)
        bars = {round(p.get_y() + p.get_height() / 2): p for p in high}
        assert bars[1].get_x() == throw.base and bars[1].get_x() + bars[1].get_width() == pytest.approx(
            throw.high_mean, abs=1e-15
        )
        assert bars[0].get_x() + bars[0].get_width() == pytest.approx(size.high_mean, abs=1e-15)
        lows = {round(p.get_y() + p.get_height() / 2): p for p in low}
        assert lows[0].get_x() + lows[0].get_width() == pytest.approx(size.low_mean, abs=1e-15)
        assert ax.get_xlabel() == "oil recovery [fraction]"
        assert [t.get_text() for t in ax.get_yticklabels()] == [
            "grid.cell_size\n50 m to 200 m",
            "faults.0.throw\n0 m to 40 m",
        ]
        assert ax.xaxis.get_offset_text().get_text() == ""
    finally:
        plt.close(fig)


def test_a_key_of_labels_is_drawn_in_order_and_its_tornado_bar_spans_its_least_and_greatest_mean():
    """A grid question (``grid`` varied as labelled sections): the labels, sorted, are the x
    ticks; the tornado's bar goes from the label of least mean recovery to that of the
    greatest, from the base at the middle label."""
    labels = ["pebi-40m", "pillars-80m", "stairs-80m"]
    recovery = np.array([[0.31, 0.33], [0.36, 0.34], [0.29, 0.30]])  # (label, realisation)
    ds = xr.Dataset(
        {
            "variant": (("grid", "realisation"), [[f"{g}_r{r}" for r in (0, 1)] for g in labels]),
            "simulation": (("grid", "realisation"), np.full((3, 2), "ok")),
            "oil_recovery": (("grid", "realisation"), recovery, {"units": "1"}),
        },
        coords={"grid": labels, "realisation": [0, 1]},
        attrs={"study": "grid_choice", "combine": "product", "varied_keys": json.dumps(["grid"])},
    )
    (swing,) = sp.tornado_swings(ds)
    assert (swing.low, swing.high) == ("stairs-80m", "pillars-80m")
    assert (swing.low_mean, swing.high_mean, swing.base) == (0.295, 0.35, 0.35)  # base: pillars-80m
    fig = sp.study_figure(ds)
    try:
        (ax,) = [a for a in fig.axes if a.get_xlabel()]
        assert ax.get_xlabel() == "grid"
        assert [t.get_text() for t in ax.get_xticklabels()] == labels
        (mean,) = _of(ax, sp.MEAN)
        assert mean.get_xdata().tolist() == [0.0, 1.0, 2.0]
        assert mean.get_ydata().tolist() == recovery.mean(axis=1).tolist()
    finally:
        plt.close(fig)


def test_a_study_whose_simulations_all_failed_says_so():
    ds = _study()
    for name in ("oil_recovery", "FOPT", "FWPT", "FPR", "WBT:PROD"):
        ds[name].values[:] = np.nan
    ds["simulation"] = ds["simulation"].copy(data=np.full(ds["simulation"].shape, "failed"))
    fig = sp.study_figure(ds)
    try:
        texts = [t.get_text() for ax in fig.axes for t in ax.texts if t.get_gid() == sp.FAILED]
        assert texts == ["no responses: 12 failed simulations"] * 2
    finally:
        plt.close(fig)
