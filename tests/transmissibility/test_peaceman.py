"""Well connection factors: Flow's own for three decks, exact values by hand, the PEBI form
against fine two-point flux solutions around a well, and bad input.

Flow's factors come from its restart file after one short report step
(flow_tools.flow_connection_factors); they are float32, so they are compared at 1e-6.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from flow_tools import PROPS_AND_SOLUTION, flow_connection_factors

import gridlib as gl
from gridlib.cornerpoint.corners import corner_points
from gridlib.cornerpoint.deck import Deck
from gridlib.cornerpoint.generators import simple_grdecl
from gridlib.cornerpoint.process import process_grdecl
from gridlib.errors import InputError
from gridlib.io.grdecl import read_grdecl, write_grdecl
from gridlib.transmissibility import deck_cell_extents, deck_well_index, transmissibility, well_index
from gridlib.transmissibility.deck_connections import rock_arrays
from gridlib.transmissibility.peaceman import PEBI_RADIUS
from gridlib.units import FIELD, METRIC

PROPS_2010 = PROPS_AND_SOLUTION.format(datum=2010, owc=2100)  # equilibrium: datum 2010 m, contact 2100 m
FLOAT32 = 1e-6

# ------------------------------------------------------------------ Flow's factors, three decks


def compare_with_flow(deck_path: Path, out: Path, completion: Callable[[str], tuple[float, float, str]]):
    """Flow's factors and ours for every connection Flow made; ``completion(well)``: the
    well's (radius, skin, direction) as its COMPDAT gives them. Returns (wells, ours, Flow's,
    the deck, the connections' cells)."""
    flow = flow_connection_factors(deck_path, out)
    deck = read_grdecl(deck_path)
    wells = [w for w, _ in flow]
    cells = np.array([g for _, g in flow])
    radius, skin, direction = (np.array([completion(w)[i] for w in wells]) for i in range(3))
    ours = deck_well_index(deck, cells, radius, skin, direction)
    return wells, ours, np.array(list(flow.values())), deck, cells


@pytest.mark.parametrize(
    ("relpath", "radius", "wells", "connections"),
    [("spe1/SPE1CASE1.DATA", 0.25, 2, 2), ("spe9/SPE9_CP.DATA", 0.5, 26, 80)],
    ids=["SPE1CASE1", "SPE9_CP"],
)
def test_vertical_wells_of_real_decks_equal_flows(decks_dir, tmp_path, relpath, radius, wells, connections):
    # every well of these decks is vertical, with the same diameter and no skin
    w, ours, flow, deck, _ = compare_with_flow(decks_dir / relpath, tmp_path, lambda _: (radius, 0.0, "z"))
    assert len(set(w)) == wells and flow.size == connections
    assert deck.units == "FIELD"
    np.testing.assert_allclose(ours, flow, rtol=FLOAT32)


WRAPPER = """\
-- a faulted corner-point deck with anisotropic permeability and NTG, wells in every direction
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
 10 20 2 10 /
START
 1 'JAN' 2020 /
UNIFOUT
GRID
INCLUDE
 'grid.grdecl' /
{props}SCHEDULE
WELSPECS
{welspecs}/
COMPDAT
{compdat}/
WCONPROD
{wconprod}/
WCONINJE
 'I1' 'WATER' 'OPEN' 'RATE' 50.0 1* 400.0 /
/
TSTEP
 1 /
END
"""

# well: (I, J, K1, K2 per record (1-based), diameter (m), skin, direction)
OWN_WELLS = {
    "P1": ([(2, 2, 1, 4)], 0.2, 0.0, "Z"),
    "P2": ([(5, 4, 1, 4)], 0.3, 1.5, "Z"),  # in the downthrown block
    "I1": ([(1, 5, 2, 3)], 0.25, -0.5, "Z"),
    "P3": ([(6, 1, 1, 3)], 0.178, 3.0, "Z"),
    "H1": ([(i, 3, 3, 3) for i in range(2, 6)], 0.2, 0.0, "X"),  # across the fault
    "H2": ([(3, j, 2, 2) for j in range(1, 6)], 0.2, 0.7, "Y"),
}


def write_own_deck(folder: Path) -> Path:
    """A 6x5x4 METRIC deck: MRST's simpleGrdecl (skewed pillars, sine-perturbed layers, a fault
    with an 8 m throw) at 2000 m depth, random anisotropic permeability and NTG."""
    base = simple_grdecl([6, 5, 4], 8.0, phys_dims=(600.0, 500.0, 40.0))
    coord = base.coord.reshape(-1, 6).copy()
    coord[:, [2, 5]] += 2000.0
    deck = Deck(base.cart_dims, coord.ravel(), base.zcorn + 2000.0, base.actnum, units="METRIC")
    rng = np.random.default_rng(7)
    n = deck.num_cells
    permx = rng.uniform(20.0, 800.0, n)
    data = {
        "PERMX": permx,
        "PERMY": permx * rng.uniform(0.1, 1.0, n),
        "PERMZ": permx * rng.uniform(0.01, 0.2, n),
        "NTG": rng.uniform(0.3, 1.0, n),
        "PORO": np.full(n, 0.2),
    }
    write_grdecl(folder / "grid.grdecl", deck, cell_data=data)
    welspecs, compdat = "", ""
    for name, (records, diameter, skin, direction) in OWN_WELLS.items():
        i, j = records[0][:2]
        phase = "WATER" if name.startswith("I") else "OIL"
        welspecs += f" '{name}' 'G1' {i} {j} 1* '{phase}' /\n"
        for i, j, k1, k2 in records:
            compdat += f" '{name}' {i} {j} {k1} {k2} 'OPEN' 1* 1* {diameter} 1* {skin} 1* '{direction}' /\n"
    wconprod = "".join(f" '{w}' 'OPEN' 'BHP' 5* 150.0 /\n" for w in OWN_WELLS if not w.startswith("I"))
    nx, ny, nz = deck.cart_dims
    path = folder / "OWN.DATA"
    path.write_text(
        WRAPPER.format(
            nx=nx,
            ny=ny,
            nz=nz,
            welspecs=welspecs,
            compdat=compdat,
            wconprod=wconprod,
            props=PROPS_AND_SOLUTION.format(datum=2010, owc=2100),
        )
    )
    return path


def test_own_faulted_deck_in_every_direction_equals_flows(tmp_path):
    src = tmp_path / "deck"
    src.mkdir()
    path = write_own_deck(src)
    completions = {w: (d / 2, s, direction) for w, (_, d, s, direction) in OWN_WELLS.items()}
    wells, ours, flow, deck, cells = compare_with_flow(path, tmp_path / "flow", completions.__getitem__)
    expected = sum(k2 - k1 + 1 for records, *_ in OWN_WELLS.values() for _, _, k1, k2 in records)
    assert flow.size == expected == 22 and set(wells) == set(OWN_WELLS)
    np.testing.assert_allclose(ours, flow, rtol=FLOAT32)

    # the same through the grid-level function, with the deck's extents and rock per grid cell
    cp = process_grdecl(deck)
    glob = cp.grid.cells.index_map
    perm, ntg = rock_arrays(deck)
    rows = np.searchsorted(glob, cells)
    radius, skin, direction = (np.array([completions[w][i] for w in wells]) for i in range(3))
    geo = gl.compute_geometry(cp.grid)
    extents = deck_cell_extents(deck, cells)
    args = (cp.grid, geo, perm[glob], rows, radius, skin, direction)
    same = well_index(*args, ntg=ntg[glob], extents=extents, units="METRIC")
    np.testing.assert_array_equal(same, ours)
    # extents from the processed grid's faces (cell_extents) are Flow's up to the faces' warp
    from_faces = well_index(*args, ntg=ntg[glob], units="METRIC")
    assert np.abs(from_faces / flow - 1).max() < 1e-4


# ------------------------------------------------------------------ exact values by hand


def test_cartesian_cell_by_hand():
    g = gl.cart_grid([3, 3, 1], [300.0, 150.0, 10.0])  # cells 100 x 50 x 10 m
    geo = gl.compute_geometry(g)
    c = METRIC.darcy_constant
    # isotropic 200 mD, radius 0.1 m, skin 2: r0 = 0.14 sqrt(100^2 + 50^2)
    r0 = 0.14 * math.sqrt(100.0**2 + 50.0**2)
    expected = 2 * math.pi * 200.0 * 10.0 * c / (math.log(r0 / 0.1) + 2.0)
    assert well_index(g, geo, 200.0, [4], 0.1, 2.0)[0] == pytest.approx(expected, rel=1e-14)

    # anisotropic kx 400, ky 100, kz 20 mD, NTG 0.5
    perm = np.tile([400.0, 100.0, 20.0], (9, 1))
    ntg = np.full(9, 0.5)
    cf = well_index(g, geo, perm, [4, 4, 4], 0.1, 0.0, ["z", "x", "y"], ntg=ntg)
    # z: across (kx, dx), (ky, dy); length dz NTG = 5 m
    r0 = 0.28 * math.sqrt(math.sqrt(100 / 400) * 100**2 + math.sqrt(400 / 100) * 50**2)
    r0 /= (100 / 400) ** 0.25 + (400 / 100) ** 0.25
    z = 2 * math.pi * math.sqrt(400 * 100) * 5.0 * c / math.log(r0 / 0.1)
    # x: across (ky, dy) and (kz, dz NTG); length dx = 100 m, NTG not on it
    r0 = 0.28 * math.sqrt(math.sqrt(20 / 100) * 50**2 + math.sqrt(100 / 20) * 5.0**2)
    r0 /= (20 / 100) ** 0.25 + (100 / 20) ** 0.25
    x = 2 * math.pi * math.sqrt(100 * 20) * 100.0 * c / math.log(r0 / 0.1)
    # y: across (kz, dz NTG) and (kx, dx); length dy = 50 m
    r0 = 0.28 * math.sqrt(math.sqrt(400 / 20) * 5.0**2 + math.sqrt(20 / 400) * 100**2)
    r0 /= (400 / 20) ** 0.25 + (20 / 400) ** 0.25
    y = 2 * math.pi * math.sqrt(20 * 400) * 50.0 * c / math.log(r0 / 0.1)
    np.testing.assert_allclose(cf, [z, x, y], rtol=1e-14)

    # FIELD: feet and cP rb/(day psi)
    f = well_index(g, geo, 200.0, [0], 0.25, units="FIELD")[0]
    r0 = 0.14 * math.sqrt(100.0**2 + 50.0**2)
    assert f == pytest.approx(2 * math.pi * 200 * 10 * FIELD.darcy_constant / math.log(r0 / 0.25), rel=1e-14)


def test_radius_beyond_r0_and_zero_permeability_as_flow():
    g = gl.cart_grid([1, 1, 1], [10.0, 10.0, 2.0])
    geo = gl.compute_geometry(g)
    # r0 = 1.98 m < radius 3 m: the logarithm is 0 (Flow's min(rw, r0)); the skin carries it
    cf = well_index(g, geo, 100.0, [0], 3.0, 0.5)[0]
    assert cf == pytest.approx(2 * math.pi * 100 * 2 * METRIC.darcy_constant / 0.5, rel=1e-14)
    with pytest.raises(InputError, match="radius, skin"):
        well_index(g, geo, 100.0, [0], 3.0)  # infinite, as Flow would compute
    assert well_index(g, geo, [[0.0, 0.0, 5.0]], [0], 0.1)[0] == 0.0
    assert well_index(g, geo, 100.0, [0], 0.1, ntg=[0.0])[0] == 0.0  # no net length


def test_deck_extents_are_flows_construction():
    deck = simple_grdecl([3, 2, 2], 0.1, phys_dims=(30.0, 20.0, 4.0))
    cells = np.arange(deck.num_cells)
    p = corner_points(deck, cells)
    ext = deck_cell_extents(deck, cells)
    i_minus, i_plus = p[:, [0, 2, 4, 6]].mean(axis=1), p[:, [1, 3, 5, 7]].mean(axis=1)
    j_minus, j_plus = p[:, [0, 1, 4, 5]].mean(axis=1), p[:, [2, 3, 6, 7]].mean(axis=1)
    np.testing.assert_allclose(ext[:, 0], np.hypot(*(i_plus - i_minus)[:, :2].T), rtol=1e-14)
    np.testing.assert_allclose(ext[:, 1], np.hypot(*(j_plus - j_minus)[:, :2].T), rtol=1e-14)
    np.testing.assert_allclose(ext[:, 2], p[:, 4:, 2].mean(axis=1) - p[:, :4, 2].mean(axis=1), rtol=1e-14)


# ------------------------------------------------------------------ the PEBI form


def numerical_r0(pebi: gl.PebiGrid, cell: int, outer: float) -> tuple[float, float]:
    """Peaceman's equivalent radius of ``cell`` from a steady two-point flux solution (K = 1,
    unit thickness) around a well in it: sites farther than ``outer`` from the well hold the
    exact radial pressure ln(r) / (2 pi) of a unit sink, the well cell's pressure is then
    ln(r0) / (2 pi). Returns (r0, the cell's area)."""
    g = pebi.grid
    geo = gl.compute_geometry(g)
    c = transmissibility(g, geo, 1.0, centres=pebi.sites)
    t = c.trans / METRIC.darcy_constant  # K l / d
    a, b = c.cells.T
    n = g.num_cells
    lap = sp.coo_matrix((np.r_[-t, -t, t, t], (np.r_[a, b, a, b], np.r_[b, a, a, b])), shape=(n, n)).tocsr()
    r = np.hypot(*(pebi.sites - pebi.sites[cell]).T)
    fixed = r > outer
    free = np.flatnonzero(~fixed)
    p_fixed = np.log(r[fixed]) / (2 * np.pi)
    rhs = -(lap[free][:, fixed] @ p_fixed)
    rhs[np.searchsorted(free, cell)] -= 1.0
    p = spl.spsolve(lap[free][:, free].tocsc(), rhs)
    return math.exp(2 * math.pi * p[np.searchsorted(free, cell)]), float(geo.cell_volumes[cell])


def test_pebi_radius_constant_is_exact_for_regular_hexagons():
    assert PEBI_RADIUS == pytest.approx(math.exp(-0.5772156649015329) / (math.sqrt(2) * 3**0.75), rel=1e-15)
    pebi = gl.pebi_grid(((0.0, 0.0), (2000.0, 2000.0)), 40.0)
    centre = int(np.argmin(np.hypot(*(pebi.sites - 1000.0).T)))
    r0, area = numerical_r0(pebi, centre, 700.0)
    assert r0 / math.sqrt(area) == pytest.approx(PEBI_RADIUS, rel=2e-4)


def test_pebi_form_against_a_fine_solution_around_a_well():
    """A well site off the lattice, replacing the nearest lattice site (its cell is no longer a
    regular hexagon): the PEBI form's r0 is the fine solution's within 0.5 %, the factor
    within 0.1 %."""
    pebi = gl.pebi_grid(((0.0, 0.0), (2000.0, 2000.0)), 40.0, wells=[gl.Well((1005.0, 1003.0))])
    cell = int(np.flatnonzero(pebi.cell_well == 1)[0])
    r0, area = numerical_r0(pebi, cell, 700.0)
    assert PEBI_RADIUS * math.sqrt(area) / r0 == pytest.approx(1.0, abs=5e-3)
    g = pebi.grid
    cf = well_index(g, gl.compute_geometry(g), 150.0, [cell], 0.1, 1.0)[0]  # 2-D: per metre
    exact = 2 * math.pi * 150.0 * METRIC.darcy_constant / (math.log(r0 / 0.1) + 1.0)
    assert cf == pytest.approx(exact, rel=1e-3)

    # the same solve on a Cartesian lattice gives Peaceman's e^-gamma / (2 sqrt 2) dx, within
    # 0.3 % of the 0.28 / sqrt(2) dx Flow uses for a square cell of the same area
    square = gl.pebi_grid(((0.0, 0.0), (2000.0, 2000.0)), 40.0, pattern="cartesian")
    centre = int(np.argmin(np.hypot(*(square.sites - 1000.0).T)))
    r0, area = numerical_r0(square, centre, 700.0)
    assert r0 / math.sqrt(area) == pytest.approx(math.exp(-0.5772156649015329) / (2 * math.sqrt(2)), rel=2e-4)
    g = square.grid
    flow_like = well_index(g, gl.compute_geometry(g), 150.0, [centre], 0.1, form="peaceman")[0]
    assert flow_like * math.log(0.28 / math.sqrt(2) * 40.0 / 0.1) == pytest.approx(
        2 * math.pi * 150.0 * METRIC.darcy_constant, rel=1e-12
    )


def test_pebi_form_in_a_layered_grid_with_anisotropy():
    pebi = gl.pebi_grid(((0.0, 0.0), (400.0, 300.0)), 50.0)
    x = pebi.grid.nodes.coords[:, 0]
    layered = gl.make_layered_grid(
        pebi.grid, depths=np.stack([1000 + 0.01 * x, 1004 + 0.02 * x, 1010 + 0.01 * x])
    )
    geo = gl.compute_geometry(layered)
    cell = int(np.argmax(geo.cell_volumes))
    area = gl.compute_geometry(pebi.grid).cell_volumes[layered.layering.column[cell]]
    thickness = geo.cell_volumes[cell] / area
    k = np.tile([300.0, 75.0, 30.0], (layered.num_cells, 1))
    cf = well_index(layered, geo, k, [cell], 0.1, ntg=np.full(layered.num_cells, 0.8))[0]
    r0 = PEBI_RADIUS * math.sqrt(area) * 2 / ((75 / 300) ** 0.25 + (300 / 75) ** 0.25)
    expected = (
        2 * math.pi * math.sqrt(300 * 75) * thickness * 0.8 * METRIC.darcy_constant / math.log(r0 / 0.1)
    )
    assert cf == pytest.approx(expected, rel=1e-12)


# ------------------------------------------------------------------ bad input


def test_bad_input_names_the_argument(tmp_path):
    g = gl.cart_grid([3, 3, 1], [30.0, 30.0, 3.0])
    geo = gl.compute_geometry(g)
    with pytest.raises(InputError, match=r"^cells: completion 1 is in cell 9, which does not exist"):
        well_index(g, geo, 100.0, [0, 9], 0.1)
    with pytest.raises(InputError, match=r"^cells: completion 0 is in cell -1"):
        well_index(g, geo, 100.0, [-1], 0.1)
    for radius in (0.0, -0.1):
        with pytest.raises(InputError, match=r"^radius: the well radius must be positive"):
            well_index(g, geo, 100.0, [0, 1], [0.1, radius])
    with pytest.raises(InputError, match=r"^permeability: required"):
        well_index(g, geo, None, [0], 0.1)
    with pytest.raises(InputError, match=r"^permeability: expected one value"):
        well_index(g, geo, np.ones(4), [0], 0.1)
    with pytest.raises(InputError, match=r"^direction: completion 0 has 'w'"):
        well_index(g, geo, 100.0, [0], 0.1, direction="w")
    deck = simple_grdecl([2, 2, 1])
    with pytest.raises(InputError, match=r"PERMX: the deck gives no permeability"):
        deck_well_index(deck, [0], 0.1)
    with_perm = Deck(deck.cart_dims, deck.coord, deck.zcorn, [1, 0, 1, 1], {"PERMX": np.full(4, 10.0)})
    with pytest.raises(InputError, match=r"^cells: completion 0 is in inactive cell 1 \(2, 1, 1\)"):
        deck_well_index(with_perm, [1], 0.1)
    with pytest.raises(InputError, match=r"^cells: completion 0 is in cell 4, which does not exist"):
        deck_well_index(with_perm, [4], 0.1)
