"""Acute wedges at fault nodes: one row of shared sites between two traces, or a trace and the boundary.

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
* **Fans.** Consecutive acute wedges sharing an arm (a splay of faults, three
  faults within a few tens of degrees) form one *fan*: the arm's step is shared, so
  the sites on either side of it are mirror images. That holds when the two wedges'
  rays are mirror images across the arm, with the same rungs. One angle fixes all the
  rays; it is chosen for the circles on the inner arms: the rows run until the side
  nearest its ray (tilt t_min) stands SPLIT / 2 ray steps off it, and an inner arm
  keeps every rung, so at the end its circles reach about t_inner / t_min times that
  far. The rays make the largest such ratio as small as the fan allows, then
  t_min as large as it can be (a single wedge: its bisector; a narrow gap beside a
  wide one: the narrow gap's bisector, the wide gap's ray close to the shared arm). A
  fan whose ratio stays above 1 / MIN_QUALITY is split at its widest gap.
* **Transition.** A side leaves the shared rows at the first rung where it stands
  ``SPLIT / 2`` (0.65) of its step off the ray next to it: beyond it the side carries
  ordinary mirrored pairs, whose sites (at most about half a step off the trace) stay
  on their own side of the ray and out of the other arms' circles. The rows go on until
  every side of the fan may leave; its inner sides stay till then, its outer sides leave
  as soon as they may.

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
MIN_QUALITY = 0.3  # a fan whose inner arms' circles would reach over 3.3 times as far (relative) is split


@dataclass
class Wedge:
    """An acute wedge, or a fan of consecutive ones, at network node ``node``.

    ``sides`` (n + 1 edge ids, -1 for the domain's boundary, which can only be an outer
    side) and ``dirs`` (n + 1, 2) unit vectors from the node, in counter-clockwise order;
    gap i lies between sides i and i + 1, ``gaps`` (n,) radians. ``rays`` (n, 2) unit
    vectors of the sites' rays; ``tilt`` (n + 1,) the angle between each side and the ray
    next to it. ``rungs`` (K + 1,) distances (m) of the rungs from the node along the
    rays, equally spaced after the first, set by :func:`plan`.
    """

    node: int
    sides: list[int]
    dirs: np.ndarray
    gaps: np.ndarray
    rays: np.ndarray | None = None
    tilt: np.ndarray | None = None
    rungs: np.ndarray | None = None
    side_count: np.ndarray | None = None  # (n + 1,) rungs each side keeps (an outer side may leave early)

    @property
    def phi(self) -> float:
        """The narrowest gap (radians)."""
        return float(self.gaps.min())

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
    """The acute wedges and fans at the ``candidates`` nodes, their rays chosen.

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
        here: list[Wedge] = []
        for run in _runs(acute, rays):  # consecutive acute gaps sharing fault arms: fans
            for part in _fan_parts(gap[run]):
                chosen = [run[k] for k in part]
                idx = [*chosen, (chosen[-1] + 1) % nr]
                w = Wedge(v, [rays[i][1] for i in idx], np.array([rays[i][2] for i in idx]), gap[chosen])
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
    """Maximal runs of consecutive acute gaps (indices) around a node between fault arms (fans),
    never closing around the whole node; a gap between a fault and the boundary is a run of its
    own (the boundary needs no mirror sites, so such a gap never has to share its fault arm)."""
    nr = acute.size
    if acute.all():  # all gaps acute: the widest one is left to the ordinary construction
        start = int(np.argmax([np.mod(rays[(g + 1) % nr][0] - rays[g][0], 2 * np.pi) for g in range(nr)]))
        acute = acute.copy()
        acute[start] = False
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


def _fan_parts(gaps: np.ndarray) -> list[list[int]]:
    """Split a run of acute gaps into fans whose rays reach MIN_QUALITY (:func:`_offsets`):
    the widest gap of a run that cannot is left out (to the ordinary construction)."""
    if gaps.size == 1 or _offsets(gaps)[1] >= MIN_QUALITY:
        return [list(range(gaps.size))]
    cut = int(np.argmax(gaps))
    left = _fan_parts(gaps[:cut]) if cut > 0 else []
    right = [[k + cut + 1 for k in p] for p in _fan_parts(gaps[cut + 1 :])] if cut + 1 < gaps.size else []
    return left + right


def _offsets(gaps: np.ndarray) -> tuple[np.ndarray, float]:
    """Angles of the rays from the first side of their gaps, mirror images across every shared
    side (the ray of gap i + 1 is as far from side i + 1 as the ray of gap i), and their quality
    t_min / (largest inner tilt) (1 without inner sides; -1: no rays inside every gap; angles
    rather than sines, which rank the same way for gaps under 40 degrees, and need no libm).

    Of the rays with the best quality, those with the largest t_min, the smallest angle between
    a side and its ray (for a single gap: its bisector)."""
    x = np.linspace(0.0, 1.0, 401)[1:-1] * gaps[0]
    off = np.empty((gaps.size, x.size))
    off[0] = x
    for i in range(1, gaps.size):  # the mirror condition fixes the next ray
        off[i] = gaps[i - 1] - off[i - 1]
    t_min = np.minimum(off, gaps[:, None] - off).min(axis=0)
    if gaps.size > 1:  # the inner sides' tilts are the offsets of the gaps after them
        quality = np.where(t_min > 0, t_min / np.abs(off[1:]).max(axis=0), -1.0)
    else:
        quality = np.ones(x.size)
    best = int(np.argmax(np.where(quality >= quality.max() - 1e-12, t_min, -np.inf)))
    return off[:, best], float(quality[best])


def _aim(w: Wedge) -> None:
    """Set the rays of a wedge or fan (:func:`_offsets`) and the tilt of every side."""
    off, _ = _offsets(w.gaps)
    n = w.gaps.size
    rays = np.empty((n, 2))
    for i in range(n):  # rotate side i counter-clockwise by the offset
        c, s = np.cos(off[i]), np.sin(off[i])
        d = w.dirs[i]
        rays[i] = (c * d[0] - s * d[1], s * d[0] + c * d[1])
    w.rays = rays
    w.tilt = np.concatenate([off, [w.gaps[-1] - off[-1]]])


def rung_count(w: Wedge) -> tuple[np.ndarray, float]:
    """Rungs kept by every side and the first rung's distance in ray steps (stretch) of a wedge.

    A side may leave the shared rows at the first rung where it stands ``SPLIT / 2``
    of its step off the ray next to it (r sin(tilt) >= SPLIT / 2 ray steps). The inner
    sides of a fan, and so the rows, go on until every side may leave; an outer side
    leaves as soon as it may (a wide gap's far side would otherwise get huge circles).
    """
    off = w.tilt[:-1]
    far = w.gaps - off
    spread = np.sin(off) / np.cos(off) + np.sin(far) / np.cos(far)  # rung length per unit ray distance
    cos2 = float(np.cos(w.tilt).min()) ** 2
    stretch = float(np.clip(np.sqrt(2.0 * TIP_AREA / (float(spread.min()) * cos2)), 1.0, MAX_STRETCH))
    need = np.minimum(0.5 * SPLIT / np.sin(w.tilt), MAX_RUNGS)  # ray distance, in ray steps, to leave
    count = 1 + np.maximum(0, np.ceil(need - stretch - 1e-9).astype(np.int64))
    count[1:-1] = count.max()  # a fan's inner sides keep every rung
    return count, stretch


def plan(w: Wedge, step: float, room: np.ndarray) -> None:
    """Rungs for a target step (m) along the sides, fitted into ``room`` (m) along each side.

    Every side must hold the rungs and one ordinary step beyond them.
    """
    count, stretch = rung_count(w)
    cos = np.cos(w.tilt)
    ray_step = step * float(cos.min())
    ray_step = min(ray_step, float((room * cos / (stretch + count)).min()))
    w.rungs = ray_step * (stretch + np.arange(int(count.max()), dtype=np.float64))
    w.side_count = count


def node_radius(w: Wedge) -> float:
    """Distance (m) from the node to the first shared sites: the node's circle radius."""
    return float(w.rungs[0] - 0.5 * w.ray_step)


def scale_to_radius(w: Wedge, radius: float) -> None:
    """Scale the rungs so that the node's circle has the given radius (several wedges at a node)."""
    w.rungs = w.rungs * (radius / node_radius(w))


@dataclass
class WedgeSites:
    """Sites and circles of a wedge or fan (local frame)."""

    shared: np.ndarray  # (n, K + 1, 2) q_k on the ray of every gap
    mirror_first: np.ndarray | None  # (K + 1, 2) the first gap's q reflected across side 0 (None: boundary)
    mirror_last: np.ndarray | None  # (K + 1, 2) the last gap's q reflected across side n
    radius_rungs: np.ndarray  # (n + 1, K + 1) circle radius at the rung points of every side
    radius_node: float


def wedge_sites(w: Wedge, node: np.ndarray) -> WedgeSites:
    """The shared rows of a planned wedge or fan, the outer mirror images and the circle radii."""
    t = w.rungs - 0.5 * w.ray_step  # q_k half a step before rung k along the ray
    q = node + t[None, :, None] * w.rays[:, None, :]
    n = w.gaps.size
    radius = np.empty((n + 1, w.rungs.size))
    for j in range(n + 1):  # every side: distance from its rung points to the q next to it
        rung = node + (w.rungs / np.cos(w.tilt[j]))[:, None] * w.dirs[j]
        rel = rung - q[min(j, n - 1)]
        radius[j] = np.hypot(rel[:, 0], rel[:, 1])
    first = _reflect(q[0], node, w.dirs[0]) if w.sides[0] >= 0 else None
    last = _reflect(q[-1], node, w.dirs[-1]) if w.sides[-1] >= 0 else None
    return WedgeSites(q, first, last, radius, node_radius(w))


def _reflect(p: np.ndarray, origin: np.ndarray, unit: np.ndarray) -> np.ndarray:
    """Points p reflected across the line through ``origin`` along ``unit``."""
    rel = p - origin
    along = rel[:, 0] * unit[0] + rel[:, 1] * unit[1]
    return origin + 2.0 * along[:, None] * unit[None, :] - rel


def side_of(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """+1 where p lies left of the directed segment a -> b, -1 right (0 on it)."""
    return np.sign(cross2(b - a, p - a))
