"""Fault-conforming sites: mirrored pairs from intersecting circles along fault traces.

Construction (ALGORITHMS.md §3.2, in our own words), all in the domain's local frame:

1. **Network.** Every fault polyline is clipped to the domain (pieces that leave
   and re-enter a concave domain become separate pieces of the same fault), a
   free end whose continuation meets the boundary or another fault within
   0.75 fault spacings is extended to it (a note says so), and faults are split
   where they cross (X) or touch (T, Y). The result is a planar graph whose
   nodes are the polyline vertices, the intersections and the boundary points.
   Geometry finer than the smallest cell the refinement may make (``min_feature``
   times the cell size, 2^-max_refinements) is not honoured but resolved, with a
   note: a trace passing that close to a corner of the domain is made to pass
   through it, and nodes that close to each other (three faults crossing nearly at
   one point, two faults leaving the domain a hair apart) become one.
2. **Circle centres.** Every polyline vertex, intersection and boundary point is
   a centre, so faces follow the trace exactly, bends included. Each segment is
   divided into steps whose length follows the fault spacing (``Fault.spacing``,
   default the local cell size), graded with a growth of at most 30 % per unit
   length away from short segments and from local refinements.
3. **Radii and sites.** A centre's radius is ``ratio`` (0.6) times the mean of its
   two steps. Consecutive circles intersect in two points mirrored across the
   step: the left and right sites. Both centres are equidistant from both sites,
   so the Voronoi edge between them is the step itself, *provided no site lies
   strictly inside a circle* (the empty-circle condition).
4. **Tips, junctions, boundary.** A free end gets a *tip site* on its circle,
   straight ahead. At a constrained node (a junction of three or more arms, two
   faults meeting end to end, a bend turning by more than 90°, a boundary point)
   every arm starts with the same step, and the node's radius is the largest
   (up to ``ratio`` times that step) at which the sites of neighbouring arms do
   not cross: the angle alpha at which an arm's first sites sit, seen from the
   node, grows with the radius, and neighbouring arms need alpha_j + alpha_k <=
   the angle between them. The tightest pair gets equality: its two inner sites
   coincide and become one site on three circles. Sites next to the boundary
   keep alpha below half the angle to it, so they stay inside.
5. **Acute wedges.** Where two arms leave a node less than 40° apart (a V, an
   acute X, T or Y, a trace kinked by a sharp bend) or a trace meets the boundary
   at less than 40°, mirrored pairs cannot fit near the node at any step (the
   wedge is s sin(angle) wide at a distance s): one row of sites shared by both
   sides fills the wedge instead (:mod:`.wedges`), exact on both traces, until the
   wedge is wide enough for two rows. The node's circle is then the wedge's, and the
   other arms' first circles are fitted to it. (Traces meeting at less than 40°
   that share an arm with a narrower wedge get smaller circles nearby instead,
   ratio down to 0.52.)
6. **Check and refine.** After the background is added, every circle is checked
   for sites strictly inside it (:func:`circle_violations`, background, fault and
   well sites alike), and every fault site for lying inside the domain. Where a
   check fails the fault step is made smaller locally, by what the geometry needs
   (a circle holding a site shrinks below that site's distance; a site outside the
   domain comes closer to its trace than the boundary is; at least halving), and
   the sites rebuilt, up to ``max_refinements`` times; if it still fails, a
   :class:`GridError` names the faults and the place.

Wells keep clear of the fault circles: :func:`ring_room` gives how far a well's
rings may reach (:mod:`.wells` shrinks them to that, with a note).

Fault ids are the 1-based positions in the ``faults`` sequence; face tags use them.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import shapely
from numpy.typing import ArrayLike
from scipy import sparse
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

from ..errors import GridError
from ..planar import cross2, group_pairs, merge_close_points
from ..reproducible import arccos, arctan2
from . import wedges as _wedges
from .domain import Domain

GROWTH = 0.3  # at most 30 % longer steps per step length away from a short one
KEY_ANGLE = np.radians(90.0)  # a bend sharper than this (inner angle) is handled as a junction
ACUTE = np.radians(40.0)  # traces meeting at less than this get smaller circles near the junction
RATIO_MIN = 0.52  # the smallest circle radius / step used there
REACH = 0.75  # free ends this close (in fault spacings) to a fault or the boundary are extended
RING_GAP = 0.25  # a well's rings end this many fault steps outside the fault circles
REFLEX_REACH = 0.1  # a trace passing a re-entrant corner closer than this x the cell size goes through it
FITTED = "its arms' first circles were fitted to it"  # a junction problem that leaves conforming sites


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
class FaultSites:
    """Sites, pairs and circles of all faults (local frame)."""

    sites: np.ndarray  # (k, 2)
    site_fault: np.ndarray  # (k,) fault id 1..n of each site
    site_step: np.ndarray  # (k,) length (m) of the step a site belongs to
    site_foot: np.ndarray  # (k, 2) the point of its trace nearest to each site
    is_tip: np.ndarray  # (k,) bool
    pairs: np.ndarray  # (p, 2) indices into sites: the two sites of a step
    pair_fault: np.ndarray  # (p,)
    centres: np.ndarray  # (c, 2) circle centres = Voronoi vertices on the traces
    radii: np.ndarray  # (c,)
    centre_fault: np.ndarray  # (c,)
    centre_step: np.ndarray  # (c,) shortest step at each centre
    trace_a: np.ndarray  # (s, 2) the steps, as segments of the traces
    trace_b: np.ndarray
    trace_fault: np.ndarray
    problems: list[tuple[int, str]] = field(default_factory=list)  # (centre, why) found while building
    site_wedge: np.ndarray | None = None  # (k,) index into ``wedges`` of the acute wedge a site is in, or -1
    wedges: list[str] = field(default_factory=list)  # a description of every acute wedge

    @staticmethod
    def empty() -> FaultSites:
        z2, zi, zf = np.zeros((0, 2)), np.zeros(0, dtype=np.int64), np.zeros(0)
        return FaultSites(
            z2, zi, zf, z2, np.zeros(0, bool), np.zeros((0, 2), np.int64), zi, z2, zf, zi, zf, z2, z2, zi
        )


@dataclass
class _Network:
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
) -> _Network | None:
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
        pts = fault.points
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise GridError(f"{label}: points must have shape (n, 2), got {pts.shape}")
        if pts.shape[0] < 2:
            raise GridError(f"{label}: a trace needs at least 2 points, got {pts.shape[0]}")
        if not np.isfinite(pts).all():
            raise GridError(
                f"{label}: point {int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])} is not finite"
            )
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


def _contract_short_edges(net: _Network, domain: Domain, size: Callable, fraction: float, notes) -> _Network:
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
            net = _Network(nodes, ea, eb, net.edge_fault, net.on_boundary, net.spacing, net.labels)
    if nn < 2:
        return net
    pairs = cKDTree(nodes).query_pairs(float(reach.max()), output_type="ndarray")
    if pairs.size:
        gap = np.linalg.norm(nodes[pairs[:, 0]] - nodes[pairs[:, 1]], axis=1)
        pairs = pairs[gap < np.minimum(reach[pairs[:, 0]], reach[pairs[:, 1]])]
    if pairs.size == 0:
        return net
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
    return _Network(
        merged[used],
        renum[a[keep]],
        renum[b[keep]],
        net.edge_fault[keep],
        on_bnd[used],
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
    that corner.
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


def _split_into_graph(pieces, domain: Domain, spacing, labels) -> _Network:
    tol = domain.tol
    seg_a = np.concatenate([p["xy"][:-1] for p in pieces])
    seg_b = np.concatenate([p["xy"][1:] for p in pieces])
    seg_piece = np.concatenate([np.full(p["xy"].shape[0] - 1, k) for k, p in enumerate(pieces)])
    seg_k = np.concatenate([np.arange(p["xy"].shape[0] - 1) for p in pieces])
    seg_fault = np.array([pieces[k]["fault"] for k in seg_piece], dtype=np.int64)
    ns = seg_a.shape[0]
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
    if par.any():
        pi_, pj_ = i[par], j[par]
        off = np.abs(cross2(q[par], r[par])) / rl[par]
        coll = off <= tol
        if coll.any():
            ri = r[par][coll]
            ui = ri / rl[par][coll][:, None]
            p0 = ((seg_a[pj_[coll]] - seg_a[pi_[coll]]) * ui).sum(axis=1)
            p1 = ((seg_b[pj_[coll]] - seg_a[pi_[coll]]) * ui).sum(axis=1)
            lo_, hi_ = np.maximum(np.minimum(p0, p1), 0.0), np.minimum(np.maximum(p0, p1), rl[par][coll])
            over = hi_ - lo_ > tol
            if over.any():
                k = int(np.flatnonzero(over)[0])
                a_, b_ = pi_[coll][k], pj_[coll][k]
                raise GridError(
                    f"{labels[seg_fault[a_] - 1]} and {labels[seg_fault[b_] - 1]} overlap near "
                    f"{domain.fmt(seg_a[b_])}: faults may cross or touch, not run along each other"
                )
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
    return _Network(nodes, ea, eb, e_fault, on_bnd, spacing, labels)


@dataclass
class _Chains:
    """Which network nodes are constrained ("key": junctions, boundary points, fault changes,
    sharp bends) and which are free ends (tips)."""

    key: np.ndarray  # (nn,) bool
    tip: np.ndarray  # (nn,) bool


def _chains(net: _Network) -> _Chains:
    nn = net.nodes.shape[0]
    deg = np.bincount(net.edge_a, minlength=nn) + np.bincount(net.edge_b, minlength=nn)
    fault_min = np.full(nn, np.iinfo(np.int64).max)
    fault_max = np.zeros(nn, dtype=np.int64)
    for end in (net.edge_a, net.edge_b):
        np.minimum.at(fault_min, end, net.edge_fault)
        np.maximum.at(fault_max, end, net.edge_fault)
    key = (deg != 2) | net.on_boundary | (fault_min != fault_max)
    # Sharp bends: the inner angle at a degree-2 node.
    two = np.flatnonzero((deg == 2) & ~key)
    if two.size:
        order = np.argsort(np.concatenate([net.edge_a, net.edge_b]), kind="stable")
        other = np.concatenate([net.edge_b, net.edge_a])[order]
        start = np.searchsorted(np.concatenate([net.edge_a, net.edge_b])[order], np.arange(nn))
        o1, o2 = other[start[two]], other[start[two] + 1]
        d1, d2 = net.nodes[o1] - net.nodes[two], net.nodes[o2] - net.nodes[two]
        cosang = (d1 * d2).sum(axis=1) / (np.linalg.norm(d1, axis=1) * np.linalg.norm(d2, axis=1))
        key[two[cosang > np.cos(KEY_ANGLE)]] = True
    # A closed loop of degree-2 nodes (not possible from simple open traces) gets one key node.
    graph = sparse.coo_matrix((np.ones(net.edge_a.size), (net.edge_a, net.edge_b)), shape=(nn, nn))
    _, comp = csgraph.connected_components(graph, directed=False)
    has_key = np.zeros(comp.max() + 1, dtype=bool)
    has_key[comp[key]] = True
    _, first = np.unique(comp, return_index=True)
    key[first[~has_key]] = True
    return _Chains(key, (deg == 1) & ~net.on_boundary)


@dataclass
class FaultLayout:
    """The network and its constrained nodes; sites are rebuilt from it for every refinement."""

    net: _Network
    ch: _Chains
    size: Callable
    ratio: float
    domain: Domain
    refine: list[tuple[float, float, float]] = field(default_factory=list)


def layout(
    faults: Sequence[Fault],
    domain: Domain,
    size: Callable,
    ratio: float,
    notes: list[str],
    min_feature: float = 0.0,
):
    net = build_network(faults, domain, size, notes, min_feature)
    if net is None:
        return None
    return FaultLayout(net, _chains(net), size, ratio, domain)


def ring_room(lay: FaultLayout, points: np.ndarray) -> tuple[np.ndarray, list[str], np.ndarray]:
    """How far (m) well sites may reach from ``points`` (k, 2; local frame) and stay clear of the faults.

    A fault circle reaches ``ratio`` x the step from its trace (a little more at
    junctions; the refinement takes care of those): rings end ``RING_GAP`` steps short
    of that, and a path's sites with no room at all are dropped. Also returns, per
    point, the label of the fault that limits it and its distance (m) to that trace.
    """
    net = lay.net
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    a, b = net.nodes[net.edge_a], net.nodes[net.edge_b]
    ab = b - a
    rel = points[:, None, :] - a[None, :, :]
    t = (rel[..., 0] * ab[:, 0] + rel[..., 1] * ab[:, 1]) / (ab[:, 0] ** 2 + ab[:, 1] ** 2)
    foot = a + np.clip(t, 0.0, 1.0)[..., None] * ab
    dist = np.hypot(points[:, None, 0] - foot[..., 0], points[:, None, 1] - foot[..., 1])
    step = _ds(lay, foot.reshape(-1, 2), np.tile(net.edge_fault, points.shape[0])).reshape(dist.shape)
    room = dist - (lay.ratio + RING_GAP) * step
    k = np.argmin(room, axis=1)
    rows = np.arange(points.shape[0])
    return room[rows, k], [net.labels[f - 1] for f in net.edge_fault[k].tolist()], dist[rows, k]


def _ds(lay: FaultLayout, xy: np.ndarray, fault: np.ndarray) -> np.ndarray:
    """Target step length at points of the given faults (m)."""
    sp = lay.net.spacing[fault - 1]
    out = np.where(np.isfinite(sp), sp, 0.0)
    need = ~np.isfinite(sp)
    if need.any():
        out[need] = lay.size(xy[need])
    if lay.refine:
        ref = np.asarray(lay.refine)
        for start in range(0, xy.shape[0], 4096):
            sl = slice(start, start + 4096)
            dist = np.linalg.norm(xy[sl, None, :] - ref[None, :, :2], axis=2)
            out[sl] = np.minimum(out[sl], (ref[None, :, 2] + GROWTH * dist).min(axis=1))
    return out


def build_sites(lay: FaultLayout) -> FaultSites:
    """Centres, radii and mirrored sites for the current refinement."""
    net, ch = lay.net, lay.ch
    nodes = net.nodes
    nn = nodes.shape[0]
    ea, eb, ef = net.edge_a, net.edge_b, net.edge_fault
    elen = np.linalg.norm(nodes[eb] - nodes[ea], axis=1)
    # Size at nodes: the fault spacing, capped by adjacent segment lengths, then graded.
    node_fault = np.zeros(nn, dtype=np.int64)
    node_fault[ea] = ef
    node_fault[eb] = ef
    hv = _ds(lay, nodes, node_fault)
    np.minimum.at(hv, ea, elen)
    np.minimum.at(hv, eb, elen)
    for _ in range(nn):  # Lipschitz grading along the network, vectorised over edges
        before = hv.copy()
        np.minimum.at(hv, ea, hv[eb] + GROWTH * elen)
        np.minimum.at(hv, eb, hv[ea] + GROWTH * elen)
        if np.array_equal(before, hv):
            break
    # At a constrained node (junction, sharp bend, boundary point) every arm starts with the same
    # step L0, and an edge needs a step of its own next to each constrained end; an acute wedge
    # (wedges.py) fixes the first centres of its arms at its rungs instead.
    constrained = ch.key & ~ch.tip
    ends_c = constrained[ea].astype(np.int64) + constrained[eb]
    l0 = hv.copy()
    np.minimum.at(l0, ea, elen / np.maximum(ends_c + 1, 2))
    np.minimum.at(l0, eb, elen / np.maximum(ends_c + 1, 2))
    wedge_list = _plan_wedges(lay, elen, l0, constrained)
    for w in wedge_list:  # the other arms at a wedge's node start with steps its circle can reach
        l0[w.node] = min(l0[w.node], _wedges.node_radius(w) / lay.ratio)
    lead, wedge_ends = _leads(wedge_list, ea, eb, l0, constrained)
    wedge_node = np.zeros(nn, dtype=bool)
    wedge_node[[w.node for w in wedge_list]] = True
    # Steps per edge.
    ne = ea.size
    n_steps = np.zeros(ne, dtype=np.int64)
    params: list[np.ndarray] = [None] * ne  # type: ignore[list-item]
    for e in range(ne):  # loop over polyline segments
        m = 65
        for _ in range(4):  # sample the size function finely enough (8 samples per step)
            tt = np.linspace(0.0, 1.0, m)
            xy = nodes[ea[e]] + tt[:, None] * (nodes[eb[e]] - nodes[ea[e]])
            caps = [
                _ds(lay, xy, np.full(m, ef[e])),
                hv[ea[e]] + GROWTH * tt * elen[e],
                hv[eb[e]] + GROWTH * (1 - tt) * elen[e],
            ]
            for end, along in ((0, tt * elen[e]), (1, (1 - tt) * elen[e])):  # grading away from a wedge
                w = lead[e][end]
                if (e, end) in wedge_ends:
                    caps.append(wedge_ends[(e, end)] + GROWTH * np.maximum(along - w[-1], 0.0))
                elif wedge_node[(ea[e], eb[e])[end]]:  # another arm at a wedge's node
                    caps.append(w[0] + GROWTH * np.maximum(along - w[0], 0.0))
            s = np.minimum.reduce(caps)
            need = int(np.ceil(8 * elen[e] / s.min())) + 1
            if need <= m or m >= 20001:
                break
            m = min(need, 20001)
        dens = elen[e] / s
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (dens[1:] + dens[:-1]) * np.diff(tt))])
        n_steps[e] = max(1, int(np.round(cum[-1])))
        params[e] = (tt, cum)
    n_steps = np.maximum(n_steps, ends_c + 1)
    # Centres: network nodes first, then the interior points of every edge.
    cen = [nodes]
    cen_fault = [node_fault]
    step_a, step_b, step_f = [], [], []
    n_cen = nn
    n_step = 0
    wedge_steps: dict[tuple[int, int], np.ndarray] = {}  # (edge, end) -> its steps, from that end
    for e in range(ne):  # loop over polyline segments
        tt, cum = params[e]
        la, lb = lead[e]
        t_a, t_b = la / elen[e], 1.0 - lb[::-1] / elen[e]
        c0, c1 = np.interp([t_a[-1] if la.size else 0.0, t_b[0] if lb.size else 1.0], tt, cum)
        if (e, 0) in wedge_ends or (e, 1) in wedge_ends:
            m_free = max(1, int(np.round(c1 - c0)))
        else:
            m_free = n_steps[e] - la.size - lb.size  # steps between the leading centres
        k = la.size + lb.size + m_free
        inner = np.interp(c0 + np.arange(1, m_free) * (c1 - c0) / m_free, cum, tt)
        tk = np.concatenate([t_a, inner, t_b])
        pts = nodes[ea[e]] + tk[:, None] * (nodes[eb[e]] - nodes[ea[e]])
        ids = np.concatenate([[ea[e]], n_cen + np.arange(k - 1), [eb[e]]])
        cen.append(pts)
        cen_fault.append(np.full(k - 1, ef[e]))
        n_cen += k - 1
        step_a.append(ids[:-1])
        step_b.append(ids[1:])
        step_f.append(np.full(k, ef[e]))
        if (e, 0) in wedge_ends:
            wedge_steps[(e, 0)] = n_step + np.arange(la.size)
        if (e, 1) in wedge_ends:
            wedge_steps[(e, 1)] = n_step + k - 1 - np.arange(lb.size)
        n_step += k
    centres = np.concatenate(cen)
    centre_fault = np.concatenate(cen_fault)
    sa, sb, sf = np.concatenate(step_a), np.concatenate(step_b), np.concatenate(step_f)
    slen = np.linalg.norm(centres[sb] - centres[sa], axis=1)
    nc = centres.shape[0]
    cnt = np.bincount(sa, minlength=nc) + np.bincount(sb, minlength=nc)
    tot = np.bincount(sa, slen, nc) + np.bincount(sb, slen, nc)
    radii = _local_ratio(lay, centres, l0, constrained & ~wedge_node) * tot / np.maximum(cnt, 1)
    cmin = np.full(nc, np.inf)
    np.minimum.at(cmin, sa, slen)
    np.minimum.at(cmin, sb, slen)
    fixed = np.zeros(nc, dtype=bool)
    shared = _wedge_rows(wedge_list, nodes, ea, sa, sb, wedge_steps, radii, fixed)
    problems: list[tuple[int, str]] = []
    _junction_radii(
        lay, centres, radii, sa, sb, slen, constrained, problems, tot / np.maximum(cnt, 1), wedge_node, fixed
    )
    # Mirrored pairs.
    ra, rb = radii[sa], radii[sb]
    uvec = (centres[sb] - centres[sa]) / slen[:, None]
    nvec = np.column_stack([-uvec[:, 1], uvec[:, 0]])
    a_off = (slen**2 - rb**2 + ra**2) / (2 * slen)
    h2 = ra**2 - a_off**2
    bad = h2 <= (1e-6 * slen) ** 2
    for k in np.flatnonzero(bad):  # pragma: no cover - radii are built to intersect
        problems.append((int(sa[k]), "its circles do not intersect"))
    hgt = np.sqrt(np.maximum(h2, 0.0))
    foot = centres[sa] + a_off[:, None] * uvec
    left = foot + hgt[:, None] * nvec
    right = foot - hgt[:, None] * nvec
    step_size = slen.copy()
    step_wedge = np.full(sa.size, -1, dtype=np.int64)
    for steps, one, other, size, w in shared:  # acute wedges: the shared sites either side of a step
        on_left = _wedges.side_of(one, centres[sa[steps]], centres[sb[steps]]) > 0
        left[steps] = np.where(on_left[:, None], one, other)
        right[steps] = np.where(on_left[:, None], other, one)
        step_size[steps] = size
        step_wedge[steps] = w
    ns_ = sa.size
    # Tips: one site straight ahead of every free end, on its circle.
    tip_nodes = np.flatnonzero(ch.tip)
    first_step = np.full(nc, -1, dtype=np.int64)
    first_step[sb[::-1]] = np.arange(sb.size)[::-1]
    first_step[sa[::-1]] = np.arange(sa.size)[::-1]
    t_step = first_step[tip_nodes]
    t_other = np.where(sa[t_step] == tip_nodes, sb[t_step], sa[t_step])
    tdir = centres[tip_nodes] - centres[t_other]
    tdir /= np.linalg.norm(tdir, axis=1, keepdims=True) if tdir.size else 1.0
    tips = centres[tip_nodes] + radii[tip_nodes, None] * tdir
    all_sites = np.concatenate([left, right, tips])
    ab = centres[sb] - centres[sa]
    pair_foot = []
    for side in (left, right):  # the nearest point of each site's step (its mirror axis)
        rel = side - centres[sa]
        t = np.clip((rel[:, 0] * ab[:, 0] + rel[:, 1] * ab[:, 1]) / slen**2, 0.0, 1.0)
        pair_foot.append(centres[sa] + t[:, None] * ab)
    all_foot = np.concatenate([*pair_foot, centres[tip_nodes]])
    site_fault = np.concatenate([sf, sf, centre_fault[tip_nodes]])
    site_step = np.concatenate([step_size, step_size, slen[t_step]])
    is_tip = np.concatenate([np.zeros(2 * ns_, dtype=bool), np.ones(tip_nodes.size, dtype=bool)])
    # Coinciding inner sites (merged at sharp junctions) become one.
    tiny = 1e-7 * float(slen.min())
    first, rep = merge_close_points(all_sites, tiny)
    sites = all_sites[first]
    pair_idx = np.column_stack([rep[:ns_], rep[ns_ : 2 * ns_]])
    return FaultSites(
        sites=sites,
        site_fault=site_fault[first],
        site_step=site_step[first],
        site_foot=all_foot[first],
        is_tip=is_tip[first],
        pairs=pair_idx,
        pair_fault=sf,
        centres=centres,
        radii=radii,
        centre_fault=centre_fault,
        centre_step=cmin,
        trace_a=centres[sa],
        trace_b=centres[sb],
        trace_fault=sf,
        problems=problems,
        site_wedge=np.concatenate([step_wedge, step_wedge, np.full(tip_nodes.size, -1)])[first],
        wedges=[_describe_wedge(w, lay) for w in wedge_list],
    )


def _describe_wedge(w, lay: FaultLayout) -> str:
    """A note on an acute wedge or fan: where, between what, at which angles, how many shared cells."""
    net = lay.net
    names = [net.labels[net.edge_fault[e] - 1] if e >= 0 else "the boundary" for e in w.sides]
    names = list(dict.fromkeys(names))
    angles = " and ".join(f"{np.degrees(g):.3g}" for g in w.gaps)
    if len(names) == 1:
        what = f"{names[0]} bends"
    elif len(names) == 2:
        what = f"{names[0]} meets {names[1]}"
    else:
        what = ", ".join(names[:-1]) + f" and {names[-1]} meet"
    rows = "one row" if w.gaps.size == 1 else f"{w.gaps.size} rows"
    return (
        f"{what} at {angles} degrees at {lay.domain.fmt(net.nodes[w.node])}: {rows} of {w.rungs.size} "
        f"cells between them up to {float(w.rungs[-1]):.3g} m from there"
    )


def _plan_wedges(lay: FaultLayout, elen: np.ndarray, l0: np.ndarray, constrained: np.ndarray) -> list:
    """The acute wedges and fans at constrained nodes, their rungs fitted into their sides.

    An arm may use its whole length if its far end is free, half of it if that end is
    constrained too; a boundary side as far as the next corner or half way to the next
    fault on it. The step is the smallest wanted along the sides as far as the rungs
    reach (refinements there). All wedges at one node share the node's circle (the
    smallest of theirs).
    """
    net, dom = lay.net, lay.domain
    nodes, ea, eb = net.nodes, net.edge_a, net.edge_b
    cand = np.flatnonzero(constrained)
    rays = {int(v): _boundary_rays(dom, nodes[v]) for v in cand if net.on_boundary[v]}
    found = _wedges.find_wedges(nodes, ea, eb, cand, rays, dom)
    for w in found:  # loop over acute wedges and fans
        room = np.empty(len(w.sides))
        for j, e in enumerate(w.sides):
            if e >= 0:
                other = eb[e] if ea[e] == w.node else ea[e]
                room[j] = float(elen[e]) * (0.5 if constrained[other] else 1.0)
            else:
                room[j] = _boundary_room(net, dom, w.node, w.dirs[j])
        step = float(l0[w.node])
        for _ in range(3):  # the step wanted along the arms as far as the rungs reach (refinements)
            _wedges.plan(w, step, room)
            for e, j in w.arms():
                along = np.linspace(0.0, float(w.side_rungs(j)[-1]) + step, 17)
                pts = net.nodes[w.node] + along[:, None] * w.dirs[j][None, :]
                step = min(step, float(_ds(lay, pts, np.full(along.size, net.edge_fault[e])).min()))
        _wedges.plan(w, step, room)
    radius: dict[int, float] = {}
    for w in found:
        radius[w.node] = min(radius.get(w.node, np.inf), _wedges.node_radius(w))
    for w in found:
        _wedges.scale_to_radius(w, radius[w.node])
    return found


def _boundary_room(net: _Network, dom: Domain, v: int, u: np.ndarray) -> float:
    """Length (m) along the boundary from node v in direction u: to the next corner, or half way
    to the next fault node on the boundary."""
    x = net.nodes[v]
    best = np.inf
    for pts, share in ((dom.xy, 1.0), (net.nodes[net.on_boundary], 0.5)):
        rel = pts - x
        along = rel[:, 0] * u[0] + rel[:, 1] * u[1]
        off = np.abs(cross2(u[None, :], rel))
        ahead = (along > dom.tol) & (off <= 1e-7 * np.maximum(along, dom.tol))
        if ahead.any():
            best = min(best, share * float(along[ahead].min()))
    return best


def _leads(wedge_list: list, ea, eb, l0, constrained) -> tuple[list[list[np.ndarray]], dict]:
    """Distances (m) of the centres fixed next to each end of every edge, and the wedge ends
    with the step (m) of their rungs along the edge.

    A constrained end has its first centre one step L0 away; a wedge's arm has its rungs.
    """
    empty = np.zeros(0)
    lead = [
        [np.array([l0[a]]) if constrained[a] else empty, np.array([l0[b]]) if constrained[b] else empty]
        for a, b in zip(ea.tolist(), eb.tolist(), strict=True)
    ]
    ends: dict[tuple[int, int], float] = {}
    for w in wedge_list:
        for e, j in w.arms():
            end = 0 if ea[e] == w.node else 1
            lead[e][end] = w.side_rungs(j)
            ends[(e, end)] = w.ray_step / float(np.cos(w.tilt[j]))
    return lead, ends


def _wedge_rows(wedge_list, nodes, ea, sa, sb, wedge_steps, radii, fixed) -> list[tuple]:
    """Shared sites of every wedge or fan: (steps, one site, the other, site size, wedge) per fault side.

    The sites of a step on an inner side of a fan are the shared sites of the wedges on
    either side, on an outer side the shared sites and their mirror images. Sets the
    radii of the wedge nodes and rung centres (and marks the rungs ``fixed``).
    """
    out = []
    for index, w in enumerate(wedge_list):  # loop over acute wedges and fans
        ws = _wedges.wedge_sites(w, nodes[w.node])
        radii[w.node] = ws.radius_node
        n = w.gaps.size
        for e, j in w.arms():
            end = 0 if ea[e] == w.node else 1
            steps = wedge_steps[(e, end)]
            rung = sb[steps] if end == 0 else sa[steps]
            k = steps.size  # the rungs this side keeps
            radii[rung] = ws.radius_rungs[j, :k]
            fixed[rung] = True
            one = ws.shared[min(j, n - 1), :k]
            if 0 < j < n:
                other = ws.shared[j - 1, :k]
            else:
                other = (ws.mirror_first if j == 0 else ws.mirror_last)[:k]
            out.append((steps, one, other, np.full(k, w.step), index))
    return out


def _local_ratio(
    lay: FaultLayout, centres: np.ndarray, l0: np.ndarray, constrained: np.ndarray
) -> np.ndarray:
    """Circle radius / step per centre: smaller near junctions whose traces meet at acute angles.

    Two traces meeting at an angle phi are s sin(phi) apart at a distance s from the
    junction, while circles and sites stand off the traces by fixed fractions of the
    step: for phi below ACUTE the ratio drops towards 0.52 (sites closer to the
    traces) within 4 steps / sin(phi) of the junction, tapering back over as much again.
    Only at the ``constrained`` nodes given, those without an acute wedge of shared sites
    (:mod:`.wedges`): where two acute wedges would share an arm, the wider one.
    """
    ratio = np.full(centres.shape[0], lay.ratio)
    net = lay.net
    for v in np.flatnonzero(constrained):  # loop over fault junctions
        arms = np.concatenate([net.edge_b[net.edge_a == v], net.edge_a[net.edge_b == v]])
        if arms.size < 2:
            continue
        d = net.nodes[arms] - net.nodes[v]
        ang = np.sort(np.mod(arctan2(d[:, 1], d[:, 0]), 2 * np.pi))
        phi = float(np.diff(np.concatenate([ang, ang[:1] + 2 * np.pi])).min())
        if phi >= ACUTE:
            continue
        low = RATIO_MIN + (lay.ratio - RATIO_MIN) * np.clip(
            (phi - np.radians(15)) / (ACUTE - np.radians(15)), 0, 1
        )
        reach = 4.0 * l0[v] / max(np.sin(phi), 0.1)
        dist = np.linalg.norm(centres - net.nodes[v], axis=1)
        w = np.clip((dist - reach) / reach, 0.0, 1.0)
        ratio = np.minimum(ratio, low + (lay.ratio - low) * w)
    return ratio


def _junction_radii(
    lay: FaultLayout, centres, radii, sa, sb, slen, constrained, problems, mean_step, wedge_node, fixed
) -> None:
    """Radii at constrained nodes (junctions, sharp bends, boundary points).

    The sites of the first step of arm j sit at an angle alpha_j from the arm, seen
    from the node; alpha_j grows with the node's radius r_v (the next radius being
    fixed). The largest r_v up to ``ratio`` times the first step is taken at which
    the sites of neighbouring arms do not cross (alpha_j + alpha_k <= gap; at
    equality they coincide and are merged into one site on three circles) and the
    sites next to the boundary stay inside it (alpha_j <= gap / 2).

    At the node of an acute wedge (``wedge_node``) r_v is the wedge's, and so are the
    radii of its rung points (``fixed``); the other arms' first circles are made smaller
    where their sites would cross (:func:`_fit_free_arms`).
    """
    dom = lay.domain
    ratio = lay.ratio
    for v in np.flatnonzero(constrained):  # loop over fault junctions
        steps = np.concatenate([np.flatnonzero(sa == v), np.flatnonzero(sb == v)])
        if steps.size == 0:
            continue
        far = np.concatenate([sb[sa == v], sa[sb == v]])
        d = centres[far] - centres[v]
        ang = np.mod(arctan2(d[:, 1], d[:, 0]), 2 * np.pi)
        lens = slen[steps]
        rw = radii[far]
        rays = [(a, k) for k, a in enumerate(ang)]
        if lay.net.on_boundary[v]:
            rays += [(float(np.mod(b, 2 * np.pi)), -1) for b in _boundary_rays(dom, centres[v])]
        rays.sort()
        nr = len(rays)
        pairs, caps = [], []  # (arm, arm, gap) between arms; (arm, limit) next to the boundary
        for g in range(nr):
            (a0, k0), (a1, k1) = rays[g], rays[(g + 1) % nr]
            gap = np.mod(a1 - a0, 2 * np.pi) if nr > 1 else 2 * np.pi
            if k0 >= 0 and k1 >= 0:
                if nr > 1:
                    pairs.append((k0, k1, gap))
            elif k0 >= 0 or k1 >= 0:
                mid = a0 + 0.5 * gap
                probe = centres[v] + 1e-6 * lens.min() * np.array([np.cos(mid), np.sin(mid)])
                if dom.inside(probe[None, :])[0] or (k0 >= 0 and k1 >= 0):
                    caps.append((k0 if k0 >= 0 else k1, 0.5 * gap))

        def fits(rv: float, lens=lens, rw=rw, pairs=pairs, caps=caps) -> bool:
            al = arccos(np.clip((rv**2 + lens**2 - rw**2) / (2 * rv * lens), -1.0, 1.0))
            return all(al[j] + al[k] <= gap * (1 + 1e-12) for j, k, gap in pairs) and all(
                al[k] <= lim for k, lim in caps
            )

        shared = _shared_first_centres(far, v, sa, sb, constrained) | fixed[far]
        if wedge_node[v]:
            if not _fit_free_arms(float(radii[v]), far, lens, radii, pairs, caps, shared):
                problems.append((int(v), "the traces meet at too sharp an angle"))
            continue
        hi = min(ratio, radii[v] / mean_step[v]) * float(lens.min())
        lo = float(np.max(lens - rw)) * (1 + 1e-9)
        if fits(hi):
            radii[v] = hi
        elif lo >= hi or not fits(lo * (1 + 1e-6)):
            # no node radius fits with these first circles (arms of different steps between tight
            # gaps, at a corner of the domain): the arms' first circles are fitted instead
            radii[v] = hi
            fitted = _fit_free_arms(hi, far, lens, radii, pairs, caps, shared)
            problems.append((int(v), FITTED if fitted else "the traces meet at too sharp an angle"))
            continue
        else:
            a, b = lo * (1 + 1e-6), hi
            for _ in range(60):  # bisection: the largest radius that fits
                m = 0.5 * (a + b)
                a, b = (m, b) if fits(m) else (a, m)
            radii[v] = a
        _close_near_pairs(int(v), float(radii[v]), far, lens, radii, pairs, caps, sa, sb, slen, constrained)


def _shared_first_centres(far: np.ndarray, v: int, sa, sb, constrained) -> np.ndarray:
    """Which first centres of the arms at node v are also next to another constrained node
    (an edge of two steps between two junctions): their radii belong to both."""
    out = np.zeros(far.size, dtype=bool)
    for j, c in enumerate(far.tolist()):  # the arms at one node (a handful)
        other = np.concatenate([sb[sa == c], sa[sb == c]])
        other = other[other != v]
        node = other[other < constrained.size]  # network nodes come first among the centres
        out[j] = bool(constrained[node].any())
    return out


def _fit_free_arms(rv: float, far, lens, radii, pairs, caps, held) -> bool:
    """Shrink the first circles of arms (not ``held``, per arm: a wedge's, or shared with another
    node) so that no sites cross at a node whose radius is given (a wedge's, or any that fits).

    Arm j's first sites sit at alpha_j from it; with the node's radius r_v fixed, alpha_j
    is set by the radius r_j of its first centre: r_j^2 = r_v^2 + L_j^2 - 2 r_v L_j cos alpha_j
    (L_j its first step). Where neighbouring arms' sites cross, the free arm's alpha is cut to
    what the gap leaves (half of it between two free arms). True if everything fits then.
    """
    tol = 1e-9

    def alphas() -> np.ndarray:
        return arccos(np.clip((rv**2 + lens**2 - radii[far] ** 2) / (2 * rv * lens), -1.0, 1.0))

    al = alphas()
    free = ~held
    bound = np.full(far.size, np.inf)
    for j, k, gap in pairs:
        if al[j] + al[k] <= gap * (1 + tol):
            continue
        if free[j] and free[k]:
            bound[j], bound[k] = min(bound[j], 0.5 * gap), min(bound[k], 0.5 * gap)
        elif free[j]:
            bound[j] = min(bound[j], gap - al[k])
        elif free[k]:
            bound[k] = min(bound[k], gap - al[j])
    for k, lim in caps:
        if free[k] and al[k] > lim * (1 + tol):
            bound[k] = min(bound[k], lim)
    cut = free & (bound < al) & (bound > 0)
    if cut.any():
        a = bound[cut]
        radii[far[cut]] = np.sqrt(rv**2 + lens[cut] ** 2 - 2 * rv * lens[cut] * np.cos(a))
        al = alphas()
    return all(al[j] + al[k] <= gap * (1 + tol) for j, k, gap in pairs) and all(
        al[k] <= lim * (1 + tol) for k, lim in caps
    )


def _close_near_pairs(v, rv, far, lens, radii, pairs, caps, sa, sb, slen, constrained) -> None:
    """Make the first sites of neighbouring arms coincide where they nearly do.

    With two (nearly) equally tight pairs of arms, as where two straight faults cross,
    only one pair coincides at the largest radius; the other pair's sites end up a hair
    apart, and their cells meet in faces of millimetres. Such a pair (sites closer than
    0.1 first steps) is closed by enlarging the circle at the first centre along one of
    its arms, so that that arm's alpha grows by the angle left: only where the arm's
    other neighbour keeps its distance, the first centre's other circle still meets it
    properly, and neither end of that step is constrained (its radius belongs to another
    junction).
    """
    al = arccos(np.clip((rv**2 + lens**2 - radii[far] ** 2) / (2 * rv * lens), -1.0, 1.0))
    slack = {(j, k): gap - (al[j] + al[k]) for j, k, gap in pairs}
    cap = dict.fromkeys(range(len(far)), np.inf)
    for k, lim in caps:
        cap[k] = min(cap[k], lim)
    close = 0.1 * float(lens.min())

    def fixed(c: int) -> bool:  # network nodes come first among the centres
        return c < constrained.size and bool(constrained[c])

    for (j, k), left in sorted(slack.items(), key=lambda t: t[1]):
        left = slack[(j, k)]
        dist = 2 * rv * np.sin(0.5 * left)
        if not (1e-7 * rv < dist < close):  # coincide already, or far enough apart
            continue
        for arm in (j, k):  # the arm whose other side has room
            others = [s for key, s in slack.items() if arm in key and key != (j, k)]
            if (others and min(others) - left < 2 * close / rv) or al[arm] + left > cap[arm]:
                continue
            c1 = int(far[arm])
            at = np.flatnonzero((sa == c1) | (sb == c1))
            if fixed(c1) or at.size != 2:
                continue
            alpha = al[arm] + left
            rw = float(np.sqrt(max(rv**2 + lens[arm] ** 2 - 2 * rv * lens[arm] * np.cos(alpha), 0.0)))
            fine = rw > 0
            for t in at.tolist():  # the circles at both ends of both steps still intersect properly
                o = int(sb[t]) if int(sa[t]) == c1 else int(sa[t])
                if o != v and fixed(o):
                    fine = False
                ro, lt = float(radii[o]), float(slen[t])
                fine = fine and abs(rw - ro) < 0.95 * lt and rw + ro > 1.05 * lt
            if not fine:
                continue
            radii[c1] = rw
            al[arm] = alpha
            for key in slack:
                if arm in key:
                    slack[key] -= left
            break


def _boundary_rays(dom: Domain, p: np.ndarray) -> list[float]:
    """Directions (angles) of the domain boundary leaving a boundary point."""
    _, edge, u = dom.nearest_boundary(p[None, :])
    e, uu = int(edge[0]), float(u[0])
    m = dom.num_vertices
    eps = dom.tol / dom.edge_len[e]
    if uu <= eps:
        d1, d2 = dom.edge_unit[e], -dom.edge_unit[(e - 1) % m]
    elif uu >= 1 - eps:
        d1, d2 = dom.edge_unit[(e + 1) % m], -dom.edge_unit[e]
    else:
        d1, d2 = dom.edge_unit[e], -dom.edge_unit[e]
    return [float(arctan2(d1[1], d1[0])), float(arctan2(d2[1], d2[0]))]


def circle_violations(
    fs: FaultSites, sites: np.ndarray | None, tree: cKDTree | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """(centre, site) pairs where a site lies strictly inside a fault circle.

    "Strictly" allows 1e-9 relative slack: the circle's own sites lie on it.
    """
    if fs.centres.shape[0] == 0 or (tree is None and sites.shape[0] == 0):
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    tree = tree or cKDTree(sites)
    hits = tree.query_ball_point(fs.centres, fs.radii * (1 - 1e-9), return_sorted=False)
    lens = tree.query_ball_point(fs.centres, fs.radii * (1 - 1e-9), return_length=True)
    c = np.repeat(np.arange(fs.centres.shape[0]), lens)
    s = np.fromiter(itertools.chain.from_iterable(hits), dtype=np.int64, count=int(lens.sum()))
    return c, s
