"""The fault layout: the fault network, which of its nodes are constrained, and the target
step along the traces.

A node is *constrained* (a "key" node) where the sites around it cannot simply follow one
trace: a junction of three or more arms, a point where two faults meet end to end, a bend
sharper than 90 degrees, a boundary point. A free end (degree 1, not on the boundary) is a
*tip*. The step along a trace is the fault's ``spacing`` where given, else the local cell
size, made smaller around local refinements (``refine``: points with a step, growing by
``GROWTH`` per metre away from them). Sites are rebuilt from the layout at every
refinement (:mod:`.fault_sites`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, replace

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

from .domain import Domain
from .fault_network import Fault, FaultNetwork, build_network

GROWTH = 0.3  # at most 30 % longer steps per step length away from a short one
KEY_ANGLE = np.radians(90.0)  # a bend sharper than this (inner angle) is handled as a junction
RING_GAP = 0.25  # a well's rings end this many fault steps outside the fault circles


@dataclass(frozen=True, eq=False)
class _Chains:
    """Which network nodes are constrained ("key": junctions, boundary points, fault changes,
    sharp bends) and which are free ends (tips)."""

    key: np.ndarray  # (nn,) bool
    tip: np.ndarray  # (nn,) bool


def _chains(net: FaultNetwork) -> _Chains:
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


Refinement = tuple[float, float, float]  # (x, y, step): the step wanted at a point (local frame, m)


@dataclass(frozen=True, eq=False)
class FaultLayout:
    """The network and its constrained nodes; sites are rebuilt from it for every refinement.

    ``refine``: the local refinements asked for so far, in the order asked.
    """

    net: FaultNetwork
    ch: _Chains
    size: Callable
    ratio: float
    domain: Domain
    refine: tuple[Refinement, ...] = ()

    def refined(self, requests: Iterable[Refinement]) -> FaultLayout:
        """This layout with the refinement ``requests`` added after those made before, less
        those another makes redundant (:func:`without_dominated`)."""
        return replace(self, refine=without_dominated(self.refine + tuple(requests)))


def without_dominated(refine: tuple[Refinement, ...]) -> tuple[Refinement, ...]:
    """The refinements, in their order, less those that change no step: a refinement (r, s) is
    redundant where another (r', s') asks at least as much everywhere, s' + GROWTH |r - r'| <= s
    (then s' + GROWTH |x - r'| <= s + GROWTH |x - r| at every x), kept with a margin of 1e-9 so
    that rounding never makes the dropped one the smaller. Of two equal ones the first stays."""
    if len(refine) < 2:
        return refine
    ref = np.asarray(refine, dtype=np.float64)
    tree = cKDTree(ref[:, :2])
    reach = (ref[:, 2].max() - ref[:, 2].min()) / GROWTH
    keep = np.ones(ref.shape[0], dtype=bool)
    for i, near in enumerate(tree.query_ball_point(ref[:, :2], reach)):  # loop over refinements
        near = np.asarray(near, dtype=np.int64)
        near = near[(near != i) & keep[near]]
        if near.size == 0:
            continue
        rel = ref[near, :2] - ref[i, :2]
        bound = ref[near, 2] + GROWTH * np.hypot(rel[:, 0], rel[:, 1])
        equal = (ref[near, 2] == ref[i, 2]) & (rel == 0).all(axis=1)
        if np.any((bound <= ref[i, 2] * (1 - 1e-9)) | (equal & (near < i))):
            keep[i] = False
    return tuple(r for r, k in zip(refine, keep.tolist(), strict=True) if k)


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
    step = step_length(lay, foot.reshape(-1, 2), np.tile(net.edge_fault, points.shape[0])).reshape(dist.shape)
    room = dist - (lay.ratio + RING_GAP) * step
    k = np.argmin(room, axis=1)
    rows = np.arange(points.shape[0])
    return room[rows, k], [net.labels[f - 1] for f in net.edge_fault[k].tolist()], dist[rows, k]


def step_length(lay: FaultLayout, xy: np.ndarray, fault: np.ndarray) -> np.ndarray:
    """Target step length at points of the given faults (m)."""
    sp = lay.net.spacing[fault - 1]
    out = np.where(np.isfinite(sp), sp, 0.0)
    need = ~np.isfinite(sp)
    if need.any():
        out[need] = lay.size(xy[need])
    if lay.refine:
        out = np.minimum(out, refined_step(np.asarray(lay.refine), xy))
    return out


def refined_step(ref: np.ndarray, xy: np.ndarray, k: int = 16) -> np.ndarray:
    """min over the refinements ``ref`` (r, 3: x, y, step) of step + GROWTH x distance, at every
    point of ``xy``: over the ``k`` nearest refinements where that settles it (every other one is
    farther, so asks at least the smallest step + GROWTH x the k-th distance), over all of them
    elsewhere; the same values either way."""
    if ref.shape[0] <= 4 * k:  # few: all of them (a tree would cost more)
        out = np.empty(xy.shape[0])
        open_ = np.arange(xy.shape[0])
    else:
        _, near = cKDTree(ref[:, :2]).query(xy, k=k)
        dist = np.hypot(xy[:, None, 0] - ref[near, 0], xy[:, None, 1] - ref[near, 1])
        out = (ref[near, 2] + GROWTH * dist).min(axis=1)
        open_ = np.flatnonzero(out > ref[:, 2].min() + GROWTH * dist[:, -1])
    chunk = max(1, 2**20 // ref.shape[0])
    for start in range(0, len(open_), chunk):  # the points the nearest ones do not settle
        rows = open_[start : start + chunk]
        d = np.hypot(xy[rows, None, 0] - ref[None, :, 0], xy[rows, None, 1] - ref[None, :, 1])
        out[rows] = (ref[None, :, 2] + GROWTH * d).min(axis=1)
    return out
