"""``horizons_to_pillar_grdecl``: a corner-point deck between horizons whose pillars follow inclined faults.

The ``fault_geometry: pillars`` mode of issue 25 (``docs/pillar-grids.md``), the sibling of
:func:`~gridlib.cornerpoint.between_horizons.horizons_to_grdecl` (same horizons, dims,
layers, ordering and fault traces):

* the lattice carries every fault on a line of its own at the top horizon, and the pillars
  along it are rulings of the fault surface; the pillars around lean with it and relax back to
  vertical over ``relax_distance``; junction pillars lie on the line where two surfaces meet,
  boundary pillars in the boundary planes (:mod:`gridlib.cornerpoint.fault_lattice`);
* every pillar is pinned at the top horizon; each horizon is evaluated where the pillar meets
  it, and the layers divide each zone proportionally along the pillar;
* the throw moves the hanging wall's corners down their pillars (vertical throw, along the
  fault surface on the fault's pillars); a column is classified by its plan centre at the top,
  which is exact here because no column straddles a fault surface;
* COORD gives each pillar at the shallowest and deepest corner depth of the grid, so Flow and
  ``process_grdecl`` read the same lines; ZCORN is monotone down every pillar;
* no pillar crosses another and no column inverts at any depth of its cells
  (:func:`~gridlib.pillars.inclined_lines.first_crossing`), else one error suggesting a larger
  ``relax_distance``.

Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..pillars.depth_order import ORDERINGS, order_depths
from ..pillars.drift import fault_rulings
from ..pillars.fault_traces import FaultTrace, fault_displacement, nearest_on_trace
from ..pillars.horizon_maps import Horizon, depth_function
from ..pillars.inclined_lines import PillarLines, check_relax_distance, default_relax_distance, first_crossing
from ..pillars.pillar_depths import depth_on_pillars
from ..pillars.zones import check_layers, layer_levels
from .between_horizons import _check_horizons, _corner_index, _pillar_lattice
from .deck import Deck, FaultSegment, runs
from .fault_lattice import FaultLattice, fault_lattice

__all__ = ["horizons_to_pillar_grdecl"]

WHO = "horizons_to_pillar_grdecl"


def horizons_to_pillar_grdecl(
    horizons: Sequence[Horizon | Mapping[str, ArrayLike] | Any],
    dims: Sequence[int] | None = None,
    layers: int | Sequence[int] = 1,
    faults: Sequence[FaultTrace] = (),
    *,
    ordering: str = "error",
    relax_distance: float | None = None,
) -> Deck:
    """A corner-point deck whose pillars follow the faults' surfaces (see the module docstring).

    ``horizons``, ``dims``, ``layers`` and ``ordering`` as in
    :func:`~gridlib.cornerpoint.between_horizons.horizons_to_grdecl`. ``faults``:
    :class:`FaultTrace` s, their ``points`` the trace at the top horizon and ``surface`` the
    fault surface (None: vertical); ``throw`` is vertical (m, positive = hanging wall down).
    Each trace must be a graph over the axis it runs along (within 45 degrees of it). Faults
    along different axes may cross or end on one another (X, T); a fault may end on another
    along the same axis (a Y: the lattice lines between them meet in one pillar at the
    junction, wedge columns on both sides), but two such faults that cross are an error
    suggesting stair_steps. A trace ending on another fault's trace (within 1e-6 of the grid's
    extent) has no tip there: its hanging wall ends at that fault. At a tip inside the grid the
    throw should taper to 0: a throw left at the tip ends the displaced block with a step
    across the lattice (as in ``horizons_to_grdecl``), which is no part of the fault surface.
    ``relax_distance`` (m): how far from a fault the pillars relax back to vertical; default
    2 H cot(dip), H the depth range of the horizons plus every fault's largest |throw| (a
    hanging wall's corners reach that much further along their pillars) and dip the smallest
    of any stick.

    Returns a :class:`~gridlib.cornerpoint.deck.Deck` (source ``"horizons_to_pillar_grdecl"``)
    with inclined COORD, FAULTS on the fault lines and ``notes``.

    >>> from gridlib.pillars.fault_surface import FaultSurface
    >>> x, y = np.linspace(0.0, 400.0, 3), np.linspace(0.0, 200.0, 3)
    >>> horizons = [Horizon(x, y, np.full((3, 3), 1000.0)), Horizon(x, y, np.full((3, 3), 1040.0))]
    >>> trace = [(200.0, -10.0), (200.0, 210.0)]  # walking north: the hanging wall east (right)
    >>> surface = FaultSurface.from_dip(trace, [1000.0, 1000.0], 60.0, "right")
    >>> fault = FaultTrace(trace, 5.0, "F1", "right", surface=surface)
    >>> deck = horizons_to_pillar_grdecl(horizons, (4, 2), 2, [fault])
    >>> deck.faults
    (FaultSegment(name='F1', i1=1, i2=1, j1=0, j2=1, k1=0, k2=1, face='X'),)
    >>> deck.pillars()[0, 2].round(3).tolist()  # the fault's pillar: 45 m deep, 45 cot(60) m east
    [[200.0, 0.0, 1000.0], [225.981, 0.0, 1045.0]]
    >>> deck.pillars()[0, 0].tolist()  # the boundary's: vertical
    [[0.0, 0.0, 1000.0], [0.0, 0.0, 1045.0]]
    """
    surfaces = _check_horizons(horizons)
    nlay = check_layers(layers, len(surfaces) - 1, who=WHO)
    if ordering not in ORDERINGS:
        raise InputError(f"{WHO}: ordering must be one of {', '.join(ORDERINGS)}, got {ordering!r}")
    if isinstance(faults, FaultTrace) or not all(isinstance(f, FaultTrace) for f in faults):
        raise InputError(f"{WHO}: faults must be a sequence of FaultTrace")
    box, px, py = _pillar_lattice(surfaces, dims)
    nx, ny = px.size - 1, py.size - 1
    depth_fns = [depth_function(hz, h) for h, hz in enumerate(horizons)]
    top = depth_fns[0]

    VX, VY = np.meshgrid(px, py)
    z_top, z_base = top(VX, VY), depth_fns[-1](VX, VY)
    if not (np.isfinite(z_top).any() and np.isfinite(z_base).any()):
        raise InputError(f"{WHO}: the top and the base horizon have no common area")
    z_range = (float(np.nanmin(z_top)), float(np.nanmax(z_base)))
    names = [t.name if t.name is not None else f"F{f + 1}" for f, t in enumerate(faults)]
    rulings, notes = [], []
    # The lattice lines follow the traces at the top horizon to a thousandth of a cell.
    tolerance = 1e-3 * min((box[1] - box[0]) / nx, (box[3] - box[2]) / ny)
    for trace, name in zip(faults, names, strict=True):
        ruling, stray = fault_rulings(
            trace, name, depth_function(horizons[0], clamped=True), z_range, tolerance
        )
        rulings.append(ruling)
        if stray > 1e-9 * _extent(box):
            notes.append(
                f"fault '{name}': its sticks bend; the pillars follow their straight chords between "
                f"depths {z_range[0]:g} and {z_range[1]:g} m, up to {stray:.3g} m from the sticks"
            )
    # The throws move hanging-wall corners further down (or up) their pillars than the horizons
    # reach, by each fault whose hanging wall holds them.
    reach = z_range[1] - z_range[0] + sum(_largest_throw(t) for t in faults)
    bound = default_relax_distance(reach, max((r.max_drift for r in rulings), default=0.0))
    relax = bound if relax_distance is None else check_relax_distance(relax_distance, WHO)
    if any(r.max_drift > 0 for r in rulings):
        notes.append(f"fault_geometry pillars: pillars relax back to vertical over {relax:g} m")

    lattice = fault_lattice(box, (nx, ny), rulings, relax, top)
    X, Y = lattice.xy[..., 0], lattice.xy[..., 1]
    point, drift = lattice.point.reshape(-1, 2), lattice.drift.reshape(-1, 2)
    z0 = lattice.depth.ravel()
    lines = np.stack([np.column_stack([point, z0]), np.column_stack([point + drift, z0 + 1.0])], axis=1)
    H = np.stack(
        [
            depth_on_pillars(f, lines, f"{WHO}: horizon {h}").reshape(ny + 1, nx + 1)
            for h, f in enumerate(depth_fns)
        ]
    )
    H = order_depths(H, ordering, X, Y, notes, who=WHO)
    Zn = layer_levels(H, nlay)
    nz = Zn.shape[0] - 1
    zc = Zn[np.ix_(_corner_index(nz), _corner_index(ny), _corner_index(nx))]
    # Cells are classified against the surface's trace at the top horizon, which the lattice line
    # follows: on a curved top it leaves the chord between the sticks (fault_rulings).
    on_top = [
        t if r.anchors.shape == t.points.shape else dataclasses.replace(t, points=r.anchors)
        for t, r in zip(faults, rulings, strict=True)
    ]
    segments = _displace(on_top, faults, names, zc, lattice.xy, lattice.lines, box, notes)
    _check_no_crossing(zc, point, drift, z0, rulings, lattice, relax, bound)
    return _deck(zc, point, drift, z0, segments, notes)


def _displace(faults, given, names, zc, xy, lines, box, notes: list[str]) -> list[FaultSegment]:
    """Move the hanging-wall corners of every fault down by its throw (``zc`` in place), as
    ``horizons_to_grdecl`` does on the lattice ``xy`` at the top horizon, except that an end of a
    trace on another fault's trace is no tip: the fault's hanging wall ends at that fault (only
    the cells on the fault's own side of it move). The FAULTS segments of the cell edges each
    fault offsets, but for those on another fault's line which that fault offsets too (the faces
    of a T's stem against its bar belong to the bar). ``faults``: the traces at the top horizon
    that classify the columns; ``given``: as given, whose ends say where a fault ends on another."""
    nz, ny, nx = (n // 2 for n in zc.shape)
    xmin, xmax, ymin, ymax = box
    tol = 1e-6 * _extent(box)
    pillars = xy.reshape(-1, 2)
    # The mean of the four corners: inside every column, the wedges at a Y junction included.
    centres = (0.25 * (xy[:-1, :-1] + xy[:-1, 1:] + xy[1:, :-1] + xy[1:, 1:])).reshape(-1, 2)
    j, i, b, a = np.indices((ny, nx, 2, 2))
    corner_pillar, corner_cell = (j + b) * (nx + 1) + (i + a), j * nx + i
    segments: list[FaultSegment] = []
    across = []
    for f, trace in enumerate(faults):
        pts = given[f].points
        ends_on = [_ends_on(pts[e], f, given, tol) for e in (0, -1)]
        open_ends = [
            not (xmin < pts[e][0] < xmax and ymin < pts[e][1] < ymax) or ends_on[k] is not None
            for k, e in enumerate((0, -1))
        ]
        disp = fault_displacement(
            trace, f, names[f], pillars, centres, corner_pillar, corner_cell, *open_ends
        )
        for other, body in zip(ends_on, (pts[1], pts[-2]), strict=True):
            if other is not None:  # keep the cells on the fault's own side of the other one
                _, _, side = nearest_on_trace(np.vstack([centres, body]), faults[other].points, True, True)
                disp *= (np.sign(side[:-1]) == np.sign(side[-1]))[corner_cell]
        zc += disp.transpose(0, 2, 1, 3).reshape(2 * ny, 2 * nx)[None]
        across.append(_across(disp))
    # Edges between coincident pillars (the row through a Y junction) have no face to fault.
    point_i = (xy[:-1, 1:-1] == xy[1:, 1:-1]).all(axis=-1)  # +i face of cell (i, j): (ny, nx - 1)
    point_j = (xy[1:-1, :-1] == xy[1:-1, 1:]).all(axis=-1)  # +j face of cell (i, j): (ny - 1, nx)
    for f, name in enumerate(names):
        across_i, across_j = across[f]
        across_i &= ~point_i
        across_j &= ~point_j
        for g, (family, index) in enumerate(lines):  # edges on another fault's line are its own
            if g != f and family == "i":
                across_i[:, index - 1] &= ~across[g][0][:, index - 1]
            elif g != f and family == "j":
                across_j[index - 1] &= ~across[g][1][index - 1]
        segs = [
            FaultSegment(name, int(i), int(i), int(j1), int(j2), 0, nz - 1, "X")
            for i, j1, j2 in zip(*runs(across_i.T), strict=True)
        ]
        segs += [
            FaultSegment(name, int(i1), int(i2), int(j), int(j), 0, nz - 1, "Y")
            for j, i1, i2 in zip(*runs(across_j), strict=True)
        ]
        if not segs:
            notes.append(f"fault '{name}' offsets no cell edge of the grid")
        segments += segs
    return segments


def _across(disp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Which cell edges a fault's corner displacement (ny, nx, 2, 2) differs across: the +i faces
    (ny, nx - 1) and the +j faces (ny - 1, nx)."""
    across_i = (disp[:, :-1, :, 1] != disp[:, 1:, :, 0]).any(axis=-1)
    across_j = (disp[:-1, :, 1, :] != disp[1:, :, 0, :]).any(axis=-1)
    return across_i, across_j


def _ends_on(point: np.ndarray, f: int, faults, tol: float) -> int | None:
    """The first other fault whose trace passes within ``tol`` of ``point``, or None."""
    for g, other in enumerate(faults):
        if g != f:
            seg, t, _ = nearest_on_trace(point[None], other.points, False, False)
            v = other.points
            near = v[seg[0]] + t[0] * (v[seg[0] + 1] - v[seg[0]])
            if np.hypot(*(near - point)) <= tol:
                return g
    return None


def _largest_throw(trace: FaultTrace) -> float:
    """The largest |throw| (m) along the trace (a function of arc length sampled at 1 % steps)."""
    if not callable(trace.throw):
        return abs(float(trace.throw))
    throw = np.asarray(trace.throw(np.linspace(0.0, 1.0, 101)), dtype=np.float64)
    return float(np.abs(throw).max(initial=0.0))


def _extent(box) -> float:
    return max(box[1] - box[0], box[3] - box[2])


def _check_no_crossing(zc, point, drift, z0, rulings, lattice: FaultLattice, relax, bound) -> None:
    """Every active column's section convex and counter-clockwise at every depth of its cells
    (corner depths grow down every pillar, so a column's range is its first top to last bottom)."""
    ny, nx = (n // 2 for n in zc.shape[1:])
    z_lo = zc[0].reshape(ny, 2, nx, 2).min(axis=(1, 3))
    z_hi = zc[-1].reshape(ny, 2, nx, 2).max(axis=(1, 3))
    jj, ii = np.nonzero(np.isfinite(z_lo) & np.isfinite(z_hi))
    n0 = jj * (nx + 1) + ii  # the column's corners counter-clockwise: (i, j), (i+1, j), (i+1, j+1), (i, j+1)
    ring = np.stack([n0, n0 + 1, n0 + nx + 2, n0 + nx + 1], axis=1).ravel()
    lines = PillarLines(np.column_stack([point, z0]), drift)
    bad = first_crossing(lines, np.arange(0, ring.size + 1, 4), ring, z_lo[jj, ii], z_hi[jj, ii])
    if bad is None:
        return
    j, i = int(jj[bad.column]), int(ii[bad.column])
    centre = 0.5 * (lattice.xy[j, i] + lattice.xy[j + 1, i + 1])
    raise InputError(
        f"fault_geometry pillars: the pillars near fault '{_nearest_fault(rulings, centre)}' cross or "
        f"invert {bad.columns} columns, first column (i, j) = ({i + 1}, {j + 1}): its pillars lean too "
        f"differently over its depth range; increase relax_distance (now {relax:g} m; the bound "
        f"2 H cot(dip) is {bound:g} m) or use fault_geometry: stair_steps"
    )


def _nearest_fault(rulings, xy: np.ndarray) -> str:
    """The name of the fault whose trace at the top horizon is nearest the plan point ``xy``."""
    dist = []
    for r in rulings:
        seg, t, _ = nearest_on_trace(xy[None], r.anchors, False, False)
        a, _, _ = r.ruling(seg, t)
        dist.append(float(np.hypot(*(a[0] - xy))))
    return rulings[int(np.argmin(dist))].name if rulings else "?"


def _deck(zc, point, drift, z0, segments: list[FaultSegment], notes: list[str]) -> Deck:
    """The deck: cells with an undefined corner inactive, every pillar given at the grid's
    shallowest and deepest corner depth (a long line: OPM takes pillars whose ends differ by
    less than 1e-6 in depth as vertical)."""
    nz, ny, nx = (n // 2 for n in zc.shape)
    with np.errstate(invalid="ignore"):
        active = np.isfinite(zc).reshape(nz, 2, ny, 2, nx, 2).all(axis=(1, 3, 5))
    if not active.any():
        raise InputError(
            f"{WHO}: the horizons have no common area: every cell has a corner where a horizon is undefined"
        )
    finite = zc[np.isfinite(zc)]
    ztop, zbot = float(finite.min()), float(finite.max())
    if zbot <= ztop:
        zbot = ztop + 1.0
    top = point + (ztop - z0)[:, None] * drift
    bot = point + (zbot - z0)[:, None] * drift
    coord = np.column_stack([top, np.full(len(top), ztop), bot, np.full(len(bot), zbot)])
    return Deck(
        (nx, ny, nz),
        coord.ravel(),
        zc.ravel(),
        active.ravel().astype(np.int32),
        faults=tuple(segments),
        source=WHO,
        notes=tuple(notes),
    )
