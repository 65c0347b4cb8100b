"""The plan view (gridlib.io.plan_view) and the top surface it maps (gridlib.io.top_surface),
checked from the matplotlib objects, on small grids built in process: a dipping box with two
named faults and wells, a deck-like box with a hole, a 2-D grid."""

from __future__ import annotations

from dataclasses import replace

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from picture_grids import DIP, faulted_box

import gridlib
from gridlib.geometry import compute_geometry
from gridlib.io import picture_style as style
from gridlib.io.plan_view import FAULT_NAME, FAULTS, WELL_NAME, contour_levels, plan_figure
from gridlib.io.top_surface import fault_traces, top_faces, top_surface
from gridlib.io.well_tracks import WellTrack, vertical_track


@pytest.fixture(scope="module")
def box():
    grid = faulted_box()
    return grid, compute_geometry(grid)


def _texts(fig, gid=None) -> list[str]:
    return [t.get_text() for ax in fig.axes for t in ax.texts if gid is None or t.get_gid() == gid]


def test_the_top_of_a_box_is_its_top_layer_and_its_traces_the_faults(box):
    grid, geo = box
    top = top_surface(grid, geo)
    assert top.faces.size == 6 * 4
    assert np.all(top.cells < 6 * 4)  # the top layer's cells
    assert top.plan_area() == pytest.approx(600.0 * 400.0, rel=1e-12)
    assert top.cell_size() == pytest.approx(100.0, rel=1e-12)
    np.testing.assert_allclose(top.points[:, 2], DIP * top.points[:, 0], atol=1e-9)
    assert top.depth_range == pytest.approx((0.0, DIP * 600.0))
    segments, ids = fault_traces(grid, top)
    length = np.hypot(*(segments[:, 1] - segments[:, 0]).T)
    assert length[ids == 1].sum() == pytest.approx(400.0) and length[ids == 2].sum() == pytest.approx(600.0)
    np.testing.assert_allclose(segments[ids == 1][:, :, 0], 300.0)
    np.testing.assert_allclose(segments[ids == 2][:, :, 1], 200.0)


def test_a_hole_in_the_top_layer_is_covered_by_the_cell_below():
    """A deck's inactive top cell: its column's top is the cell under it, once (not the floor of
    the hole and another face above)."""
    grid = gridlib.remove_cells(gridlib.cart_grid((3, 3, 3), (3.0, 3.0, 3.0)), [4, 4 + 9])
    geo = compute_geometry(grid)
    faces, cells = top_faces(grid, geo)
    assert faces.size == 9
    depth = geo.face_centroids[faces, 2]
    kmap = grid.cells.index_map[cells]
    assert sorted(kmap.tolist()) == [0, 1, 2, 3, 5, 6, 7, 8, 22]  # column 4's top is in layer 2
    assert depth[kmap == 22] == pytest.approx(2.0) and np.all(depth[kmap != 22] == 0.0)
    # without logical indices or layers: every boundary face facing up, the hole's floor too
    bare = replace(grid, cells=replace(grid.cells, face_tag=None, index_map=None))
    assert top_faces(bare, geo)[0].size == 9


def test_the_plan_of_a_dipping_faulted_box_says_what_it_shows(box):
    grid, geo = box
    wells = (
        vertical_track("INJ", (150.0, 100.0), (0.0, 60.0)),
        WellTrack("P1H", (np.array([[450.0, 350.0, -500.0], [450.0, 350.0, 20.0], [550.0, 250.0, 40.0]]),)),
    )
    fig = plan_figure(
        grid, geo, length_unit="ft", fault_names=["F-east", "F-north"], wells=wells, title="box"
    )
    ax, bar = fig.axes
    assert (ax.get_xlabel(), ax.get_ylabel()) == ("x [ft]", "y [ft]")
    assert bar.get_ylabel() == "top depth [ft]"
    assert ax.get_aspect() == 1.0
    assert sorted(_texts(fig, FAULT_NAME)) == ["F-east", "F-north"]
    assert sorted(_texts(fig, WELL_NAME)) == ["INJ", "P1H"]
    (scale,) = style.named(ax, style.SCALE_BAR)
    assert (
        scale.txt_label.get_text() == "100 ft"
    )  # a quarter of 648 ft of axes, rounded down to 1, 2, 5 x 10^k
    (north,) = style.named(ax, style.NORTH_ARROW)
    assert north.get_text() == "N" and north.xy[1] > north.xyann[1]  # the arrow points up: north
    (faults,) = style.named(ax, FAULTS)
    colours = faults.get_colors()
    first = style.fault_colours(np.array([1]))[0]
    second = style.fault_colours(np.array([2]))[0]
    assert {tuple(c) for c in colours} == {tuple(first), tuple(second)} and tuple(first) != tuple(second)
    # the contour lines: round depths inside the top's depth range, labelled
    lines = [c for c in ax.collections if type(c).__name__ == "TriContourSet" and c.filled is False]
    (contours,) = lines
    assert list(contours.levels) == list(contour_levels(0.0, 30.0)) == [2.5 * k for k in range(1, 12)]
    assert all(0.0 < level < 30.0 for level in contours.levels)
    assert len(contours.labelTexts) >= len(contours.levels)
    plt.close(fig)


def test_the_plan_of_a_2d_grid_colours_its_cells():
    grid = gridlib.cart_grid((4, 3), (40.0, 30.0))
    geo = compute_geometry(grid)
    values = np.arange(12.0)
    fig = plan_figure(grid, geo, length_unit="m", values=values, quantity=("porosity", "fraction"))
    ax, bar = fig.axes
    assert bar.get_ylabel() == "porosity [fraction]"
    (cells,) = [c for c in ax.collections if type(c).__name__ == "PolyCollection"]
    np.testing.assert_array_equal(cells.get_array(), values)
    assert len(cells.get_paths()) == 12
    assert style.named(ax, style.SCALE_BAR) and style.named(ax, style.NORTH_ARROW)
    plt.close(fig)


def test_one_colour_per_fault_id_the_same_everywhere():
    ids = np.arange(1, len(style.FAULT_PALETTE) + 1)
    rgba = style.fault_colours(ids)
    assert len({tuple(c) for c in rgba}) == ids.size  # every fault of a case its own colour
    assert [matplotlib.colors.to_hex(c) for c in rgba] == [style.fault_colour(k).lower() for k in ids]
    assert style.nice_length(1.0) == 1.0 and style.nice_length(9.99) == 5.0
    with pytest.raises(ValueError, match="positive"):
        style.nice_length(0.0)


def test_colour_bar_titles_and_labels_do_not_overlap_their_ticks(box):
    """Drawn (Agg), the colour bar's title lies beyond its tick labels, and the scale bar, the
    north arrow and the map's tick labels keep apart: extents from the renderer, not pixels."""
    grid, geo = box
    with style.picture_style():
        fig = plan_figure(grid, geo, length_unit="m", fault_names=["F-east", "F-north"], title="box")
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    ax, bar = fig.axes
    title = bar.yaxis.label.get_window_extent(renderer)
    ticks = [t.get_window_extent(renderer) for t in bar.yaxis.get_ticklabels() if t.get_text()]
    assert ticks and all(not title.overlaps(t) and title.x0 >= t.x1 for t in ticks)
    (north,) = style.named(ax, style.NORTH_ARROW)
    (scale,) = style.named(ax, style.SCALE_BAR)
    assert not north.get_window_extent(renderer).overlaps(scale.get_window_extent(renderer))
    inside = ax.get_window_extent(renderer)
    assert inside.contains(*scale.get_window_extent(renderer).p0)
    plt.close(fig)
