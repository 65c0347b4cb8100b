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


def test_a_writer_choosing_by_suffix_gets_a_temporary_file_of_its_own(tmp_path):
    """write_keeping_suffix (pictures, VTP): the writer sees a temporary path with the target's
    suffix, unique to this write, in a folder created if missing; a failure leaves nothing."""
    from gridlib.io.atomic import write_keeping_suffix

    seen = []

    def write(path):
        seen.append(path)
        path.write_text("picture")

    umask = os.umask(0o022)
    try:
        write_keeping_suffix(tmp_path / "new" / "a.png", write)
        write_keeping_suffix(tmp_path / "new" / "a.png", write)
    finally:
        os.umask(umask)
    assert [p.suffix for p in seen] == [".png", ".png"] and seen[0] != seen[1]
    assert [p.name for p in (tmp_path / "new").iterdir()] == ["a.png"]
    assert stat.S_IMODE((tmp_path / "new" / "a.png").stat().st_mode) == 0o644

    def fail(path):
        path.write_text("half a picture")
        raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        write_keeping_suffix(tmp_path / "new" / "b.png", fail)
    assert [p.name for p in (tmp_path / "new").iterdir()] == ["a.png"]
