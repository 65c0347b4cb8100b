"""cornerpoint.faces: pillar pairs where an inactive cell faces an active one in an unfaulted
deck are plain quads (no pillar-pair engine), with the engine's faces (as a set), face
geometry, bulk volumes, NNCs and transmissibilities bit for bit.

The faces are numbered differently (the quads in (k, j, i) order among the other quads, not
after them), so a cell's faces are summed in another order by ``compute_geometry``: its
volume and centroid agree to a few units in the last place, not bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from gridlib import compute_geometry
from gridlib.cornerpoint import faces
from gridlib.cornerpoint.corners import corner_nodes
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.grdecl import read_grdecl
from gridlib.transmissibility import deck_transmissibility


def _deck_text(seed: int, throw: bool) -> str:
    """A 7 x 5 x 6 DX/DY/DZ/TOPS deck with ACTNUM 0 and PORO 0 cells scattered through it;
    with ``throw``, the columns i >= 4 are 1.5 deeper (a fault along one pillar line)."""
    nx, ny, nz = 7, 5, 6
    n = nx * ny * nz
    rng = np.random.default_rng(seed)
    poro = np.round(0.05 + 0.3 * rng.random(n), 4)
    poro[rng.random(n) < 0.2] = 0.0
    actnum = (rng.random(n) > 0.1).astype(int)
    dx = np.tile(np.round(5 + 10 * rng.random(nx * ny), 2), nz)
    dz = np.repeat(np.round(1 + rng.random(nz), 3), nx * ny)  # layers of one thickness each
    tops = np.full((ny, nx), 1000.0)
    if throw:
        tops[:, 4:] += 1.5
    rows = {
        "DX": dx,
        "DZ": dz,
        "TOPS": tops.ravel(),
        "ACTNUM": actnum,
        "PORO": poro,
        "PERMX": np.round(10 ** rng.normal(2, 0.5, n), 3),
    }
    text = f"DIMENS\n {nx} {ny} {nz} /\nMETRIC\nDY\n {n}*10 /\n"
    return text + "".join(f"{k}\n{' '.join(map(str, v))} /\n" for k, v in rows.items())


def _results(deck):
    cp = process_grdecl(deck)
    geo = compute_geometry(cp.grid)
    conn = deck_transmissibility(deck, cp)
    glob = cp.grid.cells.index_map
    nb = cp.grid.faces.neighbors
    owner = np.where(nb >= 0, glob[np.maximum(nb, 0)], -1)
    face_rows = np.column_stack([owner, geo.face_areas, geo.face_centroids, geo.face_normals])
    face_rows = face_rows[np.lexsort(face_rows.T[::-1])]  # the faces as a set
    order = np.lexsort(conn.global_cells.T[::-1])
    return {
        "cells": glob,
        "volumes": geo.cell_volumes,
        "centroids": geo.cell_centroids,
        "bulk": cp.bulk_volumes,
        "faces": face_rows,
        "nnc": cp.nnc.global_cells,
        "pairs": conn.global_cells[order],
        "trans": conn.trans[order],
        "kind": conn.kind[order],
    }


def _general_pairs(deck) -> int:
    cn = corner_nodes(deck)
    return sum(faces.structured_lateral(cn.table, cn.cells, j, 0).side_cells.pair.size for j in (False, True))


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("throw", [False, True])
def test_inactive_neighbours_are_quads_bit_for_bit(tmp_path, monkeypatch, seed, throw):
    path = tmp_path / "box.grdecl"
    path.write_text(_deck_text(seed, throw))
    deck = read_grdecl(path)
    fast = _results(deck)
    fast_general = _general_pairs(deck)
    monkeypatch.setattr(faces, "_alone", lambda ex, *_: np.zeros_like(ex))  # the engine for them all
    engine = _results(deck)
    engine_general = _general_pairs(deck)

    for name, value in fast.items():
        if name in ("volumes", "centroids"):  # the same faces summed in another order
            np.testing.assert_array_max_ulp(value, engine[name], maxulp=4)
        else:
            np.testing.assert_array_equal(value, engine[name], err_msg=name, strict=True)
    assert engine_general > 0
    if throw:  # only the cells next to the fault's pillar line go to the engine
        assert 0 < fast_general < engine_general
    else:
        assert fast_general == 0
    assert fast["trans"].size > 200 and (fast["trans"] > 0).all()
