"""Circle radii at constrained fault nodes (junctions, sharp bends, boundary points).

Around a node every arm's first step has two mirrored sites; seen from the node they sit at
an angle from the arm that grows with the node's circle radius. The node's radius is the
largest (up to ``ratio`` times the first step) at which the sites of neighbouring arms do not
cross and the sites next to the boundary stay inside it; the tightest pair of arms meets
exactly, and its two inner sites become one site on three circles. Where traces meet at
less than ``ACUTE`` the ratio of radius to step is lowered near the junction
(:func:`local_ratio`), down to ``RATIO_MIN``; at the node of an acute wedge of shared sites
(:mod:`.wedges`) the radius is the wedge's and the other arms are fitted to it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..reproducible import arccos, arctan2
from .fault_layout import FaultLayout

ACUTE = np.radians(40.0)  # traces meeting at less than this get smaller circles near the junction
RATIO_MIN = 0.52  # the smallest circle radius / step used there
FITTED = "its arms' first circles were fitted to it"  # a junction problem that leaves conforming sites


@dataclass(frozen=True, eq=False)
class Steps:
    """The steps along the traces: step k runs from circle centre ``a[k]`` to ``b[k]`` and is
    ``length[k]`` long (m)."""

    a: np.ndarray
    b: np.ndarray
    length: np.ndarray


@dataclass(frozen=True, eq=False)
class _Arms:
    """The arms of the traces at one node: the first centre along each (``far``), the first
    step's length (``lens``), the pairs of neighbouring arms with the angle between them
    (``pairs``: (arm, arm, gap)) and the arms next to the boundary with the angle they may
    take (``caps``: (arm, limit))."""

    far: np.ndarray
    lens: np.ndarray
    pairs: list[tuple[int, int, float]]
    caps: list[tuple[int, float]]


def local_ratio(lay: FaultLayout, centres: np.ndarray, l0: np.ndarray, constrained: np.ndarray) -> np.ndarray:
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


def junction_radii(
    lay: FaultLayout,
    centres: np.ndarray,
    radii: np.ndarray,
    steps: Steps,
    constrained: np.ndarray,
    mean_step: np.ndarray,
    wedge_node: np.ndarray,
    fixed: np.ndarray,
) -> tuple[np.ndarray, list[tuple[int, str]]]:
    """The circle radii with those at constrained nodes (junctions, sharp bends, boundary points)
    fitted, and the problems found there: (node, why).

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
    sa, sb, slen = steps.a, steps.b, steps.length
    radii = radii.copy()
    problems: list[tuple[int, str]] = []
    for v in np.flatnonzero(constrained):  # loop over fault junctions
        at_v = np.concatenate([np.flatnonzero(sa == v), np.flatnonzero(sb == v)])
        if at_v.size == 0:
            continue
        far = np.concatenate([sb[sa == v], sa[sb == v]])
        d = centres[far] - centres[v]
        ang = np.mod(arctan2(d[:, 1], d[:, 0]), 2 * np.pi)
        lens = slen[at_v]
        rw = radii[far]
        rays = [(a, k) for k, a in enumerate(ang)]
        if lay.net.on_boundary[v]:
            rays += [(float(np.mod(b, 2 * np.pi)), -1) for b in dom.boundary_rays(centres[v])]
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

        arms = _Arms(far, lens, pairs, caps)
        shared = _shared_first_centres(far, v, sa, sb, constrained) | fixed[far]
        if wedge_node[v]:
            if not _fit_free_arms(float(radii[v]), arms, radii, shared):
                problems.append((int(v), "the traces meet at too sharp an angle"))
            continue
        hi = min(ratio, radii[v] / mean_step[v]) * float(lens.min())
        lo = float(np.max(lens - rw)) * (1 + 1e-9)
        if _fits(hi, arms, rw):
            radii[v] = hi
        elif lo >= hi or not _fits(lo * (1 + 1e-6), arms, rw):
            # no node radius fits with these first circles (arms of different steps between tight
            # gaps, at a corner of the domain): the arms' first circles are fitted instead
            radii[v] = hi
            fitted = _fit_free_arms(hi, arms, radii, shared)
            problems.append((int(v), FITTED if fitted else "the traces meet at too sharp an angle"))
            continue
        else:
            a, b = lo * (1 + 1e-6), hi
            for _ in range(60):  # bisection: the largest radius that fits
                m = 0.5 * (a + b)
                a, b = (m, b) if _fits(m, arms, rw) else (a, m)
            radii[v] = a
        _close_near_pairs(int(v), float(radii[v]), arms, radii, steps, constrained)
    return radii, problems


def _fits(rv: float, arms: _Arms, rw: np.ndarray) -> bool:
    """Whether a node radius ``rv`` keeps the first sites of neighbouring arms from crossing and
    those next to the boundary inside it (``rw``: the radii of the arms' first centres)."""
    lens = arms.lens
    al = arccos(np.clip((rv**2 + lens**2 - rw**2) / (2 * rv * lens), -1.0, 1.0))
    return all(al[j] + al[k] <= gap * (1 + 1e-12) for j, k, gap in arms.pairs) and all(
        al[k] <= lim for k, lim in arms.caps
    )


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


def _fit_free_arms(rv: float, arms: _Arms, radii: np.ndarray, held: np.ndarray) -> bool:
    """Shrink the first circles of arms (not ``held``, per arm: a wedge's, or shared with another
    node) so that no sites cross at a node whose radius is given (a wedge's, or any that fits).

    Arm j's first sites sit at alpha_j from it; with the node's radius r_v fixed, alpha_j
    is set by the radius r_j of its first centre: r_j^2 = r_v^2 + L_j^2 - 2 r_v L_j cos alpha_j
    (L_j its first step). Where neighbouring arms' sites cross, the free arm's alpha is cut to
    what the gap leaves (half of it between two free arms); ``radii`` is updated. True if
    everything fits then.
    """
    far, lens, pairs, caps = arms.far, arms.lens, arms.pairs, arms.caps
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


def _close_near_pairs(
    v: int, rv: float, arms: _Arms, radii: np.ndarray, steps: Steps, constrained: np.ndarray
) -> None:
    """Make the first sites of neighbouring arms coincide where they nearly do (``radii`` updated).

    With two (nearly) equally tight pairs of arms, as where two straight faults cross,
    only one pair coincides at the largest radius; the other pair's sites end up a hair
    apart, and their cells meet in faces of millimetres. Such a pair (sites closer than
    0.1 first steps) is closed by enlarging the circle at the first centre along one of
    its arms, so that that arm's alpha grows by the angle left: only where the arm's
    other neighbour keeps its distance, the first centre's other circle still meets it
    properly, and neither end of that step is constrained (its radius belongs to another
    junction).
    """
    far, lens, pairs, caps = arms.far, arms.lens, arms.pairs, arms.caps
    sa, sb, slen = steps.a, steps.b, steps.length
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
