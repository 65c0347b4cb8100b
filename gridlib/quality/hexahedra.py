"""The quality of corner-point hexahedra from their eight corners (docs/quality.md).

``corners`` is (n, 8, 3): corner ``a + 2b + 4c`` of a cell lies on its pillar (i + a, j + b),
at its top (c = 0) or bottom (c = 1); z is depth, positive down; lengths in the grid's unit.
A row of NaN is a cell that is not such a hexahedron: its measures are NaN.

The measures and their definitions are xtgeo's ``Grid.get_gridquality_properties`` (its C
kernel ``grdcp3d_quality_indicators``; read for its definitions, described here in our
words), so that a geomodeller comparing the two tools sees the same numbers:

* ``minangle_topbase``, ``maxangle_topbase``: the smallest and largest interior angle
  (degrees) of the top and base quadrilaterals (four corner angles each, the angle at a
  corner between its two edges); ``..._proj``: the same in plan view (z dropped);
* ``minangle_sides``, ``maxangle_sides``: the same over the four lateral quadrilaterals;
* where an edge of one of those quadrilaterals is shorter than ``EDGE_TOLERANCE`` (1e-5 in the
  grid's length unit, xtgeo's constant), the pair is (0, 180): a collapsed cell has every angle;
* ``collapsed``: 1 where the cell's thickness on at least one of its four pillars is below
  1e-5 in absolute value, else 0;
* ``negative_thickness``: 1 where the bottom is above the top on at least one pillar, else 0;
* ``concave_proj``: in plan view, 0 for a convex cell; otherwise 1 + the index (0 to 3, corner
  ``a + 2b``) of the first corner found inside, or on the boundary of, the triangle of the
  other three, looking at the top first, then the base (xtgeo's numbering of the answer).

Our own, for hexahedra:

* ``twist``: the angle (degrees) by which the base turns against the top about the cell's
  vertical axis k (the mean of the four pillar edges, bottom minus top): the i direction of
  the top (the mean of its two i edges) and that of the base are projected on the plane
  normal to k and their angle taken; likewise j; the twist is the larger of the two. 0 for any
  cell whose base is a translate of its top (Cartesian, sheared), phi for a cell whose base is
  its top turned by phi about the vertical.

Angles come from ``atan2(|u x v|, u . v)`` (:func:`gridlib.orientation.vector_angles`: the
same bits on every machine) where xtgeo takes ``acos`` of the cosine: equal to a few 1e-7
degrees, except that a corner whose two edges are exactly collinear is 0 or 180 here and
skipped by xtgeo (its ``acos`` of a cosine rounded beyond 1 is NaN).
"""

from __future__ import annotations

import numpy as np

from ..grid import FloatArray
from ..orientation import vector_angles
from ..threads import in_order

EDGE_TOLERANCE = 1e-5  # xtgeo's FLOATEPS, in the grid's length unit

NAMES = (
    "minangle_topbase", "maxangle_topbase", "minangle_topbase_proj", "maxangle_topbase_proj",
    "minangle_sides", "maxangle_sides", "collapsed", "negative_thickness", "concave_proj", "twist",
)  # fmt: skip
_Sets = list[tuple[FloatArray, FloatArray, FloatArray]]  # corner sets: see _corner_sets
_BLOCK = 1 << 15  # cells per block: the (3, block, 2, 2, 2) temporaries stay small
MAX_THREADS = 2  # blocks of cells measured at once


def dot_components(u: FloatArray, w: FloatArray) -> FloatArray:
    """Sum over the first axis of u * w (components first: contiguous, fast)."""
    out = u[0] * w[0]
    for i in range(1, u.shape[0]):
        out += u[i] * w[i]
    return out


def _edges(ct: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The twelve edges of the cells ``ct`` ((d, 8, n): components first, cells last, so that
    every operation runs over the cells): i edges (d, c, b, n) from corner (0, b, c) to
    (1, b, c), j edges (d, c, a, n), k edges (d, b, a, n)."""
    r = ct.reshape(ct.shape[0], 2, 2, 2, ct.shape[-1])  # (d, c, b, a, n)
    return r[:, :, :, 1] - r[:, :, :, 0], r[:, :, 1] - r[:, :, 0], r[:, 1] - r[:, 0]


def _corner_sets(
    edges: tuple[FloatArray, ...], sides: bool
) -> list[tuple[FloatArray, FloatArray, FloatArray]]:
    """The corners of the quadrilaterals as (e1 (d, X, Y, 1, n), e2 (d, X, 1, Z, n), sign (X, Y,
    Z, 1)): corner (x, y, z)'s angle is the one between e1[x, y] and sign * e2[x, z] (edges
    pointing away from the corner). Top and base: x = c, y = b, z = a; sides: south and north
    (x = b, y = c, z = a), west and east (x = a, y = c, z = b)."""
    ei, ej, ek = edges
    away = np.array([1.0, -1.0])
    sign = away[None, :, None, None] * away[None, None, :, None]  # (1 - 2y)(1 - 2z)
    if not sides:
        return [(ei[:, :, :, None], ej[:, :, None], sign)]
    return [
        (ei.transpose(0, 2, 1, 3)[:, :, :, None], ek[:, :, None], sign),
        (ej.transpose(0, 2, 1, 3)[:, :, :, None], ek.transpose(0, 2, 1, 3)[:, :, None], sign),
    ]


def _quad_angles(edges: tuple[FloatArray, ...], sides: bool) -> tuple[FloatArray, FloatArray]:
    """(min, max) over the corner angles of the top and base (or the four sides) of the cells
    with the :func:`_edges` ``edges``; (0, 180) where an edge is shorter than
    :data:`EDGE_TOLERANCE`. The corners of largest and smallest cosine are found first; only
    their two angles are computed."""
    sets = _corner_sets(edges, sides)
    n = edges[0].shape[-1]
    cos, short = [], np.zeros(n, dtype=bool)
    for e1, e2, sign in sets:
        l1, l2 = np.sqrt(dot_components(e1, e1)), np.sqrt(dot_components(e2, e2))
        short |= ((l1 < EDGE_TOLERANCE) | (l2 < EDGE_TOLERANCE)).reshape(-1, n).any(axis=0)
        with np.errstate(invalid="ignore", divide="ignore"):
            cos.append((sign * dot_components(e1, e2) / (l1 * l2)).reshape(8, n))
    c = np.concatenate(cos) if len(cos) > 1 else cos[0]
    c[np.isnan(c)] = 0.0  # zero edges: the row is short, its angles (0, 180)
    lo = _angles_at(sets, c.argmax(axis=0))
    hi = _angles_at(sets, c.argmin(axis=0))
    lo[short] = 0.0
    hi[short] = 180.0
    return lo, hi


def _angles_at(sets: _Sets, corner: np.ndarray) -> FloatArray:
    """The angle at ``corner`` (an index into the sets' corners, 8 per set) of every cell."""
    d, n = sets[0][0].shape[0], sets[0][0].shape[-1]
    u, w = np.empty((n, d)), np.empty((n, d))
    for s, (e1, e2, _sign) in enumerate(sets):
        rows = np.flatnonzero(corner // 8 == s)
        x, y, z = np.unravel_index(corner[rows] % 8, (2, 2, 2))
        u[rows] = e1[:, x, y, 0, rows].T
        w[rows] = (e2[:, x, 0, z, rows] * ((1 - 2 * y) * (1 - 2 * z))).T  # the sign
    return vector_angles(u, w)


def _inside_triangles(p: FloatArray, tri: FloatArray) -> np.ndarray:
    """Whether the points ``p`` (n, 2) lie inside or on the triangles ``tri`` (n, 3, 2)
    (on a vertex, on an edge, or strictly inside; any orientation, degenerate ones too)."""
    d = tri - p[:, None, :]  # (n, 3, 2)
    on_vertex = ((d[..., 0] == 0.0) & (d[..., 1] == 0.0)).any(axis=1)
    prev = np.roll(d, 1, axis=1)
    cross = prev[..., 0] * d[..., 1] - prev[..., 1] * d[..., 0]
    dot = prev[..., 0] * d[..., 0] + prev[..., 1] * d[..., 1]
    on_edge = ((cross == 0.0) & (dot <= 0.0)).any(axis=1)
    strictly = (cross > 0.0).all(axis=1) | (cross < 0.0).all(axis=1)
    return on_vertex | on_edge | strictly


def _strictly_convex(xy: FloatArray) -> np.ndarray:
    """Whether the plan-view quadrilaterals ``xy`` (n, 4, 2) (corners a + 2b) turn the same
    way, strictly, at all four corners: then no corner lies in the triangle of the others."""
    p = xy[:, [0, 1, 3, 2]]
    e = np.roll(p, -1, axis=1) - p  # edges of the cycle
    f = np.roll(e, -1, axis=1)
    turn = e[..., 0] * f[..., 1] - e[..., 1] * f[..., 0]
    return (turn > 0).all(axis=1) | (turn < 0).all(axis=1)


def _concave_proj(corners: FloatArray) -> FloatArray:
    out = np.zeros(corners.shape[0])
    cells = np.flatnonzero(~(_strictly_convex(corners[:, :4, :2]) & _strictly_convex(corners[:, 4:, :2])))
    found = np.zeros(cells.size, dtype=bool)
    for level in (0, 4):
        xy = corners[cells, level : level + 4, :2]
        for k in range(4):
            others = [m for m in range(4) if m != k]
            inside = _inside_triangles(xy[:, k], xy[:, others]) & ~found
            out[cells[inside]] = k + 1
            found |= inside
    return out


def _twist(edges: tuple[FloatArray, ...]) -> FloatArray:
    """The twist (module docstring) from the cells' :func:`_edges`."""
    ei, ej, ek = edges
    axis = ek[:, 0, 0] + ek[:, 0, 1] + ek[:, 1, 0] + ek[:, 1, 1]  # 4 x the mean
    with np.errstate(invalid="ignore", divide="ignore"):
        k = axis / np.sqrt(dot_components(axis, axis))
    pairs, cos = [], []
    for e in (ei, ej):  # the i (j) direction of the top (c = 0) and of the base (c = 1)
        top, base = e[:, 0, 0] + e[:, 0, 1], e[:, 1, 0] + e[:, 1, 1]
        top = top - dot_components(top, k) * k
        base = base - dot_components(base, k) * k
        with np.errstate(invalid="ignore", divide="ignore"):
            c = dot_components(top, base) / np.sqrt(dot_components(top, top) * dot_components(base, base))
        pairs.append((top, base))
        cos.append(np.where(np.isnan(c), np.inf, c))
    j = cos[1] < cos[0]  # the larger angle
    u = np.where(j, pairs[1][0], pairs[0][0]).T
    w = np.where(j, pairs[1][1], pairs[0][1]).T
    return vector_angles(u, w)


def hexahedron_quality(corners: FloatArray) -> dict[str, FloatArray]:
    """Every measure of the module docstring for the cells ``corners`` (n, 8, 3), float64
    (flags as 0.0 / 1.0); NaN for rows that are not finite. Blocks of cells at a time, on up
    to two threads (each block alone: the same bits for any number of threads)."""
    c = np.asarray(corners, dtype=np.float64)
    n = c.shape[0]
    out = {name: np.empty(n) for name in NAMES}
    blocks = ((slice(s, min(s + _BLOCK, n)),) for s in range(0, n, _BLOCK))
    for part, values in in_order(lambda part: (part, _block_quality(c[part])), blocks, MAX_THREADS):
        for name, v in values.items():
            out[name][part] = v
    return out


def serial_hexahedron_quality(corners: FloatArray) -> dict[str, FloatArray]:
    """:func:`hexahedron_quality` on the calling thread alone (for callers that run blocks of
    cells on threads themselves)."""
    c = np.asarray(corners, dtype=np.float64)
    out = {name: np.empty(c.shape[0]) for name in NAMES}
    for s in range(0, c.shape[0], _BLOCK):
        for name, values in _block_quality(c[s : s + _BLOCK]).items():
            out[name][s : s + _BLOCK] = values
    return out


def _block_quality(c: FloatArray) -> dict[str, FloatArray]:
    out: dict[str, FloatArray] = {}
    edges = _edges(np.ascontiguousarray(c.transpose(2, 1, 0)))  # (3, 8, n)
    flat = tuple(e[:2] for e in edges)  # plan view
    out["minangle_topbase"], out["maxangle_topbase"] = _quad_angles(edges, sides=False)
    out["minangle_topbase_proj"], out["maxangle_topbase_proj"] = _quad_angles(flat, sides=False)
    out["minangle_sides"], out["maxangle_sides"] = _quad_angles(edges, sides=True)
    thick = c[:, 4:, 2] - c[:, :4, 2]
    out["collapsed"] = (np.abs(thick) < EDGE_TOLERANCE).any(axis=1).astype(np.float64)
    out["negative_thickness"] = (thick < 0.0).any(axis=1).astype(np.float64)
    out["concave_proj"] = _concave_proj(c)
    out["twist"] = _twist(edges)
    bad = ~np.isfinite(c).all(axis=(1, 2))
    for name in out:
        out[name][bad] = np.nan
    return out
