"""Decks without throws (every pillar layered) take process_grdecl's structured fast path:
nodes numbered from the layer interfaces without a sort, no pillar pair sent to the general
engine. The grid, NNCs, names, notes and bulk volumes must be those of the generic path bit
for bit: every case is processed twice, the second time with the layer test switched off.

Random decks: skewed pillars, layers of random thickness with zero-thickness corners and
collapsed cells, ACTNUM 0 (junk corners there), PORO 0, MINPV, PINCH, z-up decks, a
tolerance; DX/DY/DZ/TOPS decks through the reader. Decks with one pillar that is not layered
(a throw on one pillar line, a gap between layers, a corner a few units in the last place
off, -0.0 and 0.0 on one pillar) must be told apart.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gridlib.cornerpoint import corners
from gridlib.cornerpoint.corners import corner_nodes
from gridlib.cornerpoint.deck import Deck
from gridlib.cornerpoint.process import FAULT, process_grdecl
from gridlib.errors import InputError
from gridlib.io.grdecl import read_grdecl


def _generic(monkeypatch: pytest.MonkeyPatch):
    """The layer test finding no deck layered: every deck takes the generic path."""
    monkeypatch.setattr(corners, "_deck_interfaces", lambda *args: None)


def _assert_layered(deck: Deck, monkeypatch: pytest.MonkeyPatch) -> None:
    """Every pillar of ``deck`` is layered: it is numbered at once from its interfaces."""
    found = []
    real = corners._deck_interfaces
    with monkeypatch.context() as m:
        m.setattr(corners, "_deck_interfaces", lambda *args: found.append(real(*args)) or found[-1])
        assert corner_nodes(deck).layered
    assert found[0] is not None


def _assert_same(fast, generic) -> None:
    g, h = fast.grid, generic.grid
    fields = {
        "cells": ("face_pos", "faces", "face_tag", "index_map"),
        "faces": ("node_pos", "nodes", "neighbors", "tag"),
    }
    pairs = {
        f"{part}.{field}": (getattr(getattr(g, part), field), getattr(getattr(h, part), field))
        for part, names in fields.items()
        for field in names
    }
    for field in ("cells", "global_cells", "kind", "face"):
        pairs[f"nnc.{field}"] = (getattr(fast.nnc, field), getattr(generic.nnc, field))
    for name, (a, b) in pairs.items():
        assert a.dtype == b.dtype, name
        np.testing.assert_array_equal(a, b, err_msg=name)
    # Floats bit for bit (signed zeros and all): compare their bit patterns.
    for name, a, b in (
        ("nodes.coords", g.nodes.coords, h.nodes.coords),
        ("bulk_volumes", fast.bulk_volumes, generic.bulk_volumes),
    ):
        assert a.shape == b.shape, name
        np.testing.assert_array_equal(a.view(np.int64), b.view(np.int64), err_msg=name)
    assert (g.cart_dims, g.history) == (h.cart_dims, h.history)
    assert fast.fault_names == generic.fault_names
    assert fast.notes == generic.notes


def _lattice_deck(seed: int, dims=(6, 5, 7), vertical: bool = False, inactive: float = 0.15) -> Deck:
    """A deck without throws: skewed pillars, per pillar and layer a random thickness (zero on
    about a fifth of them, so some cells are pinched on a pillar and some collapsed), ACTNUM 0
    and PORO 0 cells; inactive cells' corners are junk (NaN, -1e20)."""
    nx, ny, nz = dims
    rng = np.random.default_rng(seed)
    thickness = np.round(rng.uniform(0.5, 3.0, (nx + 1, ny + 1, nz)), 2)
    thickness[rng.random(thickness.shape) < 0.2] = 0.0
    thickness[1:3, 1:3, nz // 2] = 0.0  # cells collapsed on all four pillars
    Z = np.concatenate([np.full((nx + 1, ny + 1, 1), 2000.0), 2000.0 + np.cumsum(thickness, axis=2)], axis=2)
    x = np.linspace(0.0, 300.0, nx + 1)[:, None] + rng.uniform(-5, 5, (nx + 1, ny + 1))
    y = np.linspace(0.0, 200.0, ny + 1)[None, :] + rng.uniform(-5, 5, (nx + 1, ny + 1))
    lean = rng.uniform(-0.05, 0.05, (nx + 1, ny + 1, 2)) * (not vertical)  # inclined pillars
    top_z, bottom_z = Z[..., 0] - 10.0, Z[..., -1] + 10.0
    coord = np.stack(
        [x, y, top_z, x + lean[..., 0] * (bottom_z - top_z), y + lean[..., 1] * (bottom_z - top_z), bottom_z],
        axis=-1,
    ).transpose(1, 0, 2)
    corner = np.arange(1, 2 * max(dims) + 1) // 2
    zcorn = Z[np.ix_(corner[: 2 * nx], corner[: 2 * ny], corner[: 2 * nz])].transpose(2, 1, 0).copy()
    n = nx * ny * nz
    actnum = (rng.random(n) >= inactive).astype(np.int32)
    junk = np.repeat(np.repeat(np.repeat((actnum == 0).reshape(nz, ny, nx), 2, 0), 2, 1), 2, 2)
    zcorn[junk] = np.where(rng.random(int(junk.sum())) < 0.5, np.nan, -1e20)
    poro = np.round(rng.uniform(0.05, 0.3, n), 3)
    poro[rng.random(n) < 0.1] = 0.0
    return Deck(dims, coord.ravel(), zcorn.ravel(), actnum, {"PORO": poro}, source=f"lattice_{seed}")


def _both(deck: Deck, monkeypatch: pytest.MonkeyPatch, **options):
    """``deck`` processed as it comes and by the generic path."""
    fast = process_grdecl(deck, **options)
    with monkeypatch.context() as m:
        _generic(m)
        generic = process_grdecl(deck, **options)
    return fast, generic


@pytest.mark.parametrize("seed", range(12))
def test_lattice_decks_match_the_generic_path(seed, monkeypatch):
    deck = _lattice_deck(seed)
    _assert_layered(deck, monkeypatch)
    fast, generic = _both(deck, monkeypatch)
    _assert_same(fast, generic)
    assert not (fast.nnc.kind == FAULT).any() and not (fast.grid.faces.tag > 0).any()  # no throw


def test_coincident_pillars_match_the_generic_path(monkeypatch):
    """Columns of zero width (the pillars i = 4 on the lines of the pillars i = 3): the faces of
    zero area they make are removed alike."""
    deck = _lattice_deck(23, vertical=True)
    nx = deck.cart_dims[0]
    coord = deck.coord.reshape(-1, nx + 1, 6).copy()
    coord[:, 4] = coord[:, 3]
    deck = dataclasses.replace(deck, coord=coord.ravel())
    _assert_layered(deck, monkeypatch)
    fast, generic = _both(deck, monkeypatch)
    _assert_same(fast, generic)
    assert any("zero area" in note for note in fast.notes)


@pytest.mark.parametrize(
    "options", [{"minpv": 300.0}, {"pinch": True, "pinch_threshold": 2.5}, {"tolerance": 0.3}]
)
def test_minpv_pinch_and_tolerance_match_the_generic_path(options, monkeypatch):
    deck = _lattice_deck(20)
    fast, generic = _both(deck, monkeypatch, **options)
    _assert_same(fast, generic)
    if "pinch" in options:
        assert (fast.nnc.kind == 1).any()  # pinch connections across the removed cells
    if "minpv" in options:
        assert any("below MINPV" in note for note in fast.notes)


def test_z_up_deck_matches_the_generic_path(monkeypatch):
    deck = _lattice_deck(21)
    coord = deck.coord.reshape(-1, 6).copy()
    coord[:, [2, 5]] *= -1.0
    up = dataclasses.replace(deck, coord=coord.ravel(), zcorn=-deck.zcorn)
    _assert_layered(up, monkeypatch)
    fast, generic = _both(up, monkeypatch)
    _assert_same(fast, generic)
    assert "z up" in fast.notes[0]


@pytest.mark.parametrize("case", ["throw", "gap", "ulp", "negative_zero"])
def test_decks_with_a_pillar_not_layered_take_the_generic_path(case):
    """A throw along pillar column i = 3, a gap below one cell, a corner 2 ulp above its
    neighbours', -0.0 above 0.0 (where a sort may keep either as the point)."""
    deck = _lattice_deck(22)
    nx, ny, nz = deck.cart_dims
    zc = deck.zcorn.reshape(2 * nz, 2 * ny, 2 * nx).copy()
    if case == "throw":
        zc[:, :, 6:] += 0.75
    elif case == "gap":
        thick = (zc[1::2] - zc[::2]).reshape(nz, ny, 2, nx, 2).min(axis=(2, 4)) >= 0.5
        k, j, i = np.argwhere(thick & (deck.actnum.reshape(nz, ny, nx) == 1))[len(thick) // 2]
        zc[2 * k + 1, 2 * j : 2 * j + 2, 2 * i : 2 * i + 2] -= 0.25  # ends above the cell below
    elif case == "ulp":
        zc[2 * 2, 3, 3] = np.nextafter(np.nextafter(zc[2 * 2, 3, 3], -np.inf), -np.inf)
    else:
        zc -= 2000.0  # the top at depth 0, where the first layer has no thickness it ends at 0.0 ...
        zc[0] = -0.0  # ... and starts at -0.0
        coord = deck.coord.reshape(-1, 6).copy()
        coord[:, [2, 5]] -= 2000.0
        deck = dataclasses.replace(deck, coord=coord.ravel())
    deck = dataclasses.replace(deck, zcorn=zc.ravel())
    assert not corner_nodes(deck).layered
    if case == "throw":
        r = process_grdecl(deck)
        assert (r.grid.faces.tag > 0).any() and (r.nnc.kind == FAULT).any()


def _dxdydz_text(seed: int) -> str:
    """A DX/DY/DZ/TOPS deck (top layer TOPS, DZ constant per layer with zero layers), with
    ACTNUM 0 and PORO 0 cells, a MINPV and two FAULTS lines (faults without a throw)."""
    nx, ny, nz = 7, 4, 6
    n = nx * ny * nz
    rng = np.random.default_rng(seed)
    dx = np.tile(np.round(rng.uniform(10, 30, nx), 1), ny * nz)  # DX per i, DY per j
    dy = np.tile(np.repeat(np.round(rng.uniform(5, 20, ny), 1), nx), nz)
    dz = np.repeat(np.round(rng.uniform(0.5, 2.0, nz), 2), nx * ny)
    dz[2 * nx * ny : 3 * nx * ny] = 0.0  # a layer of zero thickness
    poro = np.round(rng.uniform(0.05, 0.3, n), 3)
    poro[rng.random(n) < 0.1] = 0.0
    actnum = (rng.random(n) > 0.1).astype(int)
    text = [f"DIMENS\n {nx} {ny} {nz} /\nMINPV\n 50 /\n"]
    for key, values in (("DX", dx), ("DY", dy), ("DZ", dz), ("PORO", poro), ("ACTNUM", actnum)):
        text.append(f"{key}\n" + " ".join(f"{v:g}" for v in values) + "\n/\n")
    text.append(f"TOPS\n {nx * ny}*1500 /\n")
    text.append("FAULTS\n 'F1' 3 3 1 4 1 6 'X' /\n 'F2' 1 7 2 2 2 3 'Y' /\n/\n")  # named, no throw
    return "".join(text)


@pytest.mark.parametrize("seed", range(4))
def test_dx_dy_dz_decks_match_the_generic_path(seed, tmp_path, monkeypatch):
    path = tmp_path / "box.grdecl"
    path.write_text(_dxdydz_text(seed))
    deck = read_grdecl(path)
    _assert_layered(deck, monkeypatch)
    fast, generic = _both(deck, monkeypatch, pinch=True)
    _assert_same(fast, generic)
    assert fast.fault_names == ("F1", "F2") and {1, 2} <= set(fast.grid.faces.tag.tolist())


def test_layers_overlapping_across_an_inactive_layer_are_refused_as_before():
    """Interfaces that rise down a pillar (layer 4 starting above the bottom of layer 2, layer
    3 inactive between them, every corner matching its neighbours') are not layered: the
    generic path refuses the overlap, naming the cells."""
    deck = _lattice_deck(24, inactive=0.0)
    nx, ny, nz = deck.cart_dims
    zc = deck.zcorn.reshape(2 * nz, 2 * ny, 2 * nx).copy()
    zc[2 * 2 + 1] = zc[2 * 2] + 5.0  # layer 2 is 5 thick
    zc[2 * 4] = zc[2 * 2] + 1.0  # layer 4 starts 1 below the top of layer 2 ...
    zc[2 * 4 + 1 :] += 10.0  # ... and ends deeper than it did, as the layers below
    actnum = np.ones((nz, ny, nx), dtype=np.int32)
    actnum[3] = 0
    deck = dataclasses.replace(deck, zcorn=zc.ravel(), actnum=actnum.ravel())
    assert not corner_nodes(deck).layered
    with pytest.raises(InputError, match=r"overlapping layers"):
        process_grdecl(deck)
