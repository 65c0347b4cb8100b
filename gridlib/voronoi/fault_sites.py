"""Fault-conforming sites: mirrored pairs from intersecting circles along fault traces.

Built on the network of :mod:`.fault_network` (traces clipped, extended and split into a planar
graph), all in the domain's local frame:

1. **Circle centres.** Every polyline vertex, intersection and boundary point is
   a centre, so faces follow the trace exactly, bends included. Each segment is
   divided into steps whose length follows the fault spacing (``Fault.spacing``,
   default the local cell size), graded with a growth of at most 30 % per unit
   length away from short segments and from local refinements.
2. **Radii and sites.** A centre's radius is ``ratio`` (0.6) times the mean of its
   two steps. Consecutive circles intersect in two points mirrored across the
   step: the left and right sites. Both centres are equidistant from both sites,
   so the Voronoi edge between them is the step itself, *provided no site lies
   strictly inside a circle* (the empty-circle condition).
3. **Tips, junctions, boundary.** A free end gets a *tip site* on its circle,
   straight ahead. At a constrained node (a junction of three or more arms, two
   faults meeting end to end, a bend turning by more than 90°, a boundary point)
   every arm starts with the same step, and the node's radius is the largest
   (up to ``ratio`` times that step) at which the sites of neighbouring arms do
   not cross: the angle alpha at which an arm's first sites sit, seen from the
   node, grows with the radius, and neighbouring arms need alpha_j + alpha_k <=
   the angle between them. The tightest pair gets equality: its two inner sites
   coincide and become one site on three circles. Sites next to the boundary
   keep alpha below half the angle to it, so they stay inside.
4. **Acute wedges.** Where two arms leave a node less than 40° apart (a V, an
   acute X, T or Y, a trace kinked by a sharp bend) or a trace meets the boundary
   at less than 40°, mirrored pairs cannot fit near the node at any step (the
   wedge is s sin(angle) wide at a distance s): one row of sites shared by both
   sides fills the wedge instead (:mod:`.wedges`), exact on both traces, until the
   wedge is wide enough for two rows. At a node inside the domain all its arms form
   one fan, every arm with rows of its own at common distances from the node (a splay
   of any number of faults at any angles). At a node on the boundary the other arms'
   first circles are fitted to the wedge's circle (traces meeting at less than 40°
   that share an arm with a narrower wedge get smaller circles nearby instead, ratio
   down to 0.52).
5. **Check and refine.** After the background is added, every circle is checked
   for sites strictly inside it (:func:`circle_violations`, background, fault and
   well sites alike), and every fault site for lying inside the domain. Where a
   check fails the fault step is made smaller locally, by what the geometry needs
   (a circle holding a site shrinks below that site's distance; a site outside the
   domain comes closer to its trace than the boundary is, down to a quarter of the
   fault's step; at least halving), and the sites rebuilt, down to fault steps of the
   cell size times 2^-max_refinements (``PebiTuning``); if a circle still holds a site, a
   :class:`GridError` names the faults, the place and the case keys that would help.
   Sites left outside the domain stay: the boundary closes their cells
   (:func:`.conformity.outside_sites`).

Wells keep clear of the fault circles: :func:`.fault_layout.ring_room` gives how far a well's
rings may reach (:mod:`.wells` shrinks them to that, with a note); a vertical well with no room
at all gets one of the fault's cells (:mod:`.fault_wells`).

Fault ids are the 1-based positions in the ``faults`` sequence; face tags use them.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.spatial import cKDTree

from ..planar import cross2, merge_close_points
from . import wedges as _wedges
from .domain import Domain
from .fault_junctions import Steps, junction_radii, local_ratio
from .fault_layout import GROWTH, FaultLayout, step_length
from .fault_network import FaultNetwork

REACH = 0.8  # a wedge's node circle reaches this fraction of the way to its other arms' first sites


@dataclass(frozen=True, eq=False)
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


def build_sites(lay: FaultLayout) -> FaultSites:
    """Centres, radii and mirrored sites for the current refinement."""
    net, ch = lay.net, lay.ch
    nodes = net.nodes
    nn = nodes.shape[0]
    ea, eb = net.edge_a, net.edge_b
    elen = np.linalg.norm(nodes[eb] - nodes[ea], axis=1)
    node_fault, hv = _node_steps(lay, elen)
    # At a constrained node (junction, sharp bend, boundary point) every arm starts with the same
    # step L0, and an edge needs a step of its own next to each constrained end; an acute wedge
    # (wedges.py) fixes the first centres of its arms at its rungs instead.
    constrained = ch.key & ~ch.tip
    ends_c = constrained[ea].astype(np.int64) + constrained[eb]
    l0 = hv.copy()
    np.minimum.at(l0, ea, elen / np.maximum(ends_c + 1, 2))
    np.minimum.at(l0, eb, elen / np.maximum(ends_c + 1, 2))
    arm_room = np.full(nn, np.inf)  # the longest first step every arm at a node can take
    np.minimum.at(arm_room, ea, elen / np.maximum(ends_c + 1, 2))
    np.minimum.at(arm_room, eb, elen / np.maximum(ends_c + 1, 2))
    wedge_list = _plan_wedges(lay, elen, l0, constrained, arm_room)
    for w in wedge_list:  # the other arms at a wedge's node start with steps its circle can reach
        reach = _wedges.node_radius(w)
        l0[w.node] = min(max(l0[w.node], reach / (REACH * (1 + lay.ratio))), reach / lay.ratio)
    lead, wedge_ends = _leads(wedge_list, ea, eb, l0, constrained)
    wedge_node = np.zeros(nn, dtype=bool)
    wedge_node[[w.node for w in wedge_list]] = True
    n_steps, params = _steps_per_edge(lay, elen, hv, lead, wedge_ends, wedge_node)
    n_steps = np.maximum(n_steps, ends_c + 1)
    centres, centre_fault, sa, sb, sf, wedge_steps = _centres(
        net, node_fault, elen, n_steps, params, lead, wedge_ends
    )
    # Radii: ``ratio`` x the mean of a centre's two steps, then fitted at junctions and wedges.
    slen = np.linalg.norm(centres[sb] - centres[sa], axis=1)
    nc = centres.shape[0]
    cnt = np.bincount(sa, minlength=nc) + np.bincount(sb, minlength=nc)
    tot = np.bincount(sa, slen, nc) + np.bincount(sb, slen, nc)
    radii = local_ratio(lay, centres, l0, constrained & ~wedge_node) * tot / np.maximum(cnt, 1)
    cmin = np.full(nc, np.inf)
    np.minimum.at(cmin, sa, slen)
    np.minimum.at(cmin, sb, slen)
    steps = Steps(sa, sb, slen)
    shared, radii, fixed = _wedge_rows(wedge_list, nodes, ea, steps, wedge_steps, radii)
    radii, problems = junction_radii(
        lay, centres, radii, steps, constrained, tot / np.maximum(cnt, 1), wedge_node, fixed
    )
    pairs, unmet = _mirrored_pairs(centres, radii, steps, shared)
    fs = _with_tips(ch.tip, centres, centre_fault, radii, cmin, (sa, sb, sf, slen), pairs)
    return replace(fs, problems=problems + unmet, wedges=[_describe_wedge(w, lay) for w in wedge_list])


def _node_steps(lay: FaultLayout, elen: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The fault of every network node and its step: the fault spacing, capped by the lengths of
    the adjacent segments, then graded along the network (at most ``GROWTH`` per metre)."""
    net = lay.net
    nodes = net.nodes
    nn = nodes.shape[0]
    ea, eb, ef = net.edge_a, net.edge_b, net.edge_fault
    node_fault = np.zeros(nn, dtype=np.int64)
    node_fault[ea] = ef
    node_fault[eb] = ef
    hv = step_length(lay, nodes, node_fault)
    np.minimum.at(hv, ea, elen)
    np.minimum.at(hv, eb, elen)
    for _ in range(nn):  # Lipschitz grading along the network, vectorised over edges
        before = hv.copy()
        np.minimum.at(hv, ea, hv[eb] + GROWTH * elen)
        np.minimum.at(hv, eb, hv[ea] + GROWTH * elen)
        if np.array_equal(before, hv):
            break
    return node_fault, hv


def _steps_per_edge(lay: FaultLayout, elen, hv, lead, wedge_ends, wedge_node) -> tuple[np.ndarray, list]:
    """How many steps every edge gets, and (t, cumulative step count) samples along it for
    placing them: the target step is sampled finely enough (8 samples per step), capped by the
    grading away from the edge's ends and from the acute wedges next to it."""
    net = lay.net
    nodes, ea, eb, ef = net.nodes, net.edge_a, net.edge_b, net.edge_fault
    ne = ea.size
    n_steps = np.zeros(ne, dtype=np.int64)
    params: list[np.ndarray] = [None] * ne  # type: ignore[list-item]
    for e in range(ne):  # loop over polyline segments
        m = 65
        for _ in range(4):  # sample the size function finely enough (8 samples per step)
            tt = np.linspace(0.0, 1.0, m)
            xy = nodes[ea[e]] + tt[:, None] * (nodes[eb[e]] - nodes[ea[e]])
            caps = [
                step_length(lay, xy, np.full(m, ef[e])),
                hv[ea[e]] + GROWTH * tt * elen[e],
                hv[eb[e]] + GROWTH * (1 - tt) * elen[e],
            ]
            for end, along in ((0, tt * elen[e]), (1, (1 - tt) * elen[e])):  # grading away from a wedge
                w = lead[e][end]
                if (e, end) in wedge_ends:
                    step, rows_end = wedge_ends[(e, end)]
                    caps.append(step + GROWTH * np.maximum(along - rows_end, 0.0))
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
    return n_steps, params


def _centres(net: FaultNetwork, node_fault, elen, n_steps, params, lead, wedge_ends) -> tuple:
    """Circle centres (network nodes first, then the interior points of every edge), their
    faults, the steps between consecutive centres (sa, sb, fault) and, for every edge end at an
    acute wedge, its steps counted from that end."""
    nodes, ea, eb, ef = net.nodes, net.edge_a, net.edge_b, net.edge_fault
    cen = [nodes]
    cen_fault = [node_fault]
    step_a, step_b, step_f = [], [], []
    n_cen = nodes.shape[0]
    n_step = 0
    wedge_steps: dict[tuple[int, int], np.ndarray] = {}  # (edge, end) -> its steps, from that end
    for e in range(ea.size):  # loop over polyline segments
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
    return centres, centre_fault, sa, sb, sf, wedge_steps


def _mirrored_pairs(
    centres, radii, steps: Steps, shared
) -> tuple[tuple[np.ndarray, ...], list[tuple[int, str]]]:
    """The two sites of every step, where its circles intersect (left, right of the step), or the
    shared sites of an acute wedge; the size and wedge (or -1) of every step. Also the steps
    whose circles do not intersect, as problems (centre, why)."""
    sa, sb, slen = steps.a, steps.b, steps.length
    problems: list[tuple[int, str]] = []
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
    return (left, right, step_size, step_wedge), problems


def _with_tips(tip, centres, centre_fault, radii, cmin, steps, pairs) -> FaultSites:
    """The fault sites: the mirrored pairs, one site straight ahead of every free end (``tip``)
    on its circle, coinciding sites (merged at sharp junctions) made one."""
    sa, sb, sf, slen = steps
    left, right, step_size, step_wedge = pairs
    ns_ = sa.size
    nc = centres.shape[0]
    tip_nodes = np.flatnonzero(tip)
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
        site_wedge=np.concatenate([step_wedge, step_wedge, np.full(tip_nodes.size, -1)])[first],
    )


def _describe_wedge(w, lay: FaultLayout) -> str:
    """A note on an acute wedge or fan: where, between what, at which angles, how many shared cells."""
    net = lay.net
    acute = np.flatnonzero(w.acute)
    sides = [w.sides[j] for j in sorted({*acute.tolist(), *(acute + 1).tolist()})]
    names = [net.labels[net.edge_fault[e] - 1] if e >= 0 else "the boundary" for e in sides]
    names = list(dict.fromkeys(names))
    angles = " and ".join(f"{np.degrees(g):.3g}" for g in w.gaps[acute])
    if len(names) == 1:
        what = f"{names[0]} bends"
    elif len(names) == 2:
        what = f"{names[0]} meets {names[1]}"
    else:
        what = ", ".join(names[:-1]) + f" and {names[-1]} meet"
    rows = "one row" if w.rows == 1 else f"{w.rows} rows"
    return (
        f"{what} at {angles} degrees at {lay.domain.fmt(net.nodes[w.node])}: {rows} of {w.rungs.size} "
        f"cells between them up to {float(w.rungs[-1]):.3g} m from there"
    )


def _plan_wedges(
    lay: FaultLayout, elen: np.ndarray, l0: np.ndarray, constrained: np.ndarray, arm_room: np.ndarray
) -> list:
    """The acute wedges and fans at constrained nodes, their rungs fitted into their sides.

    An arm may use its whole length if its far end is free, half of it if that end is
    constrained too; a boundary side as far as the next corner or half way to the next
    fault on it. The step is the smallest wanted along the sides as far as the rungs
    reach (refinements there). All wedges at one node share their rungs
    (:func:`.wedges.share_rungs`), and the node's circle must reach the first circles of
    the node's other arms: an arm's first step (at most ``arm_room``, m) needs a circle of
    ``ratio`` times it that overlaps the node's, so the node's radius is at most
    ``REACH (1 + ratio) arm_room``. (A very narrow wedge stretches its first cell away from
    the node, up to 3.5 steps: next to a short arm, a trace running into a corner of the
    domain, the rungs are then scaled down.)
    """
    net, dom = lay.net, lay.domain
    nodes, ea, eb = net.nodes, net.edge_a, net.edge_b
    cand = np.flatnonzero(constrained)
    rays = {int(v): dom.boundary_rays(nodes[v]) for v in cand if net.on_boundary[v]}
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
                step = min(step, float(step_length(lay, pts, np.full(along.size, net.edge_fault[e])).min()))
        _wedges.plan(w, step, room)
    for v in dict.fromkeys(w.node for w in found):
        at = [w for w in found if w.node == v]
        _wedges.share_rungs(at)
        limit = REACH * (1 + lay.ratio) * float(arm_room[v])
        if _wedges.node_radius(at[0]) > limit:
            for w in at:
                _wedges.scale_to_radius(w, limit)
    return found


def _boundary_room(net: FaultNetwork, dom: Domain, v: int, u: np.ndarray) -> float:
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
    with the step (m) of their rungs along the edge and the distance (m) along it to the end of
    the wedge's rows (the steps beyond grow only from there: the other sides' rows may run on).

    A constrained end has its first centre one step L0 away; a wedge's arm has its rungs.
    """
    empty = np.zeros(0)
    lead = [
        [np.array([l0[a]]) if constrained[a] else empty, np.array([l0[b]]) if constrained[b] else empty]
        for a, b in zip(ea.tolist(), eb.tolist(), strict=True)
    ]
    ends: dict[tuple[int, int], tuple[float, float]] = {}
    for w in wedge_list:
        for e, j in w.arms():
            end = 0 if ea[e] == w.node else 1
            lead[e][end] = w.side_rungs(j)
            ends[(e, end)] = (w.ray_step / float(np.cos(w.tilt[j])), w.rows_end(j))
    return lead, ends


def _wedge_rows(
    wedge_list, nodes, ea, all_steps: Steps, wedge_steps, radii: np.ndarray
) -> tuple[list[tuple], np.ndarray, np.ndarray]:
    """Shared sites of every wedge or fan: (steps, one site, the other, site size, wedge) per fault
    side; the radii with those of the wedge nodes and rung centres set, and which centres are
    such rungs (``fixed``).

    The sites of a step are the side's row and its mirror image (the row of the next gap where
    that gap's row is shared).
    """
    sa, sb = all_steps.a, all_steps.b
    radii = radii.copy()
    fixed = np.zeros(radii.size, dtype=bool)
    out = []
    for index, w in enumerate(wedge_list):  # loop over acute wedges and fans
        ws = _wedges.wedge_sites(w, nodes[w.node])
        radii[w.node] = ws.radius_node
        for e, j in w.arms():
            end = 0 if ea[e] == w.node else 1
            steps = wedge_steps[(e, end)]
            rung = sb[steps] if end == 0 else sa[steps]
            k = steps.size  # the rungs this side keeps
            radii[rung] = ws.radius_rungs[j, :k]
            fixed[rung] = True
            out.append((steps, ws.own[j, :k], ws.mirror[j, :k], np.full(k, w.step), index))
    return out, radii, fixed


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
