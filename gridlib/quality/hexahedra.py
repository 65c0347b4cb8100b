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

EDGE_TOLERANCE = 1e-5  # xtgeo's FLOATEPS, in the grid's length unit

# The quadrilaterals as corner cycles (corner a + 2b + 4c).
TOP_BASE = ((0, 1, 3, 2), (4, 5, 7, 6))
SIDES = ((4, 5, 1, 0), (5, 7, 3, 1), (6, 4, 0, 2), (7, 6, 2, 3))  # south, east, west, north


def _quad_angles(corners: FloatArray, cycles: tuple[tuple[int, ...], ...]) -> tuple[FloatArray, FloatArray]:
    """(min, max) over the corner angles of the quadrilaterals ``cycles``; (0, 180) where an
    edge is shorter than :data:`EDGE_TOLERANCE`."""
    n = corners.shape[0]
    lo = np.full(n, np.inf)
    hi = np.full(n, -np.inf)
    short = np.zeros(n, dtype=bool)
    for cyc in cycles:
        for m, v in enumerate(cyc):
            u = corners[:, cyc[m - 1]] - corners[:, v]
            w = corners[:, cyc[(m + 1) % 4]] - corners[:, v]
            short |= (np.sqrt((u * u).sum(axis=1)) < EDGE_TOLERANCE) | (
                np.sqrt((w * w).sum(axis=1)) < EDGE_TOLERANCE
            )
            a = vector_angles(u, w)
            np.fmin(lo, a, out=lo)
            np.fmax(hi, a, out=hi)
    lo[short] = 0.0
    hi[short] = 180.0
    bad = ~np.isfinite(corners).all(axis=(1, 2))
    lo[bad] = np.nan
    hi[bad] = np.nan
    return lo, hi


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


def _concave_proj(corners: FloatArray) -> FloatArray:
    n = corners.shape[0]
    out = np.zeros(n)
    found = np.zeros(n, dtype=bool)
    for level in (0, 4):
        xy = corners[:, level : level + 4, :2]
        for k in range(4):
            others = [m for m in range(4) if m != k]
            inside = _inside_triangles(xy[:, k], xy[:, others]) & ~found
            out[inside] = k + 1
            found |= inside
    return out


def _twist(corners: FloatArray) -> FloatArray:
    axis = (corners[:, 4:] - corners[:, :4]).mean(axis=1)
    length = np.sqrt((axis * axis).sum(axis=1))
    with np.errstate(invalid="ignore", divide="ignore"):
        k = axis / length[:, None]
    out = np.full(corners.shape[0], -np.inf)
    for step in (1, 2):  # i edges (corner m to m + 1), j edges (m to m + 2)
        ends = (0, 2) if step == 1 else (0, 1)
        top = sum(corners[:, e + step] - corners[:, e] for e in ends)
        base = sum(corners[:, 4 + e + step] - corners[:, 4 + e] for e in ends)
        top = top - (top * k).sum(axis=1)[:, None] * k
        base = base - (base * k).sum(axis=1)[:, None] * k
        out = np.fmax(out, vector_angles(top, base))
    out[~np.isfinite(out)] = np.nan
    return out


def hexahedron_quality(corners: FloatArray) -> dict[str, FloatArray]:
    """Every measure of the module docstring for the cells ``corners`` (n, 8, 3), float64
    (flags as 0.0 / 1.0); NaN for rows that are not finite."""
    c = np.asarray(corners, dtype=np.float64)
    out: dict[str, FloatArray] = {}
    out["minangle_topbase"], out["maxangle_topbase"] = _quad_angles(c, TOP_BASE)
    flat = c.copy()
    flat[..., 2] = 0.0
    out["minangle_topbase_proj"], out["maxangle_topbase_proj"] = _quad_angles(flat, TOP_BASE)
    out["minangle_sides"], out["maxangle_sides"] = _quad_angles(c, SIDES)
    thick = c[:, 4:, 2] - c[:, :4, 2]
    out["collapsed"] = (np.abs(thick) < EDGE_TOLERANCE).any(axis=1).astype(np.float64)
    out["negative_thickness"] = (thick < 0.0).any(axis=1).astype(np.float64)
    out["concave_proj"] = _concave_proj(c)
    out["twist"] = _twist(c)
    bad = ~np.isfinite(c).all(axis=(1, 2))
    for name in ("collapsed", "negative_thickness", "concave_proj"):
        out[name][bad] = np.nan
    return out
