"""Unstructured builders: ``triangle_grid``, ``tessellation_grid``, ``tetrahedral_grid``.

2-D cells are polygons given by their node cycles. Each cell is oriented
counter-clockwise in (x, y) (planar grids) or consistently across the surface
(3-D surface grids, solved as a parity problem on the cell graph). Faces are
the unique node pairs, stored as the sorted pair ``(lo, hi)``, numbered in
lexicographic order; the cell that traverses a face from lo to hi is
``neighbors[f, 0]`` (as MRST's ``triangleGrid``).

Tetrahedra are oriented to positive volume; faces are the unique node triples,
stored sorted, and the cell whose outward orientation is the even permutation
of the sorted triple is ``neighbors[f, 0]``. Delaunay tetrahedralisations of
degenerate points (lattices, layers at exact depths: co-spherical sets) have
no tetrahedron of zero volume: Qhull's flat ones on the hull are dropped, and
points whose Delaunay cells Qhull glues with flat ones inside are
tetrahedralised again with the ties broken by a tiny deterministic lift.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike
from scipy import sparse
from scipy.sparse import csgraph
from scipy.spatial import ConvexHull, Delaunay, QhullError, cKDTree

from .connectivity import offsets, repeat_ids
from .errors import GridError
from .grid import Cells, Faces, Grid, IntArray, Nodes


def _points(points: ArrayLike, dims: tuple[int, ...], what: str, min_count: int) -> np.ndarray:
    try:  # a private copy: the grid owns its coordinates (made read-only)
        p = np.array(points, dtype=np.float64, copy=True)
    except (TypeError, ValueError) as exc:
        raise GridError(f"{what}: points must be a numeric (n, d) array") from exc
    if p.ndim != 2 or p.shape[1] not in dims:
        raise GridError(f"{what}: points must have shape (n, {' or '.join(map(str, dims))}), got {p.shape}")
    if p.shape[0] < min_count:
        raise GridError(f"{what}: need at least {min_count} points, got {p.shape[0]}")
    if not np.all(np.isfinite(p)):
        bad = int(np.flatnonzero(~np.isfinite(p).all(axis=1))[0])
        raise GridError(f"{what}: point {bad} is NaN or infinite")
    return p


def _reject_duplicates(p: np.ndarray, what: str) -> None:
    _, first, counts = np.unique(p, axis=0, return_index=True, return_counts=True)
    if np.any(counts > 1):
        dup = p[first[counts > 1][0]]
        idx = np.flatnonzero((p == dup).all(axis=1))
        raise GridError(f"{what}: duplicate points {idx.tolist()} at {dup.tolist()}")


def _delaunay(p: np.ndarray, what: str) -> np.ndarray:
    """Delaunay triangles of planar points, without Qhull's slivers along the hull.

    Points that should be collinear on the hull (a rotated lattice at UTM
    coordinates, say) are off the line by round-off, and Qhull joins them with
    triangles of height ~1e-9 m whose circumcentres lie far away. Triangles
    thinner than 1e-8 of their longest edge that are reachable from the hull
    through such triangles are removed (they enclose no area); truly degenerate
    triangles elsewhere are caught by the zero-area check of ``polygon_grid``.
    """
    local = p - p.mean(axis=0)
    scale = np.abs(local).max()
    if scale == 0:
        raise GridError(f"{what}: all points coincide")
    try:
        dl = Delaunay(local / scale)
    except QhullError as exc:
        raise GridError(f"{what}: cannot triangulate the points (all collinear?)") from exc
    if dl.coplanar.size:
        raise GridError(f"{what}: points {dl.coplanar[:, 0].tolist()} were left out by Qhull")
    tri = dl.simplices.astype(np.int64)
    a, b, c = local[tri[:, 0]], local[tri[:, 1]], local[tri[:, 2]]
    area2 = np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    edges2 = np.stack([((b - a) ** 2).sum(1), ((c - b) ** 2).sum(1), ((a - c) ** 2).sum(1)])
    thin = area2 <= 1e-8 * edges2.max(axis=0)  # height <= 2e-8 x the longest edge
    if not thin.any():
        return tri
    return tri[~_peel_from_hull(thin, dl.neighbors)]


def _peel_from_hull(degenerate: np.ndarray, neighbors: np.ndarray) -> np.ndarray:
    """Degenerate simplices reachable from the hull through degenerate ones (Qhull neighbours)."""
    gone = np.zeros(degenerate.size, dtype=bool)
    while True:  # one pass per layer of slivers: a handful, each vectorised
        touch = ((neighbors < 0) | (gone[np.maximum(neighbors, 0)] & (neighbors >= 0))).any(axis=1)
        new = degenerate & ~gone & touch
        if not new.any():
            return gone
        gone |= new


def _index_table(cells: ArrayLike | Sequence[Sequence[int]], n_points: int, what: str):
    """(pos, nodes) of a ragged cell list given as an (n, m) array (-1 padded) or lists."""
    if isinstance(cells, np.ndarray) or (
        isinstance(cells, Sequence) and cells and all(len(c) == len(cells[0]) for c in cells)
    ):
        arr = np.asarray(cells)
        if arr.ndim != 2:
            raise GridError(f"{what}: cells must be an (n, m) array or a list of node lists")
        if np.issubdtype(arr.dtype, np.floating):
            arr = np.where(np.isnan(arr), -1, arr)
            if np.any(arr != np.round(arr)):
                raise GridError(f"{what}: cell node indices must be integers")
        elif not np.issubdtype(arr.dtype, np.integer):
            raise GridError(f"{what}: cell node indices must be integers, got {arr.dtype} values")
        arr = arr.astype(np.int64)
        if np.any(arr < -1):
            raise GridError(f"{what}: node index {int(arr[arr < -1][0])} out of range (-1 pads short rows)")
        valid = arr >= 0
        counts = valid.sum(axis=1)
        nodes = arr[valid]
    else:
        try:
            lists = [np.asarray(c).ravel() for c in cells]
            if any(c.size and not np.issubdtype(c.dtype, np.integer) for c in lists):
                raise TypeError("non-integer node index")
            lists = [c.astype(np.int64) for c in lists]
        except (TypeError, ValueError) as exc:
            raise GridError(f"{what}: cells must be lists of integer node indices") from exc
        counts = np.array([c.size for c in lists], dtype=np.int64)
        nodes = np.concatenate(lists) if lists else np.zeros(0, np.int64)
    if counts.size == 0:
        raise GridError(f"{what}: no cells given")
    if np.any(nodes >= n_points) or np.any(nodes < 0):
        bad = nodes[(nodes >= n_points) | (nodes < 0)][0]
        raise GridError(f"{what}: node index {bad} out of range (there are {n_points} points)")
    return offsets(counts), nodes


def _require_all_used(nodes: IntArray, n_points: int, what: str) -> None:
    used = np.zeros(n_points, dtype=bool)
    used[nodes] = True
    if not used.all():
        unused = np.flatnonzero(~used)
        raise GridError(
            f"{what}: points {unused[:10].tolist()} are used by no cell; pass only the points the cells use"
        )


def _reverse_segments(pos: IntArray, nodes: IntArray, flip: np.ndarray) -> IntArray:
    """Reverse the node order of the flagged segments of a ragged list."""
    owner = repeat_ids(pos)
    local = np.arange(nodes.size) - pos[owner]
    length = np.diff(pos)[owner]
    src = np.where(flip[owner], pos[owner] + length - 1 - local, np.arange(nodes.size))
    return nodes[src]


def _directed_edges(pos: IntArray, nodes: IntArray) -> tuple[IntArray, IntArray]:
    idx = np.arange(nodes.size)
    nxt = idx + 1
    nxt[pos[1:] - 1] = pos[:-1]
    return nodes, nodes[nxt]


def _unique_keys(lo: IntArray, hi: IntArray, n_points: int) -> tuple[IntArray, IntArray]:
    """Unique (lo, hi) pairs in lexicographic order and the inverse map."""
    key = lo * n_points + hi
    uniq, inverse = np.unique(key, return_inverse=True)
    return uniq, inverse.reshape(-1)


def _neighbors_of_faces(face_of: IntArray, column: IntArray, cell: IntArray, nf: int) -> tuple[IntArray, int]:
    """(nf, 2) neighbours from half-faces that know their column; also the first face
    claimed twice for one column (overlapping or folded cells), or -1."""
    claims = np.bincount(face_of * 2 + column, minlength=2 * nf)
    twice = np.flatnonzero(claims > 1)
    neighbors = np.full((nf, 2), -1, dtype=np.int64)
    neighbors[face_of, column] = cell
    return neighbors, int(twice[0] // 2) if twice.size else -1


def polygon_grid(coords: np.ndarray, pos: IntArray, nodes: IntArray, history: str, what: str) -> Grid:
    """A 2-D grid from polygons (node cycles); orients them and builds faces."""
    n_points = coords.shape[0]
    counts = np.diff(pos)
    if np.any(counts < 3):
        c = int(np.flatnonzero(counts < 3)[0])
        raise GridError(f"{what}: cell {c} has {counts[c]} nodes (a polygon needs >= 3)")
    _reject_duplicate_cells(pos, nodes, what)
    a, b = _directed_edges(pos, nodes)
    if np.any(a == b):
        c = int(repeat_ids(pos)[np.flatnonzero(a == b)[0]])
        raise GridError(f"{what}: cell {c} repeats a node")
    if coords.shape[1] == 2:
        local = coords - coords.mean(axis=0)  # shoelace products lose digits at UTM sizes
        area2 = np.bincount(repeat_ids(pos), local[a, 0] * local[b, 1] - local[b, 0] * local[a, 1])
        scale = np.ptp(coords, axis=0).max() ** 2
        flat = np.abs(area2) <= 1e-14 * scale
        if np.any(flat):
            c = int(np.flatnonzero(flat)[0])
            raise GridError(f"{what}: cell {c} has zero area (its nodes are collinear)")
        flip = area2 < 0
    else:
        flip = _surface_orientation(pos, nodes, n_points, what)
    if np.any(flip):
        nodes = _reverse_segments(pos, nodes, flip)
        a, b = _directed_edges(pos, nodes)

    forward = a < b
    lo, hi = np.where(forward, a, b), np.where(forward, b, a)
    uniq, face_of = _unique_keys(lo, hi, n_points)
    nf = uniq.size
    owner = repeat_ids(pos)
    neighbors, f = _neighbors_of_faces(face_of, np.where(forward, 0, 1), owner, nf)
    if f >= 0:
        raise GridError(
            f"{what}: edge ({uniq[f] // n_points}, {uniq[f] % n_points}) is shared by more than two "
            "cells or by two cells with the same orientation (overlapping or folded cells?)"
        )
    face_nodes = np.column_stack([uniq // n_points, uniq % n_points]).ravel()
    return Grid(
        cells=Cells(pos, face_of),
        faces=Faces(np.arange(0, 2 * nf + 1, 2), face_nodes, neighbors),
        nodes=Nodes(coords),
        griddim=2,
        history=(history,),
    )


def _reject_duplicate_cells(pos: IntArray, nodes: IntArray, what: str) -> None:
    """Two cells with the same node set would overlap: reject them."""
    counts = np.diff(pos)
    owner = repeat_ids(pos)
    order = np.lexsort((nodes, owner))
    table = np.full((counts.size, int(counts.max()) + 1), -1, dtype=np.int64)
    table[:, 0] = counts
    table[owner[order], 1 + np.arange(nodes.size) - pos[owner[order]]] = nodes[order]
    _, first, inverse = np.unique(table, axis=0, return_index=True, return_inverse=True)
    dup = np.flatnonzero(first[inverse.reshape(-1)] != np.arange(counts.size))
    if dup.size:
        c = int(dup[0])
        raise GridError(f"{what}: cells {int(first[inverse.reshape(-1)[c]])} and {c} have the same nodes")


def _surface_orientation(pos: IntArray, nodes: IntArray, n_points: int, what: str) -> np.ndarray:
    """Flip flags making the polygons of a surface consistently oriented.

    Two cells sharing an edge are consistent when they traverse it in opposite
    directions. On a doubled graph, vertex c means "cell c as given" and c + nc
    "cell c flipped"; a consistent pair links (u, v) and (u+nc, v+nc), an
    inconsistent one (u, v+nc) and (u+nc, v). The surface is orientable iff no
    cell is linked to its own flip; in every connected piece the component
    holding its first cell as given keeps its orientation.
    """
    a, b = _directed_edges(pos, nodes)
    owner = repeat_ids(pos)
    forward = a < b
    lo, hi = np.where(forward, a, b), np.where(forward, b, a)
    _, face_of = _unique_keys(lo, hi, n_points)
    order = np.argsort(face_of, kind="stable")
    fsorted = face_of[order]
    pair = np.flatnonzero(fsorted[1:] == fsorted[:-1])
    u, v = owner[order[pair]], owner[order[pair + 1]]
    flip_link = (forward[order[pair]] == forward[order[pair + 1]]).astype(np.int64)
    nc = pos.size - 1
    rows = np.concatenate([u, u + nc])
    cols = np.concatenate([v + flip_link * nc, v + (1 - flip_link) * nc])
    graph = sparse.coo_matrix((np.ones(rows.size), (rows, cols)), shape=(2 * nc, 2 * nc))
    _, label = csgraph.connected_components(graph, directed=False)
    as_given, flipped = label[:nc], label[nc:]
    if np.any(as_given == flipped):
        c = int(np.flatnonzero(as_given == flipped)[0])
        raise GridError(f"{what}: the surface cannot be oriented consistently (non-orientable near cell {c})")
    piece = np.minimum(as_given, flipped)  # the same for both orientations of a piece
    _, first = np.unique(piece, return_index=True)
    keep_label = np.empty(label.max() + 1, dtype=np.int64)
    keep_label[piece[first]] = as_given[first]
    return as_given != keep_label[piece]


def triangle_grid(points: ArrayLike, triangles: ArrayLike | None = None) -> Grid:
    """2-D grid of triangles: planar ((n, 2) points) or a surface in 3-D ((n, 3) points).

    Without ``triangles`` the Delaunay triangulation of the points (of their
    (x, y) projection for 3-D points) is used. Faces are the sorted node pairs
    in lexicographic order, as MRST's ``triangleGrid``.

    >>> g = triangle_grid([[0, 0], [1, 0], [0, 1], [1, 1]])
    >>> g.num_cells, g.num_faces, g.num_nodes
    (2, 5, 4)
    """
    p = _points(points, (2, 3), "triangle_grid", 3)
    if triangles is None:
        _reject_duplicates(p[:, :2], "triangle_grid")
        tri = _delaunay(p[:, :2], "triangle_grid")
    else:
        tri = np.asarray(triangles)
        if tri.ndim != 2 or tri.shape[1] != 3:
            raise GridError(f"triangle_grid: triangles must have shape (n, 3), got {tri.shape}")
    pos, nodes = _index_table(tri, p.shape[0], "triangle_grid")
    _require_all_used(nodes, p.shape[0], "triangle_grid")
    if p.shape[1] == 3:
        _reject_degenerate_triangles(p, nodes.reshape(-1, 3))
    return polygon_grid(p, pos, nodes, "triangle_grid", "triangle_grid")


def _reject_degenerate_triangles(p: np.ndarray, tri: np.ndarray) -> None:
    e1 = p[tri[:, 1]] - p[tri[:, 0]]
    e2 = p[tri[:, 2]] - p[tri[:, 0]]
    area = np.linalg.norm(np.cross(e1, e2), axis=1)
    scale = np.ptp(p, axis=0).max() ** 2
    flat = area <= 1e-14 * scale
    if np.any(flat):
        raise GridError(f"triangle_grid: triangle {int(np.flatnonzero(flat)[0])} has zero area")


def tessellation_grid(points: ArrayLike, cells: ArrayLike | Sequence[Sequence[int]]) -> Grid:
    """2-D grid from polygons given by node cycles (MRST's ``tessellationGrid``).

    ``cells`` is an (n, m) integer array (rows padded with -1 or NaN for
    polygons with fewer than m nodes) or a list of node lists. Polygons may be
    listed clockwise or counter-clockwise; they are oriented for you.
    """
    p = _points(points, (2, 3), "tessellation_grid", 3)
    pos, nodes = _index_table(cells, p.shape[0], "tessellation_grid")
    _require_all_used(nodes, p.shape[0], "tessellation_grid")
    return polygon_grid(p, pos, nodes, "tessellation_grid", "tessellation_grid")


def _signed_volume6(p: np.ndarray, tet: np.ndarray) -> np.ndarray:
    d1, d2, d3 = (p[tet[:, i]] - p[tet[:, 0]] for i in (1, 2, 3))
    return np.einsum("ij,ij->i", np.cross(d1, d2), d3)


def _delaunay_tetrahedra(p: np.ndarray, scale: float) -> np.ndarray:
    """Delaunay tetrahedra without zero-volume ones.

    Co-spherical points (lattices, layers at exact depths) make Qhull
    triangulate merged Delaunay cells with flat "glue" tetrahedra. Those lying
    in a hull plane (reachable from the hull through other flat ones) have no
    volume and no interior neighbour pair to reconnect, so they are dropped.
    Flat ones inside the domain glue two incompatible triangulations of a
    planar polygon (a box corner's rectangle, say); then the points are
    triangulated again with the ties broken (:func:`_lifted_tetrahedra`),
    which makes none inside the domain.
    """
    local = (p - p.mean(axis=0)) / np.abs(p - p.mean(axis=0)).max()
    try:
        dl = Delaunay(local)
    except QhullError as exc:
        raise GridError("tetrahedral_grid: cannot tetrahedralise the points (all coplanar?)") from exc
    tet, neighbors = dl.simplices.astype(np.int64), dl.neighbors
    flat = np.abs(_signed_volume6(p, tet)) <= 1e-13 * scale
    gone = _peel_from_hull(flat, neighbors)
    if np.any(flat & ~gone):
        tet, neighbors = _lifted_tetrahedra(p, local)
        flat = np.abs(_signed_volume6(p, tet)) <= 1e-13 * scale
        gone = _peel_from_hull(flat, neighbors)
    if np.any(flat & ~gone):
        raise GridError(
            f"tetrahedral_grid: the points are degenerate: Delaunay gives {int((flat & ~gone).sum())} "
            "zero-volume tetrahedra inside the domain; pass the tetrahedra"
        )
    return tet[~gone]


def _lifted_tetrahedra(p: np.ndarray, local: np.ndarray) -> tuple[IntArray, IntArray]:
    """Delaunay tetrahedra of co-spherical points with the ties broken: (tetrahedra, neighbours).

    The Delaunay tetrahedra are the lower facets of the convex hull of the
    points lifted onto the paraboloid h = |x|^2 (in 4-D). Co-spherical points
    lift onto one hyperplane, where Qhull's triangulated output glues
    incompatible triangulations with flat tetrahedra. Here the lift of point i
    gets a tiny extra height eps_i * w_i: w_i in [0, 1) a hash of the bits of
    its coordinates (deterministic, machine- and order-independent), eps_i =
    2^-16 d_i^2 with d_i its distance to the nearest other point (normalised
    coordinates). That is a regular triangulation with generic weights:

    * no lower facet is flat: four coplanar points lift onto a vertical
      hyperplane, which is never a lower facet (only the hull's own planes,
      whose flat tetrahedra are peeled as before);
    * no point is left out: the lower hull of the other points lies at least
      d_i^2 above point i's lift (over a simplex of others containing x, the
      interpolant of |q|^2 exceeds |x|^2 by sum(lambda_k |q_k - x|^2)), more
      than eps_i;
    * it is the Delaunay tetrahedralisation wherever that is unique (lift
      differences of order d^2, against 2^-16 d^2), and cuts every cell of
      co-spherical points into proper tetrahedra once; eps_i is still some
      1e6 times the round-off of the lift for points 1e-5 of the extent apart.

    Only the connectivity is taken: the grid keeps the exact coordinates.
    Neighbours as Qhull's (across from vertex k; -1 on the hull).
    """
    nearest = cKDTree(local).query(local, k=2)[0][:, 1]
    lift = local[:, 0] ** 2 + local[:, 1] ** 2 + local[:, 2] ** 2
    lifted = np.column_stack([local, lift + np.ldexp(nearest * nearest, -16) * _unit_hash(p)])
    try:
        hull = ConvexHull(lifted)
    except QhullError as exc:
        raise GridError("tetrahedral_grid: cannot tetrahedralise the points (all coplanar?)") from exc
    lower = hull.equations[:, 3] < 0
    index = np.where(lower, np.cumsum(lower) - 1, -1)
    tet = hull.simplices[lower].astype(np.int64)
    neighbors = index[hull.neighbors[lower]]
    missing = np.setdiff1d(np.arange(p.shape[0]), tet)
    if missing.size:
        raise GridError(f"tetrahedral_grid: points {missing[:5].tolist()} were left out by Qhull")
    return tet, neighbors


def _unit_hash(p: np.ndarray) -> np.ndarray:
    """A number in [0, 1) per row of ``p``, mixed from the bits of its coordinates (splitmix64)."""
    bits = np.ascontiguousarray(p, dtype=np.float64).view(np.uint64)
    h = np.zeros(p.shape[0], dtype=np.uint64)
    for d in range(p.shape[1]):  # three columns
        h ^= bits[:, d] + np.uint64((0x9E3779B97F4A7C15 * (d + 1)) % 2**64)
        h ^= h >> np.uint64(30)
        h *= np.uint64(0xBF58476D1CE4E5B9)
        h ^= h >> np.uint64(27)
        h *= np.uint64(0x94D049BB133111EB)
        h ^= h >> np.uint64(31)
    return np.ldexp((h >> np.uint64(11)).astype(np.float64), -53)


_TET_FACES = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def tetrahedral_grid(points: ArrayLike, tetrahedra: ArrayLike | None = None) -> Grid:
    """3-D grid of tetrahedra; Delaunay tetrahedralisation of ``points`` if none given.

    Degenerate points are fine (see the module docstring): the seed's Fig. 3.8
    example, a lattice with exact z-levels, unperturbed box faces and
    perturbed interior x, y, fills its box exactly.

    >>> g = tetrahedral_grid([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]])
    >>> g.num_cells, g.num_faces, g.num_nodes
    (1, 4, 4)
    """
    p = _points(points, (3,), "tetrahedral_grid", 4)
    extent = np.ptp(p, axis=0).max()
    scale = extent * extent * extent
    if tetrahedra is None:
        _reject_duplicates(p, "tetrahedral_grid")
        tet = _delaunay_tetrahedra(p, scale)
    else:
        tet = np.asarray(tetrahedra)
        if tet.size == 0:
            raise GridError("tetrahedral_grid: no tetrahedra given")
        if tet.ndim != 2 or tet.shape[1] != 4:
            raise GridError(f"tetrahedral_grid: tetrahedra must have shape (n, 4), got {tet.shape}")
        if not np.issubdtype(tet.dtype, np.integer):
            raise GridError("tetrahedral_grid: tetrahedra must hold integer node indices")
        tet = tet.astype(np.int64)
        if tet.min() < 0 or tet.max() >= p.shape[0]:
            raise GridError(f"tetrahedral_grid: node index out of range (there are {p.shape[0]} points)")
        _require_all_used(tet.ravel(), p.shape[0], "tetrahedral_grid")
    vol6 = _signed_volume6(p, tet)
    flat = np.abs(vol6) <= 1e-13 * scale
    if np.any(flat):
        raise GridError(
            f"tetrahedral_grid: {int(flat.sum())} tetrahedra have zero volume "
            f"(first: {int(np.flatnonzero(flat)[0])})"
        )
    tet = np.where((vol6 < 0)[:, None], tet[:, [0, 2, 1, 3]], tet)

    nt = tet.shape[0]
    tri = tet[:, _TET_FACES].reshape(-1, 3)  # outward triangles, 4 per tetrahedron
    srt = np.sort(tri, axis=1)
    # Even permutation of the sorted triple <=> the outward normal is the sorted one's.
    rot = np.argmin(tri, axis=1)
    second = tri[np.arange(tri.shape[0]), (rot + 1) % 3]
    even = second == srt[:, 1]
    n = p.shape[0]
    if n**3 < 2**62:  # machine-independent: Python integers
        key = (srt[:, 0] * n + srt[:, 1]) * n + srt[:, 2]
        uniq, face_of = np.unique(key, return_inverse=True)
        face_nodes = np.column_stack([uniq // (n * n), (uniq // n) % n, uniq % n])
    else:
        face_nodes, face_of = np.unique(srt, axis=0, return_inverse=True)
    face_of = face_of.reshape(-1)
    nf = face_nodes.shape[0]
    neighbors, f = _neighbors_of_faces(face_of, np.where(even, 0, 1), np.repeat(np.arange(nt), 4), nf)
    if f >= 0:
        raise GridError(
            f"tetrahedral_grid: face {face_nodes[f].tolist()} is shared by overlapping tetrahedra"
        )
    return Grid(
        cells=Cells(np.arange(0, 4 * nt + 1, 4), face_of),
        faces=Faces(np.arange(0, 3 * nf + 1, 3), face_nodes.ravel(), neighbors),
        nodes=Nodes(p),
        griddim=3,
        history=("tetrahedral_grid",),
    )
