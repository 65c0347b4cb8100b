"""pebi (Voronoi dual of a triangulation) and make_layered_grid of it: the seed's figures."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import ConvexHull
from seed_points import radial_points, ring

import gridlib as gl


def test_honeycomb_pebi_matches_the_seed(honeycomb):
    """Seed §3.2.2: 40 cells, 123 faces, 84 nodes; bounded by the hull."""
    g = gl.pebi(gl.triangle_grid(honeycomb))
    assert (g.num_cells, g.num_faces, g.num_nodes) == (40, 123, 84)
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(26.8467875173, abs=1e-10)
    assert geo.cell_volumes.sum() == pytest.approx(ConvexHull(honeycomb).volume, rel=1e-14)
    # Interior cells are regular hexagons of side 1/sqrt(3): area sqrt(3)/2.
    six = g.cells.num_faces == 6
    np.testing.assert_allclose(geo.cell_volumes[six & (geo.cell_volumes > 0.8)], np.sqrt(3) / 2, rtol=1e-12)
    gl.check_grid(g, geo)


def test_layered_honeycomb_matches_the_seed(honeycomb):
    g = gl.make_layered_grid(gl.pebi(gl.triangle_grid(honeycomb)), 3)
    assert (g.num_cells, g.num_faces, g.num_nodes) == (120, 529, 336)
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(80.540362552, abs=1e-9)
    gl.check_grid(g, geo)


def test_radial_grid_of_the_seed():
    """§3.3.2 Example 2: 241 cells, area of the 16-gon of radius 1."""
    g = gl.pebi(gl.triangle_grid(radial_points()))
    assert g.num_cells == 241
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(3.06146745892, abs=1e-11)
    assert geo.cell_volumes.sum() == pytest.approx(8 * np.sin(2 * np.pi / 16), rel=1e-14)
    gl.check_grid(g, geo)


def test_two_well_composite_of_the_seed():
    """§3.5.2 Fig. 3.37: rings at (2,2) and (12,6) in a 0.5 lattice on [0,14]x[0,8]."""
    well = np.concatenate([*[ring(r, 28) for r in np.exp(np.arange(-3.5, 1e-9, 0.2))], [[0.0, 0.0]]])
    x, y = np.meshgrid(np.arange(0, 14.0001, 0.5), np.arange(0, 8.0001, 0.5))
    pts = np.unique(
        np.concatenate([well + [2, 2], well + [12, 6], np.column_stack([x.ravel(), y.ravel()])]), axis=0
    )
    g = gl.pebi(gl.triangle_grid(pts))
    assert g.num_cells == pts.shape[0]
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(112.0, rel=1e-13)
    gl.check_grid(g, geo)


@pytest.mark.parametrize("seed", range(12))
def test_pebi_of_random_points_is_the_clipped_voronoi(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(20, 300))
    sites = rng.uniform(size=(n, 2)) * [3000.0, 1000.0] + [5.3e5, 6.7e6]  # UTM-sized
    g = gl.pebi(gl.triangle_grid(sites))
    geo = gl.compute_geometry(g)
    assert g.num_cells == n
    assert geo.cell_volumes.sum() == pytest.approx(ConvexHull(sites - sites.mean(0)).volume, rel=1e-10)
    # Interior faces are perpendicular bisectors of their two sites.
    inner = (g.faces.neighbors >= 0).all(axis=1)
    a, b = sites[g.faces.neighbors[inner, 0]], sites[g.faces.neighbors[inner, 1]]
    e = g.faces.nodes.reshape(-1, 2)[inner]
    p0, p1 = g.nodes.coords[e[:, 0]], g.nodes.coords[e[:, 1]]
    scale = 3000.0
    assert np.abs(((p1 - p0) * (b - a)).sum(axis=1)).max() < 1e-9 * scale**2
    d0 = np.linalg.norm(p0 - a, axis=1) - np.linalg.norm(p0 - b, axis=1)
    assert np.abs(d0).max() < 1e-7
    # Normals point from neighbour 0 to neighbour 1.
    assert np.all((geo.face_normals[inner] * (b - a)).sum(axis=1) > 0)
    gl.check_grid(g, geo)


def test_pebi_of_a_non_convex_triangulation_uses_mrst_dual():
    """An L-shaped domain: the dual is bounded by the triangulation's own boundary."""
    x, y = np.meshgrid(np.arange(7.0), np.arange(7.0))
    pts = np.column_stack([x.ravel(), y.ravel()])
    tri = gl.triangle_grid(pts)
    c = gl.compute_geometry(tri).cell_centroids
    lshape = gl.remove_cells(tri, (c[:, 0] > 3) & (c[:, 1] > 3))
    used = np.unique(lshape.faces.nodes)
    assert used.size == lshape.num_nodes  # remove_cells dropped the orphans
    g = gl.pebi(lshape)
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(36.0 - 9.0, rel=1e-12)
    assert g.num_cells == lshape.num_nodes
    gl.check_grid(g, geo)


def test_pebi_rejects_non_triangles():
    with pytest.raises(gl.GridError, match="not a triangle"):
        gl.pebi(gl.cart_grid([2, 2]))
    with pytest.raises(gl.GridError, match="planar 2-D"):
        gl.pebi(gl.cart_grid([2, 2, 2]))


@pytest.mark.parametrize("angle", [0, 20, 45, 60, 77])
def test_pebi_of_rotated_lattice_at_utm(angle):
    a = np.radians(angle)
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    x, y = np.meshgrid(np.arange(20) * 25.0, np.arange(15) * 25.0)
    p = np.column_stack([x.ravel(), y.ravel()]) @ rot.T + [5.3e5, 6.7e6]
    g = gl.pebi(gl.triangle_grid(p))
    assert g.num_cells == 300
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(19 * 14 * 625.0, rel=1e-9)
    inner = np.isclose(geo.cell_volumes, 625.0, rtol=1e-6)
    assert inner.sum() == 18 * 13  # every interior site owns a 25 m square
    gl.check_grid(g, geo)


@pytest.mark.parametrize("noise", [1e-12, 1e-10, 1e-8, 1e-7])
def test_pebi_of_nearly_cocircular_lattices(noise):
    x, y = np.meshgrid(np.arange(10.0), np.arange(8.0))
    lattice = np.column_stack([x.ravel(), y.ravel()])
    for seed in range(5):
        p = lattice + noise * np.random.default_rng(seed).standard_normal(lattice.shape)
        g = gl.pebi(gl.triangle_grid(p))
        assert g.num_cells == 80
        geo = gl.compute_geometry(g)
        assert geo.cell_volumes.sum() == pytest.approx(ConvexHull(p).volume, rel=1e-9)
        gl.check_grid(g, geo)


def test_pebi_refuses_folded_duals_of_non_convex_triangulations():
    """Random points in an L: circumcentres leave the domain; MRST folds, we say so."""
    rng = np.random.default_rng(54)
    p = rng.uniform(0, 2, (60, 2))
    p = p[(p[:, 0] < 1) | (p[:, 1] < 1)]
    tri = gl.triangle_grid(p)
    c = gl.compute_geometry(tri).cell_centroids
    lshape = gl.remove_cells(tri, (c[:, 0] > 1) & (c[:, 1] > 1))
    with pytest.raises(gl.GridError, match=r"pebi: .*refine the triangulation"):
        gl.pebi(lshape)
