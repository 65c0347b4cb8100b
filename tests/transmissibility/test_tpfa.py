"""Two-point flux transmissibilities of any grid (gridlib.transmissibility.transmissibility):
exact values on Cartesian and hexagonal PEBI grids, linear pressure fields reproduced
exactly by the fluxes, tensors, NTG and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import sparse
from scipy.sparse.linalg import spsolve

import gridlib as gl
from gridlib import InputError
from gridlib.transmissibility import FAULT, NEIGHBOR, OTHER, transmissibility
from gridlib.units import FIELD, METRIC
from gridlib.voronoi import Fault, Rings, Well, pebi_grid

C = METRIC.darcy_constant  # mD m -> cP m3/(day bar)


def test_cartesian_values_are_k_a_over_d_and_harmonic_means():
    g = gl.cart_grid([2, 1, 1], [30.0, 10.0, 2.0])  # two 15 m cells, face 10 m x 2 m
    c = transmissibility(g, gl.compute_geometry(g), [100.0, 300.0])
    # 1 / (7.5 / (100 A) + 7.5 / (300 A)) with A = 20 m2
    assert c.cells.tolist() == [[0, 1]] and c.global_cells.tolist() == [[0, 1]]
    assert c.trans[0] == pytest.approx(20.0 / (7.5 / 100 + 7.5 / 300) * C, rel=1e-14)
    assert c.kind.tolist() == [NEIGHBOR] and c.units == METRIC
    g3 = gl.cart_grid([3, 4, 2], [30.0, 40.0, 4.0])
    c3 = transmissibility(g3, gl.compute_geometry(g3), np.tile([10.0, 20.0, 1.0], (24, 1)))
    steps = np.diff(c3.global_cells, axis=1)[:, 0]
    # x: 10 mD 40/4*2... per connection: K (face area) / (centre distance)
    expected = np.select(
        [steps == 1, steps == 3, steps == 12], [10.0 * 10 * 2 / 10, 20.0 * 10 * 2 / 10, 1.0 * 10 * 10 / 2]
    )
    np.testing.assert_allclose(c3.trans, expected * C, rtol=1e-13)
    assert c3.counts() == {"neighbor": 2 * 4 * 2 + 3 * 3 * 2 + 12, "fault": 0, "pinch": 0, "other": 0}
    # FIELD: feet in, cP rb/(day psi) out
    f = transmissibility(g, gl.compute_geometry(g), 100.0, units="FIELD")
    assert f.trans[0] == pytest.approx(100.0 * 20.0 / 15.0 * FIELD.darcy_constant, rel=1e-14)


def test_full_tensor_and_ntg():
    g = gl.cart_grid([2, 1, 2], [20.0, 10.0, 4.0])
    geo = gl.compute_geometry(g)
    k = np.zeros((4, 3, 3))
    k[:] = np.diag([50.0, 80.0, 5.0])
    k[:, 0, 2] = k[:, 2, 0] = 10.0  # off-diagonal xz: c . K n picks K_xx for x faces (c || n)
    t_full = transmissibility(g, geo, k)
    t_diag = transmissibility(g, geo, np.tile([50.0, 80.0, 5.0], (4, 1)))
    np.testing.assert_allclose(t_full.trans, t_diag.trans, rtol=1e-14)
    np.testing.assert_allclose(transmissibility(g, geo, k.reshape(4, 9)).trans, t_full.trans, rtol=0)
    upper6 = np.tile([50.0, 0.0, 10.0, 80.0, 0.0, 5.0], (4, 1))  # MRST's [xx xy xz yy yz zz]
    np.testing.assert_allclose(transmissibility(g, geo, upper6).trans, t_full.trans, rtol=0)
    ntg = np.array([0.5, 1.0, 0.25, 1.0])
    t = transmissibility(g, geo, 100.0, ntg)
    steps = np.diff(t.global_cells, axis=1)[:, 0]
    base = transmissibility(g, geo, 100.0).trans
    lateral = steps == 1  # pairs (0, 1) and (2, 3): halves scaled by 0.5 (or 0.25) and 1
    half = base[lateral] * 2  # each half of equal cells is twice the total
    scale = np.array([0.5, 0.25])
    np.testing.assert_allclose(t.trans[lateral], 1 / (1 / (half * scale) + 1 / half), rtol=1e-14)
    np.testing.assert_allclose(t.trans[~lateral], base[~lateral], rtol=0)  # vertical: no NTG


def _layered_pebi(pg, thickness):
    """A layered PEBI grid, its geometry and the site centres (site x, y; centroid depth)."""
    g = gl.make_layered_grid(pg.grid, thickness=thickness)
    geo = gl.compute_geometry(g)
    centres = np.column_stack([pg.sites[g.layering.column], geo.cell_centroids[:, 2]])
    return g, geo, centres


def test_regular_hexagonal_lattice_gives_the_analytic_value():
    """A regular hexagonal lattice of spacing h: every lateral face is h / sqrt(3) long and
    joins sites h apart, so T = K (h / sqrt(3)) t / h = K t / sqrt(3), whatever h."""
    h, t, k = 50.0, 4.0, 120.0
    pg = pebi_grid(((0.0, 0.0), (1000.0, 800.0)), h)
    g, geo, centres = _layered_pebi(pg, [t])
    c = transmissibility(g, geo, k, centres=centres, distance="normal")
    sites = pg.sites
    inner = np.all((sites > [3 * h, 3 * h]) & (sites < [1000 - 3 * h, 800 - 3 * h]), axis=1)
    col = g.layering.column[c.cells]
    far = inner[col].all(axis=1)
    assert far.sum() > 300
    np.testing.assert_allclose(c.trans[far], k * t / math.sqrt(3.0) * C, rtol=1e-12)
    assert set(c.kind.tolist()) == {OTHER}


@pytest.mark.parametrize(
    "features",
    [
        {},
        {"faults": [Fault([(120.0, 60.0), (880.0, 700.0)]), Fault([(100.0, 650.0), (650.0, 90.0)])]},
        {"wells": [Well((300.0, 420.0), rings=Rings(inner=1.0, outer=60.0))]},
    ],
)
def test_linear_pressure_is_reproduced_exactly(features):
    """p = g . x at the cell centres (sites, layer mid-depth) solves the discrete problem
    with p fixed on the boundary cells: the two-point fluxes of a linear field are exact
    on a PEBI grid (faults and well rings included), so the sparse solve returns it."""
    pg = pebi_grid(((0.0, 0.0), (1000.0, 700.0)), 45.0, **features)
    g, geo, centres = _layered_pebi(pg, [2.0, 3.0, 5.0])
    c = transmissibility(g, geo, 250.0, centres=centres, distance="normal")
    grad = np.array([0.3, -0.7, 0.05])
    exact = centres @ grad
    # every face flux T (p_a - p_b) equals the exact flux -K grad . N (N from a to b)
    f = c.face
    normals = geo.face_normals[f]
    sign = np.where(g.faces.neighbors[f, 0] == c.cells[:, 0], 1.0, -1.0)
    flux = c.trans * (exact[c.cells[:, 0]] - exact[c.cells[:, 1]])
    true = -250.0 * C * sign * (normals @ grad)
    np.testing.assert_allclose(flux, true, rtol=1e-9, atol=1e-12 * np.abs(true).max())
    # and the discrete problem with Dirichlet boundary cells gives the field back
    n = g.num_cells
    boundary = np.zeros(n, bool)
    boundary[g.faces.neighbors[(g.faces.neighbors < 0).any(axis=1)].max(axis=1)] = True
    a, b = c.cells.T
    A = sparse.coo_matrix(
        (np.concatenate([c.trans, c.trans, -c.trans, -c.trans]), (np.r_[a, b, a, b], np.r_[a, b, b, a])),
        (n, n),
    ).tocsr()
    inner = np.flatnonzero(~boundary)
    rhs = -A[inner][:, boundary] @ exact[boundary]
    p = spsolve(A[inner][:, inner].tocsc(), rhs)
    assert inner.size > 100
    np.testing.assert_allclose(p, exact[inner], rtol=0, atol=1e-9 * np.abs(exact).max())


def test_centroid_distance_is_not_exact_where_face_centroids_leave_the_site_line():
    """The MRST variant (centres to face centroids) differs near faults, where Voronoi
    face centroids are off the line between the two sites: the reason PEBI grids take
    ``distance="normal"``."""
    pg = pebi_grid(((0.0, 0.0), (1000.0, 700.0)), 45.0, faults=[Fault([(120.0, 60.0), (880.0, 700.0)])])
    g, geo, centres = _layered_pebi(pg, [2.0])
    normal = transmissibility(g, geo, 100.0, centres=centres, distance="normal")
    centroid = transmissibility(g, geo, 100.0, centres=centres)
    rel = np.abs(centroid.trans / normal.trans - 1)
    assert rel.max() > 1e-3 and np.median(rel) < 1e-12


def test_logical_grids_classify_fault_connections():
    deck = gl.simple_grdecl([4, 2, 3], 0.12, flat=True)
    cp = gl.process_grdecl(deck)
    c = transmissibility(cp.grid, gl.compute_geometry(cp.grid), 100.0)
    nnc = {tuple(sorted(p)) for p in cp.nnc.global_cells.tolist()}
    got = {tuple(p) for p, k in zip(c.global_cells.tolist(), c.kind.tolist(), strict=True) if k == FAULT}
    assert got == nnc and len(nnc) > 0


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"permeability": -1.0}, "permeability: negative permeability in cell 0"),
        ({"permeability": np.ones(5)}, r"permeability: expected one value or tensor per cell \(6 cells\)"),
        ({"permeability": np.full(6, np.nan)}, "permeability: values must be finite"),
        ({"permeability": 1.0, "ntg": np.full(6, 1.5)}, r"ntg: expected one value in \[0, 1\] per cell"),
        (
            {"permeability": 1.0, "centres": np.zeros((6, 2))},
            r"centres: expected finite \(6, 3\) cell centres",
        ),
        ({"permeability": 1.0, "distance": "far"}, "distance: expected 'centroid' or 'normal'"),
        ({"permeability": 1.0, "units": "IMPERIAL"}, "unknown unit system 'IMPERIAL'"),
    ],
)
def test_bad_input_names_the_argument(kwargs, message):
    g = gl.cart_grid([3, 2, 1])
    with pytest.raises(InputError, match=message):
        transmissibility(g, gl.compute_geometry(g), **kwargs)
