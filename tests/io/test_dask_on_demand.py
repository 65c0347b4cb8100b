"""gridlib.io.dask_on_demand: a process that only reads and writes numpy-backed datasets never
imports dask, and dask arrays made later are recognised as before.

One fresh interpreter (the deferral changes xarray for the rest of a process): it writes and
reads a grid and its geometry as the stages do, then opens the file lazily (chunks={}) and
writes the dask-backed dataset again.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

SCRIPT = textwrap.dedent(
    """
    import json, sys
    from gridlib.io.dask_on_demand import defer_dask_import

    out = {"deferred": defer_dask_import(), "again": defer_dask_import()}
    import numpy as np
    import xarray as xr
    import gridlib as gl
    from gridlib.io.netcdf import read_geometry_netcdf, read_netcdf, write_geometry_netcdf, write_netcdf

    grid = gl.cart_grid([3, 2, 2], [3.0, 2.0, 1.0])
    geo = gl.compute_geometry(grid)
    write_netcdf(sys.argv[1] + "/grid.nc", grid, cell_data={"poro": np.full(12, 0.25)})
    write_geometry_netcdf(sys.argv[1] + "/geometry.nc", geo, 3)
    back = read_netcdf(sys.argv[1] + "/grid.nc")
    out["same_grid"] = bool(np.array_equal(back.grid.faces.nodes, grid.faces.nodes))
    volumes = read_geometry_netcdf(sys.argv[1] + "/geometry.nc").cell_volumes
    out["same_volumes"] = bool(np.array_equal(volumes, geo.cell_volumes))
    out["dask_before"] = sorted(m for m in sys.modules if m == "dask" or m.startswith("dask."))

    from xarray.namedarray.pycompat import array_type, is_chunked_array
    with xr.open_dataset(sys.argv[1] + "/grid.nc", chunks={}) as lazy:
        data = lazy["poro"].data
        out["lazy_type"] = type(data).__module__.split(".")[0]
        out["recognised"] = isinstance(data, array_type("dask")) and is_chunked_array(data)
        out["variable_keeps_dask"] = type(xr.Variable("cell", data).data) is type(data)
        lazy.to_netcdf(sys.argv[1] + "/again.nc")
    with xr.open_dataset(sys.argv[1] + "/again.nc") as again:
        out["rewritten"] = again["poro"].values.tolist()
    print(json.dumps(out))
    """
)


@pytest.fixture(scope="module")
def outcome(tmp_path_factory) -> dict:
    folder = tmp_path_factory.mktemp("dask_on_demand")
    res = subprocess.run(
        [sys.executable, "-c", SCRIPT, str(folder)], capture_output=True, text=True, timeout=120
    )
    assert res.returncode == 0, res.stderr[-3000:]
    return json.loads(res.stdout.splitlines()[-1])


def test_reading_and_writing_numpy_datasets_imports_no_dask(outcome):
    assert outcome["deferred"] is True and outcome["again"] is True
    assert outcome["same_grid"] and outcome["same_volumes"]
    assert outcome["dask_before"] == []


def test_dask_arrays_made_later_are_dask_arrays_to_xarray(outcome):
    assert outcome["lazy_type"] == "dask"
    assert outcome["recognised"] is True
    assert outcome["variable_keeps_dask"] is True
    assert outcome["rewritten"] == [0.25] * 12


def test_nothing_is_deferred_once_dask_is_imported():
    code = "import dask; from gridlib.io.dask_on_demand import defer_dask_import; print(defer_dask_import())"
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0 and res.stdout.split() == ["False"], res.stderr[-2000:]
