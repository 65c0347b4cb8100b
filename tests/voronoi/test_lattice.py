"""Voronoi ridges of lattices (gridlib.voronoi.lattice) on a 3 x 3 square lattice of unit spacing.

Sites are numbered row by row: site k is at (0.5 + k % 3, 0.5 + k // 3). Their Voronoi cells are
unit squares, so the ridges of non-zero length join the 12 pairs of lattice neighbours (the
diagonal neighbours share only a vertex: co-circular squares give zero-length ridges).
"""

import numpy as np
import pytest

from gridlib.voronoi.domain import Domain, rectangle
from gridlib.voronoi.lattice import Lattice, hybrid_ridges, plain_ridges, splice_ridges

NEIGHBOURS = [(0, 1), (0, 3), (1, 2), (1, 4), (2, 5), (3, 4), (3, 6), (4, 5), (4, 7), (5, 8), (6, 7), (7, 8)]


@pytest.fixture
def grid3():
    dom = Domain(rectangle(0.0, 0.0, 3.0, 3.0))
    ij = np.array([(i, j) for j in range(3) for i in range(3)])
    return dom, ij, dom.to_local(0.5 + ij.astype(float))


def real_pairs(ridges):
    coords, va, vb, p, q = ridges.coords, ridges.va, ridges.vb, ridges.cp, ridges.cq
    real = np.hypot(*(coords[va] - coords[vb]).T) > 1e-9
    return sorted(map(tuple, np.sort(np.column_stack([p[real], q[real]]), axis=1).tolist()))


def ridge(ridges, a, b):
    coords, va, vb, p, q = ridges.coords, ridges.va, ridges.vb, ridges.cp, ridges.cq
    k = np.flatnonzero(((p == a) & (q == b)) | ((p == b) & (q == a)))
    assert k.size == 1
    return sorted([tuple(coords[va[k[0]]].tolist()), tuple(coords[vb[k[0]]].tolist())])


def test_plain_ridges_join_the_lattice_neighbours(grid3):
    dom, _, sites = grid3
    ridges = plain_ridges(sites, dom)
    assert real_pairs(ridges) == NEIGHBOURS
    o = tuple(dom.origin.tolist())
    # the ridge between the centre site and its right neighbour: x = 2, from y = 1 to y = 2
    assert ridge(ridges, 4, 5) == [(2.0 - o[0], 1.0 - o[1]), (2.0 - o[0], 2.0 - o[1])]


def test_hybrid_ridges_of_a_full_lattice_are_the_same_without_qhull_inside(grid3):
    dom, ij, sites = grid3
    lat = Lattice("cartesian", dom.to_local([0.5, 0.5]), 1.0, ij)
    ridges = hybrid_ridges(sites, dom, lat)
    assert real_pairs(ridges) == NEIGHBOURS
    o = tuple(dom.origin.tolist())
    assert ridge(ridges, 4, 5) == [(2.0 - o[0], 1.0 - o[1]), (2.0 - o[0], 2.0 - o[1])]


def test_splice_ridges_after_moving_the_centre_site(grid3):
    dom, _, sites = grid3
    before = plain_ridges(sites, dom)
    moved = sites.copy()
    moved[4, 0] += 0.1  # the centre site to (1.6, 1.5)
    spliced = splice_ridges(before, moved, np.array([4]), dom, 1e-9)
    assert spliced is not None
    after, fresh = spliced
    assert fresh.all()  # every site neighbours the centre one: all ridges recomputed
    # the four squares around the centre site are no longer co-circular: each gets a real diagonal,
    # (1, 3) and (3, 7) on the left (the site moved out of their corners' circles), (2, 4) and (4, 8)
    # on the right (it moved into the circle of (1, 2, 5), resp. (5, 7, 8))
    assert real_pairs(after) == sorted(NEIGHBOURS + [(1, 3), (2, 4), (3, 7), (4, 8)])
    o = dom.origin
    # the bisector of (1.6, 1.5) and (2.5, 1.5) is x = 2.05, still between y = 1 and 2
    np.testing.assert_allclose(
        np.array(ridge(after, 4, 5)) + o, [[2.05, 1.0], [2.05, 2.0]], rtol=0, atol=1e-12
    )
    # that of (0.5, 1.5) and (1.6, 1.5) is x = 1.05; its ends are the points equidistant from
    # sites 1, 3, 4 and 3, 4, 7: (1.05, 1.05) and (1.05, 1.95)
    np.testing.assert_allclose(
        np.array(ridge(after, 3, 4)) + o, [[1.05, 1.05], [1.05, 1.95]], rtol=0, atol=1e-12
    )
