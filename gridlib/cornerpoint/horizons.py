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
  name. (The displacement rules live in ``gridlib.stratigraphic.faults``, shared
  with the 2.5D front end ``gridlib.stratigraphic.extrude``.)

Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..stratigraphic.faults import FaultTrace, fault_displacement
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


def _check_layers(layers: int | Sequence[int], n_zones: int, who: str = "horizons_to_grdecl") -> list[int]:
    what = f"{who}: layers must be a positive integer or one per zone ({n_zones} zones)"
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
    return [check_horizon(hz, h) for h, hz in enumerate(horizons)]


def check_horizon(hz: Any, h: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One gridded horizon (a :class:`Horizon`, a mapping or an object with ``x``, ``y``, ``z``)
    as an increasing x axis (nx,), an increasing y axis (ny,) and depths z[j, i] (ny, nx);
    errors name it ``horizon {h}``."""
    arrays = {}
    for key in ("x", "y", "z"):
        try:
            arrays[key] = np.asarray(_field(hz, key, h), dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise InputError(f"horizon {h}: {key} is not an array of numbers ({exc})") from exc
    x, y, z = arrays["x"], arrays["y"], arrays["z"]
    if z.ndim != 2 or min(z.shape) < 2:
        raise InputError(f"horizon {h}: z must be a 2-D array of at least 2 x 2 nodes, got shape {z.shape}")
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
                f"horizon {h}: x, y and z must have the same shape, got {x.shape}, {y.shape} and {z.shape}"
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
    return np.ascontiguousarray(xa), np.ascontiguousarray(ya), np.ascontiguousarray(z)


# --------------------------------------------------------------------------- horizons


def _interpolate(xa: np.ndarray, ya: np.ndarray, z: np.ndarray, px: np.ndarray, py: np.ndarray) -> np.ndarray:
    """Bilinear depths at the pillar nodes (ny + 1, nx + 1); NaN outside the horizon's box and
    wherever one of its NaN nodes has a non-zero weight (not just next to one)."""
    QX, QY = np.meshgrid(px, py)
    return interpolate_horizon(xa, ya, z, QX, QY)


def interpolate_horizon(xa: np.ndarray, ya: np.ndarray, z: np.ndarray, qx: np.ndarray, qy: np.ndarray):
    """Bilinear depths of the horizon (``check_horizon``'s axes and z) at the points (qx, qy), any
    shape; NaN outside its box (round-off at the box edges counts as inside) and wherever one of
    its NaN nodes has a non-zero weight."""
    from scipy.interpolate import RegularGridInterpolator  # slow to import (0.5 s): only when used

    undefined = np.isnan(z)
    values = np.stack([np.where(undefined, 0.0, z), undefined.astype(np.float64)], axis=-1)
    interp = RegularGridInterpolator((ya, xa), values, method="linear", bounds_error=False, fill_value=np.nan)

    def snap(p: np.ndarray, a: np.ndarray) -> np.ndarray:  # round-off at the box edges counts as inside
        tol = 1e-10 * (a[-1] - a[0])
        p = np.where((p < a[0]) & (p >= a[0] - tol), a[0], p)
        return np.where((p > a[-1]) & (p <= a[-1] + tol), a[-1], p)

    out = interp(np.stack([snap(qy, ya), snap(qx, xa)], axis=-1))
    return np.where(out[..., 1] > 0, np.nan, out[..., 0])


def _order(
    H: np.ndarray,
    ordering: str,
    PX: np.ndarray,
    PY: np.ndarray,
    notes: list[str],
    who: str = "horizons_to_grdecl",
    where: str = "pillar nodes",
) -> np.ndarray:
    """Check or repair the depth order of the horizons at the pillar nodes (ALGORITHMS.md §4);
    ``who`` and ``where`` name the caller and the points in messages."""
    defined = np.isfinite(H)
    with np.errstate(invalid="ignore"):
        crossing = defined[1:] & defined[:-1] & (H[1:] < H[:-1])
    if ordering == "error":
        if crossing.any():
            parts = []
            for h in np.flatnonzero(crossing.reshape(crossing.shape[0], -1).any(axis=1)):
                first = int(np.flatnonzero(crossing[h])[0])
                parts.append(
                    f"horizons {h} and {h + 1} cross at {int(crossing[h].sum())} {where} "
                    f"(horizon {h + 1} above horizon {h}), first at (x, y) = "
                    f"({PX.flat[first]:g}, {PY.flat[first]:g})"
                )
            raise InputError(f"{who}: " + "; ".join(parts) + "; pass ordering='erode' or 'onlap' to repair")
        return H
    if ordering == "erode":  # younger wins: top-down running maximum over the defined horizons
        fixed = np.fmax.accumulate(H, axis=0)
    else:  # onlap, older wins: bottom-up running minimum
        fixed = np.fmin.accumulate(H[::-1], axis=0)[::-1]
    fixed = np.where(defined, fixed, np.nan)
    changed = defined & (fixed != H)
    if changed.any():
        for h in np.flatnonzero(changed.reshape(changed.shape[0], -1).any(axis=1)):
            notes.append(
                f"ordering='{ordering}': horizon {h} was moved to the "
                f"{'horizon above' if ordering == 'erode' else 'horizon below'} it at "
                f"{int(changed[h].sum())} {where}"
            )
    return fixed


# --------------------------------------------------------------------------- faults


def _fault_displacement(trace: FaultTrace, index: int, name: str, PX, PY, box) -> np.ndarray:
    """Downward displacement of every cell corner (ny, nx, 2, 2) = [j, i, b, a] by one fault
    (:func:`~gridlib.stratigraphic.faults.fault_displacement` on the pillar lattice)."""
    xmin, xmax, ymin, ymax = box
    verts = trace.points
    ny, nx = PX.shape[0] - 1, PX.shape[1] - 1

    def inside(q: np.ndarray) -> bool:
        return bool(xmin < q[0] < xmax and ymin < q[1] < ymax)

    pillars = np.column_stack([PX.ravel(), PY.ravel()])
    cx = 0.5 * (PX[:-1, :-1] + PX[1:, 1:])
    cy = 0.5 * (PY[:-1, :-1] + PY[1:, 1:])
    centres = np.column_stack([cx.ravel(), cy.ravel()])
    # Corner (a, b) of cell (i, j) lies on pillar (i + a, j + b).
    j, i, b, a = np.indices((ny, nx, 2, 2))
    corner_pillar = (j + b) * (nx + 1) + (i + a)
    corner_cell = j * nx + i
    return fault_displacement(
        trace,
        index,
        name,
        pillars,
        centres,
        corner_pillar,
        corner_cell,
        not inside(verts[0]),
        not inside(verts[-1]),
    )


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
