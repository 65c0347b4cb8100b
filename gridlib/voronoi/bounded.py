"""The Voronoi diagram of a set of sites clipped to a polygon, as a gridlib :class:`Grid`.

Method, all in the domain's local frame (docs/pebi.md puts it in the context of the whole grid):

1. Ridges: every Delaunay edge between two sites is a ridge (a face) from the
   circumcentre of the triangle on one side to that of the other. The
   triangulation includes eight *frame* points ten diameters away, so that every
   site's region is bounded and no frame point's region reaches the domain.
   Where the sites form a regular lattice the ridges are known without Qhull
   (:mod:`.lattice`); elsewhere they come from one Qhull triangulation.
   Optionally (``adjust``), sites that make faces nearly vanish are then moved
   a little (:mod:`.degenerate`) and the ridges recomputed around them only
   (:func:`~.lattice.splice_ridges`), a few times.
2. Ridges far from the boundary (both ends inside the domain shrunk by the 99th
   percentile of the ridge lengths, and shorter than it) are kept whole. The
   others are cut where they cross the domain's boundary (exact segment-edge
   intersections, candidates from an R-tree), and the pieces whose midpoints
   lie inside the domain are kept. A crossing within ``tol`` of a ridge's end
   *is* that end (the vertex moves onto the boundary); a crossing within
   ``tol`` of a polygon corner *is* that corner; other crossings are recomputed
   from the two sites' bisector (exact to round-off, whatever the ridge's far end).
3. The boundary is cut at its corners and at every crossing, and each piece goes
   to the site nearest to its midpoint (whose Voronoi region contains it).
4. Pieces shorter than ``tol`` (the tiny ridges of co-circular sites, crossings
   a hair apart) are contracted: their end vertices become one, keeping the
   polygon's corners, then boundary points, exactly where they are. Optionally
   (``contract``), so are faces shorter than a fraction of their cells' sizes
   (except fault faces), keeping fault vertices too.

Every crossing is one vertex shared by the ridge piece and the two boundary
pieces it separates, so the topology is exact by construction: interior faces
have two cells, boundary faces one, and each cell's faces close into a cycle
(checked). Crossings are found from the distances of a ridge's ends to the edge's
line, and a ridge passing within ``tol`` of a corner crosses at that corner, so a
ridge nearly along an edge or through a corner gives no spurious crossing. A
boundary piece equidistant from two sites (their bisector runs along the edge: a
site and its mirror image) belongs to the one inside. A site whose clipped region
falls into several pieces (a concave boundary cutting it) is reported back so that
the caller can add a site for each extra piece (``ClippedVoronoi.extra_points``: the
site mirrored across the boundary edge that cuts the piece off, or a point inside the
piece). Contracting short faces never flattens a triangle of a cell (the triangular
piece of a cut region).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np
import shapely
from scipy import sparse
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

from ..errors import GridError
from ..grid import Cells, Faces, Grid, Nodes
from .cell_cycles import cell_cycles
from .domain import Domain
from .lattice import Lattice, hybrid_ridges, plain_ridges, splice_ridges
from .ridges import Ridges

WORK_RADIUS = 5.0  # after the first round, moves are looked at within this many local sizes


@dataclass(frozen=True, eq=False)
class ClippedVoronoi:
    """The clipped Voronoi diagram of ``sites`` (local frame).

    ``coords`` (nn, 2) nodes; ``face_nodes`` (nf, 2), oriented so that the
    normal (dy, -dx) points from ``neighbors[:, 0]`` to ``neighbors[:, 1]``;
    ``neighbors`` (nf, 2) sites, -1 outside; ``cell_pos``/``cell_faces`` each
    cell's faces in counter-clockwise order; ``areas`` (nc,) m²;
    ``extra_points`` (k, 2) a new site for every piece of a region that is
    not the piece holding its site (empty when every cell is one piece).
    """

    coords: np.ndarray
    face_nodes: np.ndarray
    neighbors: np.ndarray
    cell_pos: np.ndarray
    cell_faces: np.ndarray
    areas: np.ndarray
    extra_points: np.ndarray
    sites: np.ndarray | None = None  # the sites, after ``adjust`` moved some of them
    contracted: int = 0  # faces contracted because they were too short (``contract``)

    def to_grid(self, origin: np.ndarray, tags: np.ndarray | None, history: tuple[str, ...]) -> Grid:
        nf = self.face_nodes.shape[0]
        return Grid(
            cells=Cells(self.cell_pos, self.cell_faces),
            faces=Faces(np.arange(0, 2 * nf + 1, 2), self.face_nodes.ravel(), self.neighbors, tags),
            nodes=Nodes(self.coords + origin),
            griddim=2,
            history=history,
        )


@dataclass(frozen=True, eq=False)
class Contraction:
    """Which short faces :func:`clipped_voronoi` contracts: those shorter than ``fraction`` x
    the smaller ``size`` (n,) of their two sites (m), except the faces between the site pairs
    ``protect`` (k, 2) (fault faces); ``where`` (mask of sites, optional): only faces of these
    sites can be that short."""

    size: np.ndarray
    protect: np.ndarray | None
    fraction: float
    where: np.ndarray | None = None


def clipped_voronoi(
    sites: np.ndarray,
    domain: Domain,
    tol: float,
    lattice: Lattice | None = None,
    adjust: Callable[[np.ndarray, Ridges, np.ndarray | None], tuple[np.ndarray, ...]] | None = None,
    rounds: int = 4,
    contract: Contraction | None = None,
) -> ClippedVoronoi:
    """Voronoi regions of ``sites`` (local frame, all in the closed domain) clipped to ``domain``.

    ``tol`` (m) is the length below which ridges are contracted to a point.
    ``lattice`` describes the first sites if they form a regular lattice (see
    :mod:`.lattice`): their cells are then computed without Qhull.
    ``adjust(sites, ridges, fresh)``, if given, looks at the ridges (:class:`.Ridges`;
    ``fresh``: the mask of those recomputed since the last call, None for all) and
    returns sites to move, their new positions and the sites of all the short faces it
    found (:mod:`.degenerate`); the ridges around them are then recomputed
    (:func:`~.lattice.splice_ridges`), up to ``rounds`` times, and after the first
    round only the ridges within ``WORK_RADIUS`` sizes of those sites are looked at.
    The sites used are ``.sites``. ``contract`` (:class:`Contraction`): the short faces
    contracted besides the zero-length ones; ``.contracted`` says how many.

    >>> from gridlib.voronoi.domain import rectangle
    >>> d = Domain(rectangle(0, 0, 2, 1))
    >>> v = clipped_voronoi(d.to_local([[0.5, 0.5], [1.5, 0.5]]), d, 1e-9)
    >>> v.areas.tolist(), v.face_nodes.shape[0]
    ([1.0, 1.0], 7)
    """
    if sites.shape[0] == 0:
        raise GridError("pebi_grid: no sites left in the domain")

    def full(sites: np.ndarray, lattice: Lattice | None) -> Ridges:
        if lattice is not None and lattice.ij.shape[0] > 0:
            return hybrid_ridges(sites, domain, lattice)
        return plain_ridges(sites, domain)

    ridges = full(sites, lattice)
    fresh = None
    spliced = False
    tree = cKDTree(sites) if adjust is not None else None
    stale = np.zeros(sites.shape[0], dtype=bool)
    rest = None  # the ridges away from every short face (left alone), once the work is local
    inside = None
    for _ in range(rounds if adjust is not None else 0):  # move sites, recompute the ridges around them
        idx, xy, involved = adjust(sites, ridges, fresh)
        if idx.size == 0:
            break
        if rest is None and contract is not None:  # work on the ridges near the short faces only
            size = contract.size
            cp, cq = ridges.cp, ridges.cq
            near = np.union1d(involved, idx)
            hits = tree.query_ball_point(sites[near], WORK_RADIUS * size[near], return_sorted=False)
            inside = np.zeros(sites.shape[0], dtype=bool)
            inside[np.fromiter(itertools.chain.from_iterable(hits), dtype=np.int64)] = True
            for _ in range(2):  # and their Delaunay neighbours (across a concave boundary: far)
                inside[cq[inside[cp]]] = True
                inside[cp[inside[cq]]] = True
            wr = inside[cp] | inside[cq]
            rest = ridges.where(~wr)
            ridges = ridges.where(wr)
            fresh = None if fresh is None else fresh[wr]
        sites = sites.copy()
        sites[idx] = xy
        if lattice is not None and lattice.ij.shape[0] > 0:
            nl = lattice.ij.shape[0]
            active = np.ones(nl, dtype=bool) if lattice.active is None else lattice.active.copy()
            active[idx[idx < nl]] = False
            lattice = replace(lattice, active=active)
        stale[idx] = True
        got = splice_ridges(ridges, sites, idx, domain, tol, tree, stale, inside)
        if got is None:
            ridges = full(sites, lattice)
            fresh, rest, inside = None, None, None
        else:
            ridges, fresh = got
            spliced = True
    if rest is not None:  # the ridges left alone join the recomputed ones (whose vertices extend theirs)
        ridges = Ridges(
            ridges.coords,
            np.concatenate([rest.va, ridges.va]),
            np.concatenate([rest.vb, ridges.vb]),
            np.concatenate([rest.cp, ridges.cp]),
            np.concatenate([rest.cq, ridges.cq]),
        )
    if contract is not None and inside is not None:
        contract = replace(contract, where=inside)  # short faces are all among these sites' faces
    if spliced:
        try:
            return _build(domain, ridges, tol, sites, contract)
        except GridError:  # pragma: no cover - a patch that does not join up: recompute everything
            ridges = full(sites, lattice)
    return _build(domain, ridges, tol, sites, contract)


def _build(
    domain: Domain, ridges: Ridges, tol: float, sites: np.ndarray, contract: Contraction | None = None
) -> ClippedVoronoi:
    builder = _Builder(domain, ridges.coords, tol, sites)
    builder.add_ridges(ridges.va, ridges.vb, ridges.cp, ridges.cq)
    builder.close_boundary(sites)
    return replace(builder.finish(sites, contract), sites=sites)


class _Builder:
    """Vertices, faces and contractions of the clipped diagram under construction."""

    def __init__(self, domain: Domain, centre: np.ndarray, tol: float, sites: np.ndarray) -> None:
        self.domain = domain
        self.sites = sites
        self.tol = tol
        self.nt = centre.shape[0]
        m = domain.num_vertices
        # Vertex ids: circumcentres [0, nt), polygon corners [nt, nt + m), crossings after.
        self.coords = [centre.copy(), domain.xy.copy()]
        self.n_vert = self.nt + m
        self.corner_id = self.nt + np.arange(m)
        self.bnd_ids = [self.corner_id]
        self.bnd_par = [domain.cum[:-1].copy()]
        self.face_a: list[np.ndarray] = []
        self.face_b: list[np.ndarray] = []
        self.face_c0: list[np.ndarray] = []
        self.face_c1: list[np.ndarray] = []
        self.merge_a: list[np.ndarray] = []
        self.merge_b: list[np.ndarray] = []

    def add_ridges(self, va, vb, cp, cq) -> None:
        d = self.domain
        centre = self.coords[0]
        a, b = centre[va], centre[vb]
        length = np.linalg.norm(b - a, axis=1)
        # Ridges between two sites both inside the domain are mostly inside too: a length scale.
        both_in = d.inside(0.5 * (self.sites[cp] + self.sites[cq]))
        g = float(np.quantile(length[both_in], 0.99)) if both_in.any() else 0.0
        if g > 0:
            inner = d.inner_buffer(g)  # inside the domain, at least g from its boundary
            deep = shapely.contains_xy(inner, centre[:, 0], centre[:, 1])
        else:
            deep = np.zeros(centre.shape[0], dtype=bool)
        safe = deep[va] & deep[vb] & (length < g)
        tiny = safe & (length <= self.tol)
        self._merge(va[tiny], vb[tiny])
        whole = safe & ~tiny
        self._faces(va[whole], vb[whole], cp[whole], cq[whole])
        r = np.flatnonzero(~safe)
        if r.size:
            self._clip(va[r], vb[r], cp[r], cq[r])

    def _clip(self, va, vb, cp, cq) -> None:
        d = self.domain
        tol = self.tol
        centre = self.coords[0]
        a, b = centre[va], centre[vb]
        # Shorten ridges to the domain's bounding box first (they may reach the frame).
        lo = d.xy.min(axis=0) - 1e-3 * d.diameter
        hi = d.xy.max(axis=0) + 1e-3 * d.diameter
        t_lo, t_hi = _clip_to_box(a, b - a, lo, hi)
        ok = t_hi > t_lo
        va, vb, cp, cq, a, b, t_lo, t_hi = (x[ok] for x in (va, vb, cp, cq, a, b, t_lo, t_hi))
        dirn = b - a
        sa = a + t_lo[:, None] * dirn
        sb = a + t_hi[:, None] * dirn
        seg, ts, edge, uu = d.crossings(sa, sb, tol)
        span = t_hi - t_lo
        t = t_lo[seg] + ts * span[seg]
        # Vertex of every crossing: the ridge's end, a polygon corner, or a new vertex.
        vid = np.full(seg.size, -1, dtype=np.int64)
        at_a = (ts == 0) & (t_lo[seg] == 0)
        at_b = (ts == 1) & (t_hi[seg] == 1)
        vid[at_a] = va[seg[at_a]]
        vid[at_b] = vb[seg[at_b]]
        at_corner = (vid < 0) & (uu == 0)
        vid[at_corner] = self.corner_id[edge[at_corner]]
        new = vid < 0
        n_new = int(new.sum())
        # A new crossing is recomputed from the two sites' bisector, not from the ridge, whose
        # far end may be a circumcentre of a thin triangle (few correct digits in its direction).
        rs = seg[new]
        w = self.sites[cq[rs]] - self.sites[cp[rs]]
        m = 0.5 * (self.sites[cq[rs]] + self.sites[cp[rs]])
        ev = d.edge_vec[edge[new]]
        den = (ev * w).sum(axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            ub = ((m - d.edge_a[edge[new]]) * w).sum(axis=1) / den
        good = np.isfinite(ub) & (ub > 0) & (ub < 1) & (np.abs(ub - uu[new]) < 1e-6)
        uu_new = uu[new]
        uu_new[good] = ub[good]
        uu[new] = uu_new
        new_xy = d.edge_a[edge[new]] + uu[new, None] * d.edge_vec[edge[new]]
        vid[new] = self.n_vert + np.arange(n_new)
        self.coords.append(new_xy)
        self.n_vert += n_new
        # Ridge ends that sit on the boundary move onto it.
        snapped = at_a | at_b
        if snapped.any():
            centre[vid[snapped]] = d.edge_a[edge[snapped]] + uu[snapped, None] * d.edge_vec[edge[snapped]]
        on_bnd = ~at_corner
        self.bnd_ids.append(vid[on_bnd])
        self.bnd_par.append(d.perimeter_param(edge[on_bnd], uu[on_bnd]))

        # Pieces between consecutive break points along each ridge.
        k = va.size
        ends_t = np.concatenate([t_lo, t_hi])
        ends_v = np.concatenate([np.where(t_lo == 0, va, -1), np.where(t_hi == 1, vb, -1)])
        ends_r = np.concatenate([np.arange(k), np.arange(k)])
        all_r = np.concatenate([ends_r, seg])
        all_t = np.concatenate([ends_t, t])
        all_v = np.concatenate([ends_v, vid])
        order = np.lexsort((all_t, all_r))
        all_r, all_t, all_v = all_r[order], all_t[order], all_v[order]
        same = all_r[1:] == all_r[:-1]
        i0 = np.flatnonzero(same)
        r_of = all_r[i0]
        t0, t1 = all_t[i0], all_t[i0 + 1]
        v0, v1 = all_v[i0], all_v[i0 + 1]
        plen = (t1 - t0) * np.linalg.norm(dirn[r_of], axis=1)
        short = plen <= tol
        real_ends = (v0 >= 0) & (v1 >= 0)
        self._merge(v0[short & real_ends], v1[short & real_ends])
        cand = np.flatnonzero(~short)
        mid = a[r_of[cand]] + (0.5 * (t0[cand] + t1[cand]))[:, None] * dirn[r_of[cand]]
        inside = d.inside(mid)
        cand, mid = cand[inside], mid[inside]
        if cand.size:
            along = d.boundary_distance(mid) > tol  # a ridge along the boundary gives no face
            cand = cand[along]
        if np.any((v0[cand] < 0) | (v1[cand] < 0)):  # pragma: no cover
            raise GridError("pebi_grid: a clipped ridge piece inside the domain has no end vertex")
        self._faces(v0[cand], v1[cand], cp[r_of[cand]], cq[r_of[cand]])

    def close_boundary(self, sites: np.ndarray) -> None:
        d = self.domain
        ids = np.concatenate(self.bnd_ids)
        par = np.concatenate(self.bnd_par)
        ids, first = np.unique(ids, return_index=True)
        par = par[first]
        par = np.where(par >= d.perimeter, par - d.perimeter, par)
        order = np.lexsort((ids >= self.nt + d.num_vertices, par))
        ring = ids[order]
        ring_par = par[order]
        nxt = np.roll(ring, -1)
        nxt_par = np.roll(ring_par, -1)
        nxt_par[-1] += d.perimeter
        short = (nxt_par - ring_par) <= self.tol
        self._merge(ring[short], nxt[short])
        a, b = ring[~short], nxt[~short]
        mid_par = 0.5 * (ring_par[~short] + nxt_par[~short])
        mid = _perimeter_point(d, mid_par)
        owner = _piece_owner(d, sites, mid, mid_par)
        self._faces(a, b, owner, np.full(owner.size, -1, dtype=np.int64))
        self.is_boundary = np.zeros(self.n_vert, dtype=bool)
        self.is_boundary[ids] = True

    def _faces(self, a, b, c0, c1) -> None:
        self.face_a.append(a)
        self.face_b.append(b)
        self.face_c0.append(c0)
        self.face_c1.append(c1)

    def _merge(self, a, b) -> None:
        self.merge_a.append(a)
        self.merge_b.append(b)

    def finish(self, sites: np.ndarray, contract: Contraction | None = None) -> ClippedVoronoi:
        n = sites.shape[0]
        coords = np.concatenate(self.coords)
        nv = coords.shape[0]
        fa, fb = np.concatenate(self.face_a), np.concatenate(self.face_b)
        c0, c1 = np.concatenate(self.face_c0), np.concatenate(self.face_c1)
        ma, mb = np.concatenate(self.merge_a), np.concatenate(self.merge_b)
        priority = np.full(nv, 2, dtype=np.int64)
        priority[self.is_boundary[:nv]] = 1
        priority[self.corner_id] = 0
        if ma.size:
            rep = _representatives(nv, ma, mb, priority)
            fa, fb = rep[fa], rep[fb]
        keep = fa != fb
        fa, fb, c0, c1 = fa[keep], fb[keep], c0[keep], c1[keep]
        contracted = 0
        if contract is not None and contract.fraction > 0:
            fa, fb, c0, c1, contracted = self._contract(coords, fa, fb, c0, c1, contract, priority)
        used = np.zeros(nv, dtype=bool)
        used[fa] = used[fb] = True
        new_id = np.cumsum(used) - 1
        coords = coords[used]
        fa, fb = new_id[fa], new_id[fb]
        # Orientation: the normal (dy, -dx) points from c0 to c1 (outwards on the boundary).
        inner = c1 >= 0
        e = coords[fb] - coords[fa]
        towards = np.where(inner, 0.0, 1.0)
        ii = np.flatnonzero(inner)
        towards[ii] = (e[ii, 1] * (sites[c1[ii], 0] - sites[c0[ii], 0])) - (
            e[ii, 0] * (sites[c1[ii], 1] - sites[c0[ii], 1])
        )
        swap = towards < 0
        fa, fb = np.where(swap, fb, fa), np.where(swap, fa, fb)
        faces = np.column_stack([fa, fb])
        neighbors = np.column_stack([c0, c1])
        pos, cell_faces, areas, extra = cell_cycles(coords, faces, neighbors, n, sites, self.domain)
        return ClippedVoronoi(coords, faces, neighbors, pos, cell_faces, areas, extra, contracted=contracted)

    def _contract(self, coords, fa, fb, c0, c1, contract: Contraction, priority):
        """Contract the faces (fa, fb) between cells c0 and c1 shorter than ``contract.fraction``
        x the smaller size of their two cells.

        The last resort for short faces that no move of a background site collapses (their
        sites are fault or well sites, or lattice sites pinned by the co-circular squares of
        a Cartesian lattice). The face's end vertices become one, at the end that must stay
        (a corner, a boundary point, a vertex of a fault face); faces with two such ends
        (two fault vertices, a fault vertex and a boundary point, ...) and faces of
        triangular cells are left alone. Fault faces are never contracted. The faces at
        the merged vertex turn by at most about (face length / their length) radians.
        ``contract.where`` (mask of sites, optional): only faces of these cells can be short.
        """
        size, protect, where, fraction = contract.size, contract.protect, contract.where, contract.fraction
        nv = coords.shape[0]
        n = size.shape[0]
        pk = np.zeros(0, dtype=np.int64)
        if protect is not None and protect.size:
            pk = np.sort(protect, axis=1)
            pk = np.unique(pk[:, 0] * n + pk[:, 1])
        bnd = priority <= 1
        total = 0
        for _ in range(3):  # merging can shorten a neighbouring face: look again
            sub = np.arange(fa.size) if where is None else np.flatnonzero(where[c0] | (c1 >= 0) & where[c1])
            u, w, s0, s1 = fa[sub], fb[sub], c0[sub], c1[sub]
            length = np.linalg.norm(coords[w] - coords[u], axis=1)
            h = np.minimum(size[s0], np.where(s1 >= 0, size[np.maximum(s1, 0)], np.inf))
            short = length < fraction * h
            if not short.any():
                break
            fault = np.zeros(sub.size, dtype=bool)
            if pk.size:
                fk = np.minimum(s0, s1) * n + np.maximum(s0, s1)
                loc = np.minimum(np.searchsorted(pk, fk), pk.size - 1)
                fault = (s1 >= 0) & (pk[loc] == fk)
            on_fault = np.zeros(nv, dtype=bool)
            on_fault[u[fault]] = on_fault[w[fault]] = True
            fixed = on_fault | (priority == 0)
            # faces per cell (all the faces of a cell in ``where`` are in ``sub``)
            nfaces = np.bincount(s0, minlength=n) + np.bincount(s1[s1 >= 0], minlength=n)
            cand = ~fault & short
            cand &= ~(fixed[u] & fixed[w])
            cand &= ~(on_fault[u] & ~bnd[u] & bnd[w]) & ~(on_fault[w] & ~bnd[w] & bnd[u])
            cand &= (nfaces[s0] > 3) & ((s1 < 0) | (nfaces[np.maximum(s1, 0)] > 3))
            if cand.any():  # (looked at only around the candidates: a handful of cells)
                near = np.zeros(n, dtype=bool)
                near[s0[cand]] = True
                near[s1[cand & (s1 >= 0)]] = True
                around = np.flatnonzero(near[s0] | ((s1 >= 0) & near[np.maximum(s1, 0)]))
                complete = near if where is None else near & where
                flat = _closes_a_triangle(u[around], w[around], s0[around], s1[around], complete)
                cand[around[flat]] = False
            k = np.flatnonzero(cand)
            if k.size == 0:
                break
            verts, inv = np.unique(np.concatenate([u[k], w[k]]), return_inverse=True)
            m = verts.size
            graph = sparse.coo_matrix((np.ones(k.size), (inv[: k.size], inv[k.size :])), shape=(m, m))
            label = csgraph.connected_components(graph, directed=False)[1]
            # a group may hold at most one vertex that must stay, and no fault vertex off the
            # boundary together with a boundary point
            nfix = np.bincount(label[fixed[verts]], minlength=label.max() + 1)
            mixed = np.bincount(
                label[on_fault[verts] & ~bnd[verts]], minlength=label.max() + 1
            ) * np.bincount(label[bnd[verts]], minlength=label.max() + 1)
            good = ~((nfix > 1) | (mixed > 0))[label]
            prio = np.where(fixed[verts], 0, np.where(bnd[verts], 1, 2))
            local = _representatives(m, inv[: k.size], inv[k.size :], prio)
            # a group without a vertex that must stay goes to the point where the faces around
            # it turn least: each vertex weighted by 1 / the length of its shortest other face
            free = good & (np.bincount(label, prio == 2, label.max() + 1) == np.bincount(label))[label]
            if free.any():
                vmask = np.zeros(nv, dtype=bool)
                vmask[verts[free]] = True
                near = vmask[u] | vmask[w]
                near[k] = False
                at = sub[near]
                lam = np.full(nv, np.inf)
                flen = np.linalg.norm(coords[fb[at]] - coords[fa[at]], axis=1)
                np.minimum.at(lam, fa[at], flen)
                np.minimum.at(lam, fb[at], flen)
                wgt = 1.0 / np.maximum(lam[verts], 1e-300)
                grp = label[free]
                wsum = np.bincount(grp, wgt[free], label.max() + 1)
                for dim in range(2):
                    pt = np.bincount(grp, wgt[free] * coords[verts[free], dim], label.max() + 1) / np.where(
                        wsum > 0, wsum, 1.0
                    )
                    coords[verts[local[free]], dim] = pt[grp]
            rep = np.arange(nv)
            rep[verts[good]] = verts[local[good]]
            fa, fb = rep[fa], rep[fb]
            keep = fa != fb
            if keep.all():
                break
            total += int((~keep).sum())
            fa, fb, c0, c1 = fa[keep], fb[keep], c0[keep], c1[keep]
        return fa, fb, c0, c1, total


def _closes_a_triangle(u, w, s0, s1, complete: np.ndarray) -> np.ndarray:
    """Faces (u, w) whose contraction would flatten a triangle of one of their cells.

    A cell may consist of pieces (a concave boundary cutting its region), so it can have
    many faces and still a triangular piece: the face is one of a triangle (u, w, v) if the
    cell's other face at u and its other face at w share their far vertex v. A vertex with
    more than two faces of a cell (pieces touching there) counts as such too. Only cells
    whose faces are all given (``complete``, a mask of cells) are looked at.
    """
    n = u.size
    nv = max(int(u.max(initial=0)), int(w.max(initial=0))) + 1
    inner = s1 >= 0
    cell = np.concatenate([s0, s0, s1[inner], s1[inner]])
    at = np.concatenate([u, w, u[inner], w[inner]])
    far = np.concatenate([w, u, w[inner], u[inner]])
    uniq, inv = np.unique(cell * nv + at, return_inverse=True)
    deg = np.bincount(inv)
    total = np.bincount(inv, far.astype(np.float64))  # the far ends of a vertex's faces, summed
    flat = np.zeros(n, dtype=bool)
    for side in (s0, s1):  # both cells of every face
        idx = np.flatnonzero((side >= 0) & complete[np.maximum(side, 0)])
        ku = np.searchsorted(uniq, side[idx] * nv + u[idx])
        kw = np.searchsorted(uniq, side[idx] * nv + w[idx])
        odd = (deg[ku] != 2) | (deg[kw] != 2)
        flat[idx] |= odd | (total[ku] - w[idx] == total[kw] - u[idx])
    return flat


def _representatives(nv: int, ma: np.ndarray, mb: np.ndarray, priority: np.ndarray) -> np.ndarray:
    """For every vertex, the vertex it becomes when the pairs (ma, mb) are merged: the one of
    lowest priority (then lowest id) in its group."""
    graph = sparse.coo_matrix((np.ones(ma.size), (ma, mb)), shape=(nv, nv))
    _, label = csgraph.connected_components(graph, directed=False)
    order = np.lexsort((np.arange(nv), priority, label))
    lab_sorted = label[order]
    first = np.concatenate([[True], lab_sorted[1:] != lab_sorted[:-1]])
    rep_of_label = np.empty(label.max() + 1, dtype=np.int64)
    rep_of_label[lab_sorted[first]] = order[first]
    return rep_of_label[label]


def _piece_owner(d: Domain, sites: np.ndarray, mid: np.ndarray, mid_par: np.ndarray) -> np.ndarray:
    """The site whose region holds each boundary piece (given by its midpoint and perimeter parameter).

    That is the nearest site to the midpoint; where two are equally near, the piece lies
    on their bisector, which then runs along the boundary (a site and its mirror image across
    the edge's line): the region on the domain's side holds it, i.e. the site on the inner side.
    """
    if sites.shape[0] == 1:
        return np.zeros(mid.shape[0], dtype=np.int64)
    dist, idx = cKDTree(sites).query(mid, k=2)
    owner = idx[:, 0].astype(np.int64)
    tie = np.flatnonzero(dist[:, 1] - dist[:, 0] <= 1e-9 * np.maximum(dist[:, 1], d.tol))
    if tie.size:
        par = np.mod(mid_par[tie], d.perimeter)
        edge = np.clip(np.searchsorted(d.cum, par, side="right") - 1, 0, d.num_vertices - 1)
        inward = np.column_stack([-d.edge_unit[edge, 1], d.edge_unit[edge, 0]])
        depth = []
        for k in range(2):
            rel = sites[idx[tie, k]] - mid[tie]
            depth.append(rel[:, 0] * inward[:, 0] + rel[:, 1] * inward[:, 1])
        owner[tie] = np.where(depth[1] > depth[0], idx[tie, 1], idx[tie, 0])
    return owner


def _perimeter_point(d: Domain, par: np.ndarray) -> np.ndarray:
    par = np.mod(par, d.perimeter)
    edge = np.clip(np.searchsorted(d.cum, par, side="right") - 1, 0, d.num_vertices - 1)
    u = (par - d.cum[edge]) / d.edge_len[edge]
    return d.edge_a[edge] + u[:, None] * d.edge_vec[edge]


def _clip_to_box(a: np.ndarray, dirn: np.ndarray, lo: np.ndarray, hi: np.ndarray):
    """Liang-Barsky: parameter range of a + t dirn, t in [0, 1], inside the box [lo, hi]."""
    t_lo = np.zeros(a.shape[0])
    t_hi = np.ones(a.shape[0])
    for k in range(2):
        dk = dirn[:, k]
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = (lo[k] - a[:, k]) / dk
            t2 = (hi[k] - a[:, k]) / dk
        par = dk == 0
        outside = par & ((a[:, k] < lo[k]) | (a[:, k] > hi[k]))
        tmin = np.where(par, -np.inf, np.minimum(t1, t2))
        tmax = np.where(par, np.inf, np.maximum(t1, t2))
        t_lo = np.maximum(t_lo, tmin)
        t_hi = np.minimum(t_hi, tmax)
        t_hi = np.where(outside, -1.0, t_hi)
    return t_lo, t_hi
