"""Stage ``study`` of a simulated 2 x 3 x 2 study (two keys, two realisations; one variant's
Flow run failed), in process from made-up summary.json and responses.json files (no build, no
Flow): study.png, study_profiles.png and study_tornado.png are written, and the pictures' data,
read from the figure objects, are study.csv's values (each line its combination of the other
key; the tornado's bars the means by hand; the failed variant marked, not drawn)."""

from __future__ import annotations

import csv
import json

import matplotlib.pyplot as plt
import numpy as np
import pytest
import yaml

from gridlib.io import study_pictures as sp
from gridlib.io.flow_responses import Responses, failed_responses, write_responses
from gridlib.stages import study as stage
from gridlib.units import METRIC

THROWS, SIZES, REALISATIONS = [0, 40], [50, 100, 200], [0, 1]
KEYS = ["faults.0.throw", "grid.cell_size"]
FAILED = "t40_c100_r1"
DAYS = [0.0, 100.0, 365.0]


def _recovery(t: int, c: int, r: int) -> float:
    return 0.3 + 0.001 * t - 0.0002 * c + 0.01 * r


def _responses(t: int, c: int, r: int) -> Responses:
    rec = _recovery(t, c, r)
    return Responses(
        status="ok",
        unit_system="METRIC",
        units={"FOPT": "sm3", "FWPT": "sm3", "FWIT": "sm3", "FPR": "bar", "FOIP0": "sm3"}
        | {"oil_recovery": "1", "WBT:PROD": "day", "FOPR": "sm3/day", "FWCT": "1"},
        scalars={"FOPT": 3e6 * rec, "FWPT": 1e5 + t, "FWIT": 2e5, "FPR": 250.0 - t - 0.01 * c}
        | {"FOIP0": 3e6, "oil_recovery": rec, "WBT:PROD": 100.0 + c + r},
        series={
            "time": DAYS,
            "FOPR": [1000 * rec * d / 365 for d in DAYS],
            "FWCT": [rec * d / 365 for d in DAYS],
            "FPR": [250.0 - d / (100 + t) for d in DAYS],
        },
    )


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """The stage run on the study; its outputs, study.csv's rows and the figures drawn."""
    tmp = tmp_path_factory.mktemp("study")
    variants, summaries, simulations = [], [], []
    for t in THROWS:
        for c in SIZES:
            for r in REALISATIONS:
                name = f"t{t}_c{c}_r{r}"
                values = {KEYS[0]: t, KEYS[1]: c}
                variants.append({"name": name, "values": values, "realisation": r, "seed": 5 + 3 * r})
                folder = tmp / name / "simulation"
                folder.mkdir(parents=True)
                failed = failed_responses("Flow stopped: no convergence", METRIC, "simulation/V.PRT")
                write_responses(folder / "responses.json", failed if name == FAILED else _responses(t, c, r))
                simulations.append(folder)
                summaries.append(tmp / name / "summary.json")
                summary = {"case": name, "unit_system": "METRIC", "griddim": 3, "cells": 1000 + c}
                summaries[-1].write_text(json.dumps(summary | {"pore_volume": 1.5e7 + r}))
    quantities = {k: {"quantity": "length"} for k in KEYS}
    manifest = {"study": "sweep", "keys": KEYS, "key_quantities": quantities, "combine": "product"}
    manifest |= {"variants": variants, "simulation": {"times": [], "water_cut": 0.01, "on_failure": "report"}}
    (tmp / "variants.yaml").write_text(yaml.safe_dump(manifest, sort_keys=False))
    outputs = {k: str(tmp / f) for k, f in [("csv", "study.csv"), ("nc", "study.nc"), ("png", "study.png")]}
    outputs |= {"profiles": str(tmp / "study_profiles.png"), "tornado": str(tmp / "study_tornado.png")}
    drawn = {}
    real = stage.save_figure

    def keep(fig, path, dpi=None):
        drawn[str(path)] = fig
        fig.canvas.draw()
        fig.savefig(path, dpi=40)

    stage.save_figure = keep
    try:
        stage.stage_study(tmp / "variants.yaml", summaries, outputs, simulations)
    finally:
        stage.save_figure = real
    with open(outputs["csv"], newline="") as f:
        rows = list(csv.DictReader(f))
    yield outputs, rows, drawn
    for fig in drawn.values():
        plt.close(fig)


def _csv(rows, column: str, t: int, c: int, r: int) -> float:
    (row,) = [x for x in rows if x["variant"] == f"t{t}_c{c}_r{r}"]
    return float(row[column])


def test_the_pictures_are_written(study):
    outputs, _rows, drawn = study
    assert set(drawn) == {outputs["png"], outputs["profiles"], outputs["tornado"]}


def test_study_png_lines_are_study_csv_per_combination(study):
    outputs, rows, drawn = study
    fig = drawn[outputs["png"]]
    axes = [a for a in fig.axes if a.get_xlabel()]
    figures = ["oil_recovery", "FOPT", "FWPT", "FPR", "WBT:PROD"]
    assert [a.get_ylabel() for a in axes[::2]] == [
        "oil recovery [fraction]",
        "FOPT [10⁶ sm3]",
        "FWPT [10³ sm3]",
        "FPR [bar]",
        "WBT:PROD [day]",
    ]
    column = dict(
        zip(
            figures,
            ["oil_recovery [1]", "FOPT [sm3]", "FWPT [sm3]", "FPR [bar]", "WBT:PROD [day]"],
            strict=True,
        )
    )
    for i, figure in enumerate(figures):
        for j, key in enumerate(KEYS):
            ax = axes[2 * i + j]
            assert ax.get_xlabel() == f"{key} [m]"
            means = [a for a in ax.lines if a.get_gid() == sp.MEAN]
            spreads = [a for a in ax.collections if a.get_gid() == sp.SPREAD]
            others, values = (SIZES, THROWS) if j == 0 else (THROWS, SIZES)
            for line, spread, other in zip(means, spreads, others, strict=True):
                assert line.get_label() == f"{KEYS[1 - j]} = {other} m"
                ys = []
                for v in values:
                    t, c = (v, other) if j == 0 else (other, v)
                    ok = [r for r in REALISATIONS if f"t{t}_c{c}_r{r}" != FAILED]
                    ys.append([_csv(rows, column[figure], t, c, r) for r in ok])
                assert line.get_ydata().tolist() == [float(np.mean(y)) for y in ys]
                assert [tuple(s[:, 1]) for s in spread.get_segments()] == [(min(y), max(y)) for y in ys]
                assert [tuple(s[:, 0]) for s in spread.get_segments()] == [(float(v),) * 2 for v in values]
            (cross,) = [a for a in ax.lines if a.get_gid() == sp.FAILED]
            assert cross.get_xdata().tolist() == [40 if j == 0 else 100]
            assert ax.yaxis.get_offset_text().get_text() == ""


def test_tornado_bars_are_the_means_by_hand(study):
    outputs, rows, drawn = study
    (ax,) = drawn[outputs["tornado"]].axes

    def mean(t, c):
        return np.mean(
            [_csv(rows, "oil_recovery [1]", t, c, r) for r in REALISATIONS if f"t{t}_c{c}_r{r}" != FAILED]
        )

    base = mean(0, 100)  # throw's middle of (0, 40) is 0; cell size's of (50, 100, 200) is 100
    ends = sorted(
        p.get_x() + p.get_width() for p in ax.patches if p.get_gid() in (sp.TORNADO_LOW, sp.TORNADO_HIGH)
    )
    assert ends == pytest.approx(sorted([mean(0, 100), mean(40, 100), mean(0, 50), mean(0, 200)]), abs=1e-15)
    assert {p.get_x() for p in ax.patches if p.get_gid() in (sp.TORNADO_LOW, sp.TORNADO_HIGH)} == {base}


def test_profiles_leave_out_the_failed_variant(study):
    outputs, _rows, drawn = study
    axes = [a for a in drawn[outputs["profiles"]].axes if a.get_xlabel()]
    assert [a.get_ylabel() for a in axes[:3]] == ["FOPR [sm3/day]", "FWCT [fraction]", "FPR [bar]"]
    for ax in axes:
        names = {ln.get_gid() for ln in ax.lines if ln.get_gid()}
        assert len(names) == 11 and FAILED not in names
    fpr = {ln.get_gid(): ln.get_ydata().tolist() for ln in axes[2].lines if ln.get_gid()}
    assert fpr["t40_c50_r0"] == [250.0 - d / 140 for d in DAYS]
