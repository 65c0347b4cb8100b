"""The invariants every PEBI grid built by ``pebi_grid`` keeps, checked on a seeded layout.

Shared by the property tests: a valid grid (``check_grid``), areas adding up to the domain's
(1e-10), fault faces exactly on the honoured traces (``PebiGrid.fault_traces``: the input
clipped to the domain, plus any extension or merge a note names; 1e-9 h), wells owning their
cells and a vertical well's point in one of them, faces perpendicular bisectors of their sites
(except next to contracted faces), and cells of at least 0.1 h^2 and faces of at least 0.01 h
(h = ``PebiGrid.site_size``) except those a note counts.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
import shapely

import gridlib as gl
from gridlib.connectivity import cell_node_cycles_2d

MIN_AREA = 0.1  # x h^2, as tests/voronoi/test_pebi_grid_property.py
MIN_FACE = 0.01  # x h


def _count(notes: tuple[str, ...], pattern: str) -> int:
    got = [int(m.group(1)) for n in notes if (m := re.match(pattern, n))]
    return got[0] if got else 0


def _named(notes: tuple[str, ...], label: str, *words: str) -> bool:
    return any(label in n and any(w in n for w in words) for n in notes)


def build_layout(case: dict, h: float) -> gl.voronoi.PebiGrid:
    """The PEBI grid of a seeded layout: ``case``'s ``domain``, ``faults``, ``wells`` (none if
    absent) and lattice ``pattern`` (hexagonal if absent), cell size ``h`` (m)."""
    return gl.voronoi.pebi_grid(
        case["domain"], h, case["faults"], case.get("wells", ()), pattern=case.get("pattern", "hexagonal")
    )


def check_pebi(case: dict, pg: gl.voronoi.PebiGrid, seed: object = None, h: float = 10.0) -> dict:
    """Check every invariant of ``pg``, built from ``case`` (``domain``, ``faults``, ``wells`` in
    metres, ``offset`` subtracted for exact figures); ``seed`` labels failures, ``h`` is the cell
    size. Returns the figures of a summary: cells, faults, wells, the smallest area and face
    ratios, whether at UTM coordinates, the notes."""
    g = pg.grid
    geo = gl.compute_geometry(g)
    gl.check_grid(g, geo)
    offset = case["offset"]
    dom = shapely.Polygon(case["domain"] - offset)  # the caller's frame less the offset: exact figures
    xy = g.nodes.coords - offset
    assert geo.cell_volumes.sum() == pytest.approx(dom.area, rel=1e-10), seed
    e = g.faces.nodes.reshape(-1, 2)
    length = np.hypot(*(xy[e[:, 1]] - xy[e[:, 0]]).T)
    tol = 1e-9 * h
    for k, f in enumerate(case["faults"]):
        label = f"fault 'F{k + 1}' (faults[{k}])"
        seg = pg.fault_traces[k] - offset
        honoured = shapely.MultiLineString(list(seg))
        tagged = np.flatnonzero(g.faces.tag == k + 1)
        # the faces of fault k cover its honoured trace exactly, and lie on it
        assert length[tagged].sum() == pytest.approx(honoured.length, rel=1e-9), (seed, k)
        on = shapely.distance(shapely.points(xy[np.unique(e[tagged])]), honoured)
        assert on.max(initial=0.0) <= tol, (seed, k, on.max())
        mid = 0.5 * (xy[e[tagged, 0]] + xy[e[tagged, 1]])
        assert shapely.distance(shapely.points(mid), honoured).max(initial=0.0) <= tol, (seed, k)
        # the honoured trace is the input inside the domain, except where a note says otherwise
        given = shapely.LineString(f.points - offset).intersection(dom)
        extra = honoured.difference(given.buffer(1e-7 * h)).length
        missing = given.difference(honoured.buffer(1e-7 * h)).length
        if extra > 1e-6 * h:
            assert _named(pg.notes, label, "extended", "joined"), (seed, k, extra, pg.notes)
        if missing > 1e-6 * h:
            assert _named(pg.notes, label, "joined"), (seed, k, missing, pg.notes)
    # wells own their cells; a vertical well's point lies in one of them; changed rings are noted
    pos, cyc = cell_node_cycles_2d(g)
    for w_id, w in enumerate(case["wells"], start=1):
        cells = np.flatnonzero(pg.cell_well == w_id)
        assert cells.size > 0, (seed, w_id)
        if w.point is None:
            continue
        p = shapely.Point(np.asarray(w.point) - offset)
        assert any(shapely.Polygon(xy[cyc[pos[c] : pos[c + 1]]]).buffer(tol).contains(p) for c in cells), seed
        if w.rings is not None:
            sectors = max(6, round(2 * np.pi * w.rings.outer / h))
            if cells.size != 1 + sectors * w.rings.radii(sectors).size:
                assert _named(pg.notes, f"well 'W{w_id}' (wells[{w_id - 1}])", "rings"), (seed, pg.notes)
    # faces are the perpendicular bisectors of their sites (exactly, except next to contracted faces)
    sites = pg.sites - offset
    inner = np.flatnonzero((g.faces.neighbors >= 0).all(axis=1))
    t = xy[e[inner, 1]] - xy[e[inner, 0]]
    s = sites[g.faces.neighbors[inner, 1]] - sites[g.faces.neighbors[inner, 0]]
    cosang = np.abs((t * s).sum(axis=1)) / (np.hypot(*t.T) * np.hypot(*s.T))
    contracted = sum(int(n.split()[0]) for n in pg.notes if "contracted" in n)
    assert (cosang > 1e-5).sum() <= 8 * contracted, seed
    # sizes relative to each cell's target size
    size = pg.site_size
    nb = g.faces.neighbors
    h_face = np.minimum(size[nb[:, 0]], np.where(nb[:, 1] >= 0, size[np.maximum(nb[:, 1], 0)], np.inf))
    area_ratio = float((geo.cell_volumes / size**2).min())
    face_ratio = float((length / h_face).min())
    # the cells and faces below the bounds are exactly those the notes count
    small = int((geo.cell_volumes / size**2 < MIN_AREA).sum())
    short = int((length / h_face < MIN_FACE).sum())
    assert _count(pg.notes, r"(\d+) cell\(s\) smaller than 0\.1 h\^2") == small, (seed, pg.notes)
    assert _count(pg.notes, r"(\d+) face\(s\) shorter than 0\.01 h") == short, (seed, pg.notes)
    return {
        "cells": g.num_cells,
        "faults": len(case["faults"]),
        "wells": len(case["wells"]),
        "area_ratio": area_ratio,
        "face_ratio": face_ratio,
        "utm": bool(np.abs(offset).max() > 1e5),
        "notes": pg.notes,
    }
