"""Minimum curvature against closed forms: exact on circular arcs (a constant build, a constant
turn in the horizontal plane), second order on a helix; straight holes; and every check."""

from __future__ import annotations

import math

import numpy as np
import pytest

from gridlib.errors import InputError
from gridlib.wells.survey import direction, minimum_curvature, ratio_factor

HEAD = np.array([100.0, 200.0, 1000.0])


def build_arc(md, start_inclination, build, azimuth):
    """The exact hole built at ``build`` degrees per unit MD at a fixed ``azimuth`` from HEAD: a
    circular arc of radius R = 180 / (pi build) in the vertical plane of the azimuth."""
    radius = 180.0 / (math.pi * build)
    i0, turned = np.deg2rad(start_inclination), np.deg2rad(build * md)
    # cos i0 - cos i and sin i - sin i0 as products, exact to rounding also for tiny builds
    mid, half = i0 + turned / 2, np.sin(turned / 2)
    across = 2 * radius * np.sin(mid) * half  # horizontal, along the azimuth
    down = 2 * radius * np.cos(mid) * half
    a = np.deg2rad(azimuth)
    return HEAD + np.stack([across * np.sin(a), across * np.cos(a), down], axis=1)


def survey(md, inclination, azimuth):
    md = np.asarray(md, dtype=float)
    return np.stack([md, np.broadcast_to(inclination, md.shape), np.broadcast_to(azimuth, md.shape)], axis=1)


def assert_displacements(got, want, rtol=1e-9):
    """Displacements from HEAD equal to ``rtol`` of the largest one."""
    scale = np.abs(want - HEAD).max()
    np.testing.assert_allclose(got - HEAD, want - HEAD, rtol=0, atol=rtol * scale)


@pytest.mark.parametrize(
    ("start", "build", "azimuth"), [(0.0, 0.1, 30.0), (10.0, 0.1, 200.0), (60.0, 0.05, 315.0)]
)
def test_constant_build_is_the_circular_arc(start, build, azimuth):
    md = np.arange(0.0, 1200.1, 30.0)  # to 120, 130 and 120 degrees: past horizontal, turning up
    path = minimum_curvature(HEAD, survey(md, start + build * md, azimuth), name="B")
    assert path.md.tolist() == md.tolist() and path.name == "B"
    assert path.xyz[0].tolist() == HEAD.tolist()
    assert_displacements(path.xyz, build_arc(md, start, build, azimuth))
    # the points along the arcs (step 7: 5 parts of 6 each) are on the arc too
    dense = minimum_curvature(HEAD, survey(md, start + build * md, azimuth), step=7.0)
    assert dense.md.size == 5 * 40 + 1
    np.testing.assert_allclose(np.diff(dense.md), 6.0, rtol=1e-12)
    assert_displacements(dense.xyz, build_arc(dense.md, start, build, azimuth))
    assert np.array_equal(dense.xyz[::5], path.xyz)  # the stations are the same bits


def test_constant_turn_at_horizontal_is_the_circle():
    """At inclination 90 a constant turn is a circle in the horizontal plane (exact); the depth
    stays exactly the head's."""
    turn, md = 0.25, np.arange(0.0, 1000.1, 50.0)  # 250 degrees of a circle of radius 229 m
    path = minimum_curvature(HEAD, survey(md, 90.0, 45.0 + turn * md))
    radius, a0, a = 180.0 / (math.pi * turn), np.deg2rad(45.0), np.deg2rad(45.0 + turn * md)
    want = HEAD + np.stack([radius * (np.cos(a0) - np.cos(a)), radius * (np.sin(a) - np.sin(a0)), 0 * md], 1)
    assert_displacements(path.xyz, want)
    assert (path.xyz[:, 2] == HEAD[2]).all()


def test_helix_is_approximated_to_second_order():
    """A constant turn at inclination 45 is a helix, not an arc: minimum curvature's arcs lie
    below it (each interval's depth change is dMD cos(I) RF >= the helix's dMD cos(I)) and the
    error at the end falls four-fold when the stations are twice as dense."""
    inc, turn = 45.0, 0.2
    errors = []
    for spacing in (60.0, 30.0, 15.0):
        md = np.arange(0.0, 600.1, spacing)
        path = minimum_curvature(HEAD, survey(md, inc, turn * md))
        k, a = math.radians(turn), np.deg2rad(turn * md)
        s = math.sin(math.radians(inc))
        helix = HEAD + np.stack(
            [s * (1 - np.cos(a)) / k, s * np.sin(a) / k, md * math.cos(math.radians(inc))], 1
        )
        error = path.xyz - helix
        assert (error[1:, 2] > 0).all()
        errors.append(np.abs(error[-1]).max())
        beta = math.acos(np.clip(np.dot(*direction([inc, inc], [0.0, turn * spacing])), -1, 1))
        rf = math.tan(beta / 2) / (beta / 2)
        np.testing.assert_allclose(
            np.diff(path.xyz[:, 2]), spacing * math.cos(math.radians(inc)) * rf, rtol=1e-9
        )
    np.testing.assert_allclose(np.array(errors[:-1]) / errors[1:], 4.0, rtol=0.01)


def test_straight_holes():
    vertical = minimum_curvature(HEAD, survey([150.0, 250.0, 400.0], 0.0, 77.0))
    assert vertical.xyz.tolist() == [[100, 200, 1000], [100, 200, 1100], [100, 200, 1250]]
    assert vertical.md.tolist() == [150.0, 250.0, 400.0]
    inclined = minimum_curvature(HEAD, survey([0.0, 100.0, 300.0], 30.0, 90.0))  # east, 30 off vertical
    c = math.cos(math.radians(30.0))
    np.testing.assert_allclose(
        inclined.xyz - HEAD, [[0, 0, 0], [50, 0, 100 * c], [150, 0, 300 * c]], rtol=0, atol=1e-12
    )
    assert (inclined.xyz[:, 1] == 200.0).all()  # due east exactly
    north = minimum_curvature(HEAD, survey([0.0, 10.0], 90.0, 0.0))  # horizontal, due north
    assert north.xyz.tolist() == [[100, 200, 1000], [100, 210, 1000]]


def test_tiny_doglegs_and_the_ratio_factor():
    """RF = tan(h)/h by its series below h = 1e-3 and directly above: continuous there, 1 at
    0; a dogleg of 1e-9 degrees over 100 m is the arc to 1e-12."""
    h = np.array([0.0, 1e-8, 1e-5, 1e-3 - 1e-12, 1e-3, 0.1, 1.5])
    want = np.array([1.0] + [math.tan(v) / v for v in h[1:]])
    np.testing.assert_allclose(ratio_factor(h, np.tan(h)), want, rtol=2e-16)
    md, end = np.array([0.0, 100.0]), 5.0 + 1e-9
    path = minimum_curvature(HEAD, survey(md, [5.0, end], 10.0))
    assert_displacements(path.xyz, build_arc(md, 5.0, (end - 5.0) / 100.0, 10.0), rtol=1e-12)


@pytest.mark.parametrize(
    ("stations", "message"),
    [
        ([(0, 0, 0)], r"stations \(md, inclination, azimuth\): expected an \(n >= 2, 3\) array"),
        ([(0, 0, 0), (10, np.nan, 0)], r"stations \(md, inclination, azimuth\): station 1 is not finite"),
        ([(0, 0, 0), (10, 5, 0), (10, 6, 0)], r"station 2: md 10 does not exceed the station before it"),
        ([(0, 0, 0), (10, 180.5, 0)], r"station 1: inclination 180.5 is outside \[0, 180\] degrees"),
        ([(0, 0, 0), (10, -1, 0)], r"station 1: inclination -1 is outside \[0, 180\] degrees"),
        ([(0, 0, 0), (10, 90, 0), (20, 90, 180)], "stations 1 and 2 point in opposite directions"),
    ],
)
def test_every_check_names_the_station(stations, message):
    with pytest.raises(InputError, match=f"^survey of well 'P2': {message}"):
        minimum_curvature(HEAD, stations, name="P2")


def test_head_step_and_source_checks():
    with pytest.raises(
        InputError, match=r"^x.yaml: wells\[2\].survey: head \(x, y, depth\): point 0 is not finite"
    ):
        minimum_curvature((0, np.inf, 0), [(0, 0, 0), (10, 0, 0)], source="x.yaml: wells[2].survey")
    with pytest.raises(InputError, match=r"^survey: step -1 must be a number > 0"):
        minimum_curvature(HEAD, [(0, 0, 0), (10, 0, 0)], step=-1)


def test_azimuths_beyond_a_turn_are_the_same_direction():
    """An azimuth of 450 or -270 degrees is due east; one of 1e20 degrees is a direction, not a
    cast warning: angles are reduced modulo 360 (exactly) before the quarter turns."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        d = direction([90.0, 90.0, 90.0], [450.0, -270.0, 1e20])
    assert d[0].tolist() == [1.0, 0.0, 0.0] and d[1].tolist() == [1.0, 0.0, 0.0]
    assert d[2].tolist() == direction(90.0, math.fmod(1e20, 360.0)).tolist()
