"""ParaView time series (gridlib.io.pvd): pyvista's PVDReader reads every step with its time and
values; each step's VTU is byte for byte the VTU of the grid alone (the geometry laid out once);
a second series replaces the first's folder whole; bad times are refused before any file."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv

import gridlib as gl
from gridlib.errors import GridError
from gridlib.io.pvd import write_pvd, write_vtu_series
from gridlib.io.vtu import write_vtu


def steps(grid, times):
    cells = np.arange(grid.num_cells, dtype=np.float64)
    for index, t in enumerate(times):
        yield index, t, {"pressure": 200.0 + t * cells, "swat": np.full(grid.num_cells, 0.2 + t / 1000.0)}


def test_pyvista_reads_every_step_and_its_values(tmp_path):
    grid = gl.twister(gl.cart_grid([3, 2, 2]))
    times = [0.0, 90.0, 180.5]
    pvd = write_vtu_series(tmp_path / "flow" / "x_flow.pvd", grid, steps(grid, times), note="pressure [bar]")
    reader = pv.PVDReader(pvd)
    assert reader.time_values == times
    assert [d.path for d in reader.datasets] == [f"x_flow/x_flow_{k:04d}.vtu" for k in range(3)]  # relative
    for (_, t, data), path in zip(
        steps(grid, times), sorted((tmp_path / "flow" / "x_flow").iterdir()), strict=True
    ):
        reader.set_active_time_value(t)
        mesh = reader.read()[0]
        np.testing.assert_array_equal(mesh.cell_data["pressure"], data["pressure"])
        np.testing.assert_array_equal(mesh.cell_data["swat"], data["swat"])
        np.testing.assert_array_equal(mesh.points[:, 2], -grid.nodes.coords[:, 2])  # z is elevation
        alone = write_vtu(tmp_path / "alone.vtu", grid, data)
        assert path.read_bytes() == alone.read_bytes()  # the shared geometry is the VTU's own
    assert "<!-- pressure [bar] -->" in pvd.read_text()


def test_a_new_series_replaces_the_folder_whole(tmp_path):
    grid = gl.cart_grid([2, 2, 1])
    write_vtu_series(tmp_path / "s.pvd", grid, steps(grid, [0.0, 1.0, 2.0]))
    write_vtu_series(tmp_path / "s.pvd", grid, steps(grid, [0.0, 5.0]))
    assert sorted(p.name for p in (tmp_path / "s").iterdir()) == ["s_0000.vtu", "s_0001.vtu"]
    assert pv.PVDReader(tmp_path / "s.pvd").time_values == [0.0, 5.0]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s", "s.pvd"]  # no work folders left


def test_times_must_increase(tmp_path):
    grid = gl.cart_grid([2, 1, 1])
    with pytest.raises(GridError, match=r"s\.pvd: write_pvd: the times must be finite and increasing"):
        write_vtu_series(tmp_path / "s.pvd", grid, steps(grid, [0.0, 3.0, 3.0]))
    assert not (tmp_path / "s.pvd").exists()
    with pytest.raises(GridError, match="increasing"):
        write_pvd(tmp_path / "t.pvd", [(1.0, "a.vtu"), (float("nan"), "b.vtu")])
