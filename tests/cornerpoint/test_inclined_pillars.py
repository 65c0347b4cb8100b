"""horizons_to_pillar_grdecl (issue 25, fault_geometry: pillars): corner-point pillars that follow
inclined faults. MRST's simpleGrdecl fault, pinned at the top and as its own plane against
gridlib's simple_grdecl deck (analytic volumes, fault areas, NNC counts); a tilted oblique fault
(analytic block volumes, every fault node on the plane, no column inverting at any depth); a
twisted surface of sticks; tips; T, X and Y junctions against OPM Flow's dry run; vertical faults
on lattice lines (horizons_to_grdecl's deck bit for bit); and the errors."""

from __future__ import annotations

import numpy as np
import pytest
from flow_tools import assert_same_connections, flow_connections, read_keywords, rest_of_deck, run_flow_dry

import gridlib as gl
from gridlib.cornerpoint.between_horizons import Horizon, horizons_to_grdecl
from gridlib.cornerpoint.deck import FaultSegment
from gridlib.cornerpoint.generators import simple_grdecl
from gridlib.cornerpoint.pillar_grdecl import horizons_to_pillar_grdecl
from gridlib.cornerpoint.process import process_grdecl
from gridlib.errors import InputError
from gridlib.io.grdecl import read_grdecl, write_grdecl
from gridlib.pillars.fault_surface import FaultSurface
from gridlib.pillars.fault_traces import FaultTrace
from gridlib.pillars.inclined_lines import PillarLines, first_crossing
from gridlib.transmissibility import deck_transmissibility


def flat_box(lx: float, ly: float, z0: float, z1: float) -> list[Horizon]:
    x, y = np.linspace(0.0, lx, 3), np.linspace(0.0, ly, 3)
    return [Horizon(x, y, np.full((3, 3), z0)), Horizon(x, y, np.full((3, 3), z1))]


def dip_fault(points, top_depth, dip: float, side: str, throw: float, name: str) -> FaultTrace:
    pts = np.asarray(points, dtype=np.float64)
    surface = FaultSurface.from_dip(pts, top_depth, dip, side, name=name)
    return FaultTrace(pts, throw, name, side, surface=surface)


def plane_offset(nodes: np.ndarray, a, b, z_a: float, z_b: float, dip: float, side: str) -> np.ndarray:
    """Signed distance (m, horizontal, across strike) of points (n, 3) from the plane of a straight
    dip fault: trace a -> b at the top horizon (depths z_a, z_b there), dipping ``dip`` degrees
    towards ``side``. Written from the definition, independently of gridlib."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    length = np.hypot(*(b - a))
    t = (b - a) / length
    n = np.array([t[1], -t[0]]) if side == "right" else np.array([-t[1], t[0]])
    rel = nodes[:, :2] - a
    along = rel @ t / length
    return rel @ n - (nodes[:, 2] - (z_a + along * (z_b - z_a))) / np.tan(np.radians(dip))


def tagged_nodes(grid, tag: int) -> np.ndarray:
    faces = np.flatnonzero(grid.faces.tag == tag)
    idx = np.concatenate(
        [grid.faces.nodes[grid.faces.node_pos[f] : grid.faces.node_pos[f + 1]] for f in faces]
    )
    return grid.nodes.coords[np.unique(idx)]


def column_crossing(deck):
    """first_crossing of every column of the deck with cells, from its COORD and ZCORN alone."""
    nx, ny, nz = deck.cart_dims
    p = deck.pillars().reshape(-1, 2, 3)
    s = (p[:, 1, :2] - p[:, 0, :2]) / (p[:, 1, 2] - p[:, 0, 2])[:, None]
    zc = deck.zcorn_array().reshape(2 * nz, ny, 2, nx, 2)
    lo, hi = zc.min(axis=(0, 2, 4)).ravel(), zc.max(axis=(0, 2, 4)).ravel()
    jj, ii = np.divmod(np.flatnonzero(np.isfinite(lo)), nx)  # columns with an undefined corner hold no cell
    n0 = jj * (nx + 1) + ii
    ring = np.stack([n0, n0 + 1, n0 + nx + 2, n0 + nx + 1], axis=1).ravel()
    lines = PillarLines(p[:, 0], s)
    keep = jj * nx + ii
    return first_crossing(lines, np.arange(0, ring.size + 1, 4), ring, lo[keep], hi[keep])


def processed(deck):
    r = process_grdecl(deck)
    geo = gl.compute_geometry(r.grid)
    gl.check_grid(r.grid, geo)
    assert geo.cell_volumes.min() > 0
    assert column_crossing(deck) is None
    return r, geo


def assert_monotone_zcorn(deck) -> None:
    """What Flow's fixupZCORN would change: a cell's top above the bottom of the cell above on
    any corner, or a bottom above its own top. None may exist."""
    nx, ny, nz = deck.cart_dims
    z = deck.zcorn_array().reshape(nz, 2, 2 * ny, 2 * nx)
    assert np.all(z[:, 1] >= z[:, 0])
    assert np.all(z[1:, 0] >= z[:-1, 1])


# --------------------------------------------------------------------------- simpleGrdecl


@pytest.mark.parametrize(("dims", "nz", "nnc"), [((4, 2), 3, 4), ((8, 4), 5, 28)])
def test_simple_grdecl_fault_pinned_at_the_top(dims, nz, nnc):
    """MRST's simpleGrdecl fault (drift 0.1 towards +x, dip atan(10), throw d = 0.12 on the east
    half of [0, 1]^2 x [0, 0.5]) with its pillars pinned at the top instead of the base, so the
    fault runs x = 0.5 + 0.1 z: west = int_0^0.5 (0.5 + 0.1 z) dz = 0.2625, east =
    int_d^{0.5+d} (0.5 - 0.1 z) dz = 0.2375 - 0.05 d; the fault faces between the blocks cover
    (0.5 - d) sqrt(1.01) and those against nothing 2 d sqrt(1.01) (the book's 4 and 28 NNCs)."""
    d = 0.12
    dip = np.degrees(np.arctan(10.0))
    fault = dip_fault([[0.5, -0.5], [0.5, 1.5]], [0.0, 0.0], dip, "right", d, "F")
    deck = horizons_to_pillar_grdecl(flat_box(1.0, 1.0, 0.0, 0.5), dims, nz, [fault], relax_distance=0.5)
    r, geo = processed(deck)
    assert_monotone_zcorn(deck)
    i = r.grid.cells.index_map % dims[0]
    west = i < dims[0] // 2
    assert geo.cell_volumes[west].sum() == pytest.approx(0.2625, rel=1e-12)
    assert geo.cell_volumes[~west].sum() == pytest.approx(0.2375 - 0.05 * d, rel=1e-12)
    assert r.nnc.num == nnc
    tagged = r.grid.faces.tag == r.fault_names.index("F") + 1
    inner = (r.grid.faces.neighbors >= 0).all(axis=1)
    assert geo.face_areas[tagged & inner].sum() == pytest.approx((0.5 - d) * np.sqrt(1.01), rel=1e-12)
    assert geo.face_areas[tagged & ~inner].sum() == pytest.approx(2 * d * np.sqrt(1.01), rel=1e-12)
    # The fault pillars lean 0.1 m east per metre of depth, the boundary pillars stay vertical.
    p = deck.pillars()
    lean = (p[..., 1, 0] - p[..., 0, 0]) / (p[..., 1, 2] - p[..., 0, 2])
    np.testing.assert_allclose(lean[:, dims[0] // 2], 0.1, rtol=0, atol=1e-14)
    assert np.all(lean[:, [0, -1]] == 0)


@pytest.mark.parametrize("dims", [(4, 2, 3), (8, 4, 5)])
def test_simple_grdecl_fault_itself_equals_mrsts_deck(dims):
    """The same plane as MRST's simpleGrdecl fault (x = 0.45 + 0.1 z: its trace at the top is
    x = 0.45): the book's block volumes 0.2375 and 0.2625 - 0.05 d = 0.2565, and the fault faces
    and NNCs of gridlib's own simple_grdecl deck (flat, drop 0.12), whose inner pillars lean
    differently (the tent) but whose blocks, boundary and fault are the same."""
    d = 0.12
    fault = dip_fault([[0.45, -0.5], [0.45, 1.5]], [0.0, 0.0], np.degrees(np.arctan(10.0)), "right", d, "F")
    deck = horizons_to_pillar_grdecl(
        flat_box(1.0, 1.0, 0.0, 0.5), dims[:2], dims[2], [fault], relax_distance=0.5
    )
    r, geo = processed(deck)
    ref = process_grdecl(simple_grdecl(dims, d, flat=True))
    ref_geo = gl.compute_geometry(ref.grid)
    west = r.grid.cells.index_map % dims[0] < dims[0] // 2
    ref_west = ref.grid.cells.index_map % dims[0] < dims[0] // 2
    assert geo.cell_volumes[west].sum() == pytest.approx(0.2375, rel=1e-12)
    assert geo.cell_volumes[~west].sum() == pytest.approx(0.2625 - 0.05 * d, rel=1e-12)
    assert ref_geo.cell_volumes[ref_west].sum() == pytest.approx(0.2375, rel=1e-12)
    assert r.nnc.num == ref.nnc.num

    def fault_area(grid, geometry) -> float:
        """Area of the faces between the cells of columns i = nx/2 - 1 and nx/2 (any j, k)."""
        nb = grid.faces.neighbors
        i = np.where(nb >= 0, grid.cells.index_map[nb] % dims[0], -1)
        return float(
            geometry.face_areas[(i.min(axis=1) == dims[0] // 2 - 1) & (i.max(axis=1) == dims[0] // 2)].sum()
        )

    assert fault_area(r.grid, geo) == pytest.approx((0.5 - d) * np.sqrt(1.01), rel=1e-12)
    assert fault_area(ref.grid, ref_geo) == pytest.approx((0.5 - d) * np.sqrt(1.01), rel=1e-12)


# --------------------------------------------------------------------------- a tilted oblique fault

BOX = (400.0, 200.0)  # m
Z0, Z1 = 1000.0, 1060.0  # flat top and base (m)
TRACE = np.array([[170.0, -40.0], [230.0, 240.0]])  # at the top horizon, leaving the box at y = 0 and 200


def tilted(dip: float = 60.0, throw: float = 12.0, dims=(10, 5), **kw):
    fault = dip_fault(TRACE, [Z0, Z0], dip, "right", throw, "F1")
    return horizons_to_pillar_grdecl(flat_box(*BOX, Z0, Z1), dims, 3, [fault], **kw)


def test_tilted_oblique_fault_blocks_and_fault_faces_are_exact():
    """A plane through TRACE dipping 60 degrees east, throw 12 m down: x_F(y, z) is linear in y
    and z, so the footwall holds Ly H (x_F(Ly/2, mid) - 0) and the hanging wall, on
    [Z0 + T, Z1 + T], Ly H (Lx - x_F(Ly/2, mid + T)); every node of a fault face lies on the plane."""
    dip, throw = 60.0, 12.0
    deck = tilted(dip, throw)
    r, geo = processed(deck)
    assert_monotone_zcorn(deck)
    (Lx, Ly), H, mid = BOX, Z1 - Z0, 0.5 * (Z0 + Z1)
    (ax, ay), (bx, by) = TRACE
    m = (bx - ax) / (by - ay)
    t = (TRACE[1] - TRACE[0]) / np.hypot(*(TRACE[1] - TRACE[0]))
    shift = (t[1] - (-t[0]) * m) / np.tan(np.radians(dip))  # east of the trace: n = (t_y, -t_x)

    def x_fault(y, z):
        return ax + (y - ay) * m + (z - Z0) * shift

    footwall = Ly * H * x_fault(Ly / 2, mid)
    hanging = Ly * H * (Lx - x_fault(Ly / 2, mid + throw))
    (seg,) = deck.faults
    i = r.grid.cells.index_map % deck.cart_dims[0]
    fw = i <= seg.i1
    assert geo.cell_volumes[fw].sum() == pytest.approx(footwall, rel=1e-12)
    assert geo.cell_volumes[~fw].sum() == pytest.approx(hanging, rel=1e-12)
    nodes = tagged_nodes(r.grid, r.fault_names.index("F1") + 1)
    offset = plane_offset(nodes, TRACE[0], TRACE[1], Z0, Z0, dip, "right")
    assert np.abs(offset).max() < 1e-9 * Lx
    # The fault faces cover the plane between the top and the hanging wall's base.
    assert nodes[:, 2].min() == pytest.approx(Z0) and nodes[:, 2].max() == pytest.approx(Z1 + throw)


def test_a_small_relax_distance_is_one_error_naming_the_fault_and_column():
    deck = tilted(dims=(20, 5))  # 20 m cells, the fault leans 42 m over the 72 m the pillars carry
    assert column_crossing(deck) is None
    with pytest.raises(InputError, match=r"fault 'F1' cross or invert \d+ columns, first column \(i, j\) = "):
        tilted(dims=(20, 5), relax_distance=10.0)
    with pytest.raises(InputError, match="increase relax_distance \\(now 10 m"):
        tilted(dims=(20, 5), relax_distance=10.0)
    with pytest.raises(InputError, match="relax_distance must be a positive number"):
        tilted(relax_distance=0.0)


def test_vertical_faults_get_lattice_lines_and_vertical_pillars():
    """Without a surface (or at dip 90) the fault is vertical: its lattice line follows the oblique
    trace, every pillar is vertical, and the fault faces lie in the vertical plane of the trace."""
    for fault in (
        FaultTrace(TRACE, 12.0, "F1", "right"),
        dip_fault(TRACE, [Z0, Z0], 90.0, "right", 12.0, "F1"),
    ):
        deck = horizons_to_pillar_grdecl(flat_box(*BOX, Z0, Z1), (10, 5), 3, [fault])
        r, geo = processed(deck)
        p = deck.pillars()
        np.testing.assert_array_equal(p[..., 0, :2], p[..., 1, :2])
        nodes = tagged_nodes(r.grid, 1)
        assert np.abs(plane_offset(nodes, TRACE[0], TRACE[1], Z0, Z0, 90.0, "right")).max() < 1e-9 * BOX[0]
        assert geo.cell_volumes.sum() == pytest.approx(BOX[0] * BOX[1] * (Z1 - Z0), rel=1e-12)


def test_two_faults_on_lines_of_one_family_that_cross_are_one_error():
    """An X of two faults both closer to north-south: the lattice cannot carry them."""
    a = dip_fault(TRACE, [Z0, Z0], 60.0, "right", 12.0, "A")
    b = dip_fault([[300.0, -40.0], [180.0, 240.0]], [Z0, Z0], 70.0, "right", 5.0, "B")
    with pytest.raises(
        InputError, match=r"fault 'A' and fault 'B' meet or cross .*use fault_geometry: stair_steps"
    ):
        horizons_to_pillar_grdecl(flat_box(*BOX, Z0, Z1), (10, 5), 3, [a, b])


# --------------------------------------------------------------------------- junctions, against Flow

X_AXIS, Y_AXIS = np.linspace(0.0, 400.0, 5), np.linspace(0.0, 200.0, 3)


def sloping_top(x, y):
    return 1000.0 + 0.02 * x + 0.01 * y


def junction_case() -> tuple[list[Horizon], list[FaultTrace]]:
    """Sloping horizons; A crosses the box north-south dipping 60 degrees east, B comes from the
    west and ends on A (a T), dipping 70 degrees north, C crosses A (an X) dipping 75 degrees south,
    D splays off A to the north-east (a Y of two faults closer to north-south) dipping 70 degrees."""
    QX, QY = np.meshgrid(X_AXIS, Y_AXIS)
    top = sloping_top(QX, QY)
    horizons = [Horizon(X_AXIS, Y_AXIS, top), Horizon(X_AXIS, Y_AXIS, top + 40.0 + 0.01 * QX)]

    def fault(points, dip, side, throw, name):
        pts = np.asarray(points, dtype=np.float64)
        z = sloping_top(np.clip(pts[:, 0], 0.0, 400.0), np.clip(pts[:, 1], 0.0, 200.0))
        return dip_fault(pts, z, dip, side, throw, name)

    a = fault([[180.0, -50.0], [220.0, 250.0]], 60.0, "right", 8.0, "A")
    b = fault([[-50.0, 110.0], [180.0 + 40.0 * 160.0 / 300.0, 110.0]], 70.0, "left", 5.0, "B")
    c = fault([[-50.0, 60.0], [450.0, 40.0]], 75.0, "right", 4.0, "C")
    d = fault([[180.0 + 40.0 * 200.0 / 300.0, 150.0], [300.0, 260.0]], 70.0, "right", 3.0, "D")
    return horizons, [a, b, c, d]


def test_t_x_and_y_junctions_equal_flow(tmp_path):
    """The T (B on A), the X (C across A) and the Y (D off A: the lattice lines between A's and
    D's meet in one pillar at the junction, wedge columns on both sides) build; junction pillars lie
    in both planes; Flow's dry run of the native deck (inclined COORD) keeps every ZCORN value (no
    fixupZCORN adjustment) and gives gridlib's active cells, NNCs and transmissibilities (1e-6)."""
    horizons, faults = junction_case()
    deck = horizons_to_pillar_grdecl(horizons, (10, 8), 2, faults)
    r, _ = processed(deck)
    assert_monotone_zcorn(deck)
    assert set(r.fault_names) == {"A", "B", "C", "D"}
    p = deck.pillars()[..., 0, :]
    assert np.any((p[:, 1:] == p[:, :-1]).all(axis=-1))  # the Y's coincident pillars
    for name, fault, dip, side in (
        ("A", faults[0], 60.0, "right"),
        ("B", faults[1], 70.0, "left"),
        ("C", faults[2], 75.0, "right"),
        ("D", faults[3], 70.0, "right"),
    ):
        nodes = tagged_nodes(r.grid, r.fault_names.index(name) + 1)
        (p, q) = fault.points
        zp, zq = (sloping_top(*np.clip(v, 0.0, [400.0, 200.0])) for v in (p, q))
        assert np.abs(plane_offset(nodes, p, q, zp, zq, dip, side)).max() < 1e-9 * 400.0, name

    nx, ny, nz = deck.cart_dims
    rng = np.random.default_rng(25)
    perm = rng.uniform(50.0, 500.0, deck.num_cells)
    work = tmp_path / "deck"
    work.mkdir()
    write_grdecl(
        work / "grid.grdecl",
        deck,
        {"PORO": np.full(deck.num_cells, 0.2), "PERMX": perm, "PERMY": perm, "PERMZ": 0.1 * perm},
    )
    text = f"RUNSPEC\nDIMENS\n {nx} {ny} {nz} /\nOIL\nWATER\nMETRIC\nTABDIMS\n 1 1 20 20 /\nEQLDIMS\n 1 /\n"
    text += "START\n 1 'JAN' 2020 /\nUNIFOUT\nGRID\nINIT\nINCLUDE\n 'grid.grdecl' /\n"
    text += rest_of_deck(float(deck.zcorn.min()), float(deck.zcorn.max()) + 1.0)
    (work / "CASE.DATA").write_text(text)
    case = run_flow_dry(work / "CASE.DATA", tmp_path / "out")

    egrid = read_keywords(case.with_suffix(".EGRID"))
    np.testing.assert_array_equal(egrid["ZCORN"], deck.zcorn.astype(np.float32))
    np.testing.assert_array_equal(egrid["COORD"], deck.coord.astype(np.float32))
    assert int((egrid["ACTNUM"] > 0).sum()) == r.grid.num_cells
    flow_nnc = {tuple(sorted(p)) for p in zip(egrid["NNC1"] - 1, egrid["NNC2"] - 1, strict=True)}
    assert flow_nnc == {tuple(sorted(p)) for p in r.nnc.global_cells.tolist()}
    c = deck_transmissibility(read_grdecl(work / "CASE.DATA"))
    ours = dict(zip(map(tuple, c.global_cells.tolist()), c.trans.tolist(), strict=True))
    assert_same_connections(ours, flow_connections(case))


def test_horizons_that_leave_cells_undefined_give_inactive_cells_and_finite_pillars():
    x, y = np.linspace(0.0, 400.0, 9), np.linspace(0.0, 200.0, 5)
    z = np.full((5, 9), Z0)
    z[0, :3] = np.nan  # a hole at the south-west corner
    base = Horizon(np.linspace(-50.0, 450.0, 11), y, np.full((5, 11), Z1))  # wider than the top
    fault = dip_fault(TRACE, [Z0, Z0], 60.0, "right", 12.0, "F1")
    deck = horizons_to_pillar_grdecl([Horizon(x, y, z), base], (10, 5), 3, [fault])
    assert np.isfinite(deck.coord).all()
    r, _ = processed(deck)
    assert 0 < r.grid.num_cells == int(deck.actnum.sum()) < 150


# --------------------------------------------------------------------------- fault sticks


def stick(x: float, y: float, drift: float) -> np.ndarray:
    """A straight stick from depth 900 to 1200 m leaning ``drift`` m east per metre of depth."""
    return np.array([[x, y, 900.0], [x + 300.0 * drift, y, 1200.0]])


def distance_to_section(surface: FaultSurface, nodes: np.ndarray) -> np.ndarray:
    """Plan distance (m) of every node (n, 3) from the surface's section at the node's depth."""
    out = np.full(nodes.shape[0], np.inf)
    sections = surface.section(nodes[:, 2])  # (n, sticks, 2)
    for k in range(sections.shape[1] - 1):
        a, b = sections[:, k], sections[:, k + 1]
        t = np.clip(((nodes[:, :2] - a) * (b - a)).sum(axis=1) / ((b - a) ** 2).sum(axis=1), 0.0, 1.0)
        out = np.minimum(out, np.hypot(*(a + t[:, None] * (b - a) - nodes[:, :2]).T))
    return out


def test_a_twisted_surface_of_sticks_carries_its_fault_faces():
    """Three straight sticks dipping 60, 70 and 65 degrees: the surface between them is twisted
    (linear between consecutive sticks at equal depth); every node of every fault face lies on it
    (flat horizons: the faces run between rulings at equal depths); a bent stick is a note."""
    sticks = [stick(180.0, -40.0, 0.577), stick(200.0, 100.0, 0.364), stick(230.0, 240.0, 0.466)]
    surface = FaultSurface.from_sticks(sticks, name="S")
    xy, _ = surface.on_horizon(lambda x, y: np.full(np.shape(x), Z0))
    fault = FaultTrace(xy, 10.0, "S", "right", surface=surface)
    deck = horizons_to_pillar_grdecl(flat_box(*BOX, Z0, Z1), (10, 5), 3, [fault])
    r, _ = processed(deck)
    assert_monotone_zcorn(deck)
    nodes = tagged_nodes(r.grid, 1)
    assert nodes.shape[0] > 0 and distance_to_section(surface, nodes).max() < 1e-9 * BOX[0]
    assert not any("bend" in n for n in deck.notes)

    bent = [sticks[0], np.vstack([sticks[1][0], [209.0, 100.0, 1050.0], [239.0, 100.0, 1200.0]]), sticks[2]]
    fault = FaultTrace(xy, 10.0, "S", "right", surface=FaultSurface.from_sticks(bent, name="S"))
    deck = horizons_to_pillar_grdecl(flat_box(*BOX, Z0, Z1), (10, 5), 3, [fault])
    processed(deck)
    assert any(
        n.startswith("fault 'S': its sticks bend; the pillars follow their straight chords")
        for n in deck.notes
    )


def test_a_fault_with_two_tips_inside_the_grid_tapering_its_throw():
    """Tips inside the grid: the lattice line runs on beyond them untagged, and with the throw
    tapering to 0 at both tips every fault face still lies on the plane."""
    pts = np.array([[200.0, 40.0], [210.0, 160.0]])
    fault = dip_fault(pts, [Z0, Z0], 60.0, "right", 0.0, "T")
    fault = FaultTrace(pts, lambda s: 12.0 * np.sin(np.pi * s), "T", "right", surface=fault.surface)
    deck = horizons_to_pillar_grdecl(flat_box(*BOX, Z0, Z1), (20, 10), 3, [fault])
    r, _ = processed(deck)
    assert deck.faults == (FaultSegment("T", 9, 9, 2, 7, 0, 2, "X"),)
    nodes = tagged_nodes(r.grid, 1)
    assert np.abs(plane_offset(nodes, pts[0], pts[1], Z0, Z0, 60.0, "right")).max() < 1e-9 * BOX[0]


def test_vertical_faults_on_lattice_lines_give_horizons_to_grdecls_deck_bit_for_bit():
    """Where the stair-stepped grid already follows the faults (vertical traces on lattice lines),
    the pillar mode writes the very same deck: COORD, ZCORN, ACTNUM and FAULTS."""
    QX, QY = np.meshgrid(X_AXIS, Y_AXIS)
    horizons = [Horizon(X_AXIS, Y_AXIS, sloping_top(QX, QY)), Horizon(X_AXIS, Y_AXIS, 1040.0 + 0.03 * QX)]
    f1 = FaultTrace([[200.0, -10.0], [200.0, 210.0]], lambda s: 5.0 + 3.0 * s, "F1", "right")
    f2 = FaultTrace([[-10.0, 100.0], [410.0, 100.0]], 4.0, "F2", "left")
    for faults in ([], [f1], [f1, f2]):
        ref = horizons_to_grdecl(horizons, (8, 4), 3, faults)
        deck = horizons_to_pillar_grdecl(horizons, (8, 4), 3, faults)
        for key in ("coord", "zcorn", "actnum"):
            np.testing.assert_array_equal(getattr(deck, key), getattr(ref, key))
        assert deck.faults == ref.faults and deck.notes == ref.notes


# --------------------------------------------------------------------------- a case


def test_a_case_with_dipping_faults_builds_its_pillar_grid(tmp_path):
    """grid.fault_geometry: pillars in a case: the faults' dips reach the deck (inclined COORD,
    fault faces on their planes), relax_distance too, and the grid is sound."""
    from gridlib.case.grid import build_case_grid
    from gridlib.case.horizons import case_horizons
    from gridlib.config import load_case

    text = """name: dipping
horizons:
  lattice:
    x: {start: 0, stop: 400, num: 5}
    y: {start: 0, stop: 200, num: 3}
  surfaces:
    - {name: top, plane: {depth: 1000}}
    - {name: base, plane: {depth: 1060}}
faults:
  - {name: A, trace: [[170, -40], [230, 240]], dip: 60, throw: 12, side: right}
grid:
  type: cornerpoint
  dims: [10, 5]
  layers: [3]
  fault_geometry: pillars
  relax_distance: 80
"""
    (tmp_path / "dipping.yaml").write_text(text)
    case = load_case(tmp_path / "dipping.yaml")
    built = build_case_grid(case, case_horizons(case))
    assert built.fault_names == ("A",) and "relax back to vertical over 80 m" in " ".join(built.notes)
    geo = gl.compute_geometry(built.grid)
    gl.check_grid(built.grid, geo)
    nodes = tagged_nodes(built.grid, 1)
    assert np.abs(plane_offset(nodes, TRACE[0], TRACE[1], Z0, Z0, 60.0, "right")).max() < 1e-9 * BOX[0]
    assert built.deck.source.endswith("(horizons_to_pillar_grdecl)")


# --------------------------------------------------------------------------- folds (bench cases)


def dome(x, y, depth: float, relief: float, radius: float):
    """bench/inclined_faults.py's dome (gridlib.horizons.analytic.dome), crest at (1500, 1000)."""
    return depth + relief * (1.0 - np.exp(-((x - 1500.0) ** 2 + (y - 1000.0) ** 2) / radius**2))


def test_a_dipping_plane_on_a_dome_follows_its_curved_trace_at_the_top():
    """The bench's F1 (60 degrees east, 25 m throw) on its dome: the plane through the trace's
    ends meets the dome up to about 34 m west of the chord between them. The fault's lattice
    line follows that curve (pillars pinned at the chord's depth folded the columns beside the
    fault at every relax distance): every relax distance builds, no column folds, every fault
    node lies on the plane, and the fault is one run of X faces along one lattice line (the
    columns are classified against the curve their line follows)."""
    x, y = np.linspace(0.0, 3000.0, 61), np.linspace(0.0, 2000.0, 41)
    X, Y = np.meshgrid(x, y)
    horizons = [
        Horizon(x, y, dome(X, Y, z, r, a)) for z, r, a in ((2000.0, 120.0, 1200.0), (2080.0, 130.0, 1300.0))
    ]
    trace = np.array([[1000.0, -100.0], [1450.0, 2100.0]])
    z_ends = dome(np.clip(trace[:, 0], 0.0, 3000.0), np.clip(trace[:, 1], 0.0, 2000.0), 2000.0, 120.0, 1200.0)
    fault = dip_fault(trace, z_ends, 60.0, "right", 25.0, "F1")
    for relax in (None, 150.0, 400.0):
        deck = horizons_to_pillar_grdecl(horizons, (100, 5), 2, [fault], relax_distance=relax)
        r, _ = processed(deck)
        assert_monotone_zcorn(deck)
        (seg,) = deck.faults
        assert (seg.j1, seg.j2, seg.face) == (0, 4, "X")
        nodes = tagged_nodes(r.grid, r.fault_names.index("F1") + 1)
        assert np.abs(plane_offset(nodes, *trace, *z_ends, 60.0, "right")).max() < 1e-9 * 3000.0
    # The fault's pillars where they meet the top: west of the chord by (chord's depth - top's
    # depth) cot(60) along the normal, 32.5 m in x at y = 800 m (row 2).
    p = deck.pillars()[:, seg.i1 + 1, 0]
    chord_x = trace[0, 0] + (p[:, 1] - trace[0, 1]) * (trace[1, 0] - trace[0, 0]) / (
        trace[1, 1] - trace[0, 1]
    )
    top = dome(p[:, 0], p[:, 1], 2000.0, 120.0, 1200.0)
    at_top = p[:, 0] + (top - p[:, 2]) * (deck.pillars()[:, seg.i1 + 1, 1, 0] - p[:, 0]) / (
        deck.pillars()[:, seg.i1 + 1, 1, 2] - p[:, 2]
    )
    assert (chord_x - at_top).max() > 30.0


def test_the_default_relax_distance_counts_the_throws():
    """The bench's F1 (25 m throw) and its former F2 ending inside F1's hanging wall (15 m at the
    boundary, 0 at the tip) on flat horizons 80 m apart: corners in both hanging walls reach
    80 + 25 + 15 m below the pillars' pinning at the top. 2 H cot(dip) with H the horizons'
    80 m alone (92.4 m) folds the columns beside F2; the default counts the throws."""
    x, y = np.linspace(0.0, 3000.0, 3), np.linspace(0.0, 2000.0, 3)
    horizons = [Horizon(x, y, np.full((3, 3), z)) for z in (2000.0, 2080.0)]
    f1 = dip_fault([[1000.0, -100.0], [1450.0, 2100.0]], [2000.0, 2000.0], 60.0, "right", 25.0, "F1")
    pts = np.array([[1900.0, 600.0], [3100.0, 1000.0]])
    surface = FaultSurface.from_dip(pts, [2000.0, 2000.0], 60.0, "left", name="F2")
    f2 = FaultTrace(pts, lambda s: 15.0 * np.asarray(s), "F2", "left", surface=surface)
    deck = horizons_to_pillar_grdecl(horizons, (100, 50), 2, [f1, f2])
    bound = 2.0 * (80.0 + 25.0 + 15.0) / np.tan(np.radians(60.0))
    assert f"fault_geometry pillars: pillars relax back to vertical over {bound:g} m" in deck.notes
    r, _ = processed(deck)
    assert_monotone_zcorn(deck)
    for name, fault, side in (("F1", f1, "right"), ("F2", f2, "left")):
        nodes = tagged_nodes(r.grid, r.fault_names.index(name) + 1)
        # F2's tip (x = 1900 m) lies between two nodes of its line: the face across it has its
        # nodes beyond the tip on a relaxing pillar, off the plane; the nodes along F2 are on it.
        a, b = fault.points
        nodes = nodes[(nodes[:, :2] - a) @ (b - a) >= 0.0]
        offset = plane_offset(nodes, *fault.points, 2000.0, 2000.0, 60.0, side)
        assert np.abs(offset).max() < 1e-9 * 3000.0, name
    with pytest.raises(InputError, match=r"near fault 'F2' cross or invert \d+ columns"):
        horizons_to_pillar_grdecl(
            horizons, (100, 50), 2, [f1, f2], relax_distance=2.0 * 80.0 / np.tan(np.radians(60.0))
        )
