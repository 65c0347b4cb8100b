"""gridlib.io.shared_reads: inside shared_reads (a run of a case's stages) read_netcdf reads an
unchanged file once, gives each caller its own data, and reads a rewritten file again."""

from __future__ import annotations

import numpy as np
import pytest

import gridlib as gl
import gridlib.io.datasets as datasets
from gridlib.io import read_netcdf, write_netcdf
from gridlib.io.datasets import open_artifact, read_variable
from gridlib.io.netcdf_parts import length_of
from gridlib.io.shared_reads import shared_reads


def _openings(monkeypatch) -> list[str]:
    """The paths netCDF artifacts are opened at from now on."""
    opened: list[str] = []
    verified = datasets._open_verified

    def counting(path, cache=None):
        opened.append(str(path))
        return verified(path, cache)

    monkeypatch.setattr(datasets, "_open_verified", counting)
    return opened


def test_an_unchanged_file_is_read_once_and_each_caller_gets_its_own_data(tmp_path, monkeypatch):
    path = tmp_path / "grid.nc"
    grid = gl.cart_grid([3, 2, 1], [3.0, 2.0, 1.0])
    write_netcdf(path, grid, cell_data={"poro": np.arange(6) / 10.0}, attrs={"note": "first"})
    opened = _openings(monkeypatch)
    with shared_reads():
        first = read_netcdf(path)
        first.cell_data["poro"][:] = -1.0  # a caller changing its copy
        first.attrs["note"] = "changed"
        second = read_netcdf(path)
    assert opened == [str(path)]
    assert second.grid is first.grid  # shared: its arrays are read-only
    assert not second.grid.faces.neighbors.flags.writeable
    np.testing.assert_array_equal(second.cell_data["poro"], np.arange(6) / 10.0)
    assert second.attrs["note"] == "first"


def test_a_rewritten_file_is_read_again(tmp_path, monkeypatch):
    path = tmp_path / "grid.nc"
    write_netcdf(path, gl.cart_grid([3, 2, 1], [3.0, 2.0, 1.0]), cell_data={"poro": np.full(6, 0.1)})
    opened = _openings(monkeypatch)
    with shared_reads():
        before = read_netcdf(path)
        write_netcdf(path, gl.cart_grid([2, 2, 1], [2.0, 2.0, 1.0]), cell_data={"poro": np.full(4, 0.3)})
        after = read_netcdf(path)
    assert len(opened) == 2
    assert (before.grid.num_cells, after.grid.num_cells) == (6, 4)
    np.testing.assert_array_equal(after.cell_data["poro"], np.full(4, 0.3))


def test_outside_shared_reads_every_call_reads_the_file(tmp_path, monkeypatch):
    path = tmp_path / "grid.nc"
    write_netcdf(path, gl.cart_grid([2, 1, 1], [2.0, 1.0, 1.0]))
    opened = _openings(monkeypatch)
    with shared_reads():
        read_netcdf(path)
    read_netcdf(path)
    read_netcdf(path)
    assert len(opened) == 3


def test_a_small_file_is_opened_once_for_every_reader_and_closed_at_the_end(tmp_path, monkeypatch):
    path = tmp_path / "grid.nc"
    write_netcdf(path, gl.cart_grid([3, 2, 1], [3.0, 2.0, 1.0]), cell_data={"poro": np.arange(6) / 10.0})
    opened = _openings(monkeypatch)
    with shared_reads():
        read_netcdf(path)
        assert length_of(path, "poro") == 6
        with open_artifact(path) as ds:
            poro = read_variable(ds, "poro")
            poro[:] = -1.0  # a reader changing its values
            ds.attrs["note"] = "changed"
        with open_artifact(path) as ds:
            kept = ds
            np.testing.assert_array_equal(read_variable(ds, "poro"), np.arange(6) / 10.0)
            assert "note" not in ds.attrs
        assert opened == [str(path)]
        write_netcdf(path, gl.cart_grid([2, 2, 1], [2.0, 2.0, 1.0]), cell_data={"poro": np.full(4, 0.3)})
        assert length_of(path, "poro") == 4  # a rewritten file: opened again
        assert len(opened) == 2
        with open_artifact(path) as ds:
            read_variable(ds, "poro")
    assert len(opened) == 2
    with pytest.raises(RuntimeError):  # the handles are closed with the block
        kept["poro"].values  # noqa: B018


def test_a_large_file_is_opened_by_each_reader(tmp_path, monkeypatch):
    path = tmp_path / "grid.nc"
    write_netcdf(path, gl.cart_grid([3, 2, 1], [3.0, 2.0, 1.0]), cell_data={"poro": np.arange(6) / 10.0})
    monkeypatch.setattr(datasets, "KEPT_OPEN_BYTES", path.stat().st_size - 1)
    opened = _openings(monkeypatch)
    with shared_reads():
        assert length_of(path, "poro") == length_of(path, "poro") == 6
    assert len(opened) == 2
