"""The 3-D view (gridlib.io.grid_view) checked from the pyvista scene's objects, not pixels: the
colour bar's title, the axes' titles and depth labels, the texts (title, stated vertical
exaggeration), the well labels, one actor and one colour per fault with a legend of names."""

from __future__ import annotations

import numpy as np
import pytest
from matplotlib.colors import to_hex

from gridlib.cornerpoint.between_horizons import FaultTrace, Horizon, horizons_to_grdecl
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.grid_view import grid_scene, render_grid, vertical_exaggeration
from gridlib.io.picture_style import fault_colour
from gridlib.io.quantities import picture_label
from gridlib.io.vtp import write_fault_faces
from gridlib.io.well_tracks import WellTrack, vertical_track
from gridlib.units import FIELD, METRIC

X, Y = np.linspace(0.0, 2000.0, 21), np.linspace(0.0, 1000.0, 11)  # 20 x 10 columns of 100 m


@pytest.fixture(scope="module")
def faulted(tmp_path_factory):
    """A 40 m thick slab at 1000 m cut by a N-S fault F1 (5 m throw) and an E-W fault F2 (3 m),
    1000 to 1048 m deep,
    its fault faces written as the export stage writes them."""
    flat = [Horizon(X, Y, np.full((Y.size, X.size), z)) for z in (1000.0, 1040.0)]
    faults = [
        FaultTrace([(750.0, -10.0), (750.0, 1010.0)], 5.0, "F1"),
        FaultTrace([(-10.0, 450.0), (2010.0, 450.0)], 3.0, "F2"),
    ]
    r = process_grdecl(horizons_to_grdecl(flat, layers=4, faults=faults))
    path = tmp_path_factory.mktemp("view") / "faults.vtp"
    write_fault_faces(path, r.grid, list(r.fault_names))
    return r.grid, list(r.fault_names), path


WELLS = (
    WellTrack("P1", (np.array([[300.0, 200.0, 0.0], [300.0, 200.0, 1010.0], [900.0, 300.0, 1030.0]]),)),
    vertical_track("I1", (1700.0, 800.0), (1000.0, 1040.0)),
)


@pytest.fixture(scope="module")
def scene(faulted):
    grid, _, path = faulted
    poro = np.linspace(0.1, 0.3, grid.num_cells)
    plotter = grid_scene(
        grid,
        poro,
        path,
        scalar="poro",
        title="demo: 800 cells",
        bar_title=picture_label("poro", METRIC),
        length_unit="m",
        wells=WELLS,
    )
    yield plotter
    plotter.close()


def test_colour_bar_is_titled_with_its_unit_above_its_labels(scene):
    assert list(scene.scalar_bars.keys()) == ["porosity [fraction]"]
    bar = scene.scalar_bars["porosity [fraction]"]
    assert bar.GetTitle() == "porosity [fraction]"
    assert bar.GetOrientation() == 1  # vertical: the title above the bar, the labels beside it
    assert bar.GetVerticalTitleSeparation() >= 10 and bar.GetNumberOfLabels() == 5
    assert bar.GetLabelFormat() == "%.3g"


def test_axes_say_east_north_and_depth_in_the_case_unit(scene):
    axes = scene.renderer.cube_axes_actor
    assert (axes.x_title, axes.y_title, axes.z_title) == ("x (east) [m]", "y (north) [m]", "depth [m]")
    z = axes.GetAxisLabels(2)
    # the vertical axis runs from the base (bottom) up to the top: depths, not elevations
    assert [z.GetValue(k) for k in range(z.GetNumberOfValues())] == ["1048", "1024", "1000"]
    x = axes.GetAxisLabels(0)
    assert x.GetValue(0) == "0" and float(x.GetValue(x.GetNumberOfValues() - 1)) <= 2000.0


def test_title_and_the_stated_vertical_exaggeration(scene, faulted):
    assert scene.actors["title"].GetInput() == "demo: 800 cells"
    # 40 m thick (its volume over its plan area) over 2000 m: a quarter of the width is 12.5 times
    # the thickness -> 10x
    assert scene.actors["exaggeration"].GetInput() == "vertical exaggeration 10x"
    zmin, zmax = scene.actors["grid"].GetBounds()[4:]
    assert (zmin, zmax) == pytest.approx((-10480.0, -10000.0))  # 1000 to 1048 m deep (the throws), x 10


def test_wells_are_drawn_and_named(scene):
    labels = scene.actors["well labels-labels"].GetMapper().GetInputAlgorithm()
    names = labels.GetInput().GetPointData().GetAbstractArray("labels")
    assert [names.GetValue(k) for k in range(names.GetNumberOfValues())] == ["P1", "I1"]
    # P1 drawn from 24 m above the grid (half its depth range) down its path; I1 through the slab
    p1 = scene.actors["well P1"].GetMapper().GetInput()
    np.testing.assert_allclose(np.array(p1.GetBounds())[4:], [-10300.0, -9760.0])
    i1 = scene.actors["well I1"].GetMapper().GetInput()
    np.testing.assert_allclose(np.array(i1.GetBounds()), [1700, 1700, 800, 800, -10400, -10000])


def test_one_actor_and_one_colour_per_fault_with_a_legend(scene, faulted):
    grid, names, _ = faulted
    assert names[:2] == ["F1", "F2"]
    colours = {}
    for fid, name in enumerate(names, start=1):
        actor = scene.actors[f"fault {name}"]
        assert actor.GetMapper().GetInput().GetNumberOfCells() == int(np.count_nonzero(grid.faces.tag == fid))
        colours[name] = to_hex(actor.GetProperty().GetColor()).upper()
    # the colours of every picture of the case (picture_style), distinct
    assert (
        colours == {"F1": fault_colour(1).upper(), "F2": fault_colour(2).upper()}
        and len(set(colours.values())) == 2
    )
    legend = scene.legend
    assert [legend.GetEntryString(k) for k in range(legend.GetNumberOfEntries())] == ["F1", "F2"]


def test_render_grid_writes_the_picture(faulted, tmp_path):
    grid, _, path = faulted
    out = tmp_path / "demo.png"
    render_grid(
        out, grid, np.zeros(grid.num_cells), path, scalar="depth", title="demo", window_size=(400, 300)
    )
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and not list(tmp_path.glob("*.tmp*"))


def test_exaggeration_of_flat_and_thick_reservoirs():
    assert vertical_exaggeration(7500.0, 359.0, 1609.0) == 5.0  # SPE9 (ft): layers visible
    assert vertical_exaggeration(7500.0, 359.0, 359.0) == 5.0  # flat, thickness-bound (5.2)
    assert vertical_exaggeration(10_000.0, 20.0, 3000.0) == 2.0  # steep: the depth range bounds it
    assert vertical_exaggeration(1000.0, 600.0, 600.0) == 1.0  # thick: none
    assert picture_label("poro", FIELD) == "porosity [fraction]"
    assert picture_label("depth", FIELD) == "depth [ft]"
