"""Atomic writes (gridlib.io.atomic) through the grid writers: a failed write leaves no file, a
written file gets the usual permissions."""

from __future__ import annotations

import os
import stat

import numpy as np
import pytest

import gridlib as gl
from gridlib.io import write_netcdf, write_vtu


def test_failed_write_leaves_no_file(tmp_path):
    g = gl.cart_grid([2, 2])
    with pytest.raises(gl.GridError, match="cell data 'poro' has shape"):
        write_netcdf(tmp_path / "bad.nc", g, cell_data={"poro": np.ones(3)})
    with pytest.raises(gl.GridError, match="cell data 'poro' must have shape"):
        write_vtu(tmp_path / "bad.vtu", g, {"poro": np.ones(3)})
    assert list(tmp_path.iterdir()) == []


def test_written_files_get_the_usual_permissions(tmp_path):
    umask = os.umask(0o022)
    try:
        write_netcdf(tmp_path / "a.nc", gl.cart_grid([2, 2]))
        write_vtu(tmp_path / "a.vtu", gl.cart_grid([2, 2]))
    finally:
        os.umask(umask)
    for name in ("a.nc", "a.vtu"):
        assert stat.S_IMODE((tmp_path / name).stat().st_mode) == 0o644
