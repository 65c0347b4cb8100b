"""2.5D PEBI grids with inclined faults (issue 25, item 4): the areal grid conforms to the
faults' traces on the top horizon, the pillars through the fault nodes lie in the fault
surfaces and the others incline back to vertical (gridlib.pillars.fault_pillars).

Oracles: a planar fault's own plane written here from its dip (cot(dip) times the horizontal
normal towards the hanging wall), and the volume between flat horizons: the footwall fills
[z0, z1] left of the plane, the hanging wall [z0 + T, z1 + T] right of it, so the total is
Lx Ly H - Ly H T c, c the plane's shift in x per metre of depth at fixed y. Every grid also
passes the exact no-crossing test, check_grid and has positive volumes. Grids are small
(under 2,000 cells): the module runs in about a second.
"""

from __future__ import annotations

import numpy as np
import pytest

import gridlib as gl
from gridlib.errors import InputError
from gridlib.pillars.column_inputs import ColumnCorners
from gridlib.pillars.extrude import extrude
from gridlib.pillars.fault_pillars import fault_pillars, inclined
from gridlib.pillars.fault_surface import FaultSurface
from gridlib.pillars.fault_traces import FaultTrace
from gridlib.pillars.inclined_lines import PillarLines, first_crossing
from gridlib.voronoi import Fault, Rings, Well, pebi_grid

LX, LY, Z0, Z1 = 1000.0, 600.0, 2000.0, 2100.0
EXTENT = LX


def flat(depth: float):
    return lambda x, y: np.full(np.shape(x), depth)


def dip_fault(trace, dip: float, throw: float, side: str = "right", name: str = "F1") -> FaultTrace:
    trace = np.asarray(trace, dtype=np.float64)
    surface = FaultSurface.from_dip(trace, np.full(len(trace), Z0), dip, side, name=name)
    return FaultTrace(trace, throw=throw, name=name, side=side, surface=surface)


def plane_drift(trace, dip: float, side: str) -> np.ndarray:
    """cot(dip) times the horizontal unit normal of a straight trace towards ``side``."""
    along = np.diff(np.asarray(trace, dtype=np.float64), axis=0)[0]
    along /= np.hypot(*along)
    left = np.array([-along[1], along[0]])
    return (left if side == "left" else -left) / np.tan(np.radians(dip))


def plane_distance(points: np.ndarray, trace, dip: float, side: str) -> np.ndarray:
    """Distance (m) of points (n, 3) from the plane through the trace at depth Z0 dipping ``dip``
    towards ``side``."""
    a = np.asarray(trace, dtype=np.float64)[0]
    drift = plane_drift(trace, dip, side)
    normal = drift / np.hypot(*drift)
    # horizontal offset from the plane's section at the point's depth, times sin(dip)
    offset = ((points[:, :2] - a - (points[:, 2:3] - Z0) * drift) * normal).sum(axis=1)
    return np.abs(offset) * np.sin(np.radians(dip))


def face_nodes(grid: gl.Grid, faces: np.ndarray) -> np.ndarray:
    pos = grid.faces.node_pos
    return np.unique(np.concatenate([grid.faces.nodes[pos[f] : pos[f + 1]] for f in faces]))


def build(faults, wells=(), cell_size=50.0, layers=3, relax_distance=None):
    areal = pebi_grid(((0.0, 0.0), (LX, LY)), cell_size, [Fault(f.points, f.name) for f in faults], wells)
    throws = [abs(f.throw) for f in faults]
    z_lo, z_hi = Z0 - max(throws), Z1 + max(throws)
    lines = fault_pillars(
        areal.grid,
        faults,
        flat(Z0),
        z_lo,
        z_hi,
        vertical_cells=areal.cell_well > 0,
        relax_distance=relax_distance,
        sites=areal.sites,
    )
    moving = [f for f in faults if f.throw != 0]
    r = extrude(areal.grid, [Z0, Z1], layers, moving, pillars=lines.pillars(), centres=areal.sites)
    geo = gl.compute_geometry(r.grid)
    gl.check_grid(r.grid, geo)
    return areal, lines, r, geo


TRACE = [(400.0, -50.0), (450.0, 650.0)]


@pytest.fixture(scope="module")
def one_fault():
    well = Well((800.0, 300.0), name="P1", rings=Rings(inner=2.0, outer=40.0))
    return build([dip_fault(TRACE, 60.0, 20.0)], [well])


def test_fault_faces_lie_on_the_plane_and_the_volume_is_exact(one_fault):
    areal, lines, r, geo = one_fault
    grid = r.grid
    tagged = np.flatnonzero(grid.faces.tag > 0)
    assert tagged.size >= 12 * 3  # the fault's faces in every layer
    distance = plane_distance(grid.nodes.coords[face_nodes(grid, tagged)], TRACE, 60.0, "right")
    assert distance.max() < 1e-9 * EXTENT, distance.max()
    # the plane moves east with depth: the pillars on it drift across it by cot(60) per metre of
    # depth (and along it as the lines where it meets the boundary do, which lie in it too)
    fault_nodes = face_nodes(areal.grid, np.flatnonzero(areal.grid.faces.tag == 1))
    normal = plane_drift(TRACE, 60.0, "right")
    across = lines.lines.drift[fault_nodes] @ normal / np.hypot(*normal)
    np.testing.assert_allclose(across, 1 / np.tan(np.radians(60.0)), rtol=1e-12)
    assert geo.cell_volumes.min() > 0
    corners = ColumnCorners.of(areal.grid)
    assert first_crossing(lines.lines, corners.pos, corners.ring, lines.z_lo, lines.z_hi) is None
    (xa, ya), (xb, yb) = TRACE
    drift = plane_drift(TRACE, 60.0, "right")
    shift_x = drift[0] - drift[1] * (xb - xa) / (yb - ya)  # the plane's x shift per metre at fixed y
    h, throw = Z1 - Z0, 20.0
    expected = LX * LY * h - LY * h * throw * shift_x
    assert geo.cell_volumes.sum() == pytest.approx(expected, rel=1e-12)
    print(
        f"volume {geo.cell_volumes.sum():.6f} m3 vs {expected:.6f}; relax distance {lines.relax_distance:g} m"
    )


def test_pillars_blend_back_to_vertical_and_the_wells_stay_vertical(one_fault):
    areal, lines, r, _ = one_fault
    xy = areal.grid.nodes.coords[:, :2]
    drift = np.hypot(*lines.lines.drift.T)
    normal = plane_drift(TRACE, 60.0, "right")
    distance = np.abs(((xy - TRACE[0]) * normal).sum(axis=1)) / np.hypot(*normal)
    assert lines.relax_distance == pytest.approx(2 * (Z1 - Z0 + 40.0) / np.tan(np.radians(60.0)))
    assert np.all(drift[distance >= lines.relax_distance] == 0.0)
    across = lines.lines.drift @ normal / np.hypot(*normal)
    assert across.max() == pytest.approx(1 / np.tan(np.radians(60.0)), rel=1e-12)  # on the fault
    corners = ColumnCorners.of(areal.grid)
    well_nodes = np.unique(corners.ring[(areal.cell_well > 0)[corners.owner]])
    assert well_nodes.size > 20 and np.all(lines.lines.drift[well_nodes] == 0.0)
    # every node of the well's cells in the 3-D grid stands exactly above an areal node of them
    grid = r.grid
    owner = np.repeat(np.arange(grid.num_cells), np.diff(grid.cells.face_pos))
    well_faces = np.unique(grid.cells.faces[(areal.cell_well[grid.layering.column] > 0)[owner]])
    plan = grid.nodes.coords[face_nodes(grid, well_faces), :2]
    assert (plan[:, None, :] == xy[well_nodes][None]).all(axis=2).any(axis=1).all()


def test_boundary_nodes_keep_their_pillars_in_the_boundary(one_fault):
    areal, lines, _, _ = one_fault
    xy = areal.grid.nodes.coords[:, :2]
    west, east, south, north = xy[:, 0] == 0, xy[:, 0] == LX, xy[:, 1] == 0, xy[:, 1] == LY
    assert (west | east | south | north).sum() > 40
    for p in lines.pillars().transpose(1, 0, 2):  # top points, bottom points
        assert np.all(p[west, 0] == 0.0) and np.all(p[east, 0] == LX)
        assert np.all(p[south, 1] == 0.0) and np.all(p[north, 1] == LY)
    # the fault's nodes on the boundary slide along it: where the plane meets the boundary
    moving = (south | north) & (np.hypot(*lines.lines.drift.T) > 0)
    assert moving.sum() >= 2
    for z in (lines.z_lo, lines.z_hi):
        p = lines.lines.xy_at(np.full(xy.shape[0], z))[moving]
        points = np.column_stack([p, np.full(p.shape[0], z)])
        assert (
            plane_distance(points[south[moving] | north[moving]], TRACE, 60.0, "right").min() < 1e-9 * EXTENT
        )


def on_surface_distance(surface: FaultSurface, points: np.ndarray) -> np.ndarray:
    """Distance in plan (m) of points (n, 3) from the surface's horizontal section at their depths."""
    sections = surface.section(points[:, 2])  # (n, n_sticks, 2)
    best = np.full(points.shape[0], np.inf)
    for k in range(sections.shape[1] - 1):
        a, e = sections[:, k], sections[:, k + 1] - sections[:, k]
        t = np.clip(((points[:, :2] - a) * e).sum(axis=1) / (e * e).sum(axis=1), 0.0, 1.0)
        best = np.minimum(best, np.hypot(*(a + t[:, None] * e - points[:, :2]).T))
    return best


def test_fault_faces_on_a_twisted_sticks_surface():
    """Two straight sticks of different drift: a twisted (ruled, not planar) surface. The pillars
    on it are its rulings, so the fault faces lie on it (the sticks lie in the boundary's planes
    y = -50 and 650, so where it meets the boundaries y = 0 and 600 is a ruling too), and without
    throw the volume is the box's."""
    sticks = [
        np.array([[300.0, -50.0, 1900.0], [300.0 + 0.8 * 300, -50.0, 2200.0]]),
        np.array([[350.0, 650.0, 1900.0], [350.0 + 0.4 * 300, 650.0, 2200.0]]),
    ]
    twisted = FaultSurface.from_sticks(sticks, name="F1")
    xy, _ = twisted.on_horizon(flat(Z0))
    fault = FaultTrace(xy, throw=0.0, name="F1", side="right", surface=twisted)
    areal, lines, r, geo = build([fault], cell_size=60.0, layers=2)
    assert geo.cell_volumes.min() > 0
    assert geo.cell_volumes.sum() == pytest.approx(LX * LY * (Z1 - Z0), rel=1e-12)
    grid = r.grid
    points = grid.nodes.coords[face_nodes(grid, np.flatnonzero(grid.faces.tag > 0))]
    assert points.shape[0] > 30 and on_surface_distance(twisted, points).max() < 1e-9 * EXTENT
    drift = lines.lines.drift[face_nodes(areal.grid, np.flatnonzero(areal.grid.faces.tag > 0))]
    assert np.ptp(drift[:, 0]) > 0.2  # the rulings' drift varies along strike: 0.8 to 0.4


def test_crossing_faults_meet_on_their_intersection_line():
    """Two planar faults crossing (X): every fault face on its plane, the junction's pillar on
    both, no column folded, and without throw the volume is the box's."""
    f1 = dip_fault(TRACE, 60.0, 0.0, side="right", name="F1")
    second = [(-50.0, 200.0), (1050.0, 350.0)]
    f2 = dip_fault(second, 70.0, 0.0, side="left", name="F2")
    areal, lines, r, geo = build([f1, f2], cell_size=60.0, layers=2)
    grid = r.grid
    assert geo.cell_volumes.min() > 0
    assert geo.cell_volumes.sum() == pytest.approx(LX * LY * (Z1 - Z0), rel=1e-12)
    planes = {1: (TRACE, 60.0, "right"), 2: (second, 70.0, "left")}
    for tag, plane in planes.items():
        points = grid.nodes.coords[face_nodes(grid, np.flatnonzero(grid.faces.tag == tag))]
        assert points.shape[0] > 30 and plane_distance(points, *plane).max() < 1e-9 * EXTENT
    tags = areal.grid.faces.tag
    (junction,) = np.intersect1d(
        face_nodes(areal.grid, np.flatnonzero(tags == 1)), face_nodes(areal.grid, np.flatnonzero(tags == 2))
    )
    for z in (lines.z_lo, lines.z_hi):
        p = np.append(lines.lines.xy_at(np.full(areal.grid.num_nodes, z))[junction], z)[None]
        assert max(plane_distance(p, *plane)[0] for plane in planes.values()) < 1e-9 * EXTENT


def test_a_relax_distance_too_short_for_the_dip_is_one_error():
    with pytest.raises(InputError, match=r"near fault 'F1' fold areal cell \d+ at depth .* relax_distance 5"):
        build([dip_fault(TRACE, 45.0, 0.0)], relax_distance=5.0)
    # a well (vertical cells) on the hanging wall, where the fault passes below it: one error
    well = Well((520.0, 300.0), name="P1", rings=Rings(inner=2.0, outer=40.0))
    with pytest.raises(InputError, match=r"fault 'F1' .*: a well's cells, which keep vertical pillars"):
        build([dip_fault(TRACE, 60.0, 20.0)], [well])


def test_vertical_faults_change_nothing():
    trace = np.array(TRACE)
    vertical = FaultTrace(trace, 5.0, "F1", "right", FaultSurface.from_dip(trace, [Z0, Z0], 90.0, "right"))
    assert not inclined([vertical]) and not inclined([FaultTrace(trace, 5.0, "F1")])
    assert inclined([dip_fault(TRACE, 89.0, 5.0)])


def test_the_crossing_test_sees_a_fold_between_the_ends():
    """A triangle column that turns the wrong way only in the middle of the depth range (the
    signed area at its corner 5 is -0.01 + (z - 1)^2), beside a square: found at the
    quadratic's vertex, z = 1."""
    point = np.array([[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0], [20, 0, 0], [21, 0, 1], [21, -0.01, 1]])
    drift = np.zeros((7, 2))
    drift[5], drift[6] = (0.0, 1.0), (-1.0, 1.0)
    pos, ring = np.array([0, 4, 7]), np.arange(7)
    lines = PillarLines(point.astype(np.float64), drift)
    assert first_crossing(lines, pos[:2], ring[:4], 0.0, 2.0) is None
    bad = first_crossing(lines, pos, ring, 0.0, 2.0)
    assert bad is not None and bad.column == 1 and bad.depth == pytest.approx(1.0)
    assert first_crossing(lines, pos, ring, 1.2, 2.0) is None
    assert first_crossing(lines, pos, ring, 0.0, 0.8) is None
    # one depth range per column: the triangle's cells only below 1.2 m
    assert first_crossing(lines, pos, ring, np.array([0.0, 1.2]), np.array([2.0, 2.0])) is None
    # a wedge column (two of its pillars one line) is no fold
    wedge = PillarLines(point[[0, 1, 2, 2]], np.zeros((4, 2)))
    assert first_crossing(wedge, pos[:2], ring[:4], 0.0, 2.0) is None


def test_flow_takes_the_connection_form_and_simulates_it(one_fault, tmp_path):
    """The inclined grid in Flow's connection form (every cell a box, every connection an NNC
    with our T, our pore volumes): Flow's dry run has exactly our connections (fault ones
    included), T and PORV within 1e-6 (INIT's float32); a two-step oil-water run with a
    producer in the well's column and an injector across the fault runs to its end."""
    from flow_tools import flow_connections, flow_executable, read_keywords, run_flow_dry

    from gridlib.io.flow import ConnectionGrid, FlowWell, Simulation, write_flow_deck
    from gridlib.stages.simulate import run_flow
    from gridlib.transmissibility import transmissibility

    flow_executable()
    areal, lines, r, geo = one_fault
    grid = r.grid
    column, layer = grid.layering.column, grid.layering.layer
    depth = geo.cell_centroids[:, 2]
    sites = lines.sites_at(column, depth)
    conn = transmissibility(grid, geo, 100.0, centres=np.column_stack([sites, depth]), distance="normal")
    assert conn.trans.min() > 0 and (conn.kind == 1).sum() > 0  # fault connections across the throw
    ncol, nlay = areal.grid.num_cells, int(layer.max()) + 1
    index = column + ncol * layer
    boxes = ConnectionGrid(
        dims=(ncol, 1, nlay),
        index=index,
        porv=0.2 * geo.cell_volumes,
        depth=depth,
        thickness=np.full(grid.num_cells, (Z1 - Z0) / nlay),
        poro=np.full(grid.num_cells, 0.2),
        permeability=np.full((grid.num_cells, 3), 100.0),
        pairs=conn.cells,
        trans=conn.trans,
        spacing=50.0,
    )
    well_column = int(np.argmin(np.hypot(*(areal.sites - (800.0, 300.0)).T)))
    injector_column = int(np.argmin(np.hypot(*(areal.sites - (100.0, 300.0)).T)))
    wells = (
        FlowWell("P1", "producer", well_column + ncol * np.arange(nlay), 0.1, 0.0, [20.0] * nlay, bhp=150.0),
        FlowWell(
            "I1", "injector", injector_column + ncol * np.arange(nlay), 0.1, 0.0, [20.0] * nlay, rate=500.0
        ),
    )
    sim = Simulation("oil-water", Z0, 200.0, Z1 + 50.0, wells, (5.0, 10.0))
    deck = write_flow_deck(tmp_path, "inclined", boxes, sim)
    assert deck.vanished.size == 0
    result = run_flow_dry(deck.path, tmp_path / "dry")
    init = read_keywords(tmp_path / "dry" / "INCLINED.INIT")
    np.testing.assert_allclose(init["PORV"].astype(np.float64)[index], boxes.porv, rtol=1e-6)
    flow = flow_connections(result)
    ours = dict(
        zip(map(tuple, np.sort(index[conn.cells], axis=1).tolist()), conn.trans.tolist(), strict=True)
    )
    assert sorted(flow) == sorted(ours)
    keys = sorted(ours)
    np.testing.assert_allclose([flow[k] for k in keys], [ours[k] for k in keys], rtol=1e-6)
    run = run_flow(deck.path, tmp_path / "run")
    assert run.returncode == 0, run.stdout[-2000:]
    from gridlib.io.flow_results import read_summary

    summary = read_summary(tmp_path / "run" / "INCLINED")
    assert summary.time[-1] == 10.0 and summary["FOPT"][-1] > 0
    print(f"{len(ours)} connections ({int((conn.kind == 1).sum())} across the fault) equal to Flow's")


def test_a_dent_is_no_fold_for_the_star_test():
    """A node in the middle of a square's edge moving inwards with depth dents the column: no
    longer convex, still star-shaped around its centre (no fold); moving past the centre, it
    folds."""
    point = np.array([[0, 0, 0], [5, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0]], dtype=np.float64)
    pos, ring = np.array([0, 5]), np.arange(5)
    centre = PillarLines(np.array([[5.0, 5.0, 0.0]]), np.zeros((1, 2)))
    for inwards, folds in ((1.0, False), (20.0, True)):
        drift = np.zeros((5, 2))
        drift[1] = (0.0, inwards)
        lines = PillarLines(point, drift)
        assert first_crossing(lines, pos, ring, 0.0, 1.0) is not None  # not convex below the top
        assert (first_crossing(lines, pos, ring, 0.0, 1.0, centre) is not None) == folds


CASE = """name: inclined_pebi_test
horizons:
  lattice:
    x: {start: 0, stop: 1000, num: 11}
    y: {start: 0, stop: 600, num: 7}
  surfaces:
    - {name: top, plane: {depth: 2000, dip: 0, azimuth: 90}}
    - {name: base, plane: {depth: 2100, dip: 0, azimuth: 90}}
faults:
  - {name: F1, trace: [[400, -50], [450, 650]], throw: 20, DIP}
wells:
  - {name: P1, point: [800, 300], rings: {inner: 2.0, outer: 40}}
grid:
  type: pebi
  domain: {rectangle: [0, 0, 1000, 600]}
  cell_size: 50
  layers: 3
"""


def case_grid(tmp_path, dip: str):
    from gridlib.case.grid import build_case_grid
    from gridlib.config import load_case
    from gridlib.stages.horizons import case_horizons

    folder = tmp_path / dip.replace(" ", "").replace(":", "_").replace(",", "_")
    folder.mkdir()
    path = folder / "inclined_pebi_test.yaml"
    path.write_text(CASE.replace("DIP", dip))
    case = load_case(path)
    return build_case_grid(case, case_horizons(case))


def test_a_case_with_a_dip_builds_the_inclined_grid_and_dip_90_todays(tmp_path):
    """The case's `dip` reaches the grid: fault faces on the plane, the volume exact, the
    sites followed down their columns; `dip: 90` gives today's grid bit for bit."""
    built = case_grid(tmp_path, "side: right, dip: 60")
    grid = built.grid
    geo = gl.compute_geometry(grid)
    gl.check_grid(grid, geo)
    tagged = np.flatnonzero(grid.faces.tag > 0)
    assert (
        plane_distance(grid.nodes.coords[face_nodes(grid, tagged)], TRACE, 60.0, "right").max()
        < 1e-9 * EXTENT
    )
    (xa, ya), (xb, yb) = TRACE
    drift = plane_drift(TRACE, 60.0, "right")
    expected = LX * LY * (Z1 - Z0) - LY * (Z1 - Z0) * 20.0 * (drift[0] - drift[1] * (xb - xa) / (yb - ya))
    assert geo.cell_volumes.sum() == pytest.approx(expected, rel=1e-12)
    site = built.cell_data["site"]
    well = built.cell_data["well"] > 0
    column = grid.layering.column
    top_layer = grid.layering.layer == 0
    # the well's columns are vertical: their sites the same in every layer
    first = np.full(column.max() + 1, np.nan)
    first[column[top_layer]] = site[top_layer, 0]
    assert np.array_equal(site[well, 0], first[column[well]])
    # elsewhere near the fault the sites move down-dip with their columns
    assert np.ptp(site[column == column[np.argmax(np.abs(site[:, 0] - first[column]))], 0]) > 10.0
    vertical, today = case_grid(tmp_path, "side: right, dip: 90"), case_grid(tmp_path, "side: right")
    assert np.array_equal(vertical.grid.nodes.coords, today.grid.nodes.coords)
    assert np.array_equal(vertical.grid.faces.nodes, today.grid.faces.nodes)
    assert all(np.array_equal(vertical.cell_data[k], today.cell_data[k]) for k in today.cell_data)
    assert vertical.notes == today.notes


def test_a_kinked_dip_fault_keeps_both_planes():
    """A trace with a kink: each straight segment is its own plane, and the pillar at the kink
    lies on both (the mitre: cot(dip) (n_a + n_b) / (1 + n_a . n_b)); every fault face lies on
    the surface, the volume is exact without throw."""
    kinked = [(350.0, -50.0), (500.0, 300.0), (420.0, 650.0)]
    fault = dip_fault(kinked, 55.0, 0.0)
    areal, lines, r, geo = build([fault], cell_size=50.0, layers=2)
    grid = r.grid
    assert geo.cell_volumes.min() > 0
    assert geo.cell_volumes.sum() == pytest.approx(LX * LY * (Z1 - Z0), rel=1e-12)
    points = grid.nodes.coords[face_nodes(grid, np.flatnonzero(grid.faces.tag > 0))]
    assert on_surface_distance(fault.surface, points).max() < 1e-9 * EXTENT
    (kink,) = np.flatnonzero(np.hypot(*(areal.grid.nodes.coords[:, :2] - kinked[1]).T) < 1e-9 * EXTENT)
    cot = 1 / np.tan(np.radians(55.0))
    n_a, n_b = (plane_drift(segment, 55.0, "right") / cot for segment in (kinked[:2], kinked[1:]))
    np.testing.assert_allclose(lines.lines.drift[kink], cot * (n_a + n_b) / (1 + n_a @ n_b), rtol=1e-12)
