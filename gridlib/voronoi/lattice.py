"""Voronoi ridges of a site set that is mostly a regular lattice, with Qhull only where it is not.

Sites of an undisturbed hexagonal (triangular) or square lattice have known
Voronoi cells. A lattice *cell* (a triangle of three neighbouring sites, or a
square of four) is *clean* when all its corners are sites and no other site lies
within its circumcircle (with a relative margin of 1e-6): it is then a Delaunay
triangle (a Delaunay square of four co-circular sites) of the whole set, and its
centre a Voronoi vertex. A lattice site all of whose cells are clean is
*regular*: its Voronoi cell is the regular hexagon (square) around it, and its
ridges join the centres of its cells.

Everything else (sites of faults, wells, padding, finer levels, and lattice
sites next to a gap) is *irregular*. Qhull triangulates the irregular sites plus
the regular sites next to them; triangles with an irregular corner are checked
against all other sites (no site strictly inside their circumcircle) and the
offending sites are added until the check passes, so the ridges taken from that
triangulation (those with an irregular end) are exact. Qhull triangles that are
clean lattice cells are identified with them, so both kinds of ridges share
their vertices. The result equals the Delaunay-based diagram of all sites
(up to the choice of diagonal in co-circular quadruples, which only changes
zero-length ridges); only about the irregular sites' share of the work is done
by Qhull.

>>> from gridlib.voronoi.domain import Domain, rectangle
>>> d = Domain(rectangle(0, 0, 8, 8))
>>> ij = np.array([(i, j) for j in range(8) for i in range(8)])
>>> lat = Lattice("cartesian", d.to_local([0.5, 0.5]), 1.0, ij)
>>> r = hybrid_ridges(d.to_local(0.5 + ij.astype(float)), d, lat)
>>> real = r.lengths() > 1e-9  # co-circular diagonals have length 0
>>> p, q = r.cp[real], r.cq[real]
>>> int(real.sum()), bool(np.all(np.abs(ij[p] - ij[q]).sum(axis=1) == 1))  # the 112 lattice edges
(112, True)
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from scipy.spatial import Delaunay, QhullError, cKDTree

from ..errors import GridError
from ..planar import circumcentres, cross2, merge_close_points
from .domain import Domain
from .ridges import Ridges

SQRT3 = np.sqrt(3.0)


@dataclass(frozen=True, eq=False)
class Lattice:
    """The lattice of the first ``ij.shape[0]`` sites: site k = origin + h (basis @ ij[k]).

    ``active`` (n_lattice,) bool, default all: sites that are *not* active have been moved
    off their lattice position (they are treated like any other irregular site).
    """

    pattern: str  # "hexagonal" | "cartesian"
    origin: np.ndarray
    h: float
    ij: np.ndarray  # (n_lattice, 2) int64
    active: np.ndarray | None = None


def triangulate(pts: np.ndarray, domain: Domain) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Counter-clockwise Delaunay triangles, their neighbours (opposite each corner) and circumcentres."""
    try:
        dl = Delaunay(pts)
    except QhullError as exc:  # pragma: no cover - the frame makes this impossible
        raise GridError(f"pebi_grid: Qhull failed on {pts.shape[0]} points ({exc})") from exc
    if dl.coplanar.size:
        i, j = int(dl.coplanar[0, 0]), int(dl.coplanar[0, 2])
        raise GridError(
            f"pebi_grid: two generating points coincide at {domain.fmt(pts[i])} (points {i} and {j})"
        )
    tri = dl.simplices.astype(np.int64)
    nbr = dl.neighbors.astype(np.int64)
    orient = cross2(pts[tri[:, 1]] - pts[tri[:, 0]], pts[tri[:, 2]] - pts[tri[:, 0]])
    flip = orient < 0
    if flip.any():
        tri[flip] = tri[flip][:, [0, 2, 1]]
        nbr[flip] = nbr[flip][:, [0, 2, 1]]
    centre = circumcentres(pts, tri)
    if not np.isfinite(centre).all():
        t = int(np.flatnonzero(~np.isfinite(centre).all(axis=1))[0])
        raise GridError(f"pebi_grid: points {tri[t].tolist()} are collinear in a Delaunay triangle")
    return tri, nbr, centre


def edges_of(tri: np.ndarray, nbr: np.ndarray):
    """Every interior edge once: (triangle on the left of p -> q, triangle on the right, p, q)."""
    nt = tri.shape[0]
    t_id = np.repeat(np.arange(nt), 3)
    p = tri[:, [1, 2, 0]].ravel()
    q = tri[:, [2, 0, 1]].ravel()
    u = nbr.ravel()
    keep = u > t_id
    return t_id[keep], u[keep], p[keep], q[keep]


def frame_points(domain: Domain) -> np.ndarray:
    """Eight points ten diameters away: every site's region becomes bounded, none of theirs reaches in."""
    theta = np.arange(8) * (np.pi / 4) + np.pi / 8
    return 10.0 * domain.diameter * np.column_stack([np.cos(theta), np.sin(theta)])


def plain_ridges(sites: np.ndarray, domain: Domain) -> Ridges:
    """The ridges of the sites' Voronoi diagram from one Delaunay triangulation of all sites."""
    n = sites.shape[0]
    pts = np.concatenate([sites, frame_points(domain)])
    tri, nbr, centre = triangulate(pts, domain)
    t, u, p, q = edges_of(tri, nbr)
    real = (p < n) & (q < n)
    return Ridges(centre, u[real], t[real], p[real], q[real])


class _Cells:
    """Lattice cells (triangles U, D or squares S) over the box of the lattice's indices."""

    def __init__(self, lat: Lattice) -> None:
        ij = lat.ij
        self.lo = ij.min(axis=0) - 1
        self.shape = ij.max(axis=0) - self.lo + 2
        self.grid = np.full(tuple(self.shape), -1, dtype=np.int64)
        ids = np.arange(ij.shape[0]) if lat.active is None else np.flatnonzero(lat.active)
        self.grid[ij[ids, 0] - self.lo[0], ij[ids, 1] - self.lo[1]] = ids
        self.hex = lat.pattern == "hexagonal"
        self.types = 2 if self.hex else 1
        self.n = int(self.shape[0] * self.shape[1] * self.types)
        self.lat = lat
        # corners (in index offsets) of each cell type, anchored at (a, b)
        if self.hex:
            self.corners = [np.array([[0, 0], [1, 0], [0, 1]]), np.array([[1, 0], [1, 1], [0, 1]])]
            self.offset = [np.array([0.5, SQRT3 / 6]), np.array([1.0, SQRT3 / 3])]
            self.radius = lat.h / SQRT3
            # cells around a site: (type, da, db) with anchor = site + (da, db)
            self.around = [(0, 0, 0), (0, -1, 0), (0, 0, -1), (1, -1, 0), (1, -1, -1), (1, 0, -1)]
            # lattice edges from a site: (offset of the other end, the two cells on either side)
            self.edge_types = [
                ((1, 0), (0, 0, 0), (1, 0, -1)),
                ((0, 1), (0, 0, 0), (1, -1, 0)),
                ((-1, 1), (0, -1, 0), (1, -1, 0)),
            ]
        else:
            self.corners = [np.array([[0, 0], [1, 0], [1, 1], [0, 1]])]
            self.offset = [np.array([0.5, 0.5])]
            self.radius = lat.h / np.sqrt(2.0)
            self.around = [(0, 0, 0), (0, -1, 0), (0, -1, -1), (0, 0, -1)]
            self.edge_types = [((1, 0), (0, 0, 0), (0, 0, -1)), ((0, 1), (0, 0, 0), (0, -1, 0))]

    def basis(self) -> np.ndarray:
        return np.array([[1.0, 0.0], [0.5, SQRT3 / 2]]) if self.hex else np.eye(2)

    def site_at(self, i: np.ndarray, j: np.ndarray) -> np.ndarray:
        a, b = i - self.lo[0], j - self.lo[1]
        ok = (a >= 0) & (a < self.shape[0]) & (b >= 0) & (b < self.shape[1])
        out = np.full(a.shape, -1, dtype=np.int64)
        out[ok] = self.grid[a[ok], b[ok]]
        return out

    def cell_id(self, typ: int | np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
        aa, bb = a - self.lo[0], b - self.lo[1]
        ok = (aa >= 0) & (aa < self.shape[0]) & (bb >= 0) & (bb < self.shape[1])
        return np.where(ok, (aa * self.shape[1] + bb) * self.types + typ, -1)

    def all_cells(self):
        aa, bb = np.meshgrid(np.arange(self.shape[0]), np.arange(self.shape[1]), indexing="ij")
        a = aa.ravel() + self.lo[0]
        b = bb.ravel() + self.lo[1]
        return a, b

    def centres(self, cid: np.ndarray) -> np.ndarray:
        typ = cid % self.types
        rest = cid // self.types
        a = rest // self.shape[1] + self.lo[0]
        b = rest % self.shape[1] + self.lo[1]
        off = np.asarray(self.offset)[typ]
        basis = self.basis()
        return self.lat.origin + self.lat.h * (a[:, None] * basis[0] + b[:, None] * basis[1] + off)

    def present(self) -> np.ndarray:
        a, b = self.all_cells()
        out = np.empty(self.n, dtype=bool)
        for typ in range(self.types):
            ok = np.ones(a.size, dtype=bool)
            for da, db in self.corners[typ]:
                ok &= self.site_at(a + da, b + db) >= 0
            out[typ :: self.types] = ok
        return out

    def near(self, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(point, cell) pairs of the cells whose circumcircle may contain the point.

        In index coordinates a cell's centre lies 1/3 or 2/3 (hexagonal) or 1/2 (square)
        past its anchor and a point inside its circumcircle at most 2/3 (0.71) from the
        centre, so the anchors lie within one step of the point's floored coordinates.
        """
        rel = (p - self.lat.origin) / self.lat.h
        b_f = rel[:, 1] / (SQRT3 / 2) if self.hex else rel[:, 1]
        a_f = rel[:, 0] - 0.5 * b_f if self.hex else rel[:, 0]
        a0, b0 = np.floor(a_f).astype(np.int64), np.floor(b_f).astype(np.int64)
        d = np.arange(-1, 2)
        da, db = np.meshgrid(d, d, indexing="ij")
        da, db = da.ravel(), db.ravel()
        pts = np.repeat(np.arange(p.shape[0]), da.size * self.types)
        a = (a0[:, None, None] + da[None, :, None]) + np.zeros((1, 1, self.types), dtype=np.int64)
        b = (b0[:, None, None] + db[None, :, None]) + np.zeros((1, 1, self.types), dtype=np.int64)
        typ = np.broadcast_to(np.arange(self.types)[None, None, :], a.shape)
        cells = self.cell_id(typ.ravel(), a.ravel(), b.ravel())
        ok = cells >= 0
        return pts[ok], cells[ok]


def hybrid_ridges(sites: np.ndarray, domain: Domain, lat: Lattice) -> Ridges:
    """As :func:`plain_ridges`, with Qhull only around the irregular sites (see the module docstring)."""
    cells = _Cells(lat)
    clean, regular, irregular, buffer = _irregular_sites(sites, lat, cells)
    i, j = lat.ij[:, 0], lat.ij[:, 1]
    if not irregular.any():
        irregular[0] = True  # pragma: no cover - a domain without boundary sites does not exist
    tree = None
    frame = frame_points(domain)
    for _ in range(20):  # grow the buffer until every triangle at an irregular site is Delaunay
        sub = np.flatnonzero(irregular | buffer)
        pts = np.concatenate([sites[sub], frame])
        tri, nbr, centre = triangulate(pts, domain)
        ns = sub.size
        glob = np.concatenate([sub, np.full(frame.shape[0], -1)])
        has_frame = (tri >= ns).any(axis=1)
        has_irr = (irregular[np.maximum(glob[tri], 0)] & (glob[tri] >= 0)).any(axis=1)
        check = np.flatnonzero(has_irr & ~has_frame)
        others = np.flatnonzero(~(irregular | buffer))
        if others.size == 0 or check.size == 0:
            break
        if tree is None or tree.n != others.size:
            tree = cKDTree(sites[others])
        rad = np.linalg.norm(centre[check] - pts[tri[check, 0]], axis=1) * (1 - 1e-9)
        hits = tree.query_ball_point(centre[check], rad, return_sorted=False)
        bad = np.unique(np.fromiter(itertools.chain.from_iterable(hits), dtype=np.int64))
        if bad.size == 0:
            break
        buffer[others[bad]] = True
    else:  # pragma: no cover
        raise GridError("pebi_grid: the Delaunay buffer around irregular sites does not converge")

    vid = _vertex_ids(cells, lat, clean, glob[tri])
    t, u, p, q = edges_of(tri, nbr)
    gp, gq = glob[p], glob[q]
    real = (gp >= 0) & (gq >= 0)
    take = real & (irregular[np.maximum(gp, 0)] | irregular[np.maximum(gq, 0)])
    va = [vid[u[take]]]
    vb = [vid[t[take]]]
    cp = [gp[take]]
    cq = [gq[take]]
    # Analytic ridges between regular sites.
    reg = np.flatnonzero(regular)
    ri, rj = i[reg], j[reg]
    for (bi, bj), (t1, d1a, d1b), (t2, d2a, d2b) in cells.edge_types:
        s1 = cells.site_at(ri + bi, rj + bj)
        ok = s1 >= 0
        ok[ok] &= ~irregular[s1[ok]]
        c1 = cells.cell_id(t1, ri[ok] + d1a, rj[ok] + d1b)
        c2 = cells.cell_id(t2, ri[ok] + d2a, rj[ok] + d2b)
        va.append(c2)
        vb.append(c1)
        cp.append(reg[ok])
        cq.append(s1[ok])
    va, vb = np.concatenate(va), np.concatenate(vb)
    used, inv = np.unique(np.concatenate([va, vb]), return_inverse=True)
    in_cells = used < cells.n
    coords = np.empty((used.size, 2))
    coords[in_cells] = cells.centres(used[in_cells])
    coords[~in_cells] = centre[used[~in_cells] - cells.n]
    inv = inv.reshape(-1)
    return Ridges(coords, inv[: va.size], inv[va.size :], np.concatenate(cp), np.concatenate(cq))


def _irregular_sites(sites: np.ndarray, lat: Lattice, cells: _Cells) -> tuple[np.ndarray, ...]:
    """Which lattice cells are clean (all corners present, no other site in their circle),
    which lattice sites are regular (all cells around them clean), which sites are irregular
    (the others and all sites off the lattice) and the buffer: regular lattice sites next to
    irregular ones."""
    n = sites.shape[0]
    nl = lat.ij.shape[0]
    clean = cells.present()
    foreign = sites[nl:] if lat.active is None else np.concatenate([sites[:nl][~lat.active], sites[nl:]])
    if foreign.shape[0]:
        pt, cid = cells.near(foreign)
        close = np.linalg.norm(cells.centres(cid) - foreign[pt], axis=1) < cells.radius * (1 + 1e-6)
        clean[cid[close]] = False
    i, j = lat.ij[:, 0], lat.ij[:, 1]
    regular = np.ones(nl, dtype=bool)
    for typ, da, db in cells.around:
        cid = cells.cell_id(typ, i + da, j + db)
        regular &= (cid >= 0) & clean[np.maximum(cid, 0)]
    irregular = np.concatenate([~regular, np.ones(n - nl, dtype=bool)])
    # Buffer: regular lattice sites next to irregular ones.
    buffer = np.zeros(n, dtype=bool)
    nb_offsets = (
        [(1, 0), (-1, 0), (0, 1), (0, -1), (1, -1), (-1, 1)]
        if cells.hex
        else [(1, 0), (-1, 0), (0, 1), (0, -1)]
    )
    irr_l = np.flatnonzero(~regular)
    for di, dj in nb_offsets:
        k = cells.site_at(i[irr_l] + di, j[irr_l] + dj)
        k = k[k >= 0]
        buffer[k] = True
    buffer &= ~irregular
    return clean, regular, irregular, buffer


def _vertex_ids(cells: _Cells, lat: Lattice, clean: np.ndarray, corner: np.ndarray) -> np.ndarray:
    """Vertex ids of Qhull triangles (``corner``: their sites, -1 for frame points): the cell's
    id for a triangle that is a clean lattice cell, ``cells.n`` + the triangle's index otherwise."""
    nl = lat.ij.shape[0]
    vid = cells.n + np.arange(corner.shape[0])
    lat_tri = np.all((corner >= 0) & (corner < nl), axis=1)
    lt = np.flatnonzero(lat_tri)
    if lt.size:
        ci = lat.ij[corner[lt]]  # (k, 3, 2)
        for typ, da, db in cells.around:  # a cell around the first corner holding the other two
            a = ci[:, 0, 0] + da
            b = ci[:, 0, 1] + db
            cid = cells.cell_id(typ, a, b)
            ok = (cid >= 0) & clean[np.maximum(cid, 0)]
            cand = np.zeros((lt.size, len(cells.corners[typ])), dtype=np.int64)
            for m, (ca, cb) in enumerate(cells.corners[typ]):
                cand[:, m] = cells.site_at(a + ca, b + cb)
            inside1 = (cand == corner[lt, 1][:, None]).any(axis=1)
            inside2 = (cand == corner[lt, 2][:, None]).any(axis=1)
            hit = ok & inside1 & inside2 & (vid[lt] >= cells.n)
            vid[lt[hit]] = cid[hit]
    return vid


def splice_ridges(
    ridges: Ridges,
    sites: np.ndarray,
    moved: np.ndarray,
    domain: Domain,
    tol: float,
    tree: cKDTree | None = None,
    stale: np.ndarray | None = None,
    inside: np.ndarray | None = None,
) -> tuple[Ridges, np.ndarray] | None:
    """The ridges after a few sites moved a little, recomputed only around them.

    ``ridges``: the ridges before (as returned by :func:`hybrid_ridges`); ``sites``: all
    sites, ``moved`` (indices) at their new
    positions. The ridges of the moved sites and of their neighbours (set A) come from
    one Qhull triangulation of A, two rings of neighbours around it and the sites whose
    regions reach far out (so that the frame triangles are right); its triangles at A
    are checked against all sites (no site strictly inside a circumcircle), and the
    kept vertices near A against the moved sites, growing A and the patch until both
    checks pass. Kept ridges that share a vertex with a new one are joined to it by
    position (within ``tol``). Returns the new ridges and the mask of the new ones among
    them, or None where the patch does not join up (the caller recomputes
    everything). ``tree``: a cKDTree of the sites where ``stale`` (mask) is False (the
    others have moved since it was built and are checked at their current positions).
    ``inside`` (mask of sites): the ridges given are all the ridges of these sites (a
    part of the diagram); A and its neighbours must be among them.
    """
    coords, va, vb, cp, cq = ridges.coords, ridges.va, ridges.vb, ridges.cp, ridges.cq
    nv = coords.shape[0]
    patch = _patch(ridges, sites, moved, domain, tree, stale, inside)
    if patch is None:
        return None
    A, tri, nbr, centre, glob = patch
    t, u, p, q = edges_of(tri, nbr)
    gp, gq = glob[p], glob[q]
    take = (gp >= 0) & (gq >= 0) & (A[np.maximum(gp, 0)] | A[np.maximum(gq, 0)])
    t, u, gp, gq = t[take], u[take], gp[take], gq[take]
    used, inv = np.unique(np.concatenate([u, t]), return_inverse=True)
    inv = inv.reshape(-1)
    new_va, new_vb = nv + inv[: u.size], nv + inv[u.size :]
    new_xy = centre[used]
    kept = ~(A[cp] | A[cq])
    # Vertices of kept ridges that dropped ridges also used: the new ones at the same place.
    in_kept = np.zeros(nv, dtype=bool)
    in_kept[va[kept]] = in_kept[vb[kept]] = True
    in_dropped = np.zeros(nv, dtype=bool)
    in_dropped[va[~kept]] = in_dropped[vb[~kept]] = True
    seam = np.flatnonzero(in_kept & in_dropped)
    remap = np.arange(nv + new_xy.shape[0])
    if seam.size:
        d, _ = cKDTree(new_xy).query(coords[seam])
        if np.any(d > tol):
            return None
        # every seam vertex and new vertex at one place becomes one (co-circular sites can be
        # triangulated either way: the two triangulations need not share their vertices)
        ids = np.concatenate([seam, nv + np.arange(new_xy.shape[0])])
        first, group = merge_close_points(np.concatenate([coords[seam], new_xy]), tol)
        remap[ids] = ids[first[group]]  # the first id of each group
    out_va = remap[np.concatenate([va[kept], new_va])]
    out_vb = remap[np.concatenate([vb[kept], new_vb])]
    fresh = np.concatenate([np.zeros(int(kept.sum()), dtype=bool), np.ones(gp.size, dtype=bool)])
    spliced = Ridges(
        np.concatenate([coords, new_xy]),
        out_va,
        out_vb,
        np.concatenate([cp[kept], gp]),
        np.concatenate([cq[kept], gq]),
    )
    return spliced, fresh


def _patch(ridges: Ridges, sites, moved, domain: Domain, tree, stale, inside):
    """The set A of sites whose ridges are recomputed (the moved sites and their neighbours,
    grown until the check passes) and the Qhull triangulation of the patch around it
    (triangles, neighbours, circumcentres, the site of every point or -1 for frame points);
    None where the patch leaves the ``inside`` sites or does not settle."""
    coords, va, vb, cp, cq = ridges.coords, ridges.va, ridges.vb, ridges.cp, ridges.cq
    n = sites.shape[0]

    def grow(mask: np.ndarray) -> np.ndarray:
        """The sites of the mask and their Delaunay neighbours."""
        out = mask.copy()
        out[cq[mask[cp]]] = True
        out[cp[mask[cq]]] = True
        return out

    lo, hi = domain.xy.min(axis=0), domain.xy.max(axis=0)
    span = hi - lo
    far = np.any((coords < lo - span) | (coords > hi + span), axis=1)
    outer = np.zeros(n, dtype=bool)
    fr = far[va] | far[vb]
    outer[cp[fr]] = outer[cq[fr]] = True
    A = np.zeros(n, dtype=bool)
    A[moved] = True
    A = grow(A)
    if tree is None:
        tree, stale = cKDTree(sites), np.zeros(n, dtype=bool)
    stale_idx = np.flatnonzero(stale)
    stale_tree = cKDTree(sites[stale_idx]) if stale_idx.size else None
    frame = frame_points(domain)
    for _ in range(8):  # grow the patch until the triangles at A are Delaunay
        ring = grow(A)
        if inside is not None and not inside[ring].all():  # their neighbours must all be known
            return None
        P = ring.copy()
        hull = outer & grow(grow(P))  # the sites of far-reaching regions next to the patch
        sub = np.flatnonzero(P | hull)
        pts = np.concatenate([sites[sub], frame])
        tri, nbr, centre = triangulate(pts, domain)
        glob = np.concatenate([sub, np.full(frame.shape[0], -1)])
        gt = glob[tri]
        real = (gt >= 0).all(axis=1)
        at_a = (A[np.maximum(gt, 0)] & (gt >= 0)).any(axis=1)
        check = np.flatnonzero(at_a & real)
        rad = np.linalg.norm(centre[check] - pts[tri[check, 0]], axis=1) * (1 - 1e-9)
        hits = tree.query_ball_point(centre[check], rad, return_sorted=False)
        bad = np.unique(np.fromiter(itertools.chain.from_iterable(hits), dtype=np.int64))
        bad = bad[~stale[bad]]  # where the tree has old positions, the current ones are checked
        if stale_idx.size:
            hits = stale_tree.query_ball_point(centre[check], rad, return_sorted=False)
            bad = np.union1d(bad, stale_idx[np.fromiter(itertools.chain.from_iterable(hits), dtype=np.int64)])
        bad = bad[~P[bad]]
        spoilt = _spoilt_vertices(ridges, sites, moved, A, P)
        if bad.size == 0 and spoilt.size == 0:
            return A, tri, nbr, centre, glob
        A[bad] = True
        if spoilt.size:
            sv = np.isin(va, spoilt) | np.isin(vb, spoilt)
            A[cp[sv]] = A[cq[sv]] = True
    return None


def _spoilt_vertices(ridges: Ridges, sites, moved, A, P) -> np.ndarray:
    """Vertices of kept ridges (no site of A) next to the patch ``P`` that a moved site now
    lies strictly inside the circle of: they must go too."""
    coords, va, vb, cp, cq = ridges.coords, ridges.va, ridges.vb, ridges.cp, ridges.cq
    nv = coords.shape[0]
    kept = ~(A[cp] | A[cq])
    near = kept & (P[cp] | P[cq])
    kv = np.unique(np.concatenate([va[near], vb[near]]))
    if kv.size == 0:
        return np.zeros(0, dtype=np.int64)
    first = np.full(nv, -1, dtype=np.int64)
    rv = np.flatnonzero(near)
    first[va[rv]] = cp[rv]
    first[vb[rv]] = cp[rv]
    kr = np.linalg.norm(coords[kv] - sites[first[kv]], axis=1) * (1 - 1e-9)
    mt = cKDTree(sites[moved])
    invaded = mt.query_ball_point(coords[kv], kr, return_sorted=False)
    lens = np.fromiter((len(h) for h in invaded), dtype=np.int64, count=kv.size)
    return kv[lens > 0]
