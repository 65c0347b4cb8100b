"""The clipped Voronoi diagram (gridlib.voronoi.bounded) of sites whose cells are unit squares.

Three sites at (0.5, 0.5), (1.5, 0.5), (2.5, 0.5) in the rectangle 0 <= x <= 3, 0 <= y <= 1:
the cells are the unit squares around them, the interior faces x = 1 and x = 2, and the
boundary is cut at x = 1 and x = 2 top and bottom (10 faces in all).
"""

import numpy as np
import pytest

from gridlib.voronoi.bounded import clipped_voronoi
from gridlib.voronoi.domain import Domain, rectangle


@pytest.fixture
def row():
    dom = Domain(rectangle(0.0, 0.0, 3.0, 1.0))
    sites = dom.to_local(np.array([[0.5, 0.5], [1.5, 0.5], [2.5, 0.5]]))
    return dom, sites, clipped_voronoi(sites, dom, 1e-9)


def faces(dom, v):
    """Every face as (smaller cell, other cell or -1, its two nodes sorted) in the caller's frame."""
    xy = v.coords + dom.origin
    out = []
    for (a, b), (c0, c1) in zip(v.face_nodes.tolist(), v.neighbors.tolist(), strict=True):
        cells = (min(c0, c1), max(c0, c1)) if c1 >= 0 else (c0, -1)
        out.append((*cells, *sorted([tuple(xy[a].tolist()), tuple(xy[b].tolist())])))
    return sorted(out)


def test_cells_are_the_unit_squares(row):
    dom, _, v = row
    np.testing.assert_array_equal(v.areas, [1.0, 1.0, 1.0])
    assert faces(dom, v) == [
        (0, -1, (0.0, 0.0), (0.0, 1.0)),
        (0, -1, (0.0, 0.0), (1.0, 0.0)),
        (0, -1, (0.0, 1.0), (1.0, 1.0)),
        (0, 1, (1.0, 0.0), (1.0, 1.0)),
        (1, -1, (1.0, 0.0), (2.0, 0.0)),
        (1, -1, (1.0, 1.0), (2.0, 1.0)),
        (1, 2, (2.0, 0.0), (2.0, 1.0)),
        (2, -1, (2.0, 0.0), (3.0, 0.0)),
        (2, -1, (2.0, 1.0), (3.0, 1.0)),
        (2, -1, (3.0, 0.0), (3.0, 1.0)),
    ]
    assert v.extra_points.shape == (0, 2)
    assert v.contracted == 0


def test_face_normals_point_from_the_first_cell_to_the_second(row):
    _, sites, v = row
    d = v.coords[v.face_nodes[:, 1]] - v.coords[v.face_nodes[:, 0]]
    normal = np.column_stack([d[:, 1], -d[:, 0]])
    first = sites[v.neighbors[:, 0]]
    inner = v.neighbors[:, 1] >= 0
    toward = np.where(
        inner[:, None],
        sites[np.maximum(v.neighbors[:, 1], 0)] - first,
        (v.coords[v.face_nodes[:, 0]] - first),
    )
    np.testing.assert_array_equal((normal * toward).sum(axis=1) > 0, np.ones(10, dtype=bool))


def test_each_cell_lists_its_four_faces_in_one_counter_clockwise_cycle(row):
    _, _, v = row
    np.testing.assert_array_equal(v.cell_pos, [0, 4, 8, 12])
    for c in range(3):
        fs = v.cell_faces[v.cell_pos[c] : v.cell_pos[c + 1]]
        nodes = v.face_nodes[fs]
        # walking the faces in order, each face's nodes as the cell sees them (counter-clockwise)
        mine = np.where((v.neighbors[fs, 0] == c)[:, None], nodes, nodes[:, ::-1])
        np.testing.assert_array_equal(mine[:, 1], np.roll(mine[:, 0], -1))
        xy = v.coords[mine[:, 0]]
        area = 0.5 * np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1])
        assert area == 1.0


def test_to_grid_puts_the_nodes_back_in_the_callers_frame(row):
    dom, _, v = row
    g = v.to_grid(dom.origin, None, ("test",))
    assert (g.num_cells, g.num_faces, g.num_nodes) == (3, 10, 8)
    assert sorted(map(tuple, g.nodes.coords.tolist())) == [
        (0.0, 0.0),
        (0.0, 1.0),
        (1.0, 0.0),
        (1.0, 1.0),
        (2.0, 0.0),
        (2.0, 1.0),
        (3.0, 0.0),
        (3.0, 1.0),
    ]
