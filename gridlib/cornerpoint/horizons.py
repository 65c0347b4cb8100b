"""``horizons_to_grdecl``: a corner-point deck between gridded horizons, with faults.

In the spirit of MRST's ``convertHorizonsToGrid`` (MRST book §3.5, Figs. 3.18 and
3.19), written from the description in ALGORITHMS.md §4:

* every horizon is a depth map on its own rectilinear mesh; the grid covers the
  smallest rectangle holding all of them, meshed with ``dims`` cells and
  vertical pillars;
* each horizon is interpolated bilinearly at the pillars (scipy's
  ``RegularGridInterpolator``), undefined (NaN) outside its own box and next to
  its own NaN nodes; any cell with an undefined corner is inactive, so the grid
  shrinks to the horizons' common area;
* consecutive horizons are divided proportionally into ``layers`` layers;
  horizons that cross are an error unless ``ordering`` says how to repair them
  (never by sorting, which moves volume between zones);
* beyond MRST, vertical faults: a :class:`FaultTrace` (a polyline in plan view)
  is stair-stepped onto the cell edges and the cells on its hanging-wall side are
  displaced by its throw; the pillars on the trace then carry different depths
  on its two sides, which is what a fault is in a corner-point grid. The faults
  are recorded as FAULTS segments so that ``process_grdecl`` tags their faces by
  name.

Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

import numbers
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from .deck import Deck, FaultSegment

__all__ = ["FaultTrace", "Horizon", "horizons_to_grdecl"]

ORDERINGS = ("error", "erode", "onlap")


@dataclass(frozen=True, eq=False)
class Horizon:
    """A depth map on a rectilinear mesh (m; z is depth, positive down, NaN = undefined).

    ``x`` and ``y`` are either the 1-D axes (then ``z[j, i]`` is the depth at
    ``(x[i], y[j])``) or 2-D meshgrid arrays of ``z``'s shape, with x varying
    along one axis and y along the other (MATLAB's ``meshgrid``/``peaks`` or
    ``ndgrid`` layout). The arrays are copied; they are checked by
    :func:`horizons_to_grdecl`, which can name the horizon at fault.
    """

    x: NDArray[np.float64]
    y: NDArray[np.float64]
    z: NDArray[np.float64]

    def __post_init__(self) -> None:
        for name in ("x", "y", "z"):
            try:
                arr = np.array(getattr(self, name), dtype=np.float64)
            except (TypeError, ValueError) as exc:
                raise InputError(f"Horizon: {name} is not an array of numbers ({exc})") from exc
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)


@dataclass(frozen=True, eq=False)
class FaultTrace:
    """A vertical fault given by its trace in plan view.

    ``points``: the polyline, (n >= 2, 2) x, y in metres. ``throw`` (m): the
    vertical displacement of the hanging wall, positive downwards (deeper); a
    number, or a function of the normalised arc length ``s`` in [0, 1] along the
    polyline (0 at its first point) returning an array like ``s``, e.g.
    ``lambda s: 10 * (1 - s)`` for a fault dying out at its last point
    (values below 1e-12 times the largest are taken as 0, so round-off such as
    ``sin(pi)`` still gives an exact tip).
    ``side``: which side of the polyline, walked from its first point to its
    last, is the hanging wall, ``"left"`` or ``"right"`` as seen on a map with
    x to the right and y up. ``name``: the FAULTS name (default ``F1``, ``F2``,
    ... by position).

    A trace should extend beyond the grid where the fault crosses it: an end
    point strictly inside the grid's rectangle is a fault tip (see
    :func:`horizons_to_grdecl`), an end point on or outside it is not.
    """

    points: NDArray[np.float64]
    throw: float | Callable[[NDArray[np.float64]], ArrayLike]
    name: str | None = None
    side: str = "right"

    def __post_init__(self) -> None:
        label = "fault trace" if self.name is None else f"fault trace '{self.name}'"
        if self.name is not None and (not isinstance(self.name, str) or not self.name.strip()):
            raise InputError(f"{label}: name must be a non-empty string, got {self.name!r}")
        try:
            pts = np.array(self.points, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise InputError(f"{label}: points must be an (n, 2) array of x, y ({exc})") from exc
        if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2:
            raise InputError(f"{label}: points must be an (n >= 2, 2) array of x, y, got shape {pts.shape}")
        if not np.isfinite(pts).all():
            raise InputError(f"{label}: points must be finite")
        seg = np.hypot(*np.diff(pts, axis=0).T)
        if np.any(seg == 0):
            raise InputError(
                f"{label}: points {int(np.flatnonzero(seg == 0)[0])} and "
                f"{int(np.flatnonzero(seg == 0)[0]) + 1} coincide (zero-length segment)"
            )
        pts.flags.writeable = False
        object.__setattr__(self, "points", pts)
        if not callable(self.throw):
            if isinstance(self.throw, bool) or not isinstance(self.throw, numbers.Real):
                raise InputError(
                    f"{label}: throw must be a number (m) or a function of s in [0, 1], got {self.throw!r}"
                )
            if not np.isfinite(float(self.throw)):
                raise InputError(f"{label}: throw must be finite, got {self.throw!r}")
            object.__setattr__(self, "throw", float(self.throw))
        if self.side not in ("left", "right"):
            raise InputError(f"{label}: side must be 'left' or 'right', got {self.side!r}")


def horizons_to_grdecl(
    horizons: Sequence[Horizon | Mapping[str, ArrayLike] | Any],
    dims: Sequence[int] | None = None,
    layers: int | Sequence[int] = 1,
    faults: Sequence[FaultTrace] = (),
    *,
    ordering: str = "error",
) -> Deck:
    """A corner-point deck with vertical pillars between gridded horizons (MRST's
    ``convertHorizonsToGrid``, plus erosion/onlap repair and vertical faults).

    ``horizons``: at least two :class:`Horizon` (or mappings / objects with
    ``x``, ``y``, ``z``), top (shallowest) first; metres, z is depth (positive
    down), NaN where undefined.

    ``dims``: ``(nx, ny)`` cells of the areal mesh, which spans the smallest
    rectangle containing every horizon's box; default: the largest number of
    nodes of any horizon along each axis, minus one (the horizons' own lattice
    when they share it). Each horizon is interpolated bilinearly at the pillar
    nodes; it is NaN outside its box and wherever a NaN node of its own carries
    weight. Cells with an undefined corner are inactive (ACTNUM 0) and keep NaN
    in ZCORN (``process_grdecl`` never reads inactive corners).

    ``layers``: layers per zone (pair of consecutive horizons), one int for
    all or one per zone; a zone is divided proportionally, dz = (z_{h+1} -
    z_h) / n per pillar, so zero-thickness layers are kept (and removed by
    ``process_grdecl`` as collapsed cells).

    ``ordering``: what to do where a horizon lies above the one before it:
    ``"error"`` (default) raises an :class:`~gridlib.errors.InputError`
    naming the horizons, the number of pillar nodes and the first (x, y);
    ``"erode"`` (younger wins) clamps every horizon to at least the depth of
    all defined horizons above it; ``"onlap"`` (older wins) clamps every
    horizon to at most the depth of all defined horizons below it.

    ``faults``: :class:`FaultTrace` s, stair-stepped onto the pillar grid:

    * every cell is classified by its *centre*: the nearest point of the trace
      to the centre decides which side of the trace it lies on (at a vertex
      of the polyline, the side away from the turn); cells on the hanging-wall
      side are displaced, so the fault runs along the cell edges between
      displaced and undisplaced cells, the edges nearest to the trace;
    * the corners of a displaced cell on pillar p move down by ``throw(s_p)``,
      ``s_p`` being the normalised arc length of the pillar's nearest point on
      the trace: two displaced cells sharing a pillar move it alike, so the
      hanging wall stays continuous while the throw varies along the fault;
    * an end point strictly inside the grid's rectangle is a *tip*. Cells whose
      centre's nearest trace point is a tip lie beyond it; they are displaced
      by ``throw(s_p) - throw(tip)`` on the hanging-wall side of the end
      segment's line. That is 0 at every pillar beyond the line through the
      tip perpendicular to the trace, so nothing moves beyond a tip except
      within the cells at the tip, and the hanging wall is continuous across
      that perpendicular line when the throw tapers to 0 at the tip (if it does
      not, the displaced block ends on that line with a step of
      ``throw(tip)``, which becomes part of the fault). An end point on or
      outside the rectangle is no tip: the end segment is extended as a ray;
    * displacements of several faults add up; each fault's cell edges where
      its displacement differs across the edge are recorded as FAULTS
      segments (face X or Y of the cell on the lower-i or lower-j side, all
      layers), so ``process_grdecl`` tags those faces with its name.

    The displacement is the same for every layer of a column, so the layering
    (and ordering) is kept in each fault block.

    Returns a :class:`~gridlib.cornerpoint.deck.Deck` (source
    ``"horizons_to_grdecl"``), ``notes`` saying what was repaired.

    >>> import numpy as np
    >>> x, y = np.linspace(0.0, 400.0, 5), np.linspace(0.0, 200.0, 3)
    >>> top = Horizon(x, y, np.full((3, 5), 1000.0))
    >>> base = {"x": x, "y": y, "z": np.full((3, 5), 1020.0)}
    >>> fault = FaultTrace([(200.0, -10.0), (200.0, 210.0)], throw=5.0, name="F1")
    >>> deck = horizons_to_grdecl([top, base], layers=2, faults=[fault])
    >>> deck.cart_dims
    (4, 2, 2)
    >>> deck.faults
    (FaultSegment(name='F1', i1=1, i2=1, j1=0, j2=1, k1=0, k2=1, face='X'),)
    >>> deck.zcorn_array()[0, 0].tolist()  # top corners of the first row: east of x = 200 is 5 m deeper
    [1000.0, 1000.0, 1000.0, 1000.0, 1005.0, 1005.0, 1005.0, 1005.0]
    """
    surfaces = _check_horizons(horizons)
    n_zones = len(surfaces) - 1
    nlay = _check_layers(layers, n_zones)
    if ordering not in ORDERINGS:
        raise InputError(
            f"horizons_to_grdecl: ordering must be one of {', '.join(ORDERINGS)}, got {ordering!r}"
        )
    xmin = min(s[0][0] for s in surfaces)
    xmax = max(s[0][-1] for s in surfaces)
    ymin = min(s[1][0] for s in surfaces)
    ymax = max(s[1][-1] for s in surfaces)
    if dims is None:
        nx = max(s[0].size for s in surfaces) - 1
        ny = max(s[1].size for s in surfaces) - 1
    else:
        nx, ny = _check_dims(dims)
    px = np.linspace(xmin, xmax, nx + 1)
    py = np.linspace(ymin, ymax, ny + 1)
    PX, PY = np.meshgrid(px, py)  # (ny + 1, nx + 1), i fastest

    H = np.stack([_interpolate(xa, ya, z, px, py) for xa, ya, z in surfaces])
    notes: list[str] = []
    H = _order(H, ordering, PX, PY, notes)

    # Node depths (nz + 1, ny + 1, nx + 1): proportional layers in every zone.
    levels = []
    for h in range(n_zones):
        t = np.arange(nlay[h]) / nlay[h]
        lev = H[h][None] + t[:, None, None] * (H[h + 1] - H[h])[None]
        lev[0] = H[h]  # exactly the horizon, even where the next one is undefined
        levels.append(lev)
    levels.append(H[-1][None])
    Zn = np.concatenate(levels)
    nz = Zn.shape[0] - 1
    zc = Zn[np.ix_(_corner_index(nz), _corner_index(ny), _corner_index(nx))]

    segments: list[FaultSegment] = []
    if faults:
        if isinstance(faults, FaultTrace):
            raise InputError(
                "horizons_to_grdecl: faults must be a sequence of FaultTrace, got one FaultTrace"
            )
        box = (xmin, xmax, ymin, ymax)
        for f, trace in enumerate(faults):
            if not isinstance(trace, FaultTrace):
                raise InputError(f"faults[{f}]: expected a FaultTrace, got {type(trace).__name__}")
            name = trace.name if trace.name is not None else f"F{f + 1}"
            disp = _fault_displacement(trace, f, name, PX, PY, box)
            zc += disp.transpose(0, 2, 1, 3).reshape(2 * ny, 2 * nx)[None]
            segs = _fault_segments(disp, name, nz)
            if not segs:
                notes.append(f"fault '{name}' offsets no cell edge of the grid")
            segments += segs

    with np.errstate(invalid="ignore"):
        active = np.isfinite(zc).reshape(nz, 2, ny, 2, nx, 2).all(axis=(1, 3, 5))
    if not active.any():
        raise InputError(
            "horizons_to_grdecl: the horizons have no common area: every cell has a corner where some "
            f"horizon is undefined (grid rectangle x in [{xmin:g}, {xmax:g}], y in [{ymin:g}, {ymax:g}])"
        )
    finite = zc[np.isfinite(zc)]
    ztop, zbot = float(finite.min()), float(finite.max())
    if zbot <= ztop:
        zbot = ztop + 1.0  # every corner at one depth: any pillar length will do
    coord = np.stack(
        [PX, PY, np.full_like(PX, ztop), PX, PY, np.full_like(PX, zbot)],
        axis=-1,
    )
    return Deck(
        (nx, ny, nz),
        coord.ravel(),
        zc.ravel(),
        active.ravel().astype(np.int32),
        faults=tuple(segments),
        source="horizons_to_grdecl",
        notes=tuple(notes),
    )


# --------------------------------------------------------------------------- inputs


def _corner_index(n: int) -> np.ndarray:
    """Lattice node of each of the 2n corner positions: 0, 1, 1, 2, 2, ..., n."""
    return np.arange(1, 2 * n + 1) // 2


def _is_int(v: Any) -> bool:
    """An integer value: an int (not a bool) or an integral float, numpy's included."""
    if isinstance(v, bool | np.bool_):
        return False
    if isinstance(v, numbers.Integral):
        return True
    return isinstance(v, numbers.Real) and float(v).is_integer()


def _check_dims(dims: Sequence[int]) -> tuple[int, int]:
    try:
        d = tuple(dims)
    except TypeError:
        d = (dims,)
    if len(d) != 2 or not all(_is_int(v) for v in d):
        raise InputError(f"horizons_to_grdecl: dims must be two positive integers (nx, ny), got {dims!r}")
    nx, ny = (int(v) for v in d)
    if min(nx, ny) < 1:
        raise InputError(f"horizons_to_grdecl: dims must be positive, got {dims!r}")
    return nx, ny


def _check_layers(layers: int | Sequence[int], n_zones: int) -> list[int]:
    what = f"horizons_to_grdecl: layers must be a positive integer or one per zone ({n_zones} zones)"
    if _is_int(layers):
        values = [int(layers)] * n_zones  # type: ignore[arg-type]
    else:
        try:
            values = list(layers)  # type: ignore[arg-type]
        except TypeError:
            raise InputError(f"{what}, got {layers!r}") from None
        if len(values) != n_zones:
            raise InputError(f"{what}, got {len(values)} values: {layers!r}")
        if not all(_is_int(v) for v in values):
            raise InputError(f"{what}, got {layers!r}")
        values = [int(v) for v in values]
    bad = [z for z, v in enumerate(values) if v < 1]
    if bad:
        raise InputError(f"{what}; zone {bad[0]} has {values[bad[0]]}")
    return values


def _field(h: Any, key: str, index: int) -> Any:
    if isinstance(h, Mapping):
        if key not in h:
            raise InputError(f"horizon {index}: missing '{key}' (a horizon needs x, y and z)")
        return h[key]
    if not hasattr(h, key):
        raise InputError(
            f"horizon {index}: {type(h).__name__} has no '{key}' (a horizon needs x, y and z: "
            "a Horizon or a mapping)"
        )
    return getattr(h, key)


def _axis(a: np.ndarray, name: str, index: int) -> tuple[np.ndarray, bool]:
    """A strictly monotone axis as increasing, and whether it was reversed."""
    d = np.diff(a)
    if np.all(d > 0):
        return a, False
    if np.all(d < 0):
        return a[::-1], True
    raise InputError(f"horizon {index}: {name} is not strictly monotone (values must increase or decrease)")


def _check_horizons(horizons: Any) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Per horizon: increasing x axis (nx,), increasing y axis (ny,), depths z[j, i] (ny, nx)."""
    if isinstance(horizons, (Mapping, Horizon)) or not isinstance(horizons, Sequence):
        raise InputError(
            "horizons_to_grdecl: horizons must be a sequence of at least two horizons (top first), "
            f"got {type(horizons).__name__}"
        )
    if len(horizons) < 2:
        raise InputError(f"horizons_to_grdecl: need at least two horizons (top first), got {len(horizons)}")
    out = []
    for h, hz in enumerate(horizons):
        arrays = {}
        for key in ("x", "y", "z"):
            try:
                arrays[key] = np.asarray(_field(hz, key, h), dtype=np.float64)
            except (TypeError, ValueError) as exc:
                raise InputError(f"horizon {h}: {key} is not an array of numbers ({exc})") from exc
        x, y, z = arrays["x"], arrays["y"], arrays["z"]
        if z.ndim != 2 or min(z.shape) < 2:
            raise InputError(
                f"horizon {h}: z must be a 2-D array of at least 2 x 2 nodes, got shape {z.shape}"
            )
        if x.ndim != y.ndim or x.ndim not in (1, 2):
            raise InputError(
                f"horizon {h}: x and y must both be 1-D axes or both 2-D mesh arrays, "
                f"got shapes {x.shape} and {y.shape}"
            )
        if not (np.isfinite(x).all() and np.isfinite(y).all()):
            raise InputError(f"horizon {h}: x and y must be finite")
        if x.ndim == 1:
            if z.shape != (y.size, x.size):
                raise InputError(
                    f"horizon {h}: z has shape {z.shape}, expected (len(y), len(x)) = ({y.size}, {x.size})"
                )
            xa, ya = x, y
        else:
            if x.shape != z.shape or y.shape != z.shape:
                raise InputError(
                    f"horizon {h}: x, y and z must have the same shape, "
                    f"got {x.shape}, {y.shape} and {z.shape}"
                )
            tol = 1e-10 * max(1.0, float(np.abs(x).max()), float(np.abs(y).max()))

            def const(a: np.ndarray, axis: int, tol: float = tol) -> bool:
                ref = a[:1, :] if axis == 0 else a[:, :1]
                return bool(np.all(np.abs(a - ref) <= tol))

            if const(x, 0) and const(y, 1) and not const(x, 1):  # meshgrid layout: x along columns
                xa, ya = x[0], y[:, 0]
            elif const(x, 1) and const(y, 0) and not const(x, 0):  # ndgrid layout: x along rows
                xa, ya, z = x[:, 0], y[0], z.T
            else:
                raise InputError(
                    f"horizon {h}: x and y are not a rectilinear mesh (x must be constant along one "
                    "axis and y along the other, as meshgrid gives)"
                )
        xa, flip_x = _axis(xa, "x", h)
        ya, flip_y = _axis(ya, "y", h)
        if flip_x:
            z = z[:, ::-1]
        if flip_y:
            z = z[::-1, :]
        if np.isinf(z).any():
            raise InputError(f"horizon {h}: z has infinite values (use NaN for undefined depths)")
        if np.isnan(z).all():
            raise InputError(f"horizon {h}: z is undefined (NaN) everywhere")
        out.append((np.ascontiguousarray(xa), np.ascontiguousarray(ya), np.ascontiguousarray(z)))
    return out


# --------------------------------------------------------------------------- horizons


def _interpolate(xa: np.ndarray, ya: np.ndarray, z: np.ndarray, px: np.ndarray, py: np.ndarray) -> np.ndarray:
    """Bilinear depths at the pillar nodes (ny + 1, nx + 1); NaN outside the horizon's box and
    wherever one of its NaN nodes has a non-zero weight (not just next to one)."""
    from scipy.interpolate import RegularGridInterpolator  # slow to import (0.5 s): only when used

    undefined = np.isnan(z)
    values = np.stack([np.where(undefined, 0.0, z), undefined.astype(np.float64)], axis=-1)
    interp = RegularGridInterpolator((ya, xa), values, method="linear", bounds_error=False, fill_value=np.nan)

    def snap(p: np.ndarray, a: np.ndarray) -> np.ndarray:  # round-off at the box edges counts as inside
        tol = 1e-10 * (a[-1] - a[0])
        p = np.where((p < a[0]) & (p >= a[0] - tol), a[0], p)
        return np.where((p > a[-1]) & (p <= a[-1] + tol), a[-1], p)

    QX, QY = np.meshgrid(snap(px, xa), snap(py, ya))
    out = interp(np.stack([QY, QX], axis=-1))
    return np.where(out[..., 1] > 0, np.nan, out[..., 0])


def _order(H: np.ndarray, ordering: str, PX: np.ndarray, PY: np.ndarray, notes: list[str]) -> np.ndarray:
    """Check or repair the depth order of the horizons at the pillar nodes (ALGORITHMS.md §4)."""
    defined = np.isfinite(H)
    with np.errstate(invalid="ignore"):
        crossing = defined[1:] & defined[:-1] & (H[1:] < H[:-1])
    if ordering == "error":
        if crossing.any():
            parts = []
            for h in np.flatnonzero(crossing.any(axis=(1, 2))):
                first = int(np.flatnonzero(crossing[h])[0])
                parts.append(
                    f"horizons {h} and {h + 1} cross at {int(crossing[h].sum())} pillar nodes "
                    f"(horizon {h + 1} above horizon {h}), first at (x, y) = "
                    f"({PX.flat[first]:g}, {PY.flat[first]:g})"
                )
            raise InputError(
                "horizons_to_grdecl: " + "; ".join(parts) + "; pass ordering='erode' or 'onlap' to repair"
            )
        return H
    if ordering == "erode":  # younger wins: top-down running maximum over the defined horizons
        fixed = np.fmax.accumulate(H, axis=0)
    else:  # onlap, older wins: bottom-up running minimum
        fixed = np.fmin.accumulate(H[::-1], axis=0)[::-1]
    fixed = np.where(defined, fixed, np.nan)
    changed = defined & (fixed != H)
    if changed.any():
        for h in np.flatnonzero(changed.any(axis=(1, 2))):
            notes.append(
                f"ordering='{ordering}': horizon {h} was moved to the "
                f"{'horizon above' if ordering == 'erode' else 'horizon below'} it at "
                f"{int(changed[h].sum())} pillar nodes"
            )
    return fixed


# --------------------------------------------------------------------------- faults


def _nearest_on_trace(p: np.ndarray, verts: np.ndarray, open_start: bool, open_end: bool):
    """Nearest point of the polyline to every point ``p`` (m, 2): segment, parameter t on it
    (outside [0, 1] only on the rays that extend open ends) and the side value (> 0 = left)."""
    a, d = verts[:-1], np.diff(verts, axis=0)
    n_seg = d.shape[0]
    best = np.full(p.shape[0], np.inf)
    seg = np.zeros(p.shape[0], dtype=np.int64)
    tt = np.zeros(p.shape[0])
    for k in range(n_seg):  # one pass per polyline segment, vectorised over the points
        t = ((p - a[k]) @ d[k]) / (d[k] @ d[k])
        lo = -np.inf if (k == 0 and open_start) else 0.0
        hi = np.inf if (k == n_seg - 1 and open_end) else 1.0
        t = np.clip(t, lo, hi)
        dist2 = ((p - a[k] - t[:, None] * d[k]) ** 2).sum(axis=1)
        better = dist2 < best
        best[better], seg[better], tt[better] = dist2[better], k, t[better]
    rel = p - a[seg]
    side = d[seg, 0] * rel[:, 1] - d[seg, 1] * rel[:, 0]
    # Nearest point at an interior vertex: the point lies on the outer side of the turn there.
    at_vertex = np.where((tt == 0) & (seg > 0), seg, np.where((tt == 1) & (seg < n_seg - 1), seg + 1, -1))
    v = at_vertex[at_vertex > 0]
    if v.size:
        turn = d[v - 1, 0] * d[v, 1] - d[v - 1, 1] * d[v, 0]
        side[at_vertex > 0] = np.where(turn != 0, -turn, side[at_vertex > 0])
    return seg, tt, side


def _fault_displacement(trace: FaultTrace, index: int, name: str, PX, PY, box) -> np.ndarray:
    """Downward displacement of every cell corner (ny, nx, 2, 2) = [j, i, b, a] by one fault."""
    xmin, xmax, ymin, ymax = box
    verts = trace.points
    ny, nx = PX.shape[0] - 1, PX.shape[1] - 1

    def inside(q: np.ndarray) -> bool:
        return bool(xmin < q[0] < xmax and ymin < q[1] < ymax)

    open_start, open_end = not inside(verts[0]), not inside(verts[-1])
    seg_len = np.hypot(*np.diff(verts, axis=0).T)
    cum = np.concatenate([[0.0], np.cumsum(seg_len)])

    pillars = np.column_stack([PX.ravel(), PY.ravel()])
    cx = 0.5 * (PX[:-1, :-1] + PX[1:, 1:])
    cy = 0.5 * (PY[:-1, :-1] + PY[1:, 1:])
    centres = np.column_stack([cx.ravel(), cy.ravel()])
    p_seg, p_t, _ = _nearest_on_trace(pillars, verts, open_start, open_end)
    c_seg, c_t, c_side = _nearest_on_trace(centres, verts, open_start, open_end)
    s_pillar = np.clip((cum[p_seg] + p_t * seg_len[p_seg]) / cum[-1], 0.0, 1.0)

    s_all = np.concatenate([s_pillar, [0.0, 1.0]])
    label = f"fault '{name}' (faults[{index}])"
    if callable(trace.throw):
        try:
            values = np.asarray(trace.throw(s_all.copy()), dtype=np.float64)
            values = np.broadcast_to(values, s_all.shape).astype(np.float64)
        except Exception as exc:
            raise InputError(f"{label}: throw(s) failed for an array s in [0, 1]: {exc}") from exc
    else:
        values = np.full(s_all.shape, trace.throw)
    if not np.isfinite(values).all():
        raise InputError(f"{label}: throw(s) must be finite for s in [0, 1]")
    # Round-off zeros (3 * sin(pi) = 3.7e-16) are zeros: a tapered tip must match exactly.
    values = np.where(np.abs(values) <= 1e-12 * np.abs(values).max(), 0.0, values)
    t_pillar = values[:-2].reshape(ny + 1, nx + 1)
    t_start, t_end = values[-2], values[-1]

    n_seg = seg_len.size
    beyond_start = (c_seg == 0) & (c_t <= 0) & (not open_start)
    beyond_end = (c_seg == n_seg - 1) & (c_t >= 1) & (not open_end)
    hanging = (c_side > 0) if trace.side == "left" else (c_side < 0)
    correction = np.where(beyond_start, t_start, np.where(beyond_end, t_end, 0.0))
    hanging = hanging.reshape(ny, nx)
    correction = correction.reshape(ny, nx)

    # Corner (a, b) of cell (i, j) lies on pillar (i + a, j + b).
    tp = np.stack(
        [
            np.stack([t_pillar[:-1, :-1], t_pillar[:-1, 1:]], axis=-1),
            np.stack([t_pillar[1:, :-1], t_pillar[1:, 1:]], axis=-1),
        ],
        axis=-2,
    )  # (ny, nx, b, a)
    return np.where(hanging[..., None, None], tp - correction[..., None, None], 0.0)


def _runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Runs of True along the last axis of a 2-D mask: (row, first, last), row-major."""
    padded = np.pad(mask.astype(np.int8), ((0, 0), (1, 1)))
    step = np.diff(padded, axis=1)
    r0, c0 = np.nonzero(step == 1)
    _, c1 = np.nonzero(step == -1)
    return r0, c0, c1 - 1


def _fault_segments(disp: np.ndarray, name: str, nz: int) -> list[FaultSegment]:
    """FAULTS segments of the cell edges across which this fault's displacement differs."""
    across_i = (disp[:, :-1, :, 1] != disp[:, 1:, :, 0]).any(axis=-1)  # (ny, nx - 1): +i face of (i, j)
    across_j = (disp[:-1, :, 1, :] != disp[1:, :, 0, :]).any(axis=-1)  # (ny - 1, nx): +j face of (i, j)
    segs = []
    for i, j1, j2 in zip(*_runs(across_i.T), strict=True):  # runs along j in every column i
        segs.append(FaultSegment(name, int(i), int(i), int(j1), int(j2), 0, nz - 1, "X"))
    for j, i1, i2 in zip(*_runs(across_j), strict=True):  # runs along i in every row j
        segs.append(FaultSegment(name, int(i1), int(i2), int(j), int(j), 0, nz - 1, "Y"))
    return segs
