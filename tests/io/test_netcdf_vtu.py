"""netCDF round trips (lossless), UGRID for xugrid, VTU for pyvista/VTK."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import pyvista as pv
import xarray as xr
from seed_points import honeycomb_points

import gridlib as gl
from gridlib.io import read_netcdf, write_netcdf, write_vtu


def _grids():
    areal = gl.pebi(gl.triangle_grid(honeycomb_points()))
    layered = gl.make_layered_grid(areal, 3)
    return {
        "cart": gl.cart_grid([3, 2, 2]),
        "areal_pebi": areal,
        "layered": layered,
        "layered_removed": gl.remove_cells(layered, [0, 5, 77]),
        "twisted": gl.twister(gl.cart_grid([4, 3, 2])),
        "surface": gl.triangle_grid(np.column_stack([honeycomb_points(), np.arange(40.0)])),
    }


def _same_grid(a: gl.Grid, b: gl.Grid) -> None:
    parts = {
        "cells": ("face_pos", "faces", "face_tag", "index_map"),
        "faces": ("node_pos", "nodes", "neighbors", "tag"),
        "nodes": ("coords",),
    }
    for part, fields in parts.items():
        for name in fields:
            x, y = getattr(getattr(a, part), name), getattr(getattr(b, part), name)
            assert (x is None) == (y is None), (part, name)
            if x is not None:
                assert x.dtype == y.dtype and np.array_equal(x, y), (part, name)
    assert (a.griddim, a.cart_dims, a.history) == (b.griddim, b.cart_dims, b.history)


@pytest.mark.parametrize("name", ["cart", "areal_pebi", "layered", "layered_removed", "twisted", "surface"])
def test_netcdf_round_trip_is_lossless(tmp_path, name):
    g = _grids()[name]
    geo = gl.compute_geometry(g)
    rng = np.random.default_rng(0)
    cell = {
        "poro": rng.uniform(0.1, 0.3, g.num_cells),
        "facies": rng.integers(0, 4, g.num_cells).astype(np.int32),
    }
    face = {"trans": rng.uniform(size=g.num_faces)}
    path = write_netcdf(tmp_path / f"{name}.nc", g, geo, cell, face, attrs={"case": name, "seed": 7})
    back = read_netcdf(path)
    _same_grid(g, back.grid)
    for field in ("cell_volumes", "cell_centroids", "face_areas", "face_normals", "face_centroids"):
        assert np.array_equal(getattr(geo, field), getattr(back.geometry, field)), field
    for key, values in cell.items():
        assert back.cell_data[key].dtype == values.dtype and np.array_equal(back.cell_data[key], values)
    assert np.array_equal(back.face_data["trans"], face["trans"])
    assert back.attrs["case"] == name and back.attrs["seed"] == 7
    if g.layering is not None:
        assert back.grid.layering.num_layers == g.layering.num_layers
        assert np.array_equal(back.grid.layering.column, g.layering.column)
        _same_grid(g.layering.areal, back.grid.layering.areal)


def test_ugrid_footprint_opens_in_xugrid(tmp_path):
    import xugrid as xu  # a test dependency: a missing install fails here, it never skips

    g = gl.remove_cells(_grids()["layered"], [3])
    poro = np.linspace(0.1, 0.3, g.num_cells)
    write_netcdf(tmp_path / "lay.nc", g, cell_data={"poro": poro})
    ds = xu.open_dataset(tmp_path / "lay.nc")
    assert ds.ugrid.grid.n_face == 40 and ds.ugrid.grid.n_node == 84
    view = ds["poro_layered"].values
    assert view.shape == (3, 40) and np.isnan(view[0, 3])
    np.testing.assert_array_equal(view[g.layering.layer, g.layering.column], poro)
    with xr.open_dataset(tmp_path / "lay.nc") as plain:
        assert plain.attrs["Conventions"] == "CF-1.11 UGRID-1.0"
        assert plain["node_z"].attrs["positive"] == "down"
    areal = _grids()["areal_pebi"]
    write_netcdf(tmp_path / "areal.nc", areal, cell_data={"area": gl.compute_geometry(areal).cell_volumes})
    ds2 = xu.open_dataset(tmp_path / "areal.nc")
    np.testing.assert_allclose(ds2.ugrid.grid.area, ds2["area"].values, rtol=1e-12)


@pytest.mark.parametrize("name", ["cart", "layered", "layered_removed", "areal_pebi", "surface"])
def test_vtu_read_by_pyvista_has_our_volumes(tmp_path, name):
    g = _grids()[name]
    geo = gl.compute_geometry(g)
    poro = np.linspace(0.1, 0.3, g.num_cells)
    write_vtu(tmp_path / "g.vtu", g, {"poro": poro, "centroid": geo.cell_centroids})
    mesh = pv.read(tmp_path / "g.vtu")
    assert mesh.n_cells == g.num_cells and mesh.n_points == g.num_nodes
    np.testing.assert_array_equal(mesh.cell_data["poro"], poro)
    assert mesh.cell_data["centroid"].shape == (g.num_cells, g.dim)
    sizes = mesh.compute_cell_sizes(length=False, area=g.griddim == 2, volume=g.griddim == 3)
    vtk_measure = sizes.cell_data["Volume" if g.griddim == 3 else "Area"]
    np.testing.assert_allclose(vtk_measure, geo.cell_volumes, rtol=1e-9)


def test_reading_bad_files_names_the_file(tmp_path):
    with pytest.raises(gl.InputError, match=r"missing\.nc: no such file"):
        read_netcdf(tmp_path / "missing.nc")
    (tmp_path / "junk.nc").write_text("not netcdf")
    with pytest.raises(gl.InputError, match=r"junk\.nc: damaged or incomplete \(not a netCDF-4 file"):
        read_netcdf(tmp_path / "junk.nc")
    xr.Dataset({"x": ("n", np.arange(3))}).to_netcdf(tmp_path / "other.nc")
    with pytest.raises(gl.InputError, match=r"other\.nc: .*gridlib_griddim"):
        read_netcdf(tmp_path / "other.nc")


def test_layering_of_a_grid_extruded_from_a_surface_round_trips(tmp_path):
    p = np.random.default_rng(0).uniform(size=(20, 2)) * 100
    surface = gl.triangle_grid(np.column_stack([p, 1000 + 0.1 * p[:, 0]]))
    g = gl.make_layered_grid(surface, 2)
    write_netcdf(tmp_path / "s.nc", g, cell_data={"poro": np.full(g.num_cells, 0.2)})
    back = read_netcdf(tmp_path / "s.nc")
    assert back.grid.layering is not None and back.grid.layering.num_layers == 2
    _same_grid(g.layering.areal, back.grid.layering.areal)
    assert sorted(back.cell_data) == ["poro"]


def test_netcdf_refuses_names_and_attributes_it_cannot_keep(tmp_path):
    g = gl.cart_grid([3, 2, 2])
    for kwargs, message in [
        ({"cell_data": {"cell_volume": np.ones(12)}}, r"data names \['cell_volume'\] are used by gridlib"),
        ({"face_data": {"face_tag": np.ones(g.num_faces)}}, r"data names \['face_tag'\]"),
        ({"cell_data": {"node_x": np.ones(12)}}, r"data names \['node_x'\]"),
        ({"attrs": {"flag": True}}, "attribute 'flag' is True"),
        ({"attrs": {"seed": None}}, "attribute 'seed' is None"),
        ({"attrs": {"gridlib_history": "x"}}, "attribute name 'gridlib_history' is reserved"),
    ]:
        with pytest.raises(gl.GridError, match=message):
            write_netcdf(tmp_path / "x.nc", g, **kwargs)
    assert not (tmp_path / "x.nc").exists()
    # Names that merely look like ours are user data and come back.
    write_netcdf(tmp_path / "ok.nc", g, cell_data={"poro_layered": np.ones(12), "areal_poro": np.ones(12)})
    assert sorted(read_netcdf(tmp_path / "ok.nc").cell_data) == ["areal_poro", "poro_layered"]


def test_vtu_escapes_data_names(tmp_path):
    g = gl.cart_grid([2, 2, 2])
    write_vtu(tmp_path / "e.vtu", g, {'perm x&y <"k">': np.arange(8.0)})
    mesh = pv.read(tmp_path / "e.vtu")
    np.testing.assert_array_equal(mesh.cell_data['perm x&y <"k">'], np.arange(8.0))


def _awkward_values(n: int, rng: np.random.Generator) -> np.ndarray:
    """Doubles a lossy or sloppy codec would change: NaN, infinities, -0.0, subnormals, extremes."""
    values = rng.standard_normal(n) * 10.0 ** rng.integers(-300, 300, n)
    special = [np.nan, np.inf, -np.inf, -0.0, 5e-324, -2.2e-308, np.finfo(float).max, np.finfo(float).tiny]
    values[: len(special)] = special
    return values


@pytest.mark.parametrize(
    ("policy", "filters"),
    [
        (None, {"zstd"}),  # the default where netCDF4 has Zstandard (the PyPI wheels do)
        ({"zlib": True, "complevel": 1, "shuffle": True}, {"zlib", "shuffle"}),  # the fallback
    ],
    ids=["default", "deflate"],
)
def test_netcdf_variables_are_compressed_and_read_back_bit_for_bit(tmp_path, monkeypatch, policy, filters):
    from gridlib.io import datasets as _dataset

    if policy is not None:
        monkeypatch.setattr(_dataset, "COMPRESSION", policy)
    g = gl.cart_grid([60, 50, 40])  # 1.2e5 cells: many HDF5 chunks per variable
    rng = np.random.default_rng(11)
    cell = {
        "awkward": _awkward_values(g.num_cells, rng),
        "facies": rng.integers(-(2**62), 2**62, g.num_cells),
        "flag": rng.integers(0, 2, g.num_cells).astype(np.int8),
    }
    path = write_netcdf(tmp_path / "g.nc", g, cell_data=cell)
    back = read_netcdf(path)
    for key, values in cell.items():
        got = back.cell_data[key]
        assert got.dtype == values.dtype and got.tobytes() == values.tobytes(), key
    _same_grid(g, back.grid)
    with xr.open_dataset(path) as ds:
        numeric = [name for name in ds.variables if ds[name].dtype.kind in "biuf" and ds[name].size > 0]
        assert numeric and all(ds[name].encoding[f] for name in numeric for f in filters)
        assert ds["awkward"].encoding["complevel"] == 1
    raw = sum(v.nbytes for v in cell.values()) + g.faces.nodes.nbytes + g.cells.faces.nbytes
    assert path.stat().st_size < raw  # the regular topology deflates far below its raw size


def test_vtu_is_zlib_compressed_and_reads_back_bit_for_bit(tmp_path):
    # 131,072 cells: a float64 cell array is exactly one full 1 MiB block, the points several
    g = gl.cart_grid([64, 64, 32])
    rng = np.random.default_rng(12)
    data = {
        "awkward": _awkward_values(g.num_cells, rng),
        "layer": np.repeat(np.arange(32), 64 * 64).astype(np.int32),
        "vector": rng.uniform(size=(g.num_cells, 3)),
    }
    packed = write_vtu(tmp_path / "z.vtu", g, data)
    plain = write_vtu(tmp_path / "raw.vtu", g, data, compress=False)
    assert b'compressor="vtkZLibDataCompressor"' in packed.read_bytes()[:400]
    assert packed.stat().st_size < plain.stat().st_size / 2
    a, b = pv.read(packed), pv.read(plain)
    for key, values in data.items():
        assert a.cell_data[key].tobytes() == values.tobytes(), key
    assert np.asarray(a.points).tobytes() == np.asarray(b.points).tobytes()
    assert np.array_equal(a.celltypes, b.celltypes) and a.n_cells == g.num_cells
    assert np.array_equal(a.cell_connectivity, b.cell_connectivity)


@pytest.mark.parametrize("compress", [True, False])
def test_vtu_written_in_cell_blocks_is_the_same_file(tmp_path, monkeypatch, compress):
    """Cells laid out a few at a time (ragged blocks, split polyhedra streams and offsets)
    give exactly the bytes of one block of all cells."""
    from gridlib.io import vtu

    g = gl.remove_cells(gl.make_layered_grid(gl.pebi(gl.triangle_grid(honeycomb_points())), 3), [4, 50])
    data = {
        "a": np.arange(g.num_cells, dtype=float),
        "v": np.ones((g.num_cells, 3)),
        "k": np.ones(g.num_cells, bool),
    }
    whole = write_vtu(tmp_path / "whole.vtu", g, data, compress=compress).read_bytes()
    monkeypatch.setattr(vtu, "BLOCK_CELLS", 7)
    assert write_vtu(tmp_path / "blocks.vtu", g, data, compress=compress).read_bytes() == whole
    monkeypatch.setattr(vtu, "BLOCK_BYTES", 100)  # many zlib blocks, a partial last one
    mesh = pv.read(write_vtu(tmp_path / "small.vtu", g, data, compress=compress))
    assert mesh.cell_data["a"].tobytes() == data["a"].tobytes() and mesh.n_cells == g.num_cells


def test_vtk_files_store_elevation_and_keep_outward_faces(tmp_path):
    """z_vtk = -depth in the VTU: an anticline's crest (shallowest cell) is the highest in VTK,
    and the reflected polyhedra still have positive volumes (faces outward)."""
    g = gl.cart_grid([5, 5, 2], [2.0, 2.0, 1.0])
    xy = g.nodes.coords[:, :2] - 1.0
    coords = g.nodes.coords.copy()
    coords[:, 2] += 1000.0 + 0.1 * (xy**2).sum(axis=1)  # deeper away from the centre: an anticline
    g = dataclasses.replace(g, nodes=dataclasses.replace(g.nodes, coords=coords))
    geo = gl.compute_geometry(g)
    write_vtu(tmp_path / "a.vtu", g, {"depth": geo.cell_centroids[:, 2]})
    mesh = pv.read(tmp_path / "a.vtu")
    np.testing.assert_array_equal(mesh.points[:, 2], -coords[:, 2])
    crest = np.argmin(mesh.cell_data["depth"])
    assert np.argmax(mesh.cell_centers().points[:, 2]) == crest
    volumes = mesh.compute_cell_sizes(length=False, area=False, volume=True).cell_data["Volume"]
    np.testing.assert_allclose(volumes, geo.cell_volumes, rtol=1e-9)
    assert volumes.min() > 0
