"""summary.json's orientation figures (gridlib.stages.export.orientation_summary) with the cell
centres of the transmissibility stage (gridlib.stages.transmissibility.cell_centres)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

import gridlib as gl
from gridlib.io.netcdf import GridDataset
from gridlib.stages.export import orientation_summary
from gridlib.stages.transmissibility import cell_centres
from gridlib.voronoi import Fault, pebi_grid


@pytest.fixture(scope="module")
def layered_pebi():
    """A faulted PEBI grid in two flat layers, with the grid stage's ``site`` per cell."""
    pg = pebi_grid(((0.0, 0.0), (600.0, 400.0)), 80.0, [Fault([[150.0, -10.0], [420.0, 410.0]])])
    grid = gl.make_layered_grid(pg.grid, thickness=[10.0, 15.0])
    site = pg.sites[grid.layering.column]
    return GridDataset(grid, cell_data={"site": site}), gl.compute_geometry(grid)


def test_a_pebi_grid_is_measured_from_its_sites_and_is_orthogonal_there(layered_pebi):
    """Lateral faces are the sites' perpendicular bisectors and layer faces horizontal: 0 up to
    round-off from the sites (at each cell's centroid depth), whatever the anisotropy of K; the
    centroids, which are not the sites beside the fault, give angles of degrees."""
    stored, geo = layered_pebi
    nc = stored.grid.num_cells
    centres, what = cell_centres(SimpleNamespace(grid_type="pebi"), "grid.nc", stored, geo)
    assert what == "generating sites (x, y) at the centroid depth"
    np.testing.assert_array_equal(centres[:, 2], geo.cell_centroids[:, 2])
    rock = {"permx": np.full(nc, 100.0), "permy": np.full(nc, 100.0), "permz": np.full(nc, 10.0)}
    sites = orientation_summary(stored.grid, geo, centres, rock)
    assert set(sites) == {f"{p}orientation_{s}" for p in ("", "k_") for s in ("median", "p95", "max")}
    assert set(sites.values()) == {0.0}  # orthogonal up to round-off, rounded to 1e-6 degree
    centroids = orientation_summary(stored.grid, geo, None, None)
    assert set(centroids) == {"orientation_median", "orientation_p95", "orientation_max"}
    assert centroids["orientation_max"] > 1.0
    assert cell_centres(SimpleNamespace(grid_type="cornerpoint"), "grid.nc", stored, geo) == (
        None,
        "centroids",
    )
