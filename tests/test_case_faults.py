"""A case's faults: vertical ones as ever, dips and sticks as fault surfaces placed at the top
horizon, and every inconsistent fault key refused when the case is loaded (cheap, in process)."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from gridlib.case.faults import fault_traces
from gridlib.config import load_case
from gridlib.errors import InputError
from gridlib.pillars.horizon_maps import Horizon, depth_function

STICKS = Path(__file__).parent / "data" / "sticks"
CASE = """name: c
horizons:
  lattice: {{x: {{start: {x0}, stop: {x1}, num: 11}}, y: {{start: {y0}, stop: {y1}, num: 9}}}}
  surfaces:
    - {{name: top, plane: {{depth: 1000}}}}
    - {{name: base, plane: {{depth: 1100}}}}
faults:
{faults}
grid: {{type: cornerpoint, dims: [10, 8], layers: 2{grid}}}
"""


def load(tmp_path: Path, *faults: str, grid: str = "", area=(0, 0, 1000, 800)):
    x0, y0, x1, y1 = area
    text = CASE.format(faults="\n".join(f"  - {f}" for f in faults), grid=grid, x0=x0, y0=y0, x1=x1, y1=y1)
    path = tmp_path / "c.yaml"
    path.write_text(text)
    return load_case(path)


def sloping(x, y):  # the top horizon: 1000 m at the origin, deepening east and north
    return 1000.0 + 0.05 * np.asarray(x) + 0.02 * np.asarray(y)


def test_vertical_faults_are_their_traces_as_ever(tmp_path):
    case = load(
        tmp_path,
        "{name: F1, trace: [[300, -100], [400, 900]], throw: 5}",
        "{name: F2, trace: [[0, 300], [1100, 400]], dip: 90, side: left}",
    )
    f1, f2 = fault_traces(case)  # no top needed
    assert case.data["faults"][0]["side"] == "right" and case.data["faults"][0]["dip"] == 90
    assert f1.surface is None and f2.surface is None
    np.testing.assert_array_equal(f1.points, [[300, -100], [400, 900]])
    assert (f1.throw, f1.side, f2.side) == (5.0, "right", "left")


def test_a_dip_fault_is_the_plane_through_its_trace_on_the_top(tmp_path):
    case = load(tmp_path, "{name: F1, trace: [[300, 100], [400, 700]], dip: 60, throw: 5}")
    with pytest.raises(InputError, match=r"c\.yaml: faults\[0\]: fault 'F1' dips: .* needs \(top=\)"):
        fault_traces(case)
    (f1,) = fault_traces(case, top=sloping)
    np.testing.assert_array_equal(f1.points, [[300, 100], [400, 700]])
    surface = f1.surface
    assert surface.name == "F1" and surface.dip_side() == "right"
    # Each stick leaves its vertex at the top's depth there.
    for k, v in enumerate(f1.points):
        np.testing.assert_allclose(surface.section(sloping(*v))[k], v, rtol=0, atol=1e-9)
    # The plane: through the trace at the top's depths, dipping 60 degrees in the plane normal to it.
    along = np.array([100.0, 600.0]) / np.hypot(100.0, 600.0)
    normal = np.array([along[1], -along[0]])  # right of the trace
    slope = (sloping(400, 700) - sloping(300, 100)) / np.hypot(100.0, 600.0)
    gradient = slope * along + np.tan(np.radians(60.0)) * normal
    z = np.array([900.0, 1050.0, 1300.0])
    xy = surface.section(z)
    plane = sloping(300, 100) + (xy - [300.0, 100.0]) @ gradient
    np.testing.assert_allclose(plane, np.broadcast_to(z[:, None], plane.shape), rtol=1e-12)


def test_a_dip_varying_along_the_trace(tmp_path):
    case = load(
        tmp_path, "{name: F1, trace: [[300, 100], [350, 400], [400, 700]], dip: {start: 80, end: 50}}"
    )
    (f1,) = fault_traces(case, top=lambda x, y: np.full(np.shape(x), 1000.0))
    drift = np.hypot(*f1.surface.drift(1000.0, 1100.0).T)
    np.testing.assert_allclose(drift[[0, 2]], 1.0 / np.tan(np.radians([80.0, 50.0])), rtol=1e-12)


def test_a_trace_beyond_the_top_gets_sticks_where_it_leaves_it(tmp_path):
    case = load(tmp_path, "{name: F1, trace: [[-100, 0], [1100, 800]], dip: 45, side: left}")

    def top(x, y):  # defined on the lattice only
        x, y = np.asarray(x), np.asarray(y)
        return np.where((x >= 0) & (x <= 1000) & (y >= 0) & (y <= 800), sloping(x, y), np.nan)

    (f1,) = fault_traces(case, top=top)
    np.testing.assert_array_equal(f1.points, [[-100, 0], [1100, 800]])  # the case's trace
    surface = f1.surface
    tops = surface.section(surface.levels[0])
    assert tops.shape == (4, 2)
    # Sticks added where the trace enters (x = 0) and leaves (x = 1000) the area, at the top's depth.
    edges = np.array([[0.0, 800.0 / 12.0], [1000.0, 800.0 * 11 / 12]])
    for k, edge in zip((1, 2), edges, strict=True):
        np.testing.assert_allclose(surface.section(sloping(*edge))[k], edge, atol=1e-9)
    # The outer vertices take the top extrapolated linearly along the trace: on this planar
    # top, its own depth there.
    np.testing.assert_allclose(surface.section(sloping(-100.0, 0.0))[0], [-100.0, 0.0], atol=1e-9)
    np.testing.assert_allclose(surface.section(sloping(1100.0, 800.0))[3], [1100.0, 800.0], atol=1e-9)
    # So a straight trace on a planar top is one plane, within the area and beyond it: through
    # the trace at the top's depths, dipping 45 degrees (left) in the plane normal to the trace.
    along = np.array([1200.0, 800.0]) / np.hypot(1200.0, 800.0)
    normal = np.array([-along[1], along[0]])  # left of the trace
    slope = (sloping(1100, 800) - sloping(-100, 0)) / np.hypot(1200.0, 800.0)
    gradient = slope * along + np.tan(np.radians(45.0)) * normal
    z = np.linspace(900.0, 1300.0, 9)
    plane = sloping(-100, 0) + (surface.section(z) - [-100.0, 0.0]) @ gradient
    np.testing.assert_allclose(plane, np.broadcast_to(z[:, None], plane.shape), rtol=1e-12, atol=0)
    # It cuts the top on the trace (mid-way along it, at a point of the top horizon, side value 0).
    mid = np.array([500.0, 400.0])
    assert abs(surface.side_value(*mid, sloping(*mid))) <= 1e-9 * 1000**2


def test_a_sticks_fault_meets_the_top_where_its_trace_is(tmp_path):
    shutil.copy(STICKS / "f1_sticks.pol", tmp_path)
    area = (455800, 5929800, 456800, 5931800)
    case = load(tmp_path, "{name: F1, sticks: f1_sticks.pol, throw: {start: 0, end: 10}}", area=area)
    assert case.data["faults"][0]["sticks_format"] == "auto" and "side" not in case.data["faults"][0]
    with pytest.raises(InputError, match=r"faults\[0\]: fault 'F1' is given by sticks: .* \(top=\)"):
        fault_traces(case)
    top = lambda x, y: 1700.0 + 0.1 * (np.asarray(x) - 456000.0)  # noqa: E731
    (f1,) = fault_traces(case, top=top)
    assert f1.side == "right" and f1.surface.source.endswith("f1_sticks.pol")
    z = f1.surface.on_horizon(top)[1]
    np.testing.assert_allclose(top(*f1.points.T), z, rtol=1e-12)
    for k, point in enumerate(f1.points):  # each on its stick
        np.testing.assert_allclose(f1.surface.section(z[k])[k], point, rtol=1e-12)


def test_geometry_keys_default_and_are_checked(tmp_path):
    case = load(
        tmp_path,
        "{name: F1, trace: [[300, -100], [400, 900]]}",
        grid=", fault_geometry: pillars, relax_distance: 300",
    )
    assert (case.data["grid"]["fault_geometry"], case.data["grid"]["relax_distance"]) == ("pillars", 300)
    assert (
        load(tmp_path, "{name: F1, trace: [[300, -100], [400, 900]]}").data["grid"]["fault_geometry"]
        == "stair_steps"
    )


@pytest.mark.parametrize(
    ("fault", "grid", "message"),
    [
        ("{name: F, trace: [[300, -100], [400, 900]], dip: 0}", "", r"faults\[0\]"),
        ("{name: F, trace: [[300, -100], [400, 900]], dip: {start: 60, end: 91}}", "", r"faults\[0\]"),
        (
            "{name: F, trace: [[300, -100], [400, 900]], sticks: s.pol}",
            "",
            r"faults\[0\]: give exactly one of trace, sticks \(got trace, sticks\)",
        ),
        ("{name: F, throw: 3}", "", r"faults\[0\]: give exactly one of trace, sticks \(got none\)"),
        (
            "{name: F, trace: [[300, -100], [400, 900]], sticks_format: rms}",
            "",
            r"faults\[0\]\.sticks_format: fault 'F' is given by its trace, not by sticks",
        ),
        (
            "{name: F, sticks: s.pol, dip: 60}",
            "",
            r"faults\[0\]\.dip: fault 'F' is given by sticks, which give its dip",
        ),
        (
            "{name: F, sticks: none.pol}",
            "",
            r"faults\[0\]\.sticks: file 'none.pol' not found \(looked for .*none\.pol\)",
        ),
        (
            "{name: F, sticks: s.pol, side: left}",
            "",
            r"faults\[0\]\.side: fault 'F' dips to the right of its sticks .* not the left",
        ),
        (
            "{name: F, sticks: crossing.pol}",
            "",
            r"faults\[0\]\.sticks: fault 'F' \(sticks file .*crossing\.pol\): sticks 1 and 2 cross",
        ),
        (
            "{name: F, sticks: vertical.pol}",
            "",
            r"faults\[0\]\.side: fault 'F': its sticks are vertical; give",
        ),
        (
            "{name: F, sticks: far.pol}",
            "",
            r"faults\[0\]\.sticks: fault 'F' lies entirely outside the domain",
        ),
        ("{name: F, trace: [[300, -100], [400, 900]]}", ", fault_geometry: curved", r"grid"),
        ("{name: F, trace: [[300, -100], [400, 900]]}", ", relax_distance: 0", r"grid"),
    ],
)
def test_inconsistent_fault_keys_are_refused_on_load(tmp_path, fault, grid, message):
    (tmp_path / "s.pol").write_text("300 0 1000\n310 0 1100\n999 999 999\n300 800 1000\n310 800 1100\n")
    (tmp_path / "crossing.pol").write_text(
        "300 0 1000\n310 0 1100\n999 999 999\n300 800 1000\n310 -80 1100\n"
    )
    (tmp_path / "vertical.pol").write_text(
        "300 0 1000\n300 0 1100\n999 999 999\n300 800 1000\n300 800 1100\n"
    )
    (tmp_path / "far.pol").write_text("3000 0 1000\n3010 0 1100\n999 999 999\n3000 800 1000\n3010 800 1100\n")
    with pytest.raises(InputError, match=r"c\.yaml: " + message):
        load(tmp_path, fault, grid=grid)


def test_a_vertical_sticks_fault_with_a_side(tmp_path):
    (tmp_path / "v.pol").write_text("300 0 1000\n300 0 1100\n999 999 999\n300 800 1000\n300 800 1100\n")
    case = load(tmp_path, "{name: F, sticks: v.pol, side: left, throw: 2}")
    (f,) = fault_traces(case)  # a vertical fault: no top needed, no surface
    assert f.side == "left" and f.surface is None
    np.testing.assert_array_equal(f.points, [[300, 0], [300, 800]])


def test_sticks_beyond_the_top_take_the_depth_of_the_nearest_that_meets_it(tmp_path):
    shutil.copy(STICKS / "f1_sticks.xyz", tmp_path)
    area = (455800, 5929800, 456800, 5931800)
    case = load(tmp_path, "{name: F1, sticks: f1_sticks.xyz}", area=area)

    def top(x, y):  # 1700 m, undefined north of y = 5931200 (the last stick is beyond it)
        return np.where(np.asarray(y) <= 5931200.0, np.full(np.shape(x), 1700.0), np.nan)

    (f1,) = fault_traces(case, top=top)
    surface = f1.surface
    np.testing.assert_allclose(f1.points, surface.section(1700.0), rtol=1e-12)


def test_sticks_beyond_the_horizons_lattice_take_the_nearest_depth_that_meets_it(tmp_path):
    """A stick south of the lattice (y = -50, the lattice from 0) and one north of it (y = 850),
    against the case's own top: its lattice horizon as the case builds it (depth_function)."""
    (tmp_path / "f.xyz").write_text(
        "".join(
            f"{x0 + dx} {y} {z} {stick}\n"
            for stick, (x0, y) in enumerate([(300.0, -50.0), (320.0, 400.0), (340.0, 850.0)], 1)
            for dx, z in ((0.0, 900.0), (300.0, 1200.0))  # 45 degrees east
        )
    )
    case = load(tmp_path, "{name: F1, sticks: f.xyz, throw: 5}")
    x, y = np.linspace(0.0, 1000.0, 11), np.linspace(0.0, 800.0, 9)
    top = depth_function(Horizon(x, y, sloping(*np.meshgrid(x, y))))
    (f1,) = fault_traces(case, top=top)
    assert f1.side == "right"
    # The middle stick meets the top; the outer two take its depth, on their own sticks.
    z = float(top(*f1.points[1:2].T)[0])
    np.testing.assert_allclose(f1.surface.section(z)[1], f1.points[1], rtol=1e-12)
    np.testing.assert_allclose(f1.points, f1.surface.section(z), rtol=1e-12)
    assert np.isnan(top(*f1.points[[0, 2]].T)).all()
