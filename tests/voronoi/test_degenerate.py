"""Collapsing short faces (gridlib.voronoi.degenerate) on four nearly co-circular sites.

Sites (1, 0), (0, 1.01), (-1, 0), (0, -1): the circle through (1, 0), (-1, 0), (0, -1) is the
unit circle, the one through (1, 0), (0, 1.01), (-1, 0) is centred at (0, 0.0201 / 2.02), so
the face between (1, 0) and (-1, 0) is 1 cm long. Moving (0, 1.01) onto the unit circle, or
(0, -1) onto the other circle (which meets the y axis at -1 / 1.01: intersecting chords,
1 x 1 = 1.01 x |y|), makes the four sites co-circular and the face vanish.
"""

import numpy as np
import pytest

from gridlib.voronoi.degenerate import SHORT, Collapse, MoveRules, collapse_moves
from gridlib.voronoi.domain import Domain, rectangle
from gridlib.voronoi.lattice import plain_ridges


@pytest.fixture
def kite():
    dom = Domain(rectangle(-10.0, -10.0, 10.0, 10.0))
    sites = dom.to_local(np.array([[1.0, 0.0], [0.0, 1.01], [-1.0, 0.0], [0.0, -1.0]]))
    return dom, sites, plain_ridges(sites, dom)


def moves(kite, movable, state=None):
    dom, sites, ridges = kite
    state = Collapse() if state is None else state
    rules = MoveRules(dom, np.ones(4), np.array(movable), 1e-9)
    idx, xy, state = collapse_moves(ridges, sites, rules, state)
    return idx, xy + dom.origin, state


def test_the_face_is_short_by_the_threshold():
    assert 0.0201 / 2.02 < SHORT  # the face's length, in cell sizes of 1 m


def test_the_movable_site_goes_onto_the_circle_of_the_other_three(kite):
    idx, xy, state = moves(kite, [False, True, False, False])
    np.testing.assert_array_equal(idx, [1])
    np.testing.assert_allclose(xy, [[0.0, 1.0]], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(state.involved, [0, 1, 2, 3])
    assert state.pending.size == 0  # the face was collapsed
    assert state.pins == {}  # an interior collapse pins nothing


def test_the_opposite_site_goes_onto_the_other_circle(kite):
    idx, xy, _ = moves(kite, [False, False, False, True])
    np.testing.assert_array_equal(idx, [3])
    np.testing.assert_allclose(xy, [[0.0, -1.0 / 1.01]], rtol=0, atol=1e-12)


def test_nothing_moves_without_a_movable_site(kite):
    idx, xy, _ = moves(kite, [False, False, False, False])
    assert idx.shape == (0,) and xy.shape == (0, 2)


def test_a_site_of_the_face_moves_onto_the_circle_of_the_other_three(kite):
    # the circle through (0, 1.01), (-1, 0), (0, -1): centre (0.005, 0.005) (equidistant from all
    # three), radius^2 = 1.005^2 + 0.005^2; (1, 0) moves radially onto it
    centre, r = np.array([0.005, 0.005]), np.sqrt(1.005**2 + 0.005**2)
    away = np.array([1.0, 0.0]) - centre
    idx, xy, _ = moves(kite, [True, False, False, False])
    np.testing.assert_array_equal(idx, [0])
    np.testing.assert_allclose(xy, [centre + r * away / np.hypot(*away)], rtol=0, atol=1e-12)
