"""Directional connection factors of well pieces (gridlib.wells.factors) and a well's
connections (gridlib.wells.connections): pieces along the cell axes, and paths located by
path_cells, equal OPM Flow's own COMPDAT factors (one Flow run); deviated pieces the
documented combination computed here with scalar math; the cell axes ResInsight's
construction; runs and cells entered twice, and merged branches, exact arrays."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from flow_tools import PROPS_AND_SOLUTION, flow_connection_factors

import gridlib as gl
from gridlib.errors import InputError
from gridlib.grid import Nodes
from gridlib.transmissibility import cell_extents, well_index
from gridlib.units import FIELD, METRIC
from gridlib.wells import WellPath, cell_index, path_cells
from gridlib.wells.connections import merge_connections, well_connections
from gridlib.wells.factors import axis_lengths, cell_axes, main_direction, trajectory_factors
from gridlib.wells.intersect import PathCells

FLOAT32 = 1e-6  # Flow's restart file stores the factors as float32
C = METRIC.darcy_constant

# ------------------------------------------------------------------ a box deck, Flow's COMPDAT factors

DX, DY, DZ = [80.0, 120.0, 60.0], [50.0, 90.0], [4.0, 7.0]  # per column i, row j, layer k
TOP = 2000.0
NX, NY, NZ = len(DX), len(DY), len(DZ)
NTG = {(0, 0, 1): 0.5, (1, 1, 1): 0.6, (1, 0, 0): 0.8}  # 0-based (i, j, k): NTG below 1
# well: (cells (i, j, k) 1-based, diameter (m), skin, direction)
WELLS = {
    "V1": ([(1, 1, 1), (1, 1, 2)], 0.2, 0.0, "Z"),
    "V2": ([(3, 1, 1), (3, 1, 2)], 0.3, 2.5, "Z"),
    "HX": ([(1, 2, 2), (2, 2, 2), (3, 2, 2)], 0.25, -0.5, "X"),
    "HY": ([(2, 1, 1), (2, 2, 1)], 0.2, 1.0, "Y"),
}

DECK = """\
RUNSPEC
DIMENS
 {nx} {ny} {nz} /
OIL
WATER
METRIC
TABDIMS
 1 1 20 20 /
EQLDIMS
 1 /
WELLDIMS
 4 10 1 4 /
START
 1 'JAN' 2020 /
UNIFOUT
GRID
DX
 {dx} /
DY
 {dy} /
DZ
 {dz} /
TOPS
 {tops} /
PORO
 {n}*0.2 /
PERMX
 {permx} /
PERMY
 {permy} /
PERMZ
 {permz} /
NTG
 {ntg} /
{props}SCHEDULE
WELSPECS
{welspecs}/
COMPDAT
{compdat}/
WCONPROD
{wconprod}/
TSTEP
 1 /
END
"""


def rock() -> tuple[np.ndarray, np.ndarray]:
    """Anisotropic permeability (n, 3) mD and NTG (n,) per cell, i fastest."""
    n = NX * NY * NZ
    rng = np.random.default_rng(26)
    kx = np.round(rng.uniform(50.0, 900.0, n), 1)
    k = np.column_stack(
        [kx, np.round(kx * rng.uniform(0.2, 1.0, n), 1), np.round(kx * rng.uniform(0.02, 0.3, n), 2)]
    )
    ntg = np.ones(n)
    for (i, j, kk), v in NTG.items():
        ntg[i + NX * (j + NY * kk)] = v
    return k, ntg


def write_deck(folder: Path) -> Path:
    k, ntg = rock()
    per_cell = np.meshgrid(range(NX), range(NY), range(NZ), indexing="ij")
    i, j, kk = (a.transpose(2, 1, 0).ravel() for a in per_cell)  # i fastest

    def values(v: np.ndarray) -> str:
        return " ".join(f"{x:.10g}" for x in v)

    welspecs = compdat = wconprod = ""
    for name, (cells, diameter, skin, direction) in WELLS.items():
        welspecs += f" '{name}' 'G1' {cells[0][0]} {cells[0][1]} 1* 'OIL' /\n"
        for ci, cj, ck in cells:
            compdat += f" '{name}' {ci} {cj} {ck} {ck} 'OPEN' 1* 1* {diameter} 1* {skin} 1* '{direction}' /\n"
        wconprod += f" '{name}' 'OPEN' 'BHP' 5* 150.0 /\n"
    text = DECK.format(
        nx=NX,
        ny=NY,
        nz=NZ,
        n=NX * NY * NZ,
        dx=values(np.array(DX)[i]),
        dy=values(np.array(DY)[j]),
        dz=values(np.array(DZ)[kk]),
        tops=f"{NX * NY}*{TOP}",
        permx=values(k[:, 0]),
        permy=values(k[:, 1]),
        permz=values(k[:, 2]),
        ntg=values(ntg),
        props=PROPS_AND_SOLUTION.format(datum=2005, owc=2100),
        welspecs=welspecs,
        compdat=compdat,
        wconprod=wconprod,
    )
    path = folder / "BOX.DATA"
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def flow_factors(tmp_path_factory) -> dict[tuple[str, int], float]:
    """Flow's factors {(well, cell): CF} of the box deck (one short run)."""
    folder = tmp_path_factory.mktemp("box")
    return flow_connection_factors(write_deck(folder), folder / "flow")


def box_grid() -> gl.Grid:
    """The deck's grid (cell i + nx (j + ny k), z depth)."""
    return gl.tensor_grid(np.cumsum([0.0, *DX]), np.cumsum([0.0, *DY]), np.cumsum([TOP, *DZ]))


def test_pieces_along_the_axes_equal_flows_compdat_factors(flow_factors):
    g = box_grid()
    geo = gl.compute_geometry(g)
    k, ntg = rock()
    cells, radius, skin, axis, wells = [], [], [], [], []
    for name, (ijk, diameter, s, direction) in WELLS.items():
        for i, j, kk in ijk:
            cells.append(i - 1 + NX * (j - 1 + NY * (kk - 1)))
            radius.append(diameter / 2)
            skin.append(s)
            axis.append("XYZ".index(direction))
            wells.append(name)
    cells, axis = np.array(cells), np.array(axis)
    assert sorted(flow_factors) == sorted(zip(wells, cells.tolist(), strict=True))
    flow = np.array([flow_factors[(w, c)] for w, c in zip(wells, cells.tolist(), strict=True)])

    # a straight piece through the whole cell along its axis: from face centre to face centre
    size = np.column_stack(
        [np.array(DX)[cells % NX], np.array(DY)[cells // NX % NY], np.array(DZ)[cells // (NX * NY)]]
    )
    vectors = np.zeros((cells.size, 3))
    vectors[np.arange(cells.size), axis] = size[np.arange(cells.size), axis]
    lengths = axis_lengths(cell_axes(g, geo, cells), vectors)
    np.testing.assert_array_equal(lengths, vectors)
    cf, direction = trajectory_factors(g, geo, k, cells, lengths, radius, skin, ntg=ntg)
    np.testing.assert_allclose(cf, flow, rtol=FLOAT32)
    np.testing.assert_array_equal(direction, axis)
    # exactly COMPDAT's factor for that direction (well_index), NTG and skin included
    same = well_index(g, geo, k, cells, radius, skin, np.array(["x", "y", "z"])[axis], ntg=ntg)
    np.testing.assert_array_equal(cf, same)


def test_paths_through_the_box_make_flows_connections(flow_factors):
    """Whole chain: a vertical and an east-west path, located (path_cells) and connected
    (well_connections), give Flow's COMPDAT factors for V1 and HX."""
    g = box_grid()
    geo = gl.compute_geometry(g)
    k, ntg = rock()
    x_mid, y_mid = 0.5 * DX[0], DY[0] + 0.5 * DY[1]
    paths = {
        "V1": WellPath.from_points([(x_mid, 0.5 * DY[0], TOP - 10.0), (x_mid, 0.5 * DY[0], TOP + 20.0)]),
        "HX": WellPath.from_points(
            [(-10.0, y_mid, TOP + 7.5), (sum(DX) + 10.0, y_mid, TOP + 7.5)], start_md=500.0
        ),
    }
    index = cell_index(g, geo)
    for name, path in paths.items():
        ijk, diameter, skin, direction = WELLS[name]
        conn = well_connections(
            g, geo, k, ntg, path_cells(g, geo, path, index=index), diameter / 2, skin, units="METRIC"
        )
        cells = [i - 1 + NX * (j - 1 + NY * (kk - 1)) for i, j, kk in ijk]
        assert conn.cell.tolist() == cells
        assert conn.direction.tolist() == ["XYZ".index(direction)] * len(cells)
        np.testing.assert_allclose(conn.factor, [flow_factors[(name, c)] for c in cells], rtol=FLOAT32)
    np.testing.assert_allclose(conn.entry_md, 500.0 + 10.0 + np.r_[0.0, np.cumsum(DX[:-1])], rtol=1e-14)
    np.testing.assert_allclose(conn.length, DX, rtol=1e-12)


# ------------------------------------------------------------------ deviated pieces, by hand


def by_hand(k: tuple[float, float, float], d: tuple[float, float, float], lengths, rw, skin, ntg) -> float:
    """The module docstring's combination in scalar math: COMPDAT's factor per axis with the
    piece's length along it, NTG on dz and on L_z, sqrt of the sum of the squares."""
    kx, ky, kz = k
    dx, dy, dz = d
    lx, ly, lz = lengths

    def one(k1, k2, d1, d2, length):
        if k1 * k2 == 0 or length == 0:
            return 0.0
        r0 = 0.28 * math.sqrt(math.sqrt(k2 / k1) * d1 * d1 + math.sqrt(k1 / k2) * d2 * d2)
        r0 /= (k2 / k1) ** 0.25 + (k1 / k2) ** 0.25
        return 2 * math.pi * math.sqrt(k1 * k2) * length * C / (math.log(r0 / min(rw, r0)) + skin)

    cx = one(ky, kz, dy, dz * ntg, lx)
    cy = one(kz, kx, dz * ntg, dx, ly)
    cz = one(kx, ky, dx, dy, lz * ntg)
    return math.sqrt(cx * cx + cy * cy + cz * cz)


def test_a_deviated_piece_is_the_documented_combination():
    g = box_grid()
    geo = gl.compute_geometry(g)
    cell = 1 + NX * (1 + NY * 1)  # (2, 2, 2): 120 x 90 x 7 m
    perm = np.tile([400.0, 150.0, 25.0], (g.num_cells, 1))
    lengths = [[30.0, 20.0, 5.0]]
    results = {}
    for ntg, skin in [(1.0, 0.0), (0.6, 0.0), (0.6, 1.5), (1.0, -1.0)]:
        cf, direction = trajectory_factors(
            g, geo, perm, [cell], lengths, 0.1, skin, ntg=np.full(g.num_cells, ntg)
        )
        expected = by_hand((400.0, 150.0, 25.0), (120.0, 90.0, 7.0), (30.0, 20.0, 5.0), 0.1, skin, ntg)
        assert cf[0] == pytest.approx(expected, rel=1e-14)
        assert direction.tolist() == [2]  # shares 30/120, 20/90, 5/7: z
        results[ntg, skin] = cf[0]
    # NTG lowers the factor (less net length along z, a thinner cell across x and y); skin too
    assert results[0.6, 0.0] < results[1.0, 0.0] and results[0.6, 1.5] < results[0.6, 0.0]
    assert results[1.0, -1.0] > results[1.0, 0.0]
    # FIELD units: the same formula with FIELD's Darcy constant, lengths in feet
    f, _ = trajectory_factors(g, geo, perm, [cell], lengths, 0.1, units="FIELD")
    assert f[0] == pytest.approx(results[1.0, 0.0] * FIELD.darcy_constant / C, rel=1e-14)


def test_a_cell_wider_than_the_well_radius_allows_and_zero_permeability_as_flow():
    g = gl.cart_grid([1, 1, 1], [10.0, 10.0, 2.0])
    geo = gl.compute_geometry(g)
    # r0 along x (across dy = 10, dz = 2) is 0.14 sqrt(104) = 1.43 m < radius 3 m: that
    # factor's logarithm is 0 (Flow's min(rw, r0)) and the skin carries it
    cf, _ = trajectory_factors(g, geo, 100.0, [0], [[4.0, 0.0, 0.0]], 3.0, 0.5)
    assert cf[0] == pytest.approx(2 * math.pi * 100 * 4.0 * C / 0.5, rel=1e-14)
    # no permeability across z (kx = ky = 0): the z factor is 0, x's and y's remain
    cf, _ = trajectory_factors(g, geo, [[0.0, 0.0, 50.0]], [0, 0], [[0.0, 0.0, 2.0], [3.0, 0.0, 1.0]], 0.1)
    assert cf[0] == 0.0 and cf[1] == 0.0  # sqrt(ky kz) = sqrt(kz kx) = 0 too
    cf, _ = trajectory_factors(g, geo, [[20.0, 0.0, 50.0]], [0, 0], [[0.0, 0.0, 2.0], [0.0, 3.0, 0.0]], 0.1)
    assert cf[0] == 0.0
    assert cf[1] == pytest.approx(
        by_hand((20.0, 0.0, 50.0), (10.0, 10.0, 2.0), (0.0, 3.0, 0.0), 0.1, 0.0, 1.0), rel=1e-14
    )


# ------------------------------------------------------------------ cell axes


def affine_grid(a: np.ndarray) -> gl.Grid:
    """A 2 x 2 x 2 box grid (cells 40 x 30 x 5 m at 1000 m) with its nodes mapped by ``a``
    (3 x 3) about the origin: its cells' sides are parallelograms."""
    g = gl.tensor_grid([0.0, 40.0, 80.0], [0.0, 30.0, 60.0], [1000.0, 1005.0, 1010.0])
    return replace(g, nodes=Nodes(np.einsum("ij,nj->ni", a, g.nodes.coords)))


def test_axes_of_a_sheared_cell_are_resinsights_orthonormal_axes():
    shear = np.array([[1.0, 0.3, 0.1], [0.05, 1.0, -0.2], [0.02, 0.04, 1.0]])
    g = affine_grid(shear)
    geo = gl.compute_geometry(g)
    axes = cell_axes(g, geo, np.arange(8))
    # the construction by hand for every cell (all cells are the same parallelepiped):
    # I, J between the means of opposite sides' corners, K = I x J, symmetrised x and y
    i_vec = shear @ [40.0, 0.0, 0.0]
    j_vec = shear @ [0.0, 30.0, 0.0]

    def unit(v):
        return v / math.sqrt(float(v @ v))

    z = unit(np.cross(i_vec, j_vec))
    x = unit(i_vec + np.cross(j_vec, z))
    y = unit(j_vec - np.cross(i_vec, z))
    for a in axes:
        np.testing.assert_allclose(a, [x, y, z], atol=1e-14)
        np.testing.assert_allclose(a @ a.T, np.eye(3), atol=1e-14)  # orthonormal
    # lengths along orthonormal axes are projections: their squares sum to the length squared
    v = np.array([[12.0, -7.0, 3.0]] * 8)
    lengths = axis_lengths(axes, v)
    np.testing.assert_allclose(lengths, np.abs(v @ np.array([x, y, z]).T), rtol=1e-13)
    np.testing.assert_allclose((lengths**2).sum(axis=1), 202.0, rtol=1e-14)


def test_a_grid_rotated_in_plan_has_the_same_factors():
    t = math.radians(30.0)
    rotation = np.array([[math.cos(t), -math.sin(t), 0.0], [math.sin(t), math.cos(t), 0.0], [0.0, 0.0, 1.0]])
    plain, turned = affine_grid(np.eye(3)), affine_grid(rotation)
    piece = np.array([25.0, -12.0, 3.0])  # in the cell's own axes
    perm = np.tile([300.0, 80.0, 12.0], (8, 1))
    cf = []
    for g, v in ((plain, piece), (turned, rotation @ piece)):
        geo = gl.compute_geometry(g)
        lengths = axis_lengths(cell_axes(g, geo, [5]), [v])
        np.testing.assert_allclose(lengths, [np.abs(piece)], rtol=1e-13)
        cf.append(trajectory_factors(g, geo, perm, [5], lengths, 0.1, 0.3)[0][0])
    assert cf[1] == pytest.approx(cf[0], rel=1e-13)
    assert cf[0] == pytest.approx(
        by_hand((300.0, 80.0, 12.0), (40, 30, 5), np.abs(piece), 0.1, 0.3, 1.0), rel=1e-14
    )


def test_pebi_cells_use_the_global_axes_and_the_pebi_form_along_z():
    pebi = gl.pebi_grid(((0.0, 0.0), (400.0, 300.0)), 50.0)
    layered = gl.make_layered_grid(
        pebi.grid, depths=np.stack([np.full(pebi.grid.num_nodes, z) for z in (1000, 1006)])
    )
    geo = gl.compute_geometry(layered)
    cell = int(np.argmax(geo.cell_volumes))
    np.testing.assert_array_equal(cell_axes(layered, geo, [cell])[0], np.eye(3))
    perm = np.tile([300.0, 75.0, 30.0], (layered.num_cells, 1))
    ntg = np.full(layered.num_cells, 0.8)
    cf, _ = trajectory_factors(layered, geo, perm, [cell], [[0.0, 0.0, 6.0]], 0.1, ntg=ntg)
    assert cf[0] == well_index(layered, geo, perm, [cell], 0.1, ntg=ntg)[0]  # the PEBI form, as "auto"
    # along x: Peaceman's form with the bounding box's dy and the thickness V / A
    cf, _ = trajectory_factors(layered, geo, perm, [cell], [[20.0, 0.0, 0.0]], 0.1, ntg=ntg)
    full = well_index(layered, geo, perm, [cell], 0.1, direction="x", ntg=ntg)[0]  # length dx
    assert cf[0] == pytest.approx(full * 20.0 / cell_extents(layered, geo, [cell])[0, 0], rel=1e-14)


# ------------------------------------------------------------------ direction, bad input


def test_main_direction_is_the_largest_share_of_the_extent():
    ext = np.tile([100.0, 50.0, 5.0], (6, 1))
    lengths = [
        [60.0, 10.0, 1.0],
        [20.0, 20.0, 1.0],
        [10.0, 5.0, 1.0],
        [50.0, 25.0, 2.5],
        [0, 0, 0],
        [1.0, 0, 0],
    ]
    assert main_direction(lengths, ext).tolist() == [0, 1, 2, 2, 2, 0]
    assert main_direction([[1.0, 1.0, 0.0]], [[0.0, 10.0, 5.0]]).tolist() == [0]  # zero extent


def test_bad_input_names_the_argument():
    g = gl.cart_grid([2, 1, 1], [20.0, 10.0, 2.0])
    geo = gl.compute_geometry(g)
    with pytest.raises(InputError, match=r"^lengths: expected finite, non-negative"):
        trajectory_factors(g, geo, 100.0, [0], [[1.0, -1.0, 0.0]], 0.1)
    with pytest.raises(InputError, match=r"^lengths: .* shape \(2, 3\)"):
        trajectory_factors(g, geo, 100.0, [0, 1], [[1.0, 1.0, 0.0]], 0.1)
    with pytest.raises(InputError, match=r"^cells: completion 0 is in cell 2, which does not exist"):
        trajectory_factors(g, geo, 100.0, [2], [[1.0, 1.0, 0.0]], 0.1)
    with pytest.raises(InputError, match=r"^radius: the well radius must be positive"):
        trajectory_factors(g, geo, 100.0, [0], [[1.0, 1.0, 0.0]], 0.0)
    with pytest.raises(InputError, match=r"^ntg: expected one value in \[0, 1\]"):
        trajectory_factors(g, geo, 100.0, [0], [[1.0, 1.0, 0.0]], 0.1, ntg=[1.2, 1.0])
    flat = gl.cart_grid([2, 2])
    with pytest.raises(InputError, match=r"^cells: well paths cross the cells of 3-D grids only"):
        trajectory_factors(flat, gl.compute_geometry(flat), 100.0, [0], [[1.0, 1.0, 0.0]], 0.1)
    with pytest.raises(InputError, match=r"^axes: the axes of piece 0 are degenerate"):
        axis_lengths([[[1.0, 0, 0], [2.0, 0, 0], [0, 0, 1.0]]], [[1.0, 0, 0]])
    with pytest.raises(InputError, match=r"^axes, vectors: expected shapes"):
        axis_lengths(np.eye(3), [[1.0, 0, 0]])


# ------------------------------------------------------------------ a well's connections


def pieces_of(points: list[tuple[float, float, float]], cells: list[int], runs: list[int]) -> PathCells:
    """Pieces between consecutive ``points``, MD their cumulative length."""
    p = np.array(points, dtype=np.float64)
    md = np.r_[0.0, np.cumsum(np.sqrt(((p[1:] - p[:-1]) ** 2).sum(axis=1)))]
    return PathCells(np.array(cells), md[:-1], md[1:], p[:-1], p[1:], np.array(runs))


def test_pieces_make_runs_and_a_cell_entered_twice_one_connection():
    g = gl.tensor_grid(
        [0.0, 10.0, 20.0, 30.0], [0.0, 10.0, 20.0], [1000.0, 1010.0]
    )  # cells 0, 1, 2 at y < 10
    geo = gl.compute_geometry(g)
    perm = np.tile([200.0, 100.0, 20.0], (g.num_cells, 1))
    ntg = np.full(g.num_cells, 0.9)
    # into cell 0, bending in it, over to cell 1 and back to cell 0, then east through 1 and 2
    points = [(1, 5, 1002), (5, 5, 1004), (10, 5, 1005), (15, 5, 1006), (10, 5, 1007), (5, 5, 1008)]
    points += [(10, 5, 1008), (20, 5, 1008), (25, 5, 1008)]
    pieces = pieces_of(points, [0, 0, 1, 1, 0, 0, 1, 2], [0, 0, 1, 2, 3, 3, 4, 5])
    conn = well_connections(g, geo, perm, ntg, pieces, 0.1, 1.0, units="METRIC")
    md = pieces.exit_md
    np.testing.assert_array_equal(conn.cell, [0, 1, 2])
    np.testing.assert_array_equal(conn.entry_md, [0.0, md[1], md[6]])
    np.testing.assert_array_equal(conn.exit_md, [md[5], md[6], md[7]])
    np.testing.assert_array_equal(conn.entry, [points[0], points[2], points[7]])
    np.testing.assert_array_equal(conn.exit, [points[6], points[7], points[8]])
    np.testing.assert_allclose(
        conn.length, [md[1] + md[5] - md[3], md[3] - md[1] + md[6] - md[5], 5.0], rtol=1e-15
    )
    # per piece |dx|, |dy|, |dz| (the global axes of a box), summed over the cell's pieces
    np.testing.assert_array_equal(conn.axis_length, [[19.0, 0.0, 4.0], [20.0, 0.0, 2.0], [5.0, 0.0, 0.0]])
    # per run the factor of its lengths; a cell's runs add up
    runs = np.array(
        [[9.0, 0.0, 3.0], [5.0, 0.0, 1.0], [5.0, 0.0, 1.0], [10.0, 0.0, 1.0], [10.0, 0.0, 0.0], [5.0, 0, 0]]
    )
    f, _ = trajectory_factors(g, geo, perm, [0, 1, 1, 0, 1, 2], runs, 0.1, 1.0, ntg=ntg)
    np.testing.assert_array_equal(conn.factor, [f[0] + f[3], (f[1] + f[2]) + f[4], f[5]])
    np.testing.assert_array_equal(conn.direction, [0, 0, 0])
    assert len(conn) == 3 and not conn.factor.flags.writeable

    # Flow's extents given per grid cell: the same factors here (boxes), direction by share
    ext = np.tile([10.0, 10.0, 10.0], (g.num_cells, 1))
    same = well_connections(g, geo, perm, ntg, pieces, 0.1, 1.0, units="METRIC", extents=ext)
    np.testing.assert_allclose(same.factor, conn.factor, rtol=1e-14)


def test_a_cells_direction_is_its_strongest_runs_and_branches_merge():
    g = gl.tensor_grid([0.0, 10.0, 20.0, 30.0], [0.0, 10.0, 20.0], [1000.0, 1010.0])
    geo = gl.compute_geometry(g)
    perm = np.full(g.num_cells, 100.0)
    # a short run north in cell 0, out to cell 3 and back, then down in cell 0
    points = [(8, 8, 1001), (8, 10, 1001), (8, 12, 1001.5), (8, 10, 1002), (8, 9, 1009)]
    parent = pieces_of(points, [0, 3, 3, 0], [0, 1, 1, 2])
    conn = well_connections(g, geo, perm, None, parent, 0.1, 0.0, units="METRIC")
    np.testing.assert_array_equal(conn.cell, [0, 3])
    np.testing.assert_array_equal(conn.axis_length, [[0.0, 3.0, 7.0], [0.0, 4.0, 1.0]])
    assert conn.direction.tolist() == [2, 1]  # cell 0: its vertical run has the larger factor

    # a branch from cell 3 east into cell 4: cell 3 is shared, one connection
    branch = pieces_of([(3, 15, 1002), (10, 15, 1002), (14, 15, 1002)], [3, 4], [0, 1])
    lateral = well_connections(g, geo, perm, None, branch, 0.1, 0.0, units="METRIC")
    merged = merge_connections(conn, lateral)
    np.testing.assert_array_equal(merged.cell, [0, 3, 4])
    np.testing.assert_array_equal(
        merged.factor, [conn.factor[0], conn.factor[1] + lateral.factor[0], lateral.factor[1]]
    )
    np.testing.assert_array_equal(merged.axis_length[1], [7.0, 4.0, 1.0])
    np.testing.assert_array_equal(merged.entry_md, [conn.entry_md[0], conn.entry_md[1], lateral.entry_md[1]])
    np.testing.assert_array_equal(merged.exit[1], lateral.exit[0])  # the last branch's
    assert lateral.factor[0] > conn.factor[1]
    assert merged.direction.tolist() == [2, 0, 0]  # cell 3: the branch's 7 m along x has the larger factor
    assert len(merge_connections()) == 0 and merge_connections(conn).cell.tolist() == [0, 3]


def test_bad_pieces_are_named():
    g = gl.cart_grid([2, 1, 1], [20.0, 10.0, 2.0])
    geo = gl.compute_geometry(g)
    good = pieces_of([(1, 5, 1), (15, 5, 1)], [0], [0])
    with pytest.raises(InputError, match=r"^pieces: run ids must be 0, 1, \.\.\."):
        well_connections(g, geo, 100.0, None, replace(good, run=np.array([1])), 0.1, 0.0, units="METRIC")
    with pytest.raises(InputError, match=r"^pieces: inconsistent shapes .*'entry': \(1, 2\)"):
        well_connections(g, geo, 100.0, None, replace(good, entry=np.zeros((1, 2))), 0.1, 0.0, units="METRIC")
    two = pieces_of([(1, 5, 1), (5, 5, 1), (15, 5, 1)], [0, 1], [0, 0])
    with pytest.raises(InputError, match=r"^pieces: a run's pieces must all be in one cell"):
        well_connections(g, geo, 100.0, None, two, 0.1, 0.0, units="METRIC")
    with pytest.raises(InputError, match=r"^skin: expected one value or one per piece \(1\)"):
        well_connections(g, geo, 100.0, None, good, 0.1, [0.0, 1.0], units="METRIC")
    with pytest.raises(InputError, match=r"^extents: expected \(dx, dy, dz\) per grid cell, shape \(2, 3\)"):
        well_connections(g, geo, 100.0, None, good, 0.1, 0.0, units="METRIC", extents=np.ones((1, 3)))
