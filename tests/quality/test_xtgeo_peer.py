"""xtgeo's grid quality set equals xtgeo's ``get_gridquality_properties``, cell for cell.

Three decks: Reek (real, faulted; its EGRID read by both tools), a small built deck with
collapsed, negative-thickness, concave and faulted cells, and a small built twisted deck
(pillars turned 30 degrees between top and bottom). Built decks have float32 values (xtgeo
keeps GRDECL coordinates as float32), so both tools see the same corners.

Tolerance: xtgeo returns float32, rounded to nearest from its float64 angles, so its angle
v is off by at most half a float32 unit in the last place, <= v * 2**-24; ours (atan2
instead of acos) agrees with the exact angle to ~1e-12 degrees. ``rtol = 2**-23`` covers
both with a factor 2 to spare; flags must be equal. Cells compared: the active ones (xtgeo
masks the inactive).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xtgeo

from gridlib import compute_geometry
from gridlib.cornerpoint.deck import Deck
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.egrid import read_egrid
from gridlib.io.grdecl import write_grdecl
from gridlib.quality import XTGEO_NAMES, cell_quality, deck_quality
from gridlib.quality.corners import deck_corners, grid_corners

REEK = Path(__file__).parents[1] / "data" / "decks" / "reek" / "REEK.EGRID"
RTOL = 2.0**-23


def xtgeo_quality(grid: xtgeo.Grid) -> dict[str, np.ndarray]:
    """xtgeo's measures as float64 arrays in gridlib's cell order (i fastest), NaN where masked.

    xtgeo's values are (ncol, nrow, nlay) arrays (k fastest in memory): Fortran order ravels
    them i fastest."""
    out = {}
    for prop in grid.get_gridquality_properties().props:
        out[prop.name] = np.ma.filled(prop.values.astype(np.float64), np.nan).ravel(order="F")
    return out


def assert_same(ours: dict[str, np.ndarray], theirs: dict[str, np.ndarray], active: np.ndarray) -> None:
    assert set(theirs) == set(XTGEO_NAMES)
    for name in XTGEO_NAMES:
        np.testing.assert_allclose(
            ours[name][active], theirs[name][active], rtol=RTOL, atol=0.0, err_msg=name
        )


def build_deck(xy_top, xy_bottom, z_top, z_bottom, levels, throw=None, actnum=None) -> Deck:
    """A deck on straight pillars from (xy_top, z_top) to (xy_bottom, z_bottom) ((ny+1, nx+1, 2)
    and scalars) with layer boundaries ``levels`` (nz+1, ny+1, nx+1) (no gaps between layers)
    plus ``throw`` (nz, ny, nx) added to every corner of a cell; values rounded to float32."""
    nzp, nyp, nxp = levels.shape
    nx, ny, nz = nxp - 1, nyp - 1, nzp - 1
    coord = np.concatenate(
        [xy_top, np.full((nyp, nxp, 1), z_top), xy_bottom, np.full((nyp, nxp, 1), z_bottom)], axis=2
    )
    zc = np.empty((nz, 2, ny, 2, nx, 2))
    for c in (0, 1):
        for b in (0, 1):
            for a in (0, 1):
                zc[:, c, :, b, :, a] = levels[c : c + nz, b : b + ny, a : a + nx]
    if throw is not None:
        zc += throw[:, None, :, None, :, None]
    f32 = lambda v: v.astype(np.float32).astype(np.float64)  # noqa: E731
    act = None if actnum is None else np.asarray(actnum, np.int32).ravel()
    return Deck((nx, ny, nz), f32(coord.ravel()), f32(zc.ravel()), act)


def lattice(nx: int, ny: int, step: float) -> np.ndarray:
    x, y = np.meshgrid(np.arange(nx + 1) * step, np.arange(ny + 1) * step)
    return np.stack([x, y], axis=2)


def read_by_xtgeo(deck: Deck, tmp_path: Path) -> xtgeo.Grid:
    path = write_grdecl(tmp_path / "deck.grdecl", deck)
    return xtgeo.grid_from_file(path, fformat="grdecl")


@pytest.fixture(scope="module")
def reek():
    deck = read_egrid(REEK)
    return deck, deck_quality(deck), xtgeo_quality(xtgeo.grid_from_file(REEK))


def test_reek_equals_xtgeo(reek):
    deck, ours, theirs = reek
    active = deck.active.astype(bool)
    assert_same(ours, theirs, active)
    # the real deck exercises the flags: faults, collapsed corners
    assert int(ours["faulted"][active].sum()) == 5866
    assert int(ours["collapsed"][active].sum()) == 20


def test_reek_grid_measures_are_the_decks(reek):
    """The processed grid's cells: the deck's measures by index_map; the corners recovered from
    the grid's own faces are the deck's, bit for bit, for all but the cells with a collapsed
    corner whose top or bottom face lost it."""
    deck, ours, _ = reek
    grid = process_grdecl(deck).grid
    q = cell_quality(grid, compute_geometry(grid), deck=deck)
    for name in XTGEO_NAMES:
        np.testing.assert_array_equal(q[name], ours[name][grid.cells.index_map], err_msg=name)
    from_grid = grid_corners(grid)
    found = np.isfinite(from_grid).all(axis=(1, 2))
    np.testing.assert_array_equal(from_grid[found], deck_corners(deck, grid.cells.index_map)[found])
    assert grid.num_cells - int(found.sum()) == 8
    assert (ours["collapsed"][grid.cells.index_map[~found]] == 1).all()


def test_collapsed_negative_concave_faulted_deck_equals_xtgeo(tmp_path):
    nx, ny, nz = 4, 3, 3
    xy = lattice(nx, ny, 100.0)
    xy[1, 2] = (140.0, 40.0)  # pillar (2, 1) pushed into cell (1, 0): concave in plan view
    levels = 1000.0 + 10.0 * np.arange(nz + 1)[:, None, None] + np.zeros((1, ny + 1, nx + 1))
    levels[2, 1, 1] = levels[1, 1, 1]  # layer 1 has no thickness on pillar (1, 1)
    levels[3, 2, 3] = levels[2, 2, 3] - 2.0  # layer 2's bottom 2 m above its top on pillar (3, 2)
    throw = np.zeros((nz, ny, nx))
    throw[:, :, 3] = 5.0  # a fault between columns i = 2 and 3
    actnum = np.ones((nz, ny, nx), np.int32)
    actnum[0, 2, 0] = 0
    deck = build_deck(xy, xy, 0.0, 2000.0, levels, throw, actnum)
    ours = deck_quality(deck)
    assert_same(ours, xtgeo_quality(read_by_xtgeo(deck, tmp_path)), actnum.ravel() == 1)

    def cells(flag):  # (i, j, k) of the flagged cells
        k, j, i = np.nonzero(flag.reshape(nz, ny, nx))
        return sorted(zip(i.tolist(), j.tolist(), k.tolist(), strict=True))

    assert cells(ours["collapsed"] == 1) == [(0, 0, 1), (0, 1, 1), (1, 0, 1), (1, 1, 1)]
    assert cells(ours["negative_thickness"] == 1) == [(2, 1, 2), (2, 2, 2), (3, 1, 2), (3, 2, 2)]
    assert cells(ours["concave_proj"] > 0) == [(1, 0, 0), (1, 0, 1), (1, 0, 2)]
    assert (ours["concave_proj"][ours["concave_proj"] > 0] == 4).all()  # corner (1, 1): 3 + 1
    assert cells(ours["faulted"] == 1) == [(i, j, k) for i in (2, 3) for j in range(ny) for k in range(nz)]
    # a collapsed corner makes the side quadrilaterals degenerate: (0, 180)
    collapsed = ours["collapsed"] == 1
    assert (ours["minangle_sides"][collapsed] == 0).all() and (ours["maxangle_sides"][collapsed] == 180).all()


def test_twisted_deck_equals_xtgeo(tmp_path):
    nx, ny = 3, 3
    top = lattice(nx, ny, 100.0) - 150.0
    t = np.radians(30.0)
    bottom = np.stack(
        [
            np.cos(t) * top[..., 0] - np.sin(t) * top[..., 1],
            np.sin(t) * top[..., 0] + np.cos(t) * top[..., 1],
        ],
        axis=2,
    )
    levels = np.array([1000.0, 1040.0, 1100.0])[:, None, None] + np.zeros((1, ny + 1, nx + 1))
    deck = build_deck(top, bottom, 1000.0, 1100.0, levels)
    ours = deck_quality(deck)
    assert_same(ours, xtgeo_quality(read_by_xtgeo(deck, tmp_path)), np.ones(deck.num_cells, bool))
    assert (ours["twist"] > 5.0).all()
    # the grid gridlib makes of it has the same measures, from the deck or from its own faces
    grid = process_grdecl(deck).grid
    geo = compute_geometry(grid)
    from_deck = cell_quality(grid, geo, deck=deck)
    from_grid = cell_quality(grid, geo)
    assert grid.num_cells == deck.num_cells
    for name in (*XTGEO_NAMES, "twist"):
        np.testing.assert_array_equal(from_deck[name], ours[name][grid.cells.index_map], err_msg=name)
        if name != "faulted":
            np.testing.assert_allclose(from_grid[name], from_deck[name], rtol=1e-12, atol=1e-12, err_msg=name)
