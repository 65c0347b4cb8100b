"""Coarse grids: partitions, the coarse grid and its geometry, upscaling."""

from __future__ import annotations

import numpy as np
import pytest

import gridlib as gl
from gridlib.coarsen import (
    coarse_grid,
    compress_partition,
    partition_metis,
    partition_ui,
    process_partition,
    upscale_permeability,
    upscale_porosity,
)
from gridlib.cornerpoint import process_grdecl, simple_grdecl
from gridlib.errors import InputError
from gridlib.grid import E, N, S, W
from gridlib.io import write_netcdf, write_vtu


def _invariants(fine: gl.Grid, cg, geo=None) -> None:
    geo = geo or gl.compute_geometry(fine)
    # Volumes add up; every block is connected; every fine face is in one coarse face or inside a block.
    assert cg.geometry.cell_volumes.sum() == pytest.approx(geo.cell_volumes.sum(), rel=1e-12)
    assert np.array_equal(process_partition(fine, cg.partition), cg.partition)
    p = cg.partition
    nb = fine.faces.neighbors
    blocks = np.where(nb >= 0, p[np.maximum(nb, 0)], -1)
    inside = blocks[:, 0] == blocks[:, 1]
    assert np.all((cg.coarse_face_of >= 0) == ~inside)
    counts = np.bincount(cg.faces.fine, minlength=fine.num_faces)
    assert np.all(counts[~inside] == 1) and np.all(counts[inside] == 0)
    # Coarse normals are the signed sums of the fine ones; signs agree with the blocks.
    owner = np.repeat(np.arange(cg.faces.num), np.diff(cg.faces.pos))
    first = np.where(cg.faces.sign > 0, blocks[cg.faces.fine, 0], blocks[cg.faces.fine, 1])
    assert np.array_equal(first, cg.faces.neighbors[owner, 0])
    # The blocks are a grid like any other: its polyhedra hold the block volumes.
    cgeo = gl.compute_geometry(cg.grid)
    gl.check_grid(cg.grid, cgeo)
    np.testing.assert_allclose(cgeo.cell_volumes, cg.geometry.cell_volumes, rtol=1e-11)


def test_cart_4x4_in_2x2_blocks():
    g = gl.cart_grid([4, 4])
    cg = coarse_grid(g, partition_ui(g, [2, 2]))
    assert cg.num_blocks == 4 and cg.faces.num == 12
    np.testing.assert_array_equal(cg.geometry.cell_volumes, [4.0, 4.0, 4.0, 4.0])
    inner = (cg.faces.neighbors >= 0).all(axis=1)
    assert int(inner.sum()) == 4  # two x-interfaces and two y-interfaces
    np.testing.assert_array_equal(cg.geometry.face_areas[inner], 2.0)
    np.testing.assert_allclose(cg.geometry.projected_areas, cg.geometry.face_areas)
    # Block 0 (lower left) has its own W and S boundary faces.
    b0 = (cg.faces.neighbors[:, 1] == 0) & ~inner
    assert int(b0.sum()) == 2
    tags = cg.grid.cells.face_tag[cg.grid.cells.face_pos[0] : cg.grid.cells.face_pos[1]]
    assert sorted(set(tags.tolist())) == sorted({W, E, S, N})
    _invariants(g, cg)


def test_removed_octant_leaves_an_empty_block_that_disappears():
    g = gl.cart_grid([20, 20, 6])
    geo = gl.compute_geometry(g)
    c = geo.cell_centroids
    g = gl.remove_cells(g, np.flatnonzero((c[:, 0] < 10) & (c[:, 1] < 10) & (c[:, 2] < 3)))
    assert g.num_cells == 2100
    raw = partition_ui(g, [2, 2, 2])
    assert set(np.unique(raw)) == set(range(1, 8))  # block 0 (the removed octant) has no cell
    cg = coarse_grid(g, compress_partition(raw))
    assert cg.num_blocks == 7
    np.testing.assert_allclose(cg.geometry.cell_volumes, 300.0)
    _invariants(g, cg)
    with pytest.raises(InputError, match="block 0 has no cell"):
        coarse_grid(g, raw)


def test_faulted_corner_point_grid_in_25_blocks():
    r = process_grdecl(simple_grdecl([20, 20, 5], 0.05, flat=True))
    g = r.grid
    cg = coarse_grid(g, process_partition(g, partition_ui(g, [5, 5, 1])))
    assert cg.num_blocks == 25
    _invariants(g, cg)
    assert np.any(cg.grid.faces.tag > 0)  # the fault faces keep their tag


def test_pore_volume_is_conserved_and_constants_stay_constant():
    g = gl.cart_grid([12, 10, 4], [120.0, 100.0, 8.0])
    geo = gl.compute_geometry(g)
    rng = np.random.default_rng(0)
    phi = rng.uniform(0.05, 0.35, g.num_cells)
    cg = coarse_grid(g, partition_ui(g, [3, 2, 2]), geo)
    phi_c = upscale_porosity(cg, phi, geo.cell_volumes)
    assert (phi_c * cg.geometry.cell_volumes).sum() == pytest.approx(
        (phi * geo.cell_volumes).sum(), rel=1e-13
    )
    for method in ("arithmetic", "harmonic", "geometric", "harmonic-arithmetic"):
        np.testing.assert_allclose(
            upscale_permeability(cg, np.full((g.num_cells, 3), 150.0), geo.cell_volumes, method),
            150.0,
            rtol=1e-13,
        )


def test_layered_medium_arithmetic_along_harmonic_across():
    g = gl.cart_grid([6, 4, 5])
    geo = gl.compute_geometry(g)
    k_layer = np.array([10.0, 200.0, 1.0, 50.0, 5.0])
    layer = g.cells.index_map // 24
    perm = np.repeat(k_layer[layer][:, None], 3, axis=1)
    cg = coarse_grid(g, partition_ui(g, [2, 1, 1]))
    k = upscale_permeability(cg, perm, geo.cell_volumes, "harmonic-arithmetic")
    np.testing.assert_allclose(k[:, 0], k_layer.mean(), rtol=1e-14)  # along the layers
    np.testing.assert_allclose(k[:, 1], k_layer.mean(), rtol=1e-14)
    np.testing.assert_allclose(k[:, 2], 1.0 / (1.0 / k_layer).mean(), rtol=1e-14)  # across them
    arith = upscale_permeability(cg, perm, geo.cell_volumes, "arithmetic")
    harm = upscale_permeability(cg, perm, geo.cell_volumes, "harmonic")
    geom = upscale_permeability(cg, perm, geo.cell_volumes, "geometric")
    np.testing.assert_allclose(arith[:, 2], k_layer.mean(), rtol=1e-14)
    np.testing.assert_allclose(harm[:, 0], 1.0 / (1.0 / k_layer).mean(), rtol=1e-14)
    np.testing.assert_allclose(geom[:, 0], np.exp(np.log(k_layer).mean()), rtol=1e-14)
    assert np.all(harm <= geom) and np.all(geom <= arith)  # Wiener bounds around the geometric mean


def test_process_partition_splits_what_is_not_connected():
    g = gl.cart_grid([6, 6])
    ij = np.unravel_index(g.cells.index_map, (6, 6))
    checker = (ij[0] + ij[1]) % 2  # two blocks, no two cells of a block share a face
    assert np.unique(process_partition(g, checker)).size == 36
    stripes = np.where(ij[1] % 3 == 1, 1, 0)  # columns i = 1, 4 in block 1: strips 0 | 1 | 2-3 | 4 | 5
    assert np.unique(process_partition(g, stripes)).size == 5
    # A barrier face cuts a block in two.
    p = np.zeros(g.num_cells, dtype=np.int64)
    x_faces = np.flatnonzero(np.abs(gl.compute_geometry(g).face_centroids[:, 0] - 3.0) < 1e-12)
    assert np.unique(process_partition(g, p, barrier_faces=x_faces)).size == 2


def test_metis_blocks_are_connected_balanced_and_reproducible():
    g = gl.cart_grid([30, 20, 4])
    a = partition_metis(g, 12, seed=3)
    b = partition_metis(g, 12, seed=3)
    np.testing.assert_array_equal(a, b)
    assert np.unique(a).size >= 12
    np.testing.assert_array_equal(process_partition(g, a), a)
    sizes = np.bincount(a)
    assert sizes.max() <= 1.2 * g.num_cells / 12
    cg = coarse_grid(g, a)
    _invariants(g, cg)
    # Heavy faces are not cut: weight the k-faces strongly, blocks become columns.
    geo = gl.compute_geometry(g)
    weights = np.where(np.abs(geo.face_normals[:, 2]) > 0, 1e6, 1.0)
    cols = partition_metis(g, 12, face_weights=weights)
    ijk = np.unravel_index(g.cells.index_map, (4, 20, 30))
    column = ijk[1] * 30 + ijk[2]
    per_column = [np.unique(cols[column == c]).size for c in range(600)]
    assert np.mean(per_column) < 1.05


def test_layered_pebi_grid_in_areal_blocks_and_layers():
    x, y = np.meshgrid(np.arange(12.0), np.arange(10.0))
    areal = gl.pebi(gl.triangle_grid(np.column_stack([x.ravel(), y.ravel()])))
    g = gl.make_layered_grid(areal, thickness=[1.0, 2.0, 1.0, 2.0])
    p = process_partition(g, partition_ui(g, [3, 2, 2]))
    cg = coarse_grid(g, p)
    assert cg.num_blocks == 12
    _invariants(g, cg)


def test_coarse_grid_writes_to_netcdf_and_vtu(tmp_path):
    import pyvista as pv

    g = gl.cart_grid([8, 6, 3])
    cg = coarse_grid(g, partition_ui(g, [2, 3, 1]))
    write_netcdf(tmp_path / "coarse.nc", cg.grid)
    write_vtu(tmp_path / "coarse.vtu", cg.grid)
    mesh = pv.read(tmp_path / "coarse.vtu")
    assert mesh.n_cells == 6
    np.testing.assert_allclose(mesh.compute_cell_sizes()["Volume"], 24.0, rtol=1e-12)


def test_bad_partitions_are_clear_errors():
    g = gl.cart_grid([4, 3])
    with pytest.raises(InputError, match="5 blocks along i, but only 4 cells there"):
        partition_ui(g, [5, 1])
    with pytest.raises(InputError, match="13 blocks for 12 cells"):
        partition_metis(g, 13)
    with pytest.raises(InputError, match="one block per cell"):
        coarse_grid(g, np.zeros(5, dtype=np.int64))
    with pytest.raises(InputError, match="method must be one of"):
        upscale_permeability(coarse_grid(g, np.zeros(12, dtype=np.int64)), np.ones(12), np.ones(12), "mean")
    with pytest.raises(InputError, match="neither logical indices"):
        partition_ui(gl.triangle_grid(np.random.default_rng(0).random((20, 2))), [2, 2])
