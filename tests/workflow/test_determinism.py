"""Same inputs and seed, same bits: gridlib's random fields, RBF horizons, METIS partitions,
PEBI grids and geometry computed in fresh interpreters with 1 or 2 BLAS/OpenMP/gridlib
threads, other OpenBLAS kernels and numpy's SIMD dispatch switched off (tests/variants.py)
give identical arrays. The whole workflow is compared the same way in test_workflow.py.

The interpreter of each machine variant runs all four programs, one after the other, each in
a namespace of its own (tests/variants.py sections_everywhere): Python's start-up and
gridlib's imports are paid once per variant."""

from __future__ import annotations

import pytest
from variants import assert_same_section, sections_everywhere

PRELUDE = """
import hashlib, numpy as np, gridlib as gl
def show(name, *arrays):
    h = hashlib.sha256()
    for a in arrays:
        h.update(np.ascontiguousarray(a).tobytes())
    print(name, h.hexdigest())
"""


RANDOM_FIELDS_ON_LATTICE_AND_VORONOI_COLUMNS = (
    PRELUDE
    + """
from gridlib.petrophysics import Variogram, depositional_coordinates, gaussian_field, lognormal_permeability
lattice = gl.cart_grid([40, 30, 8], [800.0, 600.0, 16.0])
areal = gl.pebi(gl.triangle_grid(np.random.default_rng(2).uniform(0.0, 800.0, (3000, 2))))
voronoi = gl.make_layered_grid(areal, thickness=np.full(6, 2.0))
for name, g in (("lattice", lattice), ("voronoi", voronoi)):
    u = depositional_coordinates(g, dz_ref=2.0)
    for model in ("exponential", "gaussian", "matern"):
        v = Variogram(model, var=1.5, len_scale=[120.0, 60.0, 4.0], angles=[25.0, 3.0, 0.0], nu=1.5)
        z = gaussian_field(u, v, seed=7)
        show(f"{name} {model}", z, lognormal_permeability(z, median=100.0, sigma=1.2))
"""
)

HORIZON_INTERPOLATION_BY_EVERY_METHOD = (
    PRELUDE
    + """
from gridlib.horizons import interpolate_points_at
rng = np.random.default_rng(0)
p = rng.uniform(0.0, 2000.0, (900, 2))
z = 1500.0 + 0.05 * p[:, 0] + 8.0 * np.sin(p[:, 1] / 150.0)
x, y = np.meshgrid(np.linspace(-100.0, 2100.0, 90), np.linspace(-100.0, 2100.0, 80))
pts = np.column_stack([p, z])
show("rbf global", interpolate_points_at(pts, x, y, method="rbf", extrapolation="trend"))
show("rbf local", interpolate_points_at(pts, x, y, method="rbf", neighbors=40, smoothing=1e-4))
trace = [np.array([[300.0, -50.0], [1700.0, 2050.0]])]
for method in ("linear", "cubic", "nearest"):
    show(method, interpolate_points_at(pts, x, y, method=method, extrapolation="trend", faults=trace))
"""
)

PEBI_GRID_GEOMETRY_AND_METIS_PARTITION = (
    PRELUDE
    + """
from gridlib.voronoi import Fault, Rings, Well, pebi_grid
pg = pebi_grid(((0.0, 0.0), (1000.0, 700.0)), 40.0,
               faults=[Fault([(100.0, 80.0), (900.0, 640.0)]), Fault([(80.0, 600.0), (700.0, 60.0)])],
               wells=[Well((300.0, 420.0), rings=Rings(inner=1.0, outer=50.0))])
g = gl.make_layered_grid(pg.grid, thickness=[2.0, 3.0, 4.0])
geo = gl.compute_geometry(g)
show("grid", pg.grid.nodes.coords, pg.grid.faces.nodes, pg.grid.faces.neighbors, pg.sites)
show("geometry", geo.cell_volumes, geo.cell_centroids, geo.face_areas, geo.face_normals, geo.face_centroids)
show("metis", gl.partition_metis(g, 12, face_weights=geo.face_areas, cell_weights=geo.cell_volumes))
"""
)

TRANSMISSIBILITIES_OF_A_DECK_AND_OF_A_PEBI_GRID = (
    PRELUDE
    + """
from gridlib.cornerpoint import make_model3, process_grdecl
from gridlib.cornerpoint.deck import Deck
from gridlib.transmissibility import deck_transmissibility, transmissibility
from gridlib.voronoi import Fault, pebi_grid
d = make_model3([30, 20, 6])
rng = np.random.default_rng(3)
data = {key: rng.uniform(10.0, 500.0, d.num_cells) for key in ("PERMX", "PERMY", "PERMZ")}
data |= {"NTG": rng.uniform(0.5, 1.0, d.num_cells), "MULTX": rng.choice([1.0, 0.5], d.num_cells)}
deck = Deck(d.cart_dims, d.coord, d.zcorn, d.actnum, data, source="model3")
c = deck_transmissibility(deck)
show("deck", c.cells, c.trans, c.kind, c.face)
pg = pebi_grid(((0.0, 0.0), (1000.0, 700.0)), 40.0, faults=[Fault([(100.0, 80.0), (900.0, 640.0)])])
g = gl.make_layered_grid(pg.grid, thickness=[2.0, 3.0])
geo = gl.compute_geometry(g)
centres = np.column_stack([pg.sites[g.layering.column], geo.cell_centroids[:, 2]])
t = transmissibility(g, geo, rng.uniform(10.0, 500.0, g.num_cells), centres=centres, distance="normal")
show("pebi", t.cells, t.trans)
"""
)

PROGRAMS = {
    "random_fields_on_lattice_and_voronoi_columns": RANDOM_FIELDS_ON_LATTICE_AND_VORONOI_COLUMNS,
    "horizon_interpolation_by_every_method": HORIZON_INTERPOLATION_BY_EVERY_METHOD,
    "pebi_grid_geometry_and_metis_partition": PEBI_GRID_GEOMETRY_AND_METIS_PARTITION,
    "transmissibilities_of_a_deck_and_of_a_pebi_grid": TRANSMISSIBILITIES_OF_A_DECK_AND_OF_A_PEBI_GRID,
}


@pytest.fixture(scope="module")
def outputs() -> list[dict[str, str]]:
    return sections_everywhere(PROGRAMS)


def test_random_fields_on_lattice_and_voronoi_columns(outputs):
    """The factorised sums of both kinds of column layout, all variogram models, rotated."""
    assert_same_section(outputs, "random_fields_on_lattice_and_voronoi_columns")


def test_horizon_interpolation_by_every_method(outputs):
    """Delaunay-based methods use barycentric transforms, RBF a dense solve: neither by LAPACK."""
    assert_same_section(outputs, "horizon_interpolation_by_every_method")


def test_pebi_grid_geometry_and_metis_partition(outputs):
    assert_same_section(outputs, "pebi_grid_geometry_and_metis_partition")


def test_transmissibilities_of_a_deck_and_of_a_pebi_grid(outputs):
    """deck_transmissibility runs its steps concurrently on gridlib's threads; the NEWTRAN
    and two-point values are elementwise: the same bits everywhere."""
    assert_same_section(outputs, "transmissibilities_of_a_deck_and_of_a_pebi_grid")
