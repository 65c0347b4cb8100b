"""gridlib.connectivity on grids small enough to work out by hand.

The 2 x 1 Cartesian grid of unit squares (``cart_grid((2, 1))``)::

    3 --f5-- 4 --f6-- 5        nodes 0..5 at (0,0) (1,0) (2,0) (0,1) (1,1) (2,1)
    |        |        |        faces (node a, node b; neighbours):
    f0  c0   f1  c1   f2         f0 (0,3; -1,0)  f1 (1,4; 0,1)  f2 (2,5; 1,-1)
    |        |        |          f3 (1,0; -1,0)  f4 (2,1; -1,1)
    0 --f3-- 1 --f4-- 2          f5 (4,3; 0,-1)  f6 (5,4; 1,-1)

cell 0 lists the faces (f0, f3, f1, f5), cell 1 (f1, f4, f2, f6): west, south, east, north
(tags 0, 2, 1, 3). A half-face h = 2 f + s is side s of face f; its cell lies on the left of
the edge a -> b when s = 0 (the edge runs b -> a for that cell when s = 1).
"""

from __future__ import annotations

import numpy as np
import pytest

import gridlib as gl
from gridlib.connectivity import (
    boundary_faces,
    cell_faces_from_neighbors,
    cell_half_faces,
    cell_node_cycles_2d,
    cycle_rank,
    drop_repeated_nodes,
    face_node_matrix,
    half_face_cells,
    half_face_cycle_slots,
    half_face_signs,
    offsets,
    order_cell_faces_2d,
    ragged_arange,
    renumbering,
    repeat_ids,
    unique_rows,
)
from gridlib.errors import GridError
from gridlib.grid import Cells, Faces, Grid, Nodes


def equal(a, expected) -> bool:
    """Same values, and int64 as every index array of gridlib."""
    a = np.asarray(a)
    return a.dtype == np.int64 and np.array_equal(a, expected)


@pytest.fixture
def two_cells() -> Grid:
    return gl.cart_grid((2, 1))


@pytest.fixture
def faces_in_face_order(two_cells) -> Grid:
    """The same grid with each cell's faces listed in increasing face number, tags along."""
    g = two_cells
    cells = Cells([0, 4, 8], [0, 1, 3, 5, 1, 2, 4, 6], [0, 1, 2, 3, 0, 1, 2, 3])
    return Grid(cells, g.faces, g.nodes, 2, g.cart_dims)


def test_the_hand_made_grid_is_what_the_docstring_draws(two_cells):
    g = two_cells
    assert np.array_equal(g.nodes.coords, [[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1]])
    assert np.array_equal(g.faces.nodes, [0, 3, 1, 4, 2, 5, 1, 0, 2, 1, 4, 3, 5, 4])
    assert np.array_equal(g.faces.neighbors, [[-1, 0], [0, 1], [1, -1], [-1, 0], [-1, 1], [0, -1], [1, -1]])
    assert np.array_equal(g.cells.face_pos, [0, 4, 8])
    assert np.array_equal(g.cells.faces, [0, 3, 1, 5, 1, 4, 2, 6])
    assert np.array_equal(g.cells.face_tag, [0, 2, 1, 3, 0, 2, 1, 3])


# --------------------------------------------------------------------------- ragged lists


def test_offsets():
    assert equal(offsets([2, 0, 3]), [0, 2, 2, 5])
    assert equal(offsets([]), [0])


def test_repeat_ids():
    assert equal(repeat_ids(np.array([0, 2, 2, 5])), [0, 0, 2, 2, 2])
    assert equal(repeat_ids(np.array([0])), [])


def test_ragged_arange():
    assert equal(ragged_arange([5, 0, 7], [2, 0, 3]), [5, 6, 7, 8, 9])
    assert equal(ragged_arange([3, 1], [1, 2]), [3, 1, 2])
    assert equal(ragged_arange([4], [0]), [])


def test_renumbering():
    assert equal(renumbering(np.array([True, False, True, True])), [0, -1, 1, 2])
    assert equal(renumbering(np.array([False, False])), [-1, -1])


def test_unique_rows():
    uniq, inverse = unique_rows(np.array([[1, 2], [0, 5], [1, 2]], dtype=np.int64))
    assert equal(uniq, [[0, 5], [1, 2]])
    assert equal(inverse, [1, 0, 1])
    uniq, inverse = unique_rows(np.zeros((0, 2), dtype=np.int64))
    assert uniq.shape == (0, 2) and equal(inverse, [])


def test_drop_repeated_nodes():
    # 0 1 1 2: the repeated 1 goes; 5 6 7 5: the cycle closes on 5, which goes; 3 4 5 stays
    pos, nodes = drop_repeated_nodes(np.array([0, 4, 7, 11]), np.array([0, 1, 1, 2, 3, 4, 5, 5, 6, 7, 5]))
    assert equal(pos, [0, 3, 6, 9])
    assert equal(nodes, [0, 1, 2, 3, 4, 5, 5, 6, 7])
    pos, nodes = drop_repeated_nodes(np.array([0, 3]), np.array([0, 1, 2]))
    assert equal(pos, [0, 3]) and equal(nodes, [0, 1, 2])


# --------------------------------------------------------------------------- cells, faces, half-faces


def test_cell_faces_from_neighbors(two_cells):
    pos, faces = cell_faces_from_neighbors(two_cells.faces.neighbors, 2)
    assert equal(pos, [0, 4, 8])
    assert equal(faces, [0, 1, 3, 5, 1, 2, 4, 6])  # each cell's faces in face order


def test_cell_half_faces(two_cells):
    pos, half = cell_half_faces(two_cells.faces.neighbors, 2)
    assert equal(pos, [0, 4, 8])
    # cell 0: f0 side 1, f1 side 0, f3 side 1, f5 side 0; cell 1: f1 side 1, f2 side 0, f4 side 1, f6 side 0
    assert equal(half, [1, 2, 7, 10, 3, 4, 9, 12])
    assert np.array_equal(two_cells.faces.neighbors.ravel()[half], [0, 0, 0, 0, 1, 1, 1, 1])


def test_half_face_cells_and_signs(two_cells):
    assert equal(half_face_cells(two_cells), [0, 0, 0, 0, 1, 1, 1, 1])
    # +1 where the cell is neighbors[f, 0]: f1 and f5 for cell 0, f2 and f6 for cell 1
    assert equal(half_face_signs(two_cells), [-1, -1, 1, 1, -1, -1, 1, 1])


def test_boundary_faces(two_cells):
    assert equal(boundary_faces(two_cells), [0, 2, 3, 4, 5, 6])  # all but f1, between the cells
    # 2 x 1 x 1: x-faces 0..2, y-faces 3..6, z-faces 7..10; only x-face 1 is inside
    assert equal(boundary_faces(gl.cart_grid((2, 1, 1))), [0, 2, 3, 4, 5, 6, 7, 8, 9, 10])


def test_face_node_matrix(two_cells):
    assert equal(face_node_matrix(two_cells), [[0, 3], [1, 4], [2, 5], [1, 0], [2, 1], [4, 3], [5, 4]])


def test_face_node_matrix_refuses_faces_of_different_sizes():
    nodes = Nodes(np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]))
    faces = Faces([0, 3, 7], [0, 1, 2, 0, 1, 3, 2], [[0, -1], [0, -1]])
    grid = Grid(Cells([0, 2], [0, 1]), faces, nodes, 3)
    with pytest.raises(GridError, match="different numbers of nodes"):
        face_node_matrix(grid)


# --------------------------------------------------------------------------- 2-D cycles


def test_cell_node_cycles_2d(two_cells, faces_in_face_order):
    # counter-clockwise from the start of each cell's first half-face: 3 -> 0 -> 1 -> 4, 4 -> 1 -> 2 -> 5
    for g in (two_cells, faces_in_face_order):
        pos, nodes = cell_node_cycles_2d(g)
        assert equal(pos, [0, 4, 8])
        assert equal(nodes, [3, 0, 1, 4, 4, 1, 2, 5])


def test_half_face_cycle_slots(two_cells, faces_in_face_order):
    start, slot = half_face_cycle_slots(two_cells)
    assert equal(start, [3, 0, 1, 4, 4, 1, 2, 5])
    assert equal(slot, [0, 1, 2, 3, 4, 5, 6, 7])  # cart_grid lists the faces in cycle order
    # faces (f0, f1, f3, f5) and (f1, f2, f4, f6): edges 3-0, 1-4, 0-1, 4-3 and 4-1, 2-5, 1-2, 5-4
    start, slot = half_face_cycle_slots(faces_in_face_order)
    assert equal(start, [3, 1, 0, 4, 4, 2, 1, 5])
    assert equal(slot, [0, 2, 1, 3, 4, 6, 5, 7])


def test_order_cell_faces_2d_gives_the_cycle_order_with_the_tags(two_cells, faces_in_face_order):
    ordered = order_cell_faces_2d(faces_in_face_order)
    assert equal(ordered.cells.face_pos, [0, 4, 8])
    assert equal(ordered.cells.faces, [0, 3, 1, 5, 1, 4, 2, 6])  # the order of cart_grid
    assert np.array_equal(ordered.cells.face_tag, [0, 2, 1, 3, 0, 2, 1, 3])
    assert ordered.faces is faces_in_face_order.faces and ordered.nodes is faces_in_face_order.nodes
    assert equal(order_cell_faces_2d(two_cells).cells.faces, two_cells.cells.faces)


def test_cycle_rank():
    # owner 0: edges 0 -> 2 -> 1 -> back to 0; owner 1: edges 3 -> 4 -> back to 3
    succ = np.array([2, 0, 1, 4, 3])
    rank = cycle_rank(succ, np.array([0, 3, 5]), np.array([0, 0, 0, 1, 1]))
    assert equal(rank, [0, 2, 1, 0, 1])


def test_cycle_rank_refuses_two_cycles_in_one_cell():
    with pytest.raises(GridError, match="cell 0: its edges form more than one cycle"):
        cycle_rank(np.array([1, 0, 3, 2]), np.array([0, 4]), np.array([0, 0, 0, 0]))


def test_cycles_need_a_2d_grid_of_closed_cells():
    with pytest.raises(GridError, match="need a 2-D grid"):
        cell_node_cycles_2d(gl.cart_grid((2, 1, 1)))
    nodes = Nodes(np.array([[0.0, 0], [1, 0], [1, 1]]))
    open_cell = Grid(Cells([0, 2], [0, 1]), Faces([0, 2, 4], [0, 1, 1, 2], [[0, -1], [0, -1]]), nodes, 2)
    with pytest.raises(GridError, match="cell 0: its edges do not close"):
        cell_node_cycles_2d(open_cell)
