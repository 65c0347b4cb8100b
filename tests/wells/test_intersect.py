"""gridlib.wells.intersect: the cells a well path crosses. Analytic pieces in a Cartesian box;
lengths that add up to the path's on corner-point (faults, non-planar faces), PEBI (thrown
faults), tetrahedral and twisted grids; paths along a face, an edge, a fault wall and through
a node, each cell once; leaving and re-entering the grid, crossing a hole of inactive cells;
and xtgeo's ``Well.get_cell_intersections`` as a peer on faulted corner-point decks."""

from __future__ import annotations

import itertools
import warnings
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

import gridlib as gl
from gridlib.cornerpoint.generators import make_model3, simple_grdecl
from gridlib.cornerpoint.process import process_grdecl
from gridlib.errors import GridError, InputError
from gridlib.io.grdecl import write_grdecl
from gridlib.pillars.extrude import extrude
from gridlib.pillars.fault_traces import FaultTrace
from gridlib.wells.intersect import PathCells, cell_index, path_cells
from gridlib.wells.path import WellPath
from gridlib.wells.survey import minimum_curvature


def pieces_of(grid: gl.Grid, points, index=None) -> PathCells:
    path = WellPath.from_points(np.asarray(points, dtype=float))
    pc = path_cells(grid, gl.compute_geometry(grid), path, index=index)
    # Always: MD order, straight pieces (MD is the length along the path here), runs 0, 1, ...
    assert np.all(pc.entry_md < pc.exit_md) and np.all(pc.exit_md[:-1] <= pc.entry_md[1:])
    np.testing.assert_allclose(pc.exit_md - pc.entry_md, pc.length, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(path.at(pc.entry_md), pc.entry, rtol=0, atol=1e-12 * (1 + path.length))
    if pc.num:
        assert pc.run[0] == 0 and set(np.diff(pc.run).tolist()) <= {0, 1}
    return pc


def run_cells(pc: PathCells) -> np.ndarray:
    """The cell of every run, in MD order."""
    return pc.cell[np.r_[0, np.flatnonzero(np.diff(pc.run)) + 1]] if pc.num else pc.cell


# --------------------------------------------------------------------------- a Cartesian box


def box_pieces(points: np.ndarray, dims, spacing):
    """Independent reference: each segment split where it crosses the planes x = i dx,
    y = j dy, z = k dz (and at its ends); the pieces inside the box with their cell."""
    n = np.asarray(dims)
    h = np.asarray(spacing, dtype=float)
    cells, t_in, t_out, segs = [], [], [], []
    for s, (a, b) in enumerate(itertools.pairwise(points)):
        ts = [0.0, 1.0]
        for axis in range(3):
            if b[axis] != a[axis]:
                planes = np.arange(n[axis] + 1) * h[axis]
                t = (planes - a[axis]) / (b[axis] - a[axis])
                ts += t[(t > 0) & (t < 1)].tolist()
        ts = np.unique(ts)
        for t0, t1 in itertools.pairwise(ts):
            mid = a + 0.5 * (t0 + t1) * (b - a)
            ijk = np.floor(mid / h).astype(int)
            if np.all(ijk >= 0) and np.all(ijk < n):
                cells.append(ijk[0] + n[0] * (ijk[1] + n[1] * ijk[2]))
                t_in.append(t0)
                t_out.append(t1)
                segs.append(s)
    return np.array(cells), np.array(segs), np.array(t_in), np.array(t_out)


def test_diagonal_path_through_a_box_is_analytic():
    dims, spacing = (5, 4, 3), (20.0, 25.0, 10.0)
    grid = gl.cart_grid(dims, [d * h for d, h in zip(dims, spacing, strict=True)])
    points = np.array([[-13.0, 7.0, -4.0], [57.0, 61.0, 17.0], [93.0, 113.0, 26.0], [130.0, 40.0, 41.0]])
    pc = pieces_of(grid, points)
    cells, segs, t0, t1 = box_pieces(points, dims, spacing)
    np.testing.assert_array_equal(pc.cell, cells)
    a, b = points[segs], points[segs + 1]
    np.testing.assert_allclose(pc.entry, a + t0[:, None] * (b - a), rtol=0, atol=1e-12)
    np.testing.assert_allclose(pc.exit, a + t1[:, None] * (b - a), rtol=0, atol=1e-12)
    md = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))]
    seg_len = np.diff(md)
    np.testing.assert_allclose(pc.entry_md, md[segs] + t0 * seg_len[segs], rtol=0, atol=1e-12)
    np.testing.assert_allclose(pc.exit_md, md[segs] + t1 * seg_len[segs], rtol=0, atol=1e-12)
    # The vertex at (57, 61, 17) is inside cell (2, 2, 1): two pieces of one run there.
    at_vertex = np.flatnonzero(pc.exit_md == md[1])
    assert at_vertex.size == 1 and pc.cell[at_vertex[0]] == pc.cell[at_vertex[0] + 1] == 2 + 5 * (2 + 4 * 1)
    assert pc.run[at_vertex[0]] == pc.run[at_vertex[0] + 1]
    assert pc.run[-1] == pc.num - 2  # every other piece starts a run
    # The middle segment leaves the box through y = 100 in cell (4, 3, 2); the last one comes
    # back in through y = 100 and leaves through x = 100 in the same cell: a second run of it.
    last = 4 + 5 * (3 + 4 * 2)
    assert pc.cell[-2:].tolist() == [last, last] and pc.run[-1] == pc.run[-2] + 1
    assert pc.exit_md[-2] < md[2] < pc.entry_md[-1]
    assert pc.length.sum() == pytest.approx(float(np.sum((t1 - t0) * seg_len[segs])), rel=1e-13)


# --------------------------------------------------------------------------- every grid type


def faulted_cornerpoint() -> gl.Grid:
    """MRST's simpleGrdecl: skewed pillars, sine-perturbed (non-planar) layers, a 0.1 m drop."""
    return process_grdecl(simple_grdecl([6, 4, 5], 0.1)).grid


def pebi_with_thrown_fault() -> gl.Grid:
    rng = np.random.default_rng(26)
    edge = np.linspace(0.0, 1000.0, 9)
    inner = edge[1:-1]
    square = np.concatenate(
        [np.column_stack([edge, 0 * edge]), np.column_stack([edge, 0 * edge + 1000.0]),
         np.column_stack([0 * inner, inner]), np.column_stack([0 * inner + 1000.0, inner])]
    )  # fmt: skip
    areal = gl.pebi(gl.triangle_grid(np.concatenate([square, rng.uniform(50.0, 950.0, (60, 2))])))
    fault = FaultTrace([(420.0, -10.0), (610.0, 1010.0)], 7.0, name="F")
    return extrude(areal, [1000.0, 1030.0], layers=3, faults=[fault]).grid


def tetrahedra() -> gl.Grid:
    rng = np.random.default_rng(5)
    x, y, z = np.meshgrid([0.0, 1.0], [0.0, 1.0], [0.0, 1.0], indexing="ij")
    corners = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    return gl.tetrahedral_grid(np.concatenate([corners, rng.uniform(0.02, 0.98, (60, 3))]))


GRIDS = {
    # (grid, a path inside it: its length inside is the path's)
    "cornerpoint": (
        faulted_cornerpoint,
        [[0.05, 0.1, 0.3], [0.5, 0.5, 0.25], [0.93, 0.93, 0.34], [0.3, 0.8, 0.27]],
    ),
    "pebi": (pebi_with_thrown_fault, [[30.0, 40.0, 1006.0], [500.0, 520.0, 1020.0], [980.0, 900.0, 1028.0]]),
    "tetrahedral": (tetrahedra, [[0.01, 0.02, 0.03], [0.7, 0.4, 0.9], [0.2, 0.95, 0.5], [0.99, 0.5, 0.01]]),
    "twisted": (
        lambda: gl.twister(gl.cart_grid([6, 5, 4], [1.0, 1.0, 1.0]), 0.05),
        [[0.02, 0.03, 0.5], [0.97, 0.5, 0.1], [0.5, 0.97, 0.9], [0.1, 0.1, 0.98]],
    ),
}


@pytest.mark.parametrize("name", list(GRIDS))
def test_lengths_add_up_on_every_grid(name):
    make, points = GRIDS[name]
    grid = make()
    pc = pieces_of(grid, points)
    path = WellPath.from_points(np.asarray(points, dtype=float))
    assert pc.length.sum() == pytest.approx(path.length, rel=1e-9)
    assert pc.entry_md[0] == 0.0 and pc.exit_md[-1] == path.length
    np.testing.assert_array_equal(pc.exit_md[:-1], pc.entry_md[1:])  # no gaps, no overlaps
    assert np.unique(run_cells(pc)).size >= 8
    # Consecutive runs are neighbours: they share a face (or touch at an edge or a node).
    nodes = [set(cell_nodes(grid, c)) for c in run_cells(pc)]
    assert all(a & b for a, b in itertools.pairwise(nodes))


def test_a_survey_keeps_its_measured_depths():
    """A path by minimum curvature: its MD steps are arc lengths, longer than the chords. The
    pieces' MDs are linear along the segments (WellPath.at), their MD lengths add up to the MD
    inside, their straight lengths to the chords'."""
    grid = gl.twister(gl.cart_grid([6, 5, 4], [10.0, 10.0, 10.0]), 0.05)
    path = minimum_curvature(
        (1.0, 5.0, 1.0), [(0.0, 20.0, 90.0), (6.0, 50.0, 70.0), (12.0, 80.0, 110.0)], step=1.5
    )
    pc = path_cells(grid, gl.compute_geometry(grid), path)
    np.testing.assert_allclose(path.at(pc.entry_md), pc.entry, rtol=0, atol=1e-12)
    np.testing.assert_allclose(path.at(pc.exit_md), pc.exit, rtol=0, atol=1e-12)
    assert np.sum(pc.exit_md - pc.entry_md) == pytest.approx(path.length, rel=1e-12)
    chords = np.linalg.norm(np.diff(path.xyz, axis=0), axis=1).sum()
    assert pc.length.sum() == pytest.approx(chords, rel=1e-12) and chords < path.length
    assert pc.run[-1] + 1 < pc.num  # pieces split at the path's vertices, runs across them


def cell_nodes(grid: gl.Grid, c: int) -> np.ndarray:
    faces = grid.cells.faces[grid.cells.face_pos[c] : grid.cells.face_pos[c + 1]]
    pos = grid.faces.node_pos
    return np.concatenate([grid.faces.nodes[pos[f] : pos[f + 1]] for f in faces])


def test_tetrahedra_hold_their_pieces():
    """Independent of the winding numbers: every piece's midpoint has barycentric coordinates
    >= 0 in its tetrahedron (a convex cell)."""
    grid = tetrahedra()
    pc = pieces_of(grid, GRIDS["tetrahedral"][1])
    xyz = grid.nodes.coords
    for c, mid in zip(pc.cell, 0.5 * (pc.entry + pc.exit), strict=True):
        p = xyz[np.unique(cell_nodes(grid, c))]
        lam = np.linalg.solve(np.vstack([p.T, np.ones(4)]), np.r_[mid, 1.0])
        assert lam.min() >= -1e-12


# --------------------------------------------------------------------------- degenerate paths

DX, DY, DZ, DROP = 0.25, 0.5, 0.125, 0.1  # simple_grdecl([4, 2, 4]) flat, undisturbed, drop 0.1


def planar_faulted(actnum=None) -> tuple[gl.Grid, np.ndarray]:
    """A 4 x 2 x 4 box of 0.25 x 0.5 x 0.125 m cells, vertical pillars, flat layers; the east
    half (i >= 2) dropped by 0.1 m: a fault wall at x = 0.5. Returns the grid and the global
    (i + 4 j + 8 k) index of its cells."""
    deck = simple_grdecl([4, 2, 4], DROP, flat=True, undisturbed=True)
    if actnum is not None:
        deck = replace(deck, actnum=actnum)
    grid = process_grdecl(deck).grid
    return grid, grid.cells.index_map


def cell_at(i: int, j: int, k: int) -> int:
    return i + 4 * (j + 2 * k)


def reference_on_boundaries(a, b, breaks, cells_at):
    """Pieces of the segment a -> b split at the parameters ``breaks``, each given the lowest
    of the cells ``cells_at(midpoint)`` (the tie rule), consecutive equal cells merged."""
    ts = np.unique(np.clip(np.r_[0.0, 1.0, breaks], 0.0, 1.0))
    out = []
    for t0, t1 in itertools.pairwise(ts):
        c = min(cells_at(a + 0.5 * (t0 + t1) * (b - a)), default=None)
        if c is None:
            continue
        if out and out[-1][0] == c and out[-1][2] == t0:
            out[-1][2] = t1
        else:
            out.append([c, t0, t1])
    return out


def faulted_cells_at(p) -> list[int]:
    """The cells of the planar faulted box whose closed box holds p."""
    found = []
    for i in range(4):
        top = DROP if i >= 2 else 0.0
        for j in range(2):
            for k in range(4):
                lo = np.array([i * DX, j * DY, top + k * DZ])
                if np.all(p >= lo - 1e-12) and np.all(p <= lo + [DX, DY, DZ] + 1e-12):
                    found.append(cell_at(i, j, k))
    return found


DEGENERATE = {
    # A face: the plane y = 0.5 between rows j = 0 and 1, diagonally in x and z.
    "face": [[0.05, 0.5, 0.02], [0.45, 0.5, 0.48]],
    # An edge: x = 0.25, y = 0.5, where four columns meet, straight down the west block.
    "edge": [[0.25, 0.5, 0.02], [0.25, 0.5, 0.48]],
    # A node: from the centre of cell (0, 0, 0) through node (0.25, 0.5, 0.125) to cell (1, 1, 1).
    "node": [[0.125, 0.25, 0.0625], [0.375, 0.75, 0.1875]],
    # The fault wall x = 0.5, diagonally in y and z, from the west block's top to below its base.
    "fault wall": [[0.5, 0.1, 0.0], [0.5, 0.9, 0.6]],
}


@pytest.mark.parametrize("name", list(DEGENERATE))
def test_paths_along_faces_edges_nodes_and_fault_walls(name):
    grid, glob = planar_faulted()
    points = np.array(DEGENERATE[name])
    pc = pieces_of(grid, points)
    a, b = points
    d = b - a
    breaks = []
    for axis, planes in (
        (0, np.arange(5) * DX),
        (1, np.arange(3) * DY),
        (2, np.r_[np.arange(5) * DZ, DROP + np.arange(5) * DZ]),
    ):
        if d[axis]:
            breaks += ((planes - a[axis]) / d[axis]).tolist()
    ref = reference_on_boundaries(a, b, np.array(breaks), faulted_cells_at)
    length = float(np.linalg.norm(d))
    assert glob[pc.cell].tolist() == [c for c, _, _ in ref]  # one piece per run here: one segment
    np.testing.assert_allclose(pc.entry_md, [t0 * length for _, t0, _ in ref], rtol=0, atol=1e-13)
    np.testing.assert_allclose(pc.exit_md, [t1 * length for _, _, t1 in ref], rtol=0, atol=1e-13)
    assert np.unique(pc.cell).size == pc.num  # every cell once
    assert pc.length.sum() == pytest.approx(length, rel=1e-12)  # all of it inside closed cells
    if name == "node":
        assert glob[pc.cell].tolist() == [cell_at(0, 0, 0), cell_at(1, 1, 1)]
        assert pc.exit_md[0] == pytest.approx(length / 2, rel=1e-14)
    if name == "fault wall":  # west, east, west ... down the wall: both sides of it take turns
        assert {int(c) % 4 for c in glob[pc.cell]} == {1, 2}


def test_leaving_and_reentering_the_grid():
    """East at z = 0.05 the path leaves the grid at the fault wall (the east block starts
    at z = 0.1), comes down into the east block and back west across the fault."""
    grid, glob = planar_faulted()
    points = np.array([[0.1, 0.25, 0.05], [0.9, 0.25, 0.05], [0.9, 0.25, 0.3], [0.1, 0.25, 0.3]])
    pc = pieces_of(grid, points)
    assert glob[pc.cell].tolist() == [
        cell_at(0, 0, 0), cell_at(1, 0, 0),  # x 0.1 .. 0.25 .. 0.5, then out
        cell_at(3, 0, 0), cell_at(3, 0, 1),  # z 0.1 .. 0.225 .. 0.3
        cell_at(3, 0, 1), cell_at(2, 0, 1),  # west at z = 0.3: x 0.9 .. 0.75 .. 0.5
        cell_at(1, 0, 2), cell_at(0, 0, 2),  # the west block's layer 2: x 0.5 .. 0.25 .. 0.1
    ]  # fmt: skip
    np.testing.assert_allclose(pc.entry_md, [0.0, 0.15, 0.85, 0.975, 1.05, 1.2, 1.45, 1.7], atol=1e-13)
    np.testing.assert_allclose(pc.exit_md, [0.15, 0.4, 0.975, 1.05, 1.2, 1.45, 1.7, 1.85], atol=1e-13)
    assert pc.run.tolist() == [0, 1, 2, 3, 3, 4, 5, 6]  # cell (3, 0, 1) across the path's vertex: one run
    # Into cell (0, 0, 0) from below, out through the top and back in: two runs of one cell.
    pc = pieces_of(grid, [[0.1, 0.25, 0.1], [0.125, 0.25, -0.1], [0.15, 0.25, 0.1]])
    assert glob[pc.cell].tolist() == [cell_at(0, 0, 0)] * 2 and pc.run.tolist() == [0, 1]
    half = np.hypot(0.025, 0.2)
    np.testing.assert_allclose(
        np.c_[pc.entry_md, pc.exit_md], [[0, half / 2], [1.5 * half, 2 * half]], atol=1e-13
    )


def test_inactive_cells_are_a_hole():
    actnum = np.ones(32, dtype=np.int32)
    actnum[[cell_at(1, 0, 1), cell_at(1, 1, 1)]] = 0
    grid, glob = planar_faulted(actnum)
    pc = pieces_of(grid, [[0.1, 0.25, 0.19], [0.9, 0.25, 0.19]])
    assert glob[pc.cell].tolist() == [cell_at(0, 0, 1), cell_at(2, 0, 0), cell_at(3, 0, 0)]
    np.testing.assert_allclose(
        np.c_[pc.entry_md, pc.exit_md], [[0, 0.15], [0.4, 0.65], [0.65, 0.8]], atol=1e-13
    )
    assert pc.run.tolist() == [0, 1, 2]
    # All of a path in the hole, or outside the grid: nothing.
    for points in ([[0.3, 0.1, 0.15], [0.45, 0.9, 0.24]], [[2.0, 0.0, 0.0], [3.0, 1.0, 1.0]]):
        pc = pieces_of(grid, points)
        assert pc.num == 0 and pc.cell.dtype == np.int64 and pc.entry.shape == (0, 3)


def test_one_index_serves_many_wells_and_bad_grids_are_refused():
    grid, _ = planar_faulted()
    index = cell_index(grid, gl.compute_geometry(grid))
    for points in DEGENERATE.values():
        with_index = pieces_of(grid, points, index)
        without = pieces_of(grid, points)
        np.testing.assert_array_equal(with_index.cell, without.cell)
        np.testing.assert_array_equal(with_index.entry_md, without.entry_md)
    other = gl.cart_grid([2, 2, 2])
    with pytest.raises(GridError, match="not this grid's"):
        path_cells(
            other, gl.compute_geometry(other), WellPath.from_points([[0, 0, 0], [1, 1, 1]]), index=index
        )
    planar = gl.cart_grid([2, 2])
    with pytest.raises(InputError, match="3-D grid"):
        path_cells(planar, gl.compute_geometry(planar), WellPath.from_points([[0, 0, 0], [1, 1, 1]]))


# --------------------------------------------------------------------------- xtgeo as a peer


def xtgeo_runs(deck, tmp_path, points: np.ndarray) -> pd.DataFrame:
    """xtgeo's cells along the path (active cells only), with entry and exit MDs."""
    import xtgeo  # a test extra; imported here, where it is used (it takes a second)

    path = tmp_path / "deck.grdecl"
    write_grdecl(path, deck)
    md = WellPath.from_points(points).md
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # pandas' deprecation warnings from inside xtgeo
        grid = xtgeo.grid_from_file(path, fformat="grdecl")
        df = pd.DataFrame({"X_UTME": points[:, 0], "Y_UTMN": points[:, 1], "Z_TVDSS": points[:, 2], "MD": md})
        well = xtgeo.Well(0.0, points[0, 0], points[0, 1], "W", df, mdlogname="MD")
        return well.get_cell_intersections(grid, sampling_step=0.01, active_only=True, zerobased=True)


def runs_of(pc: PathCells) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(cell, entry MD, exit MD) of every run."""
    start = np.r_[0, np.flatnonzero(np.diff(pc.run)) + 1]
    end = np.r_[start[1:] - 1, pc.num - 1]
    return pc.cell[start], pc.entry_md[start], pc.exit_md[end]


def test_xtgeo_agrees_on_a_planar_faulted_deck(tmp_path):
    """simpleGrdecl with flat layers (its skewed pillars keep every face planar), an 8 m drop
    and two inactive cells: xtgeo's ray tracing of planar cells gives the same runs and MDs
    (to its float32 coordinates)."""
    deck = simple_grdecl([6, 5, 4], 8.0, flat=True, phys_dims=(600.0, 500.0, 40.0))
    actnum = np.ones(deck.num_cells, np.int32)
    actnum[[1 + 6 * (2 + 5 * 1), 2 + 6 * (2 + 5 * 1)]] = 0
    deck = replace(deck, actnum=actnum)
    grid = process_grdecl(deck).grid
    for points in (
        [[20.0, 30.0, -10.0], [250.0, 260.0, 18.0], [580.0, 470.0, 45.0]],
        [[590.0, 20.0, 5.0], [10.0, 480.0, 30.0]],
    ):
        points = np.array(points)
        cell, entry_md, exit_md = runs_of(pieces_of(grid, points))
        theirs = xtgeo_runs(deck, tmp_path, points)
        glob = (theirs.I + 6 * (theirs.J + 5 * theirs.K)).to_numpy()
        np.testing.assert_array_equal(grid.cells.index_map[cell], glob)
        np.testing.assert_allclose(entry_md, theirs.ENTRY_MD, rtol=0, atol=1e-6)
        np.testing.assert_allclose(exit_md, theirs.EXIT_MD, rtol=0, atol=1e-6)


def test_xtgeo_agrees_on_make_model3(tmp_path):
    """MRST's makeModel3 (two faults, pinch-outs, inactive cells, non-planar tops and bases):
    the same runs as xtgeo's (which samples the path every 1 cm and bisects: the paths have no
    run shorter than that), and MDs that differ no more than the two cell models can: the
    tops and bases are non-planar quads, which xtgeo and the hinge triangles fill differently,
    both inside the quad's hull, whose depth range is half its twist |z00 + z11 - z01 - z10|;
    a path crossing the quad at a vertical rate dz/dMD, against a surface of slope <= s, may
    then cross it a MD twist / 2 / (|dz/dMD| - s) apart. The vertical faces are planar: there
    the MDs agree to 1e-6."""
    deck = make_model3([20, 15, 5])
    nx, ny, nz = deck.cart_dims
    grid = process_grdecl(deck).grid
    zc = deck.zcorn_array()  # (2 nz, 2 ny, 2 nx)
    quads = zc.reshape(2 * nz, ny, 2, nx, 2)  # per (layer side, j, corner j, i, corner i)
    twist = np.abs(quads[:, :, 0, :, 0] + quads[:, :, 1, :, 1] - quads[:, :, 0, :, 1] - quads[:, :, 1, :, 0])
    cell_twist = np.maximum(twist[0::2], twist[1::2]).ravel()  # (k, j, i): in global order
    # The steepest slope of a top or base: its edges' slopes along x and y, combined
    slope = np.hypot(
        np.abs(zc[:, :, 1::2] - zc[:, :, 0::2]).max() / (1000.0 / nx),
        np.abs(zc[:, 1::2, :] - zc[:, 0::2, :]).max() / (600.0 / ny),
    )
    assert slope < 0.05
    for points in (  # zig-zags across the faults (x = 500 and 600, y = 200 and 320), dz/dMD 0.16
        [[450.0, 100.0, -10.0], [650.0, 250.0, 30.0], [850.0, 400.0, -10.0], [650.0, 550.0, 30.0]],
        [[100.0, 500.0, -10.0], [300.0, 350.0, 30.0], [500.0, 200.0, -10.0], [700.0, 50.0, 30.0]],
    ):
        points = np.array(points)
        pc = pieces_of(grid, points)
        cell, entry_md, exit_md = runs_of(pc)
        theirs = xtgeo_runs(deck, tmp_path, points)
        assert np.all(exit_md - entry_md >= 0.01)  # none that xtgeo's sampling could step over
        glob = grid.cells.index_map[cell]
        np.testing.assert_array_equal(glob, (theirs.I + nx * (theirs.J + ny * theirs.K)).to_numpy())
        path = WellPath.from_points(points)
        seg = np.searchsorted(path.md, entry_md, side="right") - 1
        rate = np.abs(np.diff(points[:, 2]) / np.diff(path.md))[np.minimum(seg, len(points) - 2)]
        previous = np.r_[glob[:1], glob[:-1]]
        bound = np.maximum(cell_twist[glob], cell_twist[previous]) / 2 / (rate - slope) + 1e-6
        difference = np.abs(entry_md - theirs.ENTRY_MD.to_numpy())
        assert glob.size >= 20 and np.all(difference <= bound)
        lateral = cell_twist[glob] == 0  # both models agree exactly where nothing is twisted
        assert difference.max() > 1e-3 and np.all(difference[lateral & (cell_twist[previous] == 0)] <= 1e-6)
