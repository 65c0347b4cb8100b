"""Sites of a well path: a row on the path and mirrored rows beside it.

A well's paths (one polyline, or several branches and points) are first made one planar
graph (:func:`path_graph`): coincident points become one node, a segment is split where
another branch starts or ends on it, shared stretches are kept once. Every segment gets
``n = round(length / spacing)`` equal steps ``s``; the *path sites* are the nodes and the
step points in between, so they lie exactly on the path.

The *side rows* (:func:`path_rows`) make the cells of the path sites symmetric about the
path. Along a segment, one site lies on either side of the midpoint of every step, at
``SIDE s = sqrt(3)/2 s`` from the path: the path sites and their side sites form
equilateral triangles, and each side site is the mirror image of its partner across the
path (the same construction as the mirrored pairs of fault sites, here with a site on the
line between them). The cell of a path site on a straight stretch is then a hexagon bounded
by the bisectors with its two neighbours on the path and with its four side sites; the set
of sites that bound it is mirrored by the path line, so the cell is too, and its centroid
lies on the path (to round-off). Where the steps of consecutive segments differ on a
straight line the cell is still mirrored about the line (no longer about its site).

Around a node the sites beside it are placed by the angular *sectors* between its arms: in
a sector of angle S, the first side site of each bounding arm lies 60 degrees from it at
the arm's step ``s`` from the node (that is the step's side site above); the gap of
S - 120 degrees between them is filled with sites on the circle of radius s, about 60
degrees apart. A straight node (S = 180) adds nothing, the end of a path (S = 360) gets two
more sites beside it and one straight ahead (its cell is the regular hexagon too, centred
on the end point), a point with no arm (a vertical part of a trajectory) six around it. An
inner corner whose two sites would come closer than 30 degrees gets one site in its middle,
and none if the sector is narrower than 90 degrees. Then every side site closer than
``NEAR`` x the step to a segment of the path is dropped (sharp bends, branches leaving at
small angles), and side sites closer than ``MERGE`` x their step to each other are merged.
At bends and junctions the cells are not symmetric: centroids lie on the path only along
straight stretches (from the second step after a bend on).

Background sites must stay clear: none within ``band`` of the path (``SIDE s + BAND
max(s, h)``, h the cell size, beyond every circle through three of these sites that bounds a
path cell, whose farthest point is 2/sqrt(3) s from the path) and none within ``MERGE`` x
its step of a side site.

Units are metres in the local frame of the domain.

>>> import numpy as np
>>> g = path_graph([np.array([[0.0, 0.0], [4.0, 0.0]])], 1e-9, "W")
>>> n, node_step = segment_steps(g, 1.0, None)
>>> rows = path_rows(g, n, node_step)
>>> rows.on_path[:, 0].tolist(), rows.on_path[:, 1].tolist()
([0.0, 4.0, 1.0, 2.0, 3.0], [0.0, 0.0, 0.0, 0.0, 0.0])
>>> rows.side.shape[0]  # 4 steps x 2 sides + 3 beyond each end
14
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from scipy import sparse
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

from ..connectivity import ragged_arange
from ..errors import GridError
from ..reproducible import arctan2

SIDE = math.sqrt(3.0) / 2  # lateral offset of the side rows / step (equilateral triangles)
NEAR = 0.7  # side sites closer than this x a segment's step to it are dropped
MERGE = 0.5  # side sites closer than this x their step to each other are merged
BAND = 0.6  # background sites are removed within SIDE s + BAND max(s, h) of the path
CLEAR = 0.3  # other wells keep SIDE s + CLEAR max(s, h) from the path
EDGE = 0.25  # side sites closer than this x their step to the domain's boundary are dropped
THIRD = np.pi / 3


@dataclass(frozen=True, eq=False)
class PathGraph:
    """A well's paths as one planar graph (local frame, m): ``nodes`` (k, 2), ``seg`` (m, 2)
    node ids of every straight segment (each once, no two crossing)."""

    nodes: np.ndarray
    seg: np.ndarray

    @property
    def isolated(self) -> np.ndarray:
        """The nodes on no segment (points of the path: vertical parts of a trajectory)."""
        used = np.zeros(self.nodes.shape[0], dtype=bool)
        used[self.seg.reshape(-1)] = True
        return np.flatnonzero(~used)

    @property
    def geometry(self) -> shapely.Geometry:
        """The segments and the isolated points as one shapely geometry."""
        parts = list(shapely.linestrings(self.nodes[self.seg])) if self.seg.size else []
        parts += list(shapely.points(self.nodes[self.isolated]))
        return parts[0] if len(parts) == 1 else shapely.GeometryCollection(parts)


@dataclass(frozen=True, eq=False)
class PathRows:
    """The sites of one well's paths (local frame, m): ``on_path`` (p, 2) the sites on the path
    (the nodes first, then the step points segment by segment) and their target sizes
    ``on_size``; ``side`` (q, 2) the side rows and ``side_size``."""

    on_path: np.ndarray
    on_size: np.ndarray
    side: np.ndarray
    side_size: np.ndarray


def path_graph(pieces: Sequence[np.ndarray], tol: float, label: str) -> PathGraph:
    """The planar graph of a well's ``pieces`` ((k, 2) polylines; k = 1: a point), local frame.

    Points closer than ``tol`` (m) are one node; a segment is split at every node within
    ``tol`` of its interior; segments given twice are kept once. Raises a GridError naming
    ``label`` where consecutive points of a piece coincide or the path crosses itself.
    """
    sizes = np.array([p.shape[0] for p in pieces], dtype=np.int64)
    pts = np.concatenate(pieces)
    n = pts.shape[0]
    pairs = cKDTree(pts).query_pairs(tol, output_type="ndarray")
    graph = sparse.coo_matrix((np.ones(pairs.shape[0]), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, comp = csgraph.connected_components(graph, directed=False)
    first = np.full(int(comp.max()) + 1, n)
    np.minimum.at(first, comp, np.arange(n))
    order = np.argsort(first)  # nodes numbered in the order of their first point
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    node_of = rank[comp]
    nodes = pts[first[order]]
    piece = np.repeat(np.arange(sizes.size), sizes)
    i = np.flatnonzero(piece[:-1] == piece[1:])
    seg = np.stack([node_of[i], node_of[i + 1]], axis=1)
    same = seg[:, 0] == seg[:, 1]
    if same.any():
        k = int(i[np.flatnonzero(same)[0]])
        at = k - int(np.concatenate([[0], np.cumsum(sizes)])[piece[k]])
        where = f"path[{piece[k]}]: " if len(pieces) > 1 else ""
        raise GridError(f"{label}: {where}path points {at} and {at + 1} coincide")
    seg = _split_at_nodes(nodes, seg, tol)
    seg = np.unique(np.sort(seg, axis=1), axis=0) if seg.size else seg.reshape(0, 2)
    if seg.shape[0] > 1 and not shapely.MultiLineString(list(nodes[seg])).is_simple:
        raise GridError(f"{label}: the path crosses itself")
    return PathGraph(nodes, seg)


def _split_at_nodes(nodes: np.ndarray, seg: np.ndarray, tol: float) -> np.ndarray:
    """``seg`` split at every node within ``tol`` of a segment's interior (a branch starting on
    another), in order along each segment."""
    if seg.shape[0] == 0:
        return seg
    lines = shapely.linestrings(nodes[seg])
    ni, si = shapely.STRtree(lines).query(shapely.points(nodes), predicate="dwithin", distance=tol)
    inner = (ni != seg[si, 0]) & (ni != seg[si, 1])
    ni, si = ni[inner], si[inner]
    if ni.size == 0:
        return seg
    a, b = nodes[seg[si, 0]], nodes[seg[si, 1]]
    d = b - a
    t = ((nodes[ni] - a) * d).sum(axis=1) / (d * d).sum(axis=1)
    m = seg.shape[0]
    owner = np.concatenate([np.arange(m), si, np.arange(m)])
    param = np.concatenate([np.zeros(m), t, np.ones(m)])
    point = np.concatenate([seg[:, 0], ni, seg[:, 1]])
    order = np.lexsort((param, owner))
    owner, point = owner[order], point[order]
    chain = owner[:-1] == owner[1:]
    return np.stack([point[:-1][chain], point[1:][chain]], axis=1)


def segment_steps(
    graph: PathGraph, spacing: float | None, size: Callable[[np.ndarray], np.ndarray]
) -> tuple[np.ndarray, np.ndarray]:
    """Per segment its number of equal steps, per node its step (m): the mean of its
    segments' steps, or for an isolated point the spacing or the cell size there. ``spacing``
    None: the cell size ``size`` at each segment's midpoint."""
    a, b = graph.nodes[graph.seg[:, 0]], graph.nodes[graph.seg[:, 1]]
    length = np.hypot(*(b - a).T)
    want = np.full(length.size, spacing) if spacing is not None or not length.size else size(0.5 * (a + b))
    n = np.maximum(1, np.rint(length / want)).astype(np.int64)
    step = length / n
    nn = graph.nodes.shape[0]
    ends = graph.seg.reshape(-1)
    total = np.bincount(ends, np.repeat(step, 2), minlength=nn)
    count = np.bincount(ends, minlength=nn)
    node_step = np.divide(total, count, out=np.zeros(nn), where=count > 0)
    iso = graph.isolated
    if iso.size:
        node_step[iso] = spacing if spacing is not None else size(graph.nodes[iso])
    return n, node_step


def path_rows(graph: PathGraph, n: np.ndarray, node_step: np.ndarray) -> PathRows:
    """The sites on a well's path and its side rows (see the module docstring); ``n`` the steps
    of every segment, ``node_step`` (m) the step at every node (:func:`segment_steps`)."""
    nodes, seg = graph.nodes, graph.seg
    a, b = nodes[seg[:, 0]], nodes[seg[:, 1]]
    d = b - a
    step = np.hypot(d[:, 0], d[:, 1]) / n if seg.size else np.zeros(0)
    # on the path: the nodes, then the points between the steps of every segment
    si = np.repeat(np.arange(seg.shape[0]), n - 1)
    k = ragged_arange(np.ones(seg.shape[0]), n - 1)
    inner = a[si] + (k / n[si])[:, None] * d[si]
    on_path = np.concatenate([nodes, inner])
    on_size = np.concatenate([node_step, step[si]])
    # beside the steps that touch no node
    si = np.repeat(np.arange(seg.shape[0]), np.maximum(n - 2, 0))
    k = ragged_arange(np.ones(seg.shape[0]), np.maximum(n - 2, 0))
    mid = a[si] + ((k + 0.5) / n[si])[:, None] * d[si]
    normal = np.stack([-d[si, 1], d[si, 0]], axis=1) / n[si][:, None] * SIDE  # length SIDE x step
    side = [mid + normal, mid - normal]
    side_size = [step[si], step[si]]
    xy, sz = _node_sites(graph, step, node_step)
    side.append(xy)
    side_size.append(sz)
    side_xy, side_sz = _clean(graph, step, node_step, np.concatenate(side), np.concatenate(side_size))
    return PathRows(on_path, on_size, side_xy, side_sz)


def _node_sites(graph: PathGraph, step: np.ndarray, node_step: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The side sites around every node, sector by sector between its arms (module docstring)."""
    nodes, seg = graph.nodes, graph.seg
    d = nodes[seg[:, 1]] - nodes[seg[:, 0]]
    node = np.concatenate([seg[:, 0], seg[:, 1]])
    arm = np.concatenate([d, -d])
    s = np.concatenate([step, step])
    ang = np.mod(arctan2(arm[:, 1], arm[:, 0]), 2 * np.pi)
    order = np.lexsort((ang, node))
    node, ang, s = node[order], ang[order], s[order]
    first = np.searchsorted(node, node, side="left")
    count = np.bincount(node, minlength=nodes.shape[0])[node]
    nxt = first + np.mod(np.arange(node.size) - first + 1, count)
    sector = np.where(count == 1, 2 * np.pi, np.mod(ang[nxt] - ang, 2 * np.pi))
    gap = sector - 2 * THIRD
    wide = gap >= 0.5 * THIRD
    middle = ~wide & (sector >= 1.5 * THIRD)
    parts = np.where(wide, np.maximum(1, np.rint(gap / THIRD)), 1).astype(np.int64)
    per = np.where(wide, parts + 1, middle.astype(np.int64))
    i = np.repeat(np.arange(node.size), per)
    frac = np.where(wide[i], ragged_arange(np.zeros(node.size), per) / parts[i], 0.5)
    alpha = np.where(wide[i], ang[i] + THIRD + frac * gap[i], ang[i] + 0.5 * sector[i])
    radius = s[i] + frac * (s[nxt[i]] - s[i])
    centre = nodes[node[i]]
    iso = graph.isolated  # six sites around a point
    alpha = np.concatenate([alpha, np.tile(THIRD * np.arange(6), iso.size)])
    radius = np.concatenate([radius, np.repeat(node_step[iso], 6)])
    centre = np.concatenate([centre, np.repeat(nodes[iso], 6, axis=0)])
    xy = centre + radius[:, None] * np.stack([np.cos(alpha), np.sin(alpha)], axis=1)
    return xy, radius


def _clean(
    graph: PathGraph, step: np.ndarray, node_step: np.ndarray, xy: np.ndarray, size: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The side sites without those too close to the path (``NEAR`` x the step of the segment,
    or of the isolated point) and with those closer than ``MERGE`` x their step to each other
    merged (their mean)."""
    keep = np.ones(xy.shape[0], dtype=bool)
    if graph.seg.size and xy.size:
        lines = shapely.linestrings(graph.nodes[graph.seg])
        pts = shapely.points(xy)
        pi, li = shapely.STRtree(lines).query(pts, predicate="dwithin", distance=NEAR * float(step.max()))
        near = shapely.distance(pts[pi], lines[li]) < NEAR * step[li]
        keep[pi[near]] = False
    iso = graph.isolated
    if iso.size and xy.size:
        tree = cKDTree(graph.nodes[iso])
        dist, k = tree.query(xy)
        keep &= dist >= NEAR * node_step[iso][k]
    xy, size = xy[keep], size[keep]
    if xy.shape[0] < 2:
        return xy, size
    pairs = cKDTree(xy).query_pairs(MERGE * float(size.max()), output_type="ndarray")
    if pairs.size:
        dist = np.hypot(*(xy[pairs[:, 0]] - xy[pairs[:, 1]]).T)
        pairs = pairs[dist < MERGE * np.minimum(size[pairs[:, 0]], size[pairs[:, 1]])]
    if pairs.size == 0:
        return xy, size
    n = xy.shape[0]
    graph_m = sparse.coo_matrix((np.ones(pairs.shape[0]), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    ncomp, comp = csgraph.connected_components(graph_m, directed=False)
    first = np.full(ncomp, n)
    np.minimum.at(first, comp, np.arange(n))
    order = np.argsort(first)  # groups in the order of their first site
    rank = np.empty_like(order)
    rank[order] = np.arange(ncomp)
    g = rank[comp]
    count = np.bincount(g, minlength=ncomp)
    merged = np.stack([np.bincount(g, xy[:, 0], ncomp), np.bincount(g, xy[:, 1], ncomp)], axis=1)
    return merged / count[:, None], np.bincount(g, size, ncomp) / count


def band(step_max: float, size_max: float) -> float:
    """Background sites are removed within this distance (m) of a path whose largest step is
    ``step_max`` where the largest cell size is ``size_max``."""
    return SIDE * step_max + BAND * max(step_max, size_max)


def clearance(step_max: float, size_max: float) -> float:
    """Other wells keep this distance (m) from a path (its side rows and a little more): their
    sites then lie outside every circle bounding a path cell (2/sqrt(3) s from the path)."""
    return SIDE * step_max + CLEAR * max(step_max, size_max)


def steps_of(graph: PathGraph, n: np.ndarray) -> np.ndarray:
    """The path as its steps (p, 2, 2) (local frame, m), an isolated point as a step of length 0."""
    nodes, seg = graph.nodes, graph.seg
    si = np.repeat(np.arange(seg.shape[0]), n)
    k = ragged_arange(np.zeros(seg.shape[0]), n)
    a, d = nodes[seg[si, 0]], (nodes[seg[si, 1]] - nodes[seg[si, 0]]) / n[si][:, None]
    steps = np.stack([a + k[:, None] * d, a + (k + 1)[:, None] * d], axis=1)
    point = nodes[graph.isolated]
    return np.concatenate([steps, np.stack([point, point], axis=1)])


def cells_along(
    nearest: Callable[[np.ndarray], np.ndarray], steps: np.ndarray, owner: np.ndarray, tol: float
) -> tuple[np.ndarray, np.ndarray]:
    """The cells of a Voronoi diagram that segments ``steps`` (p, 2, 2) run through, and the
    ``owner`` (p,) of the segment for each: ``nearest(points)`` gives the site (cell) of points.

    A segment meets a convex cell in one interval, so a half whose two ends lie in the same cell
    lies in it entirely: the halves whose ends differ are bisected until shorter than ``tol``
    (m), which finds every cell the segments cross for more than ``tol``.
    """
    a, b = steps[:, 0], steps[:, 1]
    ha, hb = nearest(a), nearest(b)
    cells, whose = [ha, hb], [owner, owner]
    split = (ha != hb) & (np.hypot(*(b - a).T) > tol)
    a, b, ha, hb, owner = a[split], b[split], ha[split], hb[split], owner[split]
    while a.shape[0]:  # the halves get shorter every round: about log2(step / tol) rounds
        m = 0.5 * (a + b)
        hm = nearest(m)
        cells.append(hm)
        whose.append(owner)
        long = np.hypot(*(b - a).T) > 2 * tol
        left, right = (ha != hm) & long, (hm != hb) & long
        a, b = np.concatenate([a[left], m[right]]), np.concatenate([m[left], b[right]])
        ha, hb = np.concatenate([ha[left], hm[right]]), np.concatenate([hm[left], hb[right]])
        owner = np.concatenate([owner[left], owner[right]])
    return np.concatenate(cells), np.concatenate(whose)
