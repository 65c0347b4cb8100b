"""A 3-D grid cut by a vertical section: each cell's polygon in the section and the faults'
lines, in (distance along the section, depth), exact for cells with planar faces.

The section is a polyline in plan view (x, y); each of its segments is a vertical plane,
clipped to the segment. Per segment, vectorised over the faces the plane crosses:

1. every node's signed distance to the plane (a node on the plane counts on its positive side,
   so that a face lying in the plane belongs to the one cell on its negative side, not both);
2. every edge of a crossed face whose ends lie on opposite sides gives a point (edges are taken
   with their node pair sorted, so that the faces sharing an edge give the same bits);
3. a cell's polygon is its faces' points (duplicates dropped) in cyclic order: sorted by a
   pseudo-angle (no trigonometry) around their mean; exact for convex cuts, which the cuts of
   convex cells are (and the order is unchanged by the different scales of distance and depth);
   the cut of a non-convex cell (a corner-point cell bent at a fault's sub-faces, say) is drawn
   as the polygon star-shaped around that mean through the same points;
4. a fault face's points (two for a convex face) make its line;
5. polygons and lines are clipped to the segment's extent (Sutherland-Hodgman on the two
   lines of constant distance; the cuts are convex, so each clip is one pass).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..connectivity import offsets, repeat_ids
from ..grid import Grid
from .top_surface import face_edges


@dataclass(frozen=True)
class SectionCut:
    """The cut of a grid by a section: ``polygons`` (n, ragged) as ``pos`` (n + 1 offsets) into
    ``points`` ((m, 2): distance along the section from its start, depth), the grid cell of each
    (``cells``), the fault lines (``fault_lines`` (k, 2, 2), same coordinates) with their fault
    ids (``fault_ids``), and where the section's vertices are (``vertices``: the distance of each
    point of the line). Lengths in the grid's unit."""

    pos: np.ndarray
    points: np.ndarray
    cells: np.ndarray
    fault_lines: np.ndarray
    fault_ids: np.ndarray
    vertices: np.ndarray

    def areas(self) -> np.ndarray:
        """The area of each polygon (shoelace formula)."""
        p = self.points
        owner = repeat_ids(self.pos)
        nxt = np.arange(p.shape[0]) + 1
        nxt[self.pos[1:] - 1] = self.pos[:-1]
        cross = p[:, 0] * p[nxt, 1] - p[nxt, 0] * p[:, 1]
        return 0.5 * np.abs(np.bincount(owner, cross, self.cells.size))


def cut_grid(grid: Grid, line: np.ndarray) -> SectionCut:
    """The :class:`SectionCut` of the 3-D ``grid`` by the vertical section along ``line``
    ((k, 2) x, y; consecutive points distinct)."""
    line = np.asarray(line, dtype=np.float64)
    lengths = np.hypot(*np.diff(line, axis=0).T)
    vertices = np.concatenate([[0.0], np.cumsum(lengths)])
    parts = [_cut_segment(grid, line[j], line[j + 1], vertices[j]) for j in range(lengths.size)]
    counts = np.concatenate([np.diff(p[0]) for p in parts])
    cut = SectionCut(
        offsets(counts),
        np.concatenate([p[1] for p in parts]),
        np.concatenate([p[2] for p in parts]),
        np.concatenate([p[3] for p in parts]),
        np.concatenate([p[4] for p in parts]),
        vertices,
    )
    # a cell touching a segment's end only (the clip leaves a polygon of no width) is no cut
    areas = cut.areas()
    flat = areas <= 1e-12 * (areas.max() if areas.size else 0.0)
    if not flat.any():
        return cut
    keep = ~flat
    owner = repeat_ids(cut.pos)
    return SectionCut(
        offsets(counts[keep]),
        cut.points[keep[owner]],
        cut.cells[keep],
        cut.fault_lines,
        cut.fault_ids,
        vertices,
    )


def _cut_segment(grid: Grid, a: np.ndarray, b: np.ndarray, start: float):
    """The cut by the plane through ``a`` -> ``b`` (plan view), clipped to the segment, with
    distances from ``start`` (the segment's start along the whole line)."""
    u = (b - a) / np.hypot(*(b - a))
    xyz = grid.nodes.coords
    rel = xyz[:, :2] - a
    side = rel[:, 0] * -u[1] + rel[:, 1] * u[0]  # signed distance to the plane
    along = rel[:, 0] * u[0] + rel[:, 1] * u[1]
    positive = side >= 0
    counts = np.diff(grid.faces.node_pos)
    on_positive = np.bincount(repeat_ids(grid.faces.node_pos), positive[grid.faces.nodes], counts.size)
    crossed = np.flatnonzero((on_positive > 0) & (on_positive < counts))
    edges, owner = face_edges(grid, crossed)
    edges = np.sort(edges, axis=1)
    n0, n1 = edges[:, 0], edges[:, 1]
    cuts = positive[n0] != positive[n1]
    n0, n1, owner = n0[cuts], n1[cuts], owner[cuts]
    t = side[n0] / (side[n0] - side[n1])
    point = np.column_stack(
        [along[n0] + t * (along[n1] - along[n0]), xyz[n0, 2] + t * (xyz[n1, 2] - xyz[n0, 2])]
    )
    face = crossed[owner]
    polygons = _cell_polygons(grid, face, point)
    length = float(np.hypot(*(b - a)))
    pos_c, pts, cells = _clip_polygons(*polygons, 0.0, +1.0)
    pos_c, pts, cells = _clip_polygons(pos_c, pts, cells, length, -1.0)
    lines, ids = _fault_lines(grid, face, point, length)
    pts = pts + np.array([start, 0.0])
    lines = lines + np.array([start, 0.0])
    return pos_c, pts, cells, lines, ids


def _cell_polygons(grid: Grid, face: np.ndarray, point: np.ndarray):
    """Each cut cell's points (the points of its faces' crossed edges, duplicates dropped) in
    cyclic order: (pos, points, cells)."""
    nb = grid.faces.neighbors[face]
    cell = np.concatenate([nb[:, 0], nb[:, 1]])
    pts = np.concatenate([point, point])
    keep = cell >= 0
    cell, pts = cell[keep], pts[keep]
    order = np.lexsort((pts[:, 1], pts[:, 0], cell))
    cell, pts = cell[order], pts[order]
    new = np.ones(cell.size, dtype=bool)
    new[1:] = (cell[1:] != cell[:-1]) | (pts[1:] != pts[:-1]).any(axis=1)
    cell, pts = cell[new], pts[new]
    cells, counts = np.unique(cell, return_counts=True)
    owner = np.repeat(np.arange(cells.size), counts)
    centre = np.column_stack([np.bincount(owner, pts[:, k]) / counts for k in range(2)])
    d = pts - centre[owner]
    scale = np.abs(d).max(axis=0, initial=0.0)
    d = d / np.where(scale > 0, scale, 1.0)
    angle = _pseudo_angle(d[:, 0], d[:, 1])
    pts = pts[np.lexsort((angle, owner))]  # owner is sorted: each cell's points stay together
    keep = counts >= 3
    return offsets(counts[keep]), pts[keep[owner]], cells[keep]


def _pseudo_angle(dx: np.ndarray, dy: np.ndarray) -> np.ndarray:
    """A monotone function of the angle of (dx, dy) in [-1, 3): no trigonometry."""
    r = np.abs(dx) + np.abs(dy)
    p = np.divide(dy, r, out=np.zeros_like(dy), where=r > 0)
    return np.where(dx >= 0, p, 2.0 - p)


def _clip_polygons(pos: np.ndarray, pts: np.ndarray, cells: np.ndarray, limit: float, sense: float):
    """Convex polygons (pos, pts, cells) clipped to ``sense * (distance - limit) >= 0``
    (Sutherland-Hodgman, vectorised: each edge gives its start if inside and its crossing if it
    crosses); polygons left with under 3 points are dropped."""
    if pts.shape[0] == 0:
        return pos, pts, cells
    f = sense * (pts[:, 0] - limit)
    nxt = np.arange(pts.shape[0]) + 1
    nxt[pos[1:] - 1] = pos[:-1]
    inside = f >= 0
    crosses = inside != inside[nxt]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(crosses, f / (f - f[nxt]), 0.0)
    crossing = pts + t[:, None] * (pts[nxt] - pts)
    crossing[crosses, 0] = limit  # exactly on the line
    take = np.column_stack([inside, crosses])  # per edge: its start, then its crossing
    both = np.stack([pts, crossing], axis=1)[take]
    owner = np.repeat(repeat_ids(pos), take.sum(axis=1))
    counts = np.bincount(owner, minlength=cells.size)
    keep = counts >= 3
    return offsets(counts[keep]), both[keep[owner]], cells[keep]


def _fault_lines(grid: Grid, face: np.ndarray, point: np.ndarray, length: float):
    """The lines of the crossed fault faces (each face's shallowest and deepest point), clipped
    to 0 <= distance <= ``length``: (lines (k, 2, 2), fault ids (k,))."""
    tag = grid.faces.tag[face]
    fault = tag > 0
    face, point = face[fault], point[fault]
    if face.size == 0:
        return np.zeros((0, 2, 2)), np.zeros(0, dtype=np.int64)
    order = np.lexsort((point[:, 1], face))
    face, point = face[order], point[order]
    first = np.r_[True, face[1:] != face[:-1]]
    last = np.r_[face[1:] != face[:-1], True]
    lines = np.stack([point[first], point[last]], axis=1)
    ids = grid.faces.tag[face[first]].astype(np.int64)
    lo, hi = clip_parts([lines[:, 0, 0], length - lines[:, 0, 0]], [lines[:, 1, 0], length - lines[:, 1, 0]])
    keep = lo < hi
    d = lines[:, 1] - lines[:, 0]
    clipped = np.stack([lines[:, 0] + lo[:, None] * d, lines[:, 0] + hi[:, None] * d], axis=1)
    return clipped[keep], ids[keep]


def clip_parts(start: list[np.ndarray], end: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The parameter interval [lo, hi] (within [0, 1]) of each of m straight segments where
    every one of the functions, linear along the segments and given by their values at the
    segments' ``start`` and ``end`` ((m,) each), is >= 0; lo > hi where there is none.

    >>> lo, hi = clip_parts([np.array([-1.0, 1.0])], [np.array([1.0, -3.0])])
    >>> lo.tolist(), hi.tolist()
    ([0.5, 0.0], [1.0, 0.25])
    """
    m = start[0].size
    lo, hi = np.zeros(m), np.ones(m)
    for f0, f1 in zip(start, end, strict=True):
        df = f1 - f0
        with np.errstate(divide="ignore", invalid="ignore"):
            root = np.where(df != 0, -f0 / np.where(df != 0, df, 1.0), 0.0)
        lo = np.where(df > 0, np.maximum(lo, root), lo)
        hi = np.where(df < 0, np.minimum(hi, root), hi)
        hi = np.where((df == 0) & (f0 < 0), -1.0, hi)
    return lo, hi
