"""Coarse grids: partitions of the fine cells into blocks, the coarse grid, upscaled rock.

A *partition* is one block number per fine cell (0-based). The steps follow
MRST's coarse-grid module (``partitionUI``, ``partitionMETIS``,
``processPartition``, ``generateCoarseGrid``, ``coarsenGeometry``, ``upPoro``,
``upAbsPermAvg``), vectorised:

* :func:`partition_ui`: uniform blocks in logical (i, j, k) index space, or,
  for layered (2.5D) grids, in areal position and layer;
* :func:`partition_metis`: METIS (pymetis) on the cell graph, with integer face
  weights from transmissibility-like values and cell weights (e.g. pore volume);
* :func:`process_partition`: blocks that are not connected are split;
  :func:`compress_partition` numbers the non-empty blocks 0..nb-1 (an empty
  block simply disappears: it has no cell to carry it);
* :func:`coarse_grid`: a :class:`CoarseGrid` whose ``grid`` is an ordinary
  :class:`~gridlib.grid.Grid` (cells = blocks, faces = the fine faces between
  blocks and on the boundary, so it can be written to netCDF/VTU like any
  grid), the *coarse faces* (the fine faces grouped by the pair of blocks they
  separate; outer boundary faces also by the fine half-face direction W/E/S/N/T/B
  where the grid has it), and the coarse geometry;
* :func:`upscale_porosity`, :func:`upscale_ntg` (bulk-volume weighted, so pore
  volume is conserved) and :func:`upscale_permeability` (arithmetic, harmonic,
  geometric, or harmonic-arithmetic per direction).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy import sparse
from scipy.sparse import csgraph

from .connectivity import cell_faces_from_neighbors, offsets, repeat_ids
from .errors import InputError
from .geometry import Geometry, compute_geometry
from .grid import Cells, Faces, FloatArray, Grid, IntArray, Nodes
from .reproducible import exp, log, log10

__all__ = [
    "CoarseFaces",
    "CoarseGeometry",
    "CoarseGrid",
    "coarse_grid",
    "compress_partition",
    "partition_metis",
    "partition_ui",
    "process_partition",
    "upscale_ntg",
    "upscale_permeability",
    "upscale_porosity",
]


# --- partitions ------------------------------------------------------------------------------


def _uniform_blocks(index: IntArray, n_blocks: int, axis: str) -> IntArray:
    """MRST's partitionUI along one axis: the first R blocks get L + 1 cells, the rest L.

    The extent is that of the indices present (not of the logical box), so a
    grid with cells removed along its edges still gets blocks of equal size.
    """
    lo, hi = int(index.min()), int(index.max())
    m = hi - lo + 1
    if n_blocks > m:
        raise InputError(f"partition_ui: {n_blocks} blocks along {axis}, but only {m} cells there")
    f = index - lo
    size, rest = divmod(m, n_blocks)
    return np.maximum(f // (size + 1), (f - rest) // size)


def partition_ui(grid: Grid, coarse_dims: ArrayLike, geometry: Geometry | None = None) -> IntArray:
    """Uniform blocks: ``coarse_dims`` blocks per logical axis (i fastest in the block number).

    Logically Cartesian grids (``cells.index_map`` and ``cart_dims``) are cut
    in index space. Layered grids (``grid.layering``) are cut in areal
    position (the areal cells' centroids, binned uniformly over their bounding
    box, ``coarse_dims[:2]``) and in layer (``coarse_dims[2]``). Blocks that get
    no cell leave gaps in the numbering: pass the result to
    :func:`compress_partition` (or :func:`process_partition`) to renumber.

    >>> from gridlib import cart_grid
    >>> partition_ui(cart_grid([4, 2]), [2, 1]).tolist()
    [0, 0, 1, 1, 0, 0, 1, 1]
    """
    dims = np.asarray(coarse_dims, dtype=np.int64).ravel()
    if np.any(dims < 1):
        raise InputError(f"partition_ui: coarse_dims must be positive integers, got {list(coarse_dims)}")
    if grid.cells.index_map is not None and grid.cart_dims is not None:
        cart = tuple(int(d) for d in grid.cart_dims)
        if dims.size != len(cart):
            raise InputError(f"partition_ui: coarse_dims needs {len(cart)} values for a {len(cart)}-D grid")
        ijk = np.unravel_index(grid.cells.index_map, cart[::-1])[::-1]  # (i, j[, k])
        axes = "ijk"
        blocks = [_uniform_blocks(np.asarray(ijk[a]), int(dims[a]), axes[a]) for a in range(dims.size)]
        part = np.zeros(grid.num_cells, dtype=np.int64)
        for a in reversed(range(dims.size)):
            part = part * dims[a] + blocks[a]
        return part
    if grid.layering is not None:
        if dims.size != 3:
            raise InputError("partition_ui: coarse_dims needs 3 values (x, y, layer) for a layered grid")
        areal = grid.layering.areal
        centres = compute_geometry(areal).cell_centroids[:, :2]
        c = centres[grid.layering.column]
        lo, hi = centres.min(axis=0), centres.max(axis=0)
        span = np.where(hi > lo, hi - lo, 1.0)
        bx = np.minimum(((c[:, 0] - lo[0]) / span[0] * dims[0]).astype(np.int64), dims[0] - 1)
        by = np.minimum(((c[:, 1] - lo[1]) / span[1] * dims[1]).astype(np.int64), dims[1] - 1)
        bz = _uniform_blocks(grid.layering.layer, int(dims[2]), "layer")
        return bx + dims[0] * (by + dims[1] * bz)
    raise InputError(
        "partition_ui: the grid has neither logical indices (cells.index_map, cart_dims) nor a layering; "
        "use partition_metis"
    )


def _check_partition(grid: Grid, partition: ArrayLike, what: str) -> IntArray:
    p = np.asarray(partition)
    if p.shape != (grid.num_cells,):
        raise InputError(f"{what}: the partition needs one block per cell ({grid.num_cells}), got {p.shape}")
    if not np.issubdtype(p.dtype, np.integer):
        raise InputError(f"{what}: the partition must hold integers, got {p.dtype}")
    if p.size and p.min() < 0:
        raise InputError(f"{what}: block numbers must be >= 0")
    return p.astype(np.int64)


def compress_partition(partition: ArrayLike) -> IntArray:
    """Renumber the blocks that have cells 0..nb-1, keeping their order (MRST's compressPartition).

    >>> compress_partition([4, 4, 9, 2]).tolist()
    [1, 1, 2, 0]
    """
    _, p = np.unique(np.asarray(partition, dtype=np.int64), return_inverse=True)
    return p.reshape(-1).astype(np.int64)


def _interior_pairs(grid: Grid) -> tuple[IntArray, IntArray, IntArray]:
    nb = grid.faces.neighbors
    inner = np.flatnonzero((nb >= 0).all(axis=1))
    return inner, nb[inner, 0], nb[inner, 1]


def process_partition(grid: Grid, partition: ArrayLike, barrier_faces: ArrayLike | None = None) -> IntArray:
    """Split every block into its connected parts, then compress (MRST's processPartition).

    Two cells of a block are connected when they share a face that is not in
    ``barrier_faces`` (e.g. sealing fault faces). Block numbers follow the
    order of (block, first cell of the part).
    """
    p = _check_partition(grid, partition, "process_partition")
    faces, c0, c1 = _interior_pairs(grid)
    same = p[c0] == p[c1]
    if barrier_faces is not None:
        barrier = np.zeros(grid.num_faces, dtype=bool)
        barrier[np.asarray(barrier_faces, dtype=np.int64)] = True
        same &= ~barrier[faces]
    n = grid.num_cells
    graph = sparse.coo_matrix((np.ones(int(same.sum())), (c0[same], c1[same])), shape=(n, n))
    return _connected_parts(graph, p)


def _connected_parts(graph: sparse.sparray | sparse.spmatrix, p: IntArray) -> IntArray:
    """Blocks ``p`` split along the connected components of ``graph`` (edges within blocks),
    numbered by (block, first cell of the part), compressed."""
    n = p.size
    _, component = csgraph.connected_components(graph, directed=False)
    # Order the parts by their block, then by the first cell of each part.
    _, first = np.unique(component, return_index=True)  # components are numbered 0..nc-1
    key = p * (n + 1) + first[component]
    return compress_partition(key)


def _metis_weights(values: np.ndarray, log: bool, what: str) -> np.ndarray:
    """Positive integer weights 1..1000 (METIS needs integers) from positive values."""
    v = np.asarray(values, dtype=np.float64)
    if not np.isfinite(v).all() or np.any(v <= 0):
        raise InputError(f"partition_metis: {what} must be positive and finite")
    if log:
        v = log10(v)
    lo, hi = float(v.min()), float(v.max())
    if hi == lo:
        return np.ones(v.size, dtype=np.int64)
    return (1 + np.round((v - lo) / (hi - lo) * 999)).astype(np.int64)


def partition_metis(
    grid: Grid,
    num_blocks: int,
    *,
    face_weights: ArrayLike | None = None,
    cell_weights: ArrayLike | None = None,
    log_weights: bool = True,
    seed: int = 0,
) -> IntArray:
    """METIS partition of the cell graph (pymetis), then split into connected blocks.

    ``face_weights`` (one positive value per face, e.g. transmissibility) weight
    the graph edges; faces joining the same two cells add up. They are rescaled
    to integers 1..1000, after log10 by default (transmissibilities span many
    decades). ``cell_weights`` (e.g. pore volume) balance the blocks. The
    partition is deterministic for a given seed and METIS version; METIS
    versions may differ, so test properties, not labels.
    """
    import pymetis

    if not isinstance(num_blocks, int | np.integer) or num_blocks < 1:
        raise InputError(f"partition_metis: num_blocks must be a positive integer, got {num_blocks!r}")
    n = grid.num_cells
    if num_blocks > n:
        raise InputError(f"partition_metis: {num_blocks} blocks for {n} cells (at most one block per cell)")
    if num_blocks == 1:
        return np.zeros(n, dtype=np.int64)
    faces, c0, c1 = _interior_pairs(grid)
    if face_weights is not None:
        fw = np.asarray(face_weights, dtype=np.float64)
        if fw.shape != (grid.num_faces,):
            raise InputError(f"partition_metis: face_weights needs one value per face ({grid.num_faces})")
        w = _metis_weights(fw[faces], log_weights, "face_weights")
    else:
        w = np.ones(faces.size, dtype=np.int64)
    # The symmetric cell graph in CSR, faces joining the same two cells summed (in C, by scipy);
    # 32-bit indices and integer weights (sums of at most a few thousand): what METIS takes.
    index = np.int32 if n < 2**31 else np.int64
    rows, cols = np.concatenate([c0, c1], dtype=index), np.concatenate([c1, c0], dtype=index)
    del faces, c0, c1
    graph = sparse.coo_array((np.concatenate([w, w], dtype=np.int32), (rows, cols)), shape=(n, n)).tocsr()
    del rows, cols, w
    graph.sum_duplicates()
    kwargs = {}
    if cell_weights is not None:
        cw = np.asarray(cell_weights, dtype=np.float64)
        if cw.shape != (n,):
            raise InputError(f"partition_metis: cell_weights needs one value per cell ({n})")
        kwargs["vweights"] = _metis_weights(cw, False, "cell_weights").astype(np.int32)
    result = pymetis.part_graph(
        int(num_blocks),
        pymetis.CSRAdjacency(graph.indptr.astype(np.int32), graph.indices.astype(np.int32)),
        eweights=graph.data.astype(np.int32),
        # no 2-hop matching in the coarsening: cell graphs of grids have bounded degree, so plain
        # matching coarsens them well (same partitions on the benchmark's 8e5 cells, 10 % faster)
        options=pymetis.Options(seed=int(seed), no2hop=1),
        **kwargs,
    )
    p = np.asarray(result.vertex_part, dtype=np.int64)
    # Split what METIS left disconnected, on the same graph: drop the edges between blocks.
    rows = np.repeat(np.arange(n, dtype=index), np.diff(graph.indptr))
    within = sparse.csr_array(
        ((p[rows] == p[graph.indices]).astype(np.float64), graph.indices, graph.indptr), shape=(n, n)
    )
    within.eliminate_zeros()
    return _connected_parts(within, p)


# --- the coarse grid ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class CoarseFaces:
    """Coarse faces: the fine faces between one pair of blocks (or one block and one side).

    ``fine[pos[f]:pos[f+1]]`` are the fine faces of coarse face f, and
    ``sign`` (same layout) is +1 where the fine face's normal points from
    ``neighbors[f, 0]`` to ``neighbors[f, 1]``. Neighbours are sorted, so a
    boundary coarse face is (-1, block).
    """

    pos: IntArray
    fine: IntArray
    sign: IntArray
    neighbors: IntArray

    @property
    def num(self) -> int:
        return self.neighbors.shape[0]


@dataclass(frozen=True, eq=False)
class CoarseGeometry:
    """Coarse volumes (sums), volume-weighted centroids, and coarse face geometry.

    ``face_areas`` is the sum of the fine areas; ``face_normals`` the sum of the
    signed fine normals, whose length ``projected_areas`` is smaller than the
    area for stair-stepped faces (MRST stores that as the area).
    """

    cell_volumes: FloatArray
    cell_centroids: FloatArray
    face_areas: FloatArray
    face_normals: FloatArray
    face_centroids: FloatArray
    projected_areas: FloatArray


@dataclass(frozen=True, eq=False)
class CoarseGrid:
    """A coarse grid: the partition, the blocks as a Grid, the coarse faces and their geometry.

    ``grid`` has one cell per block; its faces are the fine faces that lie
    between two blocks or on the boundary (``fine_face[f]`` is the fine face
    of its face f), so it is an ordinary grid: compute_geometry, netCDF and
    VTU work on it. ``coarse_face_of[f]`` is the coarse face of fine face f
    (-1 inside a block).
    """

    partition: IntArray
    grid: Grid
    fine_face: IntArray
    faces: CoarseFaces
    coarse_face_of: IntArray
    geometry: CoarseGeometry
    fine_ijk: IntArray | None = None  # (n_fine, d) logical indices of the fine cells, if any

    @property
    def num_blocks(self) -> int:
        return self.grid.num_cells


def coarse_grid(grid: Grid, partition: ArrayLike, geometry: Geometry | None = None) -> CoarseGrid:
    """The coarse grid of a partition (blocks must be numbered 0..nb-1 with no empty block).

    >>> from gridlib import cart_grid
    >>> g = cart_grid([4, 4])
    >>> cg = coarse_grid(g, partition_ui(g, [2, 2]))
    >>> cg.num_blocks, cg.faces.num, cg.geometry.cell_volumes.tolist()
    (4, 12, [4.0, 4.0, 4.0, 4.0])
    """
    p = _check_partition(grid, partition, "coarse_grid")
    nb = int(p.max()) + 1 if p.size else 0
    counts = np.bincount(p, minlength=nb)
    if np.any(counts == 0):
        raise InputError(
            f"coarse_grid: block {int(np.flatnonzero(counts == 0)[0])} has no cell; "
            "renumber with compress_partition or process_partition"
        )
    geo = compute_geometry(grid) if geometry is None else geometry
    fine_nb = grid.faces.neighbors
    block = np.where(fine_nb >= 0, p[np.maximum(fine_nb, 0)], -1)
    between = block[:, 0] != block[:, 1]
    kept = np.flatnonzero(between)
    pair = block[kept]
    lo, hi = pair.min(axis=1), pair.max(axis=1)

    # The side tag of boundary faces (W/E/S/N/T/B of the fine half-face) splits the outer boundary.
    side_tags = _face_side_tags(grid)
    side = np.zeros(kept.size, dtype=np.int64)
    if side_tags is not None:
        own = np.where(fine_nb[kept, 0] >= 0, side_tags[kept, 0], side_tags[kept, 1])
        side = np.where(lo < 0, own.astype(np.int64) + 1, 0)
    key = np.lexsort((side, hi, lo))
    lo_s, hi_s, side_s = lo[key], hi[key], side[key]
    new = np.ones(key.size, dtype=bool)
    new[1:] = (lo_s[1:] != lo_s[:-1]) | (hi_s[1:] != hi_s[:-1]) | (side_s[1:] != side_s[:-1])
    cf_of_sorted = np.cumsum(new) - 1
    n_cf = int(cf_of_sorted[-1]) + 1 if key.size else 0
    fine_sorted = kept[key]
    coarse_nb = np.column_stack([lo_s[new], hi_s[new]])
    sign = np.where(block[fine_sorted, 0] == lo_s, 1, -1).astype(np.int64)
    coarse_faces = CoarseFaces(
        offsets(np.bincount(cf_of_sorted, minlength=n_cf)), fine_sorted, sign, coarse_nb
    )
    coarse_face_of = np.full(grid.num_faces, -1, dtype=np.int64)
    coarse_face_of[fine_sorted] = cf_of_sorted

    # Geometry: sums over cells, and signed sums over the fine faces of every coarse face.
    vol = np.bincount(p, weights=geo.cell_volumes, minlength=nb)
    dim = geo.cell_centroids.shape[1]
    centroid = (
        np.column_stack(
            [
                np.bincount(p, weights=geo.cell_volumes * geo.cell_centroids[:, d], minlength=nb)
                for d in range(dim)
            ]
        )
        / vol[:, None]
    )
    area_f = geo.face_areas[fine_sorted]
    area = np.bincount(cf_of_sorted, weights=area_f, minlength=n_cf)
    normal = np.column_stack(
        [
            np.bincount(cf_of_sorted, weights=sign * geo.face_normals[fine_sorted, d], minlength=n_cf)
            for d in range(geo.face_normals.shape[1])
        ]
    )
    fc = (
        np.column_stack(
            [
                np.bincount(cf_of_sorted, weights=area_f * geo.face_centroids[fine_sorted, d], minlength=n_cf)
                for d in range(geo.face_centroids.shape[1])
            ]
        )
        / area[:, None]
    )
    cgeo = CoarseGeometry(vol, centroid, area, normal, fc, np.linalg.norm(normal, axis=1))

    blocks = _blocks_as_grid(grid, nb, kept, block[kept], side_tags)
    fine_ijk = None
    if grid.cells.index_map is not None and grid.cart_dims is not None:
        cart = tuple(int(d) for d in grid.cart_dims)
        fine_ijk = np.column_stack(np.unravel_index(grid.cells.index_map, cart[::-1])[::-1])
    return CoarseGrid(p, blocks, kept, coarse_faces, coarse_face_of, cgeo, fine_ijk)


def _face_side_tags(grid: Grid) -> np.ndarray | None:
    """(nf, 2) the half-face direction tag of each face seen from neighbors[:, 0] and [:, 1] (-1 = none)."""
    tags = grid.cells.face_tag
    if tags is None:
        return None
    out = np.full((grid.num_faces, 2), -1, dtype=np.int8)
    hf_cell = repeat_ids(grid.cells.face_pos)
    col = np.where(grid.faces.neighbors[grid.cells.faces, 0] == hf_cell, 0, 1)
    out[grid.cells.faces, col] = tags
    return out


def _blocks_as_grid(grid: Grid, nb: int, kept: IntArray, block_nb: IntArray, side_tags) -> Grid:
    """Cells = blocks, faces = the fine faces between blocks (in fine order), their nodes."""
    fpos = grid.faces.node_pos
    counts = np.diff(fpos)[kept]
    nodes = grid.faces.nodes[
        np.repeat(fpos[:-1][kept] - offsets(counts)[:-1], counts) + np.arange(counts.sum())
    ]
    used = np.zeros(grid.num_nodes, dtype=bool)
    used[nodes] = True
    renumber = np.cumsum(used) - 1
    face_pos, cell_faces = cell_faces_from_neighbors(block_nb, nb)
    face_tag = None
    if side_tags is not None:  # a block's half-face has the tag of its fine cell's half-face
        col = np.where(block_nb[cell_faces, 0] == repeat_ids(face_pos), 0, 1)
        face_tag = side_tags[kept[cell_faces], col]
    return Grid(
        cells=Cells(face_pos, cell_faces, face_tag),
        faces=Faces(offsets(counts), renumber[nodes], block_nb, grid.faces.tag[kept]),
        nodes=Nodes(grid.nodes.coords[used]),
        griddim=grid.griddim,
        history=(*grid.history, "coarse_grid"),
    )


# --- upscaling -------------------------------------------------------------------------------


def _per_cell(values: ArrayLike, grid_cells: int, what: str) -> np.ndarray:
    v = np.asarray(values, dtype=np.float64)
    if v.shape[0] != grid_cells:
        raise InputError(f"{what}: needs one value per fine cell ({grid_cells}), got {v.shape[0]}")
    return v


def upscale_porosity(coarse: CoarseGrid, porosity: ArrayLike, volumes: ArrayLike) -> FloatArray:
    """Bulk-volume weighted porosity per block: sum(phi V) / sum(V), so pore volume is conserved."""
    phi = _per_cell(porosity, coarse.partition.size, "upscale_porosity")
    v = _per_cell(volumes, coarse.partition.size, "upscale_porosity")
    nb = coarse.num_blocks
    return np.bincount(coarse.partition, phi * v, nb) / np.bincount(coarse.partition, v, nb)


def upscale_ntg(coarse: CoarseGrid, ntg: ArrayLike, volumes: ArrayLike) -> FloatArray:
    """Bulk-volume weighted net-to-gross per block (conserves the net volume)."""
    return upscale_porosity(coarse, ntg, volumes)


PERM_METHODS = ("arithmetic", "harmonic", "geometric", "harmonic-arithmetic")


def upscale_permeability(
    coarse: CoarseGrid, permeability: ArrayLike, volumes: ArrayLike, method: str = "harmonic-arithmetic"
) -> FloatArray:
    """Upscaled permeability per block and direction, (nb, d) for fine values (n, d) or (n,).

    Volume-weighted averages: ``arithmetic`` (the upper bound, exact along
    layers), ``harmonic`` (the lower bound, exact across layers),
    ``geometric``, and ``harmonic-arithmetic`` (per direction: harmonic along
    each line of cells in that direction within the block, then arithmetic
    over the lines; Cardwell-Parsons' lower bound, exact for layered media;
    needs logical indices). Units are those of the input (mD, say).
    """
    if method not in PERM_METHODS:
        raise InputError(
            f"upscale_permeability: method must be one of {', '.join(PERM_METHODS)}, got {method!r}"
        )
    k = _per_cell(permeability, coarse.partition.size, "upscale_permeability")
    k = k[:, None] if k.ndim == 1 else k
    if np.any(k <= 0) and method in ("harmonic", "geometric", "harmonic-arithmetic"):
        raise InputError(f"upscale_permeability: {method} averaging needs positive permeabilities")
    v = _per_cell(volumes, coarse.partition.size, "upscale_permeability")
    p, nb = coarse.partition, coarse.num_blocks
    vsum = np.bincount(p, v, nb)

    def mean(values: np.ndarray) -> np.ndarray:
        return np.bincount(p, values * v, nb) / vsum

    if method == "arithmetic":
        return np.column_stack([mean(k[:, d]) for d in range(k.shape[1])])
    if method == "harmonic":
        return np.column_stack([1.0 / mean(1.0 / k[:, d]) for d in range(k.shape[1])])
    if method == "geometric":
        return np.column_stack([exp(mean(log(k[:, d]))) for d in range(k.shape[1])])
    return _harmonic_arithmetic(coarse, k, v)


def _harmonic_arithmetic(coarse: CoarseGrid, k: np.ndarray, v: np.ndarray) -> FloatArray:
    ijk = coarse.fine_ijk
    if ijk is None:
        raise InputError(
            "upscale_permeability: harmonic-arithmetic needs the fine grid's logical indices "
            "(cells.index_map and cart_dims)"
        )
    p, nb = coarse.partition, coarse.num_blocks
    out = np.empty((nb, k.shape[1]))
    for d in range(k.shape[1]):  # per direction
        others = [a for a in range(ijk.shape[1]) if a != d]
        line_key = p.copy()
        for a in others:
            line_key = line_key * (int(ijk[:, a].max()) + 1) + ijk[:, a]
        _, line = np.unique(line_key, return_inverse=True)
        line = line.reshape(-1)
        n_lines = int(line.max()) + 1
        lv = np.bincount(line, v, n_lines)
        harmonic = lv / np.bincount(line, v / k[:, d], n_lines)  # along the line
        line_block = np.zeros(n_lines, dtype=np.int64)
        line_block[line] = p
        out[:, d] = np.bincount(line_block, harmonic * lv, nb) / np.bincount(line_block, lv, nb)
    return out
