"""The shared 2-D primitives of gridlib.planar, on inputs whose answers are known by hand."""

import numpy as np

from gridlib.planar import circumcentres, cross2, group_pairs, merge_close_points


def test_cross2_is_twice_the_signed_area_and_broadcasts():
    u = np.array([[1.0, 0.0], [0.0, 1.0], [2.0, 3.0]])
    v = np.array([[0.0, 1.0], [1.0, 0.0], [4.0, 6.0]])
    np.testing.assert_array_equal(cross2(u, v), [1.0, -1.0, 0.0])
    np.testing.assert_array_equal(cross2(u, np.array([1.0, 1.0])), [1.0, -1.0, -1.0])
    assert cross2(np.zeros((0, 2)), np.zeros((0, 2))).shape == (0,)


def test_circumcentres_of_right_and_equilateral_like_triangles():
    xy = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 2.0], [4.0, 2.0], [2.0, 4.0]])
    tri = np.array([[0, 1, 2], [1, 3, 2], [2, 3, 4]])
    # right angles at 0 and 3: the centre is the hypotenuse's midpoint; (0,2),(4,2),(2,4): (2, 2)
    np.testing.assert_array_equal(circumcentres(xy, tri), [[2.0, 1.0], [2.0, 1.0], [2.0, 2.0]])


def test_circumcentres_far_from_the_origin_are_exact_for_exact_inputs():
    xy = np.array([[5.0e5, 7.0e6], [5.0e5 + 2.0, 7.0e6], [5.0e5, 7.0e6 + 2.0]])
    np.testing.assert_array_equal(circumcentres(xy, np.array([[0, 1, 2]])), [[5.0e5 + 1.0, 7.0e6 + 1.0]])


def test_circumcentre_of_collinear_points_is_not_finite():
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    assert not np.isfinite(circumcentres(xy, np.array([[0, 1, 2]]))).all()


def test_group_pairs_joins_chains_and_numbers_groups_by_their_lowest_item():
    rep, inv = group_pairs(6, np.array([[5, 2], [2, 4], [3, 1]]))
    np.testing.assert_array_equal(rep, [0, 1, 2])
    np.testing.assert_array_equal(inv, [0, 1, 2, 1, 2, 2])


def test_group_pairs_without_pairs_keeps_every_item():
    rep, inv = group_pairs(3, np.zeros((0, 2), dtype=np.int64))
    np.testing.assert_array_equal(rep, [0, 1, 2])
    np.testing.assert_array_equal(inv, [0, 1, 2])


def test_merge_close_points_merges_chains_within_the_tolerance():
    xy = np.array([[10.0, 0.0], [0.0, 0.0], [0.0, 0.9], [0.0, 1.8], [10.0, 0.5], [5.0, 5.0]])
    rep, inv = merge_close_points(xy, 1.0)
    # 1-2-3 are a chain (0.9 apart), 0-4 are 0.5 apart; 5 is alone
    np.testing.assert_array_equal(rep, [0, 1, 5])
    np.testing.assert_array_equal(inv, [0, 1, 1, 1, 0, 2])
    np.testing.assert_array_equal(xy[rep][inv][[2, 4]], [[0.0, 0.0], [10.0, 0.0]])


def test_merge_close_points_keeps_points_further_apart_than_the_tolerance():
    xy = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    rep, inv = merge_close_points(xy, 0.5)
    np.testing.assert_array_equal(rep, [0, 1, 2])
    np.testing.assert_array_equal(inv, [0, 1, 2])
