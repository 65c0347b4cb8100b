"""The pillar lattice of a corner-point grid whose pillars follow its faults (issue 25, ``pillars``).

Like the key pillars of commercial pillar gridding, every fault gets a lattice line of its
own at the top horizon, and the pillars along it lie in the fault surface:

* each fault is carried by the lattice family most parallel to its trace (an i-line, x as a
  function of y, for a trace closer to north-south; a j-line otherwise), the line of that
  family nearest to the trace's mean position; the trace must be a graph over the other axis
  (else the fault cannot be a pillar line: use stair_steps). Beyond a tip the line continues
  parallel to its axis, untagged;
* the grid's four boundary lines stay where they are, and the lines between two fixed lines
  of a family (boundary or fault) are blended linearly by index, so they keep their order;
* a fault ending on another of its family (a Y) keeps its line beyond the junction mirrored
  about the other's, and a straight line of the other family runs through the junction: the
  lines between the two faults' then meet in one pillar there (wedge columns on both sides,
  which OPM Flow and ``process_grdecl`` accept); faults of one family that cross are an error;
  a node is where its i-line and its j-line meet (a fixed point, contracting because every
  line is within 45 degrees of its axis);
* the pillar of a node on one fault is that fault's ruling through it; of a node on two
  surfaces (two faults of different families, a fault and the boundary, two boundaries) the
  line where both planes meet, so a junction pillar lies in both faults and boundary pillars
  stay in the boundary planes; every other pillar leans by the blended drift
  (:func:`~gridlib.pillars.drift.blended_drift`), its component across a boundary tapered to
  0 at the boundary.

Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..grid import FloatArray
from ..pillars.drift import FaultRulings, blended_drift, smoothstep

Box = tuple[float, float, float, float]


@dataclass(frozen=True, eq=False)
class FaultLattice:
    """Pillars of a corner-point lattice, (ny + 1, nx + 1) nodes, i fastest.

    ``xy``: the nodes at the top horizon (plan view; what classifies the cells against the
    faults). Pillar (j, i) passes through ``point[j, i] + (z - depth[j, i]) * drift[j, i]`` at
    depth z; ``depth`` is the top horizon's there (any depth where it is undefined).
    ``lines[f]``: ``("i" or "j", index)`` of the lattice line carrying fault f.
    """

    xy: FloatArray
    point: FloatArray
    depth: FloatArray
    drift: FloatArray
    lines: tuple[tuple[str, int], ...]


@dataclass(frozen=True, eq=False)
class _Graph:
    """A fault's trace as v(u) along one axis (u = y for an i-line, v = x), continued beyond its
    ends parallel to that axis (so a line beyond a tip inside the grid stays inside it)."""

    fault: int  # -1: the straight line through a Y junction, no fault
    family: str
    u: FloatArray  # increasing
    v: FloatArray
    # A fault ending on another of its family at u_J (a Y): beyond u_J (on the side ``sign``) its
    # line mirrors its offset from the other's, so the two lines touch at the junction only.
    mirror: tuple[_Graph, float, float] | None = None

    def __call__(self, u: FloatArray) -> FloatArray:
        if self.mirror is None:
            return self._base(u)
        other, u_j, sign = self.mirror
        beyond = sign * (u - u_j) > 0
        back = np.where(beyond, 2.0 * u_j - u, u)
        v = self._base(back)
        return np.where(beyond, other(u) + (v - other(back)), v)

    def _base(self, u: FloatArray) -> FloatArray:
        u = np.clip(u, self.u[0], self.u[-1])
        k = np.clip(np.searchsorted(self.u, u) - 1, 0, self.u.size - 2)
        t = (u - self.u[k]) / (self.u[k + 1] - self.u[k])
        return self.v[k] + t * (self.v[k + 1] - self.v[k])


def fault_lattice(
    box: Box,
    dims: tuple[int, int],
    faults: Sequence[FaultRulings],
    relax: float,
    top: Callable[[np.ndarray, np.ndarray], np.ndarray],
) -> FaultLattice:
    """The lattice of ``dims`` = (nx, ny) cells over ``box`` = (xmin, xmax, ymin, ymax) whose lines
    carry ``faults`` and whose pillars follow them (see the module docstring). ``relax``: the relax
    distance (m); ``top(x, y)``: the top horizon's depth (NaN outside it)."""
    xmin, xmax, ymin, ymax = box
    nx, ny = dims
    px, py = np.linspace(xmin, xmax, nx + 1), np.linspace(ymin, ymax, ny + 1)
    graphs = [_graph(f, fault) for f, fault in enumerate(faults)]
    graphs, ys = _y_junctions(graphs, faults, 1e-6 * max(xmax - xmin, ymax - ymin))
    for family, u_j, _, _, _ in ys:  # the other family gets a straight line through the junction
        span = (xmin, xmax) if family == "i" else (ymin, ymax)
        graphs.append(_Graph(-1, "j" if family == "i" else "i", np.array(span), np.array([u_j, u_j])))
    touching = {frozenset((f, g)): u_j for _, u_j, _, f, g in ys}
    fixed_i = _fixed_lines([g for g in graphs if g.family == "i"], px, (ymin, ymax), faults, "x", touching)
    fixed_j = _fixed_lines([g for g in graphs if g.family == "j"], py, (xmin, xmax), faults, "y", touching)
    X, Y = _nodes(px, py, fixed_i, fixed_j)
    xy = np.stack([X, Y], axis=-1)
    y_nodes = [_y_nodes(y, fixed_i, fixed_j) for y in ys]
    for nodes in y_nodes:  # the nodes between the two lines in the junction's row are one point
        xy.reshape(-1, 2)[nodes] = xy.reshape(-1, 2)[nodes[0]]
    z0 = top(X, Y)
    # Where the top horizon is undefined the cells are inactive; any depth places the pillar.
    z0 = np.where(np.isfinite(z0), z0, np.nanmin(z0) if np.isfinite(z0).any() else 0.0)
    point, depth, drift = _pillars(xy, z0, faults, fixed_i, fixed_j, box, relax, y_nodes)
    lines: list[tuple[str, int]] = [("", -1)] * len(faults)
    for family, fixed in (("i", fixed_i), ("j", fixed_j)):
        for index, g in fixed.items():
            if g is not None and g.fault >= 0:
                lines[g.fault] = (family, index)
    return FaultLattice(xy, point, depth, drift, tuple(lines))


def _graph(f: int, fault: FaultRulings) -> _Graph:
    a = fault.anchors
    dx, dy = a[-1] - a[0]
    family = "i" if abs(dy) >= abs(dx) else "j"
    u, v = (a[:, 1], a[:, 0]) if family == "i" else (a[:, 0], a[:, 1])
    if u[-1] < u[0]:
        u, v = u[::-1], v[::-1]
    if np.any(np.diff(u) <= 0):
        axis = "y" if family == "i" else "x"
        raise InputError(
            f"fault_geometry pillars: the trace of fault '{fault.name}' at the top horizon turns back in "
            f"{axis}, so no lattice line can follow it; use fault_geometry: stair_steps"
        )
    if np.any(np.abs(np.diff(v)) > np.diff(u)):
        raise InputError(
            f"fault_geometry pillars: a segment of fault '{fault.name}''s trace is more than 45 degrees "
            f"from the {'y' if family == 'i' else 'x'} axis its lattice line follows; a pillar lattice "
            "cannot carry such a bend: use fault_geometry: stair_steps"
        )
    return _Graph(f, family, u.copy(), v.copy())


def _y_junctions(graphs: list[_Graph], faults, tol: float):
    """Faults of one family of which one ends on the other's trace (a Y or a lambda): the ending
    one's line mirrored beyond the junction (:class:`_Graph`), its end moved exactly onto the
    other's line; and the junctions (family, u_J, v_J, ending fault, other fault)."""
    ys = []
    out = list(graphs)
    for f, gf in enumerate(graphs):
        for g, gg in enumerate(graphs):
            if f == g or gf.family != gg.family:
                continue
            for end, sign in ((0, -1.0), (-1, 1.0)):
                u_j = gf.u[end]
                if not (gg.u[0] <= u_j <= gg.u[-1]) or abs(gf.v[end] - gg(np.array([u_j]))[0]) > tol:
                    continue
                if any(y[3] == f for y in ys):
                    raise InputError(
                        f"fault_geometry pillars: both ends of fault '{faults[f].name}' end on other faults "
                        "along its lattice family; use fault_geometry: stair_steps"
                    )
                v = gf.v.copy()
                v[end] = gg(np.array([u_j]))[0]
                out[f] = _Graph(gf.fault, gf.family, gf.u, v, (gg, float(u_j), sign))
                ys.append((gf.family, float(u_j), float(v[end]), gf.fault, gg.fault))
    return out, ys


def _y_nodes(y, fixed_i, fixed_j) -> np.ndarray:
    """Flat indices of the lattice nodes at a Y junction: in the row of the line through it,
    from the one fault's line to the other's."""
    family, u_j, _, f, g = y
    own, cross = (fixed_i, fixed_j) if family == "i" else (fixed_j, fixed_i)
    at = [k for k, line in own.items() if line is not None and line.fault in (f, g)]
    row = next(k for k, line in cross.items() if line is not None and line.fault < 0 and line.v[0] == u_j)
    nx = max(fixed_i)
    span = np.arange(min(at), max(at) + 1)
    return row * (nx + 1) + span if family == "i" else span * (nx + 1) + row


def _fixed_lines(
    graphs: list[_Graph], axis: FloatArray, span: tuple[float, float], faults, name: str, touching
) -> dict[int, _Graph | None]:
    """The fixed lines of one family: index -> fault graph (None for the two boundaries), checked
    to keep their order over the whole grid, but for two faults of a Y at their junction
    (``touching``: {frozenset of the two faults: u there})."""
    n = axis.size - 1
    h = axis[1] - axis[0]
    u = np.linspace(span[0], span[1], n + 1)
    fixed: dict[int, _Graph | None] = {0: None, n: None}
    for g in graphs:
        index = int(np.clip(np.rint((g(u).mean() - axis[0]) / h), 1, n - 1))
        if index in fixed:
            raise InputError(
                f"fault_geometry pillars: {_what(g, faults)} and {_what(fixed[index], faults)} fall on "
                f"the same lattice line ({name} line {index}); refine the grid, or use fault_geometry: "
                "stair_steps"
            )
        fixed[index] = g
    order = sorted(fixed)
    # Piecewise linear lines keep their order iff they do at every break point of both.
    mirrored = [2.0 * g.mirror[1] - g.u for g in graphs if g.mirror is not None]
    breaks = np.unique(np.concatenate([[span[0], span[1]], *(g.u for g in graphs), *mirrored]))
    breaks = breaks[(breaks >= span[0]) & (breaks <= span[1])]
    for lo, hi in itertools.pairwise(order):
        v_lo = np.full(breaks.size, axis[0]) if fixed[lo] is None else fixed[lo](breaks)
        v_hi = np.full(breaks.size, axis[-1]) if fixed[hi] is None else fixed[hi](breaks)
        bad = v_hi <= v_lo
        if fixed[lo] is not None and fixed[hi] is not None:
            u_j = touching.get(frozenset((fixed[lo].fault, fixed[hi].fault)))
            if u_j is not None:
                bad &= ~((breaks == u_j) & (np.abs(v_hi - v_lo) <= 1e-9 * (axis[-1] - axis[0])))
        if np.any(bad):
            names = [_what(fixed[k], faults) for k in (lo, hi)]
            where = float(breaks[np.flatnonzero(bad)[0]])
            other = "y" if name == "x" else "x"
            raise InputError(
                f"fault_geometry pillars: {names[0]} and {names[1]} meet or cross at the top horizon "
                f"(near {other} = {where:g}), which a pillar lattice cannot carry on lines of one family; "
                "use fault_geometry: stair_steps"
            )
    return fixed


def _what(line: _Graph | None, faults) -> str:
    if line is None:
        return "the grid's boundary"
    if line.fault < 0:
        return "the lattice line through a Y junction"
    return f"fault '{faults[line.fault].name}'"


def _family_position(fixed: dict[int, _Graph | None], axis: FloatArray, u: FloatArray) -> FloatArray:
    """Position (ncross, n + 1) of every line of a family at the cross coordinates ``u`` (ncross,
    n + 1) of its nodes: fixed lines as given, the others blended linearly by index."""
    n = axis.size - 1
    order = sorted(fixed)
    out = np.empty_like(u)
    for lo, hi in itertools.pairwise(order):
        idx = np.arange(lo, hi + 1)
        uu = u[:, idx]
        v_lo = np.full(uu.shape, axis[0]) if fixed[lo] is None else fixed[lo](uu)
        v_hi = np.full(uu.shape, axis[n]) if fixed[hi] is None else fixed[hi](uu)
        w = (idx - lo) / (hi - lo)
        out[:, idx] = v_lo + w * (v_hi - v_lo)
    return out


def _nodes(px, py, fixed_i, fixed_j) -> tuple[FloatArray, FloatArray]:
    """Node positions X, Y (ny + 1, nx + 1) where every i-line meets every j-line."""
    X, Y = np.meshgrid(px, py)
    extent = max(px[-1] - px[0], py[-1] - py[0])
    for _ in range(200):
        X_new = _family_position(fixed_i, px, Y)
        Y_new = _family_position(fixed_j, py, X_new.T).T
        change = max(np.abs(X_new - X).max(), np.abs(Y_new - Y).max())
        X, Y = X_new, Y_new
        if change <= 1e-14 * extent:
            return X, Y
    raise InputError(
        "fault_geometry pillars: the lattice lines along the faults do not settle (faults of both "
        "families at about 45 degrees); use fault_geometry: stair_steps"
    )


def _pillars(xy, z0, faults, fixed_i, fixed_j, box, relax, y_nodes):
    """Point, depth and drift of every node's pillar (see the module docstring)."""
    xmin, xmax, ymin, ymax = box
    shape = xy.shape[:2]
    flat = xy.reshape(-1, 2)
    point = flat.copy()
    depth = z0.ravel().copy()
    drift = blended_drift(flat, list(faults), relax)
    # Drift across a boundary tapers to 0 at it, so boundary pillars stay in the boundary planes.
    if relax > 0:
        drift[:, 0] *= smoothstep(np.minimum(flat[:, 0] - xmin, xmax - flat[:, 0]) / relax)
        drift[:, 1] *= smoothstep(np.minimum(flat[:, 1] - ymin, ymax - flat[:, 1]) / relax)
    else:
        drift[:] = 0.0
    # The planes every node lies in: (node, anchor, depth, drift, strike, is a boundary); at most two.
    planes: list[tuple[np.ndarray, ...]] = []
    j, i = np.indices(shape)
    for family, fixed in (("i", fixed_i), ("j", fixed_j)):
        for index, g in fixed.items():
            nodes = np.flatnonzero((i if family == "i" else j).ravel() == index)
            if g is None:  # a boundary: vertical plane along the line
                strike = np.array([0.0, 1.0]) if family == "i" else np.array([1.0, 0.0])
                zero = np.zeros((nodes.size, 2))
                planes.append(
                    (nodes, flat[nodes], depth[nodes], zero, np.tile(strike, (nodes.size, 1)), True)
                )
                continue
            if g.fault < 0:  # the line through a Y junction: no plane
                continue
            fault = faults[g.fault]
            seg, t, inside = _on_trace(fault, flat[nodes])
            nodes, seg, t = nodes[inside], seg[inside], t[inside]
            a, z, s = fault.ruling(seg, t)
            # The horizontal direction along the surface: anchors differ in depth, so their chord
            # is no strike line; d/dt of the section at the ruling's depth is.
            strike = np.diff(fault.anchors, axis=0)[seg] - np.diff(fault.depth)[seg][:, None] * s
            strike /= np.hypot(*strike.T)[:, None]
            planes.append((nodes, a, z, s, strike, False))
    node_of = np.concatenate([p[0] for p in planes])
    first = np.full(flat.shape[0], -1)
    count = np.bincount(node_of, minlength=flat.shape[0])
    cat = [np.concatenate([p[k] for p in planes]) for k in range(5)]
    is_boundary = np.concatenate([np.full(p[0].size, p[5]) for p in planes])
    order = np.argsort(node_of, kind="stable")
    node_sorted = node_of[order]
    starts = np.searchsorted(node_sorted, np.arange(flat.shape[0]))
    first[count > 0] = order[starts[count > 0]]
    in_y = np.zeros(flat.shape[0], dtype=bool)
    for nodes in y_nodes:
        in_y[nodes] = True
    one = (count == 1) & ~in_y
    plane = first[one]  # the plane of every node on exactly one
    # One fault plane: the ruling through the node (on the trace: its anchor there, to round-off),
    # at the depth where the ruling meets the top horizon.
    fault_node = np.flatnonzero(one)[~is_boundary[plane]]
    depth[fault_node] = cat[2][first[fault_node]]
    # Two planes (a junction): their line of intersection, through the top horizon's depth; at a
    # Y the nodes between the two faults' lines are one point, on each fault's plane at its end.
    two = np.flatnonzero((count == 2) & ~in_y)
    p1, p2 = order[starts[two]], order[starts[two] + 1]
    ends = [(nodes, first[nodes[0]], first[nodes[-1]]) for nodes in y_nodes]
    if any(min(a, b) < 0 for _, a, b in ends):
        raise InputError(
            "fault_geometry pillars: a Y junction does not lie on both faults' lines; use stair_steps"
        )
    sources = np.concatenate([two, [nodes[0] for nodes, _, _ in ends]]).astype(np.int64)
    p1 = np.concatenate([p1, [a for _, a, _ in ends]]).astype(np.int64)
    p2 = np.concatenate([p2, [b for _, _, b in ends]]).astype(np.int64)
    if sources.size:
        blended = drift[sources]
        point[sources], drift[sources] = _intersection(
            [c[p1] for c in cat[1:]], [c[p2] for c in cat[1:]], depth[sources]
        )
        # Near a junction the pillars take its difference to the blended drift, tapering off over
        # the relax distance: the pillars along a fault slide towards the junction gradually.
        steepest = max((f.max_drift for f in faults), default=0.0)
        drift = _towards_junctions(flat, drift, sources, drift[sources] - blended, relax, steepest)
        for nodes, _, _ in ends:
            point[nodes], drift[nodes], depth[nodes] = point[nodes[0]], drift[nodes[0]], depth[nodes[0]]
    # Every node on one plane keeps to it: its drift projected onto the plane.
    on_one = np.flatnonzero(one)
    s_p, strike = cat[3][plane], cat[4][plane]
    along = ((drift[on_one] - s_p) * strike).sum(axis=1)
    drift[on_one] = s_p + along[:, None] * strike
    return point.reshape(*shape, 2), depth.reshape(shape), drift.reshape(*shape, 2)


def _towards_junctions(
    xy: FloatArray, drift: FloatArray, junction, jump: FloatArray, relax: float, steepest: float
) -> FloatArray:
    """``drift`` plus each junction's ``jump`` (its pillar's drift minus the blended one there)
    weighted by smoothstep(1 - d / R), d the distance to the junction, weights capped at 1. R is
    the relax distance scaled by the jump over the steepest fault's drift (when larger): the
    relax distance bounds the drift's gradient for a change of that drift."""
    if relax <= 0:
        return drift
    correction = np.zeros_like(drift)
    weight = np.zeros(xy.shape[0])
    for n, jump_n in zip(junction, jump, strict=True):
        radius = relax * max(1.0, float(np.hypot(*jump_n)) / steepest) if steepest > 0 else relax
        w = smoothstep(1.0 - np.hypot(*(xy - xy[n]).T) / radius)
        correction += w[:, None] * jump_n
        weight += w
    out = drift + correction / np.maximum(weight, 1.0)[:, None]
    out[junction] = drift[junction]
    return out


def _on_trace(fault: FaultRulings, p: FloatArray):
    """Segment and fraction of the trace at the nodes ``p`` of its lattice line, and which of
    them lie within the trace (not beyond a tip: those are ordinary nodes)."""
    a = fault.anchors
    d = np.diff(a, axis=0)
    use_y = abs(a[-1, 1] - a[0, 1]) >= abs(a[-1, 0] - a[0, 0])
    k = 1 if use_y else 0
    u = a[:, k]
    sign = 1.0 if u[-1] > u[0] else -1.0
    su, pu = sign * u, sign * p[:, k]
    seg = np.clip(np.searchsorted(su, pu) - 1, 0, u.size - 2)
    t = (p[:, k] - u[seg]) / d[seg, k]
    tol = 1e-9 * max(np.ptp(a[:, 0]), np.ptp(a[:, 1]), 1.0)
    inside = (pu >= su[0] - tol) & (pu <= su[-1] + tol)
    return seg, t, inside


def _intersection(plane1, plane2, z0):
    """Point at depth ``z0`` and drift of the line where two planes meet; each plane is (anchor,
    depth, drift, strike) per node: the points a + (z - za) s + alpha * strike."""
    a1, za1, s1, t1 = plane1
    a2, za2, s2, t2 = plane2
    det = t1[:, 0] * (-t2[:, 1]) - t1[:, 1] * (-t2[:, 0])
    if np.any(np.abs(det) < 1e-6):
        raise InputError(
            "fault_geometry pillars: two faults (or a fault and the grid's boundary) meet at a "
            "grazing angle, so their line of intersection is undefined; use fault_geometry: stair_steps"
        )

    def alpha(rhs):  # solve alpha * t1 - beta * t2 = rhs for alpha
        return (rhs[:, 0] * (-t2[:, 1]) - rhs[:, 1] * (-t2[:, 0])) / det

    c1 = a1 + (z0 - za1)[:, None] * s1
    c2 = a2 + (z0 - za2)[:, None] * s2
    point = c1 + alpha(c2 - c1)[:, None] * t1
    drift = s1 + alpha(s2 - s1)[:, None] * t1
    return point, drift
