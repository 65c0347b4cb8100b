"""The cells of a clipped Voronoi diagram: each cell's faces ordered into one closed cycle.

Every face is split into two half-edges, one per cell, oriented so that the cell lies on
its left; each half-edge is followed by the one of the same cell that starts where it ends
(where several do, at a vertex the cell passes twice, the first clockwise from the reversed
incoming half-edge, which keeps each piece on the left).
A cell whose half-edges close into more than one cycle was cut into pieces by a concave
boundary: the extra pieces are reported (a site mirrored across the boundary edge that cuts
a piece off, or a point inside the piece) so that the caller adds a site for each. The
faces of every cell are then listed in cycle order, starting at its first face.
"""

from __future__ import annotations

import numpy as np
import shapely
from scipy import sparse
from scipy.sparse import csgraph

from ..connectivity import cycle_rank, offsets
from ..errors import GridError
from ..planar import cross2
from ..reproducible import arctan2
from .domain import Domain


def cell_cycles(coords, faces, neighbors, n, sites, domain: Domain):
    """Each cell's faces in counter-clockwise cycle order, its area, and extra pieces."""
    nf = faces.shape[0]
    inner = neighbors[:, 1] >= 0
    hc = np.concatenate([neighbors[:, 0], neighbors[inner, 1]])
    hf = np.concatenate([np.arange(nf), np.flatnonzero(inner)])
    ha = np.concatenate([faces[:, 0], faces[inner, 1]])
    hb = np.concatenate([faces[:, 1], faces[inner, 0]])
    order = np.argsort(hc, kind="stable")
    hc, hf, ha, hb = hc[order], hf[order], ha[order], hb[order]
    count = np.bincount(hc, minlength=n)
    if np.any(count < 3):
        c = int(np.flatnonzero(count < 3)[0])
        raise GridError(
            f"pebi_grid: the cell of site {c} at {domain.fmt(sites[c])} has {count[c]} faces "
            "(sites closer than the merge tolerance?)"
        )
    pos = offsets(count)
    nn = coords.shape[0]
    succ = _successors(hc, ha, hb, nn, coords, sites, domain)
    nh = hc.size
    graph = sparse.coo_matrix((np.ones(nh), (np.arange(nh), succ)), shape=(nh, nh))
    _, cyc = csgraph.connected_components(graph, directed=True, connection="weak")
    pair = np.unique(hc.astype(np.int64) * (nh + 1) + cyc)
    cycles_per_cell = np.bincount(pair // (nh + 1), minlength=n)
    area_h = 0.5 * cross2(coords[ha], coords[hb])
    if np.any(cycles_per_cell > 1):
        extra = _extra_pieces(np.flatnonzero(cycles_per_cell > 1), hc, ha, cyc, succ, coords, sites, domain)
        return pos, hf, np.bincount(hc, area_h, n), extra
    rank = cycle_rank(succ, pos, hc)
    cell_faces = np.empty(nh, dtype=np.int64)
    cell_faces[pos[hc] + rank] = hf
    areas = np.bincount(hc, area_h, n)
    if np.any(areas <= 0):
        c = int(np.flatnonzero(areas <= 0)[0])
        raise GridError(f"pebi_grid: the cell of site {c} at {domain.fmt(sites[c])} has area {areas[c]:.3g}")
    return pos, cell_faces, areas, np.zeros((0, 2))


def _successors(hc, ha, hb, nn, coords, sites, domain: Domain) -> np.ndarray:
    """The half-edge of the same cell that starts where each half-edge ends.

    Where a cell passes twice through a node (two pieces of a region touching),
    the successor is the first of its outgoing half-edges clockwise from the
    reversed incoming one: that keeps each piece on the left.
    """
    key_start = hc * nn + ha
    order = np.argsort(key_start, kind="stable")
    sorted_keys = key_start[order]
    key_end = hc * nn + hb
    lo = np.searchsorted(sorted_keys, key_end, side="left")
    hi = np.searchsorted(sorted_keys, key_end, side="right")
    cnt = hi - lo
    if np.any(cnt == 0):
        h = int(np.flatnonzero(cnt == 0)[0])
        c = int(hc[h])
        raise GridError(
            f"pebi_grid: the faces of the cell of site {c} at {domain.fmt(sites[c])} do not close "
            f"(open at {domain.fmt(coords[hb[h]])})"
        )
    succ = order[np.minimum(lo, sorted_keys.size - 1)]
    amb = np.flatnonzero(cnt > 1)
    if amb.size:
        k = cnt[amb]
        h_in = np.repeat(amb, k)
        cand = order[np.repeat(lo[amb], k) + (np.arange(k.sum()) - np.repeat(np.cumsum(k) - k, k))]
        v = coords[hb[h_in]]
        back = coords[ha[h_in]] - v
        out = coords[hb[cand]] - v
        ang_back = arctan2(back[:, 1], back[:, 0])
        ang_out = arctan2(out[:, 1], out[:, 0])
        cw = np.mod(ang_back - ang_out, 2 * np.pi)
        cw = np.where(cw <= 0, 2 * np.pi, cw)
        o = np.lexsort((cw, h_in))
        first = np.concatenate([[True], h_in[o][1:] != h_in[o][:-1]])
        succ[h_in[o][first]] = cand[o][first]
    if np.bincount(succ, minlength=hc.size).max() > 1:
        h = int(np.argmax(np.bincount(succ, minlength=hc.size)))
        c = int(hc[h])
        raise GridError(f"pebi_grid: the faces of the cell of site {c} at {domain.fmt(sites[c])} cross")
    return succ


def _extra_pieces(cells, hc, ha, cyc, succ, coords, sites, domain: Domain) -> np.ndarray:
    """A new site for every piece of a split region other than the one holding its site.

    A region splits where it reaches around a re-entrant corner, across the outside. The
    new site is the region's site mirrored across the line of a boundary edge that
    separates the piece from the site (then that line is the bisector of the two, and the
    new cell takes the cut-off side whole, as a cell as wide as the old one); failing that,
    a point inside the piece.
    """
    out = []
    for c in cells:  # a handful of cells cut in two by a concave boundary
        hs = np.flatnonzero(hc == c)
        polys = []
        for label in np.unique(cyc[hs]):
            start = hs[cyc[hs] == label][0]
            ring = [start]
            h = succ[start]
            while h != start:
                ring.append(h)
                h = succ[h]
            polys.append(shapely.Polygon(coords[ha[ring]]))
        site = shapely.Point(sites[c])
        dist = np.array([poly.distance(site) for poly in polys])
        main = int(np.argmin(dist))
        for i, poly in enumerate(polys):
            if i != main:
                out.append(_mirror_site(sites[c], poly, polys[main], domain))
    return np.asarray(out, dtype=np.float64).reshape(-1, 2)


def _mirror_site(site: np.ndarray, piece, main, domain: Domain) -> list[float]:
    """The site mirrored across a boundary edge's line that has the piece on its far side and the
    main piece on the near side (the candidate nearest to the piece); else a point in the piece."""
    a, u = domain.edge_a, domain.edge_unit
    n = np.column_stack([-u[:, 1], u[:, 0]])
    off = (site[0] - a[:, 0]) * n[:, 0] + (site[1] - a[:, 1]) * n[:, 1]  # signed distance to each line
    mirror = site[None, :] - 2.0 * off[:, None] * n
    piece_xy = np.asarray(piece.exterior.coords)
    main_xy = np.asarray(main.exterior.coords)
    best, pick = np.inf, None
    for e in np.flatnonzero(np.abs(off) > domain.tol).tolist():  # the boundary edges (a few)
        far = -np.sign(off[e])
        side_piece = far * ((piece_xy[:, 0] - a[e, 0]) * n[e, 0] + (piece_xy[:, 1] - a[e, 1]) * n[e, 1])
        side_main = far * ((main_xy[:, 0] - a[e, 0]) * n[e, 0] + (main_xy[:, 1] - a[e, 1]) * n[e, 1])
        if side_piece.min() < -domain.tol or side_main.max() > domain.tol:
            continue
        if domain.inside(mirror[e][None, :])[0]:
            gap = piece.distance(shapely.Point(mirror[e]))
            if gap < best:
                best, pick = gap, mirror[e]
    if pick is None:
        rp = piece.point_on_surface()
        return [float(rp.x), float(rp.y)]
    return [float(pick[0]), float(pick[1])]
