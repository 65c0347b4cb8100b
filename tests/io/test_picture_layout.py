"""The fixed layout of the matplotlib pictures (gridlib.io.picture_style: MARGINS, panel_layout,
fit_figure, colour_bar): nothing drawn outside the figure (not cropped), colour bars beside
their axes' drawn box, figures fitted to their maps, drawn once when saved, the same bytes
every time; on small grids built in process, one of them at UTM-like coordinates in feet."""

from __future__ import annotations

from dataclasses import replace

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.figure import Figure
from picture_grids import faulted_box

from gridlib.geometry import compute_geometry
from gridlib.io import picture_style as style
from gridlib.io.cross_section import section_figure
from gridlib.io.pictures import histogram_figure, save_figure
from gridlib.io.plan_view import plan_figure
from gridlib.io.quality_histograms import quality_figure
from gridlib.io.well_tracks import vertical_track
from gridlib.units import METRIC

UTM = (456_000.0, 6_780_000.0)  # a plan view's tick labels of 7 characters


def _shifted(grid, offset):
    xyz = grid.nodes.coords.copy()
    xyz[:, :2] += offset
    return replace(grid, nodes=replace(grid.nodes, coords=xyz))


@pytest.fixture(scope="module", params=["local", "utm"])
def box(request):
    grid = faulted_box()
    if request.param == "utm":
        grid = _shifted(grid, UTM)
    return grid, compute_geometry(grid), request.param


def _plan(grid, geo, unit="m"):
    x0, y0 = grid.nodes.coords[:, :2].min(axis=0)
    with style.picture_style():
        return plan_figure(
            grid,
            geo,
            length_unit=unit,
            fault_names=["F-east", "F-north"],
            wells=(vertical_track("W1", (x0 + 150.0, y0 + 100.0), (0.0, 60.0)),),
            title="box",
            section=np.array([[x0, y0 + 150.0], [x0 + 600.0, y0 + 150.0]]),
        )


def _section(grid):
    x0, y0 = grid.nodes.coords[:, :2].min(axis=0)
    with style.picture_style():
        return section_figure(
            grid,
            np.array([[x0, y0 + 150.0], [x0 + 600.0, y0 + 150.0]]),
            length_unit="ft",
            values=np.linspace(0.1, 0.3, grid.num_cells),
            quantity=("porosity", "fraction"),
            fault_names=["F-east", "F-north"],
            title="box",
        )


def _inside_the_figure(fig) -> None:
    """Every artist's extent (tick labels, axis labels, titles, colour bars, names) lies within
    the figure: nothing is cropped."""
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    drawn = fig.get_tightbbox(renderer)  # inches
    width, height = fig.get_size_inches()
    assert drawn.x0 >= 0.0 and drawn.y0 >= 0.0, (drawn, width, height)
    assert drawn.x1 <= width and drawn.y1 <= height, (drawn, width, height)


def _beside(fig, ax, bar_ax) -> None:
    """The colour bar's box: COLOUR_BAR's gap right of the axes' drawn box, its width, a fixed
    fraction of the axes' height and centred on it; within the figure."""
    width = fig.get_size_inches()[0]
    box, bar = ax.get_position(), bar_ax.get_position()
    assert (bar.x0 - box.x1) * width == pytest.approx(style.COLOUR_BAR["pad"], abs=1e-9)
    assert bar.width * width == pytest.approx(style.COLOUR_BAR["width"], abs=1e-9)
    assert bar.height == pytest.approx(style.COLOUR_BAR["length"] * box.height, rel=1e-9)
    assert bar.y0 + 0.5 * bar.height == pytest.approx(box.y0 + 0.5 * box.height, rel=1e-9)


def test_the_plan_view_fits_its_map_and_is_not_cropped(box):
    grid, geo, where = box
    fig = _plan(grid, geo, unit="ft" if where == "utm" else "m")
    assert fig.get_layout_engine() is None  # fixed margins: no layout pass, no second draw
    ax, bar = fig.axes
    _inside_the_figure(fig)
    _beside(fig, ax, bar)
    # the figure as tall as the map (600 x 400 and 4 % margins) needs: the axes' box keeps its
    # place (the margins in inches), its aspect the data's (equal)
    m = style.MAP_MARGINS
    width, height = fig.get_size_inches()
    assert width == style.FIGURE_SIZES["plan"][0]
    drawn = width - m["left"] - m["right"]
    room = m["bottom"] + m["top"]
    assert height == pytest.approx(drawn * (400.0 + 48.0) / (600.0 + 48.0) + room, rel=1e-12)
    position = ax.get_position()
    assert position.x0 * width == pytest.approx(m["left"])
    assert position.y0 * height == pytest.approx(m["bottom"])
    assert position.width * width == pytest.approx(drawn, rel=1e-9)
    plt.close(fig)


def test_a_section_in_feet_is_not_cropped(box):
    grid, _, _ = box
    fig = _section(grid)
    assert fig.get_layout_engine() is None
    ax, bar = fig.axes
    _inside_the_figure(fig)
    _beside(fig, ax, bar)
    plt.close(fig)


def test_the_histograms_are_not_cropped(box):
    grid, geo, _ = box
    poro = np.linspace(0.1, 0.3, grid.num_cells)
    trans = np.geomspace(1e-3, 1e3, grid.num_faces)  # a logarithmic panel
    fig = histogram_figure(geo, poro, 3, "box: 72 cells", METRIC, trans)
    _inside_the_figure(fig)
    plt.close(fig)
    values = {"aspect_ratio": np.geomspace(1.0, 1e4, 72), "maxangle_sides": np.linspace(90.0, 130.0, 72)}
    fig = quality_figure(values, [{"quantity": "maxangle_sides", "max": 120.0, "action": "warn"}], "box")
    assert len(fig.axes) == 2  # the panels shown, no empty axes
    _inside_the_figure(fig)
    plt.close(fig)


def test_a_picture_is_drawn_once_and_the_same_bytes_every_time(box, tmp_path, monkeypatch):
    grid, geo, _ = box
    draws = []
    draw = Figure.draw
    monkeypatch.setattr(Figure, "draw", lambda fig, renderer: draws.append(fig) or draw(fig, renderer))
    saved = []
    for k in range(2):
        for name, fig in (("plan", _plan(grid, geo)), ("section", _section(grid))):
            save_figure(fig, tmp_path / f"{name}{k}.png", dpi=style.DPI)
            saved.append(fig)
    assert len(draws) == len(saved)  # savefig draws each figure once (no layout pass first)
    for name in ("plan", "section"):
        assert (tmp_path / f"{name}0.png").read_bytes() == (tmp_path / f"{name}1.png").read_bytes()
