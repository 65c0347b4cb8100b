"""``make_layered_grid``: extrude a 2-D grid along vertical pillars (2.5D grids).

Numbering follows MRST's ``makeLayeredGrid``: the nodes of interface k (k = 0
is the top) are ``k * nn2 + v``; faces are first the (nl + 1) * nc2 layer
interfaces (face ``k * nc2 + c`` is the top of cell c in layer k, normal +z,
i.e. downwards from the upper to the lower cell), then the nl * nf2 lateral
faces (``n_interfaces + k * nf2 + f`` extrudes areal face f in layer k, normal
as the areal face's). Cell ``k * nc2 + c`` lies in layer k below areal cell c;
its faces are listed in increasing face order (top, bottom, laterals).

Depths are positive downwards (z is depth). Pinched (zero-thickness) layers
are the pillar engine's job; here every layer must be strictly thicker than 0
at every node.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .connectivity import cell_node_cycles_2d, offsets, repeat_ids
from .errors import GridError
from .grid import B, Cells, Faces, Grid, Layering, Nodes, T


def make_layered_grid(
    grid: Grid,
    num_layers: int | None = None,
    *,
    thickness: ArrayLike | None = None,
    depths: ArrayLike | None = None,
) -> Grid:
    """Extrude a 2-D grid into layers along vertical pillars.

    Give exactly one of:

    * ``num_layers``: that many layers of thickness 1 m;
    * ``thickness``: one thickness per layer (m, > 0);
    * ``depths``: the depth of every layer interface, shape (nl + 1,) or
      (nl + 1, nn2) for a depth per areal node (m, strictly increasing downwards).

    With ``num_layers``/``thickness`` the top is at depth 0, or at the areal
    grid's z for a surface grid (3-D coordinates), so extruding a triangulated
    horizon follows it.

    >>> from gridlib import cart_grid
    >>> g = make_layered_grid(cart_grid([2, 2]), 3)
    >>> g.num_cells, g.num_faces, g.num_nodes, g.cart_dims
    (12, 52, 36, (2, 2, 3))
    """
    if grid.griddim != 2:
        raise GridError("make_layered_grid: the areal grid must be 2-D (griddim 2)")
    given = [v is not None for v in (num_layers, thickness, depths)]
    if sum(given) != 1:
        raise GridError("make_layered_grid: give exactly one of num_layers, thickness, depths")
    nn2, nc2 = grid.num_nodes, grid.num_cells
    top = grid.nodes.coords[:, 2] if grid.dim == 3 else np.zeros(nn2)
    z = _interface_depths(num_layers, thickness, depths, top, nn2)
    nl = z.shape[0] - 1

    pos2, cyc, reverse = _counter_clockwise_cycles(grid)
    xy = grid.nodes.coords[:, :2]
    node_pos, face_nodes, neighbors = _faces(grid, pos2, cyc, reverse, nl)
    n_h = (nl + 1) * nc2
    face_pos, cell_faces, face_tag = _cell_faces(grid, nl, n_h)
    cell_id = np.arange(nc2)
    k_cells = np.arange(nl)

    cart_dims, index_map = None, None
    if grid.cart_dims is not None and len(grid.cart_dims) == 2:
        nx, ny = grid.cart_dims
        cart_dims = (nx, ny, nl)
        im2 = np.arange(nc2) if grid.cells.index_map is None else grid.cells.index_map
        index_map = (im2[None, :] + k_cells[:, None] * nx * ny).ravel()

    coords = np.column_stack([np.tile(xy[:, 0], nl + 1), np.tile(xy[:, 1], nl + 1), z.ravel()])
    return Grid(
        cells=Cells(face_pos, cell_faces, face_tag, index_map),
        faces=Faces(
            node_pos,
            face_nodes,
            neighbors,
            np.concatenate([np.zeros(n_h, np.int32), np.tile(grid.faces.tag, nl)]),
        ),
        nodes=Nodes(coords),
        griddim=3,
        cart_dims=cart_dims,
        history=(*grid.history, "make_layered_grid"),
        layering=Layering(grid, np.tile(cell_id, nl), np.repeat(k_cells, nc2), nl),
    )


def _counter_clockwise_cycles(grid: Grid) -> tuple[np.ndarray, np.ndarray, bool]:
    """The areal cells' node cycles (``pos2``, ``cyc``) turned counter-clockwise in (x, y), so that
    top-face normals point down, and whether they had to be reversed."""
    nc2 = grid.num_cells
    pos2, cyc = cell_node_cycles_2d(grid)
    xy = grid.nodes.coords[:, :2]
    owner = repeat_ids(pos2)
    nxt = np.arange(cyc.size) + 1
    nxt[pos2[1:] - 1] = pos2[:-1]
    local = xy - xy.mean(axis=0)  # shoelace products lose digits at UTM sizes
    a, b = local[cyc], local[cyc[nxt]]
    plan_area = np.bincount(owner, a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1], nc2)
    if np.any(plan_area == 0):
        c = int(np.flatnonzero(plan_area == 0)[0])
        raise GridError(f"make_layered_grid: areal cell {c} has zero area in plan view")
    flip = plan_area < 0
    if flip.any() and not flip.all():
        raise GridError("make_layered_grid: the areal grid folds over itself in plan view")
    reverse = bool(flip[0])
    if reverse:  # orient cycles counter-clockwise in (x, y): top-face normals point down
        local = np.arange(cyc.size) - pos2[owner]
        cyc = cyc[pos2[owner] + (np.diff(pos2)[owner] - 1 - local)]
    return pos2, cyc, reverse


def _faces(grid: Grid, pos2, cyc, reverse: bool, nl: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The faces' node offsets, nodes and neighbours: the layer interfaces, then the lateral faces."""
    nn2, nc2, nf2 = grid.num_nodes, grid.num_cells, grid.num_faces
    k_nodes = np.arange(nl + 1)[:, None] * nn2
    # Layer-interface faces.
    h_nodes = (cyc[None, :] + k_nodes).ravel()
    h_count = np.tile(np.diff(pos2), nl + 1)
    cell_id = np.arange(nc2)
    upper = np.concatenate([np.full(nc2, -1), (np.arange(nl)[:, None] * nc2 + cell_id).ravel()])
    lower = np.concatenate([(np.arange(nl)[:, None] * nc2 + cell_id).ravel(), np.full(nc2, -1)])

    # Lateral faces.
    e = grid.faces.nodes.reshape(-1, 2)
    if reverse:
        e = e[:, ::-1]
    k_lat = np.arange(nl)[:, None]
    n0 = e[None, :, 0] + k_lat * nn2
    n1 = e[None, :, 1] + k_lat * nn2
    l_nodes = np.stack([n0, n1, n1 + nn2, n0 + nn2], axis=-1).reshape(-1)
    nb2 = grid.faces.neighbors
    l_nb = np.where(nb2[None, :, :] >= 0, nb2[None, :, :] + k_lat[:, :, None] * nc2, -1).reshape(-1, 2)

    neighbors = np.concatenate([np.column_stack([upper, lower]), l_nb])
    node_pos = offsets(np.concatenate([h_count, np.full(nl * nf2, 4)]))
    face_nodes = np.concatenate([h_nodes, l_nodes])
    return node_pos, face_nodes, neighbors


def _cell_faces(grid: Grid, nl: int, n_h: int) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Every cell's faces (top, bottom, then the lateral faces in increasing face order) and their
    half-face tags (None if the areal grid has none)."""
    nc2, nf2 = grid.num_cells, grid.num_faces
    cell_id = np.arange(nc2)
    hc2 = repeat_ids(grid.cells.face_pos)
    order2 = np.lexsort((grid.cells.faces, hc2))
    k_cells = np.arange(nl)
    face_pos = offsets(np.tile(grid.cells.num_faces + 2, nl))
    starts = face_pos[:-1]
    tops = (k_cells[:, None] * nc2 + cell_id).ravel()
    cell_faces = np.empty(int(face_pos[-1]), dtype=np.int64)
    cell_faces[starts] = tops
    cell_faces[starts + 1] = tops + nc2
    owner_lat = np.tile(hc2, nl) + np.repeat(k_cells, hc2.size) * nc2
    slot_lat = face_pos[owner_lat] + 2 + np.tile(np.arange(hc2.size) - grid.cells.face_pos[hc2], nl)
    cell_faces[slot_lat] = (n_h + k_cells[:, None] * nf2 + grid.cells.faces[order2][None, :]).ravel()

    face_tag = None
    if grid.cells.face_tag is not None:
        face_tag = np.empty(cell_faces.size, dtype=np.int8)
        face_tag[starts] = T
        face_tag[starts + 1] = B
        face_tag[slot_lat] = np.tile(grid.cells.face_tag[order2], nl)
    return face_pos, cell_faces, face_tag


def _interface_depths(num_layers, thickness, depths, top, nn2) -> np.ndarray:
    """(nl + 1, nn2) depth of every layer interface at every areal node."""
    if num_layers is not None:
        if not isinstance(num_layers, (int, np.integer)) or num_layers < 1:
            raise GridError(f"make_layered_grid: num_layers must be a positive integer, got {num_layers!r}")
        thickness = np.ones(int(num_layers))
    if thickness is not None:
        try:
            t = np.asarray(thickness, dtype=np.float64).ravel()
        except (TypeError, ValueError) as exc:
            raise GridError(f"make_layered_grid: thickness must be numbers, got {thickness!r}") from exc
        if t.size == 0 or not np.all(np.isfinite(t)) or np.any(t <= 0):
            raise GridError(f"make_layered_grid: thickness must be positive numbers, got {t.tolist()}")
        return top[None, :] + np.concatenate([[0.0], np.cumsum(t)])[:, None]
    try:
        z = np.asarray(depths, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise GridError("make_layered_grid: depths must be an array of numbers") from exc
    if z.ndim == 1:
        z = np.repeat(z[:, None], nn2, axis=1)
    if z.ndim != 2 or z.shape[1] != nn2 or z.shape[0] < 2:
        raise GridError(
            f"make_layered_grid: depths must have shape (nl+1,) or (nl+1, {nn2}), got {np.shape(depths)}"
        )
    if not np.all(np.isfinite(z)):
        raise GridError("make_layered_grid: depths contain NaN or infinite values")
    dz = np.diff(z, axis=0)
    if np.any(dz <= 0):
        k, v = np.argwhere(dz <= 0)[0]
        raise GridError(
            f"make_layered_grid: layer {k} has thickness {dz[k, v]} <= 0 at areal node {v}; "
            "depths must increase downwards (use the pillar engine for pinch-outs)"
        )
    return z
