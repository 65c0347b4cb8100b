"""process_grdecl on generated decks: the seed's figures, invariants, orientation, junk."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import gridlib as gl
from gridlib.cornerpoint import corners
from gridlib.cornerpoint.deck import Deck, FaultSegment
from gridlib.cornerpoint.generators import cut_grdecl, make_model3, simple_grdecl
from gridlib.cornerpoint.process import FAULT, PINCH, process_grdecl

SINE = lambda y: 0.05 * (np.sin(2 * np.pi * y) - 0.5)  # noqa: E731  (MRST's example drop)


def _transformed(deck: Deck, sx: float = 1, sy: float = 1, sz: float = 1) -> Deck:
    c = np.array(deck.coord).reshape(-1, 6) * [sx, sy, sz, sx, sy, sz]
    return dataclasses.replace(deck, coord=c.ravel(), zcorn=np.array(deck.zcorn) * sz)


def test_seed_simple_grdecl_flat_drop_012():
    """simpleGrdecl([4,2,3], .12, 'flat', true): the seed's numbers."""
    r = process_grdecl(simple_grdecl([4, 2, 3], 0.12, flat=True))
    g = r.grid
    assert (g.num_cells, g.num_faces, g.num_nodes) == (24, 106, 72)
    fault = g.faces.tag > 0
    inner = (g.faces.neighbors >= 0).all(axis=1)
    assert (int(fault.sum()), int((fault & inner).sum()), int((fault & ~inner).sum())) == (14, 10, 4)
    assert int((g.cells.num_faces == 7).sum()) == 12
    geo = gl.compute_geometry(g)
    assert geo.cell_volumes.sum() == pytest.approx(0.494, abs=1e-12)
    gl.check_grid(g, geo)
    # Interior fault faces join different layers: each is a fault NNC.
    assert r.nnc.num == 4 and np.all(r.nnc.kind == FAULT)
    assert r.fault_names == ("fault_1",)


def test_unfaulted_deck_reproduces_cart_grid_exactly():
    ref = gl.cart_grid([4, 3, 2], [4.0, 3.0, 2.0])
    g = process_grdecl(simple_grdecl([4, 3, 2], 0.0, undisturbed=True, phys_dims=(4, 3, 2))).grid
    for part, field in (
        ("faces", "neighbors"),
        ("cells", "faces"),
        ("cells", "face_tag"),
        ("cells", "index_map"),
    ):
        np.testing.assert_array_equal(getattr(getattr(g, part), field), getattr(getattr(ref, part), field))
    np.testing.assert_array_equal(g.nodes.coords[g.faces.nodes], ref.nodes.coords[ref.faces.nodes])
    assert g.num_faces == 5 * 3 * 2 + 4 * 4 * 2 + 4 * 3 * 3


DROPS = [0.0, 0.05, 0.12, 0.25, 0.5, SINE]


def _standalone_hexahedra(deck: Deck) -> np.ndarray:
    """Volume of every active cell as an isolated hexahedron of its 8 corners (the oracle)."""
    nx, ny, _ = deck.cart_dims
    act = np.flatnonzero(deck.active)
    i, j, k = act % nx, (act // nx) % ny, act // (nx * ny)
    a, b, c = (
        np.array(v) for v in ([0, 1, 0, 1, 0, 1, 0, 1], [0, 0, 1, 1, 0, 0, 1, 1], [0, 0, 0, 0, 1, 1, 1, 1])
    )
    z = deck.zcorn_array()[2 * k[:, None] + c, 2 * j[:, None] + b, 2 * i[:, None] + a]
    lines = deck.pillars().reshape(-1, 2, 3)[(i[:, None] + a) + (nx + 1) * (j[:, None] + b)]
    t = (z - lines[..., 0, 2]) / (lines[..., 1, 2] - lines[..., 0, 2])
    xyz = lines[..., 0, :] + t[..., None] * (lines[..., 1, :] - lines[..., 0, :])
    one = gl.cart_grid([1, 1, 1])  # its 8 nodes are numbered like the corners above
    n = act.size
    faces = gl.Faces(
        np.arange(0, 24 * n + 1, 4),
        (one.faces.nodes.reshape(1, 6, 4) + 8 * np.arange(n)[:, None, None]).ravel(),
        np.where(one.faces.neighbors[None] >= 0, np.arange(n)[:, None, None], -1).reshape(-1, 2),
    )
    cells = gl.Cells(np.arange(0, 6 * n + 1, 6), (one.cells.faces[None] + 6 * np.arange(n)[:, None]).ravel())
    grid = gl.Grid(cells, faces, gl.Nodes(xyz.reshape(-1, 3)), 3)
    return gl.compute_geometry(grid).cell_volumes


@pytest.mark.parametrize("drop", DROPS, ids=["0", "0.05", "0.12", "0.25", "0.5", "sine"])
@pytest.mark.parametrize("flat", [True, False])
def test_simple_grdecl_drops_give_valid_grids(drop, flat):
    deck = simple_grdecl([10, 8, 5], drop, flat=flat)
    r = process_grdecl(deck)
    geo = gl.compute_geometry(r.grid)
    gl.check_grid(r.grid, geo)
    assert r.grid.num_cells == 400
    hexa = _standalone_hexahedra(deck)[r.grid.cells.index_map]
    np.testing.assert_allclose(r.bulk_volumes, hexa, rtol=1e-12)  # ECLIPSE's convention, always
    if flat:  # planar faces: subdividing them must not change any cell's volume
        np.testing.assert_allclose(geo.cell_volumes, hexa, rtol=1e-12)
    else:  # warped faces: shared pieces differ from each cell's own hexahedron, not the total
        assert geo.cell_volumes.sum() == pytest.approx(r.bulk_volumes.sum(), rel=1e-3)


def test_faces_per_cell_reach_eight_with_a_sine_drop():
    g = process_grdecl(simple_grdecl([10, 8, 5], SINE)).grid
    assert g.cells.num_faces.max() >= 8


def test_make_model3_is_valid_and_has_faults_and_inactive_cells():
    deck = make_model3([30, 20, 6])
    r = process_grdecl(deck)
    geo = gl.compute_geometry(r.grid)
    gl.check_grid(r.grid, geo)
    assert r.grid.num_cells <= int(deck.active.sum())
    assert (r.grid.faces.tag > 0).sum() > 0 and r.nnc.num > 0
    assert r.grid.cells.num_faces.max() >= 8


@pytest.mark.parametrize(
    "make", [lambda: simple_grdecl([4, 2, 3], 0.12, flat=True), lambda: make_model3([20, 12, 5])]
)
def test_mirrored_and_z_up_decks_give_the_same_cells(make):
    deck = make()
    ref = np.sort(gl.compute_geometry(process_grdecl(deck).grid).cell_volumes)
    for sx, sy, sz in [(-1, 1, 1), (1, -1, 1), (1, 1, -1), (-1, 1, -1)]:
        r = process_grdecl(_transformed(deck, sx, sy, sz))
        geo = gl.compute_geometry(r.grid)
        gl.check_grid(r.grid, geo)
        np.testing.assert_allclose(np.sort(geo.cell_volumes), ref, rtol=1e-12)
        assert np.all(r.bulk_volumes > 0)
        assert r.notes  # says what it normalised


@pytest.mark.parametrize("junk", [np.nan, -1e20, 1e20])
def test_junk_in_inactive_cells_is_ignored(junk):
    deck = make_model3([30, 20, 6])
    nx, ny, nz = deck.cart_dims
    z = np.array(deck.zcorn).reshape(2 * nz, 2 * ny, 2 * nx)
    cells = np.flatnonzero(~deck.active)
    i, j, k = cells % nx, (cells // nx) % ny, cells // (nx * ny)
    for a in (0, 1):
        for b in (0, 1):
            for c in (0, 1):
                z[2 * k + c, 2 * j + b, 2 * i + a] = junk
    r = process_grdecl(dataclasses.replace(deck, zcorn=z.ravel()))
    ref = process_grdecl(deck)
    np.testing.assert_array_equal(r.grid.cells.index_map, ref.grid.cells.index_map)
    np.testing.assert_allclose(
        gl.compute_geometry(r.grid).cell_volumes, gl.compute_geometry(ref.grid).cell_volumes, rtol=1e-14
    )


def test_non_finite_active_corner_is_a_clear_error():
    deck = make_model3([30, 20, 6])
    z = np.array(deck.zcorn)
    c0 = int(np.flatnonzero(deck.active)[5])
    nx, ny = 30, 20
    i, j, k = c0 % nx, (c0 // nx) % ny, c0 // (nx * ny)
    z.reshape(12, 40, 60)[2 * k, 2 * j, 2 * i] = np.nan
    with pytest.raises(
        gl.InputError, match=rf"active cell \({i + 1}, {j + 1}, {k + 1}\) has a non-finite corner"
    ):
        process_grdecl(dataclasses.replace(deck, zcorn=z))


@pytest.mark.parametrize("block", [1 << 18, 2400])  # all layers at once; one layer (4 nx ny corners)
@pytest.mark.parametrize("up", [False, True])
def test_inverted_corner_is_named_whatever_the_blocks(block, up, monkeypatch):
    """depth_sign reads ZCORN a few layers at a time: the deck's sign and the first cell with a
    top corner below its bottom corner are those of the whole deck, z down or z up."""
    monkeypatch.setattr(corners, "_BLOCK", block)
    deck = make_model3([30, 20, 6])
    nx, ny = 30, 20
    z = np.array(deck.zcorn).reshape(12, 40, 60)
    active = np.flatnonzero(deck.active)
    first, later = int(active[active // (nx * ny) == 2][7]), int(active[active // (nx * ny) == 4][0])
    for g in (later, first):
        i, j, k = g % nx, (g // nx) % ny, g // (nx * ny)
        z[2 * k, 2 * j + 1, 2 * i + 1] = z[2 * k + 1, 2 * j + 1, 2 * i + 1] + 1.0  # top below bottom
    sign = -1 if up else 1
    i, j, k = first % nx, (first // nx) % ny, first // (nx * ny)
    with pytest.raises(gl.InputError, match=rf"cell \({i + 1}, {j + 1}, {k + 1}\) has a top corner below"):
        corners.depth_sign(dataclasses.replace(deck, zcorn=(sign * z).ravel()))
    assert corners.depth_sign(dataclasses.replace(deck, zcorn=sign * np.array(deck.zcorn))) == sign


def test_non_finite_pillar_of_an_active_cell_is_named():
    deck = simple_grdecl([3, 2, 2], 0.0, flat=True)
    coord = np.array(deck.coord, dtype=float).reshape(3, 4, 6)  # (ny + 1, nx + 1) pillars
    coord[2, 1, 0] = np.inf  # pillar (2, 3): a corner of cells (1, 2) and (2, 2)
    with pytest.raises(gl.InputError, match=r"COORD: pillar \(2, 3\) of an active cell is NaN.* \(1 such"):
        process_grdecl(dataclasses.replace(deck, coord=coord.ravel()))


def test_overlapping_layers_are_a_clear_error():
    deck = simple_grdecl([2, 2, 2], 0.0, flat=True)
    z = np.array(deck.zcorn).reshape(4, 4, 4)
    z[1] += 0.3  # the first layer's bottom below the second layer's top
    with pytest.raises(gl.InputError, match=r"cell \(1, 1, 1\) reaches below the top of cell \(1, 1, 2\)"):
        process_grdecl(dataclasses.replace(deck, zcorn=z.ravel()))


def test_collapsed_cells_are_removed_and_their_neighbours_touch():
    deck = simple_grdecl([3, 2, 3], 0.0, flat=True)
    z = np.array(deck.zcorn).reshape(6, 4, 6)
    z[3] = z[2]  # layer 2 (k = 1) has zero thickness everywhere
    z[4] = z[2]
    r = process_grdecl(dataclasses.replace(deck, zcorn=z.ravel()))
    g = r.grid
    assert g.num_cells == 12 and set(g.cells.index_map // 6) == {0, 2}
    assert (
        "6 ACTNUM-active cells of zero thickness (top and bottom corners the same on all four pillars) "
        "were removed" in r.notes
    )
    gl.check_grid(g)
    # Layers 0 and 2 now share faces: vertical non-neighbour connections of PINCH kind.
    assert r.nnc.num == 6 and np.all(r.nnc.kind == PINCH)
    assert np.all(np.diff(r.nnc.global_cells, axis=1)[:, 0] == 12)


def test_pinch_connects_across_thin_inactive_layers():
    deck = simple_grdecl([2, 2, 3], 0.0, flat=True)
    act = np.ones(12, np.int32)
    act[4:8] = 0  # the middle layer inactive (thickness 1/6)
    thin = dataclasses.replace(deck, actnum=act)
    assert process_grdecl(thin).nnc.num == 0
    r = process_grdecl(thin, pinch=True, pinch_threshold=0.2)
    assert r.nnc.num == 4 and np.all(r.nnc.kind == PINCH) and np.all(r.nnc.face == -1)
    assert process_grdecl(thin, pinch=True, pinch_threshold=0.1).nnc.num == 0


def test_named_faults_tag_their_faces():
    deck = simple_grdecl([4, 2, 3], 0.12, flat=True)
    named = dataclasses.replace(deck, faults=(FaultSegment("MIDDLE", 1, 1, 0, 1, 0, 2, "X"),))
    r = process_grdecl(named)
    tags = r.grid.faces.tag
    assert r.fault_names[0] == "MIDDLE"
    assert int((tags == 1).sum()) == 14  # every piece of the +x faces of cells i = 1
    assert not np.any(tags > 1)


def test_tolerance_merges_close_depths():
    deck = simple_grdecl([2, 1, 2], 1e-4, flat=True, undisturbed=True)
    exact = process_grdecl(deck).grid
    merged = process_grdecl(deck, tolerance=1e-3).grid
    assert exact.num_faces > merged.num_faces and not np.any(merged.faces.tag > 0)
    gl.check_grid(merged)


def test_cut_grdecl_keeps_the_box():
    deck = make_model3([30, 20, 6])
    sub = cut_grdecl(deck, ((5, 20), (3, 15), (1, 5)))
    assert sub.cart_dims == (15, 12, 4)
    r = process_grdecl(sub)
    gl.check_grid(r.grid)
    full = process_grdecl(deck)
    ijk = np.array(np.unravel_index(full.grid.cells.index_map, (6, 20, 30))).T
    inside = (ijk[:, 2] >= 5) & (ijk[:, 2] < 20) & (ijk[:, 1] >= 3) & (ijk[:, 1] < 15)
    inside &= (ijk[:, 0] >= 1) & (ijk[:, 0] < 5)
    vol_full = np.sort(gl.compute_geometry(full.grid).cell_volumes[inside])
    np.testing.assert_allclose(np.sort(gl.compute_geometry(r.grid).cell_volumes), vol_full, rtol=1e-12)
    with pytest.raises(gl.InputError, match="is not inside"):
        cut_grdecl(deck, ((0, 31), (0, 1), (0, 1)))


def test_no_active_cell_is_an_error():
    deck = simple_grdecl([2, 2, 2])
    with pytest.raises(gl.InputError, match="no active cells"):
        process_grdecl(dataclasses.replace(deck, actnum=np.zeros(8, np.int32)))


def test_cell_collapsed_on_one_pillar_has_triangular_side_faces():
    """A layer pinched to zero on one pillar: its lateral faces there are triangles, not quads
    with a repeated node (Reek has such cells)."""
    deck = simple_grdecl([2, 1, 2], 0.0, flat=True)
    z = np.array(deck.zcorn).reshape(4, 2, 4)
    z[1, :, 0] = z[0, :, 0]  # bottom of layer 0 = its top on the pillars at i = 0
    z[2, :, 0] = z[0, :, 0]
    g = process_grdecl(dataclasses.replace(deck, zcorn=z.ravel())).grid
    geo = gl.compute_geometry(g)
    gl.check_grid(g, geo)
    assert g.num_cells == 4
    assert int((g.faces.num_nodes == 3).sum()) == 2  # S and N faces of cell (0, 0, 0); its W face vanishes


def test_cell_pinched_on_a_whole_pair_is_no_neighbour_there():
    """Cell 0 has zero thickness on both pillars it shares with cell 1: it is a wedge whose
    edge touches cell 1 along a line, so cell 1's face there is on the boundary."""
    deck = simple_grdecl([2, 1, 1], 0.0, flat=True, undisturbed=True)
    z = np.array(deck.zcorn).reshape(2, 2, 4)
    z[1, :, 1] = z[0, :, 1]  # cell 0's east corners (on the shared pillars) collapse
    r = process_grdecl(dataclasses.replace(deck, zcorn=z.ravel()))
    geo = gl.compute_geometry(r.grid)
    gl.check_grid(r.grid, geo)
    np.testing.assert_allclose(geo.cell_volumes, r.bulk_volumes, rtol=1e-12)
    assert not np.any((r.grid.faces.neighbors >= 0).all(axis=1))  # no interior face


def test_faults_named_by_the_deck_leave_no_automatic_names():
    deck = simple_grdecl([4, 2, 3], 0.12, flat=True)
    r = process_grdecl(dataclasses.replace(deck, faults=(FaultSegment("MIDDLE", 1, 1, 0, 1, 0, 2, "X"),)))
    assert r.fault_names == ("MIDDLE",)
    partial = dataclasses.replace(deck, faults=(FaultSegment("TOP", 1, 1, 0, 1, 0, 0, "X"),))
    r = process_grdecl(partial)  # the lower layers' fault faces keep an automatic id
    assert r.fault_names == ("TOP", "fault_1")
    assert set(np.unique(r.grid.faces.tag)) == {0, 1, 2}


def test_deck_of_collapsed_cells_only_is_a_clear_error():
    deck = simple_grdecl([2, 2, 1], 0.0, flat=True)
    z = np.array(deck.zcorn).reshape(2, 4, 4)
    z[1] = z[0]
    with pytest.raises(gl.InputError, match="every active cell has zero thickness"):
        process_grdecl(dataclasses.replace(deck, zcorn=z.ravel()))
