"""``extrude``: layers between horizons below any areal 2-D grid, with faults, through the pillar engine.

The 2.5D front end of the pillar engine (``docs/pillar-grids.md``), the twin of
``horizons_to_grdecl`` + ``process_grdecl`` for areal grids of any polygons
(Voronoi/PEBI cells, triangles, quadrilaterals):

* every horizon (top first) is evaluated at the pillars: a callable
  ``f(x, y)`` (vectorised), an array of one depth per areal node, or a gridded
  :class:`~gridlib.cornerpoint.between_horizons.Horizon` interpolated bilinearly;
* horizons that cross are an error unless ``ordering`` repairs them
  (``"erode"``: younger wins, ``"onlap"``: older wins), as in
  ``horizons_to_grdecl``;
* every zone (pair of consecutive horizons) is divided proportionally into
  ``layers`` layers, dz = (z_{h+1} - z_h) / n at every pillar; zero-thickness
  layers become collapsed cells, which the engine removes (the cells above and
  below then share a face, a PINCH connection when they are layers apart);
* :class:`~gridlib.pillars.fault_traces.FaultTrace` s displace the hanging wall
  exactly as in ``horizons_to_grdecl``: every areal cell is classified by its
  centre (its centroid, or ``centres``), and the corners of hanging-wall cells
  move down by the throw at their pillar, tapering to tips; the two columns of
  an edge between displaced and undisplaced cells then carry different depths
  on the same pillars, which the engine turns into subdivided fault faces and
  non-neighbour connections. On a fault-conforming areal grid (its edges along
  the fault tagged in ``faces.tag``), the trace follows those edges and the
  throw makes them a true fault;
* the result is :func:`~gridlib.pillars.columns.extrude_columns`' grid.

Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

import numbers
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import GridError, InputError
from ..geometry import compute_geometry
from ..grid import FloatArray, Grid, IntArray
from ..threads import num_threads
from .columns import ColumnCorners, PillarPairs, extrude_column_corners, pillar_lines
from .depth_order import ORDERINGS, order_depths
from .fault_traces import FaultTrace, cell_displacement, fault_displacement
from .horizon_maps import Horizon, depth_function
from .nnc import NNC
from .pillar_depths import depth_on_pillars
from .zones import check_layers, layer_levels

__all__ = ["ExtrudedGrid", "extrude"]

HorizonLike = Callable[[np.ndarray, np.ndarray], ArrayLike] | ArrayLike | Horizon | Mapping[str, ArrayLike]


@dataclass(frozen=True, eq=False)
class ExtrudedGrid:
    """What :func:`extrude` returns.

    ``grid``: the 3-D grid (``layering`` holds the areal grid, each cell's
    column and layer); ``nnc``: its non-neighbour connections (kind FAULT
    across faults, PINCH across removed layers; see ``process_grdecl``);
    ``fault_names[t - 1]`` names fault tag t of ``grid.faces.tag`` (the areal
    grid's tags first, as ``fault_<t>``, then the fault traces');
    ``zone[c]``: the zone (0 = between horizons 0 and 1) of every grid cell;
    ``horizons``: (n_horizons, n_areal_nodes) depths (m) of the horizons at
    the pillars, after the ordering repair and before the faults; ``notes``:
    what was repaired or removed.
    """

    grid: Grid
    nnc: NNC
    fault_names: tuple[str, ...]
    notes: tuple[str, ...]
    zone: IntArray
    horizons: FloatArray


def extrude(
    areal: Grid,
    horizons: Sequence[HorizonLike],
    layers: int | Sequence[int] = 1,
    faults: Sequence[FaultTrace] = (),
    *,
    pillars: ArrayLike | None = None,
    active: ArrayLike | None = None,
    ordering: str = "error",
    centres: ArrayLike | None = None,
) -> ExtrudedGrid:
    """Extrude ``areal`` into layers between ``horizons`` (see the module docstring).

    ``areal``: a 2-D grid (griddim 2; only x, y of its nodes are used).
    ``horizons``: at least two, top (shallowest) first, each a callable
    ``f(x, y)`` returning depths (m) for arrays of x and y, an array of one
    depth per areal node, a number (a flat horizon), or a
    :class:`~gridlib.cornerpoint.between_horizons.Horizon` (or mapping with ``x``,
    ``y``, ``z``) interpolated bilinearly; z is depth, positive down. A
    horizon must be defined (finite) at every node of the active cells of the
    zones it bounds.
    ``layers``: layers per zone, one int for all or one per zone.
    ``faults``: :class:`~gridlib.pillars.fault_traces.FaultTrace` s; an end
    point strictly inside the areal grid's domain is a tip.
    ``pillars``: None for vertical pillars through the areal nodes, or
    (n_areal_nodes, 2, 3) straight pillars (top and bottom points, as COORD):
    a callable or gridded horizon is then evaluated where the pillar meets it
    (a fixed-point iteration; an array gives the depths on the pillars), while
    fault sides and throws use the areal grid's plan-view positions.
    ``active``: (n_layers, n_areal_cells) or (n_areal_cells,) booleans; cells
    that are False are left out before anything else.
    ``ordering``: ``"error"`` (default), ``"erode"`` or ``"onlap"``, as in
    :func:`~gridlib.cornerpoint.between_horizons.horizons_to_grdecl`.
    ``centres``: (n_areal_cells, 2) points that classify the cells against
    the fault traces (e.g. the PEBI sites); default the cell centroids.

    >>> from gridlib import cart_grid, compute_geometry
    >>> areal = cart_grid([4, 2], [400.0, 200.0])
    >>> fault = FaultTrace([(200.0, -10.0), (200.0, 210.0)], throw=5.0, name="F1")
    >>> r = extrude(areal, [1000.0, lambda x, y: 1020.0 + 0.0 * x], layers=2, faults=[fault])
    >>> r.grid.num_cells, r.nnc.num, r.fault_names
    (16, 2, ('F1',))
    >>> round(float(compute_geometry(r.grid).cell_volumes.sum()), 6)
    1600000.0
    """
    if not isinstance(areal, Grid) or areal.griddim != 2:
        what = f"a {areal.griddim}-D grid" if isinstance(areal, Grid) else type(areal).__name__
        raise GridError(f"extrude: areal must be a 2-D grid (griddim 2), got {what}")
    if ordering not in ORDERINGS:
        raise InputError(f"extrude: ordering must be one of {', '.join(ORDERINGS)}, got {ordering!r}")
    if isinstance(horizons, (Mapping, Horizon, np.ndarray)) or callable(horizons):
        raise InputError(
            "extrude: horizons must be a sequence of at least two horizons (top first), "
            f"got {type(horizons).__name__}"
        )
    try:
        horizons = list(horizons)
    except TypeError:
        raise InputError(
            f"extrude: horizons must be a sequence of at least two horizons, got {type(horizons).__name__}"
        ) from None
    if len(horizons) < 2:
        raise InputError(f"extrude: need at least two horizons (top first), got {len(horizons)}")
    n_zones = len(horizons) - 1
    nlay = check_layers(layers, n_zones, who="extrude")
    nl = sum(nlay)
    corners = ColumnCorners.of(areal)
    pos, ring, owner = corners.pos, corners.ring, corners.owner
    nn2, nc2 = areal.num_nodes, areal.num_cells
    xy = areal.nodes.coords[:, :2]
    lines = pillar_lines(pillars, nn2)
    act = _active(active, nl, nc2)
    zone_of_layer = np.repeat(np.arange(n_zones), nlay)
    notes: list[str] = []

    H = np.stack([_evaluate(hz, h, xy, lines) for h, hz in enumerate(horizons)])
    _check_defined(H, act, zone_of_layer, pos, ring, owner, xy)
    H = order_depths(H, ordering, xy[:, 0], xy[:, 1], notes, who="extrude", where="areal nodes")
    H.flags.writeable = False

    etag = np.asarray(areal.faces.tag, dtype=np.int64).copy()
    n_areal_tags = int(etag.max(initial=0))
    names = [f"fault_{t}" for t in range(1, n_areal_tags + 1)]

    def corner_depths() -> FloatArray:
        z = _corner_depths(H, nlay, ring)
        if faults:
            _apply_faults(faults, areal, centres, corners, xy, z, etag, names, notes)
        return z

    # The depths go to the engine as a temporary (nothing here keeps them): it drops them, the size
    # of the grid's nodes several times over, once they are ranks. etag and names are then final.
    r = extrude_column_corners(areal, corners, corner_depths(), lines, act, etag, tuple(names), "extrude")
    grid = r.grid
    zone = zone_of_layer[grid.layering.layer]
    zone.flags.writeable = False
    return ExtrudedGrid(grid, r.nnc, r.fault_names, (*notes, *r.notes), zone, H)


# --------------------------------------------------------------------------- horizons


def _active(active: ArrayLike | None, nl: int, nc2: int) -> np.ndarray:
    if active is None:
        return np.ones((nl, nc2), dtype=bool)
    arr = np.asarray(active)
    if arr.shape == (nc2,):
        arr = np.broadcast_to(arr, (nl, nc2))
    if arr.shape != (nl, nc2):
        raise InputError(
            f"extrude: active must have shape (n_layers, n_areal_cells) = ({nl}, {nc2}) or ({nc2},), "
            f"got {arr.shape}"
        )
    if arr.dtype != bool:
        if not np.issubdtype(arr.dtype, np.number) or not np.isin(arr, (0, 1)).all():
            raise InputError("extrude: active must be booleans (or 0/1) per layer and areal cell")
        arr = arr != 0
    return np.ascontiguousarray(arr)


def _corner_depths(H: FloatArray, nlay: Sequence[int], ring: IntArray) -> FloatArray:
    """Depths (n_levels, n_corners) of the layer interfaces at every corner: proportional layers in
    every zone, dz = (z_{h+1} - z_h) / n at every pillar (``H``: the horizons at the pillars)."""
    return np.take(layer_levels(H, nlay), ring, axis=1)


def _evaluate(hz: Any, h: int, xy: FloatArray, lines: FloatArray | None) -> FloatArray:
    """Depths (n_nodes,) of horizon ``h`` at the pillars."""
    n = xy.shape[0]
    if callable(hz):

        def f(x: np.ndarray, y: np.ndarray) -> np.ndarray:
            try:
                out = np.asarray(hz(x, y), dtype=np.float64)
                return np.broadcast_to(out, x.shape).astype(np.float64)
            except Exception as exc:
                raise InputError(
                    f"extrude: horizon {h}: f(x, y) failed for arrays of {x.size} x and y ({exc}); "
                    "a horizon function must return one depth (m) per point"
                ) from exc

    elif isinstance(hz, (Horizon, Mapping)) or all(hasattr(hz, k) for k in ("x", "y", "z")):
        try:
            f = depth_function(hz, h)
        except InputError as exc:
            raise InputError(f"extrude: {exc}") from None

    elif isinstance(hz, numbers.Real) and not isinstance(hz, bool | np.bool_):
        return np.full(n, float(hz)) if np.isfinite(hz) else _not_finite(h)
    else:
        try:
            arr = np.asarray(hz, dtype=np.float64)
        except (TypeError, ValueError):
            raise InputError(
                f"extrude: horizon {h}: expected a function f(x, y), an array of one depth per areal "
                f"node or a Horizon, got {type(hz).__name__}"
            ) from None
        if arr.shape != (n,):
            raise InputError(
                f"extrude: horizon {h}: an array horizon needs one depth per areal node ({n},), "
                f"got shape {arr.shape}"
            )
        if np.isinf(arr).any():
            raise InputError(f"extrude: horizon {h}: infinite depths (use NaN for undefined ones)")
        return arr.copy()
    if lines is None:
        z = f(xy[:, 0].copy(), xy[:, 1].copy())
    else:
        z = depth_on_pillars(f, lines, f"extrude: horizon {h}")
    if np.isinf(z).any():
        raise InputError(f"extrude: horizon {h}: infinite depths (use NaN for undefined ones)")
    return z


def _not_finite(h: int):
    raise InputError(f"extrude: horizon {h}: a constant depth must be finite")


def _check_defined(H, act, zone_of_layer, pos, ring, owner, xy) -> None:
    """A horizon must be finite at the nodes of the active cells of the zones it bounds."""
    nh = H.shape[0]
    for h in range(nh):
        bad_node = ~np.isfinite(H[h])
        if not bad_node.any():
            continue
        zones = [z for z in (h - 1, h) if 0 <= z < nh - 1]
        layer_active = act[np.isin(zone_of_layer, zones)].any(axis=0)  # (n_cells,)
        bad_cell = np.bincount(owner, bad_node[ring], minlength=pos.size - 1) > 0
        hit = layer_active & bad_cell
        if hit.any():
            nodes = np.unique(ring[hit[owner] & bad_node[ring]])
            x, y = xy[nodes[0]]
            raise InputError(
                f"extrude: horizon {h} is undefined (NaN) at {nodes.size} areal nodes of active cells, "
                f"first at (x, y) = ({x:g}, {y:g}); mask those cells with active= or use horizons that "
                "cover the areal grid"
            )


# --------------------------------------------------------------------------- faults


def _apply_faults(faults, areal, centres, corners, xy, z, etag, names, notes) -> None:
    """Displace the hanging-wall corners of every fault (``z`` in place) and tag the edges across
    which a fault's displacement differs (``etag``, ``names`` in place)."""
    if isinstance(faults, FaultTrace) or not isinstance(faults, Sequence):
        raise InputError(f"extrude: faults must be a sequence of FaultTrace, got {type(faults).__name__}")
    if centres is None:
        centre_xy = compute_geometry(areal).cell_centroids[:, :2]
    else:
        centre_xy = np.asarray(centres, dtype=np.float64)
        if centre_xy.shape != (areal.num_cells, 2) or not np.isfinite(centre_xy).all():
            raise InputError(
                f"extrude: centres must be ({areal.num_cells}, 2) finite x, y, got shape {centre_xy.shape}"
            )
    # The corners of both columns of every interior edge, on its two nodes.
    pairs = PillarPairs.of(areal, corners, False)
    inner = np.flatnonzero((areal.faces.neighbors >= 0).all(axis=1))
    qa1, qa2 = pairs.q1[0][inner], pairs.q2[0][inner]
    qb1, qb2 = pairs.q1[1][inner], pairs.q2[1][inner]
    ring, owner = corners.ring, corners.owner
    ca, cb = owner[qa1], owner[qb1]  # the cells on both sides (those of qa2, qb2 are the same)
    boundary = _Boundary.of(areal)
    ends = []  # per fault: its first and last points are not tips
    for f, trace in enumerate(faults):
        if not isinstance(trace, FaultTrace):
            raise InputError(f"extrude: faults[{f}]: expected a FaultTrace, got {type(trace).__name__}")
        open_start, open_end = ~boundary.strictly_inside(trace.points[[0, -1]])
        ends.append((bool(open_start), bool(open_end)))

    def per_cell_of(f: int) -> FloatArray | None:
        return cell_displacement(faults[f], centre_xy, *ends[f])

    # The faults of constant throw displace whole cells: those found on two threads, in advance.
    if len(faults) > 1 and num_threads(2) > 1:
        with ThreadPoolExecutor(2) as pool:
            per_cells = list(pool.map(per_cell_of, range(len(faults))))
    else:
        per_cells = [per_cell_of(f) for f in range(len(faults))]
    for f, trace in enumerate(faults):
        name = trace.name if trace.name is not None else f"F{f + 1}"
        per_cell = per_cells[f]
        if per_cell is None:  # a throw varying along the trace
            disp = fault_displacement(trace, f, name, xy, centre_xy, ring, owner, *ends[f])
            across = (disp[qa1] != disp[qb1]) | (disp[qa2] != disp[qb2])
        else:  # the same displacement at every corner of a cell
            disp = per_cell[owner]
            across = per_cell[ca] != per_cell[cb]
        z += disp[None, :]
        names.append(name)
        if not across.any():
            notes.append(f"fault '{name}' offsets no edge of the areal grid")
            continue
        edges = inner[across]
        free = edges[etag[edges] == 0]
        etag[free] = len(names)
        if free.size < edges.size:
            notes.append(
                f"fault '{name}': {edges.size - free.size} of the {edges.size} edges it offsets keep the tag "
                "they already had"
            )


@dataclass(frozen=True, eq=False)
class _Boundary:
    """The boundary edges (a -> c) of an areal grid, and the extent of its nodes (m)."""

    a: FloatArray
    c: FloatArray
    extent: float

    @classmethod
    def of(cls, areal: Grid) -> _Boundary:
        nb = areal.faces.neighbors
        b = np.flatnonzero((nb < 0).any(axis=1))
        e = areal.faces.nodes.reshape(-1, 2)[b]
        xy = areal.nodes.coords[:, :2]
        return cls(xy[e[:, 0]], xy[e[:, 1]], float(np.ptp(xy, axis=0).max()))

    def strictly_inside(self, points: np.ndarray) -> np.ndarray:
        """Which points lie strictly inside the areal grid's domain (not on or near its boundary)."""
        a, c = self.a, self.c
        out = np.zeros(points.shape[0], dtype=bool)
        for i, p in enumerate(points):  # the two end points of a trace
            up = (a[:, 1] > p[1]) != (c[:, 1] > p[1])
            with np.errstate(divide="ignore", invalid="ignore"):
                x_cross = a[:, 0] + (p[1] - a[:, 1]) * (c[:, 0] - a[:, 0]) / (c[:, 1] - a[:, 1])
            inside = bool(np.count_nonzero(up & (x_cross > p[0])) % 2)
            d = c - a
            t = np.clip(((p - a) * d).sum(axis=1) / (d * d).sum(axis=1), 0.0, 1.0)
            dist = np.sqrt((((a + t[:, None] * d) - p) ** 2).sum(axis=1)).min()
            out[i] = inside and dist > 1e-10 * self.extent
        return out
