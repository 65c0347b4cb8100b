"""The fault network: fault traces clipped to the domain, extended and split into one planar graph.

All in the domain's local frame (:class:`.domain.Domain`). Every fault polyline is clipped to
the domain (pieces that leave and re-enter a concave domain become separate pieces of the same
fault), a free end whose continuation meets the boundary or another fault within 0.75 fault
spacings is extended to it (a note says so), and faults are split where they cross (X) or
touch (T, Y). The result, a :class:`FaultNetwork`, is a planar graph whose nodes are the
polyline vertices, the intersections and the boundary points, and whose edges carry the id of
their fault.

Geometry finer than the smallest cell the refinement may make (``min_feature`` times the cell
size, 2^-max_refinements) is not honoured but resolved, with a note: a trace passing that close
to a corner of the domain is made to pass through it, and nodes that close to each other (three
faults crossing nearly at one point, two faults leaving the domain a hair apart) become one.

The sites that make the grid's faces follow this network are placed by :mod:`.fault_sites`.
Fault ids are the 1-based positions in the ``faults`` sequence; face tags use them.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import shapely
from numpy.typing import ArrayLike
from scipy.spatial import cKDTree

from ..arrays import point_array
from ..errors import GridError
from ..planar import cross2, group_pairs, merge_close_points
from .domain import Domain

REACH = 0.75  # free ends this close (in fault spacings) to a fault or the boundary are extended
REFLEX_REACH = 0.1  # a trace passing a re-entrant corner closer than this x the cell size goes through it


@dataclass(frozen=True, eq=False)
class Fault:
    """A fault trace in plan view: a polyline of (x, y) points in metres.

    ``name`` defaults to ``F<k>`` (k = 1-based position in the list of faults);
    ``spacing`` (m) is the target distance between circle centres along the
    trace, by default the grid's cell size where the fault runs.

    >>> f = Fault([(0, 0), (10, 5)], name="main")
    >>> f.points.shape, f.name
    ((2, 2), 'main')
    """

    points: ArrayLike
    name: str | None = None
    spacing: float | None = None

    def __post_init__(self) -> None:
        try:
            pts = np.array(self.points, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise GridError(
                f"Fault {self.name!r}: points must be (x, y) pairs, got {self.points!r:.60}"
            ) from exc
        pts.flags.writeable = False
        object.__setattr__(self, "points", pts)


@dataclass
class FaultNetwork:
    """Fault traces as one planar graph (local frame): nodes, edges with their fault id."""

    nodes: np.ndarray  # (nn, 2)
    edge_a: np.ndarray  # (ne,)
    edge_b: np.ndarray
    edge_fault: np.ndarray  # (ne,) fault id
    on_boundary: np.ndarray  # (nn,) bool
    spacing: np.ndarray  # (n_faults,) given spacing or nan
    labels: list[str]


def fault_label(fault: Fault, i: int) -> str:
    return f"fault {fault.name or f'F{i + 1}'!r} (faults[{i}])"


def build_network(
    faults: Sequence[Fault], domain: Domain, size: Callable, notes: list[str], min_feature: float = 0.0
) -> FaultNetwork | None:
    """Clip, extend and split the fault traces into one planar graph.

    Pieces of trace between two network nodes shorter than ``min_feature`` times the
    local cell size (crossings a hair apart) are contracted to a point (a note says so).
    """
    if not faults:
        return None
    tol = domain.tol
    labels = []
    spacing = np.full(len(faults), np.nan)
    pieces: list[dict] = []
    for i, fault in enumerate(faults):
        if not isinstance(fault, Fault):
            raise GridError(f"faults[{i}]: expected a Fault, got {type(fault).__name__}")
        label = fault_label(fault, i)
        labels.append(label)
        pts = point_array(fault.points, 2, label, min_points=0, error=GridError)
        if pts.shape[0] < 2:
            raise GridError(f"{label}: a trace needs at least 2 points, got {pts.shape[0]}")
        if fault.spacing is not None:
            if not (
                isinstance(fault.spacing, int | float) and np.isfinite(fault.spacing) and fault.spacing > 0
            ):
                raise GridError(
                    f"{label}: spacing must be a positive length in metres, got {fault.spacing!r}"
                )
            spacing[i] = float(fault.spacing)
        local = domain.to_local(pts)
        seg_len = np.linalg.norm(np.diff(local, axis=0), axis=1)
        if np.any(seg_len <= tol):
            k = int(np.flatnonzero(seg_len <= tol)[0])
            raise GridError(f"{label}: points {k} and {k + 1} coincide")
        if np.all(local[0] == local[-1]) or np.hypot(*(local[0] - local[-1])) <= tol:
            raise GridError(
                f"{label}: the trace is closed (first point = last point); split it into two faults"
            )
        line = shapely.LineString(local)
        if not line.is_simple:
            raise GridError(f"{label}: the trace crosses itself")
        local = _through_near_corners(local, domain, size, min_feature, label, notes)
        got = _clip_polyline(local, domain, label)
        if not got:
            raise GridError(f"{label}: the trace lies outside the domain")
        kept = sum(float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) for p, _, _ in got)
        if kept < seg_len.sum() * (1 - 1e-12):
            notes.append(f"{label}: clipped to the domain ({kept:.6g} of {seg_len.sum():.6g} m inside)")
        for p, b0, b1 in got:
            pieces.append({"xy": p, "fault": i + 1, "bnd": [b0, b1]})
    _extend_free_ends(pieces, domain, size, spacing, labels, notes, min_feature)
    net = _split_into_graph(pieces, domain, spacing, labels)
    return _contract_short_edges(net, domain, size, min_feature, notes)


def _corner_reach(domain: Domain, size: Callable, fraction: float) -> np.ndarray:
    """Distance (m) within which a trace is made to pass through each corner of the domain.

    ``fraction`` x the cell size (the smallest cell); at a re-entrant corner at least
    ``REFLEX_REACH`` x the cell size: the fault cells between the trace and such a corner
    would be slivers reaching around it, cut in pieces by the boundary.
    """
    return np.where(domain.reflex, max(fraction, REFLEX_REACH), fraction) * size(domain.xy)


def _through_near_corners(
    xy: np.ndarray, domain: Domain, size: Callable, fraction: float, label: str, notes: list[str]
) -> np.ndarray:
    """The trace made to pass through the domain's corners it passes closer than ``fraction`` x the
    cell size (a sliver of rock thinner than the smallest cell, between the trace and a corner;
    see :func:`_corner_reach` for re-entrant corners).

    The nearest point of the trace moves onto the corner (a vertex there if one is that
    close, else a new vertex), so that the trace touches or leaves the boundary exactly there.
    """
    if fraction <= 0:
        return xy
    line = shapely.LineString(xy)
    corners = domain.xy
    reach = _corner_reach(domain, size, fraction)
    gap = shapely.distance(shapely.points(corners), line)
    close = np.flatnonzero((gap > domain.tol) & (gap < reach))
    joined: set[int] = set()
    m = domain.num_vertices
    for k in close[np.argsort(gap[close])].tolist():  # corners next to the trace, the nearest first
        if (k - 1) % m in joined or (k + 1) % m in joined:
            continue  # not both ends of an edge: the trace would run along it
        joined.add(k)
        line = shapely.LineString(xy)
        along = float(line.project(shapely.Point(corners[k])))
        cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))])
        near = np.flatnonzero(np.abs(cum - along) < reach[k])
        moved = float(gap[k])
        if near.size:  # that vertex moves onto the corner
            moved = max(moved, float(np.hypot(*(xy[near[0]] - corners[k]))))
            xy = xy.copy()
            xy[near[0]] = corners[k]
        else:
            i = int(np.searchsorted(cum, along)) - 1
            xy = np.insert(xy, i + 1, corners[k], axis=0)
        notes.append(
            f"{label}: passes {gap[k]:.3g} m from the domain's corner at {domain.fmt(corners[k])} (too close "
            f"for the cells between them): joined to the corner, the trace moves by at most {moved:.3g} m"
        )
    return xy


def _contract_short_edges(
    net: FaultNetwork, domain: Domain, size: Callable, fraction: float, notes
) -> FaultNetwork:
    """Join network nodes closer than ``fraction`` x the local cell size.

    Such nodes (three faults crossing nearly at one point, a crossing next to a bend, two
    faults reaching the boundary a hair apart) make a feature smaller than the smallest
    cell the refinement may make: they become one node, the first boundary point among
    them if there is one, else at their mean, and the edges between them vanish.
    """
    nodes, ea, eb = net.nodes, net.edge_a, net.edge_b
    nn = nodes.shape[0]
    if fraction <= 0:
        return net
    reach = fraction * size(nodes)
    bnd = np.flatnonzero(net.on_boundary)
    if bnd.size:  # a boundary point that close to a corner of the domain (an end extended there) is it
        gap, k = cKDTree(domain.xy).query(nodes[bnd])
        snap = (gap > 0) & (gap < _corner_reach(domain, size, fraction)[k])
        if snap.any():
            nodes = nodes.copy()
            nodes[bnd[snap]] = domain.xy[k[snap]]
            for i, g in zip(bnd[snap].tolist(), gap[snap].tolist(), strict=True):
                faults_at = np.unique(net.edge_fault[(ea == i) | (eb == i)])
                names = ", ".join(net.labels[f - 1] for f in faults_at.tolist())
                notes.append(
                    f"{names}: leaves the domain {g:.3g} m from its corner at {domain.fmt(nodes[i])} (too "
                    f"close for the cells between them): joined to the corner, the trace moves by at most "
                    f"{g:.3g} m"
                )
            net = FaultNetwork(nodes, ea, eb, net.edge_fault, net.on_boundary, net.spacing, net.labels)
    if nn < 2:
        return net
    pairs = cKDTree(nodes).query_pairs(float(reach.max()), output_type="ndarray")
    if pairs.size:
        gap = np.linalg.norm(nodes[pairs[:, 0]] - nodes[pairs[:, 1]], axis=1)
        pairs = pairs[gap < np.minimum(reach[pairs[:, 0]], reach[pairs[:, 1]])]
    if pairs.size == 0:
        return _without_edges_along_boundary(net, domain)
    first, new_of = group_pairs(nn, pairs)
    count = np.bincount(new_of)
    merged = np.column_stack([np.bincount(new_of, nodes[:, k]) for k in range(2)]) / count[:, None]
    on_bnd = np.bincount(new_of, net.on_boundary.astype(np.float64)) > 0
    bnd = np.flatnonzero(net.on_boundary)
    merged[new_of[bnd[::-1]]] = nodes[bnd[::-1]]  # the first boundary point of a group (set last)
    single = count == 1
    merged[single] = nodes[first[single]]  # untouched nodes keep their exact position
    a, b = new_of[ea], new_of[eb]
    keep = a != b
    key = np.where(keep, np.minimum(a, b) * merged.shape[0] + np.maximum(a, b), -1 - np.arange(a.size))
    _, once = np.unique(key, return_index=True)
    uniq = np.zeros(key.size, dtype=bool)
    uniq[once] = True
    keep &= uniq
    # a piece of trace from a joined boundary point to another boundary point may now run along the
    # boundary (a crossing a hair inside it joined to where the other fault leaves): it is the boundary
    along = keep & on_bnd[a] & on_bnd[b]
    if along.any():
        mid = 0.5 * (merged[a[along]] + merged[b[along]])
        keep[np.flatnonzero(along)[domain.boundary_distance(mid) <= domain.tol]] = False
    used = np.zeros(merged.shape[0], dtype=bool)
    used[a[keep]] = used[b[keep]] = True
    renum = np.cumsum(used) - 1
    for g in np.flatnonzero(count > 1).tolist():  # a note per joined group (a handful)
        members = np.flatnonzero(new_of == g)
        touching = np.isin(ea, members) | np.isin(eb, members)
        names = ", ".join(net.labels[f - 1] for f in np.unique(net.edge_fault[touching]).tolist())
        spread = float(np.linalg.norm(nodes[members] - nodes[members].mean(axis=0), axis=1).max())
        moved = float(np.linalg.norm(nodes[members] - merged[g], axis=1).max())
        notes.append(
            f"{names}: crossings, bends or ends within {2 * spread:.3g} m of each other near "
            f"{domain.fmt(merged[g])} (less than the smallest cell) joined at one point; the traces "
            f"move by at most {moved:.3g} m there"
        )
    return FaultNetwork(
        merged[used],
        renum[a[keep]],
        renum[b[keep]],
        net.edge_fault[keep],
        on_bnd[used],
        net.spacing,
        net.labels,
    )


def _without_edges_along_boundary(net: FaultNetwork, domain: Domain) -> FaultNetwork:
    """The network less its edges between two boundary points that run along the boundary (both
    ends joined to the two corners of an edge): such a piece of trace is the boundary."""
    ea, eb = net.edge_a, net.edge_b
    along = np.flatnonzero(net.on_boundary[ea] & net.on_boundary[eb])
    mid = 0.5 * (net.nodes[ea[along]] + net.nodes[eb[along]])
    along = along[domain.boundary_distance(mid) <= domain.tol]
    if along.size == 0:
        return net
    keep = np.ones(ea.size, dtype=bool)
    keep[along] = False
    used = np.zeros(net.nodes.shape[0], dtype=bool)
    used[ea[keep]] = used[eb[keep]] = True
    renum = np.cumsum(used) - 1
    return FaultNetwork(
        net.nodes[used],
        renum[ea[keep]],
        renum[eb[keep]],
        net.edge_fault[keep],
        net.on_boundary[used],
        net.spacing,
        net.labels,
    )


def _clip_polyline(xy: np.ndarray, domain: Domain, label: str) -> list[tuple[np.ndarray, bool, bool]]:
    """Pieces of a polyline inside the domain, split at every boundary point.

    Each piece is (points, starts on the boundary, ends on the boundary).
    """
    tol = domain.tol
    a, b = xy[:-1], xy[1:]
    seg, t, _, _ = domain.crossings(a, b, tol)
    ns = a.shape[0]
    # Break points: segment ends and crossings, in order along the polyline.
    br_seg = np.concatenate([np.arange(ns), np.arange(ns), seg])
    br_t = np.concatenate([np.zeros(ns), np.ones(ns), t])
    br_bnd = np.concatenate([np.zeros(2 * ns, dtype=bool), np.ones(seg.size, dtype=bool)])
    order = np.lexsort((~br_bnd, br_t, br_seg))
    br_seg, br_t, br_bnd = br_seg[order], br_t[order], br_bnd[order]
    # Merge break points at the same place (segment end = crossing there).
    key = br_seg + br_t
    glob = np.where(br_t == 1.0, br_seg + 1.0, key)
    uniq, inv = np.unique(glob, return_inverse=True)
    bnd = np.zeros(uniq.size, dtype=bool)
    np.logical_or.at(bnd, inv, br_bnd)
    seg_of = np.minimum(np.floor(uniq).astype(np.int64), ns - 1)
    t_of = uniq - seg_of
    pts = a[seg_of] + t_of[:, None] * (b[seg_of] - a[seg_of])
    exact = t_of == 0
    pts[exact] = a[seg_of[exact]]
    last = uniq == ns
    pts[last] = b[-1]
    mid_par = 0.5 * (uniq[:-1] + uniq[1:])
    ms = np.minimum(np.floor(mid_par).astype(np.int64), ns - 1)
    mid = a[ms] + (mid_par - ms)[:, None] * (b[ms] - a[ms])
    inside = domain.inside(mid)
    plen = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    along = (domain.boundary_distance(mid) <= tol) & (plen > tol)
    if along.any():
        k = int(np.flatnonzero(along)[0])
        raise GridError(
            f"{label}: the trace runs along the domain boundary near {domain.fmt(mid[k])} "
            "(the boundary is not a fault; move the trace inside)"
        )
    out = []
    k = 0
    n_int = inside.size
    while k < n_int:  # loop over polyline pieces (a few per fault)
        if not inside[k]:
            k += 1
            continue
        start = k
        while k + 1 < n_int and inside[k + 1] and not bnd[k + 1]:
            k += 1
        piece = pts[start : k + 2]
        if np.linalg.norm(np.diff(piece, axis=0), axis=1).sum() > tol:
            out.append((piece.copy(), bool(bnd[start]), bool(bnd[k + 1])))
        k += 1
    return out


def _ray_hits(origin: np.ndarray, d: np.ndarray, a: np.ndarray, b: np.ndarray, tol: float) -> np.ndarray:
    """Distances along the unit ray origin + s d (s > tol) to the segments a -> b (inf if missed)."""
    s_vec = b - a
    den = cross2(d[None, :], s_vec)
    q = a - origin
    with np.errstate(divide="ignore", invalid="ignore"):
        s = cross2(q, s_vec) / den
        u = cross2(q, d[None, :]) / den
    ok = (den != 0) & (s > tol) & (u >= -1e-12) & (u <= 1 + 1e-12)
    return np.where(ok, s, np.inf)


def _extend_free_ends(pieces, domain: Domain, size, spacing, labels, notes, min_feature: float = 0.0) -> None:
    """Extend free ends that stop just short of the boundary or of another fault.

    An extension passing a corner of the domain closer than :func:`_corner_reach` ends at
    that corner, unless the last segment would then run along an edge (it comes from a point
    of that edge, or its other corner): it meets the boundary where it reaches it instead.
    """
    tol = domain.tol
    corner_reach = np.zeros(domain.num_vertices)
    if min_feature > 0:
        corner_reach = _corner_reach(domain, size, min_feature)
    for pi, piece in enumerate(pieces):  # loop over fault pieces and their two ends
        for end in (0, 1):
            if piece["bnd"][end]:
                continue
            xy = piece["xy"]
            tip, prev = (xy[0], xy[1]) if end == 0 else (xy[-1], xy[-2])
            d = tip - prev
            d = d / np.hypot(d[0], d[1])
            sp = spacing[piece["fault"] - 1]
            ds = sp if np.isfinite(sp) else float(size(tip[None, :])[0])
            reach = REACH * ds
            best, what, onto_bnd = np.inf, "", False
            hits = _ray_hits(tip, d, domain.edge_a, domain.edge_b, tol)
            if hits.min() <= reach:
                best, what, onto_bnd = float(hits.min()), "the domain boundary", True
            rel = domain.xy - tip
            along = rel[:, 0] * d[0] + rel[:, 1] * d[1]
            by = np.abs(rel[:, 0] * d[1] - rel[:, 1] * d[0])
            near = np.flatnonzero((along > tol) & (along <= min(best, reach)) & (by < corner_reach))
            if near.size:  # not to a corner the last segment would reach along an edge
                near = near[domain.boundary_distance(0.5 * (prev + domain.xy[near])) > tol]
            corner = None
            if near.size:  # the extension passes a corner: it ends there
                corner = int(near[np.argmin(along[near])])
                best, what, onto_bnd = float(along[corner]), "a corner", True
            for pj, other in enumerate(pieces):
                oxy = other["xy"]
                a, b = oxy[:-1], oxy[1:]
                if pj == pi:  # not its own first/last segment
                    a, b = (a[1:], b[1:]) if end == 0 else (a[:-1], b[:-1])
                if a.shape[0] == 0:
                    continue
                h = _ray_hits(tip, d, a, b, tol)
                # ...or the end already lies on the other trace (a T drawn exactly)
                rel = tip - a
                sv = b - a
                w = np.clip((rel * sv).sum(axis=1) / (sv * sv).sum(axis=1), 0, 1)
                off = np.linalg.norm(rel - w[:, None] * sv, axis=1)
                if off.min() <= tol:
                    best, what, onto_bnd, corner = 0.0, labels[other["fault"] - 1], False, None
                    break
                if h.min() < best and h.min() <= reach:
                    best, what, onto_bnd, corner = float(h.min()), labels[other["fault"] - 1], False, None
            if np.isfinite(best) and best > tol:
                xy = xy.copy()
                xy[0 if end == 0 else -1] = tip + best * d if corner is None else domain.xy[corner]
                piece["xy"] = xy
                label = labels[piece["fault"] - 1]
                if corner is None:
                    notes.append(
                        f"{label}: its end at {domain.fmt(tip)} was extended by {best:.3g} m to meet {what}"
                    )
                else:
                    notes.append(
                        f"{label}: its end at {domain.fmt(tip)} was extended by {best:.3g} m to the domain's "
                        f"corner at {domain.fmt(domain.xy[corner])}, which it passes {by[corner]:.3g} m "
                        f"away: joined to the corner, the trace moves by at most {by[corner]:.3g} m"
                    )
            if onto_bnd and np.isfinite(best):
                piece["bnd"][end] = True


def _split_into_graph(pieces, domain: Domain, spacing, labels) -> FaultNetwork:
    """The pieces of trace as one planar graph: split at every crossing and touching point, nodes
    within the domain's tolerance made one, nodes on the boundary marked."""
    tol = domain.tol
    seg_a = np.concatenate([p["xy"][:-1] for p in pieces])
    seg_b = np.concatenate([p["xy"][1:] for p in pieces])
    seg_piece = np.concatenate([np.full(p["xy"].shape[0] - 1, k) for k, p in enumerate(pieces)])
    seg_k = np.concatenate([np.arange(p["xy"].shape[0] - 1) for p in pieces])
    seg_fault = np.array([pieces[k]["fault"] for k in seg_piece], dtype=np.int64)
    ns = seg_a.shape[0]
    ins_seg, ins_t, ins_x = _crossings(_Segments(seg_a, seg_b, seg_piece, seg_k, seg_fault), domain, labels)
    # Vertices of every segment: its start, inserted points; then the last end of each piece.
    all_seg = np.concatenate([np.arange(ns), ins_seg])
    all_t = np.concatenate([np.zeros(ns), ins_t])
    all_x = np.concatenate([seg_a, ins_x])
    order = np.lexsort((all_t, all_seg))
    all_seg, all_t, all_x = all_seg[order], all_t[order], all_x[order]
    # Edges: consecutive vertices along a piece (the next vertex may be the next segment's start).
    nxt_x = np.empty_like(all_x)
    nxt_x[:-1] = all_x[1:]
    last_of_seg = np.ones(all_seg.size, dtype=bool)
    last_of_seg[:-1] = all_seg[1:] != all_seg[:-1]
    piece_end = np.ones(ns, dtype=bool)
    piece_end[:-1] = seg_piece[1:] != seg_piece[:-1]
    tail = last_of_seg & piece_end[all_seg]
    nxt_x[tail] = seg_b[all_seg[tail]]
    e_fault = seg_fault[all_seg]
    pts = np.concatenate([all_x, nxt_x])
    first, node_of = merge_close_points(pts, tol)
    nodes = pts[first]
    ea, eb = node_of[: all_x.shape[0]], node_of[all_x.shape[0] :]
    keep = ea != eb
    ea, eb, e_fault = ea[keep], eb[keep], e_fault[keep]
    key = np.minimum(ea, eb) * nodes.shape[0] + np.maximum(ea, eb)
    _, cnt = np.unique(key, return_counts=True)
    if np.any(cnt > 1):  # pragma: no cover - overlaps were rejected above
        raise GridError("faults overlap")
    on_bnd = np.zeros(nodes.shape[0], dtype=bool)
    ends = []
    for p in pieces:
        for end, xy in ((0, p["xy"][0]), (1, p["xy"][-1])):
            if p["bnd"][end]:
                ends.append(xy)
    if ends:
        dist, idx = cKDTree(nodes).query(np.asarray(ends))
        on_bnd[idx[dist <= tol]] = True
    near = domain.boundary_distance(nodes) <= tol
    on_bnd |= near
    return FaultNetwork(nodes, ea, eb, e_fault, on_bnd, spacing, labels)


@dataclass(frozen=True, eq=False)
class _Segments:
    """The segments of the pieces of trace: from ``a`` to ``b`` (k, 2), the ``piece`` each is of,
    its position ``k`` along that piece and its fault id."""

    a: np.ndarray
    b: np.ndarray
    piece: np.ndarray
    k: np.ndarray
    fault: np.ndarray


def _crossings(segs: _Segments, domain: Domain, labels) -> tuple[np.ndarray, ...]:
    """Where segments of the traces cross or touch (within the domain's tolerance), as points
    inserted into segments: (segment, parameter along it in (0, 1), point). Overlaps and a trace
    touching itself are errors."""
    seg_a, seg_b, seg_piece, seg_k, seg_fault = segs.a, segs.b, segs.piece, segs.k, segs.fault
    tol = domain.tol
    tree = shapely.STRtree(shapely.linestrings(np.stack([seg_a, seg_b], axis=1)))
    i, j = tree.query(shapely.linestrings(np.stack([seg_a, seg_b], axis=1)))
    sel = i < j
    i, j = i[sel], j[sel]
    adjacent = (seg_piece[i] == seg_piece[j]) & (np.abs(seg_k[i] - seg_k[j]) == 1)
    i, j = i[~adjacent], j[~adjacent]
    r = seg_b[i] - seg_a[i]
    s = seg_b[j] - seg_a[j]
    q = seg_a[j] - seg_a[i]
    rl, sl = np.linalg.norm(r, axis=1), np.linalg.norm(s, axis=1)
    den = cross2(r, s)
    par = np.abs(den) <= 1e-12 * rl * sl
    # Collinear overlaps are errors; parallel segments sharing an end point are joined by the nodes.
    _reject_overlaps(i[par], j[par], r[par], q[par], rl[par], segs, domain, labels)
    ok = ~par
    i, j, r, s, q, rl, sl, den = i[ok], j[ok], r[ok], s[ok], q[ok], rl[ok], sl[ok], den[ok]
    t = cross2(q, s) / den
    u = cross2(q, r) / den
    et, eu = tol / rl, tol / sl
    hit = (t >= -et) & (t <= 1 + et) & (u >= -eu) & (u <= 1 + eu)
    i, j, t, u, r, et, eu = i[hit], j[hit], t[hit], u[hit], r[hit], et[hit], eu[hit]
    t = np.where(t <= et, 0.0, np.where(t >= 1 - et, 1.0, t))
    u = np.where(u <= eu, 0.0, np.where(u >= 1 - eu, 1.0, u))
    x = seg_a[i] + t[:, None] * r
    x = np.where((t == 0)[:, None], seg_a[i], np.where((t == 1)[:, None], seg_b[i], x))
    x = np.where((u == 0)[:, None], seg_a[j], np.where((u == 1)[:, None], seg_b[j], x))
    # Same-fault self-contacts after clipping/extension are errors too.
    same = (seg_fault[i] == seg_fault[j]) & (seg_piece[i] == seg_piece[j])
    if same.any():
        k = int(np.flatnonzero(same)[0])
        raise GridError(f"{labels[seg_fault[i[k]] - 1]}: the trace touches itself near {domain.fmt(x[k])}")
    ins_seg = np.concatenate([i, j])
    ins_t = np.concatenate([t, u])
    ins_x = np.concatenate([x, x])
    inner = (ins_t > 0) & (ins_t < 1)
    ins_seg, ins_t, ins_x = ins_seg[inner], ins_t[inner], ins_x[inner]
    return ins_seg, ins_t, ins_x


def _reject_overlaps(pi_, pj_, r, q, rl, segs: _Segments, domain: Domain, labels) -> None:
    """Raise if parallel segment pairs (``pi_``, ``pj_``; ``r`` = the first's vector, ``q`` from
    its start to the second's start, ``rl`` = the first's length) run along each other for more
    than the domain's tolerance."""
    if pi_.size == 0:
        return
    seg_a, seg_b, seg_fault = segs.a, segs.b, segs.fault
    tol = domain.tol
    off = np.abs(cross2(q, r)) / rl
    coll = off <= tol
    if coll.any():
        ri = r[coll]
        ui = ri / rl[coll][:, None]
        p0 = ((seg_a[pj_[coll]] - seg_a[pi_[coll]]) * ui).sum(axis=1)
        p1 = ((seg_b[pj_[coll]] - seg_a[pi_[coll]]) * ui).sum(axis=1)
        lo_, hi_ = np.maximum(np.minimum(p0, p1), 0.0), np.minimum(np.maximum(p0, p1), rl[coll])
        over = hi_ - lo_ > tol
        if over.any():
            k = int(np.flatnonzero(over)[0])
            a_, b_ = pi_[coll][k], pj_[coll][k]
            raise GridError(
                f"{labels[seg_fault[a_] - 1]} and {labels[seg_fault[b_] - 1]} overlap near "
                f"{domain.fmt(seg_a[b_])}: faults may cross or touch, not run along each other"
            )
