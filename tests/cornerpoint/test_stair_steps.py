"""Inclined faults stair-stepped on vertical pillars (gridlib.cornerpoint.stair_steps) against
analytic planes: every cell on its block's side at its own depth, fault faces next to the plane,
the throw exact on every fault face, the bulk volume of the box less what the report says was cut
out; and against OPM Flow's dry run of a two-fault deck (cells, connections, T, ZCORN unchanged)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from flow_tools import assert_same_connections, flow_connections, read_keywords, run_flow_dry
from wedge_decks import write_data_deck

from gridlib.cornerpoint.between_horizons import Horizon, horizons_to_grdecl
from gridlib.cornerpoint.deck import FaultSegment
from gridlib.cornerpoint.process import process_grdecl
from gridlib.cornerpoint.stair_steps import FOOTWALL, HANGING_WALL, MISSING, stair_steps
from gridlib.geometry import compute_geometry
from gridlib.io.grdecl import read_grdecl
from gridlib.pillars.fault_surface import FaultSurface
from gridlib.pillars.fault_traces import FaultTrace
from gridlib.transmissibility import deck_transmissibility

# A 600 x 200 m box between flat horizons at 1000 and 1060 m: 30 x 4 columns of 20 x 50 m, 12 layers of 5 m.
X, Y = np.linspace(0.0, 600.0, 31), np.linspace(0.0, 200.0, 5)
TOP, BASE = 1000.0, 1060.0
DIMS, LAYERS = (30, 4), 12
HORIZONS = [Horizon(X, Y, np.full((5, 31), TOP)), Horizon(X, Y, np.full((5, 31), BASE))]
BOX_VOLUME = 600.0 * 200.0 * (BASE - TOP)


def dipping(x0: float, dip: float, throw: float, side: str, name: str, y_end: float = 210.0) -> FaultTrace:
    """A fault whose trace on the top horizon runs north along x = x0, dipping ``dip`` degrees
    towards ``side`` (east for right)."""
    trace = [(x0, -10.0), (x0, y_end)]
    return FaultTrace(trace, throw, name, side, FaultSurface.from_dip(trace, TOP, dip, side, name))


def plane_offset(fault: FaultTrace, dip: float, x: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Horizontal distance (m) of points east of the fault's plane at their depth: the plane is
    x = x0 +- (z - TOP) / tan(dip), + for a fault dipping east."""
    x0 = fault.points[0, 0]
    east = 1.0 if fault.side == "right" else -1.0
    return x - (x0 + east * (z - TOP) / np.tan(np.radians(dip)))


def layering() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The unfaulted corner depths (2 nz, 2 ny, 2 nx) and the pillar lattice."""
    PX, PY = np.meshgrid(np.linspace(0.0, 600.0, DIMS[0] + 1), np.linspace(0.0, 200.0, DIMS[1] + 1))
    return horizons_to_grdecl(HORIZONS, DIMS, LAYERS).zcorn_array().copy(), PX, PY


def centres(z: np.ndarray, PX: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Plan x (nz, ny, nx) and depth (nz, ny, nx) of the eight-corner centre of every cell."""
    nz, ny, nx = (n // 2 for n in z.shape)
    depth = z.reshape(nz, 2, ny, 2, nx, 2).mean(axis=(1, 3, 5))
    x = np.broadcast_to(0.5 * (PX[:-1, :-1] + PX[:-1, 1:]), depth.shape)
    return x, depth


F1_DIP = 30.0


@pytest.fixture(scope="module")
def one_fault():
    """One fault dipping 30 degrees east with a 7 m throw (more than a layer): its trace moves
    104 m (5.2 columns) between the top and the base."""
    fault = dipping(200.0, F1_DIP, 7.0, "right", "F1")
    zc, PX, PY = layering()
    steps = stair_steps([fault], zc, PX, PY, (0.0, 600.0, 0.0, 200.0))
    deck = horizons_to_grdecl(HORIZONS, DIMS, LAYERS, [fault])
    return fault, zc, PX, steps, deck, process_grdecl(deck)


def test_every_cell_centre_is_on_its_blocks_side_of_the_plane(one_fault):
    fault, zc, PX, steps, deck, _ = one_fault
    block = steps.block[0]
    assert (block == HANGING_WALL).any() and (block == FOOTWALL).any() and (block == MISSING).any()
    x, depth = centres(zc, PX)
    throw = 7.0
    hanging, footwall, missing = block == HANGING_WALL, block == FOOTWALL, block == MISSING
    # The hanging wall (east of the plane, above it) at the displaced centre, the footwall at the
    # undisplaced one; a missing cell is neither: its section lies between the two blocks.
    assert (plane_offset(fault, F1_DIP, x, depth + throw)[hanging] > 0).all()
    assert (plane_offset(fault, F1_DIP, x, depth)[footwall] <= 0).all()
    assert (plane_offset(fault, F1_DIP, x, depth)[missing] > 0).all()
    assert (plane_offset(fault, F1_DIP, x, depth + throw)[missing] <= 0).all()
    # The deck's cells are where their blocks put them: hanging-wall cells moved down by the throw,
    # never clamped; the deck's own centres of the cells kept are on their side too.
    z = deck.zcorn_array()
    nz, ny, nx = block.shape
    moved = (z - zc).reshape(nz, 2, ny, 2, nx, 2).transpose(0, 2, 4, 1, 3, 5)
    assert np.allclose(moved[hanging], throw, rtol=0, atol=1e-12)
    _, deck_depth = centres(z, PX)
    kept = ~missing
    side = plane_offset(fault, F1_DIP, x, deck_depth)
    assert (side[hanging] > 0).all() and (side[footwall & kept] <= 0).all()
    thickness = (z[1::2] - z[0::2]).reshape(nz, ny, 2, nx, 2).transpose(0, 1, 3, 2, 4)
    assert (thickness[missing] == 0).all()


def test_the_trace_moves_five_columns_and_every_column_is_cut_at_its_depth(one_fault):
    _, _, _, steps, _, _ = one_fault
    block = steps.block[0]
    first_hanging = (block == HANGING_WALL).argmax(axis=2)  # (nz, ny): the westmost hanging-wall column
    assert first_hanging[0].tolist() == [11] * 4 and first_hanging[-1].tolist() == [16] * 4
    # Down every column: hanging wall, then missing section, then footwall.
    order = np.where(block == HANGING_WALL, 0, np.where(block == MISSING, 1, 2))
    assert (np.diff(order, axis=0) >= 0).all()


def test_fault_faces_lie_within_one_cell_of_the_plane_and_carry_the_name(one_fault):
    fault, _, _, _, _, r = one_fault
    g = r.grid
    tagged = np.flatnonzero(g.faces.tag > 0)
    assert r.fault_names == ("F1",)
    geometry = compute_geometry(g)
    centroid = geometry.face_centroids[tagged]
    along = np.abs(plane_offset(fault, F1_DIP, centroid[:, 0], centroid[:, 2]))
    diagonal = np.hypot(np.hypot(20.0, 50.0), 5.0)
    distance = along * np.sin(np.radians(F1_DIP))  # horizontal offset -> distance to the plane
    assert distance.max() <= diagonal
    # Every face between cells of different blocks is a fault face: lateral and horizontal steps.
    normal = geometry.face_normals[tagged]
    up = np.abs(normal[:, 2]) / np.linalg.norm(normal, axis=1)
    block = one_fault[3].block[0]
    split = int(((block == FOOTWALL).any(axis=0) & (block == HANGING_WALL).any(axis=0)).sum())
    assert split == 16 and (up > 0.99).sum() == split  # one horizontal step in every column cut
    assert (up < 0.01).sum() >= 4 * 6  # lateral steps: every row, every layer the trace moves through
    # and every face between cells of different blocks is tagged
    left, right = g.faces.neighbors[:, 0], g.faces.neighbors[:, 1]
    interior = (left >= 0) & (right >= 0)
    of_cell = block.ravel()[g.cells.index_map]
    across = interior & (of_cell[np.maximum(left, 0)] != of_cell[np.maximum(right, 0)])
    assert across.sum() > 0 and (g.faces.tag[across] > 0).all()


def test_the_throw_is_exact_on_every_fault_face(one_fault):
    """Nominal depths (before clamping): hanging-wall minus footwall corner depth on the pillars
    shared across every X face between the blocks, and across every Z step = the throw."""
    _, zc, _, steps, _, _ = one_fault
    nz, ny, nx = steps.block.shape[1:]
    z = steps.nominal.reshape(nz, 2, ny, 2, nx, 2)
    layer = zc.reshape(nz, 2, ny, 2, nx, 2)
    block = steps.block[0]
    west, east = block[..., :-1], block[..., 1:]
    pairs = (west != MISSING) & (east != MISSING) & (west != east)
    assert pairs.sum() > 0
    step = z[:, :, :, :, 1:, 0] - z[:, :, :, :, :-1, 1]  # east minus west corner at the shared pillar
    sign = np.where(east == HANGING_WALL, 1.0, -1.0)[:, None, :, None, :]
    assert np.allclose((sign * step).transpose(0, 2, 4, 1, 3)[pairs], 7.0, rtol=0, atol=1e-12)
    # Z steps: the hanging-wall cell's corners against the layering's at the same depth index
    hanging = block == HANGING_WALL
    assert np.allclose((z - layer).transpose(0, 2, 4, 1, 3, 5)[hanging], 7.0, rtol=0, atol=1e-12)


def test_bulk_volume_is_the_box_less_the_missing_and_clamped_volumes(one_fault):
    _, _, _, steps, deck, r = one_fault
    assert steps.missing_cells > 0 and steps.clamped_cells > 0
    missing = int((steps.block[0] == MISSING).sum())
    assert steps.missing_cells == missing
    assert steps.missing_volume == pytest.approx(missing * 20.0 * 50.0 * 5.0, rel=1e-12)
    total = BOX_VOLUME - steps.missing_volume - steps.clamped_volume
    assert r.bulk_volumes.sum() == pytest.approx(total, rel=1e-12)
    assert any(f"{missing} cells of missing section" in n for n in deck.notes)
    assert deck.pinch is not None  # the blocks meet across the removed cells as across pinch-outs


def test_reverse_throw_leaves_gaps_and_no_overlap():
    fault = dipping(200.0, F1_DIP, -4.0, "right", "R")
    zc, PX, PY = layering()
    steps = stair_steps([fault], zc, PX, PY, (0.0, 600.0, 0.0, 200.0))
    assert steps.missing_cells == 0 and steps.clamped_cells == 0 and steps.gap_cells > 0
    z = steps.zcorn
    assert (np.diff(z, axis=0) >= 0).all()
    # Raised 4 m, a cell east of the plane at its depth is east of it 4 m higher too: no cell is
    # missing, and the blocks are the plane's sides at the cells' own depths.
    x, depth = centres(zc, PX)
    east = plane_offset(fault, F1_DIP, x, depth) > 0
    assert np.array_equal(steps.block[0], np.where(east, HANGING_WALL, FOOTWALL))


def test_vertical_faults_take_todays_path_bit_for_bit():
    trace = [(200.0, -10.0), (260.0, 210.0)]
    plain = FaultTrace(trace, 7.0, "F1", "right")
    vertical = FaultTrace(trace, 7.0, "F1", "right", FaultSurface.from_dip(trace, TOP, 90.0, "right"))
    a = horizons_to_grdecl(HORIZONS, DIMS, LAYERS, [plain])
    b = horizons_to_grdecl(HORIZONS, DIMS, LAYERS, [vertical])
    assert np.array_equal(a.zcorn, b.zcorn) and a.faults == b.faults and a.notes == b.notes
    # and the stair-step rules on that vertical fault give the same grid
    zc, PX, PY = layering()
    steps = stair_steps([plain], zc, PX, PY, (0.0, 600.0, 0.0, 200.0))
    assert np.array_equal(steps.zcorn.ravel(), a.zcorn)


@pytest.fixture(scope="module")
def two_faults(tmp_path_factory):
    """F1 (30 degrees east, 7 m) and F2, dipping 45 degrees west with a 5 m throw and a tip
    inside the grid: a graben between them where both hanging walls meet."""
    f1 = dipping(200.0, F1_DIP, 7.0, "right", "F1")
    f2 = dipping(480.0, 45.0, 5.0, "left", "F2", y_end=120.0)
    deck = horizons_to_grdecl(HORIZONS, DIMS, LAYERS, [f1, f2])
    n = deck.num_cells
    rock = {"PORO": np.full(n, 0.2), "PERMX": np.full(n, 100.0), "PERMY": np.full(n, 80.0)}
    rock["PERMZ"] = np.full(n, 10.0)
    folder = tmp_path_factory.mktemp("stairs")
    path = write_data_deck(folder, "STAIRS", deck, rock)
    return deck, path, run_flow_dry(path, folder / "out")


def test_two_fault_deck_equals_flows_dry_run(two_faults):
    deck, path, case = two_faults
    egrid = read_keywords(Path(f"{case}.EGRID"))
    # Flow read ZCORN unchanged (its fixup adjusted nothing): equal to ours in float32
    assert np.array_equal(egrid["ZCORN"], deck.zcorn.astype(np.float32))
    ours = read_grdecl(path)
    c = deck_transmissibility(ours)
    r = process_grdecl(ours)
    flow_active = np.flatnonzero(egrid["ACTNUM"] > 0) if "ACTNUM" in egrid else np.arange(deck.num_cells)
    assert np.array_equal(np.sort(r.grid.cells.index_map), flow_active)
    mine = dict(zip(map(tuple, c.global_cells.tolist()), c.trans.tolist(), strict=True))
    ref = flow_connections(case)
    assert_same_connections(mine, ref)
    nx, ny, _ = deck.cart_dims
    layer = nx * ny
    k, column = np.divmod(np.array(sorted(ref)), layer)
    lateral_nnc = (column[:, 0] != column[:, 1]) & (k[:, 0] != k[:, 1])
    vertical_step = (column[:, 0] == column[:, 1]) & (k[:, 1] - k[:, 0] > 1)  # across missing section
    assert lateral_nnc.sum() > 0 and vertical_step.sum() > 0
    assert set(r.fault_names) == {"F1", "F2"}


def test_faults_z_lines_name_the_bottom_and_top_faces_of_their_cells():
    deck = horizons_to_grdecl(HORIZONS, (3, 1), 3)
    lines = (FaultSegment("A", 0, 0, 0, 0, 0, 0, "Z"), FaultSegment("B", 1, 2, 0, 0, 2, 2, "Z-"))
    r = process_grdecl(replace(deck, faults=lines))
    g = r.grid
    cell = g.cells.index_map
    up, down = g.faces.neighbors[:, 0], g.faces.neighbors[:, 1]
    named = {
        (int(cell[u]), int(cell[d])): r.fault_names[t - 1]
        for u, d, t in zip(up, down, g.faces.tag, strict=True)
        if t > 0
    }
    # (i, j, k) -> i + 3 k: A is the bottom of (1, 1, 1); B the tops of (2, 1, 3) and (3, 1, 3)
    assert named == {(0, 3): "A", (4, 7): "B", (5, 8): "B"}


def test_a_kinked_fault_classifies_every_cell_by_its_surface_at_the_cells_depth():
    """The per-column shortcut (one side test per column the surface does not cross) against the
    rule applied to every cell: a trace kinked twice, dipping 40 degrees west, 6 m throw."""
    trace = [(380.0, -10.0), (300.0, 90.0), (420.0, 210.0)]
    surface = FaultSurface.from_dip(trace, TOP, 40.0, "left", "K")
    fault = FaultTrace(trace, 6.0, "K", "left", surface)
    zc, PX, PY = layering()
    steps = stair_steps([fault], zc, PX, PY, (0.0, 600.0, 0.0, 200.0))
    x, depth = centres(zc, PX)
    y = np.broadcast_to(0.5 * (PY[:-1, :-1] + PY[1:, :-1]), depth.shape)
    west_now = surface.side_value(x, y, depth) > 0  # left of the section walked north-ish: west
    west_moved = surface.side_value(x, y, depth + 6.0) > 0
    expected = np.where(~west_now, FOOTWALL, np.where(west_moved, HANGING_WALL, MISSING))
    assert np.array_equal(steps.block[0], expected)
    assert (expected == MISSING).sum() > 0 and (expected == HANGING_WALL).sum() > 0
