"""Stage pictures: a faulted PEBI case with wells built in process gets its 3-D view,
histograms, plan view and cross-section; their content read from the figures; a section line
given in the case is checked when the case is read, and one that misses the grid stops the
stage naming the key."""

from __future__ import annotations

from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest
import yaml

from gridlib import artifacts
from gridlib.config import check_case_data, load_case
from gridlib.errors import InputError
from gridlib.io import picture_style as style
from gridlib.io.cross_section import EXAGGERATION
from gridlib.io.plan_view import FAULT_NAME, SECTION, WELL_NAME
from gridlib.stages import case_outputs, run_stage
from gridlib.stages.pictures import case_figures, read_scene, stage_pictures

ROOT = Path(__file__).resolve().parents[2]
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """faulted_pebi without its coarsening, built into a folder up to its pictures: (case file,
    folder)."""
    tmp = tmp_path_factory.mktemp("pictures")
    data = yaml.safe_load((ROOT / "config" / "cases" / "faulted_pebi.yaml").read_text())
    del data["coarsen"]
    path = tmp / "faulted_pebi.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    case = load_case(path)
    paths = case_outputs(case.name, tmp / "out")
    for stage in artifacts.STAGES:  # up to the pictures (not the Flow deck: a second faster)
        if stage.when(case) and not stage.on_request and stage.name != "flow_deck":
            run_stage(stage.name, case, paths)
    return path, tmp / "out"


def _named(ax, gid: str) -> list[str]:
    return sorted(t.get_text() for t in ax.texts if t.get_gid() == gid)


def test_the_pictures_of_a_faulted_pebi_case(built):
    path, folder = built
    out = case_outputs("faulted_pebi", folder)
    for key in ("png", "histograms", "plan", "section"):
        assert out[key].read_bytes()[:8] == PNG, key
    case = load_case(path)
    scene = read_scene(case, out["grid"], out["geometry"], out["petrophysics"], out["transmissibility"])
    figures = case_figures(case, scene)
    plan, section = figures["plan"].axes[0], figures["section"].axes[0]
    assert (plan.get_xlabel(), plan.get_ylabel()) == ("x [m]", "y [m]")
    assert figures["plan"].axes[1].get_ylabel() == "top depth [m]"
    assert _named(plan, FAULT_NAME) == _named(section, FAULT_NAME) == ["EW", "NS"]
    assert _named(plan, WELL_NAME) == _named(section, WELL_NAME) == ["I1", "P1"]
    assert style.named(plan, style.SCALE_BAR) and style.named(plan, style.NORTH_ARROW)
    assert [t.get_text() for t in style.named(plan, SECTION) if hasattr(t, "get_text")] == ["A", "A'"]
    # the default line: from the box's edge through P1 and I1 (in order along their direction)
    (drawn,) = [a for a in plan.lines if a.get_gid() == SECTION]
    line = drawn.get_xydata()
    np.testing.assert_allclose(line[1:3], [[450.0, 350.0], [1550.0, 1150.0]])
    assert figures["section"].axes[1].get_ylabel() == "porosity [fraction]"
    assert _named(section, EXAGGERATION) == ["vertical exaggeration 5x"]
    assert section.get_ylim()[0] > section.get_ylim()[1]
    for figure in figures.values():
        plt.close(figure)


def test_a_section_line_that_misses_the_grid_stops_the_stage(built, tmp_path):
    path, folder = built
    data = yaml.safe_load(path.read_text()) | {"pictures": {"section": [[5000, 0], [6000, 0]]}}
    elsewhere = tmp_path / "faulted_pebi.yaml"
    elsewhere.write_text(yaml.safe_dump(data, sort_keys=False))
    out = case_outputs("faulted_pebi", folder)
    mine = case_outputs("faulted_pebi", tmp_path)
    inputs = {k: out[k] for k in ("grid", "geometry", "faults", "petrophysics", "transmissibility")}
    outputs = {k: mine[k] for k in ("png", "histograms", "plan", "section")}
    with pytest.raises(InputError, match=r"faulted_pebi.yaml: pictures.section: the line cuts no cell"):
        stage_pictures(load_case(elsewhere), **inputs, **outputs)


@pytest.mark.parametrize(
    ("section", "grid", "message"),
    [
        (
            [[0, 0], [100, 50], [100, 50]],
            {"type": "cartesian", "dims": [4, 3, 2], "lengths": [400, 300, 20]},
            r"x.yaml: pictures.section\[2\]: \(100, 50\) repeats the point before it",
        ),
        (
            [[0, 0], [100, 50]],
            {"type": "cartesian", "dims": [4, 3], "lengths": [400, 300]},
            "x.yaml: pictures.section: a 2-D grid has no cross-section",
        ),
        ([[0, 0]], {"type": "cartesian", "dims": [4, 3, 2], "lengths": [400, 300, 20]}, "pictures.section: "),
    ],
)
def test_a_section_line_is_checked_when_the_case_is_read(section, grid, message):
    data = {"name": "x", "grid": grid, "pictures": {"section": section}}
    with pytest.raises(InputError, match=message):
        check_case_data(data, Path("x.yaml"), "x.yaml")


def test_the_pictures_are_the_same_bytes_when_drawn_again(built, tmp_path):
    """Deterministic pictures (the 3-D view's rendering, matplotlib's PNG and its metadata):
    drawn again from the same stage files, every PNG is byte for byte the first."""
    path, folder = built
    out = case_outputs("faulted_pebi", folder)
    again = case_outputs("faulted_pebi", tmp_path)
    inputs = {k: out[k] for k in ("grid", "geometry", "faults", "petrophysics", "transmissibility")}
    drawn = ("png", "histograms", "plan", "section")
    stage_pictures(load_case(path), **inputs, **{k: again[k] for k in drawn})
    for key in drawn:
        assert again[key].read_bytes() == out[key].read_bytes(), key
