"""triangle_grid, tessellation_grid, tetrahedral_grid."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import ConvexHull
from seed_points import seven_points

import gridlib as gl

SEED_TRIANGLES = [[0, 2, 1], [0, 3, 2], [0, 6, 3], [1, 2, 5], [2, 3, 4], [2, 4, 5], [3, 6, 4], [4, 6, 5]]


def test_triangle_grid_reproduces_mrst_example_2():
    """Seed §3.4 Example 2: 8 cells, 14 faces, 7 nodes, faces = sorted node pairs."""
    g = gl.triangle_grid(seven_points(), SEED_TRIANGLES)
    assert (g.num_cells, g.num_faces, g.num_nodes) == (8, 14, 7)
    pairs = ["".join(map(str, f)) for f in g.faces.nodes.reshape(-1, 2)]
    assert pairs == "01 02 03 06 12 15 23 24 25 34 36 45 46 56".split()
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(0.765, rel=1e-14)
    assert np.all(geo.cell_volumes > 0)  # clockwise input triangles were oriented
    gl.check_grid(g, geo)


def test_triangle_grid_delaunay_covers_the_hull():
    rng = np.random.default_rng(3)
    p = rng.uniform(size=(200, 2)) * [1000.0, 300.0] + [5.3e5, 6.7e6]
    g = gl.triangle_grid(p)
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(ConvexHull(p - p.mean(0)).volume, rel=1e-10)
    # Euler characteristic of a disc: V - E + F = 1.
    assert g.num_nodes - g.num_faces + g.num_cells == 1
    gl.check_grid(g, geo)


def test_triangle_grid_on_a_3d_surface_is_consistently_oriented():
    xy = seven_points()
    z = 1000.0 + 0.3 * xy[:, 0] - 0.2 * xy[:, 1]  # a tilted plane, depth positive down
    tris = np.array(SEED_TRIANGLES)
    tris[1::2] = tris[1::2, ::-1]  # mixed orientation on input
    g = gl.triangle_grid(np.column_stack([xy, z]), tris)
    assert g.is_surface
    geo = gl.compute_geometry(g)
    unit = geo.cell_normals / np.linalg.norm(geo.cell_normals, axis=1, keepdims=True)
    assert np.allclose(unit, unit[0], atol=1e-12)  # one orientation for all cells
    # Area of the tilted plane over the seed's footprint: 0.765 * sqrt(1 + 0.3^2 + 0.2^2).
    assert geo.cell_volumes.sum() == pytest.approx(0.765 * np.sqrt(1.13), rel=1e-12)
    gl.check_grid(g, geo)


def test_tessellation_grid_mixed_polygons_in_any_orientation():
    pts = [[0, 0], [1, 0], [2, 0], [0, 1], [1, 1], [2, 1], [1.5, 2]]
    cells = [[0, 1, 4, 3], [1, 2, 5, 4], [4, 5, 6]]  # CCW quads and a CCW triangle
    g = gl.tessellation_grid(pts, [c[::-1] if i == 1 else c for i, c in enumerate(cells)])
    geo = gl.compute_geometry(g)
    np.testing.assert_allclose(geo.cell_volumes, [1.0, 1.0, 0.5], rtol=1e-15)
    np.testing.assert_allclose(geo.cell_centroids[2], [1.5, 4.0 / 3.0], rtol=1e-15)
    assert g.num_faces == 9
    gl.check_grid(g, geo)
    padded = np.array([[0, 1, 4, 3], [1, 2, 5, 4], [4, 5, 6, -1]])
    assert gl.tessellation_grid(pts, padded).num_faces == 9


def test_tessellation_grid_mrst_cartesian_example():
    """Seed §3.2.3: an n x m Cartesian mesh from tessellationGrid equals cart_grid's geometry."""
    n, m = 4, 3
    x, y = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, m + 1))
    idx = np.arange((n + 1) * (m + 1)).reshape(n + 1, m + 1).T  # numbered y first, like MATLAB
    quads = np.column_stack(
        [idx[:-1, :-1].ravel("F"), idx[:-1, 1:].ravel("F"), idx[1:, 1:].ravel("F"), idx[1:, :-1].ravel("F")]
    )
    g = gl.tessellation_grid(np.column_stack([x.ravel("F"), y.ravel("F")]), quads)
    assert (g.num_cells, g.num_faces, g.num_nodes) == (12, 31, 20)
    np.testing.assert_allclose(gl.compute_geometry(g).cell_volumes, 1 / 12, rtol=1e-14)


def test_tetrahedral_grid_fills_the_hull():
    rng = np.random.default_rng(1)
    p = rng.uniform(size=(300, 3)) * [100.0, 50.0, 10.0]
    g = gl.tetrahedral_grid(p)
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(ConvexHull(p).volume, rel=1e-12)
    assert np.all(g.cells.num_faces == 4)
    gl.check_grid(g, geo)


def test_tetrahedral_grid_single_tet_volume_and_centroid():
    p = np.array([[0, 0, 0], [2, 0, 0], [0, 3, 0], [0, 0, 4.0]])
    g = gl.tetrahedral_grid(p, [[0, 2, 1, 3]])  # negatively oriented on input
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes[0] == pytest.approx(4.0, rel=1e-15)
    np.testing.assert_allclose(geo.cell_centroids[0], p.mean(axis=0), rtol=1e-15)


@pytest.mark.parametrize("seed", range(3))
def test_tetrahedral_grid_drops_hull_slivers_of_lattice_faces(seed):
    """Lattice points on the cube's faces are co-circular: Qhull glues them with flat
    tetrahedra on the hull, which must be removed (not returned, not an error)."""
    from scipy.spatial import Delaunay

    rng = np.random.default_rng(seed)
    s = np.linspace(0, 1, 4)
    a, b = (m.ravel() for m in np.meshgrid(s, s))
    faces = []
    for axis in range(3):
        for value in (0.0, 1.0):
            q = np.empty((16, 3))
            q[:, [i for i in range(3) if i != axis]] = np.column_stack([a, b])
            q[:, axis] = value
            faces.append(q)
    p = np.unique(np.concatenate([rng.uniform(0.05, 0.95, (80, 3)), *faces]), axis=0)
    t = Delaunay(p - 0.5).simplices
    d1, d2, d3 = (p[t[:, i]] - p[t[:, 0]] for i in (1, 2, 3))
    qhull_flat = int((np.abs(np.einsum("ij,ij->i", np.cross(d1, d2), d3)) < 1e-13).sum())
    assert qhull_flat > 0  # the situation under test really occurs
    g = gl.tetrahedral_grid(p)
    assert g.num_cells == t.shape[0] - qhull_flat
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(1.0, rel=1e-13)
    assert geo.cell_volumes.min() > 0
    gl.check_grid(g, geo)


def seed_fig_3_8_points(seed: int) -> np.ndarray:
    """The seed's Fig. 3.8 points (MRST book §3.2.1): an 8 x 6 x 4 lattice on [0, 7] x [0, 5] x [0, 3]
    whose interior columns are moved by 0.3 randn in x and y; z-levels exact, box faces unmoved.

        N=7; M=5; K=3;
        [x,y,z] = ndgrid(0:N,0:M,0:K);
        x(2:N,2:M,:) = x(2:N,2:M,:) + 0.3*randn(N-1,M-1,K+1);
        y(2:N,2:M,:) = y(2:N,2:M,:) + 0.3*randn(N-1,M-1,K+1);
        G = tetrahedralGrid([x(:) y(:) z(:)]);
    """
    n, m, k = 7, 5, 3
    x, y, z = np.meshgrid(np.arange(n + 1.0), np.arange(m + 1.0), np.arange(k + 1.0), indexing="ij")
    rng = np.random.default_rng(seed)
    x[1:n, 1:m, :] += 0.3 * rng.standard_normal((n - 1, m - 1, k + 1))
    y[1:n, 1:m, :] += 0.3 * rng.standard_normal((n - 1, m - 1, k + 1))
    return np.column_stack([x.ravel(order="F"), y.ravel(order="F"), z.ravel(order="F")])


def interior_glue(p: np.ndarray) -> int:
    """Qhull's flat Delaunay tetrahedra whose four neighbours are proper ones (glue inside the domain)."""
    from scipy.spatial import Delaunay

    dl = Delaunay(p - p.mean(axis=0))
    t = dl.simplices
    d1, d2, d3 = (p[t[:, i]] - p[t[:, 0]] for i in (1, 2, 3))
    flat = np.abs(np.einsum("ij,ij->i", np.cross(d1, d2), d3)) < 1e-12
    inside = (dl.neighbors >= 0).all(axis=1)
    return int((flat & inside & ~flat[np.maximum(dl.neighbors, 0)].any(axis=1)).sum())


def test_seed_fig_3_8_tetrahedral_grid_fills_its_box():
    """Layers at exact z and unmoved box faces make co-spherical sets (a box corner's vertical
    rectangle with the corner edge, lattice squares on the faces): Qhull glues incompatible
    triangulations with flat tetrahedra, also inside the box. They are tetrahedralised again with
    the ties broken: a valid grid of the exact box volume, 7 x 5 x 3 = 105."""
    glued = 0
    for seed in range(8):
        p = seed_fig_3_8_points(seed)
        glued += interior_glue(p)
        g = gl.tetrahedral_grid(p)
        geo = gl.compute_geometry(g)
        gl.check_grid(g, geo)
        assert g.num_nodes == 192 and np.all(g.cells.num_faces == 4)
        assert geo.cell_volumes.sum() == pytest.approx(105.0, rel=1e-14)
        assert geo.cell_volumes.min() > 1e-6
        np.testing.assert_array_equal(g.nodes.coords, p)  # the exact coordinates, not the tie-breaking
        again = gl.tetrahedral_grid(p)  # deterministic
        np.testing.assert_array_equal(again.faces.nodes, g.faces.nodes)
    assert glued > 0  # the situation under test really occurs


@pytest.mark.parametrize("n", [2, 3, 4, 6])
def test_tetrahedral_grid_of_an_exact_lattice(n):
    """Every cube of a lattice is co-spherical with its neighbours' corners: the most degenerate
    input there is; it fills the cube exactly (it was an error before)."""
    x, y, z = np.meshgrid(*(np.arange(n + 1.0),) * 3, indexing="ij")
    p = np.column_stack([x.ravel(), y.ravel(), z.ravel()]) * [10.0, 20.0, 1.0] + [4.6e5, 6.7e6, 1500.0]
    g = gl.tetrahedral_grid(p)
    geo = gl.compute_geometry(g)
    gl.check_grid(g, geo)
    assert geo.cell_volumes.sum() == pytest.approx(200.0 * n**3, rel=1e-12)
    assert geo.cell_volumes.min() >= 200.0 / 6 * (1 - 1e-9)  # no sliver: a sixth of a cube at least


def test_tetrahedral_grid_of_a_large_degenerate_lattice_fills_its_hull():
    """Fig. 3.8's construction at 31 x 21 x 11 points (7161): vectorised, no loop per cell."""
    n, m, k = 30, 20, 10
    x, y, z = np.meshgrid(np.arange(n + 1.0), np.arange(m + 1.0), np.arange(k + 1.0), indexing="ij")
    rng = np.random.default_rng(3)
    x[1:n, 1:m, :] += 0.3 * rng.standard_normal((n - 1, m - 1, k + 1))
    y[1:n, 1:m, :] += 0.3 * rng.standard_normal((n - 1, m - 1, k + 1))
    p = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    g = gl.tetrahedral_grid(p)
    geo = gl.compute_geometry(g)
    gl.check_grid(g, geo)
    assert geo.cell_volumes.sum() == pytest.approx(ConvexHull(p).volume, rel=1e-12)
    assert geo.cell_volumes.min() > 0


@pytest.mark.parametrize("angle", [0, 10, 30, 45, 60, 77])
def test_triangle_grid_of_rotated_lattice_at_utm(angle):
    """Round-off makes hull points of a rotated lattice not quite collinear: no slivers remain."""
    a = np.radians(angle)
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    x, y = np.meshgrid(np.arange(20) * 25.0, np.arange(15) * 25.0)
    p = np.column_stack([x.ravel(), y.ravel()]) @ rot.T + [5.3e5, 6.7e6]
    g = gl.triangle_grid(p)
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(19 * 14 * 625.0, rel=1e-9)
    assert geo.cell_volumes.min() > 1.0  # no sliver survives
    gl.check_grid(g, geo)


def test_surface_orientation_special_cases():
    single = gl.triangle_grid([[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    assert single.num_cells == 1
    # Two pentagons sharing two edges (a node of degree 2 on their interface).
    pts = [[0, 0], [1, 0], [2, 0], [2, 1], [1, 2], [0, 1], [1, 1]]
    cells = [[0, 1, 6, 4, 5], [1, 2, 3, 4, 6]]
    flat = gl.tessellation_grid(pts, cells)
    lifted = gl.tessellation_grid(np.column_stack([pts, np.full(7, 1000.0)]), [cells[0], cells[1][::-1]])
    a, b = gl.compute_geometry(flat), gl.compute_geometry(lifted)
    np.testing.assert_allclose(b.cell_volumes, a.cell_volumes, rtol=1e-14)
    gl.check_grid(lifted, b)
    # Many disconnected pieces are oriented piece by piece.
    tri = np.array([[0, 1, 2], [2, 1, 3]])
    quads = np.array([[0, 0], [1, 0], [0, 1], [1, 1.0]])
    pts3 = np.concatenate([np.column_stack([quads + 3 * k, np.zeros(4)]) for k in range(50)])
    tris = np.concatenate([tri[:, ::-1] + 4 * k if k % 3 else tri + 4 * k for k in range(50)])
    many = gl.triangle_grid(pts3, tris)
    gl.check_grid(many)


def test_builders_do_not_touch_or_alias_the_callers_arrays():
    base = np.random.default_rng(0).uniform(size=(40, 2))
    g = gl.triangle_grid(base[:20])
    assert base.flags.writeable
    base[0] += 100.0
    assert g.nodes.coords.max() < 1.5


@pytest.mark.parametrize(
    ("points", "triangles", "message"),
    [
        ([[0, 0], [1, 0]], None, "at least 3 points"),
        ([[0, 0], [1, 1], [2, 2], [3, 3]], None, "collinear"),
        ([[0, 0], [1, 0], [0, 1], [1, 0]], None, r"duplicate points \[1, 3\]"),
        ([[0, 0], [1, 0], [np.nan, 1]], None, "point 2 is NaN"),
        ([[0, 0], [1, 0], [0, 1]], [[0, 1, 5]], "node index 5 out of range"),
        ([[0, 0], [1, 0], [0, 1]], [["a", "b", "c"]], "must be integers"),
        ([[0, 0], [1, 0], [0, 1]], [[0, 1, -3]], r"node index -3 out of range \(-1 pads"),
        ([[0, 0], [1, 0], [2, 0]], [[0, 1, 2]], "zero area"),
        ([[0, 0], [1, 0], [0, 1], [5, 5]], [[0, 1, 2]], r"points \[3\] are used by no cell"),
        ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2], [1, 2, 0]], "cells 0 and 1 have the same nodes"),
        (
            [[0, 0], [1, 0], [0, 1], [1, 1], [0.5, -1]],
            [[0, 1, 2], [1, 3, 2], [0, 1, 4], [0, 1, 3]],
            "shared by more than two",
        ),
    ],
)
def test_triangle_grid_rejects_bad_input(points, triangles, message):
    with pytest.raises(gl.GridError, match=message):
        gl.triangle_grid(points, triangles)


def test_tetrahedral_grid_rejects_bad_input():
    with pytest.raises(gl.GridError, match="at least 4 points"):
        gl.tetrahedral_grid([[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    with pytest.raises(gl.GridError, match="coplanar"):
        gl.tetrahedral_grid([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]])
    with pytest.raises(gl.GridError, match="zero volume"):
        gl.tetrahedral_grid([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2, 3]])
