"""Straight inclined pillars that follow inclined faults and relax back to vertical away from them.

One concept serves corner-point lattices and 2.5D (PEBI) grids alike: every pillar is a
straight line, given by one of its points (x, y, depth) and its *drift* (dx/dz, dy/dz): the
horizontal metres it moves per metre of depth. A pillar in a fault surface takes the drift
of the surface's ruling; the other pillars take a drift that blends back to vertical:

* :func:`harmonic_drift`: the drift of the free nodes of a plan graph, discrete-harmonic
  between the given ones (the pillars on the faults; 0 at wells and beyond the *relax
  distance* R from every inclined fault), sliding along a straight domain boundary: it blends
  the faults' drifts back to vertical as smoothly as the graph allows, junctions included;
* :func:`default_relax_distance`: R = 2 H s_max (H the largest depth span a pillar carries, s_max the
  largest fault drift, cot(dip) for a dip fault). The map X0 -> X0 + dz s(X0) preserves
  orientation while dz |grad s| < 1; a drift falling from s_max to 0 over R evenly has
  H |grad s| = 0.5 there;
* :func:`first_crossing`: the exact test that no column of the grid inverts or folds at
  any depth of the model (a bound is no proof where several faults, wells and boundaries
  meet);
* :func:`interior_drift`: the drift of a point inside a column that moves with it (the PEBI
  sites, as the cells' centres at depth).

The test: at depth z every pillar is at P(z) = a + z s, linear in z, so the signed area of
the triangle (P_{c-1}, P_c, P_{c+1}) at every corner c of a column is a quadratic in z. If
none is negative over the depth range, every column's horizontal section is a convex,
positively oriented polygon at every depth: no two pillars of a column cross and no
column inverts (its cells then have positive volumes when their layers are in depth order).
Corners whose three pillars are collinear (nodes along a straight fault trace, whose
pillars lie in one plane, or along a straight domain boundary) stay collinear: the section
may turn the wrong way there by no more than round-off, 1e-9 radians. Convexity is more than
needed: with a line inside every column (its centre followed down it), the triangles from
the centre over every edge keeping their orientation (quadratics alike) make every section
star-shaped around the centre, hence simple: no fold, no crossing, while a short edge may
turn a little (what the PEBI grids use).

Columns are given as node cycles (``pos``/``ring``, as
:class:`~gridlib.pillars.column_inputs.ColumnCorners`: corner-point cells have four, PEBI
cells as many as their polygon). Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.sparse import coo_matrix
from scipy.sparse.linalg import spsolve

from ..errors import InputError
from ..grid import FloatArray, IntArray

__all__ = [
    "Crossing",
    "PillarLines",
    "default_relax_distance",
    "first_crossing",
    "harmonic_drift",
    "interior_drift",
]

# The section of a column may turn the wrong way at a corner by this much (radians) without
# folding: collinear pillars (one fault plane, one boundary edge) stay collinear up to round-off.
COLLINEAR_TOLERANCE = 1e-9


@dataclass(frozen=True, eq=False)
class PillarLines:
    """Straight pillars, one per node: ``point`` (n, 3) a point of each (x, y, depth, m) and
    ``drift`` (n, 2) its horizontal displacement per metre of depth (0 = vertical)."""

    point: FloatArray
    drift: FloatArray

    def xy_at(self, z: ArrayLike) -> FloatArray:
        """(n, 2): where every pillar is at depth ``z`` (a number or one depth per pillar)."""
        dz = np.asarray(z, dtype=np.float64) - self.point[:, 2]
        return self.point[:, :2] + dz[:, None] * self.drift

    def as_pillars(self, z_top: float, z_bottom: float) -> FloatArray:
        """(n, 2, 3): the top and bottom points of every pillar at depths ``z_top`` < ``z_bottom``,
        as :func:`~gridlib.pillars.extrude.extrude` and COORD take them. A pillar of drift 0 keeps
        its x, y exactly."""
        n = self.point.shape[0]
        out = np.empty((n, 2, 3))
        for k, z in enumerate((z_top, z_bottom)):
            out[:, k, :2] = self.xy_at(z)
            out[:, k, 2] = z
        return out


def default_relax_distance(thickness: float, max_drift: float) -> float:
    """R = 2 H s_max (m): ``thickness`` H the largest depth span a pillar carries, ``max_drift`` the largest
    horizontal drift of a fault (cot(dip) for a dip fault). 0 when no fault is inclined."""
    return 2.0 * float(thickness) * float(max_drift)


def harmonic_drift(
    xy: FloatArray,
    edges: IntArray,
    fixed: np.ndarray,
    value: FloatArray,
    slide: FloatArray | None = None,
) -> FloatArray:
    """The drift (n, 2) of the nodes ``xy`` (n, 2) of a plan graph (``edges`` (m, 2)) that is
    discrete-harmonic (every free node's drift the mean of its neighbours', weighted by 1 /
    edge length) where it is not given: ``fixed`` (n,) nodes keep ``value`` (n, 2) (the fault
    pillars, wells and nodes beyond the relax distance, 0); nodes with a ``slide`` direction (n, 2)
    (unit, NaN for none; a straight domain boundary) drift only along it, harmonic along it.
    A harmonic field has no interior extremum and spreads every change as evenly as the graph
    allows: near a junction of two faults it blends their pillars' drifts without the kinks a
    per-fault taper makes. One sparse solve (SuperLU) for the free and sliding nodes only, the
    same for any thread count."""
    n = xy.shape[0]
    a, b = edges[:, 0], edges[:, 1]
    w = 1.0 / np.hypot(*(xy[a] - xy[b]).T)
    rows = np.concatenate([a, b, a, b])
    cols = np.concatenate([a, b, b, a])
    vals = np.concatenate([w, w, -w, -w])
    lap = coo_matrix((vals, (rows, cols)), shape=(n, n)).tocsr()
    sliding = np.zeros(n, dtype=bool) if slide is None else np.isfinite(slide[:, 0]) & ~fixed
    tangent = np.where(sliding[:, None], slide if slide is not None else 0.0, 0.0)
    free = ~fixed & ~sliding
    # Unknowns: x drifts then y drifts. Rows: free nodes' Laplacian per component; sliding
    # nodes' Laplacian along the slide and no drift across it.
    blocks_r: list[np.ndarray] = []
    blocks_c: list[np.ndarray] = []
    blocks_v: list[np.ndarray] = []
    lap_coo = lap.tocoo()
    r, c, v = lap_coo.row, lap_coo.col, lap_coo.data
    for comp in (0, 1):
        keep = free[r]
        blocks_r.append(r[keep] + comp * n)
        blocks_c.append(c[keep] + comp * n)
        blocks_v.append(v[keep])
        keep = sliding[r]  # the tangent row of a sliding node: t . (L s)
        blocks_r.append(r[keep])
        blocks_c.append(c[keep] + comp * n)
        blocks_v.append(v[keep] * tangent[r[keep], comp])
        # the normal row of a sliding node: s . n = 0, n = (-t_y, t_x)
        nodes = np.flatnonzero(sliding)
        blocks_r.append(nodes + n)
        blocks_c.append(nodes + comp * n)
        blocks_v.append(tangent[nodes, 1 - comp] * (-1.0 if comp == 0 else 1.0))
    matrix = coo_matrix(
        (np.concatenate(blocks_v), (np.concatenate(blocks_r), np.concatenate(blocks_c))), shape=(2 * n, 2 * n)
    ).tocsr()
    # The given drifts go to the right-hand side (most of a big grid is beyond the relax distance).
    known = np.concatenate([fixed, fixed])
    solution = np.concatenate([np.where(fixed, value[:, 0], 0.0), np.where(fixed, value[:, 1], 0.0)])
    unknown = np.flatnonzero(~known)
    if unknown.size:
        rows = matrix[unknown]
        rhs = -(rows[:, np.flatnonzero(known)] @ solution[known])  # machine-independent: scipy's sparse loop
        solution[unknown] = spsolve(rows[:, unknown].tocsc(), rhs)
    return np.column_stack([solution[:n], solution[n:]])


@dataclass(frozen=True)
class Crossing:
    """The first column (0-based) whose section turns the wrong way, at which corner (its node)
    and depth (m), by how much (the sine of the wrong turn), and how many columns do."""

    column: int
    node: int
    depth: float
    turn: float
    columns: int = 1


def first_crossing(
    lines: PillarLines,
    pos: IntArray,
    ring: IntArray,
    z_lo: ArrayLike,
    z_hi: ArrayLike,
    centres: PillarLines | None = None,
) -> Crossing | None:
    """The exact no-crossing test (module docstring) of the columns ``pos``/``ring`` (node cycles,
    all walked the same way round, as the cells of an areal grid: the way is that of their total
    area) over depths [``z_lo``, ``z_hi``] (m; numbers, or one range per column: the depths its
    cells occupy); None when every column stays convex and oriented that way at every depth.
    With ``centres`` (one line per column inside it, e.g. the PEBI sites followed down), the
    weaker test that every column stays *star-shaped* around its centre: the triangles (centre,
    P_c, P_c+1) keep their orientation, quadratics in z alike. A star-shaped polygon is simple,
    so the column still neither folds nor crosses a neighbour, but it may turn a little the
    wrong way at a short edge (a convex column need not stay convex). Two consecutive pillars of
    a column that are the same line (a wedge column's collapsed edge) are passed over.
    Vectorised over all corners."""
    n_corner = ring.size
    n_col = pos.size - 1
    owner = np.repeat(np.arange(n_col), np.diff(pos))
    nxt = np.arange(1, n_corner + 1)
    nxt[pos[1:] - 1] = pos[:-1]
    prv = np.arange(-1, n_corner - 1)
    prv[pos[:-1]] = pos[1:] - 1
    lo = np.broadcast_to(np.asarray(z_lo, dtype=np.float64), (n_col,))
    hi = np.broadcast_to(np.asarray(z_hi, dtype=np.float64), (n_col,))
    z_mid = (0.5 * (lo + hi))[owner]
    # Positions at the column's mid depth, relative to its first node (no digits lost at UTM
    # sizes), and depths relative to mid depth: P = a + zeta s with zeta in [-h, h].
    s = lines.drift[ring]
    at_mid = lines.point[ring, :2] + (z_mid - lines.point[ring, 2])[:, None] * s
    a = at_mid - at_mid[pos[:-1]][owner]
    if centres is None:  # the corner's turn
        u, du = a - a[prv], s - s[prv]
        v, dv = a[nxt] - a, s[nxt] - s
        same = np.all((u == 0) & (du == 0), axis=1) | np.all((v == 0) & (dv == 0), axis=1)
    else:  # the triangle from the centre over the edge to the next node
        c = centres.point[:, :2] + (0.5 * (lo + hi) - centres.point[:, 2])[:, None] * centres.drift
        c = c[owner] - at_mid[pos[:-1]][owner]
        dc = centres.drift[owner]
        u, du = a - c, s - dc
        v, dv = a[nxt] - c, s[nxt] - dc
        same = np.all((a[nxt] == a) & (s[nxt] == s), axis=1)
    c0 = _cross(u, v)
    c1 = _cross(u, dv) + _cross(du, v)
    c2 = _cross(du, dv)
    sign = -1.0 if _cross(a, a[nxt]).sum() < 0 else 1.0  # the grid's orientation: its total area
    h = (0.5 * (hi - lo))[owner]
    candidates = [-h, h]
    with np.errstate(divide="ignore", invalid="ignore"):
        vertex = np.where(c2 != 0, -c1 / (2.0 * c2), -h)
    candidates.append(np.clip(vertex, -h, h))
    worst_turn = np.full(n_corner, np.inf)
    worst_zeta = np.zeros(n_corner)
    for zeta in candidates:
        area = sign * (c0 + zeta * (c1 + zeta * c2))
        lengths = np.hypot(*(u + zeta[:, None] * du).T) * np.hypot(*(v + zeta[:, None] * dv).T)
        with np.errstate(divide="ignore", invalid="ignore"):
            turn = np.where(lengths > 0, area / lengths, -1.0)  # a vanishing edge folds the column
        turn[same] = np.inf
        lower = turn < worst_turn
        worst_turn[lower] = turn[lower]
        worst_zeta[lower] = zeta[lower]
    bad = np.flatnonzero(worst_turn < -COLLINEAR_TOLERANCE)
    if bad.size == 0:
        return None
    q = int(bad[np.argmin(owner[bad])])
    depth, columns = float(z_mid[q] + worst_zeta[q]), int(np.unique(owner[bad]).size)
    return Crossing(int(owner[q]), int(ring[q]), depth, float(worst_turn[q]), columns)


def interior_drift(
    lines: PillarLines, pos: IntArray, ring: IntArray, node_xy: FloatArray, points: FloatArray
) -> FloatArray:
    """The drift (n_columns, 2) of one point inside every column that moves with it: ``points``
    (n_columns, 2) inside the convex polygons of the nodes ``node_xy`` (``pos``/``ring``) take the
    pillars' drifts averaged with their Wachspress coordinates there (generalised barycentric
    coordinates, positive inside a convex polygon). A point so moved stays inside its column's
    section at every depth where the section is convex (the PEBI sites as cell centres)."""
    owner = np.repeat(np.arange(pos.size - 1), np.diff(pos))
    nxt = np.arange(1, ring.size + 1)
    nxt[pos[1:] - 1] = pos[:-1]
    prv = np.arange(-1, ring.size - 1)
    prv[pos[:-1]] = pos[1:] - 1
    v = node_xy[ring] - points[owner]  # relative to the point: no digits lost at UTM sizes
    corner_area = _cross(v - v[prv], v[nxt] - v)
    before, after = _cross(v[prv], v), _cross(v, v[nxt])
    with np.errstate(divide="ignore", invalid="ignore"):
        w = corner_area / (before * after)
    w = np.where(np.isfinite(w), w, 0.0)
    total = np.bincount(owner, w, minlength=pos.size - 1)
    out = np.empty((pos.size - 1, 2))
    for d in (0, 1):
        out[:, d] = np.bincount(owner, w * lines.drift[ring, d], minlength=pos.size - 1) / total
    return out


def _cross(p: FloatArray, q: FloatArray) -> FloatArray:
    return p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0]


def check_relax_distance(relax: float, who: str) -> float:
    """``relax`` as a float, or one InputError naming ``who`` if it is not a positive number of
    metres."""
    try:
        value = float(relax) if not isinstance(relax, bool) else np.nan
    except (TypeError, ValueError):
        value = np.nan
    if not np.isfinite(value) or value <= 0:
        raise InputError(f"{who}: relax_distance must be a positive number of metres, got {relax!r}")
    return value
