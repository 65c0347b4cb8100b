"""The fault network (gridlib.voronoi.fault_network, fault_layout) on traces whose graph is known by hand."""

import numpy as np
import pytest

from gridlib.errors import GridError
from gridlib.voronoi.domain import Domain, rectangle
from gridlib.voronoi.fault_layout import layout, ring_room
from gridlib.voronoi.fault_network import Fault, build_network


def one(p):
    return np.full(len(p), 1.0)


@pytest.fixture
def square():
    return Domain(rectangle(0.0, 0.0, 10.0, 10.0))


def edges_xy(net, dom):
    """The network's edges as sorted ((x, y), (x, y), fault) tuples in the caller's frame."""
    xy = net.nodes + dom.origin
    out = []
    for a, b, f in zip(net.edge_a.tolist(), net.edge_b.tolist(), net.edge_fault.tolist(), strict=True):
        out.append((*sorted([tuple(xy[a].tolist()), tuple(xy[b].tolist())]), f))
    return sorted(out)


def test_two_crossing_faults_split_at_their_crossing(square):
    notes: list[str] = []
    net = build_network([Fault([(1, 5), (9, 5)]), Fault([(5, 1), (5, 9)])], square, one, notes)
    assert sorted(map(tuple, (net.nodes + square.origin).tolist())) == [
        (1.0, 5.0),
        (5.0, 1.0),
        (5.0, 5.0),
        (5.0, 9.0),
        (9.0, 5.0),
    ]
    assert edges_xy(net, square) == [
        ((1.0, 5.0), (5.0, 5.0), 1),
        ((5.0, 1.0), (5.0, 5.0), 2),
        ((5.0, 5.0), (5.0, 9.0), 2),
        ((5.0, 5.0), (9.0, 5.0), 1),
    ]
    assert not net.on_boundary.any()
    assert net.labels == ["fault 'F1' (faults[0])", "fault 'F2' (faults[1])"]
    assert notes == []


def test_a_trace_leaving_the_domain_is_clipped_at_the_boundary(square):
    notes: list[str] = []
    net = build_network([Fault([(-5, 5), (5, 5)])], square, one, notes)
    np.testing.assert_array_equal(net.nodes + square.origin, [[0.0, 5.0], [5.0, 5.0]])
    np.testing.assert_array_equal(net.edge_a, [0])
    np.testing.assert_array_equal(net.edge_b, [1])
    np.testing.assert_array_equal(net.on_boundary, [True, False])
    assert notes == ["fault 'F1' (faults[0]): clipped to the domain (5 of 10 m inside)"]


def test_a_free_end_within_reach_of_the_boundary_is_extended_to_it(square):
    notes: list[str] = []
    net = build_network([Fault([(2, 5), (9.5, 5)])], square, one, notes)  # 0.5 < 0.75 cells from x = 10
    np.testing.assert_array_equal(net.nodes + square.origin, [[2.0, 5.0], [10.0, 5.0]])
    np.testing.assert_array_equal(net.on_boundary, [False, True])
    assert notes == [
        "fault 'F1' (faults[0]): its end at (9.5, 5) was extended by 0.5 m to meet the domain boundary"
    ]


def test_faults_running_along_each_other_are_an_error(square):
    with pytest.raises(GridError, match="overlap"):
        build_network([Fault([(1, 5), (6, 5)]), Fault([(4, 5), (9, 5)])], square, one, [])


def test_a_closed_trace_is_an_error(square):
    with pytest.raises(GridError, match="closed"):
        build_network([Fault([(1, 1), (5, 1), (5, 5), (1, 1)])], square, one, [])


def test_layout_marks_the_junction_constrained_and_the_free_ends_tips(square):
    lay = layout([Fault([(1, 5), (9, 5)]), Fault([(5, 1), (5, 9)])], square, one, 0.6, [])
    xy = [tuple(p) for p in (lay.net.nodes + square.origin).tolist()]
    key = dict(zip(xy, lay.ch.key.tolist(), strict=True))
    tip = dict(zip(xy, lay.ch.tip.tolist(), strict=True))
    assert key == dict.fromkeys(xy, True)  # degree 4 at the crossing, degree 1 at the ends
    assert tip == {(1.0, 5.0): True, (5.0, 1.0): True, (5.0, 5.0): False, (5.0, 9.0): True, (9.0, 5.0): True}


def test_ring_room_is_the_distance_to_the_nearest_trace_less_the_circles_and_a_gap(square):
    lay = layout([Fault([(1, 5), (9, 5)]), Fault([(5, 1), (5, 9)])], square, one, 0.6, [])
    room, by, dist = ring_room(lay, square.to_local(np.array([[5.0, 8.0], [2.0, 7.0]])))
    # step 1 m everywhere: the circles reach 0.6 m, the rings stop 0.25 m short of them
    np.testing.assert_array_equal(room, [0.0 - (0.6 + 0.25), 2.0 - (0.6 + 0.25)])
    np.testing.assert_array_equal(dist, [0.0, 2.0])
    assert by == ["fault 'F2' (faults[1])", "fault 'F1' (faults[0])"]
