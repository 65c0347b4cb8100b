"""ECLIPSE's corner-point transmissibilities (NEWTRAN) as OPM Flow computes them.

For a face between cells i and j of a processed corner-point grid:

* the centre of a cell is the plain mean of its 8 corners (from COORD and ZCORN), the
  same point for every direction;
* the centre of a cell's face is the mean of the 4 corners of its own *logical* face
  (W/E/S/N/T/B), even across a fault, where it is not the centre of the overlap;
* the area vector A is that of the actual face polygon (the overlap on faults),
  ½ sum p_k x p_k+1 over its nodes, used by both halves; between two cells of one
  column it is the upper cell's bottom quad of 4 corners (the processed grid may
  hold extra nodes there, where fault faces cross its edges, which Flow's does not);
* T_i = K_i |A . d_i| / (d_i . d_i), d_i from the cell centre to its face centre and
  K_i its PERMX, PERMY or PERMZ by the face's logical axis (diagonal only); NTG
  multiplies the I and J halves; T = 1 / (1/T_i + 1/T_j), 0 if a half is below
  1e-30 m3.

Lengths are in the deck's unit, permeability in mD; the result is converted to the
deck's transmissibility unit (:mod:`gridlib.units`).
"""

from __future__ import annotations

import numpy as np

from ..connectivity import repeat_ids
from ..cornerpoint.corners import corner_points
from ..cornerpoint.deck import Deck
from ..geometry import cross
from ..grid import FloatArray, Grid, IntArray
from ..units import MILLIDARCY, UnitSystem

# Corners (a + 2b + 4c) of each logical face W, E, S, N, T, B (grid.W..grid.B)
FACE_CORNERS = np.array([[0, 2, 4, 6], [1, 3, 5, 7], [0, 1, 4, 5], [2, 3, 6, 7], [0, 1, 2, 3], [4, 5, 6, 7]])
HALF_MINIMUM = 1e-30  # m3: below this a half-transmissibility makes the connection 0 (Flow)
_BLOCK = 1 << 16  # cells per block of corner coordinates


def cell_and_face_centres(deck: Deck, cells: IntArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Centres (n, 3) of ``cells`` (linear ijk indices) and of their six logical faces
    (n, 6, 3), means of the 8 and of the 4 corners, and the area vector (n, 3) of each
    cell's bottom face, in the processed grid's frame."""
    cells = np.asarray(cells, dtype=np.int64)
    centre = np.empty((cells.size, 3))
    faces = np.empty((cells.size, 6, 3))
    bottom = np.empty((cells.size, 3))
    for s in range(0, cells.size, _BLOCK):
        p = corner_points(deck, cells[s : s + _BLOCK])  # (m, 8, 3)
        acc = p[:, 0].copy()
        for c in range(1, 8):
            acc += p[:, c]
        centre[s : s + _BLOCK] = acc / 8.0
        for f, (a, b, c, d) in enumerate(FACE_CORNERS):
            faces[s : s + _BLOCK, f] = (((p[:, a] + p[:, b]) + p[:, c]) + p[:, d]) / 4.0
        bottom[s : s + _BLOCK] = quad_vector_area(p[:, 4], p[:, 5], p[:, 7], p[:, 6])
    return centre, faces, bottom


def quad_vector_area(p0: FloatArray, p1: FloatArray, p2: FloatArray, p3: FloatArray) -> FloatArray:
    """½ (p0 - p2) x (p1 - p3): the area vector of the quad p0 p1 p2 p3 (rows), planar or not."""
    return 0.5 * cross((p0 - p2).T, (p1 - p3).T).T


def vector_areas(grid: Grid, faces: IntArray) -> FloatArray:
    """½ sum p_k x p_k+1 over the node cycle of each of ``faces``: (m, 3) area vectors."""
    pos = grid.faces.node_pos
    starts, counts = pos[faces], pos[faces + 1] - pos[faces]
    owner = np.repeat(np.arange(faces.size), counts)
    idx = np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
    here = grid.faces.nodes[np.repeat(starts, counts) + idx]
    nxt = grid.faces.nodes[np.repeat(starts, counts) + (idx + 1) % np.repeat(counts, counts)]
    p, q = grid.nodes.coords[here], grid.nodes.coords[nxt]
    c = cross(p.T, q.T)  # (3, entries)
    return np.stack([np.bincount(owner, c[d], faces.size) for d in range(3)], axis=1) * 0.5


def interior_half_faces(grid: Grid) -> tuple[IntArray, IntArray, IntArray, IntArray, IntArray]:
    """The interior faces f and, for each, its two cells and their logical face tags:
    (f, cell_a, tag_a, cell_b, tag_b), a = neighbors[f, 0]."""
    nb = grid.faces.neighbors
    hf_cell = repeat_ids(grid.cells.face_pos)
    hf_face = grid.cells.faces
    tag = grid.cells.face_tag
    first = hf_cell == nb[hf_face, 0]
    tag_of = np.full((grid.num_faces, 2), -1, dtype=np.int64)
    tag_of[hf_face, np.where(first, 0, 1)] = tag
    f = np.flatnonzero((nb >= 0).all(axis=1))
    return f, nb[f, 0], tag_of[f, 0], nb[f, 1], tag_of[f, 1]


def half_transmissibilities(
    area: FloatArray, centre: FloatArray, face_centre: FloatArray, perm: FloatArray
) -> FloatArray:
    """K |A . d| / (d . d) with d = face_centre - centre (rows), K per row (mD, deck lengths)."""
    d = face_centre - centre
    num = (area[:, 0] * d[:, 0] + area[:, 1] * d[:, 1]) + area[:, 2] * d[:, 2]
    den = (d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1]) + d[:, 2] * d[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(den > 0.0, perm * np.abs(num) / den, 0.0)


def combine(ta: FloatArray, tb: FloatArray, units: UnitSystem) -> FloatArray:
    """The harmonic combination of two halves (mD x deck length), in the deck's unit;
    0 where a half is below ``HALF_MINIMUM`` m3."""
    si = MILLIDARCY * units.length
    small = (ta * si < HALF_MINIMUM) | (tb * si < HALF_MINIMUM)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(small, 0.0, 1.0 / (1.0 / np.where(small, 1.0, ta) + 1.0 / np.where(small, 1.0, tb)))
    return t * (si / units.transmissibility)
