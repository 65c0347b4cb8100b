"""Acute wedges at fault nodes: one row of shared sites between two traces, or a trace and the boundary.

Where two fault arms leave a node at a small angle phi (a V, an acute X, T or Y, a
sharply kinked trace), or a fault meets the domain's boundary at a shallow angle, the
wedge between them is narrower than two rows of mirrored sites near the node: at a
distance s it is only about s phi wide, while mirrored sites stand off their trace by a
fixed fraction of the step. Halving the steps does not help (the configuration is the
same at every scale), so the wedge gets a construction of its own, exact and with no
refinement:

* **Rungs.** Points at equal distances s_0 < s_1 < ... < s_K from the node along both
  arms (``c^A_k``, ``c^B_k``) are joined by *rungs*, perpendicular to the wedge's
  bisector. The steps along the arms are the pieces between consecutive rungs (the
  first from the node), so these points are circle centres on the traces.
* **Shared sites.** One site ``q_k`` on the bisector between rung k - 1 (the node for
  k = 0) and rung k serves both arms: q_{k+1} is q_k reflected across rung k, so every
  rung is the perpendicular bisector of q_k and q_{k+1}; q_0 is placed so that all
  later sites lie half way between their rungs. Its partners across the traces are its
  mirror images ``p^A_k``, ``p^B_k`` (none across the boundary). The cell of q_k is the
  trapezoid between its rungs: its faces on the traces are the steps, exactly.
* **Circles.** Every rung point is equidistant from q_k, q_{k+1} and their mirrors,
  and the node from q_0 and its mirrors: these distances are the circle radii, and
  the circles are empty by symmetry (the sites farther along the bisector are
  farther away, and a site is nearer to its own side's points than its mirror is).
* **Transition.** The row ends at the first rung where the wedge is ``SPLIT`` (1.3)
  steps wide: beyond it the arms carry ordinary mirrored pairs, whose sites (at most
  about half a step off the trace) stay on their own side of the bisector and out of
  the other arm's circles.

The first rung is moved out (s_0 up to ``MAX_STRETCH`` steps) where the wedge is so
narrow that the triangular first cell would be smaller than ``TIP_AREA`` step². Rungs
are fitted into the arms (a short arm gets proportionally shorter steps). Lengths in
metres, angles in radians, local frame.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .domain import Domain, _cross2

ACUTE = np.radians(40.0)  # wedges narrower than this get a row of shared sites
SPLIT = 1.3  # the row ends where the wedge is this many steps wide
TIP_AREA = 0.125  # smallest area of the first (triangular) cell, x step^2
MAX_STRETCH = 4.0  # the first rung at most this many steps from the node
MAX_RUNGS = 200  # a wedge under about 0.4 degrees: the row ends before it is SPLIT steps wide


@dataclass
class Wedge:
    """An acute wedge at network node ``node`` between arm ``edge_a`` and ``edge_b``.

    ``edge_b`` is -1 where the second side is the domain's boundary. ``dir_a``,
    ``dir_b``: unit vectors from the node along the two sides, ``phi`` (radians) apart.
    ``rungs`` (K + 1,): distances of the rung points from the node along both sides (m),
    equally spaced after the first, set by :func:`plan`.
    """

    node: int
    edge_a: int
    edge_b: int
    dir_a: np.ndarray
    dir_b: np.ndarray
    phi: float
    rungs: np.ndarray | None = None

    @property
    def bisector(self) -> np.ndarray:
        m = self.dir_a + self.dir_b
        return m / np.hypot(m[0], m[1])

    @property
    def half(self) -> float:
        return 0.5 * self.phi

    def arms(self) -> list[tuple[int, np.ndarray]]:
        """(edge, direction) of the fault arms (one or two)."""
        out = [(self.edge_a, self.dir_a)]
        if self.edge_b >= 0:
            out.append((self.edge_b, self.dir_b))
        return out


def find_wedges(
    nodes: np.ndarray,
    edge_a: np.ndarray,
    edge_b: np.ndarray,
    candidates: np.ndarray,
    boundary_rays: dict[int, list[float]],
    domain: Domain,
) -> list[Wedge]:
    """The acute wedges at the ``candidates`` nodes, each arm in at most one (the narrowest first).

    ``boundary_rays[v]``: directions (angles) along the boundary from boundary node v;
    a gap between a fault arm and a boundary ray counts when it lies inside the domain.
    """
    found: list[Wedge] = []
    for v in candidates.tolist():  # loop over constrained fault nodes
        arms = np.concatenate([np.flatnonzero(edge_a == v), np.flatnonzero(edge_b == v)])
        far = np.concatenate([edge_b[edge_a == v], edge_a[edge_b == v]])
        d = nodes[far] - nodes[v]
        ang = np.mod(np.arctan2(d[:, 1], d[:, 0]), 2 * np.pi)
        unit = d / np.hypot(d[:, 0], d[:, 1])[:, None]
        rays = [(float(a), int(e), unit[k]) for k, (a, e) in enumerate(zip(ang, arms, strict=True))]
        for b in boundary_rays.get(v, []):
            rays.append((float(np.mod(b, 2 * np.pi)), -1, np.array([np.cos(b), np.sin(b)])))
        if len(rays) < 2:
            continue
        rays.sort(key=lambda r: (r[0], r[1]))
        for g in range(len(rays)):
            (a0, e0, ua), (a1, e1, ub) = rays[g], rays[(g + 1) % len(rays)]
            gap = float(np.mod(a1 - a0, 2 * np.pi))
            if not (0.0 < gap < ACUTE) or (e0 < 0 and e1 < 0):
                continue
            if e0 < 0 or e1 < 0:  # a fault and the boundary: the gap must be inside the domain
                mid = a0 + 0.5 * gap
                probe = nodes[v] + 1e-6 * domain.diameter * np.array([np.cos(mid), np.sin(mid)])
                if not domain.inside(probe[None, :])[0]:
                    continue
            if e0 < 0:  # the fault arm first, the boundary second: mirror the wedge's orientation
                found.append(Wedge(v, e1, -1, ub, ua, gap))
            else:
                found.append(Wedge(v, e0, e1, ua, ub, gap))
    found.sort(key=lambda w: w.phi)
    used: set[tuple[int, int]] = set()
    kept = []
    for w in found:  # an arm between two acute wedges joins the narrower one only
        ids = {(e, w.node) for e, _ in w.arms()}
        if ids & used:
            continue
        used |= ids
        kept.append(w)
    return kept


def rung_count(phi: float) -> tuple[int, float]:
    """Number of rungs K + 1 and the first rung's distance in steps (stretch g) for angle phi."""
    stretch = float(np.clip(np.sqrt(2.0 * TIP_AREA / np.sin(phi)), 1.0, MAX_STRETCH))
    width = 2.0 * np.sin(0.5 * phi)  # wedge width per unit distance from the node
    extra = int(np.ceil(min(SPLIT / width, MAX_RUNGS) - stretch - 1e-9))
    return 1 + max(0, extra), stretch


def plan(wedge: Wedge, step: float, room: float) -> None:
    """Rung distances for a target step (m), fitted into ``room`` (m) along the arms.

    The arms must hold the rungs and one ordinary step beyond them.
    """
    n, stretch = rung_count(wedge.phi)
    reach = stretch + n  # (n - 1) steps after the first rung, plus one ordinary step
    step = min(step, room / reach)
    wedge.rungs = step * (stretch + np.arange(n, dtype=np.float64))


def node_radius(wedge: Wedge) -> float:
    """Distance (m) from the node to the first shared site: the node's circle radius."""
    r = wedge.rungs
    step = r[1] - r[0] if r.size > 1 else r[0]
    return (r[0] - 0.5 * step) * np.cos(wedge.half)


def scale_to_radius(wedge: Wedge, radius: float) -> None:
    """Scale the rungs so that the node's circle has the given radius (several wedges at a node)."""
    wedge.rungs = wedge.rungs * (radius / node_radius(wedge))


@dataclass
class WedgeSites:
    """Sites and circles of one wedge (local frame): shared sites, mirrors and rung radii."""

    shared: np.ndarray  # (K + 1, 2) q_k
    mirror_a: np.ndarray  # (K + 1, 2) q_k reflected across arm A
    mirror_b: np.ndarray | None  # (K + 1, 2) across arm B, None at the boundary
    rung_a: np.ndarray  # (K + 1, 2) rung points on A
    rung_b: np.ndarray  # (K + 1, 2) on B (on the boundary for a boundary wedge)
    radius_rungs: np.ndarray  # (K + 1,) circle radius at the rung points
    radius_node: float


def wedge_sites(wedge: Wedge, node: np.ndarray) -> WedgeSites:
    """The shared row of a planned wedge, its mirror images and circle radii."""
    s = wedge.rungs
    cos_b = np.cos(wedge.half)
    m = wedge.bisector
    step = s[1] - s[0] if s.size > 1 else s[0]
    # q_k half a step before rung k along the bisector: q_{k+1} is q_k reflected across rung k
    # (equal steps after the first), and q_0 is where that puts it inside the first triangle
    t = (s - 0.5 * step) * cos_b
    q = node + t[:, None] * m
    rung_a = node + s[:, None] * wedge.dir_a
    rung_b = node + s[:, None] * wedge.dir_b
    mirror_a = _reflect(q, node, wedge.dir_a)
    mirror_b = _reflect(q, node, wedge.dir_b) if wedge.edge_b >= 0 else None
    rel = rung_a - q
    radius = np.sqrt(rel[:, 0] ** 2 + rel[:, 1] ** 2)
    return WedgeSites(q, mirror_a, mirror_b, rung_a, rung_b, radius, float(t[0]))


def _reflect(p: np.ndarray, origin: np.ndarray, unit: np.ndarray) -> np.ndarray:
    """Points p reflected across the line through ``origin`` along ``unit``."""
    rel = p - origin
    along = rel[:, 0] * unit[0] + rel[:, 1] * unit[1]
    return origin + 2.0 * along[:, None] * unit[None, :] - rel


def side_of(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """+1 where p lies left of the directed segment a -> b, -1 right (0 on it)."""
    return np.sign(_cross2(b - a, p - a))
