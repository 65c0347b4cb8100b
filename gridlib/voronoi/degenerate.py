"""Short faces from nearly degenerate sites, collapsed exactly by moving background sites a little.

A Voronoi face is short when the two vertices at its ends nearly coincide: four
sites lie nearly on one circle, or three sites nearly on a circle centred on the
domain's boundary, or the bisector of two sites passes close to a polygon corner.
Generic site sets do this everywhere along the boundary and wherever a regular
lattice meets fault or well sites, so that faces of 1e-4 cell sizes and less
appear (useless for simulation: near-zero transmissibility, nodes a hair apart in
2.5D grids). Contracting them would move Voronoi vertices off the bisectors, and
faces would no longer be perpendicular to their site pairs. Instead, one *movable*
site (a background site) is moved radially onto the circle that makes the
degeneracy exact: the face then has length zero and is contracted (the
vertex becomes one point shared by four cells, or lies exactly on the boundary,
or the bisector passes exactly through the corner), and every face of the diagram
stays an exact perpendicular bisector.

For a short face of length l the site moves by at most about 2 l; faces shorter
than ``SHORT`` (5 %) of the smaller local size of their two sites are collapsed.
Three kinds are found from the unclipped ridges (vertex = circumcentre):

* **interior**: a ridge (p, q) between vertices V1 (sites p, q, r) and V2 (p, q, s):
  s is moved onto the circle of V1, or r onto the circle of V2;
* **boundary**: a vertex V (sites a, b, c) within ``SHORT`` sizes of a boundary
  edge: for a pair (a, b), X is where their bisector meets the edge, and c is
  moved onto the circle of centre X through a and b (the vertex becomes X);
* **corner**: a ridge (p, q) passing close to a convex polygon corner K: p is moved
  onto the circle of centre K through q (or q onto the one through p). At a
  re-entrant corner the opposite: a ridge through K would cut the cell on the side
  of the outside wedge into two pieces touching at K, so the ridge is pushed off, to
  about ``SHORT`` sizes from K (K stays in the cell it is nearer to), and no pin is kept.

Candidates are taken greedily by displacement, one per group of sites involved,
and only where the caller allows the new position (inside the domain, outside the
fault circles); the diagram is then recomputed, and the search repeated.

A site that is already on an exact degenerate circle (a vertex shared by four or
more cells: the squares of a Cartesian lattice, a face collapsed before, the
boundary point a vertex was put on) must stay on it, or that collapse would come
undone as a new short face: with one such circle it moves to the nearer
intersection of the two circles, with two or more it does not move.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..planar import group_pairs
from .domain import Domain
from .ridges import Ridges

SHORT = 0.05  # faces shorter than this fraction of the local size are collapsed
CONTRACT = 0.01  # ... or, where no site can move, contracted if shorter than this fraction
REACH = 3.0  # a site moves by at most REACH x SHORT x its size


@dataclass(frozen=True, eq=False)
class Collapse:
    """What :func:`collapse_moves` did in earlier rounds.

    ``pins``: site -> circles it was put on at the boundary or at a corner, as
    ``("edge", p, q, e)`` (centred where the bisector of sites p and q meets
    boundary edge e, through p) or ``("corner", k, y)`` (centred on corner k,
    through site y), recomputed from the current sites (collapses inside the domain
    are found again as degenerate vertices); ``pending``: the sites of the short
    faces not collapsed yet (looked at again next round); ``involved``: the sites of
    all the short faces the last round found.
    """

    pins: Mapping[int, tuple[tuple, ...]] = field(default_factory=dict)
    pending: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    involved: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))


@dataclass(frozen=True, eq=False)
class MoveRules:
    """What :func:`collapse_moves` may do with the sites of one diagram.

    ``domain``; ``size`` (n,) the local size of every site (m); ``movable`` (n,) bool, the
    sites that may move; ``tol`` the length below which ridges count as zero (m);
    ``allowed(xy)`` says which new positions are acceptable (default: any inside the
    domain); faces shorter than ``short`` x the smaller size of their sites are collapsed.
    """

    domain: Domain
    size: np.ndarray
    movable: np.ndarray
    tol: float
    allowed: Callable[[np.ndarray], np.ndarray] | None = None
    short: float = SHORT


@dataclass(frozen=True, eq=False)
class _Vertices:
    """The Voronoi vertices with those joined by zero-length ridges made one (co-circular sites):
    ``xy`` of each group, the group at either end of every ridge (``ga``, ``gb``) and
    ``sites_of(g)``, the sites of group g (for the groups looked at)."""

    xy: np.ndarray
    ga: np.ndarray
    gb: np.ndarray
    sites_of: Callable[[int], np.ndarray]


def collapse_moves(
    ridges: Ridges,
    sites: np.ndarray,
    rules: MoveRules,
    state: Collapse,
    focus: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, Collapse]:
    """Sites to move and their new positions (local frame) that collapse the short faces, and
    the state after this round.

    ``ridges``: the ridges of the Voronoi diagram of ``sites``; ``rules``: the sizes, the
    movable sites and the positions allowed; ``state``: what earlier rounds did; ``focus``
    (mask of ridges, default all): only faces at the vertices of these (and of the faces
    left over last time) are looked at.
    """
    n = sites.shape[0]
    domain, size, short = rules.domain, rules.size, rules.short
    if not rules.movable.any() or ridges.va.size == 0:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 2)), state
    full = ridges
    length = ridges.lengths()
    zero = length <= rules.tol
    full_zero = zero
    if focus is not None:  # only the ridges at the vertices of the focus (and their co-circular groups)
        ridges, length, zero = _around_focus(focus, state, n, ridges, length, zero)
    coords, va, vb, cp, cq = ridges.coords, ridges.va, ridges.vb, ridges.cp, ridges.cq
    nv = coords.shape[0]
    # Vertices joined by zero-length ridges are one vertex (co-circular sites).
    first, label = group_pairs(nv, np.column_stack([va[zero], vb[zero]]))
    gxy = coords[first]
    ga, gb = label[va], label[vb]
    h_ridge = np.minimum(size[cp], size[cq])
    found = _Found(rules.movable)
    # Interior: short ridges with a part inside the domain (or touching it).
    sr = np.flatnonzero(~zero & (length < short * h_ridge) & (ga != gb))
    if sr.size:
        mid = 0.5 * (coords[va[sr]] + coords[vb[sr]])
        sr = sr[domain.covers(mid, float(short * size.max()))]
    # Boundary: vertices within short x size of the boundary (either side); corners: ridges
    # at vertices within reach of the boundary.
    wide = _band(domain, gxy, 1.5 * float(size.max()))
    band = wide.copy()
    band[wide] = _band(domain, gxy[wide], short * float(size.max()))
    need = np.zeros(gxy.shape[0], dtype=bool)
    need[ga[sr]] = need[gb[sr]] = True
    need |= band
    sites_of = _sites_at_vertices(ga, gb, ridges, np.flatnonzero(need[ga] | need[gb]), n, gxy.shape[0])
    groups = _Vertices(gxy, ga, gb, sites_of)
    for r in sr.tolist():  # a few hundred short ridges
        _short_ridge_moves(found, r, ridges, length, groups, sites, domain)
    _boundary_moves(found, np.flatnonzero(band), groups, sites, rules)
    wr = np.flatnonzero((wide[ga] | wide[gb]) & ~zero)
    if wr.size:
        _corner_moves(found, ridges.where(wr), h_ridge[wr], sites, rules)
    if not found.raw:
        involved = _sites_of_features(found.features, set())
        return np.zeros(0, dtype=np.int64), np.zeros((0, 2)), Collapse(state.pins, involved, involved)
    return _chosen_moves(found, (full, full_zero), sites, rules, state)


class _Found:
    """The moves found for the short faces: (site, target circle, feature length, lockset,
    feature id, pin or None) in ``raw``, and the lockset of every short face in ``features``."""

    def __init__(self, movable: np.ndarray) -> None:
        self.movable = movable
        self.raw: list[tuple] = []
        self.features: list[tuple] = []

    def add(self, x: int, circle, feature: float, lock: tuple, pin: tuple | None = None) -> None:
        if not self.features or self.features[-1] is not lock:
            self.features.append(lock)
        if self.movable[x] and circle is not None:
            self.raw.append((int(x), circle, feature, lock, len(self.features) - 1, pin))


def _around_focus(
    focus: np.ndarray, state: Collapse, n: int, ridges: Ridges, length: np.ndarray, zero: np.ndarray
) -> tuple[Ridges, np.ndarray, np.ndarray]:
    """The ridges at the vertices of the ``focus`` ridges and of the sites still pending (and
    their co-circular groups), their vertices renumbered; their lengths and zero-length mask."""
    coords, va, vb, cp, cq = ridges.coords, ridges.va, ridges.vb, ridges.cp, ridges.cq
    if state.pending.size:
        pend = np.zeros(n, dtype=bool)
        pend[state.pending] = True
        focus = focus | pend[cp] | pend[cq]
    vmask = np.zeros(coords.shape[0], dtype=bool)
    vmask[va[focus]] = vmask[vb[focus]] = True
    for _ in range(4):
        z = zero & (vmask[va] | vmask[vb])
        vmask[va[z]] = vmask[vb[z]] = True
    keep = vmask[va] | vmask[vb]
    va, vb, cp, cq, length, zero = (x[keep] for x in (va, vb, cp, cq, length, zero))
    used, inv = np.unique(np.concatenate([va, vb]), return_inverse=True)
    return Ridges(coords[used], inv[: va.size], inv[va.size :], cp, cq), length, zero


def _sites_at_vertices(ga, gb, ridges: Ridges, sel, n: int, ng: int) -> Callable[[int], np.ndarray]:
    """The sites of every (grouped) vertex involved, from the ridges ``sel`` at it."""
    cp, cq = ridges.cp, ridges.cq
    gs_g = np.concatenate([ga[sel], ga[sel], gb[sel], gb[sel]])
    gs_s = np.concatenate([cp[sel], cq[sel], cp[sel], cq[sel]])
    key = np.unique(gs_g * n + gs_s)
    kg, ks = key // n, key % n
    start = np.searchsorted(kg, np.arange(ng + 1))

    def sites_of(g: int) -> np.ndarray:
        return ks[start[g] : start[g + 1]]

    return sites_of


def _short_ridge_moves(
    found: _Found, r: int, ridges: Ridges, length, groups: _Vertices, sites, domain: Domain
) -> None:
    """Moves collapsing the short ridge ``r``: the one site of a vertex not at the other onto the
    other vertex's circle, or a site of the ridge onto the circle of the other three."""
    cp, cq, gxy, sites_of = ridges.cp, ridges.cq, groups.xy, groups.sites_of
    g1, g2 = int(groups.ga[r]), int(groups.gb[r])
    s1, s2 = sites_of(g1), sites_of(g2)
    lock = tuple(np.union1d(s1, s2).tolist())
    only1, only2 = np.setdiff1d(s1, s2), np.setdiff1d(s2, s1)
    for g_at, others in ((g1, only2), (g2, only1)):
        if others.size != 1:  # one site moved onto the circle of the other vertex
            continue
        centre = gxy[g_at]
        found.add(int(others[0]), (centre, float(np.hypot(*(sites[cp[r]] - centre)))), float(length[r]), lock)
    if only1.size == 1 and only2.size == 1:  # or a site of the ridge onto the circle of the other three
        for x, y in ((int(cp[r]), int(cq[r])), (int(cq[r]), int(cp[r]))):
            found.add(
                x,
                _circle(("circle", y, int(only1[0]), int(only2[0])), sites, domain),
                float(length[r]),
                lock,
            )


def _boundary_moves(found: _Found, bnd, groups: _Vertices, sites, rules: MoveRules) -> None:
    """Moves putting a vertex of three sites near the boundary (``bnd``) onto it: one site onto
    the circle, through the other two, centred where their bisector meets the edge (next to a
    corner: only at the corner)."""
    if not bnd.size:
        return
    gxy, sites_of = groups.xy, groups.sites_of
    domain, size, tol, short = rules.domain, rules.size, rules.tol, rules.short
    dist, edge, _ = domain.nearest_boundary(gxy[bnd])
    for g, d, e in zip(bnd.tolist(), dist.tolist(), edge.tolist(), strict=True):
        s = sites_of(g)
        if s.size != 3 or d <= tol or d >= short * float(size[s].min()):
            continue
        lock = tuple(s.tolist())
        nm = domain.num_vertices
        # next to a corner, the vertex must go to the corner (else a piece of boundary between
        # them stays): once a ridge passes through it (the corner case below), a third site moves
        at_corner = float(np.hypot(*(domain.xy[[e, (e + 1) % nm]] - gxy[g]).T).min()) < short * float(
            size[s].min()
        )
        for m in range(3):  # the third site moves; the bisector of the other two meets the edge at X
            p, q, x = int(s[(m + 1) % 3]), int(s[(m + 2) % 3]), int(s[m])
            for ee in (int(e), (int(e) - 1) % nm, (int(e) + 1) % nm):  # near a corner: either edge
                pin = _edge_pin(p, q, ee, sites, domain, tol)
                if pin is not None and (pin[0] == "corner" or not at_corner):
                    found.add(x, _circle(pin, sites, domain), d, lock, pin)


def _corner_moves(found: _Found, near: Ridges, h_ridge, sites, rules: MoveRules) -> None:
    """Moves for the ridges ``near`` the boundary (``h_ridge``: the smaller size of their sites)
    passing close to a corner of the domain: through the corner (a site onto the circle
    centred on it through the other), or, at a re-entrant corner, off it."""
    domain, size, tol, short = rules.domain, rules.size, rules.tol, rules.short
    cp, cq = near.cp, near.cq
    corners = domain.xy
    kt = cKDTree(corners)
    a, b = near.coords[near.va], near.coords[near.vb]
    best = np.full(cp.size, np.inf)
    which = np.zeros(cp.size, dtype=np.int64)
    for pt in (a, b, 0.5 * (a + b)):
        _, k = kt.query(pt)
        d = _point_segment(corners[k], a, b)
        better = d < best
        best[better], which[better] = d[better], k[better]
    reflex = domain.reflex
    hit = np.flatnonzero(((best > tol) | reflex[which]) & (best < short * h_ridge))
    for i in hit.tolist():
        p, q = int(cp[i]), int(cq[i])
        k = corners[which[i]]
        if reflex[which[i]]:  # push the ridge off a re-entrant corner (see _push_off)
            for x, y in ((p, q), (q, p)):
                margin = short * float(min(size[x], size[y]))
                found.add(x, _push_off(k, sites[x], sites[y], margin), max(float(best[i]), margin), (p, q))
            continue
        if abs(np.hypot(*(sites[p] - k)) - np.hypot(*(sites[q] - k))) <= tol:
            continue  # their bisector passes through the corner already (the ridge ends short of it)
        for x, y in ((p, q), (q, p)):
            pin = ("corner", int(which[i]), y)
            found.add(x, _circle(pin, sites, domain), float(best[i]), (p, q), pin)


def _chosen_moves(
    found: _Found, full: tuple[Ridges, np.ndarray], sites, rules: MoveRules, state: Collapse
) -> tuple[np.ndarray, np.ndarray, Collapse]:
    """The moves made: each site onto its circle (or where it meets a circle the site is on
    already), smallest moves first, inside the domain and ``allowed``, at most one per short
    face and none touching the sites of a face already collapsed; the state after them.
    ``full``: all the ridges and which are of zero length."""
    n = sites.shape[0]
    domain, size, tol, short = rules.domain, rules.size, rules.tol, rules.short
    raw, features = found.raw, found.features
    pins = _pins(np.unique([c[0] for c in raw]), full, sites, domain, state, tol)
    cand = []
    for x, circle, feature, lock, fid, pin in raw:
        on = [c for c in pins.get(x, []) if np.hypot(*(c[0] - circle[0])) > 1e3 * tol]
        if len(on) >= 2:
            continue
        new = _project(circle, sites[x]) if not on else _intersection(on[0], circle, sites[x])
        if new is None:
            continue
        moved = float(np.hypot(*(new - sites[x])))
        if moved <= tol or moved > REACH * short * float(size[x]) or moved > 4.0 * feature:
            continue  # (a site already on its circle: the short face has another cause)
        cand.append((moved, x, new, lock, fid, pin))
    if not cand:
        involved = _sites_of_features(features, set())
        return np.zeros(0, dtype=np.int64), np.zeros((0, 2)), Collapse(state.pins, involved, involved)
    cand.sort(key=lambda c: (c[0], c[1]))
    xy = np.array([c[2] for c in cand])
    ok = domain.inside(xy)
    if rules.allowed is not None:
        ok &= rules.allowed(xy)
    locked = np.zeros(n, dtype=bool)
    idx, new = [], []
    fixed: set[int] = set()
    new_pins = dict(state.pins)
    for k, (_, x, p, lock, fid, pin) in enumerate(cand):
        if not ok[k] or locked[x] or locked[list(lock)].any():
            continue
        locked[list(lock)] = True
        locked[x] = True
        idx.append(x)
        new.append(p)
        fixed.add(fid)
        if pin is not None:
            new_pins[x] = (*new_pins.get(x, ()), pin)
    after = Collapse(new_pins, _sites_of_features(features, fixed), _sites_of_features(features, set()))
    if not idx:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 2)), after
    return np.asarray(idx, dtype=np.int64), np.asarray(new), after


def _pins(
    xs, full: tuple[Ridges, np.ndarray], sites, domain: Domain, state: Collapse, tol: float
) -> dict[int, list]:
    """The exact circles each site of ``xs`` lies on, (centre, radius) each: its degenerate
    vertices (shared by four or more cells: one vertex with four or more sites, as the
    squares of a lattice, or vertices joined by a zero-length ridge) and the boundary
    points it was put on before."""
    ridges, zero = full
    coords, va, vb, cp, cq = ridges.coords, ridges.va, ridges.vb, ridges.cp, ridges.cq
    n = sites.shape[0]
    want = np.zeros(n, dtype=bool)
    want[xs] = True
    rx = np.flatnonzero(want[cp] | want[cq])
    vmask = np.zeros(coords.shape[0], dtype=bool)
    vmask[va[rx]] = vmask[vb[rx]] = True
    rv = np.flatnonzero(vmask[va] | vmask[vb])
    pv = np.concatenate([va[rv], va[rv], vb[rv], vb[rv]])
    ps = np.concatenate([cp[rv], cq[rv], cp[rv], cq[rv]])
    key = np.unique(pv * n + ps)
    count = np.bincount(key // n, minlength=coords.shape[0])
    degenerate = count >= 4
    degenerate[va[zero]] = degenerate[vb[zero]] = True
    out: dict[int, list] = {}
    for s_col in (cp, cq):
        r = rx[want[s_col[rx]]]
        for v_col in (va, vb):
            v = v_col[r]
            z = degenerate[v]
            for x, vv in zip(s_col[r[z]].tolist(), v[z].tolist(), strict=True):
                out.setdefault(x, []).append(coords[vv])
    pins: dict[int, list] = {}
    for x, centres in out.items():
        uniq: list[np.ndarray] = []
        for c in centres:
            if all(np.hypot(*(c - u)) > 1e3 * tol for u in uniq):
                uniq.append(c)
        pins[x] = [(c, float(np.hypot(*(sites[x] - c)))) for c in uniq]
    for x in xs.tolist():
        for pin in state.pins.get(x, ()):
            circle = _circle(pin, sites, domain)
            if circle is not None and all(np.hypot(*(circle[0] - c[0])) > 1e3 * tol for c in pins.get(x, [])):
                pins.setdefault(x, []).append(circle)
    return pins


def _push_off(corner: np.ndarray, x: np.ndarray, y: np.ndarray, margin: float) -> tuple[np.ndarray, float]:
    """The circle about a re-entrant corner that site x moves onto so that its bisector with y
    passes about ``margin`` (m) from the corner, the corner staying in the cell it is nearer to.

    A ridge through a re-entrant corner cuts the cell on the side of the corner's outside
    wedge in two pieces touching at the corner (and a ridge that close leaves tiny faces):
    unlike at a convex corner, the degeneracy is not made exact but avoided.
    """
    dx = float(np.hypot(*(x - corner)))
    dy = float(np.hypot(*(y - corner)))
    return corner, (dy - 2.0 * margin if dx <= dy else dy + 2.0 * margin)


def _sites_of_features(features: list[tuple], fixed: set[int]) -> np.ndarray:
    rest = [f for k, f in enumerate(features) if k not in fixed]
    if not rest:
        return np.zeros(0, dtype=np.int64)
    return np.unique(np.concatenate([np.asarray(f, dtype=np.int64) for f in rest]))


def _edge_pin(p: int, q: int, e: int, sites: np.ndarray, domain: Domain, tol: float) -> tuple | None:
    """Where the bisector of sites p and q meets boundary edge e: ``("edge", p, q, e)``, or
    ``("corner", k, p)`` if that is (within ``tol``) the edge's corner k; None if it misses."""
    a, b = domain.edge_a[e], domain.edge_vec[e]
    w = sites[q] - sites[p]
    den = float(b[0] * w[0] + b[1] * w[1])
    if den == 0.0:
        return None
    m = 0.5 * (sites[p] + sites[q]) - a
    t = float(m[0] * w[0] + m[1] * w[1]) / den
    eps = tol / float(domain.edge_len[e])
    if t < -eps or t > 1 + eps:
        return None
    if t <= eps:
        return ("corner", e, p)
    if t >= 1 - eps:
        return ("corner", (e + 1) % domain.num_vertices, p)
    return ("edge", p, q, e)


def _circle(con: tuple, sites: np.ndarray, domain: Domain) -> tuple[np.ndarray, float] | None:
    """(centre, radius) of a constraint, from the current sites."""
    kind = con[0]
    if kind == "circle":
        a, b, c = sites[con[1]], sites[con[2]], sites[con[3]]
        u, v = b - a, c - a
        d = 2.0 * (u[0] * v[1] - u[1] * v[0])
        if d == 0.0:
            return None
        uu, vv = u[0] * u[0] + u[1] * u[1], v[0] * v[0] + v[1] * v[1]
        centre = a + np.array([v[1] * uu - u[1] * vv, u[0] * vv - v[0] * uu]) / d
        return centre, float(np.hypot(*(a - centre)))
    if kind == "edge":
        p, q, e = sites[con[1]], sites[con[2]], con[3]
        a, b = domain.edge_a[e], domain.edge_vec[e]
        w = q - p
        den = float(b[0] * w[0] + b[1] * w[1])
        if den == 0.0:
            return None
        m = 0.5 * (p + q) - a
        t = float(m[0] * w[0] + m[1] * w[1]) / den
        if not (1e-9 < t < 1 - 1e-9):  # off the edge: the corner case handles it
            return None
        centre = a + t * b
        return centre, float(np.hypot(*(p - centre)))
    centre = domain.xy[con[1]]
    return centre, float(np.hypot(*(sites[con[2]] - centre)))


def _project(circle: tuple[np.ndarray, float], x: np.ndarray) -> np.ndarray | None:
    centre, radius = circle
    rel = x - centre
    dist = float(np.hypot(*rel))
    return None if dist == 0.0 else centre + rel * (radius / dist)


def _intersection(c1: tuple[np.ndarray, float], c2: tuple[np.ndarray, float], x: np.ndarray):
    """The intersection of two circles nearer to x, or None."""
    (p1, r1), (p2, r2) = c1, c2
    dv = p2 - p1
    d = float(np.hypot(*dv))
    if d == 0.0 or d > r1 + r2 or d < abs(r1 - r2):
        return None
    a = (d * d + r1 * r1 - r2 * r2) / (2 * d)
    h = np.sqrt(max(r1 * r1 - a * a, 0.0))
    u = dv / d
    base = p1 + a * u
    nrm = np.array([-u[1], u[0]])
    pts = (base + h * nrm, base - h * nrm)
    return min(pts, key=lambda p: float(np.hypot(*(p - x))))


def _band(domain: Domain, xy: np.ndarray, width: float) -> np.ndarray:
    """Points within ``width`` of the boundary, either side (a superset is fine)."""
    out = ~shapely.contains_xy(domain.inner_buffer(width), xy[:, 0], xy[:, 1])
    k = np.flatnonzero(out)
    if k.size:
        outer = domain.polygon.buffer(1.02 * width, quad_segs=4)
        out[k] = shapely.contains_xy(outer, xy[k, 0], xy[k, 1])
    return out


def _point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ab = b - a
    den = (ab * ab).sum(axis=1)
    t = np.clip(((p - a) * ab).sum(axis=1) / np.where(den > 0, den, 1.0), 0.0, 1.0)
    return np.linalg.norm(p - (a + t[:, None] * ab), axis=1)
