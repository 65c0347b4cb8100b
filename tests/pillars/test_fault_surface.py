"""FaultSurface: planes from a dip (straight and kinked traces, flat and sloping tops) checked
against their plane equations, sticks against dips, side and depth queries against hand values."""

from __future__ import annotations

import numpy as np
import pytest

from gridlib.errors import InputError
from gridlib.pillars.fault_surface import FaultSurface
from gridlib.pillars.fault_traces import FaultTrace, nearest_on_trace

DEPTHS = np.array([800.0, 1000.0, 1234.5, 1600.0, 2500.0])  # above, inside and below the levels


def sloping_top(x, y):
    return 1000.0 + 0.05 * np.asarray(x) + 0.02 * np.asarray(y)


def plane_depth(trace, top_depth, dip_deg, side, segment):
    """The depth of segment ``segment``'s plane as a function of x, y: through the trace segment
    at the top's depths, dipping ``dip_deg`` towards ``side`` in the vertical plane normal to it."""
    v0, v1 = np.asarray(trace[segment], float), np.asarray(trace[segment + 1], float)
    length = np.hypot(*(v1 - v0))
    along = (v1 - v0) / length
    normal = (1 if side == "left" else -1) * np.array([-along[1], along[0]])
    slope = (top_depth[segment + 1] - top_depth[segment]) / length
    gradient = slope * along + np.tan(np.radians(dip_deg)) * normal
    return lambda x, y: top_depth[segment] + gradient[0] * (x - v0[0]) + gradient[1] * (y - v0[1])


def test_straight_trace_under_a_sloping_top_is_one_plane():
    trace = np.array([(100.0, 200.0), (420.0, 400.0), (900.0, 700.0)])  # collinear vertices
    top = sloping_top(*trace.T)
    surface = FaultSurface.from_dip(trace, top, 60.0, "right", name="F1")
    plane = plane_depth(trace, top, 60.0, "right", 0)
    sections = surface.section(DEPTHS)  # (5, 3, 2)
    assert sections.shape == (5, 3, 2)
    residual = plane(sections[..., 0], sections[..., 1]) - DEPTHS[:, None]
    assert np.abs(residual).max() <= 1e-12 * DEPTHS.max()
    # Every stick passes through its trace vertex at the top's depth there.
    at_top = np.stack([surface.section(z)[k] for k, z in enumerate(top)])
    np.testing.assert_allclose(at_top, trace, rtol=0, atol=1e-12 * 1000)
    # Collinear vertices: parallel sticks (a plane, not a twisted strip); drift = cot(60) * normal.
    normal = np.array([500.0, -800.0]) / np.hypot(500.0, 800.0)  # right of the trace (800, 500)
    expected = normal / np.tan(np.radians(60.0))
    np.testing.assert_allclose(surface.drift(1000.0, 2000.0), np.tile(expected, (3, 1)), rtol=1e-12)
    assert not surface.is_vertical and surface.dip_side() == "right"


def test_nearest_on_section_is_nearest_on_trace_of_the_section_at_each_points_depth():
    trace = np.array([(0.0, 0.0), (500.0, 0.0), (800.0, 400.0), (800.0, 900.0), (400.0, 1300.0)])
    surface = FaultSurface.from_dip(trace, sloping_top(*trace.T), 50.0, "left")
    rng = np.random.default_rng(11)
    points = rng.uniform(-300.0, 1400.0, (80, 2))
    z = rng.uniform(900.0, 1300.0, 80)
    for open_start, open_end in ((True, True), (False, True), (False, False)):
        seg, t = surface.nearest_on_section(points[:, 0], points[:, 1], z, open_start, open_end)
        for p, depth, s, u in zip(points, z, seg, t, strict=True):
            want_seg, want_t, _ = nearest_on_trace(p[None], surface.section(depth), open_start, open_end)
            assert (s, u) == pytest.approx((want_seg[0], want_t[0]), rel=1e-9, abs=1e-12)
        assert (t < 0).any() == open_start and (t > 1).any() == open_end


@pytest.mark.parametrize("top_fn", [lambda x, y: np.full(np.shape(x), 1500.0), sloping_top])
def test_kinked_trace_keeps_every_segment_on_its_own_plane(top_fn):
    trace = np.array([(0.0, 0.0), (500.0, 0.0), (800.0, 400.0), (800.0, 900.0), (400.0, 1300.0)])
    top = top_fn(*trace.T)
    surface = FaultSurface.from_dip(trace, top, 50.0, "left")
    t = np.linspace(0.0, 1.0, 7)[:, None]
    for segment in range(len(trace) - 1):
        plane = plane_depth(trace, top, 50.0, "left", segment)
        ends = surface.section(DEPTHS)[:, segment : segment + 2]  # (5, 2, 2)
        # The ruled surface between the two sticks: points along the section at each depth.
        between = (1 - t[None]) * ends[:, :1] + t[None] * ends[:, 1:]  # (5, 7, 2)
        residual = plane(between[..., 0], between[..., 1]) - DEPTHS[:, None]
        assert np.abs(residual).max() <= 1e-12 * DEPTHS.max(), segment


def test_mitre_under_a_flat_top_is_the_bisector_over_the_cosine_of_half_the_turn():
    trace = [(0.0, 0.0), (100.0, 0.0), (100.0, 100.0)]  # a left turn of 90 degrees
    surface = FaultSurface.from_dip(trace, [1000.0] * 3, 45.0, "right")
    # Right of east is south (0, -1); right of north is east (1, 0): mitre (1, -1).
    np.testing.assert_allclose(surface.drift(1000.0, 1100.0)[1], [1.0, -1.0], rtol=1e-15)


def test_dip_90_gives_vertical_sticks_under_the_trace():
    trace = np.array([(0.0, 0.0), (300.0, 50.0), (500.0, 400.0)])
    surface = FaultSurface.from_dip(trace, [1000.0, 1010.0, 990.0], 90, "left")
    assert surface.is_vertical
    np.testing.assert_array_equal(surface.section(DEPTHS), np.broadcast_to(trace, (5, 3, 2)))
    with pytest.raises(InputError, match="vertical, it dips to neither side"):
        surface.dip_side()
    assert np.isnan(surface.depth_at([10.0, 250.0], [5.0, 40.0])).all()


def test_sticks_of_a_dip_fault_give_the_same_surface():
    trace = np.array([(0.0, 0.0), (500.0, 0.0), (800.0, 400.0), (800.0, 900.0)])
    top = sloping_top(*trace.T)
    dip = FaultSurface.from_dip(trace, top, [70.0, 60.0, 55.0, 65.0], "right", name="F2")
    # Sticks from each vertex at its top depth down 700 m: the levels differ from from_dip's.
    sticks = [
        np.column_stack([dip.section(z)[:, k], z]) for k, z in enumerate(np.stack([top, top + 700.0], 1))
    ]
    from_sticks = FaultSurface.from_sticks(sticks, name="F2", source="f2.xyz")
    assert from_sticks.levels.size == 8
    np.testing.assert_allclose(from_sticks.section(DEPTHS), dip.section(DEPTHS), rtol=0, atol=1e-12 * 2500)
    rng = np.random.default_rng(5)
    x, y, z = rng.uniform(-200, 1000, 50), rng.uniform(-200, 1100, 50), rng.uniform(900, 1800, 50)
    np.testing.assert_array_equal(np.sign(from_sticks.side_value(x, y, z)), np.sign(dip.side_value(x, y, z)))
    np.testing.assert_allclose(from_sticks.depth_at(x, y), dip.depth_at(x, y), rtol=1e-12)
    assert from_sticks.dip_side() == dip.dip_side() == "right"
    reversed_sticks = FaultSurface.from_sticks(sticks[::-1])
    assert reversed_sticks.dip_side() == "left"


def test_side_value_by_hand():
    # Walking north along x = 0 at the top (1000 m), dipping 45 degrees east: at 1010 m, x = 10.
    surface = FaultSurface.from_dip([(0.0, 0.0), (0.0, 100.0)], [1000.0, 1000.0], 45.0, "right")
    # cross(strike (0, 100), point - stick 1 at 1010 m): 100 * (10 - x).
    values = surface.side_value([3.0, 12.0, 12.0, 12.0, 9.0], [50.0, 50.0, 150.0, -80.0, 50.0], 1010.0)
    np.testing.assert_allclose(values, [700.0, -200.0, -200.0, -200.0, 100.0], rtol=1e-12)
    # The point (9, 50) is left of the fault at 1010 m, on it at 1009 m and right of it below.
    z = np.array([1005.0, 1009.0, 1020.0])
    np.testing.assert_allclose(surface.side_value(9.0, 50.0, z), [-400.0, 0.0, 1100.0], atol=1e-9)


def test_side_value_follows_nearest_on_trace_at_every_depth():
    trace = np.array([(0.0, 0.0), (500.0, 0.0), (800.0, 400.0), (800.0, 900.0), (400.0, 1300.0)])
    surface = FaultSurface.from_dip(trace, sloping_top(*trace.T), 50.0, "left")
    rng = np.random.default_rng(7)
    points = rng.uniform(-300.0, 1400.0, (400, 2))
    points[:3] = [(900.0, -100.0), (500.0, -50.0), (-100.0, -10.0)]  # at a vertex, beyond the ends
    for z in (900.0, 1300.0):
        section = surface.section(z)
        seg, t, expected = nearest_on_trace(points, section, True, True)
        values = surface.side_value(points[:, 0], points[:, 1], z)
        np.testing.assert_array_equal(np.sign(values), np.sign(expected))
        # Beside a segment, the same cross product; nearest a stick, |segment| * distance.
        inside = ((t > 0) & (t < 1)) | ((seg == 0) & (t < 1)) | ((seg == 3) & (t > 0))
        assert 0 < inside.sum() < 400
        np.testing.assert_allclose(values[inside], expected[inside], rtol=1e-9)
        vertex = np.where(t[~inside] == 0, seg[~inside], seg[~inside] + 1)
        segment = np.hypot(*(section[seg[~inside] + 1] - section[seg[~inside]]).T)
        distance = np.hypot(*(points[~inside] - section[vertex]).T)
        np.testing.assert_allclose(np.abs(values[~inside]), segment * distance, rtol=1e-9)


@pytest.mark.parametrize("top_fn", [lambda x, y: np.full(np.shape(x), 1500.0), sloping_top])
def test_depth_at_lies_on_the_plane_of_the_segment(top_fn):
    trace = np.array([(0.0, 0.0), (500.0, 0.0), (800.0, 400.0)])
    top = top_fn(*trace.T)
    surface = FaultSurface.from_dip(trace, top, 65.0, "right")
    # Points above the first segment's plane far from the kink: its plane gives the depth.
    x, y = np.linspace(-200.0, 350.0, 12), np.linspace(-300.0, -20.0, 12)
    depth = surface.depth_at(x, y)
    expected = plane_depth(trace, top, 65.0, "right", 0)(x, y)
    np.testing.assert_allclose(depth, expected, rtol=1e-12)
    # Anywhere: the point at that depth is on the surface.
    gx, gy = np.meshgrid(np.linspace(-100, 1000, 15), np.linspace(-400, 600, 15))
    gz = surface.depth_at(gx, gy)
    assert np.isfinite(gz).all()
    assert np.abs(surface.side_value(gx, gy, gz)).max() <= 1e-9 * 500.0**2


def test_depth_at_a_listric_surface_from_sticks():
    # Two listric sticks 100 m apart: x = 0 at 1000 m, 100 at 1100 m, 150 at 1300 m (drifting east);
    # below 1300 m the last interval goes on: x = 200 at 1500 m.
    stick = np.array([(0.0, 1000.0), (100.0, 1100.0), (150.0, 1300.0)])
    sticks = [np.column_stack([stick[:, 0], np.full(3, y), stick[:, 1]]) for y in (0.0, 100.0)]
    surface = FaultSurface.from_sticks(sticks)
    np.testing.assert_allclose(
        surface.depth_at([50.0, 125.0, 200.0], [50.0, 20.0, 80.0]), [1050.0, 1200.0, 1500.0]
    )


def test_on_horizon_against_a_plane_horizon():
    trace = np.array([(0.0, 0.0), (500.0, 0.0), (800.0, 400.0)])
    top = sloping_top(*trace.T)
    surface = FaultSurface.from_dip(trace, top, 60.0, "right", name="F1")
    # The top horizon itself gives the trace back (the reference trace at the top).
    xy, z = surface.on_horizon(sloping_top)
    np.testing.assert_allclose(xy, trace, rtol=0, atol=1e-12 * 1000)
    np.testing.assert_allclose(z, top, rtol=1e-13)
    # Another plane, 1200 + 0.1 x - 0.05 y: stick k meets it where z = 1200 + a.(v_k + (z - z0_k) h_k).
    a = np.array([0.1, -0.05])
    drift = surface.drift(1000.0, 2000.0)
    expected_z = (1200.0 + trace @ a - top * (drift @ a)) / (1.0 - drift @ a)
    xy, z = surface.on_horizon(lambda x, y: 1200.0 + a[0] * x + a[1] * y)
    np.testing.assert_allclose(z, expected_z, rtol=1e-13)
    np.testing.assert_allclose(xy, trace + (expected_z - top)[:, None] * drift, rtol=0, atol=1e-9)


def test_on_horizon_curved_and_partly_undefined():
    trace = np.array([(0.0, 0.0), (0.0, 400.0)])
    surface = FaultSurface.from_dip(trace, [1000.0, 1000.0], 45.0, "right", name="F3")

    def dome(x, y):  # undefined west of x = 50: the stick's first level, the secant's start, is NaN
        return np.where(
            np.asarray(x) > 50.0, 1100.0 - 1e-3 * np.asarray(x) ** 2 + 0.1 * np.asarray(y), np.nan
        )

    xy, z = surface.on_horizon(dome)
    np.testing.assert_allclose(z, dome(*xy.T), rtol=1e-12)
    np.testing.assert_allclose(xy[:, 0], z - 1000.0, rtol=1e-12)  # on the stick: x = z - 1000
    with pytest.raises(InputError, match=r"fault 'F3': stick 1 does not meet the horizon"):
        surface.on_horizon(lambda x, y: np.full(np.shape(x), np.nan))


def two_sticks(y0=0.0, y1=100.0):
    return [
        np.array([(0.0, y0, 1000.0), (50.0, y0, 1100.0)]),
        np.array([(0.0, y1, 1000.0), (50.0, y1, 1100.0)]),
    ]


@pytest.mark.parametrize(
    ("sticks", "message"),
    [
        (two_sticks()[:1], "a fault surface needs at least 2 sticks, got 1"),
        ([two_sticks()[0], two_sticks()[1][:1]], "stick 2 has 1 point"),
        (
            [two_sticks()[0], np.array([(0.0, 100.0, 1000.0), (np.nan, 100.0, 1100.0)])],
            "stick 2, point 2: not finite",
        ),
        (
            [two_sticks()[0], np.array([(0.0, 100.0, 1000.0), (9.0, 100.0, 1100.0), (20.0, 100.0, 1050.0)])],
            r"stick 2: depth must increase strictly down a stick .* point 3 \(z=1050\)",
        ),
        ([two_sticks()[0], np.array([[0.0, 100.0]])], r"stick 2: expected a \(k >= 2, 3\) array"),
        (two_sticks(0.0, 0.0), "sticks 1 and 2 coincide at depth 1000 m"),
        (
            # Stick 2 runs from north of stick 1 at 1000 m to south of it at 1100 m.
            [two_sticks()[0], np.array([(0.0, 100.0, 1000.0), (50.0, -60.0, 1100.0)])],
            r"sticks 1 and 2 cross \(they swap order along strike between depths 1050 and 1100 m\)",
        ),
        (
            [*two_sticks(), np.array([(0.0, 50.0, 1000.0), (50.0, 50.0, 1100.0)])],
            "the surface folds back on itself at stick 2 .* at depth 1000 m",
        ),
        (
            [
                *two_sticks(),
                np.array([(100.0, 50.0, 1000.0), (150.0, 50.0, 1100.0)]),
                np.array([(-50.0, 50.0, 1000.0), (0.0, 50.0, 1100.0)]),
            ],
            "the surface between sticks 1 and 2 crosses the surface between sticks 3 and 4 at depth 1000 m",
        ),
    ],
)
def test_malformed_sticks_give_one_error_naming_file_and_stick(sticks, message):
    with pytest.raises(InputError, match=r"^fault 'F9' \(sticks file data/f9\.xyz\): " + message):
        FaultSurface.from_sticks(sticks, name="F9", source="data/f9.xyz")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            ([(0, 0), (0, 1)], [1000, 1000], 0.0, "right"),
            r"dip must be in \(0, 90\] degrees, got 0 at trace vertex 1",
        ),
        (
            ([(0, 0), (0, 1)], [1000, 1000], [60, 95], "right"),
            r"dip must be in \(0, 90\] degrees, got 95 at trace vertex 2",
        ),
        (([(0, 0), (0, 1)], [1000, 1000], 60, "up"), "side must be 'left' or 'right'"),
        (([(0, 0), (0, 0)], [1000, 1000], 60, "left"), "trace vertices 1 and 2 coincide"),
        (([(0, 0), (0, 1)], [1000, np.nan], 60, "left"), "top horizon depth: not finite at trace vertex 2"),
        (
            ([(0, 0), (0, 1)], [1000, 1000, 1000], 60, "left"),
            "top horizon depth: expected a number or one per",
        ),
    ],
)
def test_bad_dip_input(args, message):
    with pytest.raises(InputError, match=r"^fault 'F1': " + message):
        FaultSurface.from_dip(*args, name="F1")


def test_fault_trace_carries_an_optional_surface():
    trace = [(0.0, 0.0), (0.0, 100.0)]
    assert FaultTrace(trace, throw=5.0).surface is None
    surface = FaultSurface.from_dip(trace, [1000.0, 1000.0], 60.0, "right")
    assert FaultTrace(trace, throw=5.0, surface=surface).surface is surface
    with pytest.raises(InputError, match="surface must be a FaultSurface or None"):
        FaultTrace(trace, throw=5.0, surface="F1.xyz")


@pytest.mark.parametrize("budget", [1, 1 << 20])
def test_a_crossing_found_at_its_depth_whatever_the_block_size(monkeypatch, budget):
    from gridlib.pillars import fault_surface

    monkeypatch.setattr(fault_surface, "_PAIR_BUDGET", budget)
    vertical = [
        np.array([(x, y, 1000.0), (x, y, 1100.0)]) for x, y in ((0.0, 0.0), (0.0, 100.0), (100.0, 50.0))
    ]
    # Stick 4 runs west under stick 3: its segment reaches the first one (x = 0) at 1050 m.
    sticks = [*vertical, np.array([(50.0, 50.0, 1000.0), (-50.0, 50.0, 1100.0)])]
    with pytest.raises(InputError, match=r"between sticks 1 and 2 crosses .* sticks 3 and 4 at depth 1050 m"):
        FaultSurface.from_sticks(sticks)


def test_on_horizon_carries_the_horizon_on_to_sticks_beyond_it():
    trace = np.array([(0.0, 0.0), (0.0, 100.0), (0.0, 200.0), (0.0, 300.0)])
    surface = FaultSurface.from_dip(trace, np.full(4, 1000.0), 45.0, "right", name="F4")

    def south(x, y):  # 1100 + 0.1 y, undefined north of y = 150
        y = np.asarray(y)
        return np.where(y <= 150.0, 1100.0 + 0.1 * y, np.nan)

    with pytest.raises(InputError, match="fault 'F4': stick 3 does not meet the horizon"):
        surface.on_horizon(south)
    xy, z = surface.on_horizon(south, missing="nearest")
    np.testing.assert_allclose(z, [1100.0, 1110.0, 1110.0, 1110.0], rtol=1e-13)
    np.testing.assert_allclose(xy, [[100.0, 0.0], [110.0, 100.0], [110.0, 200.0], [110.0, 300.0]], rtol=1e-12)
    with pytest.raises(InputError, match="stick 1 does not meet the horizon"):
        surface.on_horizon(lambda x, y: np.full(np.shape(x), np.nan), missing="nearest")


def test_check_sections_finds_a_dip_fault_folded_by_a_sharp_bend():
    # East, then back west-south-west, dipping into the acute bend: the stick under it drifts
    # 20 m west per metre of depth, and the section folds a few metres below the top.
    trace = [(0.0, 0.0), (100.0, 0.0), (0.0, -10.0)]
    surface = FaultSurface.from_dip(trace, [1000.0] * 3, 45.0, "right", name="F5")
    np.testing.assert_allclose(surface.drift(1000.0, 1100.0)[1], [-(np.sqrt(10100.0) + 100.0) / 10.0, -1.0])
    surface.check_sections(900.0, 1000.0)  # above the top the bend opens outwards: no fold
    with pytest.raises(InputError, match=r"^fault 'F5': .*sticks"):
        surface.check_sections(1000.0, 1100.0)
    gentle = FaultSurface.from_dip([(0.0, 0.0), (100.0, 0.0), (200.0, 30.0)], [1000.0] * 3, 45.0, "left")
    gentle.check_sections(1000.0, 1100.0)
