"""``horizons_to_grdecl``: a corner-point deck between gridded horizons, with faults.

In the spirit of MRST's ``convertHorizonsToGrid`` (MRST book §3.5, Figs. 3.18 and
3.19); ``docs/pillar-grids.md`` says how the resulting deck becomes a grid:

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
  name. (The displacement rules live in ``gridlib.pillars.fault_traces``, shared
  with the 2.5D front end ``gridlib.pillars.extrude``.) Inclined faults (a
  ``FaultTrace.surface``) are stair-stepped cell by cell on the same vertical
  pillars, laterally and vertically (:mod:`gridlib.cornerpoint.stair_steps`).

Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..pillars.depth_order import ORDERINGS, order_depths
from ..pillars.fault_traces import FaultTrace, fault_displacement
from ..pillars.horizon_maps import Horizon, check_horizon, interpolate_horizon
from ..pillars.zones import check_layers, is_integer, layer_levels
from .deck import Deck, FaultSegment, runs, shown
from .stair_steps import is_inclined, stair_steps

__all__ = ["FaultTrace", "Horizon", "horizons_to_grdecl"]

PINCH_THRESHOLD = 0.001  # m: ECLIPSE's default PINCH thickness, for the missing-section cells of stair steps


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

    A fault with an inclined ``surface`` (``FaultTrace.surface``, not vertical)
    is stair-stepped cell by cell instead (:mod:`~gridlib.cornerpoint.stair_steps`,
    ``fault_geometry: stair_steps``): every cell goes to the hanging wall or the
    footwall by where its centre lies against the surface at its own depth, the
    fault follows cell faces laterally and horizontally (FAULTS X, Y and Z),
    missing-section cells get zero thickness and overlaps are clamped as OPM
    Flow's ZCORN fixup would; where cells were cut out the deck gets PINCH
    (0.001 m, ECLIPSE's defaults) so that the blocks connect across them.

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
    nlay = check_layers(layers, n_zones)
    if ordering not in ORDERINGS:
        raise InputError(
            f"horizons_to_grdecl: ordering must be one of {', '.join(ORDERINGS)}, got {ordering!r}"
        )
    box, px, py = _pillar_lattice(surfaces, dims)
    nx, ny = px.size - 1, py.size - 1
    PX, PY = np.meshgrid(px, py)  # (ny + 1, nx + 1), i fastest

    H = np.stack([_interpolate(xa, ya, z, px, py) for xa, ya, z in surfaces])
    notes: list[str] = []
    H = order_depths(H, ordering, PX, PY, notes)

    Zn = layer_levels(H, nlay)  # node depths (nz + 1, ny + 1, nx + 1): proportional layers per zone
    nz = Zn.shape[0] - 1
    zc = Zn[np.ix_(_corner_index(nz), _corner_index(ny), _corner_index(nx))]
    if not isinstance(faults, FaultTrace) and any(is_inclined(f) for f in faults):
        steps = stair_steps(faults, zc, PX, PY, box)
        notes += steps.notes
        # The blocks meet across the removed missing-section cells as across pinch-outs: PINCH
        # (ECLIPSE's defaults) gives them their vertical connection, in gridlib and in Flow.
        pinch = (PINCH_THRESHOLD, 1e20) if steps.missing_cells or steps.gap_cells else None
        return _deck(steps.zcorn, PX, PY, box, list(steps.segments), notes, pinch)
    segments = _apply_faults(faults, zc, PX, PY, box, notes) if faults else []
    return _deck(zc, PX, PY, box, segments, notes)


def _pillar_lattice(surfaces, dims) -> tuple[tuple[float, float, float, float], np.ndarray, np.ndarray]:
    """The grid's rectangle (xmin, xmax, ymin, ymax), the smallest holding every horizon's box, and
    the pillars' x (nx + 1,) and y (ny + 1,) axes meshing it with ``dims`` cells (default: the most
    nodes of any horizon along each axis, minus one)."""
    xmin = min(s[0][0] for s in surfaces)
    xmax = max(s[0][-1] for s in surfaces)
    ymin = min(s[1][0] for s in surfaces)
    ymax = max(s[1][-1] for s in surfaces)
    if dims is None:
        nx = max(s[0].size for s in surfaces) - 1
        ny = max(s[1].size for s in surfaces) - 1
    else:
        nx, ny = _check_dims(dims)
    return (xmin, xmax, ymin, ymax), np.linspace(xmin, xmax, nx + 1), np.linspace(ymin, ymax, ny + 1)


def _apply_faults(faults, zc: np.ndarray, PX, PY, box, notes: list[str]) -> list[FaultSegment]:
    """Displace the corners ``zc`` (2 nz, 2 ny, 2 nx) of the hanging wall of every fault, in place;
    the FAULTS segments of the cell edges each offsets."""
    if isinstance(faults, FaultTrace):
        raise InputError("horizons_to_grdecl: faults must be a sequence of FaultTrace, got one FaultTrace")
    nz, ny, nx = (n // 2 for n in zc.shape)
    segments: list[FaultSegment] = []
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
    return segments


def _deck(zc: np.ndarray, PX, PY, box, segments: list[FaultSegment], notes: list[str], pinch=None) -> Deck:
    """The deck of the corners ``zc``: cells with an undefined corner inactive, vertical pillars
    through the pillar nodes spanning every defined depth; ``pinch``: its PINCH threshold and
    maximum gap, or None."""
    nz, ny, nx = (n // 2 for n in zc.shape)
    xmin, xmax, ymin, ymax = box
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
        pinch=pinch,
        source="horizons_to_grdecl",
        notes=tuple(notes),
    )


# --------------------------------------------------------------------------- inputs


def _corner_index(n: int) -> np.ndarray:
    """Lattice node of each of the 2n corner positions: 0, 1, 1, 2, 2, ..., n."""
    return np.arange(1, 2 * n + 1) // 2


def _check_dims(dims: Sequence[int]) -> tuple[int, int]:
    try:
        d = tuple(dims)
    except TypeError:
        d = (dims,)
    if len(d) != 2 or not all(is_integer(v) for v in d):
        raise InputError(
            f"horizons_to_grdecl: dims must be two positive integers (nx, ny), got {shown(dims)}"
        )
    nx, ny = (int(v) for v in d)
    if min(nx, ny) < 1:
        raise InputError(f"horizons_to_grdecl: dims must be positive, got {shown(dims)}")
    return nx, ny


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


# --------------------------------------------------------------------------- horizons


def _interpolate(xa: np.ndarray, ya: np.ndarray, z: np.ndarray, px: np.ndarray, py: np.ndarray) -> np.ndarray:
    """Bilinear depths at the pillar nodes (ny + 1, nx + 1); NaN outside the horizon's box and
    wherever one of its NaN nodes has a non-zero weight (not just next to one)."""
    QX, QY = np.meshgrid(px, py)
    return interpolate_horizon(xa, ya, z, QX, QY)


# --------------------------------------------------------------------------- faults


def _fault_displacement(trace: FaultTrace, index: int, name: str, PX, PY, box) -> np.ndarray:
    """Downward displacement of every cell corner (ny, nx, 2, 2) = [j, i, b, a] by one fault
    (:func:`~gridlib.pillars.fault_traces.fault_displacement` on the pillar lattice)."""
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


def _fault_segments(disp: np.ndarray, name: str, nz: int) -> list[FaultSegment]:
    """FAULTS segments of the cell edges across which this fault's displacement differs."""
    across_i = (disp[:, :-1, :, 1] != disp[:, 1:, :, 0]).any(axis=-1)  # (ny, nx - 1): +i face of (i, j)
    across_j = (disp[:-1, :, 1, :] != disp[1:, :, 0, :]).any(axis=-1)  # (ny - 1, nx): +j face of (i, j)
    segs = []
    for i, j1, j2 in zip(*runs(across_i.T), strict=True):  # runs along j in every column i
        segs.append(FaultSegment(name, int(i), int(i), int(j1), int(j2), 0, nz - 1, "X"))
    for j, i1, i2 in zip(*runs(across_j), strict=True):  # runs along i in every row j
        segs.append(FaultSegment(name, int(i1), int(i2), int(j), int(j), 0, nz - 1, "Y"))
    return segs
