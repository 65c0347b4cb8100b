"""What bounds the memory of the 1e7-cell grid and export stages changes no bit: the closure
test of check_grid and the orientation angles of the export's summary a block at a time equal
those over the whole grid at once, the geometry without face centroids (check_grid's) has the
same bits, and cell data read only when written (Deferred) gives the same VTU and netCDF."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import xarray as xr

import gridlib as gl
from gridlib import checks, orientation
from gridlib.io import write_netcdf, write_vtu
from gridlib.io.deferred import Deferred
from gridlib.io.netcdf import deferred_data


@pytest.fixture(scope="module")
def twisted():
    grid = gl.twister(gl.cart_grid([7, 5, 4], [700.0, 500.0, 40.0]))
    return grid, gl.compute_geometry(grid)


def _closure_whole(grid, geometry):
    """The closure defect over the surface area of every cell, over all half-faces at once."""
    hc = np.repeat(np.arange(grid.num_cells), np.diff(grid.cells.face_pos))
    cf = grid.cells.faces
    s = np.where(grid.faces.neighbors[cf, 0] == hc, 1.0, -1.0)
    net = np.stack([np.bincount(hc, s * geometry.face_normals[cf, i], grid.num_cells) for i in range(3)])
    surface = np.bincount(hc, geometry.face_areas[cf], grid.num_cells)
    return np.sqrt((net * net).sum(axis=0)) / surface


def test_closure_block_by_block_is_that_of_the_whole_grid(twisted, monkeypatch):
    grid, geo = twisted
    rng = np.random.default_rng(3)
    normals = np.array(geo.face_normals)
    tilted = rng.choice(grid.num_faces, 9, replace=False)
    normals[tilted] += 1e-6 * geo.face_areas[tilted, None] * rng.normal(size=(9, 3))
    geo = dataclasses.replace(geo, face_normals=normals)
    monkeypatch.setattr(checks, "_CELLS", 11)  # 140 cells: 13 blocks, the last one short
    cells = checks.degenerate_cells(grid, geo, 1e-10)
    expected = _closure_whole(grid, geo)
    assert cells.not_closed.tolist() == np.flatnonzero(expected > 1e-10).tolist()
    assert 9 <= cells.not_closed.size <= 18  # each tilted face opens its cell(s)
    assert cells.closure.tobytes() == expected[cells.not_closed].tobytes()


def test_face_angles_block_by_block_are_those_of_one_block(twisted, monkeypatch):
    grid, geo = twisted
    centres = np.array(geo.cell_centroids)
    centres[[4, 60]] = np.nan  # a cell without a centre: its faces are left out
    perm = np.random.default_rng(5).uniform(1.0, 500.0, size=(grid.num_cells, 3))
    perm[17] = 0.0  # no permeability: it does not count
    whole = orientation.face_angles(grid.faces.neighbors, geo.face_normals, centres, perm)
    monkeypatch.setattr(orientation, "_FACES", 37)
    blocks = orientation.face_angles(grid.faces.neighbors, geo.face_normals, centres, perm)
    assert blocks.faces.tolist() == whole.faces.tolist()
    assert blocks.angles.tobytes() == whole.angles.tobytes()
    assert blocks.k_angles.tobytes() == whole.k_angles.tobytes()
    interior = (grid.faces.neighbors >= 0).all(axis=1) & ~np.isin(grid.faces.neighbors, [4, 60]).any(axis=1)
    assert whole.faces.tolist() == np.flatnonzero(interior).tolist()
    assert 0.0 < np.nanmax(whole.angles) < 90.0  # twisted: off the centre line, never across it


def test_geometry_without_face_centroids_has_the_same_bits(twisted):
    grid, full = twisted
    lean = gl.compute_geometry(grid, face_centroids=False)
    assert lean.face_centroids.shape == (0, 3)
    for name in ("cell_volumes", "cell_centroids", "face_areas", "face_normals"):
        assert getattr(lean, name).tobytes() == getattr(full, name).tobytes(), name


def _deferred(values, reads):
    """``values`` as a Deferred array that counts its reads in ``reads``."""

    def load():
        reads.append(1)
        return values

    return Deferred(values.shape, values.dtype, load)


def test_deferred_cell_data_write_the_same_vtu_and_netcdf(twisted, tmp_path):
    """Cell data read only when written: the same VTU bytes and the same netCDF variables, each
    array read once per file."""
    grid, geo = twisted
    rng = np.random.default_rng(9)
    data = {"poro": rng.uniform(0.1, 0.3, grid.num_cells), "block": rng.integers(0, 9, grid.num_cells)}
    data["centroid"] = geo.cell_centroids
    reads = []
    lazy = {name: _deferred(values, reads) for name, values in data.items()}
    for compress in (True, False):
        eager = write_vtu(tmp_path / f"eager_{compress}.vtu", grid, data, compress=compress).read_bytes()
        assert (
            write_vtu(tmp_path / f"lazy_{compress}.vtu", grid, lazy, compress=compress).read_bytes() == eager
        )
    assert len(reads) == 2 * len(data)
    assert not [p for p in tmp_path.iterdir() if p.suffix != ".vtu"]  # no scratch file is left
    pairs = np.column_stack([np.arange(5), np.arange(1, 6)])
    extra = {"pair": xr.Variable(("pair_row", "two"), pairs, {"long_name": "pairs"})}
    lazy_extra = {
        "pair": xr.Variable(
            ("pair_row", "two"), deferred_data(_deferred(pairs, reads)), {"long_name": "pairs"}
        )
    }
    write_netcdf(tmp_path / "eager.nc", grid, geo, cell_data=data, extra=extra)
    write_netcdf(tmp_path / "lazy.nc", grid, geo, cell_data=lazy, extra=lazy_extra)
    assert len(reads) == 3 * len(data) + 1
    with xr.open_dataset(tmp_path / "eager.nc") as a, xr.open_dataset(tmp_path / "lazy.nc") as b:
        assert list(a.variables) == list(b.variables)
        for name in a.variables:
            assert a[name].dtype == b[name].dtype and a[name].values.tobytes() == b[name].values.tobytes(), (
                name
            )
            assert repr(a[name].attrs) == repr(b[name].attrs), name


def test_small_files_are_read_at_once_large_ones_deferred_with_the_same_values(tmp_path, monkeypatch):
    """The export's quality measures and connection variables: read in one opening of their
    file below EAGER_BYTES (a small case), Deferred above it (a 1e7-cell one), the same values
    and attributes either way."""
    from gridlib.io import deferred
    from gridlib.io.netcdf import write_dataset
    from gridlib.io.quality_file import deferred_quality, write_quality
    from gridlib.io.transmissibility_file import connections_dataset, deferred_connection_variables
    from gridlib.transmissibility import Connections
    from gridlib.units import METRIC

    n = 40
    rng = np.random.default_rng(3)
    measures = {"orientation_error": rng.uniform(0.0, 30.0, n), "aspect_ratio": rng.uniform(1.0, 5.0, n)}
    write_quality(tmp_path / "quality.nc", measures, {"case": "q"}, [{"quantity": "aspect_ratio"}])
    cells = np.column_stack([np.arange(n - 1), np.arange(1, n)])
    conn = Connections(cells, None, rng.uniform(0.1, 9.0, n - 1), np.zeros(n - 1), np.arange(n - 1))
    ds = connections_dataset(conn, rng.uniform(1.0, 2.0, n), np.arange(n), (n, 1, 1), METRIC)
    write_dataset(tmp_path / "transmissibility.nc", ds)

    def read():
        return deferred_quality(tmp_path / "quality.nc"), deferred_connection_variables(
            tmp_path / "transmissibility.nc"
        )

    (eager, eager_qc), eager_vars = read()
    monkeypatch.setattr(deferred, "EAGER_BYTES", 0)
    (lazy, lazy_qc), lazy_vars = read()
    assert all(type(v) is np.ndarray for v in eager.values())
    assert all(isinstance(v, Deferred) for v in lazy.values())
    assert eager_qc == lazy_qc == [{"quantity": "aspect_ratio"}]
    assert list(eager) == list(lazy) == ["orientation_error", "aspect_ratio"]  # MEASURES' order
    for name, values in measures.items():
        assert np.asarray(eager[name]).tobytes() == np.asarray(lazy[name]).tobytes() == values.tobytes()
    assert list(eager_vars) == list(lazy_vars)
    for name, var in eager_vars.items():
        assert var._in_memory and not lazy_vars[name]._in_memory, name
        assert var.values.tobytes() == lazy_vars[name].values.tobytes(), name
        assert var.dims == lazy_vars[name].dims and repr(var.attrs) == repr(lazy_vars[name].attrs), name
    assert eager_vars["trans"].values.tobytes() == conn.trans.tobytes()


def test_a_deferred_array_read_with_another_shape_is_refused(twisted, tmp_path):
    grid, _ = twisted
    wrong = Deferred((grid.num_cells,), np.dtype(np.float64), lambda: np.zeros(3), "quality.nc: twist")
    with pytest.raises(
        ValueError, match=r"quality.nc: twist: read float64 \(3,\), expected float64 \(140,\)"
    ):
        write_vtu(tmp_path / "x.vtu", grid, {"twist": wrong})
    assert not list(tmp_path.iterdir())


def test_fault_face_trans_from_the_connections_beside_the_faults():
    """The export's T of the fault faces, looked up among the connections of cells beside a
    fault, equals the lookup of every face among all connections (the first of equal pairs)."""
    from wedge_decks import wedge_deck

    from gridlib.cornerpoint.process import process_grdecl
    from gridlib.stages.export import _face_trans
    from gridlib.transmissibility import face_connections

    grid = process_grdecl(wedge_deck()).grid
    nb = grid.faces.neighbors
    pairs = np.unique(np.sort(nb[(nb >= 0).all(axis=1)], axis=1), axis=0)
    rng = np.random.default_rng(4)
    cells = np.concatenate([pairs, pairs[rng.choice(len(pairs), 7)]])[rng.permutation(len(pairs) + 7)]
    variables = {
        "connection_cells": xr.DataArray(cells),
        "trans": xr.DataArray(rng.uniform(1, 2, len(cells))),
    }
    conn = face_connections(nb, cells)
    whole = np.where(conn >= 0, variables["trans"].values[np.maximum(conn, 0)], 0.0)
    faults = grid.faces.tag > 0
    assert faults.sum() > 10 and (whole[faults] > 0).sum() > 5
    got = _face_trans(grid, variables)
    assert got[faults].tobytes() == whole[faults].tobytes() and not got[~faults].any()
