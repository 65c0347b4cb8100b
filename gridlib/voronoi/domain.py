"""The domain of a PEBI grid: a simple polygon, handled in local coordinates.

Every computation of :func:`~gridlib.voronoi.pebi_grid.pebi_grid` happens in a
local frame: the input coordinates minus an origin near the centre of the
domain's bounding box, a multiple of a power of two close to the domain's size
(so that at UTM magnitudes the subtraction is exact). Qhull and the formulas for
circumcentres and circle intersections lose digits when the coordinates are large
(500 km from the origin a coordinate is resolved to about 1e-10 m, and these formulas
take differences of products of coordinates, which cancel most of the digits left); in
the local frame, whose coordinates are of the domain's size, they do not.

Units are metres; x, y in plan view. The polygon may be given in either
orientation and is closed implicitly (a repeated first vertex is dropped); it is
stored counter-clockwise with collinear vertices removed.

>>> d = Domain(rectangle(0.0, 0.0, 4.0, 2.0))
>>> d.area, d.xy.shape
(8.0, (4, 2))
>>> Domain([(0, 0), (2, 2), (2, 0), (0, 1)])
Traceback (most recent call last):
...
gridlib.errors.GridError: domain: the polygon's boundary intersects itself near (0.666667, 0.666667)
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import shapely
from numpy.typing import ArrayLike

from ..arrays import point_array
from ..errors import GridError
from ..planar import cross2
from ..reproducible import arctan2


def rectangle(xmin: float, ymin: float, xmax: float, ymax: float) -> np.ndarray:
    """The four vertices (counter-clockwise) of an axis-parallel rectangle, in metres.

    >>> rectangle(0, 0, 2, 1).tolist()
    [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]
    """
    if not (np.isfinite([xmin, ymin, xmax, ymax]).all() and xmax > xmin and ymax > ymin):
        raise GridError(
            f"rectangle: need xmin < xmax and ymin < ymax, got ({xmin}, {ymin}), ({xmax}, {ymax})"
        )
    return np.array([[xmin, ymin], [xmax, ymin], [xmax, ymax], [xmin, ymax]], dtype=np.float64)


def polygon_vertices(domain: object, what: str = "domain") -> np.ndarray:
    """The vertices (n, 2) of a domain given as vertices, two corners or a shapely Polygon."""
    vertices: object = domain
    if isinstance(domain, shapely.Polygon):
        if len(domain.interiors):
            raise GridError(f"{what}: polygons with holes are not supported")
        vertices = domain.exterior.coords
    elif isinstance(domain, shapely.LineString | shapely.LinearRing):
        if not domain.is_closed:
            raise GridError(f"{what}: the line is not closed; give a polygon (its vertices)")
        vertices = domain.coords
    xy = point_array(vertices, 2, what, point="vertex", error=GridError)
    if xy.shape[0] == 2:  # two opposite corners of a rectangle
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        if np.any(hi <= lo):
            raise GridError(f"{what}: the two corners {xy.tolist()} do not span a rectangle")
        return rectangle(lo[0], lo[1], hi[0], hi[1])
    return xy


class Domain:
    """A simple polygon (no holes) in a local frame.

    Attributes: ``origin`` (2,) subtracted from every input coordinate; ``xy``
    (M, 2) the counter-clockwise vertices in the local frame; ``polygon`` the
    shapely polygon of ``xy`` (prepared); ``area`` (m²); ``diameter`` (m, of the
    bounding box); ``tol`` (m) the length below which two points are one; ``reflex``
    (M,) which corners are re-entrant (interior angle above 180°).
    """

    def __init__(self, domain: object, what: str = "domain") -> None:
        xy = polygon_vertices(domain, what)
        if xy.shape[0] > 1 and np.all(xy[0] == xy[-1]):
            xy = xy[:-1]
        keep = np.any(xy != np.roll(xy, 1, axis=0), axis=1)
        xy = xy[keep] if keep.any() else xy[:1]
        if xy.shape[0] < 3:
            raise GridError(f"{what}: a polygon needs at least 3 distinct vertices, got {xy.shape[0]}")
        rel = xy - xy[0]
        if np.all(np.abs(cross2(rel, rel[-1 if np.any(rel[-1]) else 1])) <= 1e-12 * np.abs(rel).max() ** 2):
            raise GridError(f"{what}: the polygon encloses no area (its vertices are collinear)")
        if not shapely.LinearRing(xy).is_simple:
            p = _self_intersection(xy)
            raise GridError(
                f"{what}: the polygon's boundary intersects itself near ({_fmt(p[0])}, {_fmt(p[1])})"
            )
        lo, hi = xy.min(axis=0), xy.max(axis=0)
        extent = float(np.max(hi - lo))
        centre = 0.5 * (lo + hi)
        quantum = math.ldexp(1.0, math.frexp(extent)[1] - 1) if extent > 0 else 1.0  # 2^floor(log2)
        self.origin = np.round(centre / quantum) * quantum  # x - origin exact for |x| >> extent
        local = xy - self.origin
        self.diameter = float(np.hypot(*(hi - lo)))
        area2 = float(cross2(local, np.roll(local, -1, axis=0)).sum())
        if not abs(area2) > 1e-12 * self.diameter**2:
            raise GridError(f"{what}: the polygon encloses no area (are its vertices collinear?)")
        if area2 < 0:
            local = local[::-1].copy()
        self.tol = 1e-10 * self.diameter
        # Drop vertices where the boundary goes straight on (they carry no corner).
        prev, nxt = np.roll(local, 1, axis=0), np.roll(local, -1, axis=0)
        d_in, d_out = local - prev, nxt - local
        turn = cross2(d_in, d_out)
        straight = (np.abs(turn) <= 1e-12 * np.linalg.norm(d_in, axis=1) * np.linalg.norm(d_out, axis=1)) & (
            (d_in * d_out).sum(axis=1) > 0
        )
        local = local[~straight]
        ring = shapely.LinearRing(local)
        if not ring.is_simple:
            p = _self_intersection(local)
            raise GridError(
                f"{what}: the polygon's boundary intersects itself near "
                f"({_fmt(p[0] + self.origin[0])}, {_fmt(p[1] + self.origin[1])})"
            )
        self.xy = local
        self.xy.flags.writeable = False
        self.polygon = shapely.Polygon(local)
        shapely.prepare(self.polygon)
        self.area = 0.5 * abs(area2)
        self.edge_a = local
        self.edge_b = np.roll(local, -1, axis=0)
        self.edge_vec = self.edge_b - self.edge_a
        self.edge_len = np.linalg.norm(self.edge_vec, axis=1)
        self.edge_unit = self.edge_vec / self.edge_len[:, None]
        d_in = self.edge_unit[np.arange(local.shape[0]) - 1]
        self.reflex = cross2(d_in, self.edge_unit) < 0  # re-entrant corners: the boundary turns clockwise
        self.cum = np.concatenate([[0.0], np.cumsum(self.edge_len)])
        self.perimeter = float(self.cum[-1])
        self._edge_tree = shapely.STRtree(shapely.linestrings(np.stack([self.edge_a, self.edge_b], axis=1)))

    @property
    def num_vertices(self) -> int:
        return self.xy.shape[0]

    def to_local(self, p: ArrayLike) -> np.ndarray:
        return np.asarray(p, dtype=np.float64) - self.origin

    def fmt(self, p: Sequence[float] | np.ndarray) -> str:
        """A local point written in global coordinates, for messages."""
        return f"({_fmt(p[0] + self.origin[0])}, {_fmt(p[1] + self.origin[1])})"

    def inside(self, p: np.ndarray) -> np.ndarray:
        """Strictly inside (boundary points may go either way: use ``boundary_distance``)."""
        p = np.asarray(p, dtype=np.float64).reshape(-1, 2)
        return shapely.contains_xy(self.polygon, p[:, 0], p[:, 1])

    def covers(self, p: np.ndarray, tol: float | None = None) -> np.ndarray:
        """Inside or within ``tol`` (default ``self.tol``) of the boundary."""
        tol = self.tol if tol is None else tol
        p = np.asarray(p, dtype=np.float64).reshape(-1, 2)
        ins = self.inside(p)
        out = np.flatnonzero(~ins)
        if out.size:
            ins[out] = self.boundary_distance(p[out]) <= tol
        return ins

    def boundary_distance(self, p: np.ndarray) -> np.ndarray:
        """Distance (m) of local points to the polygon's boundary."""
        return self.nearest_boundary(p)[0]

    def nearest_boundary(self, p: np.ndarray):
        """Distance to the boundary, nearest edge and parameter u in [0, 1] along it."""
        p = np.asarray(p, dtype=np.float64).reshape(-1, 2)
        if p.shape[0] == 0:
            return np.zeros(0), np.zeros(0, dtype=np.int64), np.zeros(0)
        geoms = shapely.points(p)
        idx = self._edge_tree.query_nearest(geoms, all_matches=False)
        pt, edge = idx[0], idx[1]
        order = np.argsort(pt, kind="stable")
        edge = edge[order]
        rel = p - self.edge_a[edge]
        u = np.clip((rel * self.edge_unit[edge]).sum(axis=1) / self.edge_len[edge], 0.0, 1.0)
        foot = self.edge_a[edge] + u[:, None] * self.edge_vec[edge]
        return np.linalg.norm(p - foot, axis=1), edge.astype(np.int64), u

    def boundary_rays(self, p: np.ndarray) -> list[float]:
        """Directions (angles) of the domain boundary leaving a boundary point."""
        _, edge, u = self.nearest_boundary(p[None, :])
        e, uu = int(edge[0]), float(u[0])
        m = self.num_vertices
        eps = self.tol / self.edge_len[e]
        if uu <= eps:
            d1, d2 = self.edge_unit[e], -self.edge_unit[(e - 1) % m]
        elif uu >= 1 - eps:
            d1, d2 = self.edge_unit[(e + 1) % m], -self.edge_unit[e]
        else:
            d1, d2 = self.edge_unit[e], -self.edge_unit[e]
        return [float(arctan2(d1[1], d1[0])), float(arctan2(d2[1], d2[0]))]

    def perimeter_param(self, edge: np.ndarray, u: np.ndarray) -> np.ndarray:
        return self.cum[edge] + u * self.edge_len[edge]

    def inner_buffer(self, distance: float) -> shapely.Geometry:
        """The points farther than ``distance`` from the boundary (conservative, prepared)."""
        geom = self.polygon.buffer(-1.02 * distance, quad_segs=8)
        shapely.prepare(geom)
        return geom

    def segment_edge_pairs(self, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Candidate (segment, boundary edge) pairs whose bounding boxes overlap."""
        if a.shape[0] == 0:
            return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
        lines = shapely.linestrings(np.stack([a, b], axis=1))
        seg, edge = self._edge_tree.query(lines)
        return seg.astype(np.int64), edge.astype(np.int64)

    def crossings(self, a: np.ndarray, b: np.ndarray, tol: float):
        """Where segments a -> b cross the boundary.

        Returns (segment, t, edge, u): the crossing lies at ``a + t (b - a)`` and at
        ``edge_a[edge] + u edge_vec[edge]``. Crossings within ``tol`` of a segment end
        have t snapped to 0 or 1, within ``tol`` of a polygon vertex u to 0 or 1.
        Segments within ``tol`` of an edge's line at both ends (running along it) give
        no crossing.

        The crossing is found from the signed distances of the segment's ends to the edge's
        line, so that a segment nearly parallel to an edge (a Voronoi ridge through a corner,
        along its edge) crosses where it actually does, not wherever round-off puts it.
        """
        seg, edge = self.segment_edge_pairs(a, b)
        nrm = np.column_stack([-self.edge_unit[edge, 1], self.edge_unit[edge, 0]])
        rel_a, rel_b = a[seg] - self.edge_a[edge], b[seg] - self.edge_a[edge]
        sa = rel_a[:, 0] * nrm[:, 0] + rel_a[:, 1] * nrm[:, 1]
        sb = rel_b[:, 0] * nrm[:, 0] + rel_b[:, 1] * nrm[:, 1]
        on_a, on_b = np.abs(sa) <= tol, np.abs(sb) <= tol
        ok = (on_a | on_b | (sa * sb < 0)) & ~(on_a & on_b)
        seg, edge, sa, sb, on_a, on_b, nrm = seg[ok], edge[ok], sa[ok], sb[ok], on_a[ok], on_b[ok], nrm[ok]
        t = np.where(on_a, 0.0, np.where(on_b, 1.0, sa / np.where(on_a | on_b, 1.0, sa - sb)))
        r = b[seg] - a[seg]
        rl = np.hypot(r[:, 0], r[:, 1])
        x = a[seg] + t[:, None] * r
        rel = x - self.edge_a[edge]
        unit = self.edge_unit[edge]
        u = (rel[:, 0] * unit[:, 0] + rel[:, 1] * unit[:, 1]) / self.edge_len[edge]
        et = tol / np.maximum(rl, 1e-300)
        eu = tol / self.edge_len[edge]
        # A segment passing within tol of a corner crosses there (at a shallow angle to one of the
        # edges, its crossing with that edge's line may lie farther from the corner than tol).
        for end, corner in ((0.0, self.edge_a[edge]), (1.0, self.edge_b[edge])):
            rel = corner - a[seg]
            w = np.clip((rel[:, 0] * r[:, 0] + rel[:, 1] * r[:, 1]) / np.maximum(rl**2, 1e-300), 0.0, 1.0)
            gap = np.hypot(rel[:, 0] - w * r[:, 0], rel[:, 1] - w * r[:, 1])
            snap = (gap <= tol) & (np.abs(u - end) * self.edge_len[edge] <= np.sqrt(tol * rl) + tol)
            u, t = np.where(snap, end, u), np.where(snap, w, t)
        hit = (u >= -eu) & (u <= 1 + eu)
        seg, edge, t, u, et, eu = seg[hit], edge[hit], t[hit], u[hit], et[hit], eu[hit]
        t = np.where(t <= et, 0.0, np.where(t >= 1 - et, 1.0, t))
        # A crossing at a polygon vertex counts once, on the edge that starts there.
        at_end = u >= 1 - eu
        edge = np.where(at_end, (edge + 1) % self.num_vertices, edge)
        u = np.where(at_end | (u <= eu), 0.0, u)
        key = np.unique(np.column_stack([seg, edge, np.round(t * 2**40)]), axis=0, return_index=True)[1]
        key.sort()
        return seg[key], t[key], edge[key], u[key]


def _fmt(v: float) -> str:
    """A coordinate for messages: millimetres for metre-sized and larger values (UTM too)."""
    if abs(v) >= 1.0:
        return f"{v:.3f}".rstrip("0").rstrip(".")
    return f"{v:.6g}"


def _self_intersection(xy: np.ndarray) -> np.ndarray:
    """A point where a closed polyline crosses itself (for messages)."""
    a, b = xy, np.roll(xy, -1, axis=0)
    n = a.shape[0]
    i, j = np.triu_indices(n, 2)
    adjacent = (j == i + 1) | ((i == 0) & (j == n - 1))
    i, j = i[~adjacent], j[~adjacent]
    r, s, q = b[i] - a[i], b[j] - a[j], a[j] - a[i]
    den = cross2(r, s)
    with np.errstate(divide="ignore", invalid="ignore"):
        t, u = cross2(q, s) / den, cross2(q, r) / den
    hit = (t >= 0) & (t <= 1) & (u >= 0) & (u <= 1) & (den != 0)
    if hit.any():
        k = int(np.flatnonzero(hit)[0])
        return a[i[k]] + t[k] * r[k]
    # collinear overlap or a repeated vertex
    _, inv, cnt = np.unique(xy, axis=0, return_inverse=True, return_counts=True)
    if np.any(cnt > 1):
        return xy[np.flatnonzero(cnt[inv.ravel()] > 1)[0]]
    return xy[0]
