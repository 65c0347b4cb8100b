"""Fault sites (gridlib.voronoi.fault_sites) of a straight fault, placed by hand: unit steps,
circles of 0.6 m, mirrored pairs where consecutive circles meet, a tip site beyond each end."""

import numpy as np
import pytest

from gridlib.voronoi.domain import Domain, rectangle
from gridlib.voronoi.fault_layout import layout
from gridlib.voronoi.fault_network import Fault
from gridlib.voronoi.fault_sites import FaultSites, build_sites, circle_violations


@pytest.fixture
def straight():
    dom = Domain(rectangle(0.0, 0.0, 10.0, 10.0))
    lay = layout([Fault([(2, 5), (8, 5)], spacing=1.0)], dom, lambda p: np.full(len(p), 1.0), 0.6, [])
    return dom, build_sites(lay)


def test_centres_are_the_trace_ends_then_every_metre_between(straight):
    dom, fs = straight
    np.testing.assert_array_equal(
        fs.centres + dom.origin,
        [[2.0, 5.0], [8.0, 5.0], [3.0, 5.0], [4.0, 5.0], [5.0, 5.0], [6.0, 5.0], [7.0, 5.0]],
    )
    np.testing.assert_array_equal(fs.radii, np.full(7, 0.6))  # ratio 0.6 x the mean of unit steps
    np.testing.assert_array_equal(fs.centre_step, np.ones(7))
    np.testing.assert_array_equal(fs.centre_fault, np.ones(7, dtype=np.int64))


def test_sites_are_mirrored_pairs_at_the_step_midpoints_and_two_tips(straight):
    dom, fs = straight
    h = np.sqrt(0.6**2 - 0.5**2)  # where two circles of 0.6 m, 1 m apart, meet
    x = np.arange(2.5, 8.0)
    want = np.concatenate(
        [
            np.column_stack([x, 5.0 + np.full(6, h)]),
            np.column_stack([x, 5.0 - np.full(6, h)]),
            [[1.4, 5.0], [8.6, 5.0]],
        ]
    )
    np.testing.assert_allclose(fs.sites + dom.origin, want, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(fs.pairs, np.column_stack([np.arange(6), np.arange(6, 12)]))
    np.testing.assert_array_equal(fs.pair_fault, np.ones(6, dtype=np.int64))
    np.testing.assert_array_equal(fs.is_tip, [False] * 12 + [True, True])
    np.testing.assert_array_equal(fs.site_step, np.ones(14))
    np.testing.assert_array_equal(fs.site_wedge, np.full(14, -1))
    # a site's foot is the nearest point of its step: the step's midpoint; a tip's, its end
    np.testing.assert_allclose(
        fs.site_foot + dom.origin,
        np.concatenate([np.column_stack([x, np.full(6, 5.0)])] * 2 + [[[2.0, 5.0], [8.0, 5.0]]]),
        rtol=0,
        atol=1e-12,
    )
    assert fs.problems == [] and fs.wedges == []


def test_the_steps_are_the_trace_between_consecutive_centres(straight):
    dom, fs = straight
    np.testing.assert_array_equal(
        fs.trace_a + dom.origin, [[2.0, 5.0], [3.0, 5.0], [4.0, 5.0], [5.0, 5.0], [6.0, 5.0], [7.0, 5.0]]
    )
    np.testing.assert_array_equal(
        fs.trace_b + dom.origin, [[3.0, 5.0], [4.0, 5.0], [5.0, 5.0], [6.0, 5.0], [7.0, 5.0], [8.0, 5.0]]
    )


def test_circle_violations_are_sites_strictly_inside_a_circle(straight):
    dom, fs = straight
    points = dom.to_local(np.array([[2.0, 5.5], [2.0, 5.6], [5.0, 7.0], [5.5, 5.0]]))
    c, s = circle_violations(fs, points)
    # (2, 5.5) is 0.5 m from centre 0; (2, 5.6) lies on its circle; (5.5, 5) is inside the circles of 5 and 6
    order = np.lexsort((c, s))
    np.testing.assert_array_equal(c[order], [0, 4, 5])
    np.testing.assert_array_equal(s[order], [0, 3, 3])


def test_no_faults_no_sites():
    fs = FaultSites.empty()
    assert fs.sites.shape == (0, 2) and fs.pairs.shape == (0, 2) and fs.centres.shape == (0, 2)
    c, s = circle_violations(fs, np.zeros((3, 2)))
    assert c.size == 0 and s.size == 0
