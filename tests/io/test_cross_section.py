"""The cross-section (gridlib.io.cross_section) and the cut it draws (gridlib.io.section_cut):
the cut polygons' areas against the analytic cut of a box, the faults' lines, the default line,
and the figure's content from its matplotlib objects."""

from __future__ import annotations

import itertools

import matplotlib
import numpy as np
import pytest
from picture_grids import DIP, faulted_box

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from gridlib.io.cross_section import (
    EXAGGERATION,
    FAULT_NAME,
    WELL_NAME,
    default_section,
    section_figure,
    well_heads,
)
from gridlib.io.section_cut import cut_grid
from gridlib.io.well_tracks import WellTrack, vertical_track

THICKNESS = 30.0


@pytest.fixture(scope="module")
def box():
    return faulted_box((6, 4, 3), (600.0, 400.0, THICKNESS))


def _inside_length(line: np.ndarray, lo=(0.0, 0.0), hi=(600.0, 400.0)) -> float:
    """The length of the polyline inside the box lo..hi (fine sampling of each segment: the
    reference, independent of the cut's clipping)."""
    total = 0.0
    for a, b in itertools.pairwise(line):
        t = (np.arange(200_000) + 0.5) / 200_000
        p = a + t[:, None] * (b - a)
        inside = np.all((p >= lo) & (p <= hi), axis=1)
        total += inside.mean() * float(np.hypot(*(b - a)))
    return total


@pytest.mark.parametrize(
    "line",
    [
        [[-10.0, 55.5], [700.0, 355.5]],  # oblique, beyond the box at both ends
        [[100.0, 100.0], [500.0, 300.0], [500.0, 350.0]],  # a bend, ends inside the box
        [[0.0, 200.0], [600.0, 200.0]],  # along the faces at y = 200: each cell once
        [[300.0, -50.0], [300.0, 450.0]],  # along the faces at x = 300, through every layer
    ],
)
def test_the_cut_area_is_the_thickness_times_the_length_inside(box, line):
    """A vertical section through a box dipping along x (a shear: every vertical line crosses
    the same thickness) cuts THICKNESS x its length inside the box; a section along faces cuts
    each cell once."""
    line = np.array(line)
    cut = cut_grid(box, line)
    assert cut.areas().sum() == pytest.approx(THICKNESS * _inside_length(line), rel=1e-4)
    assert np.all(cut.areas() > 0)
    if (line.shape[0] == 2 and (line[:, 0] == line[0, 0]).all()) or (line[:, 1] == line[0, 1]).all():
        assert np.unique(cut.cells).size == cut.cells.size
    np.testing.assert_allclose(cut.vertices[-1], np.hypot(*np.diff(line, axis=0).T).sum())


def test_the_cut_is_exact_where_it_can_be_checked_by_hand(box):
    line = np.array([[0.0, 150.0], [600.0, 150.0]])
    cut = cut_grid(box, line)
    assert cut.cells.size == 6 * 3
    np.testing.assert_allclose(cut.areas(), 100.0 * 10.0, rtol=1e-12)
    # depth = DIP x + layer: each polygon's corners
    s, z = cut.points.T
    np.testing.assert_allclose(np.mod(z - DIP * s + 1e-9, 10.0), 1e-9, atol=1e-8)
    # fault 1 (faces at x = 300) crosses the section as a vertical line 30 long at s = 300
    ones = cut.fault_lines[cut.fault_ids == 1]
    np.testing.assert_allclose(ones[:, :, 0], 300.0)
    assert np.abs(ones[:, 1, 1] - ones[:, 0, 1]).sum() == pytest.approx(THICKNESS)
    assert not np.any(cut.fault_ids == 2)  # fault 2 (y = 200) is parallel to the section


def test_the_default_section_runs_through_the_wells_in_order_to_the_box():
    heads = np.array([[500.0, 350.0], [100.0, 50.0], [300.0, 210.0]])
    line = default_section(heads, np.array([0.0, 0.0]), np.array([600.0, 400.0]))
    np.testing.assert_allclose(line[1:-1], heads[[1, 2, 0]])
    np.testing.assert_allclose(line[0], [100.0 - 200.0 * 50.0 / 160.0, 0.0])  # on along A - B to y = 0
    np.testing.assert_allclose(line[-1], [500.0 + 200.0 * 50.0 / 140.0, 400.0])  # on along C - B
    one = default_section(heads[:1], np.array([0.0, 0.0]), np.array([600.0, 400.0]))
    np.testing.assert_allclose(one, [[0.0, 350.0], [600.0, 350.0]])
    deep = WellTrack("D", (np.array([[10.0, 20.0, -900.0], [50.0, 60.0, 5.0], [90.0, 60.0, 40.0]]),))
    got = well_heads([deep, vertical_track("V", (7.0, 8.0), (0.0, 30.0))], (0.0, 30.0))
    np.testing.assert_allclose(got, [[50.0, 60.0], [7.0, 8.0]])  # where the path reaches the grid


def test_the_section_figure_says_what_it_shows(box):
    line = np.array([[0.0, 150.0], [600.0, 150.0]])
    wells = (
        vertical_track("NEAR", (250.0, 140.0), (0.0, 60.0)),  # 10 from the line: drawn
        vertical_track("FAR", (250.0, 390.0), (0.0, 60.0)),  # 240 away: not
        WellTrack("H1", (np.array([[420.0, 0.0, 0.0], [420.0, 150.0, 25.0], [580.0, 150.0, 34.0]]),)),
    )
    poro = np.linspace(0.1, 0.3, box.num_cells)
    fig = section_figure(
        box,
        line,
        length_unit="m",
        values=poro,
        quantity=("porosity", "fraction"),
        fault_names=["F-east", "F-north"],
        wells=wells,
        cell_size=100.0,
        title="box",
    )
    ax, bar = fig.axes
    assert ax.get_xlabel() == "distance along the section [m]" and ax.get_ylabel() == "depth [m]"
    assert bar.get_ylabel() == "porosity [fraction]"
    top, bottom = ax.get_ylim()[1], ax.get_ylim()[0]
    assert bottom > top  # depth increases downwards
    texts = {t.get_gid(): [] for t in ax.texts}
    for t in ax.texts:
        texts[t.get_gid()].append(t.get_text())
    assert texts[FAULT_NAME] == ["F-east"]
    assert sorted(texts[WELL_NAME]) == ["H1", "NEAR"]
    # 600 long, 60 deep with the wells and margins: half of 600 / 66 is 4.5 -> 2x
    assert texts[EXAGGERATION] == ["vertical exaggeration 2x"] and ax.get_aspect() == 2.0
    (cells,) = [c for c in ax.collections if type(c).__name__ == "PolyCollection"]
    cut = cut_grid(box, line)
    np.testing.assert_array_equal(cells.get_array(), poro[cut.cells])
    # drawn: the stated exaggeration clear of the axis label and tick labels, the bar's title
    # beyond its ticks
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    (stated,) = [t for t in ax.texts if t.get_gid() == EXAGGERATION]
    box = stated.get_window_extent(renderer)
    others = [ax.xaxis.label, *ax.get_xticklabels()]
    assert not any(box.overlaps(t.get_window_extent(renderer)) for t in others if t.get_text())
    title = bar.yaxis.label.get_window_extent(renderer)
    assert all(title.x0 >= t.get_window_extent(renderer).x1 for t in bar.get_yticklabels() if t.get_text())
    plt.close(fig)


def test_a_section_that_misses_the_grid_is_refused(box):
    with pytest.raises(ValueError, match="cuts no cell"):
        section_figure(
            box,
            np.array([[0.0, 900.0], [600.0, 900.0]]),
            length_unit="m",
            values=np.zeros(72),
            quantity=("x", None),
        )
    plt.close("all")
