"""Acute wedges at fault nodes: rows of shared sites between traces, or a trace and the boundary.

Where two fault arms leave a node at a small angle phi (a V, an acute X, T or Y, a
sharply kinked trace), or a fault meets the domain's boundary at a shallow angle, the
wedge between them is narrower than two rows of mirrored sites near the node: at a
distance s it is only about s phi wide, while mirrored sites stand off their trace by a
fixed fraction of the step. Halving the steps does not help (the configuration is the
same at every scale), so the wedge gets a construction of its own, exact and with no
refinement:

* **Ray and rungs.** The sites of the wedge lie on a *ray* from the node inside it
  (its bisector for a single wedge). Lines perpendicular to the ray at distances
  r_0 < r_1 < ... < r_K from the node, the *rungs*, cut both sides; the steps along
  the sides are the pieces between consecutive rungs (the first from the node), so
  the rung points are circle centres on the traces.
* **Shared sites.** One site ``q_k`` on the ray half a step before rung k serves both
  sides: q_{k+1} is q_k reflected across rung k (the steps after the first are equal),
  so every rung is the perpendicular bisector of q_k and q_{k+1}. Its partners across
  the traces are its mirror images (none across the boundary). The cell of q_k is the
  strip between its rungs: its faces on the traces are the steps, exactly.
* **Circles.** Every rung point is equidistant from q_k, q_{k+1} and their mirrors,
  and the node from q_0 and its mirrors: these distances are the circle radii, and
  the circles are empty (the sites farther along the ray are farther away, and a site
  is nearer to its own side's points than its mirror is).
* **Fans.** At a node inside the domain with an acute gap, all its arms form one
  *fan* (a splay of faults, an acute X, T or Y, a V; at a node on the boundary, a run
  of consecutive acute gaps between faults, or a gap between a fault and the boundary).
  Every side gets its own rows, the mirror images of each other across it, on the rays
  at its *tilt* t_j either side of it: half the narrower gap next to it (at most 20
  degrees). In every gap the tilts of its two sides add up to at most the gap, so their
  rows keep their order; a gap both of whose sides take half of it holds one row on its
  bisector, shared by both (a single wedge: its bisector, as above). There is no chain
  of mirror images around the fan (a row is shared only where both sides want it), so
  any gaps at any angles fit.
* **Common rungs.** All rows of the wedges at a node use the same rungs, so every row's
  sites lie at the same distances t_0 < t_1 < ... from the node. That keeps every
  circle empty: the circle at side j's rung k holds q_k and q_{k+1} of its own row (at
  angle t_j from the side), so it holds no point at a distance outside (t_k, t_{k+1})
  from the node at that angle, nor at any larger angle from the side; every other
  row's sites are at those distances and at least t_j from side j.
* **Transition.** A side leaves the rows at the first rung where its own rows stand
  ``SPLIT / 2`` (0.65) of a ray step off it and, in a gap holding two rows, the other
  row stands ``FAR`` (1.2) ray steps off it: beyond it the side carries ordinary
  mirrored pairs (at most about 0.6 of a step off the trace, at a step kept until all
  the fan's rows end), which stay out of the other rows' circles and keep their own
  circles clear of those rows. The two sides of a shared row leave together; every
  other row ends where its side leaves. A side's circles thus reach at most about 1.3
  ray steps, whatever the other gaps are (a single chain of rows mirrored round the
  whole fan at one angle, as before, made the inner arms' circles several steps wide
  where the gaps differed, and refused 144 of the 500 splays of the property test
  ``tests/voronoi/test_pebi_splays.py``).

The first rung is moved out (up to ``MAX_STRETCH`` steps) where a wedge is so narrow
that the triangular first cell would be smaller than ``TIP_AREA`` step². Rungs are
fitted into the arms (a short arm gets proportionally shorter steps). Lengths in metres,
angles in radians, local frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..planar import cross2
from ..reproducible import arctan2
from .domain import Domain

ACUTE = np.radians(40.0)  # wedges narrower than this get a row of shared sites
SPLIT = 1.3  # the rows end where every wedge is this many steps wide
TIP_AREA = 0.125  # smallest area of the first (triangular) cell, x step^2
MAX_STRETCH = 4.0  # the first rung at most this many steps from the node
MAX_RUNGS = 200  # a wedge under about 0.4 degrees: the row ends before it is SPLIT steps wide
FAR = 1.2  # a side leaves two rows in a gap once the other row is this many ray steps off it


@dataclass
class Wedge:
    """An acute wedge, or a fan of consecutive ones, at network node ``node``.

    ``sides`` (n + 1 edge ids, -1 for the domain's boundary, which can only be an outer
    side) and ``dirs`` (n + 1, 2) unit vectors from the node, in counter-clockwise order;
    gap i lies between sides i and i + 1, ``gaps`` (n,) radians. ``beyond`` (2,): the gaps
    (radians) next to the first and the last side outside the fan (inf: none, or the
    boundary's); ``closed``: the fan goes round the node, and ``beyond`` is the one gap left
    out between its last and its first side. ``tilt`` (n + 1,) the angle between each side
    and its rows; ``shared`` (n,) which gaps hold one row (their sides' tilts are half the
    gap) rather than two. ``rungs`` (K + 1,) distances (m) of the rungs from the node along
    the rows, equally spaced after the first, set by :func:`plan`.
    """

    node: int
    sides: list[int]
    dirs: np.ndarray
    gaps: np.ndarray
    beyond: tuple[float, float] = (np.inf, np.inf)
    closed: bool = False
    tilt: np.ndarray | None = None
    shared: np.ndarray | None = None
    rungs: np.ndarray | None = None
    side_count: np.ndarray | None = None  # (n + 1,) rungs each side keeps
    room: np.ndarray | None = None  # (n + 1,) length (m) along each side the rungs must fit into

    @property
    def phi(self) -> float:
        """The narrowest gap (radians)."""
        return float(self.gaps.min())

    @property
    def acute(self) -> np.ndarray:
        """(n,) which gaps are acute (a fan of all the arms at a node has wider ones too)."""
        return self.gaps < ACUTE

    @property
    def rows(self) -> int:
        """How many rows of sites the acute gaps hold (one per shared gap, two per other gap)."""
        return int(2 * self.acute.sum() - (self.shared & self.acute).sum())

    @property
    def ray_step(self) -> float:
        r = self.rungs
        return float(r[1] - r[0]) if r.size > 1 else float(r[0])

    def arms(self) -> list[tuple[int, int]]:
        """(edge, side index) of the fault sides."""
        return [(e, j) for j, e in enumerate(self.sides) if e >= 0]

    def side_rungs(self, j: int) -> np.ndarray:
        """Distances (m) of the rung points from the node along side j (those it keeps)."""
        return self.rungs[: self.side_count[j]] / np.cos(self.tilt[j])

    def rows_end(self, j: int) -> float:
        """Distance (m) along side j to the last rung of the fan (where its rows all end)."""
        return float(self.rungs[-1] / np.cos(self.tilt[j]))

    @property
    def step(self) -> float:
        """The longest step along a side after the first (m): the wedge cells' target size."""
        return self.ray_step / float(np.cos(self.tilt).min())


def find_wedges(
    nodes: np.ndarray,
    edge_a: np.ndarray,
    edge_b: np.ndarray,
    candidates: np.ndarray,
    boundary_rays: dict[int, list[float]],
    domain: Domain,
) -> list[Wedge]:
    """The acute wedges and fans at the ``candidates`` nodes, their tilts chosen.

    ``boundary_rays[v]``: directions (angles) along the boundary from boundary node v;
    a gap between a fault arm and a boundary ray counts when it lies inside the domain.
    """
    found: list[Wedge] = []
    for v in candidates.tolist():  # loop over constrained fault nodes
        arms = np.concatenate([np.flatnonzero(edge_a == v), np.flatnonzero(edge_b == v)])
        far = np.concatenate([edge_b[edge_a == v], edge_a[edge_b == v]])
        d = nodes[far] - nodes[v]
        ang = np.mod(arctan2(d[:, 1], d[:, 0]), 2 * np.pi)
        unit = d / np.hypot(d[:, 0], d[:, 1])[:, None]
        rays = [(float(a), int(e), unit[k]) for k, (a, e) in enumerate(zip(ang, arms, strict=True))]
        for b in boundary_rays.get(v, []):
            rays.append((float(np.mod(b, 2 * np.pi)), -1, np.array([np.cos(b), np.sin(b)])))
        if len(rays) < 2:
            continue
        rays.sort(key=lambda r: (r[0], r[1]))
        nr = len(rays)
        acute = np.zeros(nr, dtype=bool)  # gap g lies between rays g and g + 1
        gap = np.zeros(nr)
        for g in range(nr):
            (a0, e0, _), (a1, e1, _) = rays[g], rays[(g + 1) % nr]
            gap[g] = float(np.mod(a1 - a0, 2 * np.pi))
            if not (0.0 < gap[g] < ACUTE) or (e0 < 0 and e1 < 0):
                continue
            if e0 < 0 or e1 < 0:  # a fault and the boundary: the gap must be inside the domain
                mid = a0 + 0.5 * gap[g]
                probe = nodes[v] + 1e-6 * domain.diameter * np.array([np.cos(mid), np.sin(mid)])
                if not domain.inside(probe[None, :])[0]:
                    continue
            acute[g] = True
        if acute.any() and all(r[1] >= 0 for r in rays):  # a node inside: one fan of all its arms
            wide = int(np.argmax(gap))
            run = [(wide + 1 + k) % nr for k in range(nr - 1)]
            idx = [*run, wide]
            w = Wedge(v, [rays[i][1] for i in idx], np.array([rays[i][2] for i in idx]), gap[run])
            w.beyond, w.closed = (float(gap[wide]), float(gap[wide])), True
            _aim(w)
            found.append(w)
            continue
        here: list[Wedge] = []
        for run in _runs(acute, rays):  # on the boundary: consecutive acute gaps sharing fault arms
            idx = [*run, (run[-1] + 1) % nr]
            before, after = (run[0] - 1) % nr, (run[-1] + 1) % nr
            beyond = tuple(
                np.inf if min(rays[g][1], rays[(g + 1) % nr][1]) < 0 or g in run else float(gap[g])
                for g in (before, after)
            )
            w = Wedge(v, [rays[i][1] for i in idx], np.array([rays[i][2] for i in idx]), gap[run])
            w.beyond = beyond
            _aim(w)
            here.append(w)
        found += _one_per_arm(here)
    return found


def _one_per_arm(wedges: list[Wedge]) -> list[Wedge]:
    """The wedges at one node such that every fault arm is in one at most, the narrowest first."""
    used: set[int] = set()
    kept = []
    for w in sorted(wedges, key=lambda w: w.phi):
        arms = {e for e in w.sides if e >= 0}
        if not arms & used:
            used |= arms
            kept.append(w)
    return kept


def _runs(acute: np.ndarray, rays: list) -> list[list[int]]:
    """Maximal runs of consecutive acute gaps (indices) around a node on the boundary between fault
    arms (fans); a gap between a fault and the boundary is a run of its own (the boundary needs no
    mirror sites, so such a gap never has to share its fault arm). The gap between the node's two
    boundary rays is never acute, so no run closes around the node."""
    nr = acute.size
    out: list[list[int]] = []
    first = next((g for g in range(nr) if not acute[g]), None)
    if first is None:
        return out
    run: list[int] = []
    for k in range(1, nr + 1):  # walk once around from a gap that is not acute
        g = (first + k) % nr
        boundary = rays[g][1] < 0 or rays[(g + 1) % nr][1] < 0
        if acute[g] and not boundary and run:
            run.append(g)
            continue
        if run:
            out.append(run)
        run = [g] if acute[g] else []
        if boundary and run:
            out.append(run)
            run = []
    if run:
        out.append(run)
    return out


def _aim(w: Wedge) -> None:
    """Set the tilt of every side: half the narrower gap next to it (inside the fan or just beyond
    it), so that in every gap the rows of its two sides keep their order (tilts adding up to at
    most the gap); a gap both of whose sides take half of it holds one shared row."""
    before = np.concatenate([[w.beyond[0]], w.gaps])
    after = np.concatenate([w.gaps, [w.beyond[1]]])
    w.tilt = np.minimum(0.5 * np.minimum(before, after), 0.5 * ACUTE)
    half = 0.5 * w.gaps
    w.shared = (w.tilt[:-1] == half) & (w.tilt[1:] == half)


def _two_row_gaps(w: Wedge) -> list[tuple[int, int, float]]:
    """(side, other side, angle from the side to the other side's row) for the gaps holding two
    rows: those of the fan that are not shared, and the gap left out of a closed fan."""
    out = []
    for i in np.flatnonzero(~w.shared).tolist():
        out += [(i, i + 1, float(w.gaps[i] - w.tilt[i + 1])), (i + 1, i, float(w.gaps[i] - w.tilt[i]))]
    if w.closed:
        n = w.gaps.size
        out += [(n, 0, float(w.beyond[1] - w.tilt[0])), (0, n, float(w.beyond[0] - w.tilt[n]))]
    return out


def rung_count(w: Wedge) -> tuple[np.ndarray, float]:
    """Rungs kept by every side and the first rung's distance in ray steps (stretch) of a wedge.

    A side may leave the rows at the first rung where its own rows stand ``SPLIT / 2`` of its
    step off it (r sin(tilt) >= SPLIT / 2 ray steps) and the other row of a gap holding two
    stands ``FAR`` ray steps off it: its ordinary mirrored sites beyond (at most about 0.6 of a
    step off the trace) then stay out of that row's circles, and the row's sites out of its own.
    The sides of a shared row leave together; every other row ends with its side.
    """
    n = w.gaps.size
    tilt = w.tilt
    two = _two_row_gaps(w)
    # rung length per unit ray distance of every row's first cell: to the far side, or the mid-line
    spread = []
    for i in np.flatnonzero(w.shared).tolist():
        far = w.gaps[i] - tilt[i]
        spread.append(float(np.sin(tilt[i]) / np.cos(tilt[i]) + np.sin(far) / np.cos(far)))
    for i, _, beta in two:
        half = min(0.5 * (beta - tilt[i]), 0.25 * np.pi)
        spread.append(float(np.sin(tilt[i]) / np.cos(tilt[i]) + np.sin(half) / np.cos(half)))
    cos2 = float(np.cos(tilt).min()) ** 2
    stretch = float(np.clip(np.sqrt(2.0 * TIP_AREA / (min(spread) * cos2)), 1.0, MAX_STRETCH))
    need = 0.5 * SPLIT / np.sin(tilt)  # ray distance, in ray steps, to leave
    for i, _, beta in two:
        need[i] = max(need[i], FAR / np.sin(min(beta, 0.5 * np.pi)))
    need = np.minimum(need, MAX_RUNGS)
    count = 1 + np.maximum(0, np.ceil(need - stretch - 1e-9).astype(np.int64))
    for _ in range(n):  # the sides of a shared row leave together (a handful of gaps)
        for i in np.flatnonzero(w.shared).tolist():
            count[i] = count[i + 1] = max(count[i], count[i + 1])
    return count, stretch


def plan(w: Wedge, step: float, room: np.ndarray) -> None:
    """Rungs for a target step (m) along the sides, fitted into ``room`` (m) along each side.

    Every side must hold the rungs and one ordinary step beyond them.
    """
    count, stretch = rung_count(w)
    w.side_count, w.room = count, room
    ray_step = min(step * float(np.cos(w.tilt).min()), _fitted_step(w, stretch))
    w.rungs = ray_step * (stretch + np.arange(int(count.max()), dtype=np.float64))


def _fitted_step(w: Wedge, stretch: float) -> float:
    """The largest ray step (m) at which every side's rungs and one step beyond fit into its room."""
    return float((w.room * np.cos(w.tilt) / (stretch + w.side_count)).min())


def share_rungs(wedges: list[Wedge]) -> None:
    """Give the planned wedges at one node the same rungs (the smallest ray step, the largest
    first rung): every row's sites then lie at the same distances from the node, which keeps
    each side's circles clear of the rows of the other wedges (see the module's docstring)."""
    first = max(float(w.rungs[0] / w.ray_step) for w in wedges)
    ray_step = min(min(w.ray_step, _fitted_step(w, first)) for w in wedges)
    for w in wedges:
        w.rungs = ray_step * (first + np.arange(int(w.side_count.max()), dtype=np.float64))


def node_radius(w: Wedge) -> float:
    """Distance (m) from the node to the first shared sites: the node's circle radius."""
    return float(w.rungs[0] - 0.5 * w.ray_step)


def scale_to_radius(w: Wedge, radius: float) -> None:
    """Scale the rungs so that the node's circle has the given radius (m); the rows of the wedges
    at one node scaled alike keep their common distances from it."""
    w.rungs = w.rungs * (radius / node_radius(w))


@dataclass
class WedgeSites:
    """Sites and circles of a wedge or fan (local frame)."""

    own: np.ndarray  # (n + 1, K + 1, 2) every side's row in the gap its circles were measured in
    mirror: np.ndarray  # (n + 1, K + 1, 2) its mirror image across the side (nan: the boundary)
    radius_rungs: np.ndarray  # (n + 1, K + 1) circle radius at the rung points of every side
    radius_node: float


def wedge_sites(w: Wedge, node: np.ndarray) -> WedgeSites:
    """The rows of a planned wedge or fan, their mirror images across the sides and the circle radii.

    Every side's rows lie on the rays at its tilt either side of it, a shared row on the gap's
    bisector; a row's site ``q_k`` lies half a step before rung k along its ray.
    """
    t = w.rungs - 0.5 * w.ray_step
    n = w.gaps.size
    k1 = w.rungs.size
    ccw = np.full((n + 1, k1, 2), np.nan)  # the row counter-clockwise of each side
    cw = np.full((n + 1, k1, 2), np.nan)
    primary_cw = np.zeros(n + 1, dtype=bool)
    for i in np.flatnonzero(w.shared).tolist():  # one row on the bisector, for both sides
        ccw[i] = _row(node, w.dirs[i], w.tilt[i], t)
        cw[i + 1] = ccw[i]
        primary_cw[i + 1] = True
    for j in range(n + 1):
        if w.sides[j] < 0:
            continue
        if np.isnan(ccw[j, 0, 0]) and not primary_cw[j]:
            ccw[j] = _row(node, w.dirs[j], w.tilt[j], t)
        if np.isnan(ccw[j, 0, 0]):
            ccw[j] = _reflect(cw[j], node, w.dirs[j])
        elif np.isnan(cw[j, 0, 0]):
            cw[j] = _reflect(ccw[j], node, w.dirs[j])
    own = np.where(primary_cw[:, None, None], cw, ccw)
    mirror = np.where(primary_cw[:, None, None], ccw, cw)
    for j in range(n + 1):  # the boundary side of a shared row has no mirror image
        if w.sides[j] < 0:
            own[j] = ccw[j] if j == 0 else cw[j]
            mirror[j] = np.nan
    radius = np.empty((n + 1, k1))
    for j in range(n + 1):  # every side: distance from its rung points to its row
        rung = node + (w.rungs / np.cos(w.tilt[j]))[:, None] * w.dirs[j]
        rel = rung - own[j]
        radius[j] = np.hypot(rel[:, 0], rel[:, 1])
    return WedgeSites(own, mirror, radius, node_radius(w))


def _row(node: np.ndarray, unit: np.ndarray, angle: float, t: np.ndarray) -> np.ndarray:
    """Points at distances t from ``node`` on the ray ``unit`` turned counter-clockwise by ``angle``."""
    c, s = np.cos(angle), np.sin(angle)
    ray = np.array([c * unit[0] - s * unit[1], s * unit[0] + c * unit[1]])
    return node + t[:, None] * ray[None, :]


def _reflect(p: np.ndarray, origin: np.ndarray, unit: np.ndarray) -> np.ndarray:
    """Points p reflected across the line through ``origin`` along ``unit``."""
    rel = p - origin
    along = rel[:, 0] * unit[0] + rel[:, 1] * unit[1]
    return origin + 2.0 * along[:, None] * unit[None, :] - rel


def side_of(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """+1 where p lies left of the directed segment a -> b, -1 right (0 on it)."""
    return np.sign(cross2(b - a, p - a))
