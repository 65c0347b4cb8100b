"""Checks of a PEBI grid's sites and of the finished grid.

Fault sites *conform* when no site lies strictly inside a fault circle (the empty-circle
condition: then the Voronoi face between the two sites of a step is the step itself) and every
fault site lies inside the domain. :func:`fault_problems` lists where either fails, with the
smaller fault step wanted there, for :func:`~.pebi_grid.pebi_grid` to refine and rebuild; fault
sites outside the domain ask for steps no smaller than ``GRAZE_FLOOR`` (beyond, the boundary
closes their cells: :func:`outside_sites`, with a note from :func:`graze_notes`).
:func:`raise_fault_problem` names the faults, the place and the case keys that would help
(the traces, a well's position, ``cell_size``) once the local refinement has run its rounds.
:func:`verify` checks the finished grid end to end: cell areas sum to the domain's area, the
fault faces cover the traces, every well owns cells.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..errors import GridError
from ..reproducible import arctan2
from .domain import Domain
from .fault_layout import RING_GAP, step_length
from .fault_sites import circle_violations

# A fault site outside the domain refines its step down to this fraction of the fault's
# unrefined step (its spacing, else the cell size) and no further: below, the boundary closes
# its cell (:func:`outside_sites`); smaller steps would only add cells as narrow as the gap.
GRAZE_FLOOR = 0.25
FLOOR_SLACK = 1.5  # steps come in whole numbers per segment and are graded: within this of the floor is at it


def fault_problems(
    fs, sites, n_bg: int, dom: Domain, bg_tree, keep, graze_floor: np.ndarray | None = None
) -> list[tuple[np.ndarray, float]]:
    """Where fault sites break conformity: (location, step wanted there, m) to refine.

    ``sites``: the ``n_bg`` background sites kept (``keep``, a mask over the background sites
    of ``bg_tree``), then the fault sites ``fs``, then the well sites. Every site is checked
    against every fault circle: the kept background sites through the tree of all background
    sites, the fault and well sites through a tree of their own; and every fault site for
    lying inside the domain. The step wanted is the local step
    scaled by what the geometry needs (circles and sites scale with the step): a circle
    holding a site at distance d from its centre shrinks below d, a site outside the domain
    comes closer to its trace than the boundary is; at least halved, at most by 20.

    ``graze_floor`` (one step per fault site, m; None: no floor) bounds the refinement a site
    outside the domain asks for: never below its floor, and a site whose step is at its floor
    already (within ``FLOOR_SLACK``) is no problem (the boundary closes its cell, see
    :func:`outside_sites`).
    """
    out: list[tuple[np.ndarray, float]] = []
    if fs.centres.shape[0] == 0:
        return out
    n_f = fs.sites.shape[0]
    c, s = circle_violations(fs, sites[n_bg:])
    s = s + n_bg
    if bg_tree is not None:
        cb, sb = circle_violations(fs, None, bg_tree)
        kept = keep[sb]
        position = np.cumsum(keep) - 1
        c, s = np.concatenate([cb[kept], c]), np.concatenate([position[sb[kept]], s])
    if c.size:  # a site in a fault circle (a background, fault or well site): smaller steps there
        c, s = c[:2000], s[:2000]
        rel = sites[s] - fs.centres[c]
        scale = refine_factor(0.9 * np.hypot(rel[:, 0], rel[:, 1]) / fs.radii[c])
        for ci, si, f in zip(c.tolist(), s.tolist(), scale.tolist(), strict=True):
            out.append((fs.centres[ci], f * float(fs.centre_step[ci])))
            if n_bg <= si < n_bg + n_f:
                out.append((fs.sites[si - n_bg], f * float(fs.site_step[si - n_bg])))
    outside = outside_sites(fs, dom)
    if graze_floor is not None:
        outside = outside[fs.site_step[outside] > FLOOR_SLACK * graze_floor[outside]]
    outside = outside[:200]
    if outside.size:  # closer to the trace than the boundary is
        foot = fs.site_foot[outside]
        rel = fs.sites[outside] - foot
        room = np.where(dom.inside(foot), dom.boundary_distance(foot), 0.0)
        want = (
            refine_factor(0.8 * room / np.maximum(np.hypot(rel[:, 0], rel[:, 1]), 1e-300))
            * fs.site_step[outside]
        )
        if graze_floor is not None:
            want = np.maximum(want, graze_floor[outside])
        for k, step in zip(outside.tolist(), want.tolist(), strict=True):
            out.append((fs.sites[k], step))
    for ci, _why in fs.problems[:200]:
        out.append((fs.centres[ci], 0.5 * float(fs.centre_step[ci])))
    return out


def outside_sites(fs, dom: Domain) -> np.ndarray:
    """The fault sites outside the domain (indices into ``fs.sites``).

    Such a site belongs to a step of a trace that runs closer to the boundary than the site
    lies from it. Its Voronoi face with its mirror image is still the step, exactly: the
    empty-circle condition does not ask the sites to lie inside. Clipped to the domain, its
    region is the strip between the trace and the boundary, one step long, closed by the
    boundary (the boundary acts as the far side of a cell whose site lies beyond it).
    """
    return np.flatnonzero(~dom.inside(fs.sites))


def graze_notes(fs, dom: Domain, labels) -> list[str]:
    """A note per fault with sites outside the domain (:func:`outside_sites`): how many of its
    cells the boundary closes, and where the trace runs closest to the boundary."""
    out = outside_sites(fs, dom)
    notes = []
    for f in np.unique(fs.site_fault[out]).tolist():
        mine = out[fs.site_fault[out] == f]
        foot = fs.site_foot[mine]
        gap = dom.boundary_distance(foot)
        k = int(np.argmin(gap))
        notes.append(
            f"{labels[f - 1]} runs {gap[k]:.3g} m from the boundary near {dom.fmt(foot[k])}: {mine.size} of "
            "its cells there are closed by the boundary (their sites, mirror images across the trace, lie "
            "outside the domain; the fault faces stay on the trace)"
        )
    return notes


def problem_kinds(problems: list, fs) -> list[str]:
    """The reason of each problem from :func:`fault_problems`: ``FITTED`` for the junctions listed
    last whose arms were fitted to them (smaller steps are tried first, but they conform as they
    are), "" for the others."""
    kinds = [""] * len(problems)
    tail = fs.problems[:200]
    for k, (_, why) in enumerate(tail):
        kinds[len(problems) - len(tail) + k] = why
    return kinds


def refine_factor(need: np.ndarray) -> np.ndarray:
    """How much a local step is scaled for a refinement: what is needed, at least halving."""
    return np.clip(need, 0.05, 0.5)


def raise_fault_problem(problems, fs, dom: Domain, lay, times: int, ws=None) -> None:
    """Raise the GridError naming the faults (and a well ``ws`` has close by) where the fault
    sites still break the empty-circle condition after ``times`` rounds of local refinement,
    the place, the fault step reached there, and what in the case to change: the traces, the
    well's position or the ``cell_size``."""
    labels = lay.net.labels
    where = problems[0][0]
    d = np.linalg.norm(fs.centres - where, axis=1)
    near = np.flatnonzero(d <= 2.0 * d.min() + 2.0 * float(fs.centre_step.max()))
    ids = sorted(set(fs.centre_fault[near].tolist()))
    names = " and ".join(labels[i - 1] for i in ids[:2])
    h = float(lay.size(where[None, :])[0])
    step = float(step_length(lay, where[None, :], np.array([ids[0]]))[0])
    reached = f"fault cells of {step:.3g} m there (refined locally from the cell size, {h:.3g} m)"
    outside = ~dom.inside(where[None, :])[0]
    if outside:
        raise GridError(
            f"{names}: its trace runs too close to the domain's boundary near {dom.fmt(where)}: even "
            f"{reached} leave the domain; move the trace away from the boundary there, or give a "
            "smaller cell_size"
        )
    # the sharpest angle between traces at the nearest junction or bend, if there is one close by
    net = lay.net
    node = int(np.argmin(np.linalg.norm(net.nodes - where, axis=1)))
    arms = np.concatenate([net.edge_b[net.edge_a == node], net.edge_a[net.edge_b == node]])
    angle = ""
    if arms.size >= 2 and np.hypot(*(net.nodes[node] - where)) <= 2.0 * float(fs.centre_step.max()):
        v = net.nodes[arms] - net.nodes[node]
        ang = np.sort(np.mod(arctan2(v[:, 1], v[:, 0]), 2 * np.pi))
        gaps = np.diff(np.concatenate([ang, ang[:1] + 2 * np.pi]))
        angle = f" (they meet at {np.degrees(gaps.min()):.3g} degrees at {dom.fmt(net.nodes[node])})"
    well = _nearest_well(ws, where, 2.0 * float(fs.centre_step.max()))
    if well:
        raise GridError(
            f"{well} lies too close to {names} near {dom.fmt(where)}: its sites fall into the fault's "
            f"circles even with {reached}; put the well on the trace (a fault cell is then its cell), "
            f"or move it at least {(lay.ratio + RING_GAP) * h:.3g} m from the trace, or give a smaller "
            "cell_size"
        )
    raise GridError(
        f"{names}: no conforming PEBI sites near {dom.fmt(where)}{angle}: even with {reached} a site "
        "falls inside a fault circle (the empty-circle condition), because the traces meet at too sharp "
        "an angle or run too close to each other; widen the angle or the separation of the traces, or "
        "give a smaller cell_size"
    )


def _nearest_well(ws, where: np.ndarray, reach: float) -> str:
    """The label of the well with a site within ``reach`` of ``where`` (the nearest), or ""."""
    if ws is None or not ws.sites.shape[0]:
        return ""
    d = np.linalg.norm(ws.sites - where, axis=1)
    k = int(np.argmin(d))
    return ws.labels[int(ws.site_well[k]) - 1] if d[k] <= reach else ""


def snap_to_traces(coords: np.ndarray, fault_faces: np.ndarray, fs) -> None:
    """Voronoi vertices of fault faces are circle centres: give them the exact trace points."""
    nodes = np.unique(fault_faces)
    if nodes.size == 0:
        return
    d, k = cKDTree(fs.centres).query(coords[nodes])
    close = d <= 1e-6 * fs.centre_step[k]
    coords[nodes[close]] = fs.centres[k[close]]


def verify(vor, dom: Domain, tags, fs, labels, ws, cell_well) -> None:
    """Cheap end-to-end checks: areas add up, fault faces cover the traces, wells own cells."""
    total = float(vor.areas.sum())
    if not abs(total - dom.area) <= 1e-9 * dom.area:
        raise GridError(
            f"pebi_grid: internal error: cell areas sum to {total:.17g}, the domain's area is {dom.area:.17g}"
        )
    if fs.trace_a.shape[0]:
        e = vor.face_nodes
        length = np.linalg.norm(vor.coords[e[:, 1]] - vor.coords[e[:, 0]], axis=1)
        got = np.bincount(tags, length, minlength=len(labels) + 1)[1:]
        want = np.bincount(fs.trace_fault, np.linalg.norm(fs.trace_b - fs.trace_a, axis=1), len(labels) + 1)[
            1:
        ]
        bad = np.abs(got - want) > 1e-9 * np.maximum(want, dom.tol)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise GridError(
                f"pebi_grid: internal error: the faces of {labels[k]} cover {got[k]:.9g} m of its "
                f"{want[k]:.9g} m trace"
            )
    counts = np.bincount(cell_well, minlength=ws.count + 1)[1:]
    if np.any(counts == 0):  # pragma: no cover
        k = int(np.flatnonzero(counts == 0)[0])
        raise GridError(f"pebi_grid: internal error: {ws.labels[k]} has no cell")
