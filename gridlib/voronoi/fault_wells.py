"""Vertical wells on a fault: which of the fault's cells is the well's.

A vertical well on a fault trace, at its tip, at a junction of faults, or closer to a trace
than the fault's cells are wide (its site would fall into the fault's circles, which must hold
no site for the fault's faces to lie on the trace; :func:`~.wells.build_wells`) has no site of
its own. One cell of the fault's sites becomes the well's instead, chosen by the well's
``fault_side``:

* ``"left"`` or ``"right"``: of the fault sites on that side of the nearest fault, as drawn
  (looking from its first point towards its last, along its segment nearest the well), the
  one nearest the well;
* ``None`` (the default): the fault site nearest the well, which lies on the well's side of
  the trace; where both sides are equally near (the well on the trace), the left one.

Where several sites are equally near (within 1e-9 of the fault step: at a junction, at a tip)
the one farthest along the fault is taken. A well on the trace, at a tip or at a junction then
lies on its cell's boundary (the fault faces, the Voronoi vertices on the trace); a well next
to the trace lies in its cell unless ``fault_side`` names the other side. Every such well
gets a note saying which cell is its and why.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..errors import GridError

TIE = 1e-9  # of the fault step: sites this much nearer than another are as near
SIDE_NAMES = {1: "left", -1: "right"}


def fault_cells(
    wells: np.ndarray,
    points: np.ndarray,
    sides: np.ndarray,
    fault_sites: np.ndarray,
    site_step: np.ndarray,
    traces: Sequence[np.ndarray],
    fault_labels: Sequence[str],
    well_labels: Sequence[str],
    had_rings: np.ndarray,
    fmt: Callable[[np.ndarray], str],
) -> tuple[np.ndarray, list[str]]:
    """The fault site (index into ``fault_sites``) whose cell is each on-fault well's, and a
    note per well.

    ``wells`` (1-based ids), ``points`` (f, 2) and ``sides`` (+1 left, -1 right, 0 the nearer)
    describe the wells without a site (:class:`~.wells.WellSites`); ``traces`` are the faults'
    polylines as drawn (local frame, m), ``had_rings`` (f,) says which wells' rings are not
    built. Two wells never share a cell: a well takes the best cell not yet taken.
    """
    seg_a = np.concatenate([t[:-1] for t in traces])
    seg_b = np.concatenate([t[1:] for t in traces])
    seg_fault = np.concatenate([np.full(t.shape[0] - 1, k) for k, t in enumerate(traces)])
    ab = seg_b - seg_a
    length = np.hypot(ab[:, 0], ab[:, 1])
    tangent = ab / length[:, None]
    taken = np.zeros(fault_sites.shape[0], dtype=bool)
    cells = np.zeros(wells.size, dtype=np.int64)
    notes = []
    for j in range(wells.size):  # loop over the wells on faults (a handful)
        p = points[j]
        rel = p - seg_a
        along = np.clip((rel[:, 0] * tangent[:, 0] + rel[:, 1] * tangent[:, 1]) / length, 0.0, 1.0)
        foot = seg_a + along[:, None] * ab
        dist = np.hypot(p[0] - foot[:, 0], p[1] - foot[:, 1])
        free = np.flatnonzero(~taken)
        if free.size == 0:  # pragma: no cover - build_wells only makes on-fault wells where faults are
            raise GridError(f"pebi_grid: internal error: no fault cell left for {well_labels[wells[j] - 1]}")
        d_site = np.hypot(*(fault_sites[free] - p).T)
        step = float(site_step[free[np.argmin(d_site)]])
        tie = TIE * step
        seg = int(np.flatnonzero(dist <= dist.min() + tie)[0])  # the first fault's segment among the nearest
        t = tangent[seg]
        rel_s = fault_sites[free] - seg_a[seg]
        cross = t[0] * rel_s[:, 1] - t[1] * rel_s[:, 0]
        ahead = t[0] * rel_s[:, 0] + t[1] * rel_s[:, 1]
        side = int(sides[j])
        pool = np.flatnonzero(side * cross > tie) if side else np.arange(free.size)
        if pool.size == 0:  # no fault site on that side left: the nearest one
            pool = np.arange(free.size)
        near = pool[d_site[pool] <= d_site[pool].min() + tie]
        pick = near[np.lexsort((-ahead[near], ~(cross[near] > tie)))[0]]
        cell = int(free[pick])
        taken[cell] = True
        cells[j] = cell
        on = np.unique(seg_fault[dist <= dist.min() + tie])
        notes.append(
            _note(
                well_labels[wells[j] - 1],
                [fault_labels[k] for k in on.tolist()],
                float(dist.min()),
                _at_an_end(p, traces[int(seg_fault[seg])], tie),
                tie,
                _side_name(float(cross[pick]), tie),
                fmt(fault_sites[cell]),
                side,
                bool(had_rings[j]),
            )
        )
    return cells, notes


def _at_an_end(p: np.ndarray, trace: np.ndarray, tie: float) -> bool:
    """Whether ``p`` is the first or the last point of ``trace``."""
    return bool(min(np.hypot(*(p - trace[0])), np.hypot(*(p - trace[-1]))) <= tie)


def _side_name(cross: float, tie: float) -> str:
    return "left of" if cross > tie else "right of" if cross < -tie else "ahead on the line of"


def _note(
    well: str,
    faults: list[str],
    dist: float,
    end: bool,
    tie: float,
    side: str,
    at: str,
    asked: int,
    rings: bool,
) -> str:
    """The note saying which fault cell became the well's and why."""
    fault = faults[0]
    if dist > tie:
        where = f"lies {dist:.3g} m from {fault}, closer than the fault's cells are wide"
    elif len(faults) > 1:
        where = f"lies where {', '.join(faults[:-1])} and {faults[-1]} meet"
    else:
        where = f"lies {'at the end of' if end else 'on'} {fault}"
    if asked:
        why = f"as its fault_side ({SIDE_NAMES[asked]!r}) says"
    elif dist <= tie:
        why = "both sides are equally near, the left is the default (fault_side chooses)"
    else:
        why = "its site is the fault site nearest the well (fault_side chooses a side)"
    return (
        f"{well} {where}: it has no site of its own (it would lie in the fault's circles); its cell "
        f"is the fault cell {side} {fault} (as drawn), site at {at}: {why}"
        + ("; its rings are not built" if rings else "")
    )
