"""Cell volumes and centroids, face areas, normals and centroids (MRST book §3.4).

Faces of 3-D grids are tessellated about their hinge point h (the mean of the
face's nodes) into triangles (p_k, p_k+1, h). A face's normal is the sum of the
triangle vector areas n_k, its area the sum of the triangle areas |n_k| (the
book's formula; ``|normal| <= area``, with equality for planar faces) and its
centroid the area-weighted mean of the triangle centroids. A triangle whose
n_k points against the face normal (the hinge lies outside a non-convex face)
counts with a negative area, so areas and centroids are exact for every planar
polygon, convex or not. Each cell is then split into
tetrahedra joining an apex x0 (the first node of its first face) to every face
triangle. Volumes are *signed* tetrahedron volumes with outward orientation, so
the cell volume is exactly the divergence-theorem volume of the hinge-tessellated
surface; no triangle is flipped (MRST and OPM flip triangles that point against
their face normal; that changes nothing for planar convex faces).

Because the offset d_k from the hinge to a triangle's centroid lies in the
triangle's plane, ``d_k . n_k = 0`` and the cell volume reduces to
``V = sum_f s_f (h_f - x0) . N_f / 3``. Only the centroid needs a per-triangle
sum, computed face by face in chunks. Nothing loops over cells.

2-D planar grids: faces are edges with normal (dy, -dx), length and midpoint;
cell areas and centroids come from signed triangles (x0, p_a, p_b), exact for
any simple polygon. 2-D surface grids in 3-D: cells use the hinge tessellation
of 3-D faces (same signed triangle areas), ``cell_normals`` holds their
vector areas, and a face (edge) normal is the in-surface vector ``e x n``
(n the mean unit normal of its cells), scaled to the edge length.

Units: metres in, m^3 (3-D) or m^2 (2-D) volumes, m^2 (3-D) or m (2-D) areas.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from functools import partial

import numpy as np

from .connectivity import half_face_cells
from .errors import GridError
from .grid import FloatArray, Grid
from .threads import in_order

_CHUNK = 1 << 14  # faces per vectorised block: temporaries stay in cache and are reused


@dataclass(frozen=True, eq=False)
class Geometry:
    """Geometric quantities of a grid; arrays are read-only."""

    cell_volumes: FloatArray  # (nc,) m^3, or m^2 for 2-D grids
    cell_centroids: FloatArray  # (nc, d)
    face_areas: FloatArray  # (nf,) m^2, or edge length in m for 2-D grids
    face_normals: FloatArray  # (nf, d) area-weighted, from neighbors[:,0] to [:,1]
    face_centroids: FloatArray  # (nf, d)
    cell_normals: FloatArray | None = None  # (nc, 3) vector areas, surface grids only

    def __post_init__(self) -> None:
        for name in (
            "cell_volumes",
            "cell_centroids",
            "face_areas",
            "face_normals",
            "face_centroids",
            "cell_normals",
        ):
            arr = getattr(self, name)
            if arr is not None:
                arr.flags.writeable = False


def compute_geometry(grid: Grid, *, face_centroids: bool = True) -> Geometry:
    """Geometry of a planar 2-D, surface or 3-D grid (see module docstring).
    ``face_centroids=False`` leaves a 3-D grid's face centroids empty (shape (0, 3)): a
    third less memory for a caller that does not use them (:func:`gridlib.checks.check_grid`);
    every other array has the same bits.

    >>> from gridlib import cart_grid
    >>> geo = compute_geometry(cart_grid([2, 1, 1], [2.0, 1.0, 3.0]))
    >>> geo.cell_volumes.tolist(), geo.face_areas[:3].tolist()
    ([3.0, 3.0], [3.0, 3.0, 3.0])
    """
    if grid.num_cells == 0:
        raise GridError("compute_geometry: the grid has no cells (every cell inactive or removed)")
    counts = _node_counts(grid.faces.node_pos)
    if grid.griddim == 3:
        if counts.min(initial=3) < 3:
            f = int(np.flatnonzero(counts < 3)[0])
            raise GridError(f"compute_geometry: face {f} has {counts[f]} nodes (3-D faces need >= 3)")
        del counts
        return _geometry_3d(grid, face_centroids)
    if np.any(counts != 2):
        f = int(np.flatnonzero(counts != 2)[0])
        raise GridError(f"compute_geometry: face {f} of a 2-D grid has {counts[f]} nodes (need 2)")
    if grid.dim == 2:
        return _geometry_planar(grid)
    return _geometry_surface(grid)


def _cell_apex(grid: Grid, coords_t: np.ndarray) -> np.ndarray:
    """(3|2, nc) apex per cell: the first node of the cell's first face."""
    first_face = grid.cells.faces[grid.cells.face_pos[:-1]]
    return np.take(coords_t, grid.faces.nodes[grid.faces.node_pos[first_face]], axis=1)


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product of component-major arrays (3, ...): a[0] is x of every vector."""
    return np.stack([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _face_blocks(grid: Grid):
    """Yield (face ids, node ids) blocks of k faces with m nodes each: the faces of every size m
    present, ascending, in increasing order, ``_CHUNK`` at a time. The node ids come as a function
    returning them, (m, k), so that they are gathered where the block is worked on."""
    pos = grid.faces.node_pos
    counts = _node_counts(pos)
    nodes = grid.faces.nodes
    if counts.size > 0 and np.all(counts == counts[0]):
        m = int(counts[0])
        table = nodes.reshape(-1, m)
        for start in range(0, counts.size, _CHUNK):
            stop = min(start + _CHUNK, counts.size)
            yield slice(start, stop), partial(_transposed, table[start:stop])
        return
    for m in _sizes_present(counts):
        for f in _faces_of_size(counts, m):
            if f[-1] - f[0] == f.size - 1:  # a run of consecutive faces: slices beat index arrays
                first = pos[f[0]]
                block = nodes[first : first + m * f.size].reshape(f.size, m)
                yield slice(int(f[0]), int(f[-1]) + 1), partial(_transposed, block)
            else:
                yield f, partial(_gathered, nodes, pos, f, int(m))


def _transposed(block: np.ndarray) -> np.ndarray:
    """(m, k) node ids of faces given as rows (k, m)."""
    return np.ascontiguousarray(block.T)


def _gathered(nodes: np.ndarray, pos: np.ndarray, f: np.ndarray, m: int) -> np.ndarray:
    """(m, k) node ids of the faces ``f`` with m nodes each."""
    return nodes[pos[f][None, :] + np.arange(m)[:, None]]


_WINDOW = 1 << 20  # faces scanned at a time for the faces of one size: no array of all faces


def _node_counts(pos: np.ndarray) -> np.ndarray:
    """The number of nodes of every face, in the smallest of uint8, int32 and int64 that holds them
    (an eighth of the memory of ``np.diff`` as a rule), computed a window at a time."""
    n = pos.size - 1
    windows = [slice(start, min(start + _WINDOW, n)) for start in range(0, n, _WINDOW)]
    top = max((int(np.max(pos[w.start + 1 : w.stop + 1] - pos[w])) for w in windows), default=0)
    counts = np.empty(n, dtype=next(t for t in (np.uint8, np.int32, np.int64) if top <= np.iinfo(t).max))
    for w in windows:
        np.subtract(pos[w.start + 1 : w.stop + 1], pos[w], out=counts[w], casting="unsafe")
    return counts


def _sizes_present(counts: np.ndarray) -> np.ndarray:
    """The face sizes that occur, ascending."""
    present = np.zeros(0, dtype=np.int64)
    for start in range(0, counts.size, _WINDOW):
        found = np.bincount(counts[start : start + _WINDOW])
        present = np.pad(present, (0, max(found.size - present.size, 0)))
        present[: found.size] += found
    return np.flatnonzero(present)


def _faces_of_size(counts: np.ndarray, m: int):
    """The faces with ``m`` nodes, ascending, in blocks of ``_CHUNK`` (the last one shorter):
    the blocks of ``np.flatnonzero(counts == m)``, found a window at a time."""
    carry = np.zeros(0, dtype=np.int64)
    for start in range(0, counts.size, _WINDOW):
        found = np.flatnonzero(counts[start : start + _WINDOW] == m)
        found += start
        ids = np.concatenate([carry, found]) if carry.size else found
        full = ids.size - ids.size % _CHUNK
        for begin in range(0, full, _CHUNK):
            yield ids[begin : begin + _CHUNK]
        carry = ids[full:]
    if carry.size:
        yield carry


def _geometry_3d(grid: Grid, with_face_centroids: bool = True) -> Geometry:
    """Hinge tessellation of 3-D faces; arrays are (3, m, k) blocks: component, node, face.

    The blocks of faces are tessellated on a few threads (numpy releases the GIL in its loops);
    their contributions are added to the cells' sums in block order, so the result does not depend
    on the number of threads.
    """
    nf, nc = grid.num_faces, grid.num_cells
    rows = np.zeros((grid.num_nodes, 4))
    rows[:, :3] = grid.nodes.coords
    first_face = grid.cells.faces[grid.cells.face_pos[:-1]]  # the apex, as _cell_apex: rows gather faster
    apex = np.take(rows, grid.faces.nodes[grid.faces.node_pos[first_face]], axis=0)
    x0 = np.ascontiguousarray(apex[:, :3].T)
    del first_face, apex
    nb = grid.faces.neighbors
    areas = np.empty(nf)
    normals = np.empty((3, nf))
    centroids = np.empty((3, nf if with_face_centroids else 0))
    sums = _CellSums(nc)  # volume, and first moment about the apex times 4/3

    def block(f: slice | np.ndarray, nodes_of) -> list[tuple]:
        """Write the areas, normals and centroids of a block's faces (node ids ``nodes_of()``);
        return the partial sums over the cells of each of its sides that has a cell."""
        ids = nodes_of()
        k = ids.shape[1]
        sides = []
        for side, sign in ((0, 1.0), (1, -1.0)):
            cell = nb[f, side]
            inside = cell >= 0
            if inside.any():  # outside sides get zero weight, on a cell of the block
                sides.append((np.where(inside, cell, cell[inside].min()), np.where(inside, sign / 6.0, 0.0)))
        dn = np.empty((len(sides), k))
        mom_w = np.empty((len(sides), 3, k))
        for start in range(0, k, _SUB):
            sub = slice(start, min(start + _SUB, k))
            faces = slice(f.start + sub.start, f.start + sub.stop) if isinstance(f, slice) else f[sub]
            h, n, N2, a, v = _hinge_triangles(rows, ids[:, sub])
            m, ks = a.shape
            tk = np.empty(ks)  # buffers: the per-face products go into them, not into new arrays
            tmk = np.empty((m, ks))
            A2 = a.sum(axis=0)
            areas[faces] = 0.5 * A2
            normals[:, faces] = 0.5 * N2
            if with_face_centroids:
                a3 = 3.0 * A2
                for i in range(3):
                    np.einsum("mk,mk->k", a, v[i], out=tk)
                    with np.errstate(invalid="ignore", divide="ignore"):
                        tk /= a3
                    centroids[i, faces] = np.add(h[i], tk, out=tk)
            for s, (cell, weight) in enumerate(sides):
                delta = np.take(x0, cell[sub], axis=1)  # (3, k)
                np.subtract(h, delta, out=delta)
                d = dn[s, sub]  # 2 (delta . N) ...
                np.multiply(delta[0], N2[0], out=d)
                for i in (1, 2):
                    np.multiply(delta[i], N2[i], out=tk)
                    d += tk
                w = np.multiply(n[0], delta[0])  # ... and 2 (delta . n_k)
                for i in (1, 2):
                    np.multiply(n[i], delta[i], out=tmk)
                    w += tmk
                d *= weight[sub]
                # sum_k V_k (c_k - x0) = s/3 [sum_k (delta . n_k) d_k + (delta . N) delta]
                w3 = weight[sub] / 3.0
                for i in range(3):
                    W = mom_w[s, i, sub]
                    np.einsum("mk,mk->k", w, v[i], out=W)  # 6 sum_k (delta . n_k) d_k
                    W *= w3
                    np.multiply(d, delta[i], out=tk)
                    W += tk
        return [sums.partial(cell, dn[s], mom_w[s]) for s, (cell, _) in enumerate(sides)]

    for parts in in_order(block, _face_blocks(grid), _MAX_THREADS):
        for part in parts:
            sums.add(*part)

    zero_area = areas <= 0.0
    if np.any(zero_area):
        fz = int(np.flatnonzero(zero_area)[0])
        raise GridError(
            f"compute_geometry: {int(zero_area.sum())} face(s) have zero area "
            f"(first: face {fz}); remove degenerate faces before computing geometry"
        )
    vol, mom = sums.vol, sums.mom
    with np.errstate(invalid="ignore", divide="ignore"):
        mom *= 0.75 / vol
    mom += x0
    # Vectors are stored component-major; the (n, 3) arrays are transposed views.
    return Geometry(vol, mom.T, areas, normals.T, centroids.T)


_SUB = 1 << 13  # faces per sub-block of the per-face arithmetic
_MAX_THREADS = 2  # blocks of faces tessellated at once (each block alone: the same result)


def _hinge_triangles(rows: np.ndarray, ids: np.ndarray):
    """The hinge tessellation of faces with nodes ``ids`` (m, k), node coordinates ``rows``
    (n_nodes, 4) (x, y, z and padding: one 32-byte row per node gathers fastest): hinges h (3, k),
    twice the triangle vector areas n (3, m, k) and their sum N2 (3, k), twice the (signed) triangle
    areas a (m, k), and 3 (triangle centroid - hinge) v (3, m, k)."""
    m, k = ids.shape
    q = np.take(rows, ids, axis=0)  # (m, k, 4) node coordinates ...
    hk = q.sum(axis=0)
    hk *= 1.0 / m  # ... hinge (k, 4) ...
    p = np.empty((3, m + 1, k))  # ... and node offsets from the hinge, component-major, the first
    for i in range(3):  # node's again at the end (a copy, not a second gather)
        np.subtract(q[:, :, i], hk[:, i], out=p[i, :m])
    p[:, m] = p[:, 0]
    del q
    h = np.ascontiguousarray(hk[:, :3].T)
    v, vn = p[:, :m], p[:, 1:]  # every node and the next one
    n = np.empty((3, m, k))  # twice the triangle vector areas v x vn
    tmp = np.empty((m, k))
    for i, j, r in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        np.multiply(v[j], vn[r], out=n[i])
        np.multiply(v[r], vn[j], out=tmp)
        n[i] -= tmp
    N2 = n.sum(axis=1)
    a = np.multiply(n[0], n[0])  # twice the areas (m, k)
    for i in (1, 2):
        np.multiply(n[i], n[i], out=tmp)
        a += tmp
    np.sqrt(a, out=a)
    # A triangle facing against the face normal (hinge outside a non-convex face)
    # counts negatively: exact area and centroid for any planar polygon.
    sign = np.multiply(n[0], N2[0])
    for i in (1, 2):
        np.multiply(n[i], N2[i], out=tmp)
        sign += tmp
    np.copysign(a, sign, out=a)
    c = v + vn  # 3 x (triangle centroid - hinge)
    return h, n, N2, a, c


class _CellSums:
    """Per-cell sums of face contributions, block by block: ``vol`` (nc,) and ``mom`` (3, nc).

    Every block adds its partial sums (its contributions to a cell, in face order) to the cells'
    totals. Over the block's range of cells when that is compact (structured numberings), else
    over the cells it touches only: the same partial sums either way. The partial sums of a block
    (:meth:`partial`) can be formed on any thread; :meth:`add` adds them, in block order.
    """

    def __init__(self, nc: int) -> None:
        self.vol = np.zeros(nc)
        self.mom = np.zeros((3, nc))
        self._local = threading.local()  # per thread: a representative entry of every cell (< _CHUNK)

    def partial(self, cell: np.ndarray, dn: np.ndarray, mom_w: np.ndarray) -> tuple:
        """The partial sums of the contributions ``dn`` (k,) and ``mom_w`` (3, k) of a block's
        faces to ``cell``: (the cells lo:hi as a slice, or the cells touched, in an array; their
        partial volumes; their partial moments (3, n))."""
        k = cell.size
        lo, hi = int(cell.min()), int(cell.max()) + 1
        if hi - lo <= 2 * k:
            local = cell - lo
            vol = np.bincount(local, dn, hi - lo)
            mom = np.empty((3, hi - lo))
            for i in range(3):
                mom[i] = np.bincount(local, mom_w[i], hi - lo)
            return slice(lo, hi), vol, mom
        rep_of = getattr(self._local, "rep", None)
        if rep_of is None:
            rep_of = np.zeros(self.vol.size, dtype=np.int16 if _CHUNK <= 1 << 15 else np.intp)
            self._local.rep = rep_of
        rep_of[cell] = np.arange(k)
        rep = rep_of[cell]  # the same entry for every entry of a cell
        first = np.flatnonzero(rep == np.arange(k))
        mom = np.empty((3, first.size))
        for i in range(3):
            mom[i] = np.bincount(rep, mom_w[i], k)[first]
        return cell[first], np.bincount(rep, dn, k)[first], mom

    def add(self, cells: slice | np.ndarray, vol: np.ndarray, mom: np.ndarray) -> None:
        """Add a block's partial sums (:meth:`partial`) to the cells' totals."""
        self.vol[cells] += vol
        self.mom[:, cells] += mom


def _edge_data(grid: Grid, ct: np.ndarray):
    ends = grid.faces.nodes.reshape(-1, 2)
    pa, pb = ct[:, ends[:, 0]], ct[:, ends[:, 1]]
    e = pb - pa
    length = np.sqrt(np.einsum("if,if->f", e, e))
    if np.any(length <= 0.0):
        f = int(np.flatnonzero(length <= 0.0)[0])
        raise GridError(f"compute_geometry: face {f} has zero length")
    return pa, pb, e, length, 0.5 * (pa + pb)


def _geometry_planar(grid: Grid) -> Geometry:
    nc = grid.num_cells
    ct = np.ascontiguousarray(grid.nodes.coords.T)
    _, _, e, length, mid = _edge_data(grid, ct)
    normals = np.stack([e[1], -e[0]])
    x0 = _cell_apex(grid, ct)
    hc = half_face_cells(grid)
    cf = grid.cells.faces
    sign = np.where(grid.faces.neighbors[cf, 0] == hc, 1.0, -1.0)
    delta = mid[:, cf] - x0[:, hc]
    tri_area = sign * np.einsum("ih,ih->h", delta, normals[:, cf]) / 2.0
    area = np.bincount(hc, tri_area, nc)
    mom = np.stack([np.bincount(hc, tri_area * delta[i], nc) for i in range(2)])
    with np.errstate(invalid="ignore", divide="ignore"):
        cent = x0 + (2.0 / 3.0) * mom / area
    return Geometry(area, cent.T.copy(), length, normals.T.copy(), mid.T.copy())


def _geometry_surface(grid: Grid) -> Geometry:
    nc = grid.num_cells
    ct = np.ascontiguousarray(grid.nodes.coords.T)
    _, _, e, length, mid = _edge_data(grid, ct)
    hc = half_face_cells(grid)
    cf = grid.cells.faces
    forward = grid.faces.neighbors[cf, 0] == hc
    ends = grid.faces.nodes.reshape(-1, 2)
    a = np.where(forward, ends[cf, 0], ends[cf, 1])
    b = np.where(forward, ends[cf, 1], ends[cf, 0])
    counts = grid.cells.num_faces
    # Hinge of each cell: the mean of its edge midpoints (= mean of its nodes).
    hinge = np.stack([np.bincount(hc, mid[i, cf], nc) for i in range(3)]) / counts
    va = ct[:, a] - hinge[:, hc]
    vb = ct[:, b] - hinge[:, hc]
    n = 0.5 * cross(va, vb)
    vec_area = np.stack([np.bincount(hc, n[i], nc) for i in range(3)])
    tri_a = np.sqrt(np.einsum("ih,ih->h", n, n))
    np.copysign(tri_a, np.einsum("ih,ih->h", n, vec_area[:, hc]), out=tri_a)
    area = np.bincount(hc, tri_a, nc)
    d = (va + vb) / 3.0
    with np.errstate(invalid="ignore", divide="ignore"):
        cent = hinge + np.stack([np.bincount(hc, tri_a * d[i], nc) for i in range(3)]) / area
        unit = vec_area / np.sqrt(np.einsum("ic,ic->c", vec_area, vec_area))
    nb = grid.faces.neighbors
    mean_normal = np.zeros_like(e)
    for side in (0, 1):
        cell = nb[:, side]
        mean_normal += np.where(cell >= 0, unit[:, np.maximum(cell, 0)], 0.0)
    fn = cross(e, mean_normal)
    with np.errstate(invalid="ignore", divide="ignore"):
        fn *= length / np.sqrt(np.einsum("if,if->f", fn, fn))
    return Geometry(area, cent.T.copy(), length, fn.T.copy(), mid.T.copy(), vec_area.T.copy())
