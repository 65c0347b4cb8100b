"""Seeded property test of pebi_grid: random domains, faults (X, Y/T, free ends, through the
boundary) and wells; every case is checked against invariants computed independently with shapely."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from scipy.spatial import ConvexHull

import gridlib as gl
from gridlib.connectivity import cell_node_cycles_2d
from gridlib.voronoi import Fault, Rings, Well, pebi_grid

SCALE = 100.0  # m
H = SCALE / 12.5  # cell size: about 500 cells per case
# Sizes relative to each cell's target size h (PebiGrid.site_size: the lattice spacing, the fault
# step, the ring spacing). The smallest legitimate cells are fault cells in the wedges of junctions
# and where a fault meets the boundary at a shallow angle (here >= 45 and >= 35 degrees): about
# 0.15 h^2 and more, so 0.1 h^2 (a tenth of the target, a ninth of a regular hexagon's pore volume)
# catches slivers without flagging them. Faces shorter than 1 % of h are collapsed or contracted by
# the generator (gridlib.voronoi.degenerate): such a face carries under 1 % of a normal face's
# transmissibility, and below that length faces are artefacts of nearly co-circular sites.
MIN_AREA = 0.1  # x h^2
MIN_FACE = 0.01  # x h


def _domain(rng) -> np.ndarray:
    if rng.random() < 0.5:  # convex
        pts = rng.uniform(-1, 1, (14, 2)) * [1.3, 1.0]
        poly = pts[ConvexHull(pts).vertices]
    else:  # star-shaped, not convex
        m = int(rng.integers(7, 12))
        th = (np.arange(m) + rng.uniform(-0.3, 0.3, m)) * 2 * np.pi / m
        r = rng.uniform(0.6, 1.0, m)
        poly = np.column_stack([1.3 * r * np.cos(th), r * np.sin(th)])
    if rng.random() < 0.5:
        poly = poly[::-1]
    return poly * SCALE


def _angle(u, v) -> float:
    c = abs(float(np.dot(u, v))) / (np.linalg.norm(u) * np.linalg.norm(v))
    return float(np.degrees(np.arccos(min(1.0, c))))


def _crossing_angles_ok(a: np.ndarray, b: np.ndarray, min_deg: float) -> bool:
    """Every crossing of polylines a and b at an angle of at least min_deg."""
    for i in range(len(a) - 1):
        for j in range(len(b) - 1):
            s1 = shapely.LineString(a[i : i + 2])
            s2 = shapely.LineString(b[j : j + 2])
            if s1.intersects(s2) and _angle(a[i + 1] - a[i], b[j + 1] - b[j]) < min_deg:
                return False
    return True


def _acceptable(pts: np.ndarray, kind: str, out: list[np.ndarray], poly: np.ndarray) -> bool:
    """Whether a new trace keeps its features apart from everything else (see the checks)."""
    dom = shapely.Polygon(poly)
    line = shapely.LineString(pts)
    clipped = line.intersection(dom)
    if clipped.is_empty or clipped.geom_type != "LineString" or clipped.length < 3 * H:
        return False
    # free ends: far from the boundary and from other faults
    free = [p for p in (pts[0], pts[-1]) if dom.contains(shapely.Point(p))]
    if kind in ("T", "Y"):
        free = [pts[-1]]
    for p in free:
        if dom.exterior.distance(shapely.Point(p)) < 2 * H:
            return False
        if any(shapely.LineString(o).distance(shapely.Point(p)) < 2 * H for o in out):
            return False
    # where it meets the boundary: not at a shallow angle, away from corners
    seg = np.asarray(clipped.coords)
    for q, dseg in ((seg[0], seg[1] - seg[0]), (seg[-1], seg[-1] - seg[-2])):
        if dom.exterior.distance(shapely.Point(q)) < 1e-9 * SCALE:
            if np.linalg.norm(poly - q, axis=1).min() < 1.5 * H:
                return False
            edges = [shapely.LineString([a, b]) for a, b in zip(poly, np.roll(poly, -1, 0), strict=True)]
            k = int(np.argmin([e.distance(shapely.Point(q)) for e in edges]))
            if _angle(np.roll(poly, -1, 0)[k] - poly[k], dseg) < 35:
                return False
    # other faults: cross at >= 45 degrees or stay 2 cells away; crossings apart from everything else
    crossings = []
    for o in out:
        lo = shapely.LineString(o)
        inter = line.intersection(lo)
        if inter.is_empty:
            if line.distance(lo) < 2 * H:
                return False
            continue
        if inter.geom_type not in ("Point", "MultiPoint") or not _crossing_angles_ok(pts, o, 45):
            return False
        for g in getattr(inter, "geoms", [inter]):
            ip = np.array(g.coords[0])
            if dom.exterior.distance(shapely.Point(ip)) < 2 * H:
                return False
            for trace in (pts, o):  # away from bends and ends (unless it is one)
                dv = np.linalg.norm(trace - ip, axis=1)
                if np.any((dv > 1e-9 * SCALE) & (dv < 2 * H)):
                    return False
            crossings.append(ip)
    for o in out:  # existing crossings on other traces must stay apart from the new ones
        for o2 in out:
            if o2 is o:
                continue
            inter = shapely.LineString(o).intersection(shapely.LineString(o2))
            for g in getattr(inter, "geoms", [inter]) if not inter.is_empty else []:
                q = np.array(g.coords[0])
                for ip in crossings:
                    d = np.linalg.norm(q - ip)
                    if 1e-9 * SCALE < d < 2 * H:
                        return False
    return True


def _faults(rng, poly: np.ndarray):
    """Up to four fault features with well separated crossings; returns traces and their kinds."""
    dom = shapely.Polygon(poly)
    inner = dom.buffer(-2 * H)
    out: list[np.ndarray] = []
    kinds: list[str] = []
    for _ in range(int(rng.integers(1, 5))):
        for _attempt in range(30):
            kind = str(rng.choice(["through", "inner", "T", "X", "Y"] if out else ["through", "inner", "Y"]))
            ang = rng.uniform(0, 2 * np.pi)
            d = np.array([np.cos(ang), np.sin(ang)])
            new: list[np.ndarray] = []
            if kind in ("T", "X"):
                host = out[int(rng.integers(len(out)))]
                k = int(rng.integers(len(host) - 1))
                t = rng.uniform(0.25, 0.75)
                p0 = host[k] + t * (host[k + 1] - host[k])  # exactly on the host trace
                if _angle(d, host[k + 1] - host[k]) < 50:
                    continue
                if kind == "T":
                    new = [np.array([p0, p0 + rng.uniform(3, 6) * H * d])]
                else:
                    new = [np.array([p0 - rng.uniform(3, 5) * H * d, p0 + rng.uniform(3, 5) * H * d])]
            else:
                c = poly.mean(axis=0) + rng.uniform(-0.4, 0.4, 2) * SCALE
                if not inner.contains(shapely.Point(c)):
                    continue
                if kind == "Y":  # three (or two: a V) faults starting at one point
                    arms = 3 if rng.random() < 0.7 else 2
                    angs = (
                        ang + np.radians([0.0, 120 + rng.uniform(-15, 15), 240 + rng.uniform(-15, 15)])[:arms]
                    )
                    for a in angs:
                        e = np.array([np.cos(a), np.sin(a)])
                        new.append(np.array([c, c + rng.uniform(3, 5) * H * e]))
                else:
                    half = 3 * SCALE if kind == "through" else rng.uniform(2.5, 4) * H
                    pts = np.array([c - half * d, c + half * d])
                    if rng.random() < 0.5:  # a bend of up to 45 degrees in the middle
                        turn = np.radians(rng.uniform(-45, 45))
                        rot = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
                        pts = np.array([pts[0], c, c + rot @ (pts[1] - c)])
                    new = [pts]
            trial = list(out)
            ok = True
            for pts in new:
                if not _acceptable(pts, kind, trial, poly):
                    ok = False
                    break
                trial.append(pts)
            if ok:
                out = trial
                kinds += [kind] * len(new)
                break
    return out, kinds


def _wells(rng, poly, faults):
    dom = shapely.Polygon(poly)
    lines = [shapely.LineString(f) for f in faults]
    wells: list[Well] = []
    placed: list[shapely.Geometry] = []
    for k in range(int(rng.integers(0, 3))):
        for _attempt in range(30):
            c = poly.mean(axis=0) + rng.uniform(-0.6, 0.6, 2) * SCALE
            if k == 1 and rng.random() < 0.5:  # a path
                d = rng.normal(size=2)
                d /= np.linalg.norm(d)
                path = np.array([c, c + 2.5 * H * d, c + 2.5 * H * d + 2 * H * np.array([-d[1], d[0]])])
                geom = shapely.LineString(path)
                clear = 3 * H
                well = Well(path=path)
            else:
                r_out = 1.5 * H
                geom = shapely.Point(c).buffer(r_out)
                clear = 2 * H
                well = Well(c, rings=Rings(inner=0.1 * H, outer=r_out))
            if not dom.buffer(-H).contains(geom):
                continue
            if any(geom.distance(line) < clear for line in lines):
                continue
            if any(geom.distance(p) < 3 * H for p in placed):
                continue
            wells.append(well)
            placed.append(geom)
            break
    return wells


def _case(seed: int):
    rng = np.random.default_rng(seed)
    poly = _domain(rng)
    faults, kinds = _faults(rng, poly)
    wells = _wells(rng, poly, faults)
    pattern = "cartesian" if rng.random() < 0.3 else "hexagonal"
    offset = np.array([5.3e5, 6.7e6]) if seed % 4 == 3 else rng.uniform(-50, 50, 2)
    return poly, faults, kinds, wells, pattern, offset


def _shift(wells, offset):
    out = []
    for w in wells:
        if w.point is not None:
            out.append(Well(np.asarray(w.point) + offset, rings=w.rings))
        else:
            out.append(Well(path=np.asarray(w.path) + offset))
    return out


def _check(seed: int) -> dict:
    poly, faults, kinds, wells, pattern, offset = _case(seed)
    pg = pebi_grid(
        poly + offset, H, [Fault(f + offset) for f in faults], _shift(wells, offset), pattern=pattern
    )
    g = pg.grid
    geo = gl.compute_geometry(g)
    gl.check_grid(g, geo)
    dom = shapely.Polygon(poly)  # local frame: exact reference values
    xy = g.nodes.coords - offset
    assert geo.cell_volumes.sum() == pytest.approx(dom.area, rel=1e-10)
    e = g.faces.nodes.reshape(-1, 2)
    length = np.linalg.norm(xy[e[:, 1]] - xy[e[:, 0]], axis=1)
    pos, cyc = cell_node_cycles_2d(g)
    for k, f in enumerate(faults):
        tagged = np.flatnonzero(g.faces.tag == k + 1)
        trace = shapely.LineString(f).intersection(dom)
        assert length[tagged].sum() == pytest.approx(trace.length, rel=1e-9), (seed, k)
        nodes = np.unique(e[tagged])
        dist = shapely.distance(shapely.points(xy[nodes]), trace)
        assert dist.max() <= 1e-9 * SCALE, (seed, k)
        # no cell touching a segment of the trace has vertices strictly on both of its sides
        seg = np.stack([f[:-1], f[1:]], axis=1)
        mid = 0.5 * (xy[e[tagged, 0]] + xy[e[tagged, 1]])
        rel = mid[:, None, :] - seg[None, :, 0, :]
        dvec = seg[None, :, 1, :] - seg[None, :, 0, :]
        tt = np.clip((rel * dvec).sum(axis=2) / (dvec * dvec).sum(axis=2), 0, 1)
        which = np.argmin(np.linalg.norm(rel - tt[..., None] * dvec, axis=2), axis=1)
        for side in (0, 1):
            cell = g.faces.neighbors[tagged, side]
            n_of = np.diff(pos)[cell]
            start = np.repeat(pos[cell] - (np.cumsum(n_of) - n_of), n_of)
            vert = xy[cyc[start + np.arange(n_of.sum())]]
            a = np.repeat(seg[which, 0], n_of, axis=0)
            u = np.repeat(seg[which, 1] - seg[which, 0], n_of, axis=0)
            u /= np.linalg.norm(u, axis=1, keepdims=True)
            sd = u[:, 0] * (vert - a)[:, 1] - u[:, 1] * (vert - a)[:, 0]
            face = np.repeat(np.arange(cell.size), n_of)
            mx = np.full(cell.size, -np.inf)
            mn = np.full(cell.size, np.inf)
            np.maximum.at(mx, face, sd)
            np.minimum.at(mn, face, sd)
            assert not np.any((mx > 1e-9 * SCALE) & (mn < -1e-9 * SCALE)), (seed, k)
    # each well's point (each path vertex) lies in a cell of that well
    polys = [shapely.Polygon(xy[cyc[pos[c] : pos[c + 1]]]) for c in range(g.num_cells)]
    for w_id, w in enumerate(wells, start=1):
        pts = [np.asarray(w.point)] if w.point is not None else list(np.asarray(w.path))
        cells = np.flatnonzero(pg.cell_well == w_id)
        assert cells.size > 0
        for p in pts:
            assert any(polys[c].buffer(1e-9 * SCALE).contains(shapely.Point(p)) for c in cells), (seed, w_id)
    # every site lies in its own cell; interior faces are perpendicular to their site pairs: exactly,
    # except at the few faces next to one contracted because no background site could be moved to
    # collapse it (within a degree: the contracted faces are shorter than 1 % of the cell size)
    sites = pg.sites - offset
    inside = [polys[c].buffer(1e-9 * SCALE).contains(shapely.Point(sites[c])) for c in range(g.num_cells)]
    assert all(inside), seed
    inner = np.flatnonzero((g.faces.neighbors >= 0).all(axis=1))
    t = xy[e[inner, 1]] - xy[e[inner, 0]]
    s = sites[g.faces.neighbors[inner, 1]] - sites[g.faces.neighbors[inner, 0]]
    cosang = np.abs((t * s).sum(axis=1)) / (np.linalg.norm(t, axis=1) * np.linalg.norm(s, axis=1))
    contracted = sum(int(n.split()[0]) for n in pg.notes if "contracted" in n)
    assert np.degrees(np.arcsin(min(cosang.max(), 1.0))) < 1.0, seed
    assert (cosang > 1e-5).sum() <= 8 * contracted, seed
    # no slivers and no tiny faces, relative to the target size of the cells
    size = pg.site_size
    assert np.all(size > 0) and size.shape == (g.num_cells,)
    area_ratio = geo.cell_volumes / size**2
    nb = g.faces.neighbors
    h_face = np.minimum(size[nb[:, 0]], np.where(nb[:, 1] >= 0, size[np.maximum(nb[:, 1], 0)], np.inf))
    face_ratio = length / h_face
    assert area_ratio.min() >= MIN_AREA, (seed, area_ratio.min(), pg.site_kind[np.argmin(area_ratio)])
    assert face_ratio.min() >= MIN_FACE, (seed, face_ratio.min())
    return {
        "kinds": kinds,
        "wells": len(wells),
        "cells": g.num_cells,
        "area_ratio": float(area_ratio.min()),
        "face_ratio": float(face_ratio.min()),
    }


def test_random_domains_faults_and_wells():
    """60 seeded cases: X, T, Y (and V), free ends and through-going faults, ring and path wells, convex and
    star-shaped domains, hexagonal and Cartesian lattices, some at UTM coordinates."""
    seen: dict[str, int] = {}
    wells = 0
    worst_area = worst_face = np.inf
    for seed in range(60):
        info = _check(seed)
        for k in info["kinds"]:
            seen[k] = seen.get(k, 0) + 1
        wells += info["wells"]
        worst_area = min(worst_area, info["area_ratio"])
        worst_face = min(worst_face, info["face_ratio"])
    # the generator covered every feature
    assert all(seen.get(k, 0) >= 5 for k in ("through", "inner", "T", "X", "Y")), seen
    assert wells >= 20
    # the bounds are not vacuous: junction cells and short faces come close to them
    assert worst_area < 3 * MIN_AREA and worst_face < 3 * MIN_FACE, (worst_area, worst_face)
