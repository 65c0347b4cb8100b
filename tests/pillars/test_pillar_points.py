"""gridlib.pillars.pillar_points: distinct depths per pillar as node ids, exactly."""

from __future__ import annotations

import numpy as np

from gridlib.pillars.pillar_points import (
    depth_resolution,
    points_on_pillars,
    sorted_points_rows,
    unique_points,
    unique_points_rows,
)


def test_depth_resolution_is_64_ulps_of_the_largest_depth():
    assert depth_resolution(np.array([3000.0, -1.0])).tolist() == [
        4.263256414560601e-11,
        1.4210854715202004e-14,
    ]


def test_unique_points_numbers_pillar_by_pillar_and_by_depth():
    # Pillar 1 holds 0.1 + 0.2 and 0.3 (one point up to rounding, the shallower kept) and 5;
    # pillar 0 holds 3 twice; pillar 2 holds nothing.
    p = unique_points(np.array([1, 0, 1, 0, 1]), np.array([5.0, 3.0, 0.1 + 0.2, 3.0, 0.3]), 3)
    assert p.node_of_corner.tolist() == [2, 0, 1, 0, 1]
    assert p.offset.tolist() == [0, 1, 3, 3]
    assert p.pillar.tolist() == [0, 1, 1]
    assert p.z.tolist() == [3.0, 0.3, 5.0]
    assert p.num_nodes == 3
    assert p.rank(np.array([0, 1, 2])).tolist() == [0, 0, 1]


def test_unique_points_keeps_depths_apart_beyond_the_resolution():
    assert unique_points(np.array([0, 0]), np.array([1000.0, 1000.0 + 1e-10]), 1).z.tolist() == [
        1000.0,
        1000.0000000001,
    ]
    assert unique_points(np.array([0, 0]), np.array([1000.0, 1000.0 + 1e-11]), 1).z.tolist() == [1000.0]


def test_unique_points_with_a_tolerance_rounds_to_its_multiples_first():
    p = unique_points(np.array([0, 0, 0, 0]), np.array([1.04, 0.96, 1.5, 1.46]), 1, tol=0.1)
    assert p.node_of_corner.tolist() == [0, 0, 1, 1]
    assert p.offset.tolist() == [0, 2]
    assert p.z.tolist() == [1.0, 1.5]


def test_unique_points_rows_numbers_a_table_row_by_row_from_first_id():
    rows = np.array([[3.0, np.nan, 1.0, 0.1 + 0.2], [2.0, 2.0, np.nan, np.nan], [np.nan] * 4])
    ids, count, z = unique_points_rows(rows, first_id=10)
    assert ids.tolist() == [[12, -1, 11, 10], [13, 13, -1, -1], [-1, -1, -1, -1]]
    assert count.tolist() == [3, 1, 0]
    assert z.tolist() == [0.30000000000000004, 1.0, 3.0, 2.0]
    ids, count, z = unique_points_rows(np.array([[1.04, 0.96, 1.5]]), tol=0.1)
    assert (ids.tolist(), count.tolist(), z.tolist()) == ([[0, 0, 1]], [2], [1.0, 1.5])


def test_sorted_points_rows_equals_unique_points_rows_on_growing_rows():
    """Rows that grow (with NaN gaps, repeated depths, depths within the resolution of the one
    before, a row without depths): the ids, counts and depths of the sorting twin, exactly."""
    rng = np.random.default_rng(5)
    steps = rng.choice([0.0, 1e-12, 3e-11, 0.25, 1.5], size=(40, 30))
    rows = 2500.0 + np.cumsum(steps, axis=1)
    rows[rng.random(rows.shape) < 0.3] = np.nan
    rows[7] = np.nan
    ids, count, z = sorted_points_rows(rows, first_id=3)
    ids_sorted, count_sorted, z_sorted = unique_points_rows(rows, first_id=3)
    np.testing.assert_array_equal(ids, ids_sorted)
    np.testing.assert_array_equal(count, count_sorted)
    np.testing.assert_array_equal(z, z_sorted)
    assert count[7] == 0 and (ids[7] == -1).all()
    assert 0 < count.sum() < np.isfinite(rows).sum()  # some depths merged


def test_points_on_pillars_inclined_and_nearly_flat():
    # Pillar 0 runs from (0, 0, 0) to (10, 0, 100); pillar 1's ends differ by 1e-7 in depth (below
    # 1e-6): it has no usable direction and is vertical through its top point.
    lines = np.array([[[0, 0, 0], [10, 0, 100]], [[5, 5, 10], [6, 5, 10 + 1e-7]]], dtype=float)
    xyz = points_on_pillars(lines, np.array([0, 0, 1]), np.array([50.0, 100.0, 20.0]))
    assert xyz.tolist() == [[5.0, 0.0, 50.0], [10.0, 0.0, 100.0], [5.0, 5.0, 20.0]]
    out = np.zeros((1, 3))
    assert points_on_pillars(lines, np.array([0]), np.array([25.0]), out=out) is out
    assert out.tolist() == [[2.5, 0.0, 25.0]]
