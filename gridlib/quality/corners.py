"""The eight corners of corner-point cells, from a deck or from a grid, and xtgeo's
``faulted`` flag (docs/quality.md).

Corners are (n, 8, 3) with corner ``a + 2b + 4c`` on pillar (i + a, j + b) at the cell's top
(c = 0) or bottom (c = 1), z depth (z-up decks negated, as :func:`process_grdecl` does).

* :func:`deck_corners`: from the deck's COORD and ZCORN (each cell's own top and bottom),
  :func:`gridlib.cornerpoint.corners.corner_points` a block of cells at a time;
* :func:`grid_corners`: from a grid whose cells carry ``face_tag`` (W, E, S, N, T, B): a cell
  with one top and one bottom face is a hexahedron; its corners are the nodes of those faces
  that lie on exactly one of its W / E sides and one of its S / N sides (the crossing nodes a
  fault inserts into an edge lie on one side only). Any other cell is a row of NaN;
* :func:`deck_faulted`: xtgeo's ``faulted`` flag for every deck cell.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from functools import partial

import numpy as np
from numpy.typing import ArrayLike

from ..connectivity import half_face_cells, ragged_arange
from ..cornerpoint.corners import corner_points
from ..cornerpoint.deck import Deck
from ..grid import B, E, FloatArray, Grid, N, S, T, W
from .hexahedra import EDGE_TOLERANCE

_BLOCK = 1 << 16  # cells per block of corners: (block, 8, 3) float64 = 12 MiB


def deck_corners(deck: Deck, cells: ArrayLike | None = None) -> FloatArray:
    """Corners (n, 8, 3) of ``cells`` (linear indices, i fastest; default: every cell)."""
    blocks = [corners() for _, corners in deck_corner_blocks(deck, cells)]
    return np.concatenate(blocks) if blocks else np.empty((0, 8, 3))


def deck_corner_blocks(
    deck: Deck, cells: ArrayLike | None = None
) -> Iterator[tuple[slice, Callable[[], FloatArray]]]:
    """:func:`deck_corners` a block of cells at a time: (the block's slice of ``cells``, a
    function returning its corners), so that a caller never holds the corners of every cell
    and may compute each block's on the thread that uses them."""
    g = np.arange(deck.num_cells) if cells is None else np.asarray(cells, dtype=np.int64).ravel()
    sign = _depth_sign(deck)
    for s in range(0, g.size, _BLOCK):
        yield slice(s, min(s + _BLOCK, g.size)), partial(_corners, deck, g[s : s + _BLOCK], sign)


def _corners(deck: Deck, cells: np.ndarray, sign: int) -> FloatArray:
    with np.errstate(invalid="ignore"):  # inactive cells may hold junk
        return corner_points(deck, cells, sign)


def _depth_sign(deck: Deck) -> int:
    """-1 for a z-up deck (most active cells have their bottom above their top), else 1:
    :func:`~gridlib.cornerpoint.corners.depth_sign`'s vote, without its refusal of cells of
    negative thickness, which are measured here."""
    nx, ny, nz = deck.cart_dims
    zc = deck.zcorn_array()
    act = np.repeat(np.repeat(deck.active.reshape(nz, ny, nx), 2, axis=1), 2, axis=2)
    with np.errstate(invalid="ignore"):
        dz = (zc[1::2] - zc[0::2])[act]
    return -1 if np.count_nonzero(dz < 0) > np.count_nonzero(dz > 0) else 1


def deck_faulted(deck: Deck) -> FloatArray:
    """xtgeo's ``faulted`` flag (1.0 / 0.0) of every deck cell, i fastest.

    At each of a cell's eight corner nodes (pillar (i + a, j + b) at the boundary between
    layers k + c - 1 and k + c, as xtgeo stores a grid: a layer's top, the last layer's bottom)
    the four cells around the pillar (sw, se, nw, ne) have their own depths; the cell is
    faulted where, at one of its nodes, sw differs from se, nw or ne, or se from nw, by more
    than 1e-5. On the model's edge a missing neighbour takes the depth of the cell across
    the pillar, so only the cells present are compared. These are xtgeo's comparisons: a
    step of the ne cell alone against three equal others is not flagged.
    """
    nx, ny, nz = deck.cart_dims
    zc = deck.zcorn_array()
    levels = np.concatenate([zc[0::2], zc[-1:]])  # (nz + 1, 2 ny, 2 nx)
    v = np.full((4, nz + 1, ny + 1, nx + 1), np.nan)  # sw, se, nw, ne of each pillar node
    v[0, :, 1:, 1:] = levels[:, 1::2, 1::2]
    v[1, :, 1:, :nx] = levels[:, 1::2, 0::2]
    v[2, :, :ny, 1:] = levels[:, 0::2, 1::2]
    v[3, :, :ny, :nx] = levels[:, 0::2, 0::2]
    _fill_edges(v, nx, ny)
    with np.errstate(invalid="ignore"):
        node = (
            (np.abs(v[0] - v[1]) > EDGE_TOLERANCE)
            | (np.abs(v[0] - v[2]) > EDGE_TOLERANCE)
            | (np.abs(v[0] - v[3]) > EDGE_TOLERANCE)
            | (np.abs(v[1] - v[2]) > EDGE_TOLERANCE)
        )
    cell = np.zeros((nz, ny, nx), dtype=bool)
    for c in (0, 1):
        for b in (0, 1):
            for a in (0, 1):
                cell |= node[c : c + nz, b : b + ny, a : a + nx]
    return cell.ravel().astype(np.float64)


def _fill_edges(v: FloatArray, nx: int, ny: int) -> None:
    """Give the missing cells around the pillars on the model's edge the depth of the cell
    across the pillar (xtgeo's rule), in place; ``v`` is (4: sw se nw ne, levels, ny+1, nx+1)."""
    sw, se, nw, ne = range(4)
    v[[sw, se], :, 0, 1:nx] = v[[nw, ne], :, 0, 1:nx]  # south edge
    v[[sw, nw], :, 1:ny, 0] = v[[se, ne], :, 1:ny, 0]  # west edge
    v[[se, ne], :, 1:ny, nx] = v[[sw, nw], :, 1:ny, nx]  # east edge
    v[[nw, ne], :, ny, 1:nx] = v[[sw, se], :, ny, 1:nx]  # north edge
    for (j, i), own in (((0, 0), ne), ((0, nx), nw), ((ny, 0), se), ((ny, nx), sw)):
        v[:, :, j, i] = v[own, :, j, i]


def grid_corners(grid: Grid) -> FloatArray:
    """Corners (nc, 8, 3) of the hexahedral cells of ``grid`` (module docstring), NaN rows for
    the others (and all NaN for a grid without ``face_tag`` or not 3-D)."""
    nc = grid.num_cells
    out = np.full((nc, 8, 3), np.nan)
    tag = grid.cells.face_tag
    if tag is None or grid.griddim != 3:
        return out
    hc = half_face_cells(grid)
    n_top = np.bincount(hc[tag == T], minlength=nc)
    n_base = np.bincount(hc[tag == B], minlength=nc)
    # (cell, node) of every lateral half-face node, with the side's bit
    lateral = np.flatnonzero(tag <= N)
    key, bits = _half_face_nodes(grid, lateral, hc)
    order = np.argsort(key, kind="stable")
    key, bits = key[order], (1 << tag[lateral].astype(np.int64))[bits][order]
    first = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    ukey, ubits = key[first], np.bitwise_or.reduceat(bits, first) if key.size else bits
    slot_count = np.zeros((nc, 8), dtype=np.int64)
    for c, side in ((0, T), (1, B)):
        hf = np.flatnonzero(tag == side)
        k, _ = _half_face_nodes(grid, hf, hc)
        cell, node = divmod(k, grid.num_nodes)
        where = np.clip(np.searchsorted(ukey, k), 0, max(ukey.size - 1, 0))
        b = np.where(ukey[where] == k, ubits[where], 0) if ukey.size else np.zeros_like(k)
        west, east = (b >> W) & 1, (b >> E) & 1
        south, north = (b >> S) & 1, (b >> N) & 1
        corner = ((west ^ east) == 1) & ((south ^ north) == 1)
        slot = east + 2 * north + 4 * c
        cell, node, slot = cell[corner], node[corner], slot[corner]
        np.add.at(slot_count, (cell, slot), 1)
        out[cell, slot] = grid.nodes.coords[node]
    good = (slot_count == 1).all(axis=1) & (n_top == 1) & (n_base == 1)
    out[~good] = np.nan
    return out


def _half_face_nodes(grid: Grid, half_faces: np.ndarray, hc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Keys ``cell * num_nodes + node`` of every node of ``half_faces`` (entries of
    ``cells.faces``) and, per key, the position in ``half_faces`` it came from."""
    f = grid.cells.faces[half_faces]
    count = grid.faces.num_nodes[f]
    nodes = grid.faces.nodes[ragged_arange(grid.faces.node_pos[f], count)]
    src = np.repeat(np.arange(half_faces.size), count)
    return hc[half_faces][src] * grid.num_nodes + nodes, src
