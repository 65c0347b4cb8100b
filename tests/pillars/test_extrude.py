"""2.5D extrusion through the pillar engine (gridlib.pillars.columns / extrude): exact volumes
on several areal grids, make_layered_grid reproduced, equivalence with process_grdecl on corner-point
decks (faults, pinch-outs, inactive cells, inclined pillars) and with horizons_to_grdecl's fault
traces, the seed's peaks, faults on PEBI grids, pinch-outs, masks and bad input."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import gridlib as gl
from gridlib.connectivity import cell_faces_from_neighbors, half_face_signs
from gridlib.cornerpoint.between_horizons import FaultTrace, Horizon, horizons_to_grdecl
from gridlib.cornerpoint.generators import make_model3, simple_grdecl
from gridlib.cornerpoint.process import FAULT, PINCH
from gridlib.grid import B, E, Faces, N, S, T, W
from gridlib.pillars.columns import areal_corners, extrude_columns
from gridlib.pillars.extrude import extrude


def peaks(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """MATLAB's peaks function."""
    return (
        3 * (1 - x) ** 2 * np.exp(-(x**2) - (y + 1) ** 2)
        - 10 * (x / 5 - x**3 - y**5) * np.exp(-(x**2) - y**2)
        - np.exp(-((x + 1) ** 2) - y**2) / 3
    )


def square_sites(n: int, half: float = 3.0) -> np.ndarray:
    """A hexagonal lattice of about n x n sites on [-half, half]^2, its boundary sampled."""
    h = 2 * half / n
    pts = []
    for j in range(n + 1):
        xs = np.arange(n + 1) * h - half + (0.5 * h if j % 2 else 0.0)
        xs = xs[xs <= half + 1e-9]
        if j % 2:
            xs = np.concatenate([[-half], xs, [half]])
        pts.append(np.column_stack([xs, np.full(xs.size, j * h - half)]))
    return np.unique(np.round(np.concatenate(pts), 12), axis=0)


RNG = np.random.default_rng(2026)
AREALS = {
    "cart": gl.cart_grid([7, 5], [70.0, 50.0]),
    "pebi": gl.pebi(gl.triangle_grid(RNG.uniform(0.0, 1000.0, (300, 2)))),
    "triangles": gl.triangle_grid(RNG.uniform(0.0, 100.0, (80, 2))),
}


def areal_area(areal: gl.Grid) -> float:
    return float(gl.compute_geometry(areal).cell_volumes.sum())


def checked(grid: gl.Grid) -> gl.Geometry:
    geo = gl.compute_geometry(grid)
    gl.check_grid(grid, geo)
    # The cells' faces come out in increasing face order, as a transpose of neighbors gives them.
    pos, faces = cell_faces_from_neighbors(grid.faces.neighbors, grid.num_cells)
    np.testing.assert_array_equal(grid.cells.face_pos, pos)
    np.testing.assert_array_equal(grid.cells.faces, faces)
    return geo


def flat(depth: float):
    return lambda x, y: np.full_like(x, depth)


def plane(z0: float, a: float, b: float):
    return lambda x, y: z0 + a * x + b * y


# --------------------------------------------------------------------------- exact volumes


@pytest.mark.parametrize("name", list(AREALS))
def test_flat_and_tilted_layers_have_thickness_times_area(name):
    areal = AREALS[name]
    area = areal_area(areal)
    for top, base, thickness in (
        (flat(1000.0), flat(1030.0), 30.0),
        (plane(2000.0, 0.05, -0.02), plane(2012.5, 0.05, -0.02), 12.5),
    ):
        r = extrude(areal, [top, base], layers=[4])
        assert r.grid.num_cells == 4 * areal.num_cells
        geo = checked(r.grid)
        assert geo.cell_volumes.sum() == pytest.approx(thickness * area, rel=1e-12)
        np.testing.assert_allclose(
            np.bincount(r.grid.layering.layer, geo.cell_volumes), thickness / 4 * area, rtol=1e-12
        )
        assert r.nnc.num == 0 and r.notes == () and not r.grid.faces.tag.any()
        np.testing.assert_array_equal(r.grid.cells.index_map, np.arange(4 * areal.num_cells))
        np.testing.assert_array_equal(r.zone, 0)


def test_zones_get_their_layers_proportionally():
    areal = AREALS["pebi"]
    r = extrude(areal, [flat(1000.0), plane(1010.0, 0.01, 0.0), flat(1040.0)], layers=[2, 3])
    geo = checked(r.grid)
    assert r.grid.num_cells == 5 * areal.num_cells
    np.testing.assert_array_equal(np.bincount(r.zone), [2 * areal.num_cells, 3 * areal.num_cells])
    np.testing.assert_allclose(r.horizons[1], 1010.0 + 0.01 * areal.nodes.coords[:, 0], rtol=0, atol=1e-12)
    assert geo.cell_volumes.sum() == pytest.approx(40.0 * areal_area(areal), rel=1e-12)


@pytest.mark.parametrize("name", list(AREALS))
def test_unfaulted_extrusion_reproduces_make_layered_grid(name):
    areal = AREALS[name]
    xy = areal.nodes.coords
    depths = np.stack([1000.0 + 0.01 * xy[:, 0] + k * (3.0 + 0.001 * xy[:, 1]) for k in range(4)])
    ref = gl.make_layered_grid(areal, depths=depths)
    _, ring = areal_corners(areal)
    g = extrude_columns(areal, depths[:, ring]).grid
    for part, field in (
        ("cells", "face_pos"),
        ("cells", "faces"),
        ("faces", "node_pos"),
        ("faces", "nodes"),
        ("faces", "neighbors"),
        ("faces", "tag"),
        ("nodes", "coords"),
    ):
        np.testing.assert_array_equal(getattr(getattr(g, part), field), getattr(getattr(ref, part), field))
    assert g.cart_dims == ref.cart_dims and g.num_nodes == ref.num_nodes
    assert (g.cells.face_tag is None) == (ref.cells.face_tag is None) == (name != "cart")
    if name == "cart":
        np.testing.assert_array_equal(g.cells.face_tag, ref.cells.face_tag)
        np.testing.assert_array_equal(g.cells.index_map, ref.cells.index_map)
    np.testing.assert_array_equal(g.layering.column, ref.layering.column)
    np.testing.assert_array_equal(g.layering.layer, ref.layering.layer)


def test_clockwise_areal_grid_gives_positive_volumes():
    ref = AREALS["cart"]
    mirrored = dataclasses.replace(ref, nodes=gl.Nodes(ref.nodes.coords * [-1.0, 1.0]), cart_dims=None)
    assert gl.compute_geometry(mirrored).cell_volumes.max() < 0  # the areal grid turns clockwise
    r = extrude(mirrored, [flat(100.0), plane(110.0, 0.1, 0.0)], layers=2)
    geo = checked(r.grid)
    x = mirrored.nodes.coords[:, 0]
    assert geo.cell_volumes.sum() == pytest.approx(70 * 50 * (10.0 + 0.1 * x.mean()), rel=1e-12)
    # With a fault along x = -30 (a 3 m throw, 5 m layers): one NNC per row of cells.
    r = extrude(mirrored, [100.0, 110.0], layers=2, faults=[FaultTrace([(-30.0, -10.0), (-30.0, 60.0)], 3.0)])
    geo = checked(r.grid)
    assert geo.cell_volumes.sum() == pytest.approx(70 * 50 * 10.0, rel=1e-12)
    assert r.nnc.num == 5 and int((r.grid.faces.tag == 1).sum()) == 5 * 5


def test_half_face_tags_point_their_way():
    """On a Cartesian areal grid the half-faces are tagged W, E, S, N, T, B as in process_grdecl."""
    r = extrude(gl.cart_grid([4, 3], [4.0, 3.0]), [flat(0.0), flat(2.0)], layers=2)
    g = r.grid
    geo = gl.compute_geometry(g)
    outward = geo.face_normals[g.cells.faces] * half_face_signs(g)[:, None]
    expected = {W: (-1, 0, 0), E: (1, 0, 0), S: (0, -1, 0), N: (0, 1, 0), T: (0, 0, -1), B: (0, 0, 1)}
    for tag, direction in expected.items():
        sel = g.cells.face_tag == tag
        assert sel.any()
        unit = outward[sel] / np.linalg.norm(outward[sel], axis=1)[:, None]
        np.testing.assert_allclose(unit, np.broadcast_to(direction, unit.shape), atol=1e-14)
    assert g.cart_dims == (4, 3, 2)


# --------------------------------------------------------------------------- equivalence with process_grdecl


def as_columns(deck):
    """A corner-point deck as the engine's input: the Cartesian areal grid, depths per corner and
    level, the pillars and the active mask (the decks have no gaps between layers)."""
    nx, ny, nz = deck.cart_dims
    areal = gl.cart_grid([nx, ny])
    pos, ring = areal_corners(areal)
    c = np.repeat(np.arange(nx * ny), np.diff(pos))
    i, j = c % nx, c // nx
    col, row = 2 * i + (ring % (nx + 1) - i), 2 * j + (ring // (nx + 1) - j)
    zc = deck.zcorn_array()
    np.testing.assert_array_equal(zc[2:-1:2], zc[1:-1:2])  # bottom of layer k = top of layer k + 1
    z = zc[np.r_[2 * np.arange(nz), 2 * nz - 1]][:, row, col]
    return areal, z, deck.pillars().reshape(-1, 2, 3), deck.active.reshape(nz, nx * ny).astype(bool)


def assert_same_grid(r, cp):
    """Same cells (by ijk), faces, nodes, volumes, fault faces and NNC pairs."""
    g, h = r.grid, cp.grid
    assert (g.num_cells, g.num_faces, g.num_nodes) == (h.num_cells, h.num_faces, h.num_nodes)
    np.testing.assert_array_equal(g.cells.index_map, h.cells.index_map)  # both in (k, j, i) order

    def points(grid):  # the nodes, sorted
        c = grid.nodes.coords
        return c[np.lexsort(c.T[::-1])]

    np.testing.assert_array_equal(points(g), points(h))  # the same points, bit for bit
    vol, ref = checked(g).cell_volumes, gl.compute_geometry(h).cell_volumes
    np.testing.assert_allclose(vol, ref, rtol=1e-12, atol=1e-13 * ref.max())
    np.testing.assert_array_equal(np.bincount(g.faces.tag), np.bincount(h.faces.tag))
    np.testing.assert_array_equal(np.bincount(g.cells.face_tag), np.bincount(h.cells.face_tag))

    def pairs(nnc):
        return {(tuple(sorted(p)), int(k)) for p, k in zip(nnc.global_cells.tolist(), nnc.kind, strict=True)}

    assert pairs(r.nnc) == pairs(cp.nnc)
    assert r.fault_names == cp.fault_names


@pytest.mark.parametrize(
    ("deck", "counts"),
    [
        (simple_grdecl([4, 2, 3], 0.12, flat=True), (24, 106, 4)),  # the seed's model, inclined pillars
        (simple_grdecl([6, 5, 4], lambda y: 0.05 * (np.sin(2 * np.pi * y) - 0.5)), (120, 469, 21)),
        (make_model3([30, 20, 6]), (2778, 9463, 378)),  # two faults, pinch-outs, inactive cells
        # Linear throws meeting other layers' depths at pillars (equal only up to rounding there).
        (simple_grdecl([2, 2, 5], lambda y: 0.6 * y, flat=True), (20, 107, 12)),
        (simple_grdecl([4, 3, 5], lambda y: 1 / 6 + 0.1 * y, flat=True), (60, 245, 17)),
    ],
)
def test_engine_on_a_corner_point_deck_is_process_grdecl(deck, counts):
    cp = gl.process_grdecl(deck)
    areal, z, lines, active = as_columns(deck)
    r = extrude_columns(areal, z, pillars=lines, active=active)
    assert (r.grid.num_cells, r.grid.num_faces, r.nnc.num) == counts
    assert_same_grid(r, cp)
    assert r.grid.cart_dims == deck.cart_dims


AXIS = np.linspace(0.0, 100.0, 11)


def flat_horizon(depth: float) -> Horizon:
    return Horizon(AXIS, AXIS, np.full((11, 11), depth))


TRACES = {
    "straight": [FaultTrace([(50.0, -10.0), (50.0, 110.0)], 2.0, "MAIN")],
    "tip": [FaultTrace([(50.0, -10.0), (50.0, 52.0)], lambda s: 4.0 * (1.0 - s), "TIP")],
    "lens": [FaultTrace([(50.0, 22.0), (50.0, 78.0)], lambda s: 3.0 * np.sin(np.pi * s), "LENS")],
    "block": [FaultTrace([(50.0, -10.0), (50.0, 52.0)], 4.0, "BLOCK")],
    "oblique": [FaultTrace([(-10.0, -5.0), (110.0, 115.0)], 3.0, "DIAG")],
    "bent": [FaultTrace([(28.0, -10.0), (50.0, 50.0), (72.0, -10.0)], 2.5, "WEDGE")],
    "two": [
        FaultTrace([(50.0, -10.0), (50.0, 110.0)], 2.0, "NS"),
        FaultTrace([(-10.0, 50.0), (110.0, 50.0)], 3.0, "EW"),
    ],
}


@pytest.mark.parametrize("name", list(TRACES))
def test_fault_traces_mean_what_they_mean_in_horizons_to_grdecl(name):
    faults = TRACES[name]
    horizons = [flat_horizon(1000.0), flat_horizon(1020.0)]
    cp = gl.process_grdecl(horizons_to_grdecl(horizons, layers=4, faults=faults))
    r = extrude(gl.cart_grid([10, 10], [100.0, 100.0]), horizons, layers=4, faults=faults)
    assert_same_grid(r, cp)
    assert r.fault_names == tuple(f.name for f in faults)
    assert checked(r.grid).cell_volumes.sum() == pytest.approx(20.0 * 100 * 100, rel=1e-13)


# --------------------------------------------------------------------------- the seed's peaks


PX, PY = np.meshgrid(np.linspace(-3, 3, 15), np.linspace(-3, 3, 15))
PEAKS = peaks(PX, PY)
SEED_AREAL = gl.pebi(gl.triangle_grid(square_sites(40)))


def test_seed_peaks_horizons_on_a_fine_pebi_grid():
    """peaks(15) + 8 and + 16 as gridded horizons, interpolated bilinearly at a PEBI grid's nodes:
    bilinear interpolation is linear in the data, so the thickness is 8 m at every node and the
    volume 8 x 36 m^3 up to round-off (the interpolation error cancels exactly)."""
    top, base = Horizon(PX, PY, PEAKS + 8), Horizon(PX, PY, PEAKS + 16)
    r = extrude(SEED_AREAL, [top, base], layers=4)
    geo = checked(r.grid)
    assert areal_area(SEED_AREAL) == pytest.approx(36.0, rel=1e-13)
    assert geo.cell_volumes.sum() == pytest.approx(288.0, rel=1e-12)
    np.testing.assert_allclose(r.horizons[1] - r.horizons[0], 8.0, rtol=0, atol=1e-13)
    # At the horizon's own nodes that fall on pillars, the top is the sampled value exactly.
    xy = SEED_AREAL.nodes.coords
    on = np.flatnonzero(np.isclose(xy[:, 0], -3.0) & np.isclose(xy[:, 1], -3.0))
    assert on.size == 1 and r.horizons[0][on[0]] == pytest.approx(PEAKS[0, 0] + 8, abs=1e-12)
    # As functions: the same 8 m, now the exact peaks at every node.
    r = extrude(SEED_AREAL, [lambda x, y: peaks(x, y) + 8, lambda x, y: peaks(x, y) + 16], layers=2)
    assert checked(r.grid).cell_volumes.sum() == pytest.approx(288.0, rel=1e-12)


def test_peaks_over_a_flat_base_converges_within_the_interpolation_bound():
    """Top peaks + 8 (exact at the nodes), base 20 m: the cells' tops are the hinge triangulation of
    the nodes (the face's node mean as hinge), so the volume is the integral of that piecewise
    linear interpolant. Per point |f - interpolant| <= M2 h^2 / 2 and the hinge value is off by at
    most M2 h^2 / 2 over a third of the area: |V - V_exact| <= (2/3) M2 h^2 A, with M2 the largest
    Hessian norm of peaks and h the largest cell diameter; the error falls as h^2."""
    xg, wg = np.polynomial.legendre.leggauss(200)  # peaks is entire: Gauss-Legendre is exact here
    gx, gy = np.meshgrid(3 * xg, 3 * xg)
    exact = 36 * 12.0 - float((np.outer(wg, wg) * 9 * peaks(gx, gy)).sum())
    d = 1e-4
    hx, hy = np.meshgrid(np.linspace(-3, 3, 601), np.linspace(-3, 3, 601))
    fxx = (peaks(hx + d, hy) - 2 * peaks(hx, hy) + peaks(hx - d, hy)) / d**2
    fyy = (peaks(hx, hy + d) - 2 * peaks(hx, hy) + peaks(hx, hy - d)) / d**2
    fxy = (peaks(hx + d, hy + d) - peaks(hx + d, hy - d) - peaks(hx - d, hy + d) + peaks(hx - d, hy - d)) / (
        4 * d**2
    )
    m2 = 1.1 * float(np.max(np.abs(fxx + fyy) / 2 + np.sqrt((fxx - fyy) ** 2 / 4 + fxy**2)))  # 10% margin
    errors = []
    for n in (20, 40):
        areal = gl.pebi(gl.triangle_grid(square_sites(n)))
        r = extrude(areal, [lambda x, y: peaks(x, y) + 8, flat(20.0)], layers=3)
        volume = checked(r.grid).cell_volumes.sum()
        pos, ring = areal_corners(areal)
        centre = gl.compute_geometry(areal).cell_centroids[
            np.repeat(np.arange(areal.num_cells), np.diff(pos))
        ]
        h = 2 * np.sqrt(((areal.nodes.coords[ring] - centre) ** 2).sum(axis=1)).max()
        assert abs(volume - exact) <= 2 / 3 * m2 * h**2 * 36
        errors.append(abs(volume - exact))
    assert errors[1] < 3e-3 and 3.0 < errors[0] / errors[1] < 6.0  # second order: halving h quarters it


# --------------------------------------------------------------------------- faults on PEBI grids


PEBI = gl.pebi(gl.triangle_grid(np.random.default_rng(3).uniform(0.0, 1000.0, (400, 2))))
TOP, BASE = plane(1000.0, 0.02, 0.0), plane(1050.0, 0.02, 0.0)


def edge_of_faces(areal: gl.Grid, geo: gl.Geometry, faces: np.ndarray) -> np.ndarray:
    """The areal edge under every lateral face of ``faces``: the one its centroid lies on."""
    e = areal.faces.nodes.reshape(-1, 2)
    a, b = areal.nodes.coords[e[:, 0]], areal.nodes.coords[e[:, 1]]
    p = geo.face_centroids[faces, None, :2]
    t = np.clip(((p - a) * (b - a)).sum(axis=2) / ((b - a) ** 2).sum(axis=1), 0.0, 1.0)
    dist = np.linalg.norm(a + t[..., None] * (b - a) - p, axis=2)
    assert np.all(dist.min(axis=1) < 1e-9)
    return dist.argmin(axis=1)


def test_fault_with_throw_on_a_pebi_grid():
    fault = FaultTrace([(480.0, -50.0), (530.0, 1050.0)], 7.0, "F")
    r = extrude(PEBI, [TOP, BASE], layers=5, faults=[fault])
    g = r.grid
    geo = checked(g)
    assert r.fault_names == ("F",) and r.notes == ()
    assert geo.cell_volumes.sum() == pytest.approx(50.0 * areal_area(PEBI), rel=1e-12)
    on = np.flatnonzero(g.faces.tag == 1)
    edge = edge_of_faces(PEBI, geo, on)
    edges = np.unique(edge)
    assert edges.size > 10 and np.all((PEBI.faces.neighbors[edges] >= 0).all(axis=1))
    # Per fault edge (10 m layers, 7 m throw): 5 same-layer overlaps, 4 layer k against k - 1 (the
    # NNCs) and the two 7 m pieces facing the void above and below: 11 faces.
    np.testing.assert_array_equal(np.bincount(edge)[edges], 11)
    assert r.nnc.num == 4 * edges.size and np.all(r.nnc.kind == FAULT)
    assert np.all(g.faces.tag[r.nnc.face] == 1)
    layer = g.layering.layer[r.nnc.cells]
    np.testing.assert_array_equal(np.abs(layer[:, 0] - layer[:, 1]), 1)
    # Seen from either side, the pieces of a fault edge tile that column's whole 50 m high face.
    e2 = PEBI.faces.nodes.reshape(-1, 2)
    length = np.linalg.norm(PEBI.nodes.coords[e2[:, 0]] - PEBI.nodes.coords[e2[:, 1]], axis=1)
    for side in (0, 1):
        seen = np.bincount(edge, geo.face_areas[on] * (g.faces.neighbors[on, side] >= 0), PEBI.num_faces)
        np.testing.assert_allclose(seen[edges], 50.0 * length[edges], rtol=1e-12)
    # The hanging wall (east of the trace) moved down by 7 m, the footwall did not.
    ref = gl.compute_geometry(extrude(PEBI, [TOP, BASE], layers=5).grid)
    shift = geo.cell_centroids[:, 2] - ref.cell_centroids[:, 2]
    x = geo.cell_centroids[:, 0] - (480.0 + 50.0 / 1100.0 * (geo.cell_centroids[:, 1] + 50.0))
    np.testing.assert_allclose(shift[x > 20.0], 7.0, rtol=0, atol=1e-9)
    np.testing.assert_allclose(shift[x < -20.0], 0.0, rtol=0, atol=1e-9)


def test_fault_tapering_to_a_tip_on_a_pebi_grid_moves_nothing_beyond_it():
    tip = np.array([505.0, 500.0])
    fault = FaultTrace([(480.0, -50.0), tuple(tip)], lambda s: 7.0 * (1.0 - s), "T")
    r = extrude(PEBI, [TOP, BASE], layers=5, faults=[fault])
    ref = extrude(PEBI, [TOP, BASE], layers=5)
    geo, geo_ref = checked(r.grid), gl.compute_geometry(ref.grid)
    assert r.grid.num_cells == ref.grid.num_cells
    assert geo.cell_volumes.sum() == pytest.approx(geo_ref.cell_volumes.sum(), rel=1e-12)
    # Beyond the line through the tip perpendicular to the trace, every node is where it was.
    direction = tip - np.array([480.0, -50.0])
    beyond_ref = ((ref.grid.nodes.coords[:, :2] - tip) @ direction) > 1e-9
    beyond = ((r.grid.nodes.coords[:, :2] - tip) @ direction) > 1e-9
    ref_points = {tuple(p) for p in np.round(ref.grid.nodes.coords[beyond_ref], 9).tolist()}
    points = {tuple(p) for p in np.round(r.grid.nodes.coords[beyond], 9).tolist()}
    assert points == ref_points
    # Fault faces lie only on edges of columns reaching before that line (the cells at the tip).
    on = np.flatnonzero(r.grid.faces.tag == 1)
    edges = np.unique(edge_of_faces(PEBI, geo, on))
    pos, ring = areal_corners(PEBI)
    before = np.bincount(
        np.repeat(np.arange(PEBI.num_cells), np.diff(pos)),
        ((PEBI.nodes.coords[ring] - tip) @ direction) < 0,
        PEBI.num_cells,
    )
    columns = PEBI.faces.neighbors[edges]
    assert edges.size > 5 and np.all((before[columns] > 0).any(axis=1))
    assert r.nnc.num > 0 and np.all(r.grid.faces.tag[r.nnc.face] == 1)
    # The throw tapers from 7 m: no cell moves by more, some near the start move by nearly that.
    shift = np.abs(geo.cell_centroids[:, 2] - geo_ref.cell_centroids[:, 2])
    assert 5.0 < shift.max() <= 7.0 + 1e-9


def test_fault_conforming_areal_grid_keeps_its_tags():
    """An areal grid whose edges along x = 50 are tagged (as a fault-conforming PEBI grid's are):
    the trace gives them their throw, the lateral faces there keep the areal tag."""
    areal = gl.cart_grid([10, 4], [100.0, 40.0])
    e = areal.faces.nodes.reshape(-1, 2)
    on_fault = np.all(np.isclose(areal.nodes.coords[e, 0], 50.0), axis=1)
    tagged = dataclasses.replace(
        areal,
        faces=Faces(
            areal.faces.node_pos, areal.faces.nodes, areal.faces.neighbors, on_fault.astype(np.int32)
        ),
    )
    fault = FaultTrace([(50.0, -10.0), (50.0, 50.0)], 2.5, "MAIN")
    r = extrude(tagged, [flat(1000.0), flat(1010.0)], layers=2, faults=[fault])
    checked(r.grid)
    assert r.fault_names == ("fault_1", "MAIN")
    assert any("keep the tag they already had" in n for n in r.notes)
    # Per edge: 2 same-layer overlaps, 1 NNC (layer 1 against layer 0), 2 void pieces.
    assert int((r.grid.faces.tag == 1).sum()) == 4 * 5 and not (r.grid.faces.tag == 2).any()
    assert r.nnc.num == 4
    # Without throw the tags are still carried, with matching faces and no NNC.
    r = extrude(tagged, [flat(1000.0), flat(1010.0)], layers=2)
    assert int((r.grid.faces.tag == 1).sum()) == 4 * 2 and r.nnc.num == 0


def test_engine_tags_untagged_throw_as_an_automatic_fault():
    areal = gl.cart_grid([2, 1], [2.0, 1.0])
    z = np.array([[100.0] * 8, [110.0] * 4 + [112.0] * 4, [120.0] * 8])  # a throw in layer 0 only
    r = extrude_columns(areal, z)
    assert r.fault_names == ("fault_1",) and r.nnc.num == 1 and r.nnc.kind[0] == FAULT
    np.testing.assert_allclose(gl.compute_geometry(r.grid).cell_volumes, [10.0, 12.0, 10.0, 8.0])
    assert int((r.grid.faces.tag == 1).sum()) == 3  # the three pieces on the middle edge


# --------------------------------------------------------------------------- pinch-outs and masks


def test_zero_thickness_zone_gives_no_cells_and_no_zero_area_faces():
    areal = AREALS["pebi"]
    r = extrude(areal, [flat(1000.0), flat(1000.0), flat(1030.0)], layers=[2, 3])
    geo = checked(r.grid)
    assert r.grid.num_cells == 3 * areal.num_cells
    np.testing.assert_array_equal(r.zone, 1)
    assert geo.face_areas.min() > 1e-6 * geo.face_areas.max()
    assert geo.cell_volumes.sum() == pytest.approx(30.0 * areal_area(areal), rel=1e-12)
    assert r.nnc.num == 0
    assert any(f"{2 * areal.num_cells} cells of zero thickness" in n for n in r.notes)


def test_eroded_layer_pinches_out_and_the_cells_around_it_touch():
    # Zone 1 (1010 m down to a plane 1000 + 0.4 x) is eroded away where the plane lies above 1010 m.
    areal = gl.cart_grid([10, 10], [100.0, 100.0])
    horizons = [flat(1000.0), flat(1010.0), plane(1000.0, 0.4, 0.0), flat(1050.0)]
    with pytest.raises(gl.InputError, match=r"horizons 1 and 2 cross at 33 areal nodes"):
        extrude(areal, horizons)
    r = extrude(areal, horizons, layers=1, ordering="erode")
    assert any("ordering='erode': horizon 2" in n for n in r.notes)
    g = r.grid
    geo = checked(g)
    assert g.num_cells == 300 - 20  # columns i = 0, 1 (x <= 20) have no zone-1 cell
    assert geo.cell_volumes.min() > 0 and geo.face_areas.min() > 1e-6 * geo.face_areas.max()
    assert geo.cell_volumes.sum() == pytest.approx(50.0 * 100 * 100, rel=1e-12)
    # The zone-0 and zone-2 cells of the pinched columns share a face: a PINCH connection.
    assert r.nnc.num == 20 and np.all(r.nnc.kind == PINCH)
    layers = g.layering.layer[r.nnc.cells]
    np.testing.assert_array_equal(layers, np.broadcast_to([0, 2], layers.shape))
    np.testing.assert_array_equal(np.sort(g.layering.column[r.nnc.cells[:, 0]] % 10), np.repeat([0, 1], 10))
    f = r.nnc.face
    np.testing.assert_allclose(geo.face_areas[f], 100.0, rtol=1e-12)
    np.testing.assert_allclose(geo.face_centroids[f, 2], 1010.0, rtol=1e-14)
    # Column i = 2 is pinched on its western pillars only: a wedge, kept with its positive volume.
    wedge = (g.layering.layer == 1) & (g.layering.column % 10 == 2)
    np.testing.assert_allclose(geo.cell_volumes[wedge], 10 * 10 * 2.0 / 2, rtol=1e-12)


def test_active_masks_cells_and_their_junk_is_never_read():
    areal = AREALS["triangles"]
    area = gl.compute_geometry(areal).cell_volumes
    active = np.ones((3, areal.num_cells), dtype=bool)
    active[1, ::3] = False  # a gap in every third column
    active[:, 5] = False  # a whole column
    r = extrude(areal, [flat(0.0), flat(30.0)], layers=3, active=active)
    geo = checked(r.grid)
    assert r.grid.num_cells == int(active.sum())
    assert geo.cell_volumes.sum() == pytest.approx(10.0 * (area * active.sum(axis=0)).sum(), rel=1e-12)
    assert r.nnc.num == 0  # nothing joins cells across the masked ones
    # Depths undefined at the nodes of masked columns only are fine; elsewhere they are an error.
    _, ring = areal_corners(areal)
    pos = areal.cells.face_pos
    own_nodes = ring[pos[5] : pos[6]]
    shared = np.isin(own_nodes, np.delete(ring, np.arange(pos[5], pos[6])))
    base = np.full(areal.num_nodes, 30.0)
    base[own_nodes[~shared]] = np.nan
    if (~shared).any():
        r2 = extrude(areal, [flat(0.0), base], layers=3, active=active)
        assert r2.grid.num_cells == r.grid.num_cells
    base[own_nodes] = np.nan
    with pytest.raises(
        gl.InputError, match=r"horizon 1 is undefined \(NaN\) at \d+ areal nodes of active cells"
    ):
        extrude(areal, [flat(0.0), base], layers=3, active=active)
    # A per-column mask applies to every layer.
    r3 = extrude(areal, [flat(0.0), flat(30.0)], layers=3, active=np.arange(areal.num_cells) != 5)
    assert r3.grid.num_cells == 3 * (areal.num_cells - 1)


# --------------------------------------------------------------------------- inclined pillars


def test_inclined_pillars_match_the_equivalent_corner_point_deck():
    """Skewed straight pillars through a Cartesian areal grid, tilted horizons given as functions:
    the depth where each pillar meets each horizon (the fixed point), then the same deck through
    process_grdecl gives the same grid and volumes."""
    nx, ny = 6, 4
    areal = gl.cart_grid([nx, ny], [600.0, 400.0])
    xy = areal.nodes.coords
    shift = np.column_stack([0.1 * xy[:, 0] - 0.05 * xy[:, 1], 0.08 * xy[:, 1]])
    lines = np.stack(
        [
            np.column_stack([xy, np.full(len(xy), 900.0)]),
            np.column_stack([xy + shift, np.full(len(xy), 1200.0)]),
        ],
        axis=1,
    )
    top, base = plane(1000.0, 0.05, 0.02), plane(1060.0, -0.03, 0.04)
    fault = FaultTrace([(290.0, -10.0), (310.0, 410.0)], 12.0, "F")
    r = extrude(areal, [top, base], layers=3, faults=[fault], pillars=lines)
    g = r.grid
    checked(g)
    # The top nodes lie on the top horizon, on their pillars.
    top_nodes = g.faces.nodes[g.faces.node_pos[0] : g.faces.node_pos[1]]
    p = g.nodes.coords[top_nodes]
    np.testing.assert_allclose(p[:, 2], top(p[:, 0], p[:, 1]), rtol=0, atol=1e-9)
    # The equivalent deck: COORD = the pillars, ZCORN = the corner depths the front end computed.
    H = r.horizons
    levels = np.concatenate([H[0] + (H[1] - H[0]) * t for t in (0.0, 1 / 3, 2 / 3)] + [H[1]]).reshape(4, -1)
    pos, ring = areal_corners(areal)
    c = np.repeat(np.arange(nx * ny), np.diff(pos))
    i, j = c % nx, c // nx
    col, row = 2 * i + (ring % (nx + 1) - i), 2 * j + (ring // (nx + 1) - j)
    centre_x = gl.compute_geometry(areal).cell_centroids[:, 0]
    hanging = (
        np.interp(gl.compute_geometry(areal).cell_centroids[:, 1], [-10.0, 410.0], [290.0, 310.0]) < centre_x
    )
    zc = np.empty((6, 2 * ny, 2 * nx))
    for k in range(3):
        zc[2 * k, row, col] = levels[k, ring] + 12.0 * hanging[c]
        zc[2 * k + 1, row, col] = levels[k + 1, ring] + 12.0 * hanging[c]
    deck = gl.Deck((nx, ny, 3), lines.reshape(-1), zc.ravel(), None, source="test")
    cp = gl.process_grdecl(deck)
    assert (g.num_cells, g.num_faces, r.nnc.num) == (cp.grid.num_cells, cp.grid.num_faces, cp.nnc.num)
    np.testing.assert_allclose(
        gl.compute_geometry(g).cell_volumes, gl.compute_geometry(cp.grid).cell_volumes, rtol=1e-12
    )
    assert r.nnc.num > 0


def test_parallel_inclined_pillars_shear_without_changing_volume():
    areal = AREALS["pebi"]
    xy = areal.nodes.coords
    lines = np.stack(
        [
            np.column_stack([xy, np.zeros(len(xy))]),
            np.column_stack([xy + [300.0, -100.0], np.full(len(xy), 1000.0)]),
        ],
        axis=1,
    )
    r = extrude(areal, [flat(100.0), flat(130.0)], layers=3, pillars=lines)
    geo = checked(r.grid)
    assert geo.cell_volumes.sum() == pytest.approx(30.0 * areal_area(areal), rel=1e-12)
    np.testing.assert_allclose(
        geo.cell_centroids[:, 0].mean() - gl.compute_geometry(areal).cell_centroids[:, 0].mean(),
        0.3 * 115.0,
        rtol=0.05,
    )


# --------------------------------------------------------------------------- bad input


AREAL = gl.cart_grid([3, 2], [3.0, 2.0])
H0, H1 = flat(0.0), flat(10.0)


@pytest.mark.parametrize(
    ("args", "kwargs", "error", "message"),
    [
        (
            (gl.cart_grid([2, 2, 2]), [H0, H1]),
            {},
            gl.GridError,
            r"extrude: areal must be a 2-D grid \(griddim 2\)",
        ),
        ((AREAL, H0), {}, gl.InputError, r"horizons must be a sequence of at least two horizons"),
        ((AREAL, [H0]), {}, gl.InputError, r"need at least two horizons \(top first\), got 1"),
        ((AREAL, [H0, "deep"]), {}, gl.InputError, r"horizon 1: expected a function f\(x, y\), an array"),
        (
            (AREAL, [H0, np.zeros(5)]),
            {},
            gl.InputError,
            r"horizon 1: an array horizon needs one depth per areal node \(12,\)",
        ),
        ((AREAL, [H0, lambda x, y: x[:2]]), {}, gl.InputError, r"horizon 1: f\(x, y\) failed"),
        (
            (AREAL, [H0, lambda x, y: np.nan * x]),
            {},
            gl.InputError,
            r"horizon 1 is undefined \(NaN\) at 12 areal nodes",
        ),
        (
            (AREAL, [H0, {"x": AXIS, "y": AXIS[:5], "z": np.zeros((11, 11))}]),
            {},
            gl.InputError,
            r"extrude: horizon 1: z has shape",
        ),
        (
            (AREAL, [H0, H1]),
            {"layers": 0},
            gl.InputError,
            r"extrude: layers must be a positive integer.*zone 0 has 0",
        ),
        ((AREAL, [H0, H1, H1]), {"layers": [2]}, gl.InputError, r"one per zone \(2 zones\), got 1 values"),
        (
            (AREAL, [H1, H0]),
            {},
            gl.InputError,
            r"extrude: horizons 0 and 1 cross at 12 areal nodes .*first at \(x, y\) = \(0, 0\)",
        ),
        (
            (AREAL, [H0, H1]),
            {"ordering": "sort"},
            gl.InputError,
            r"ordering must be one of error, erode, onlap",
        ),
        (
            (AREAL, [H0, H1]),
            {"active": np.ones((2, 6), bool)},
            gl.InputError,
            r"active must have shape \(n_layers, n_areal_cells\) = \(1, 6\)",
        ),
        (
            (AREAL, [H0, H1]),
            {"pillars": np.zeros((12, 3))},
            gl.InputError,
            r"pillars: expected .* \(12, 2, 3\)",
        ),
        (
            (AREAL, [H0, H1]),
            {"pillars": np.full((12, 2, 3), np.nan)},
            gl.InputError,
            r"pillars: coordinates must be finite",
        ),
        ((AREAL, [H0, H1]), {"faults": ["F"]}, gl.InputError, r"faults\[0\]: expected a FaultTrace"),
        (
            (AREAL, [H0, H1]),
            {"faults": FaultTrace([(0, 0), (1, 1)], 1.0)},
            gl.InputError,
            r"faults must be a sequence",
        ),
        (
            (AREAL, [H0, H1]),
            {"faults": [FaultTrace([(0, 0), (1, 1)], lambda s: s / 0)]},
            gl.InputError,
            r"fault 'F1' \(faults\[0\]\): throw\(s\) must be finite",
        ),
        (
            (AREAL, [H0, H1]),
            {"centres": np.zeros((6, 3)), "faults": [FaultTrace([(0, 0), (1, 1)], 1.0)]},
            gl.InputError,
            r"centres must be \(6, 2\)",
        ),
    ],
)
def test_bad_input_is_a_clear_error(args, kwargs, error, message):
    with np.errstate(all="ignore"), pytest.raises(error, match=message):
        extrude(*args, **kwargs)


@pytest.mark.parametrize(
    ("z", "kwargs", "message"),
    [
        (np.zeros((2, 5)), {}, r"z: expected depths of shape \(n_levels >= 2, 24\)"),
        (np.zeros((1, 24)), {}, r"z: expected depths of shape"),
        (
            np.r_[np.zeros((1, 24)), -np.ones((1, 24))],
            {},
            r"z: the cell in layer 0 of areal cell 0 has its bottom above its top",
        ),
        (
            np.r_[np.zeros((1, 24)), np.full((1, 24), np.nan)],
            {},
            r"z: level 1, corner 0 \(areal cell 0\) of an active cell is NaN",
        ),
        (np.zeros((2, 24)), {}, r"z: every active cell has zero thickness"),
        (
            np.r_[np.zeros((1, 24)), np.ones((1, 24))],
            {"active": np.zeros((1, 6), bool)},
            r"active: no active cell",
        ),
        (
            np.r_[np.zeros((1, 24)), np.ones((1, 24))],
            {"active": np.ones(6, bool)},
            r"active: expected shape \(n_layers, n_areal_cells\) = \(1, 6\)",
        ),
        (
            np.r_[np.zeros((1, 24)), np.ones((1, 24))],
            {"edge_tag": np.ones(3, int)},
            r"edge_tag: expected one non-negative integer per areal edge \(17\)",
        ),
    ],
)
def test_engine_bad_input_is_a_clear_error(z, kwargs, message):
    with pytest.raises(gl.InputError, match=message):
        extrude_columns(AREAL, z, **kwargs)


def test_engine_needs_a_2d_areal_grid():
    with pytest.raises(gl.GridError, match=r"areal: expected a 2-D grid \(griddim 2\), got a 3-D grid"):
        extrude_columns(gl.cart_grid([1, 1, 1]), np.zeros((2, 4)))
