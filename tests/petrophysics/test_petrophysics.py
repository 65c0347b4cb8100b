"""Petrophysics (gridlib.petrophysics): fields in depositional coordinates, cubes (rock: test_rock.py)."""

from __future__ import annotations

import gstools as gs
import numpy as np
import pytest

import gridlib as gl
from gridlib import InputError
from gridlib.cornerpoint import FaultTrace, Horizon, horizons_to_grdecl, process_grdecl
from gridlib.io.cube_files import read_property_cube, write_property_cube
from gridlib.petrophysics import (
    VARIOGRAM_MODELS,
    Depositional,
    PropertyCube,
    Variogram,
    depositional_coordinates,
    gaussian_field,
    layer_index,
    sample_cube,
)


def test_grf_statistics_on_1e5_cells():
    g = gl.cart_grid([50, 50, 40], [500.0, 500.0, 400.0])  # 10 m cubes, 100,000 cells
    u = depositional_coordinates(g, dz_ref=10.0)
    v = Variogram("exponential", var=4.0, len_scale=10.0)
    f = gaussian_field(u, v, seed=0, mean=10.0)
    assert f.shape == (100_000,)
    # 1000 modes: the realised variance carries a ~1/sqrt(1000) = 3% randomisation error, plus the
    # ergodic one; over seeds 0..7 the mean is within 0.1 (5% of sigma) and the variance within 5%.
    assert abs(f.mean() - 10.0) < 0.1
    assert abs(f.var() / 4.0 - 1.0) < 0.05
    # gstools' empirical variogram over every lattice pair at lags of 1, 2, 3 cells (10, 20, 30 m), the
    # mean of the three axes (isotropic model); over seeds 0..7 within 8% of the model's
    cube = f.reshape(40, 50, 50)  # (k, j, i): cart_grid numbers cells i fastest
    gamma = np.mean([gs.vario_estimate_axis(cube, direction=d)[1:4] for d in (0, 1, 2)], axis=0)
    model = v.covmodel(3).variogram(np.array([10.0, 20.0, 30.0]))
    assert np.abs(gamma / model - 1.0).max() < 0.1


@pytest.mark.parametrize("model", VARIOGRAM_MODELS)
@pytest.mark.parametrize("columns", ["lattice", "scattered"])
def test_factorised_sum_is_gstools_field(model, columns):
    if columns == "lattice":  # column centres on a tensor lattice: the x-y split as well
        g = gl.cart_grid([12, 9, 6], [240.0, 180.0, 12.0])
    else:  # Voronoi columns: one term per column
        areal = gl.pebi(gl.triangle_grid(np.random.default_rng(2).uniform(0.0, 240.0, (150, 2))))
        g = gl.make_layered_grid(areal, thickness=np.full(6, 2.0))
    u = depositional_coordinates(g, dz_ref=2.0)
    v = Variogram(model, var=2.5, len_scale=[80.0, 40.0, 3.0], angles=[30.0, 5.0, 0.0], nu=1.5)
    fast = gaussian_field(u, v, seed=11, mean=1.0)
    srf = gs.SRF(v.covmodel(3), mode_no=1000, seed=11)
    plain = 1.0 + srf(u.points.T, mesh_type="unstructured")
    assert np.abs(fast - plain).max() < 1e-11
    assert np.array_equal(gaussian_field(u.points, v, seed=11, mean=1.0), plain)


def test_same_seed_same_arrays():
    g = gl.cart_grid([30, 20, 5], [300.0, 200.0, 10.0])
    u = depositional_coordinates(g, dz_ref=2.0)
    v = Variogram("gaussian", var=1.0, len_scale=[50.0, 50.0, 4.0])
    a, b = gaussian_field(u, v, seed=5), gaussian_field(u, v, seed=5)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, gaussian_field(u, v, seed=6))
    pts = u.points[:100]
    assert np.array_equal(gaussian_field(pts, v, seed=5), gaussian_field(pts, v, seed=5))
    # the same field at other positions: a sub-grid sees the same values
    sub = Depositional(u.column_xy, u.w_edges, u.column[::7], u.layer[::7])
    assert np.allclose(gaussian_field(sub, v, seed=5), a[::7], rtol=0, atol=1e-12)  # to round-off


def faulted(throw: float):
    """Two flat horizons 50 m apart, 40 x 20 columns of 10 m, 10 layers of 5 m, a fault at x = 200."""
    x, y = np.linspace(0.0, 400.0, 41), np.linspace(0.0, 200.0, 21)
    top, base = Horizon(x, y, np.full((21, 41), 1000.0)), Horizon(x, y, np.full((21, 41), 1050.0))
    fault = FaultTrace([(200.0, -10.0), (200.0, 210.0)], throw=throw)
    deck = horizons_to_grdecl([top, base], layers=10, faults=[fault])
    return deck, process_grdecl(deck).grid


def pearson(f, a, b):
    return float(np.corrcoef(f[a], f[b])[0, 1])


def test_fault_throw_does_not_decorrelate_depositional_sampling():
    deck, g = faulted(throw=25.0)  # five layers of throw
    assert g.num_cells == 8000 and int((g.faces.tag > 0).sum()) > 0
    geo = gl.compute_geometry(g)
    u = depositional_coordinates(g, coord=deck.coord, dz_ref=5.0)
    i = g.cells.index_map % 40
    lookup = np.full(8000, -1)
    lookup[g.cells.index_map] = np.arange(g.num_cells)
    jk = np.arange(20 * 10)  # every (j, k)
    j, k = jk % 20, jk // 20

    def cells(col):
        return lookup[col + 40 * j + 800 * k]

    west, east, west2 = cells(19), cells(20), cells(18)  # across the fault at x = 200, and lateral
    assert (i[west] == 19).all() and (geo.cell_centroids[east, 2] - geo.cell_centroids[west, 2] == 25.0).all()
    v = Variogram("exponential", var=1.0, len_scale=[100.0, 100.0, 5.0])
    across_dep, lateral_dep, across_phys, lateral_phys = [], [], [], []
    for seed in range(4):
        fd = gaussian_field(u, v, seed=seed)
        fp = gaussian_field(geo.cell_centroids, v, seed=seed)
        across_dep.append(fd[np.r_[west, east]].reshape(2, -1))
        lateral_dep.append(fd[np.r_[west2, west]].reshape(2, -1))
        across_phys.append(fp[np.r_[west, east]].reshape(2, -1))
        lateral_phys.append(fp[np.r_[west2, west]].reshape(2, -1))
    rho = {
        name: float(np.corrcoef(np.concatenate(pairs, axis=1))[0, 1])
        for name, pairs in (
            ("across_dep", across_dep),
            ("lateral_dep", lateral_dep),
            ("across_phys", across_phys),
            ("lateral_phys", lateral_phys),
        )
    }
    expected_lateral = np.exp(-10.0 / 100.0)  # 0.905: neighbours 10 m apart
    assert abs(rho["across_dep"] - rho["lateral_dep"]) < 0.05  # as correlated as lateral neighbours
    assert rho["across_dep"] > expected_lateral - 0.1
    assert abs(rho["lateral_phys"] - expected_lateral) < 0.1
    assert rho["across_phys"] < 0.3  # at centroids: 25 m = 5 vertical correlation lengths apart
    assert rho["lateral_dep"] - rho["across_phys"] > 0.5

    # the throw is a relabelling only: the same values as the grid without it, cell for cell
    deck0, g0 = faulted(throw=0.0)
    u0 = depositional_coordinates(g0, coord=deck0.coord, dz_ref=5.0)
    assert np.array_equal(g0.cells.index_map, g.cells.index_map)
    assert np.array_equal(gaussian_field(u0, v, seed=3), gaussian_field(u, v, seed=3))
    assert not np.array_equal(
        gaussian_field(gl.compute_geometry(g0).cell_centroids, v, seed=3),
        gaussian_field(geo.cell_centroids, v, seed=3),
    )


def test_depositional_coordinates_of_corner_point_and_layered_grids():
    deck, g = faulted(throw=25.0)
    from_pillars = depositional_coordinates(g, coord=deck.coord, dz_ref=5.0)
    from_centroids = depositional_coordinates(g)  # column means of the centroids, dz from them
    assert np.allclose(from_pillars.points, from_centroids.points, rtol=0, atol=1e-9)
    assert from_pillars.points[0].tolist() == [5.0, 5.0, 2.5]
    assert np.array_equal(layer_index(g), g.cells.index_map // 800)

    zones = depositional_coordinates(g, dz_ref=np.repeat([2.0, 8.0], 5))  # two zones of 5 layers
    assert zones.w_edges.tolist()[:7] == [0.0, 2.0, 4.0, 6.0, 8.0, 10.0, 18.0] and zones.layer_w[9] == 46.0

    areal = gl.pebi(gl.triangle_grid(np.random.default_rng(0).uniform(0.0, 100.0, (60, 2))))
    layered = gl.make_layered_grid(areal, thickness=[1.0, 2.0, 3.0])
    u = depositional_coordinates(layered)
    centres = gl.compute_geometry(areal).cell_centroids
    assert np.array_equal(u.column, layered.layering.column) and np.array_equal(
        u.layer, layered.layering.layer
    )
    assert np.allclose(u.column_xy, centres[:, :2], rtol=0, atol=1e-12)
    assert u.w_edges.tolist() == pytest.approx([0.0, 2.0, 4.0, 6.0])  # median centroid step 2 m

    with pytest.raises(InputError, match="logically Cartesian grid"):
        depositional_coordinates(gl.triangle_grid(np.random.default_rng(1).uniform(0, 1, (10, 2))))
    with pytest.raises(InputError, match="dz_ref: expected a positive thickness"):
        depositional_coordinates(g, dz_ref=[1.0, 2.0])


def test_unknown_variogram_model_names_the_option():
    with pytest.raises(InputError, match=r"variogram\.model: unknown model 'spherical'; expected one of"):
        Variogram("spherical")
    with pytest.raises(InputError, match=r"variogram\.len_scale: must be positive"):
        Variogram("gaussian", len_scale=[100.0, 0.0, 1.0])
    with pytest.raises(InputError, match=r"seed: expected an integer"):
        gaussian_field(np.zeros((3, 3)), Variogram(), seed=1.5)
    with pytest.raises(InputError, match=r"variogram.len_scale: 3 lengths for a 2-D field"):
        gaussian_field(np.zeros((3, 2)), Variogram(len_scale=[1.0, 2.0, 3.0]), seed=1)


def test_cube_sampling_at_centroids_and_depositional_coordinates(tmp_path):
    deck, g = faulted(throw=25.0)
    # a cube over the same box: 20 x 10 columns of 20 m, 10 layers of 5 m; value = the cube's layer
    x, y, z = np.arange(10.0, 400.0, 20.0), np.arange(10.0, 200.0, 20.0), np.arange(1002.5, 1050.0, 5.0)
    kk = np.broadcast_to(np.arange(10.0)[:, None, None], (10, 10, 20))
    cube = PropertyCube(x, y, z, {"layer": kk, "poro": 0.1 + 0.02 * kk})
    write_property_cube(tmp_path / "cube.nc", cube)
    cube = read_property_cube(tmp_path / "cube.nc")
    assert cube.z.tolist() == z.tolist() and set(cube.values) == {"layer", "poro"}

    k = g.cells.index_map // 800
    east = (g.cells.index_map % 40) >= 20  # the downthrown block, 25 m deeper
    u = depositional_coordinates(g, coord=deck.coord, dz_ref=5.0)
    dep = sample_cube(cube, u)
    assert np.array_equal(dep["layer"], k.astype(float))  # layers follow the grid through the fault
    phys = sample_cube(cube, gl.compute_geometry(g).cell_centroids)
    assert np.array_equal(phys["layer"][~east], k[~east].astype(float))
    assert np.array_equal(phys["layer"][east], np.minimum(k[east] + 5, 9).astype(float))  # shifted, clipped
    nan = sample_cube(cube, gl.compute_geometry(g).cell_centroids, outside="nan")
    assert np.isnan(nan["layer"]).sum() == int((east & (k >= 5)).sum())

    # elevation (positive up) cubes are turned into depth
    import xarray as xr

    up = xr.Dataset(
        {"poro": (("z", "y", "x"), np.asarray(cube.values["poro"])[::-1])},
        coords={"z": ("z", -z[::-1], {"positive": "up"}), "y": y, "x": x},
    )
    up.to_netcdf(tmp_path / "up.nc")
    flipped = read_property_cube(tmp_path / "up.nc")
    assert flipped.z.tolist() == z.tolist() and np.array_equal(flipped.values["poro"], cube.values["poro"])
    with pytest.raises(InputError, match=r"no property 'permx' in the cube"):
        sample_cube(cube, u, names=["permx"])
    with pytest.raises(InputError, match=r"coordinate x must be increasing and regularly spaced"):
        PropertyCube([0.0, 1.0, 3.0], [0.0], [0.0], {"a": np.zeros((1, 1, 3))})


def test_fields_do_not_depend_on_the_number_of_threads(monkeypatch):
    """The workflow sets GRIDLIB_NUM_THREADS to each rule's threads: 1 or 3 threads, same arrays."""
    sites = np.random.default_rng(2).uniform(0.0, 1000.0, (5000, 2))  # irregular: blocks of columns
    g = gl.make_layered_grid(gl.pebi(gl.triangle_grid(sites)), 3)
    u = depositional_coordinates(g, dz_ref=2.0)
    v = Variogram("exponential", var=1.0, len_scale=[80.0, 40.0, 3.0])
    fields = []
    for n in ("1", "3"):
        monkeypatch.setenv("GRIDLIB_NUM_THREADS", n)
        fields.append(gaussian_field(u, v, seed=4))
    assert np.array_equal(fields[0], fields[1])
    monkeypatch.setenv("GRIDLIB_NUM_THREADS", "two")
    with pytest.raises(InputError, match=r"GRIDLIB_NUM_THREADS: expected an integer >= 1, got 'two'"):
        gaussian_field(u, v, seed=4)
