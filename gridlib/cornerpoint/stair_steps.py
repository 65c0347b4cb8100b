"""Inclined faults stair-stepped onto vertical pillars (``fault_geometry: stair_steps``).

The pillars stay vertical and the lattice rectilinear (as for vertical faults in
:func:`~gridlib.cornerpoint.between_horizons.horizons_to_grdecl`); an inclined fault
(a :class:`~gridlib.pillars.fault_traces.FaultTrace` with a ``surface``) zigzags through
the lattice along cell faces, lateral ones between columns and horizontal ones inside
a column, because every *cell* (not every column) is assigned to a block:

* a cell's centre is the mean of its plan corners and of its eight corner depths in the
  layering between the horizons (the footwall geometry, depth ``c``); its hanging-wall
  displacement is ``d = mean of throw(s_p)`` over its four pillars (minus the tip
  correction, as for vertical faults);
* the cell is in the **footwall** if its undisplaced centre ``(x, y, c)`` lies on the
  footwall side of the fault surface at depth ``c`` (or on it); otherwise in the
  **hanging wall** if its displaced centre ``(x, y, c + d)`` lies on the hanging-wall
  side at depth ``c + d``; otherwise it is **missing section**: for a normal fault
  (surface dipping under the hanging wall, positive throw) the layers cut out between
  the two blocks. A missing-section cell has zero thickness (top = bottom = the bottom
  of the cell above it) and ``process_grdecl`` removes it; the cells above and below
  then meet, or are clamped (next point);
* the corners of a hanging-wall cell on pillar p move down by ``throw(s_p)``, exactly as
  for vertical faults, so the throw between the blocks is exact on every fault face;
* where the last hanging-wall cell of a column reaches below the top of the first
  footwall cell (the throw is smaller than a cell's thickness, or a missing-section
  cell was not removed), the footwall cell's top is clamped to the hanging-wall
  cell's bottom, corner by corner down every pillar: the rule OPM Flow applies to
  ZCORN itself (``ZcornMapper::fixupZCORN``), so Flow reads the deck unchanged.
  Where the cells cut out are thicker than the throw (cells are whole: up to half a
  cell on either side), or the throw is negative (reverse: repeated section cannot be
  represented), a gap opens above the first footwall cell instead; the gaps are
  counted. ``horizons_to_grdecl`` gives such decks PINCH so that the two blocks
  connect across the removed cells;
* several faults: each classifies every cell on its own (with its own throw); the
  displacements of the faults a cell is in the hanging wall of add up, and a cell
  missing for any fault is missing;
* FAULTS segments: the lateral (X, Y) faces of cell k between columns whose cells k
  differ in depth at the shared pillars, named after the first fault that moves the two
  cells differently (at layer k, else at any layer of that pair of columns), and the
  horizontal (Z) faces between a cell and the next non-missing cell below it in another
  block, so ``process_grdecl`` tags every step face with the fault's name and
  MULTFLT applies to all of them.

Vertical faults (no ``surface``) in the same list classify their columns by their
trace in plan view, every layer alike, as
:mod:`~gridlib.pillars.fault_traces` does.

Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..grid import FloatArray
from ..pillars.fault_traces import FaultTrace, nearest_on_trace, pillar_throws
from .deck import FaultSegment, runs

FOOTWALL, HANGING_WALL, MISSING = 0, 1, 2


@dataclass(frozen=True, eq=False)
class StairSteps:
    """The stair-stepped corners of a layering and what was done to them (see the module).

    ``zcorn``: (2 nz, 2 ny, 2 nx) corner depths for the deck, never decreasing down a
    pillar through a column (NaN where the layering is undefined); ``nominal``: the
    layering plus each cell's fault displacement, before missing-section cells are
    collapsed and overlaps clamped; ``block``: (n_faults, nz, ny, nx) FOOTWALL,
    HANGING_WALL or MISSING per fault; ``segments``: the FAULTS lines. Volumes in m3:
    ``missing_volume`` is the layering's volume of the missing-section cells,
    ``clamped_volume`` what the clamps took from the cells below overlaps, so the bulk
    volume of the grid is the layering's minus both.
    """

    zcorn: FloatArray
    nominal: FloatArray
    block: NDArray[np.int8]
    segments: tuple[FaultSegment, ...]
    missing_cells: int
    missing_volume: float
    clamped_cells: int
    clamped_volume: float
    gap_cells: int
    notes: tuple[str, ...]


def is_inclined(trace: Any) -> bool:
    """The fault has an inclined surface (a FaultTrace whose ``surface`` is not vertical)."""
    surface = getattr(trace, "surface", None)
    return surface is not None and not surface.is_vertical


def stair_steps(
    faults: Any, zc: FloatArray, PX: FloatArray, PY: FloatArray, box: tuple[float, float, float, float]
) -> StairSteps:
    """Stair-step the faults into the layering ``zc`` (2 nz, 2 ny, 2 nx) on the pillar lattice
    ``PX``, ``PY`` (ny + 1, nx + 1) of the rectangle ``box`` (xmin, xmax, ymin, ymax).

    >>> from gridlib.pillars.fault_traces import FaultTrace
    >>> PX, PY = np.meshgrid([0.0, 1.0, 2.0], [0.0, 1.0])
    >>> zc = np.concatenate([np.full((1, 2, 4), 1000.0), np.full((1, 2, 4), 1010.0)])  # 2 x 1 x 1 cells
    >>> r = stair_steps([FaultTrace([(1.0, -1.0), (1.0, 2.0)], throw=4.0)], zc, PX, PY, (0, 2, 0, 1))
    >>> r.zcorn[0, 0].tolist(), r.block[0].ravel().tolist()  # vertical fault: the east column moves
    ([1000.0, 1000.0, 1004.0, 1004.0], [0, 1])
    """
    if isinstance(faults, FaultTrace):
        raise InputError("horizons_to_grdecl: faults must be a sequence of FaultTrace, got one FaultTrace")
    nz, ny, nx = (n // 2 for n in zc.shape)
    cells = zc.reshape(nz, 2, ny, 2, nx, 2)
    with np.errstate(invalid="ignore"):
        depth = cells.mean(axis=(1, 3, 5))  # (nz, ny, nx): NaN where the layering is undefined
    defined = np.isfinite(depth)
    cx = 0.25 * (PX[:-1, :-1] + PX[:-1, 1:] + PX[1:, :-1] + PX[1:, 1:])
    cy = 0.25 * (PY[:-1, :-1] + PY[:-1, 1:] + PY[1:, :-1] + PY[1:, 1:])
    j, i, b, a = np.indices((ny, nx, 2, 2))
    corner_pillar = (j + b) * (nx + 1) + (i + a)  # corner (a, b) of column (i, j) is on pillar (i + a, j + b)
    pillars = np.column_stack([PX.ravel(), PY.ravel()])

    names, blocks, x_moves, y_moves = [], [], [], []
    disp = np.zeros((nz, ny, nx, 2, 2))  # [k, j, i, b, a]: downward displacement of every corner
    for f, trace in enumerate(faults):
        if not isinstance(trace, FaultTrace):
            raise InputError(f"faults[{f}]: expected a FaultTrace, got {type(trace).__name__}")
        name = trace.name if trace.name is not None else f"F{f + 1}"
        open_start, open_end = (not _inside(trace.points[e], box) for e in (0, -1))
        t_pillar, t_start, t_end = pillar_throws(trace, f, name, pillars, open_start, open_end)
        throw = t_pillar[corner_pillar]  # (ny, nx, 2, 2)
        block, correction = _blocks(
            trace, (open_start, open_end), (t_start, t_end), cx, cy, depth, defined, throw
        )
        mine = np.where(block == HANGING_WALL, 1.0, 0.0)[..., None, None] * (
            throw[None] - correction[..., None, None]
        )
        disp += mine
        x_move, y_move = _moves_across(mine, block == MISSING)
        names.append(name)
        blocks.append(block)
        x_moves.append(x_move)
        y_moves.append(y_move)
    block = np.stack(blocks).astype(np.int8)
    missing = (block == MISSING).any(axis=0)

    by_corner = disp.transpose(0, 1, 3, 2, 4)[:, None]  # (nz, 1, ny, 2, nx, 2): top and bottom alike
    nominal = zc + np.broadcast_to(by_corner, (nz, 2, ny, 2, nx, 2)).reshape(zc.shape)
    # Only columns whose cells move unlike each other (or lose some) can overlap or open gaps.
    mixed = missing.any(axis=0) | (disp != disp[:1]).any(axis=(0, 3, 4))
    area = ((PX[:-1, 1:] - PX[:-1, :-1]) * (PY[1:, :-1] - PY[:-1, :-1]))[mixed]
    zcorn = nominal.copy()
    kept = defined & ~missing
    settled = _settle(zc, zcorn, mixed, (missing & defined).transpose(1, 2, 0)[mixed], kept, area)

    notes: list[str] = []
    segments = _segments(names, block, np.stack(x_moves), np.stack(y_moves), zcorn, kept, notes)
    note = settle_note(settled)
    if note is not None:
        notes.append(note)
    return StairSteps(zcorn, nominal, block, tuple(segments), *settled, tuple(notes))


def settle_steps(
    layering: FloatArray,
    nominal: FloatArray,
    missing: np.ndarray,
    defined: np.ndarray,
    moved: np.ndarray,
    PX,
    PY,
) -> tuple[FloatArray, Settled]:
    """Stair-stepped corners (2 nz, 2 ny, 2 nx) from ``nominal`` (every cell's corners in its own
    block, before anything is cut out) on the rectilinear pillar lattice ``PX``, ``PY``: the
    ``missing`` cells (nz, ny, nx) collapsed and the overlaps clamped as :func:`stair_steps` does,
    in the columns with a missing cell or flagged in ``moved`` (ny, nx: cells in different
    blocks); and what was cut, clamped and left open. ``defined``: (nz, ny, nx) cells whose
    corners are all defined; ``layering``: the corners the missing volume is measured in."""
    mixed = missing.any(axis=0) | moved
    area = ((PX[:-1, 1:] - PX[:-1, :-1]) * (PY[1:, :-1] - PY[:-1, :-1]))[mixed]
    zcorn = nominal.copy()
    kept = defined & ~missing
    settled = _settle(layering, zcorn, mixed, (missing & defined).transpose(1, 2, 0)[mixed], kept, area)
    return zcorn, settled


def step_segments(
    names: list[str], block: NDArray[np.int8], zcorn: FloatArray, kept: np.ndarray
) -> tuple[list[FaultSegment], list[str]]:
    """FAULTS lines of cells placed per fault: ``block`` (n_faults, nz, ny, nx) FOOTWALL,
    HANGING_WALL or MISSING; a lateral face is named after the first fault whose blocks differ
    across it (at its layer, else in that pair of columns) where the corners are offset, a
    horizontal one as in :func:`stair_steps`; and the notes."""
    x_moves = block[..., :-1] != block[..., 1:]
    y_moves = block[:, :, :-1] != block[:, :, 1:]
    notes: list[str] = []
    return _segments(names, block, x_moves, y_moves, zcorn, kept, notes), notes


def settle_note(settled: Settled) -> str | None:
    """The note of what stair-stepping cut out, clamped and left open, or None."""
    if not (settled.missing_cells or settled.clamped_cells or settled.gap_cells):
        return None
    return (
        f"stair-stepped faults: {settled.missing_cells} cells of missing section (zero thickness; "
        f"{settled.missing_volume:.6g} m3 of the layering), {settled.clamped_cells} cells clamped "
        f"below the cell above (OPM Flow's ZCORN rule; {settled.clamped_volume:.6g} m3), "
        f"{settled.gap_cells} cells with a gap above them (more layers cut out than the throw, "
        "or a reverse throw)"
    )


# --------------------------------------------------------------------------- blocks


def _inside(q: np.ndarray, box) -> bool:
    xmin, xmax, ymin, ymax = box
    return bool(xmin < q[0] < xmax and ymin < q[1] < ymax)


def _blocks(trace: FaultTrace, open_ends, end_throws, cx, cy, depth, defined, throw):
    """Block of every cell (nz, ny, nx) for one fault, and the throw its corners lose beyond a
    tip (that of the tip, else 0)."""
    sign = 1.0 if trace.side == "left" else -1.0
    t_start, t_end = end_throws
    if not is_inclined(trace):  # vertical: the plan-view rule of fault_traces, every layer alike
        seg, t, side = nearest_on_trace(np.column_stack([cx.ravel(), cy.ravel()]), trace.points, *open_ends)
        hanging = (sign * side > 0).reshape(cx.shape)
        correction = _tip_correction(seg, t, trace.points.shape[0] - 1, open_ends, end_throws)
        block = np.where(hanging, HANGING_WALL, FOOTWALL)
        return np.broadcast_to(block, depth.shape), np.broadcast_to(correction.reshape(cx.shape), depth.shape)

    surface = trace.surface
    correction = np.zeros(depth.shape)
    if not all(open_ends) and (t_start != 0.0 or t_end != 0.0):
        x, y = np.broadcast_to(cx, depth.shape)[defined], np.broadcast_to(cy, depth.shape)[defined]
        seg, t = surface.nearest_on_section(x, y, depth[defined], *open_ends)
        n_seg = surface.points.shape[1] - 1
        correction[defined] = _tip_correction(seg, t, n_seg, open_ends, end_throws)
    centre_throw = throw.mean(axis=(2, 3)) - correction  # (nz, ny, nx)
    block = np.full(depth.shape, FOOTWALL, dtype=np.int8)
    steady, hanging_column = _steady_columns(surface, sign, cx, cy, depth, depth + centre_throw, defined)
    block[:, steady & hanging_column] = HANGING_WALL
    cut = defined & ~steady  # columns the surface crosses between their shallowest and deepest test
    z, z_moved = depth[cut], (depth + centre_throw)[cut]
    x, y = np.broadcast_to(cx, depth.shape)[cut], np.broadcast_to(cy, depth.shape)[cut]
    footwall = sign * surface.side_value(x, y, z) <= 0.0
    hanging = sign * surface.side_value(x, y, z_moved) > 0.0
    block[cut] = np.where(footwall, FOOTWALL, np.where(hanging, HANGING_WALL, MISSING))
    return block, correction


def _steady_columns(surface, sign: float, cx, cy, depth, moved, defined) -> tuple[np.ndarray, np.ndarray]:
    """Columns (ny, nx) on one side of the surface at every depth their cells are tested at (the
    undisplaced and displaced centres), and whether that side is the hanging wall: the surface's
    side at the shallowest and the deepest of those depths agree and the vertical line through
    the column does not meet the surface between them. Only the line's shallowest crossing is
    known (FaultSurface.depth_at); if it lies above the range, another one inside the range makes
    the two sides differ, and only a third (a surface folding back on itself) would go unseen."""
    with np.errstate(invalid="ignore"):
        low = np.where(defined, np.minimum(depth, moved), np.inf).min(axis=0)
        high = np.where(defined, np.maximum(depth, moved), -np.inf).max(axis=0)
    column = np.isfinite(low)
    low, high = np.where(column, low, 0.0), np.where(column, high, 0.0)
    top_side = sign * surface.side_value(cx, cy, low)
    base_side = sign * surface.side_value(cx, cy, high)
    crossing = surface.depth_at(cx, cy)
    with np.errstate(invalid="ignore"):
        crossed = (crossing >= low) & (crossing <= high)
    steady = column & (np.sign(top_side) == np.sign(base_side)) & (top_side != 0) & ~crossed
    return steady, top_side > 0


def _tip_correction(seg, t, n_seg: int, open_ends, end_throws) -> np.ndarray:
    """The throw of the tip a point's nearest trace point is, else 0 (fault_traces' rule)."""
    open_start, open_end = open_ends
    beyond_start = (seg == 0) & (t <= 0) & (not open_start)
    beyond_end = (seg == n_seg - 1) & (t >= 1) & (not open_end)
    return np.where(beyond_start, end_throws[0], np.where(beyond_end, end_throws[1], 0.0))


# --------------------------------------------------------------------------- corners


class Settled(NamedTuple):
    """What stair-stepping cut out (cells, m3 of the layering), clamped (cells, m3) and left open
    (cells with a gap above them)."""

    missing_cells: int
    missing_volume: float
    clamped_cells: int
    clamped_volume: float
    gap_cells: int


def _settle(zc: FloatArray, zcorn: FloatArray, mixed, cut_out, kept, area) -> Settled:
    """Collapse the missing-section cells ``cut_out`` (columns, nz) of the columns ``mixed``
    (ny, nx) and clamp their overlaps in ``zcorn`` (in place; ``zc`` the layering); what was cut
    and clamped, and the gaps left (``kept``: (nz, ny, nx) cells neither missing nor undefined,
    ``area``: of every mixed column)."""
    layering, moved = _columns(zc, mixed), _columns(zcorn, mixed)  # (columns, 2 nz, 4 pillars)
    work = _collapse(moved, layering, np.repeat(cut_out, 2, axis=1)[..., None])
    final = _monotone(work)
    _put_columns(zcorn, mixed, final)
    kept_here = kept.transpose(1, 2, 0)[mixed]
    with np.errstate(invalid="ignore"):
        clamped = kept_here & (final != work).reshape(*kept_here.shape, 2, 4).any(axis=(2, 3))
        gaps = (final[:, 2::2] > final[:, 1:-1:2]).any(axis=2) & kept_here[:, 1:]
    return Settled(
        int(cut_out.sum()),
        float(_volumes(layering, area)[cut_out].sum()),
        int(clamped.sum()),
        float((_volumes(work, area) - _volumes(final, area))[clamped].sum()),
        int(gaps.sum()),
    )


def _columns(z: FloatArray, mask: np.ndarray) -> FloatArray:
    """The corner depths (2 nz, 2 ny, 2 nx) of the columns ``mask`` (ny, nx): (columns, 2 nz, 4),
    every pillar's corners down the column, top and bottom of each cell in turn."""
    n2z, n2y, n2x = z.shape
    by_column = z.reshape(n2z, n2y // 2, 2, n2x // 2, 2).transpose(1, 3, 0, 2, 4)
    return by_column[mask].reshape(-1, n2z, 4)


def _put_columns(z: FloatArray, mask: np.ndarray, columns: FloatArray) -> None:
    """Write ``columns`` (as :func:`_columns` gives them) back into ``z``, in place."""
    n2z, n2y, n2x = z.shape
    z.reshape(n2z, n2y // 2, 2, n2x // 2, 2).transpose(1, 3, 0, 2, 4)[mask] = columns.reshape(-1, n2z, 2, 2)


def _collapse(nominal: FloatArray, layering: FloatArray, missing: np.ndarray) -> FloatArray:
    """``nominal`` (columns, 2 nz, 4) with every missing-section corner at the deepest corner above
    it on its pillar (the bottom of the cell above), or, at the top of a column, at the shallowest
    corner below it."""
    with np.errstate(invalid="ignore"):
        above = np.fmax.accumulate(np.where(missing, -np.inf, nominal), axis=1)
        below = np.fmin.accumulate(np.where(missing, np.inf, nominal)[:, ::-1], axis=1)[:, ::-1]
    fill = np.where(np.isfinite(above), above, np.where(np.isfinite(below), below, layering))
    return np.where(missing, fill, nominal)


def _monotone(z: FloatArray) -> FloatArray:
    """Every corner (columns, 2 nz, 4) at least as deep as every corner above it on its pillar
    (OPM Flow's ZCORN fixup, done once); undefined (NaN) corners stay NaN and are skipped."""
    return np.where(np.isnan(z), np.nan, np.fmax.accumulate(z, axis=1))


def _volumes(z: FloatArray, area: FloatArray) -> FloatArray:
    """Volume of every cell (columns, nz) between vertical pillars on a rectilinear lattice: the
    column's area times the mean of the thicknesses at its four pillars (exact: the top and bottom
    are bilinear)."""
    return (z[:, 1::2] - z[:, 0::2]).mean(axis=2) * area[:, None]


# --------------------------------------------------------------------------- FAULTS


def _moves_across(disp: np.ndarray, missing: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where one fault moves cell k differently from cell k of the next column, along i
    (nz, ny, nx - 1) and along j (nz, ny - 1, nx): its displacements (nz, ny, nx, b, a) differ
    at the shared pillars, or one of the cells is missing section and the other not."""
    x_move = (disp[:, :, :-1, :, 1] != disp[:, :, 1:, :, 0]).any(axis=-1) | (
        missing[..., :-1] != missing[..., 1:]
    )
    y_move = (disp[:, :-1, :, 1, :] != disp[:, 1:, :, 0, :]).any(axis=-1) | (
        missing[:, :-1] != missing[:, 1:]
    )
    return x_move, y_move


def _segments(
    names: list[str], block, x_moves, y_moves, zcorn: FloatArray, kept: np.ndarray, notes: list[str]
):
    """FAULTS lines of every fault, fault by fault: X, then Y, then Z faces (see the module)."""
    nz, ny, nx = kept.shape
    z = zcorn.reshape(nz, 2, ny, 2, nx, 2)
    x_offset = ~_same(z[:, :, :, :, :-1, 1], z[:, :, :, :, 1:, 0]).all(axis=(1, 3))  # (nz, ny, nx - 1)
    y_offset = ~_same(z[:, :, :-1, 1], z[:, :, 1:, 0]).all(axis=(1, 4))  # (nz, ny - 1, nx)
    x_cause, x_multi = _cause(x_moves, x_offset)
    y_cause, y_multi = _cause(y_moves, y_offset)
    z_cause, z_multi = _z_cause(block, kept)
    segments: list[FaultSegment] = []
    for f, name in enumerate(names):
        mine = []
        for k, i, j1, j2 in _box_runs((x_cause == f).transpose(0, 2, 1)):  # runs along j per (k, i)
            mine.append(FaultSegment(name, i, i, j1, j2, k, k, "X"))
        for k, j, i1, i2 in _box_runs(y_cause == f):
            mine.append(FaultSegment(name, i1, i2, j, j, k, k, "Y"))
        for k, j, i1, i2 in _box_runs(z_cause == f):
            mine.append(FaultSegment(name, i1, i2, j, j, k, k, "Z"))
        if not mine:
            notes.append(f"fault '{name}' offsets no cell face of the grid")
        segments += mine
    multi = x_multi + y_multi + z_multi
    if multi:
        notes.append(
            f"{multi} cell faces lie between cells in different blocks of two or more faults: "
            "each is named after the first of them"
        )
    return segments


def _same(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return (a == b) | (np.isnan(a) & np.isnan(b))


def _cause(differs: np.ndarray, offset: np.ndarray) -> tuple[np.ndarray, int]:
    """The fault (index, -1 = none) naming each lateral face of cell k (nz, ...): offset in depth,
    and the first fault that moves the cells on its two sides differently at layer k, else at any
    layer of the pair of columns (a clamp below that fault's step)."""
    at_layer = differs.any(axis=0)
    anywhere = differs.any(axis=1, keepdims=True)
    cause = np.where(
        at_layer, differs.argmax(axis=0), np.where(anywhere.any(axis=0), anywhere.argmax(axis=0), -1)
    )
    cause = np.where(offset & (cause >= 0), cause, -1)
    return cause, int(((differs.sum(axis=0) >= 2) & (cause >= 0)).sum())


def _z_cause(block: np.ndarray, kept: np.ndarray) -> tuple[np.ndarray, int]:
    """The fault (index, -1 = none) naming the bottom face of every kept cell: the first fault
    whose block differs between the cell and the next kept cell below it."""
    nz = kept.shape[0]
    k = np.arange(nz)[:, None, None]
    next_kept = np.minimum.accumulate(np.where(kept, k, nz)[::-1], axis=0)[::-1]
    below = np.concatenate([next_kept[1:], np.full((1, *kept.shape[1:]), nz)])
    has_below = kept & (below < nz)
    other = np.take_along_axis(block, np.minimum(below, nz - 1)[None], axis=1)
    differs = (block != other) & has_below[None]
    cause = np.where(differs.any(axis=0), differs.argmax(axis=0), -1)
    return cause, int((differs.sum(axis=0) >= 2).sum())


def _box_runs(mask: np.ndarray):
    """(k, row, first, last) of the runs of True along the last axis of a (nz, rows, n) mask."""
    nz, rows, n = mask.shape
    r, first, last = runs(mask.reshape(nz * rows, n))
    k, row = np.divmod(r, rows)
    return zip(k.tolist(), row.tolist(), first.tolist(), last.tolist(), strict=True)
