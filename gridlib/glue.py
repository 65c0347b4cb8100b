"""``glue_2d``: join two planar 2-D grids along their common boundary.

As MRST's ``glue2DGrid``, but without needing face tags and vectorised: boundary
edges of each grid are split where a boundary node of the other grid lies on
them (so non-matching interfaces become conforming, with hanging nodes),
coincident boundary nodes are merged, and boundary edges with the same two end
nodes become interior faces between the two grids. Cells of ``g1`` come first,
then those of ``g2``; face tags and directional half-face tags are kept.
"""

from __future__ import annotations

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

from .connectivity import boundary_faces, offsets, order_cell_faces_2d, ragged_arange, repeat_ids
from .errors import GridError
from .grid import Cells, Faces, Grid, Nodes


def glue_2d(g1: Grid, g2: Grid, tol: float | None = None) -> Grid:
    """One grid from two planar 2-D grids that touch along (parts of) their boundaries.

    ``tol`` (m) is the distance under which nodes coincide or a node lies on an
    edge; default 1e-9 times the size of the union's bounding box. The grids
    must not overlap; grids sharing no boundary give one grid of two
    disconnected pieces (as MRST's ``glue2DGrid``).

    >>> from gridlib import cart_grid, translate_grid
    >>> g = glue_2d(cart_grid([2, 2]), translate_grid(cart_grid([3, 3], [1, 2]), [2, 0]))
    >>> g.num_cells, g.num_faces
    (13, 35)
    """
    for name, g in (("g1", g1), ("g2", g2)):
        if g.griddim != 2 or g.dim != 2:
            raise GridError(f"glue_2d: {name} must be a planar 2-D grid")
    coords = np.concatenate([g1.nodes.coords, g2.nodes.coords])
    tol = _tolerance(tol, coords)
    nn1, nf1, nc1 = g1.num_nodes, g1.num_faces, g1.num_cells

    # Concatenate the two grids.
    e = np.concatenate([g1.faces.nodes.reshape(-1, 2), g2.faces.nodes.reshape(-1, 2) + nn1])
    nb2 = np.where(g2.faces.neighbors >= 0, g2.faces.neighbors + nc1, -1)
    nb = np.concatenate([g1.faces.neighbors, nb2])
    ftag = np.concatenate([g1.faces.tag, g2.faces.tag])
    cpos = offsets(np.concatenate([g1.cells.num_faces, g2.cells.num_faces]))
    cfaces = np.concatenate([g1.cells.faces, g2.cells.faces + nf1])
    ctag = None
    if g1.cells.face_tag is not None and g2.cells.face_tag is not None:
        ctag = np.concatenate([g1.cells.face_tag, g2.cells.face_tag])
    grid_of_face = np.repeat([0, 1], [nf1, g2.num_faces])
    grid_of_node = np.repeat([0, 1], [nn1, g2.num_nodes])

    # 1. Split boundary edges at boundary nodes of the other grid lying inside them.
    bf = np.concatenate([boundary_faces(g1), boundary_faces(g2) + nf1])
    edge, node, t = _nodes_inside_edges(coords, e, bf, grid_of_face, grid_of_node, tol)
    e, nb, ftag, cpos, cfaces, ctag = _split_edges(e, nb, ftag, cpos, cfaces, ctag, edge, node, t)
    # 2. Merge coincident boundary nodes of the two grids (the lowest index survives).
    e = _merged_nodes(coords, e, nb, grid_of_node, tol)
    # 3. Boundary edges of g1 and g2 with the same end nodes become one interior face.
    e, nb, ftag, cfaces = _joined_edges(e, nb, ftag, cfaces, coords.shape[0])

    used = np.zeros(coords.shape[0], dtype=bool)
    used[e.ravel()] = True
    new_node = np.cumsum(used) - 1
    nf = len(nb)
    grid = Grid(
        cells=Cells(cpos, cfaces, ctag),
        faces=Faces(np.arange(0, 2 * nf + 1, 2), new_node[e].ravel(), nb, ftag),
        nodes=Nodes(coords[used]),
        griddim=2,
        history=("glue_2d",),
    )
    try:
        return order_cell_faces_2d(grid)
    except GridError as exc:
        raise GridError(f"glue_2d: the grids overlap or do not fit together ({exc})") from exc


def _tolerance(tol, coords: np.ndarray) -> float:
    """``tol`` checked (positive), default 1e-9 times the largest side of the nodes' bounding box."""
    if tol is None:
        tol = 1e-9 * float(np.ptp(coords, axis=0).max())
    try:
        tol = float(tol)
    except (TypeError, ValueError) as exc:
        raise GridError(f"glue_2d: tol must be a number, got {tol!r}") from exc
    if not tol > 0:
        raise GridError(f"glue_2d: tol must be positive, got {tol}")
    return tol


def _nodes_inside_edges(coords, e, bf, grid_of_face, grid_of_node, tol: float):
    """The boundary nodes of one grid lying inside (not at the ends of) a boundary edge ``bf`` of the
    other: (the edge, the node, its position t in (0, 1) along the edge)."""
    bnodes = np.unique(e[bf].ravel())
    pa, pb = coords[e[bf, 0]], coords[e[bf, 1]]
    seg = pb - pa
    length = np.linalg.norm(seg, axis=1)
    tree = cKDTree(coords[bnodes])
    hits = tree.query_ball_point(0.5 * (pa + pb), 0.5 * length + tol)
    n_hit = np.fromiter((len(h) for h in hits), dtype=np.int64, count=len(hits))
    cand_edge = np.repeat(np.arange(bf.size), n_hit)
    cand_node = (
        bnodes[np.concatenate([np.asarray(h, dtype=np.int64) for h in hits])]
        if n_hit.sum()
        else np.zeros(0, np.int64)
    )
    other = grid_of_node[cand_node] != grid_of_face[bf[cand_edge]]
    cand_edge, cand_node = cand_edge[other], cand_node[other]
    rel = coords[cand_node] - pa[cand_edge]
    t = (rel * seg[cand_edge]).sum(axis=1) / length[cand_edge] ** 2
    dist = np.abs(rel[:, 0] * seg[cand_edge, 1] - rel[:, 1] * seg[cand_edge, 0]) / length[cand_edge]
    inner = (dist <= tol) & (t * length[cand_edge] > tol) & ((1 - t) * length[cand_edge] > tol)
    cand_edge, cand_node, t = cand_edge[inner], cand_node[inner], t[inner]
    return bf[cand_edge], cand_node, t


def _merged_nodes(coords, e, nb, grid_of_node, tol: float):
    """The edges' nodes with the coincident boundary nodes of the two grids merged (the lowest index
    survives)."""
    bnodes = np.unique(e[(nb < 0).any(axis=1)].ravel())
    pairs = bnodes[cKDTree(coords[bnodes]).query_pairs(tol, output_type="ndarray")].reshape(-1, 2)
    pairs = pairs[grid_of_node[pairs[:, 0]] != grid_of_node[pairs[:, 1]]]
    nn = coords.shape[0]
    graph = sparse.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(nn, nn))
    _, label = csgraph.connected_components(graph, directed=False)
    _, lowest = np.unique(label, return_index=True)
    return lowest[label][e]


def _joined_edges(e, nb, ftag, cfaces, nn: int):
    """Boundary edges with the same end nodes joined into one interior face (the first keeps its
    index, the second is dropped): the edges, neighbours, tags and the cells' faces renumbered."""
    bnd = (nb < 0).any(axis=1)
    key = np.sort(e, axis=1)
    kk = key[:, 0] * nn + key[:, 1]
    cand = np.flatnonzero(bnd)
    order = cand[np.argsort(kk[cand], kind="stable")]
    same = kk[order[1:]] == kk[order[:-1]]
    first, second = order[:-1][same], order[1:][same]
    if np.any(np.bincount(np.concatenate([first, second]), minlength=len(nb)) > 1):
        raise GridError("glue_2d: more than two boundary edges coincide (do the grids overlap?)")
    c2 = nb[second].max(axis=1)
    slot = np.where(nb[first, 0] < 0, 0, 1)
    nb[first, slot] = c2
    drop = np.zeros(len(nb), dtype=bool)
    drop[second] = True
    remap = np.arange(len(nb))
    remap[second] = first
    new_face = np.cumsum(~drop) - 1
    cfaces = new_face[remap[cfaces]]
    return e[~drop], nb[~drop], ftag[~drop], cfaces


def _split_edges(e, nb, ftag, cpos, cfaces, ctag, edge, node, t):
    """Split each listed edge at the listed nodes (ordered by t along the edge)."""
    if edge.size == 0:
        return e, nb, ftag, cpos, cfaces, ctag
    if np.any((nb[edge] >= 0).all(axis=1)):
        raise GridError("glue_2d: internal error, splitting an interior edge")
    order = np.lexsort((t, edge))
    edge, node = edge[order], node[order]
    nf = len(nb)
    n_ins = np.bincount(edge, minlength=nf)
    split = np.flatnonzero(n_ins)
    # Chain a, n1, n2, ..., b for every split edge; pieces keep the edge's direction.
    k = n_ins[split]
    chain_pos = offsets(k + 2)
    chain = np.empty(int(chain_pos[-1]), dtype=np.int64)
    chain[chain_pos[:-1]] = e[split, 0]
    chain[chain_pos[1:] - 1] = e[split, 1]
    inner_slots = ragged_arange(chain_pos[:-1] + 1, k)
    chain[inner_slots] = node
    piece_owner = np.repeat(np.arange(split.size), k + 1)
    piece_start = ragged_arange(chain_pos[:-1], k + 1)
    pieces = np.column_stack([chain[piece_start], chain[piece_start + 1]])
    first_piece = offsets(k + 1)

    # Each split edge keeps its index for its first piece; the others are appended.
    new_ids = np.empty(pieces.shape[0], dtype=np.int64)
    new_ids[first_piece[:-1]] = split
    extra = np.ones(pieces.shape[0], dtype=bool)
    extra[first_piece[:-1]] = False
    new_ids[extra] = nf + np.arange(int(extra.sum()))
    e = np.concatenate([e, pieces[extra]])
    e[split] = pieces[first_piece[:-1]]
    nb = np.concatenate([nb, nb[split[piece_owner[extra]]]])
    ftag = np.concatenate([ftag, ftag[split[piece_owner[extra]]]])

    # Replace each half-face of a split edge by its pieces (order fixed afterwards).
    piece_list = new_ids  # grouped by split edge, in chain order
    n_pieces = np.zeros(nf, dtype=np.int64)
    n_pieces[split] = k + 1
    reps = np.where(n_pieces[cfaces] > 0, n_pieces[cfaces], 1)
    hc = repeat_ids(cpos)
    new_cpos = offsets(np.bincount(np.repeat(hc, reps), minlength=cpos.size - 1))
    expanded = np.repeat(cfaces, reps)
    is_split = np.repeat(n_pieces[cfaces] > 0, reps)
    local = np.arange(expanded.size) - np.repeat(np.cumsum(reps) - reps, reps)
    where = np.searchsorted(split, expanded[is_split])
    expanded[is_split] = piece_list[first_piece[where] + local[is_split]]
    new_ctag = None if ctag is None else np.repeat(ctag, reps)
    return e, nb, ftag, new_cpos, expanded, new_ctag
