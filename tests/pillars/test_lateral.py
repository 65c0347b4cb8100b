"""gridlib.pillars.lateral.general_pieces: the face pieces of one pillar pair, exactly.

One pair: pillar p1 at (0, 0), p2 at (1, 0), both vertical. Side A holds cell 0, side B cell 1,
each one layer (k = 0). Node ids are pillar-major: those of p1 first, by depth, then p2's;
crossing nodes are numbered after them.
"""

from __future__ import annotations

import numpy as np

from gridlib.pillars.lateral import SideCells, general_pieces
from gridlib.pillars.pillar_points import unique_points


def pieces(z_p1, z_p2, ranks_a, ranks_b, reverse=False):
    """The pieces of the pair with the given depths on its pillars and the cells' ranks
    (t1, b1, t2, b2) on sides A and B."""
    pillar = np.array([0] * len(z_p1) + [1] * len(z_p2))
    pts = unique_points(pillar, np.array(z_p1 + z_p2, dtype=float), 2)
    xyz = np.column_stack([pts.pillar.astype(float), np.zeros(pts.num_nodes), pts.z])
    rows = [(0, 0, 0, 0, *ranks_a), (0, 1, 1, 0, *ranks_b)]  # pair, side, cell, k, t1, b1, t2, b2
    side = SideCells(*(np.array(column, dtype=np.int64) for column in zip(*rows, strict=True)))
    return general_pieces(side, 1, np.array([0]), np.array([1]), np.array([reverse]), pts, xyz)


def cycles(r):
    return [r.nodes[a:b].tolist() for a, b in zip(r.node_pos[:-1], r.node_pos[1:], strict=True)]


def test_no_fault_gives_one_quadrilateral():
    r = pieces([0, 10], [0, 10], (0, 1, 0, 1), (0, 1, 0, 1))
    assert cycles(r) == [[0, 2, 3, 1]]
    assert (r.cell_a.tolist(), r.cell_b.tolist(), r.k_a.tolist(), r.k_b.tolist()) == ([0], [1], [0], [0])
    assert r.pair.tolist() == [0]
    assert r.mismatch.tolist() == [False]
    assert r.crossing_coords.shape == (0, 3) and r.crossing_lines.shape == (0, 2, 2)


def test_constant_throw_gives_three_quadrilaterals():
    # B is 5 m deeper: A against B's void above, A against B, A's void below against B.
    r = pieces([0, 5, 10, 15], [0, 5, 10, 15], (0, 2, 0, 2), (1, 3, 1, 3))
    assert cycles(r) == [[0, 4, 5, 1], [1, 5, 6, 2], [2, 6, 7, 3]]
    assert r.cell_a.tolist() == [0, 0, -1]
    assert r.cell_b.tolist() == [-1, 1, 1]
    assert r.k_a.tolist() == [0, 0, -1]
    assert r.k_b.tolist() == [-1, 0, 0]
    assert r.mismatch.tolist() == [True, True, True]


def test_reversed_pair_walks_the_cycles_backwards():
    r = pieces([0, 5, 10, 15], [0, 5, 10, 15], (0, 2, 0, 2), (1, 3, 1, 3), reverse=True)
    assert cycles(r) == [[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6]]


def test_scissor_fault_makes_crossing_nodes():
    # p1: 0, 5, 10, 15 (nodes 0-3); p2: -5, 0, 5, 10 (nodes 4-7). A is 0..10 on both pillars, B
    # 5..15 on p1 and -5..5 on p2: the tops cross mid-pair at z = 0 (node 8), the bottoms at
    # z = 10 (node 9).
    r = pieces([0, 5, 10, 15], [-5, 0, 5, 10], (0, 2, 1, 3), (1, 3, 0, 2))
    assert cycles(r) == [[4, 5, 8], [0, 8, 1], [1, 8, 5, 6, 9, 2], [6, 7, 9], [2, 9, 3]]
    assert r.cell_a.tolist() == [-1, 0, 0, 0, -1]
    assert r.cell_b.tolist() == [1, -1, 1, -1, 1]
    assert r.crossing_coords.tolist() == [[0.5, 0.0, 0.0], [0.5, 0.0, 10.0]]
    assert r.crossing_lines.tolist() == [[[0, 5], [1, 4]], [[2, 7], [3, 6]]]


def test_lines_touching_at_a_pillar_give_a_triangle():
    # A: 0..10 on p1, 0..10 on p2; B: 10..20 on p1, 5..15 on p2. A and B touch at p1 (z = 10).
    r = pieces([0, 10, 20], [0, 5, 10, 15], (0, 1, 0, 2), (1, 2, 1, 3))
    assert cycles(r) == [[0, 3, 4, 1], [4, 5, 1], [1, 5, 6, 2]]
    assert r.cell_a.tolist() == [0, 0, -1]
    assert r.cell_b.tolist() == [-1, 1, 1]


def test_cells_that_only_touch_along_a_line_share_no_piece():
    r = pieces([0, 10, 20], [0, 10, 20], (0, 1, 0, 1), (1, 2, 1, 2))
    assert cycles(r) == [[0, 3, 4, 1], [1, 4, 5, 2]]
    assert r.cell_a.tolist() == [0, -1]
    assert r.cell_b.tolist() == [-1, 1]
