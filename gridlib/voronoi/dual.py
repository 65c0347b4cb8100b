"""``pebi``: the perpendicular-bisector (Voronoi) dual of a planar triangulation.

As MRST's ``pebi`` (book §3.2.2), every node of the triangulation becomes a
cell, every triangle contributes its circumcentre as a vertex, and every
interior triangle edge becomes the bisector face between its two end nodes.
The dual is bounded by the triangulation's boundary: boundary nodes get half
cells centred on the boundary, and straight boundary sides carry no vertices
other than where a bisector meets them.

Convex triangulations (every Delaunay triangulation of a point set) give the
exact Voronoi diagram of the nodes clipped to the hull: each bisector segment,
and the bisector ray of every boundary edge, is clipped to the hull polygon
(a circumcentre outside the hull is replaced by the point where its bisectors
leave it, which is what MRST's auxiliary mirrored triangles achieve at obtuse
boundary triangles, and also right where MRST's repair does not apply); the
hull between consecutive boundary vertices is given to the nearest node.

Non-convex triangulations (a meshed polygon with re-entrant corners) use
MRST's construction: circumcentres, midpoints of boundary edges and boundary
nodes, with MRST's repair of obtuse boundary triangles. Their circumcentres
must lie inside the domain; the result is validated.

In both cases vertices closer than ``tol`` times the median edge length are
merged (nearly co-circular nodes give nearly coincident circumcentres) and
faces collapsing to a point are dropped. Coordinates are shifted to a local
origin first: Qhull and circumcentre formulas lose digits at UTM magnitudes.
"""

from __future__ import annotations

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph
from scipy.spatial import ConvexHull, cKDTree

from ..connectivity import cell_faces_from_neighbors, cell_node_cycles_2d, order_cell_faces_2d
from ..errors import GridError
from ..grid import Cells, Faces, Grid, Nodes
from ..planar import circumcentres, cross2, merge_close_points


def pebi(tri_grid: Grid, tol: float = 1e-9) -> Grid:
    """Voronoi (PEBI) grid dual to a planar triangle grid, bounded by its boundary.

    >>> import numpy as np
    >>> from gridlib import triangle_grid
    >>> x, y = np.meshgrid(np.arange(4.0), np.arange(3.0))
    >>> g = pebi(triangle_grid(np.column_stack([x.ravel(), y.ravel()])))
    >>> g.num_cells, g.num_faces
    (12, 31)
    """
    if tri_grid.griddim != 2 or tri_grid.dim != 2:
        raise GridError("pebi: needs a planar 2-D triangle grid (e.g. from triangle_grid)")
    if not (isinstance(tol, int | float) and 0 < tol < 1e-2):
        raise GridError(
            f"pebi: tol must be a small positive number (relative to the edge length), got {tol!r}"
        )
    if np.any(tri_grid.cells.num_faces != 3):
        c = int(np.flatnonzero(tri_grid.cells.num_faces != 3)[0])
        raise GridError(f"pebi: cell {c} of the input is not a triangle")
    origin = tri_grid.nodes.coords.mean(axis=0)
    t = _Triangulation(tri_grid.nodes.coords - origin, cell_node_cycles_2d(tri_grid)[1].reshape(-1, 3))
    corners = t.convex_corners(tol)
    if corners is not None:
        coords, fa, fb, ca, cb = _clipped_voronoi(t, corners, tol)
    else:
        coords, fa, fb, ca, cb = _mrst_dual(t, tol)

    fa, fb = _merge_close_vertices(coords, fa, fb, tol * t.h)
    keep = fa != fb
    fa, fb, ca, cb = fa[keep], fb[keep], ca[keep], cb[keep]
    n_sites = t.xy.shape[0]
    faces_per_site = np.bincount(ca, minlength=n_sites) + np.bincount(cb[cb >= 0], minlength=n_sites)
    if np.any(faces_per_site < 3):
        lost = np.flatnonzero(faces_per_site < 3)
        raise GridError(
            f"pebi: the cells of nodes {lost[:5].tolist()} vanish (nodes closer than {tol:g} x the "
            "typical edge length to others?)"
        )
    advice = (
        "the triangulation is not Delaunay, or circumcentres of triangles near its (non-convex) "
        "boundary fall outside it: refine the triangulation there"
    )
    try:
        grid = _assemble(coords + origin, fa, fb, ca, cb, n_sites, tri_grid.history)
    except GridError as exc:
        raise GridError(f"pebi: the dual is not a valid grid ({exc}); {advice}") from exc
    problems = _dual_violations(grid, t, origin, check_inside=corners is None)
    if problems:
        raise GridError(f"pebi: {problems}; {advice}")
    return grid


def _dual_violations(grid: Grid, t: _Triangulation, origin: np.ndarray, check_inside: bool) -> str:
    """What makes the dual invalid: inverted cells, reversed bisectors, vertices outside."""
    areas = _cell_areas(grid)
    if np.any(areas <= 0):
        return f"cells {np.flatnonzero(areas <= 0)[:5].tolist()} come out inverted"
    nb = grid.faces.neighbors
    inner = np.flatnonzero((nb >= 0).all(axis=1))
    e = grid.faces.nodes.reshape(-1, 2)[inner]
    p0, p1 = grid.nodes.coords[e[:, 0]] - origin, grid.nodes.coords[e[:, 1]] - origin
    normal = np.column_stack([p1[:, 1] - p0[:, 1], p0[:, 0] - p1[:, 0]])
    towards = ((t.xy[nb[inner, 1]] - t.xy[nb[inner, 0]]) * normal).sum(axis=1)
    if np.any(towards < 0):
        return f"faces {inner[towards < 0][:5].tolist()} point from their second cell to their first"
    if not check_inside:
        return ""
    b = np.flatnonzero(t.on_boundary.ravel())
    qa, qb = t.xy[t.ea.ravel()[b]], t.xy[t.eb.ravel()[b]]
    pts = grid.nodes.coords - origin
    eps = 1e-9 * t.h
    outside = np.zeros(pts.shape[0], dtype=bool)
    chunk = max(1, 2_000_000 // max(1, b.size))
    for start in range(0, pts.shape[0], chunk):
        p = pts[start : start + chunk, None, :]
        d = qb - qa
        rel = p - qa
        along = np.clip((rel * d).sum(axis=2) / (d * d).sum(axis=1), 0.0, 1.0)
        dist = np.sqrt(((rel - along[..., None] * d) ** 2).sum(axis=2)).min(axis=1)
        up = (qa[:, 1] > p[..., 1]) != (qb[:, 1] > p[..., 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            x_cross = qa[:, 0] + (p[..., 1] - qa[:, 1]) * d[:, 0] / d[:, 1]
        inside = ((up & (p[..., 0] < x_cross)).sum(axis=1) % 2) == 1
        outside[start : start + chunk] = ~inside & (dist > eps)
    if outside.any():
        return f"vertices {np.flatnonzero(outside)[:5].tolist()} lie outside the domain"
    return ""


class _Triangulation:
    """Triangles (CCW), their edges and circumcentres in a local frame."""

    def __init__(self, xy: np.ndarray, tri: np.ndarray) -> None:
        self.xy, self.tri = xy, tri
        if np.any(cross2(xy[tri[:, 1]] - xy[tri[:, 0]], xy[tri[:, 2]] - xy[tri[:, 0]]) <= 0):
            raise GridError("pebi: the triangle grid has inverted or degenerate triangles")
        nn = xy.shape[0]
        self.ea, self.eb = tri, np.roll(tri, -1, axis=1)  # edge k: tri[k] -> tri[k+1]
        key = np.minimum(self.ea, self.eb) * nn + np.maximum(self.ea, self.eb)
        _, edge_of = np.unique(key.ravel(), return_inverse=True)
        self.edge_of = edge_of.reshape(-1, 3)
        uses = np.bincount(self.edge_of.ravel())
        if np.any(uses > 2):
            raise GridError("pebi: an edge is shared by more than two triangles")
        self.on_boundary = (uses == 1)[self.edge_of]  # per (triangle, local edge)
        self.centre = circumcentres(xy, tri)
        self.h = float(np.median(np.linalg.norm(xy[self.eb] - xy[self.ea], axis=2)))
        flat = self.edge_of.ravel()
        order = np.argsort(flat, kind="stable")
        pair = np.flatnonzero(flat[order][1:] == flat[order][:-1])
        # The two half-edges of every interior edge: "left" is listed first.
        self.hf_left, self.hf_right = order[pair], order[pair + 1]

    def convex_corners(self, tol: float) -> np.ndarray | None:
        """Corners of the convex hull (counter-clockwise) if the boundary is one convex loop.

        The boundary counts as convex when no turn is reflex by more than a sine
        of 1e-6: a Delaunay triangulation of points is convex up to round-off
        (and up to the hull slivers ``triangle_grid`` removes). The corners are
        then those of the exact convex hull of the boundary nodes, turning by
        more than ``tol``. Returns None for non-convex or multiply connected
        triangulations.
        """
        b = np.flatnonzero(self.on_boundary.ravel())
        start, end = self.ea.ravel()[b], self.eb.ravel()[b]
        nn = self.xy.shape[0]
        if np.bincount(start, minlength=nn).max() > 1 or np.bincount(end, minlength=nn).max() > 1:
            return None
        graph = sparse.coo_matrix((np.ones(b.size), (start, end)), shape=(nn, nn))
        _, label = csgraph.connected_components(graph, directed=False)
        if np.unique(label[start]).size != 1:
            return None  # several boundary loops (holes)
        prev = np.full(nn, -1, dtype=np.int64)
        prev[end] = start
        d_in = self.xy[start] - self.xy[prev[start]]
        d_out = self.xy[end] - self.xy[start]
        turn = cross2(d_in, d_out)
        scale = np.linalg.norm(d_in, axis=1) * np.linalg.norm(d_out, axis=1)
        if np.any(turn < -1e-6 * scale):
            return None
        hull = self.xy[start][ConvexHull(self.xy[start]).vertices]  # counter-clockwise
        d_in = hull - np.roll(hull, 1, axis=0)
        d_out = np.roll(hull, -1, axis=0) - hull
        turn = cross2(d_in, d_out)
        scale = np.linalg.norm(d_in, axis=1) * np.linalg.norm(d_out, axis=1)
        return hull[turn > tol * scale]


def _clipped_voronoi(t: _Triangulation, corners: np.ndarray, tol: float):
    """The Voronoi diagram of the points clipped to their convex hull (``corners``): vertex
    coordinates and faces (two vertices, the cells either side, -1 outside)."""
    xy = t.xy
    side_dir = np.roll(corners, -1, axis=0) - corners
    inward = np.column_stack([-side_dir[:, 1], side_dir[:, 0]])
    inward /= np.linalg.norm(inward, axis=1, keepdims=True)
    eps = tol * t.h
    A, D, B, cells_a, cells_b = _segments_and_rays(t, eps)
    s_lo, s_hi, side_lo, side_hi = _clip_to_convex(A, D, corners, inward)
    length = np.linalg.norm(D, axis=1)
    keep = (s_hi - s_lo) * length > eps
    A, B, D, s_lo, s_hi = A[keep], B[keep], D[keep], s_lo[keep], s_hi[keep]
    side_lo, side_hi = side_lo[keep], side_hi[keep]
    cells_a, cells_b = cells_a[keep], cells_b[keep]
    n_seg = A.shape[0]

    # Vertices: corners, then the two ends of every kept segment. A clipped end is
    # recomputed as the crossing of the two sites' bisector with the hull side:
    # A + s D loses digits when A is the far circumcentre of a thin triangle.
    ncorner = corners.shape[0]
    start = A.copy()  # unclipped ends stay the exact circumcentres
    end = B.copy()
    mid = 0.5 * (xy[cells_a] + xy[cells_b])
    along = xy[cells_b] - xy[cells_a]
    bisector = np.column_stack([-along[:, 1], along[:, 0]])
    for point, side, clipped in ((start, side_lo, s_lo > 0), (end, side_hi, s_hi < 1)):
        k = side[clipped]
        num = ((corners[k] - mid[clipped]) * inward[k]).sum(axis=1)
        point[clipped] = (
            mid[clipped] + (num / (bisector[clipped] * inward[k]).sum(axis=1))[:, None] * bisector[clipped]
        )
    coords = np.concatenate([corners, start, end])
    start_id = ncorner + np.arange(n_seg)
    end_id = start_id + n_seg
    start_on = s_lo > 0
    end_on = s_hi < 1
    # Circumcentres lying on the hull (right triangles, co-circular hull points).
    dist_start, wedge_start = _distance_to_hull(start, corners, inward)
    dist_end, wedge_end = _distance_to_hull(end, corners, inward)
    start_on |= dist_start <= eps
    end_on |= dist_end <= eps
    side_lo = np.where(s_lo > 0, side_lo, wedge_start)
    side_hi = np.where(s_hi < 1, side_hi, wedge_end)

    # Perimeter parameter of every boundary vertex; corners first so they win merges.
    side_len = np.linalg.norm(side_dir, axis=1)
    cum = np.concatenate([[0.0], np.cumsum(side_len)])
    unit = side_dir / side_len[:, None]

    def param(points: np.ndarray, side: np.ndarray) -> np.ndarray:
        along = ((points - corners[side]) * unit[side]).sum(axis=1)
        return cum[side] + np.clip(along, 0.0, side_len[side])

    b_ids = np.concatenate([np.arange(ncorner), start_id[start_on], end_id[end_on]])
    b_par = np.concatenate(
        [cum[:-1], param(start[start_on], side_lo[start_on]), param(end[end_on], side_hi[end_on])]
    )
    rep = _representatives(coords, eps)
    b_ids = rep[b_ids]
    b_ids, first = np.unique(b_ids, return_index=True)
    b_par = b_par[first]
    order = np.argsort(b_par, kind="stable")
    ring = b_ids[order]
    piece_a, piece_b = ring, np.roll(ring, -1)
    mid = 0.5 * (coords[piece_a] + coords[piece_b])
    owner = cKDTree(xy).query(mid)[1]

    fa = np.concatenate([rep[start_id], piece_a])
    fb = np.concatenate([rep[end_id], piece_b])
    ca = np.concatenate([cells_a, owner])
    cb = np.concatenate([cells_b, np.full(owner.size, -1)])
    return coords, fa, fb, ca, cb


def _segments_and_rays(t: _Triangulation, eps: float) -> tuple[np.ndarray, ...]:
    """The unclipped Voronoi edges: start A, direction D, end B and the cells either side.

    Segments: interior edges (from the right triangle's centre to the left one's), then rays:
    one per boundary edge, from the centre outwards across the edge.
    """
    xy = t.xy
    nt = t.tri.shape[0]
    ea, eb = t.ea.ravel(), t.eb.ravel()
    tri_of = np.repeat(np.arange(nt), 3)
    left, right = t.hf_left, t.hf_right
    seg_a = t.centre[tri_of[right]]
    seg_d = t.centre[tri_of[left]] - seg_a
    normal = xy[eb[left]] - xy[ea[left]]
    across = np.column_stack([-normal[:, 1], normal[:, 0]])  # left of v -> w
    reversed_ = (seg_d * across).sum(axis=1) < -eps * np.linalg.norm(across, axis=1)
    if np.any(reversed_):
        i = int(np.flatnonzero(reversed_)[0])
        raise GridError(
            f"pebi: the triangulation is not Delaunay at edge ({ea[left[i]]}, {eb[left[i]]}); "
            "use the Delaunay triangulation of the points"
        )
    bnd = np.flatnonzero(t.on_boundary.ravel())
    ray_a = t.centre[tri_of[bnd]]
    out_dir = xy[eb[bnd]] - xy[ea[bnd]]
    ray_d = np.column_stack([out_dir[:, 1], -out_dir[:, 0]])  # right of v -> w: outside
    ray_d *= 4.0 * np.ptp(xy, axis=0).max() / np.linalg.norm(ray_d, axis=1, keepdims=True)

    A = np.concatenate([seg_a, ray_a])
    D = np.concatenate([seg_d, ray_d])
    B = np.concatenate([t.centre[tri_of[left]], ray_a + ray_d])
    # A segment runs to the left of v -> w, so its normal points from v to w; a
    # ray runs to the right (outwards), so its normal points from w to v.
    cells_a = np.concatenate([ea[left], eb[bnd]])
    cells_b = np.concatenate([eb[left], ea[bnd]])
    return A, D, B, cells_a, cells_b


def _clip_to_convex(A, D, corners, inward):
    """Cyrus-Beck: parameter range [s_lo, s_hi] in [0, 1] of A + s D inside the polygon."""
    n = A.shape[0]
    s_lo = np.zeros(n)
    s_hi = np.ones(n)
    side_lo = np.full(n, -1, dtype=np.int64)
    side_hi = np.full(n, -1, dtype=np.int64)
    chunk = max(1, 2_000_000 // max(1, corners.shape[0]))
    for start in range(0, n, chunk):
        sl = slice(start, min(n, start + chunk))
        num = ((A[sl, None, :] - corners[None, :, :]) * inward[None, :, :]).sum(axis=2)
        den = (D[sl, None, :] * inward[None, :, :]).sum(axis=2)
        with np.errstate(divide="ignore", invalid="ignore"):
            s = -num / den
        enter = np.where(den > 0, s, -np.inf)
        leave = np.where(den < 0, s, np.inf)
        parallel_out = (den == 0) & (num < 0)
        k_in = np.argmax(enter, axis=1)
        k_out = np.argmin(leave, axis=1)
        rows = np.arange(enter.shape[0])
        lo, hi = enter[rows, k_in], leave[rows, k_out]
        s_lo[sl] = np.maximum(0.0, lo)
        s_hi[sl] = np.minimum(1.0, hi)
        side_lo[sl] = k_in
        side_hi[sl] = k_out
        dead = parallel_out.any(axis=1)
        s_hi[sl] = np.where(dead, s_lo[sl], s_hi[sl])
    return s_lo, s_hi, side_lo, side_hi


def _distance_to_hull(p, corners, inward):
    """Distance of points inside a convex polygon to its boundary, and the nearest side."""
    d = np.empty(p.shape[0])
    k = np.empty(p.shape[0], dtype=np.int64)
    chunk = max(1, 2_000_000 // max(1, corners.shape[0]))
    for start in range(0, p.shape[0], chunk):
        sl = slice(start, min(p.shape[0], start + chunk))
        dist = ((p[sl, None, :] - corners[None, :, :]) * inward[None, :, :]).sum(axis=2)
        k[sl] = np.argmin(dist, axis=1)
        d[sl] = dist[np.arange(dist.shape[0]), k[sl]]
    return d, k


def _mrst_dual(t: _Triangulation, tol: float):
    """MRST's dual for non-convex triangulations (circumcentres must lie inside)."""
    xy, tri, nn = t.xy, t.tri, t.xy.shape[0]
    nt = tri.shape[0]
    ea, eb = t.ea.ravel(), t.eb.ravel()
    side = cross2(xy[t.eb] - xy[t.ea], t.centre[:, None, :] - xy[t.ea])
    bad_edge = (side < -tol * t.h * t.h) & t.on_boundary
    if np.any(bad_edge.sum(axis=1) > 1):
        raise GridError("pebi: a triangle's circumcentre lies outside two of its edges")
    bad_tri = bad_edge.any(axis=1)
    k_bad = np.argmax(bad_edge, axis=1)

    vert_xy = [t.centre]
    vert_of = np.repeat(np.arange(nt)[:, None], 3, axis=1)
    n_vert = nt
    bt = np.flatnonzero(bad_tri)
    kb = k_bad[bt]
    i1, i2, i3 = tri[bt, kb], tri[bt, (kb + 1) % 3], tri[bt, (kb + 2) % 3]
    if bt.size:
        c1 = _bisector_on_line(xy[i1], xy[i2], xy[i3])
        c2 = _bisector_on_line(xy[i2], xy[i1], xy[i3])
        c1_id = n_vert + np.arange(bt.size)
        c2_id = c1_id + bt.size
        vert_xy += [c1, c2]
        n_vert += 2 * bt.size
        vert_of[bt, (kb + 2) % 3] = c1_id  # edge i3 -> i1
        vert_of[bt, (kb + 1) % 3] = c2_id  # edge i2 -> i3
    vo = vert_of.ravel()
    left, right = t.hf_left, t.hf_right
    faces_a, faces_b = [vo[right]], [vo[left]]
    cells_a, cells_b = [ea[left]], [eb[left]]

    bnd = np.flatnonzero(t.on_boundary.ravel() & ~bad_edge.ravel())
    va, vb = ea[bnd], eb[bnd]
    mid_id = n_vert + np.arange(bnd.size)
    vert_xy.append(0.5 * (xy[va] + xy[vb]))
    n_vert += bnd.size
    all_b = np.flatnonzero(t.on_boundary.ravel())
    bnode = np.unique(np.concatenate([ea[all_b], eb[all_b]]))
    bnode_id = np.full(nn, -1, dtype=np.int64)
    bnode_id[bnode] = n_vert + np.arange(bnode.size)
    vert_xy.append(xy[bnode])
    faces_a += [mid_id, bnode_id[va], mid_id]
    faces_b += [vo[bnd], mid_id, bnode_id[vb]]
    cells_a += [va, va, vb]
    cells_b += [vb, np.full_like(va, -1), np.full_like(vb, -1)]
    if bt.size:
        faces_a += [bnode_id[i1], c1_id, c2_id]
        faces_b += [c1_id, c2_id, bnode_id[i2]]
        cells_a += [i1, i3, i2]
        cells_b += [np.full_like(i1, -1)] * 3
    coords = np.concatenate(vert_xy)
    fa, fb = np.concatenate(faces_a), np.concatenate(faces_b)
    ca, cb = np.concatenate(cells_a), np.concatenate(cells_b)
    return (coords, *_merge_collinear_boundary(coords, fa, fb, ca, cb, bnode_id[bnode], tol))


def _assemble(coords, fa, fb, ca, cb, n_sites, history) -> Grid:
    """Grid from 2-node faces; sites whose cells have fewer than 3 faces disappear."""
    nfaces = np.bincount(ca, minlength=n_sites) + np.bincount(cb[cb >= 0], minlength=n_sites)
    alive = nfaces >= 3
    if not alive.all():
        new_cell = np.cumsum(alive) - 1
        ca = np.where(alive[ca], new_cell[ca], -1)
        cb = np.where((cb >= 0) & alive[np.maximum(cb, 0)], new_cell[np.maximum(cb, 0)], -1)
        swap = ca < 0
        fa, fb = np.where(swap, fb, fa), np.where(swap, fa, fb)
        ca, cb = np.where(swap, cb, ca), np.where(swap, -1, cb)
        keep = ca >= 0
        fa, fb, ca, cb = fa[keep], fb[keep], ca[keep], cb[keep]
    used = np.zeros(coords.shape[0], dtype=bool)
    used[fa] = used[fb] = True
    new_node = np.cumsum(used) - 1
    neighbors = np.column_stack([ca, cb])
    face_pos, cell_faces = cell_faces_from_neighbors(neighbors, int(alive.sum()))
    nf = neighbors.shape[0]
    grid = Grid(
        cells=Cells(face_pos, cell_faces),
        faces=Faces(
            np.arange(0, 2 * nf + 1, 2), np.column_stack([new_node[fa], new_node[fb]]).ravel(), neighbors
        ),
        nodes=Nodes(coords[used]),
        griddim=2,
        history=(*history, "pebi"),
    )
    return order_cell_faces_2d(grid)


def _cell_areas(grid: Grid) -> np.ndarray:
    pos, cyc = cell_node_cycles_2d(grid)
    p = grid.nodes.coords[cyc] - grid.nodes.coords.mean(axis=0)
    owner = np.repeat(np.arange(grid.num_cells), np.diff(pos))
    nxt = np.arange(cyc.size) + 1
    nxt[pos[1:] - 1] = pos[:-1]
    return 0.5 * np.bincount(owner, cross2(p, p[nxt]), grid.num_cells)


def _bisector_on_line(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Point on line p -> q equidistant from p and r."""
    u = q - p
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    w = r - p
    s = (w * w).sum(axis=1) / (2.0 * (w * u).sum(axis=1))
    return p + s[:, None] * u


def _merge_collinear_boundary(coords, fa, fb, ca, cb, bnode_vertices, tol):
    """Join the two boundary pieces meeting at a boundary node where they are collinear."""
    bnd = cb < 0
    is_bnode = np.zeros(coords.shape[0], dtype=bool)
    is_bnode[bnode_vertices] = True
    incoming = np.flatnonzero(bnd & is_bnode[fb])
    outgoing = np.flatnonzero(bnd & is_bnode[fa])
    inc = incoming[np.argsort(fb[incoming])]
    out = outgoing[np.argsort(fa[outgoing])]
    if inc.size != out.size or np.any(fb[inc] != fa[out]):
        raise GridError("pebi: the triangulation's boundary is not a simple closed curve")
    d1 = coords[fb[inc]] - coords[fa[inc]]
    d2 = coords[fb[out]] - coords[fa[out]]
    cross = np.abs(cross2(d1, d2))
    scale = np.linalg.norm(d1, axis=1) * np.linalg.norm(d2, axis=1)
    straight = (cross <= tol * scale) & ((d1 * d2).sum(axis=1) > 0)
    fb = fb.copy()
    fb[inc[straight]] = fb[out[straight]]
    keep = np.ones(fa.size, dtype=bool)
    keep[out[straight]] = False
    return fa[keep], fb[keep], ca[keep], cb[keep]


def _representatives(coords: np.ndarray, radius: float) -> np.ndarray:
    """For every vertex, the lowest-numbered vertex within a chain of ``radius`` of it."""
    lowest, group = merge_close_points(coords, radius)
    return lowest[group]


def _merge_close_vertices(coords, fa, fb, radius):
    rep = _representatives(coords, radius)
    return rep[fa], rep[fb]
