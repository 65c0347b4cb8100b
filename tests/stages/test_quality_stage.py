"""The ``quality`` stage (issue 27, item 1): quality.nc and {case}_quality.png of a small case
built in this process, the case's ``qc:`` rules (warn and fail messages word for word, a fail
leaving no quality.nc), the measures in {case}.nc and summary.json, and the qc section's checks
when the case is read."""

from __future__ import annotations

import json
import logging
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from gridlib.config import load_case
from gridlib.errors import InputError
from gridlib.stages import case_outputs, run_case, run_stage
from gridlib.stages.quality import check_rules, rule_message

# 3 x 2 x 2 cells of 100 m x 100 m x 10 m: every angle 90 degrees, centre lines along the normals,
# and the centroid 50 m from the side faces, 5 m from top and base: aspect ratio 10.
SMALL = """name: small
grid: {type: cartesian, dims: [3, 2, 2], lengths: [300, 200, 20], origin: [0, 0, 1000]}
petrophysics: {porosity: {constant: 0.2}, permeability: {constant: 100}}
"""
RULES = """qc:
  - {quantity: aspect_ratio, max: 5, action: warn}
  - {quantity: minangle_sides, min: 89, action: fail}
  - {quantity: k_orientation_error, max: 1, fraction: 0.5, action: warn}
"""
WARNING = (
    "{path}: qc[0]: aspect_ratio above max 5 (warn) in 12 of 12 cells (100 %): "
    "(1, 1, 1), (2, 1, 1), (3, 1, 1), (1, 2, 1), (2, 2, 1) and 7 more"
)


def write_case(folder: Path, text: str, name: str = "small") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"{name}.yaml"
    path.write_text(text.replace("name: small", f"name: {name}"))
    return path


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> tuple[Path, Path]:
    """The small case with its rules, every stage run in this process: (case file, results)."""
    folder = tmp_path_factory.mktemp("quality")
    case = write_case(folder, SMALL + RULES)
    run_case(case, folder / "out")
    return case, folder / "out"


def test_quality_nc_holds_every_measure_with_its_unit(built):
    _, out = built
    with xr.open_dataset(out / "quality.nc") as ds:
        assert ds.attrs["unit_system"] == "METRIC" and ds.attrs["case_name"] == "small"
        for name in ("minangle_topbase", "maxangle_topbase", "minangle_sides", "maxangle_sides"):
            np.testing.assert_allclose(ds[name].values, 90.0, atol=1e-12)
            assert ds[name].attrs["units"] == "degree" and ds[name].attrs["hexahedral_only"] == 1
        for name in ("orientation_error", "k_orientation_error", "twist"):
            np.testing.assert_allclose(ds[name].values, 0.0, atol=1e-9)
        np.testing.assert_allclose(ds["aspect_ratio"].values, 10.0, rtol=1e-12)
        assert ds["aspect_ratio"].attrs["units"] == "1" and ds["aspect_ratio"].attrs["hexahedral_only"] == 0
        for flag in ("collapsed", "faulted", "negative_thickness", "concave_proj"):
            np.testing.assert_array_equal(ds[flag].values, 0.0)
            assert "units" not in ds[flag].attrs  # a flag is no physical quantity (CF)
        assert [r["status"] for r in json.loads(ds.attrs["qc"])] == ["warn", "pass", "pass"]


def test_the_case_nc_and_summary_hold_the_measures_and_the_qc_results(built):
    _, out = built
    with xr.open_dataset(out / "small.nc") as ds:
        np.testing.assert_allclose(ds["aspect_ratio"].values, 10.0, rtol=1e-12)
        assert ds["maxangle_sides"].attrs["units"] == "degree"
        assert "units" not in ds["collapsed"].attrs
    summary = json.loads((out / "summary.json").read_text())
    quality = summary["quality"]
    assert quality["aspect_ratio"] == {"median": 10.0, "p95": 10.0, "max": 10.0}
    assert quality["minangle_sides"] == {"median": 90.0, "p95": 90.0, "max": 90.0}
    assert quality["orientation_error"] == {"median": 0.0, "p95": 0.0, "max": 0.0}
    assert quality["flagged_cells"] == {
        "collapsed": 0,
        "faulted": 0,
        "negative_thickness": 0,
        "concave_proj": 0,
    }
    first = [[1, 1, 1], [2, 1, 1], [3, 1, 1], [1, 2, 1], [2, 2, 1]]
    assert summary["qc"] == [
        {
            "rule": "qc[0]",
            "quantity": "aspect_ratio",
            "max": 5.0,
            "action": "warn",
            "fraction": 0.0,
            "status": "warn",
            "cells": 12,
            "evaluated": 12,
            "first_cells": first,
        },
        {
            "rule": "qc[1]",
            "quantity": "minangle_sides",
            "min": 89.0,
            "action": "fail",
            "fraction": 0.0,
            "status": "pass",
            "cells": 0,
            "evaluated": 12,
            "first_cells": [],
        },
        {
            "rule": "qc[2]",
            "quantity": "k_orientation_error",
            "max": 1.0,
            "action": "warn",
            "fraction": 0.5,
            "status": "pass",
            "cells": 0,
            "evaluated": 12,
            "first_cells": [],
        },
    ]


def test_a_warn_rule_logs_one_message_naming_the_cells(built, tmp_path, caplog):
    case, out = built
    paths = case_outputs("small", out) | {"quality": tmp_path / "q.nc", "quality_png": tmp_path / "q.png"}
    with caplog.at_level(logging.INFO, logger="gridlib"):
        run_stage("quality", case, paths)
    warnings = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    assert warnings == [WARNING.format(path=case)]


def test_a_fail_rule_stops_the_stage_and_leaves_no_quality_file(built, tmp_path):
    _, out = built
    failing = write_case(tmp_path, SMALL + RULES.replace("max: 5, action: warn", "max: 5, action: fail"))
    paths = case_outputs("small", out) | {"quality": tmp_path / "q.nc", "quality_png": tmp_path / "q.png"}
    with pytest.raises(InputError) as err:
        run_stage("quality", failing, paths)
    assert str(err.value) == WARNING.format(path=failing).replace("(warn)", "(fail)")
    assert not (tmp_path / "q.nc").exists() and not (tmp_path / "q.png").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["small.yaml"]  # no temporary file either


def test_rules_count_the_cells_where_the_measure_is_defined():
    values = {"maxangle_sides": np.array([91.0, 120.0, np.nan, 130.0]), "aspect_ratio": np.ones(4)}
    rules = [
        {"quantity": "maxangle_sides", "max": 100, "action": "warn"},
        {"quantity": "maxangle_sides", "max": 100, "fraction": 2 / 3, "action": "fail"},  # 2 of 3: allowed
        {"quantity": "maxangle_sides", "max": 100, "fraction": 0.5, "action": "fail"},
        {"quantity": "aspect_ratio", "min": 1, "action": "fail"},  # 1 is not below 1
        {"quantity": "k_orientation_error", "max": 10, "action": "warn"},  # not computed: undefined
    ]
    results = check_rules(values, rules)
    assert [r.cells.tolist() for r in results] == [[1, 3], [1, 3], [1, 3], [], []]
    assert [r.evaluated for r in results] == [3, 3, 3, 4, 0]
    assert [r.status for r in results] == ["warn", "pass", "fail", "pass", "undefined"]


def test_cells_without_logical_indices_are_named_by_number(built):
    from gridlib import cart_grid

    case = load_case(built[0])
    grid = cart_grid([2, 1, 1])
    grid = replace(grid, cells=replace(grid.cells, index_map=None))
    values = {"maxangle_sides": np.array([95.0, 99.5])}
    rule = {"quantity": "maxangle_sides", "max": 95, "fraction": 0.25, "action": "fail"}
    (result,) = check_rules(values, [rule])
    assert rule_message(case, grid, result) == (
        f"{case.path}: qc[0]: maxangle_sides above max 95 degree (fail) in 1 of 2 cells "
        "(50 %, more than the 25 % allowed): cell 1"
    )


def test_the_figure_shows_each_varying_measure_with_its_unit_and_the_limits():
    import matplotlib.pyplot as plt

    from gridlib.io.quality_histograms import quality_figure

    n = 200
    values = {
        "maxangle_sides": np.linspace(90.0, 130.0, n),
        "faulted": (np.arange(n) % 10 == 0).astype(float),
        "negative_thickness": np.zeros(n),  # one value, no rule: no panel
        "twist": np.full(n, np.nan),  # defined nowhere: no panel
        "aspect_ratio": np.geomspace(1.0, 50.0, n),
    }
    rules = [
        {"quantity": "maxangle_sides", "max": 120, "action": "warn"},
        {"quantity": "maxangle_sides", "max": 125, "action": "fail"},
        {"quantity": "aspect_ratio", "min": 2, "action": "warn"},
    ]
    fig = quality_figure(values, rules, "small: 200 cells")
    try:
        axes = fig.axes
        assert [ax.get_xlabel() for ax in axes] == ["maxangle_sides [degree]", "faulted", "aspect_ratio [1]"]
        assert all(ax.get_ylabel() == "cells" for ax in axes)
        lines = {(ax.get_xlabel(), line.get_xdata()[0], line.get_color()) for ax in axes for line in ax.lines}
        assert lines == {
            ("maxangle_sides [degree]", 120.0, "tab:orange"),
            ("maxangle_sides [degree]", 125.0, "tab:red"),
            ("aspect_ratio [1]", 2.0, "tab:orange"),
        }
        legend = [t.get_text() for t in axes[0].get_legend().get_texts()]
        assert legend == ["warn max 120: 50 cells past it", "fail max 125: 25 cells past it"]
        assert [t.get_text() for t in axes[2].get_legend().get_texts()] == ["warn min 2: 36 cells past it"]
        assert [p.get_height() for p in axes[1].patches] == [180, 20]  # a flag: cells per value
        assert fig._suptitle.get_text() == "small: 200 cells: cell quality"
    finally:
        plt.close(fig)


@pytest.mark.parametrize(
    ("rule", "message"),
    [
        (
            "{quantity: maxangle, max: 5, action: warn}",
            "qc[1].quantity: unknown measure 'maxangle'; the measures are minangle_topbase, ",
        ),
        ("{quantity: aspect_ratio, action: warn}", "qc[1]: give exactly one of max, min (got none)"),
        (
            "{quantity: aspect_ratio, max: 5, min: 1, action: warn}",
            "qc[1]: give exactly one of max, min (got max, min)",
        ),
        (
            "{quantity: aspect_ratio, max: 5, action: stop}",
            "qc[1].action: 'stop' is not one of ['warn', 'fail']",
        ),
        (
            "{quantity: aspect_ratio, max: 5, fraction: 2, action: warn}",
            "qc[1].fraction: 2 is greater than the maximum of 1",
        ),
    ],
)
def test_a_broken_rule_is_one_error_naming_the_case_and_the_key(tmp_path, rule, message):
    case = write_case(tmp_path, SMALL + f"qc:\n  - {{quantity: twist, max: 1, action: warn}}\n  - {rule}\n")
    with pytest.raises(InputError) as err:
        load_case(case)
    assert str(err.value).startswith(f"{case}: {message}")
    if "unknown measure" in message:
        assert str(err.value).endswith("aspect_ratio, face_nonplanarity")


def test_a_rule_on_a_measure_the_grid_lacks_is_refused(tmp_path):
    bare = SMALL.split("petrophysics")[0]
    case = write_case(tmp_path, bare + "qc: [{quantity: k_orientation_error, max: 1, action: warn}]\n")
    with pytest.raises(
        InputError, match=r"qc\[0\]\.quantity: k_orientation_error needs the case's permeability"
    ):
        load_case(case)
    flat = SMALL.replace("dims: [3, 2, 2], lengths: [300, 200, 20], origin: [0, 0, 1000]", "dims: [3, 2]")
    case = write_case(tmp_path, flat + "qc: [{quantity: maxangle_sides, max: 100, action: warn}]\n")
    with pytest.raises(InputError) as err:
        load_case(case)
    assert str(err.value) == (
        f"{case}: qc[0].quantity: maxangle_sides is defined on corner-point hexahedra, "
        "not on a 2-D grid's cells"
    )
    data = yaml.safe_load((Path(__file__).parents[2] / "config" / "cases" / "honeycomb.yaml").read_text())
    data["qc"] = [{"quantity": "minangle_sides", "min": 80, "action": "warn"}]
    path = tmp_path / "honeycomb.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(InputError) as err:
        load_case(path)
    assert str(err.value) == (
        f"{path}: qc[0].quantity: minangle_sides is defined on corner-point hexahedra only (cartesian, "
        "tensor, cornerpoint, deck grids), not on the prisms of a layered grid"
    )


def test_a_limit_measures_what_its_measure_measures():
    from gridlib.config.key_units import KeyQuantity, key_quantity, key_unit

    data = {"qc": [{"quantity": "maxangle_sides", "max": 100}, {"quantity": "aspect_ratio", "min": 1}]}
    assert key_quantity("qc.0.max", data) == KeyQuantity("angle", "METRIC")
    assert key_unit("qc.0.max", "FIELD", data) == "degree"
    assert key_unit("qc.1.min", "FIELD", data) == "1"
    assert key_quantity("qc.0.fraction") == KeyQuantity("fraction")
