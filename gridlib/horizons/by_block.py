"""Horizons of already-faulted surfaces: one surface per fault block, and corner-point cells that
take their corners from their own block's surfaces.

Picks of a horizon that a fault has offset (seismic interpretation, well tops) hold the throw
themselves. Interpolated across the trace, the offset would be smeared over the cells next to
it; interpolated per block (:func:`block_horizons`), each block's surface is made from its own
picks only and extended over the whole lattice with the horizon's ``extrapolation``
(``trend`` or ``nearest``: each block's cells next to a fault need their surface a little
beyond the block). :func:`horizons_to_grdecl_by_block` then builds one corner-point deck per
block and gives every cell (classified by its centre) the corners of its own block: the throw
appears as an exact offset along the stair-stepped trace, and ``process_grdecl`` finds the
fault faces and their non-neighbour connections as in any faulted deck.

A trace that ends inside the area (a tip) does not separate blocks; there the picks on both
sides are interpolated together (:func:`~gridlib.horizons.fault_blocks` notes it).

An inclined fault (a ``surface``) is given by its footwall cut-off, its trace where it meets
the top of the block on its footwall side (:func:`~gridlib.horizons.blocks.footwall_top`):
picks and cells go to blocks by the surface at their own depth, and the throw in the picks
appears as stair steps (:mod:`~gridlib.cornerpoint.stair_steps`: lateral and horizontal fault
faces, the section a normal fault cut out removed).
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ..cornerpoint.between_horizons import PINCH_THRESHOLD, horizons_to_grdecl
from ..cornerpoint.deck import Deck
from ..cornerpoint.stair_steps import (
    FOOTWALL,
    HANGING_WALL,
    MISSING,
    is_inclined,
    settle_note,
    settle_steps,
    step_segments,
)
from ..errors import InputError
from ..grid import FloatArray
from ..pillars.fault_traces import FaultTrace, nearest_on_trace
from ..pillars.horizon_maps import Horizon
from .blocks import FaultBlocks, fault_blocks, with_surfaces


def block_horizons(ds: xr.Dataset) -> tuple[list[list[Horizon]], FaultBlocks] | None:
    """The per-block horizon stacks of a horizons Dataset made with ``per_block=True``
    (``depth_by_block`` (fault_block, horizon, y, x)) and the fault blocks they refer to; None for a
    Dataset without them."""
    if "depth_by_block" not in ds:
        return None
    x, y = ds["x"].values, ds["y"].values
    depth = ds["depth_by_block"].values
    attrs = ds["depth_by_block"].attrs
    traces = [np.asarray(t, dtype=np.float64).reshape(-1, 2) for t in json.loads(attrs["traces"])]
    extent = tuple(float(v) for v in np.ravel(attrs["extent"]))
    stacks = [[Horizon(x, y, depth[b, k]) for k in range(depth.shape[1])] for b in range(depth.shape[0])]
    return stacks, fault_blocks(traces, extent)


def horizons_to_grdecl_by_block(
    stacks: Sequence[Sequence[Horizon]],
    blocks: FaultBlocks,
    dims: Sequence[int] | None = None,
    layers: int | Sequence[int] = 1,
    faults: Sequence[FaultTrace] = (),
    *,
    ordering: str = "error",
) -> Deck:
    """A corner-point deck whose cells take their corners from their own block's horizons.

    ``stacks[b]``: the horizons of fault block ``b`` of ``blocks`` (top first, each defined
    over the whole lattice); ``dims``, ``layers``, ``ordering``: as
    :func:`~gridlib.cornerpoint.between_horizons.horizons_to_grdecl`. ``faults``: the traces, with no
    throw (the offset is in the surfaces), recorded as FAULTS so that the fault faces carry
    their names. With vertical faults only, every column belongs to the block that contains its
    centre in plan. With an inclined fault (a ``surface``; ``blocks`` cut by the same traces)
    every *cell* is placed as :mod:`~gridlib.cornerpoint.stair_steps` places it: it belongs to
    block b if its centre in block b's layering (plan centre, mean of its eight corner depths)
    lies in block b by the fault surfaces at that depth
    (:meth:`~gridlib.horizons.blocks.FaultBlocks.classify`); of several such blocks (a repeated
    section) the deepest; of none, it is missing section (a normal fault's cut-out layers: zero
    thickness, the cells above and below meet, overlaps clamped as OPM Flow would, PINCH set).
    The fault faces (lateral and horizontal steps) are named after the fault whose sides differ
    across them.

    >>> from gridlib.horizons import fault_blocks
    >>> x, y = np.linspace(0.0, 1000.0, 11), np.linspace(0.0, 500.0, 6)
    >>> west = [Horizon(x, y, np.full((6, 11), d)) for d in (1000.0, 1050.0)]
    >>> east = [Horizon(x, y, np.full((6, 11), d)) for d in (1030.0, 1080.0)]  # 30 m lower
    >>> trace = [(500.0, -10.0), (500.0, 510.0)]
    >>> deck = horizons_to_grdecl_by_block(
    ...     [west, east], fault_blocks([trace], (0.0, 1000.0, 0.0, 500.0)), [10, 5], 2,
    ...     [FaultTrace(trace, throw=0.0, name="F")])
    >>> z = deck.zcorn.reshape(4, 10, 20)  # (2 nz, 2 ny, 2 nx): the top of the first layer
    >>> z[0, 0, [0, 9, 10, 19]].tolist(), deck.faults[0].name
    ([1000.0, 1000.0, 1030.0, 1030.0], 'F')
    """
    if len(stacks) != blocks.num:
        raise InputError(f"horizons_to_grdecl_by_block: {len(stacks)} horizon stacks for {blocks.num} blocks")
    moving = [f.name or f"fault {k}" for k, f in enumerate(faults) if _has_throw(f)]
    if moving:
        raise InputError(
            f"horizons_to_grdecl_by_block: the offset is in the per-block surfaces; faults {moving} "
            "must not have a throw as well"
        )
    decks = [horizons_to_grdecl(list(s), dims, layers, ordering=ordering) for s in stacks]
    first = decks[0]
    lines = np.stack([d.coord.reshape(-1, 6) for d in decks])  # (blocks, pillars, top xyz + bottom xyz)
    for d, line in zip(decks[1:], lines[1:], strict=True):
        if d.cart_dims != first.cart_dims or not np.array_equal(
            line[:, [0, 1, 3, 4]], lines[0][:, [0, 1, 3, 4]]
        ):
            raise InputError(
                "horizons_to_grdecl_by_block: the blocks' horizons span different areas (give every "
                "block the same lattice, defined everywhere)"
            )
    coord = lines[0].copy()  # vertical pillars: the same lines, from the shallowest top to the deepest base
    coord[:, 2], coord[:, 5] = lines[:, :, 2].min(axis=0), lines[:, :, 5].max(axis=0)
    nx, ny, nz = first.cart_dims
    pillars = coord.reshape(ny + 1, nx + 1, 6)
    if any(is_inclined(f) for f in faults):
        return _stepped(decks, coord, pillars, with_surfaces(blocks, faults), faults)
    cx = 0.25 * (pillars[:-1, :-1, 0] + pillars[1:, :-1, 0] + pillars[:-1, 1:, 0] + pillars[1:, 1:, 0])
    cy = 0.25 * (pillars[:-1, :-1, 1] + pillars[1:, :-1, 1] + pillars[:-1, 1:, 1] + pillars[1:, 1:, 1])
    column_block = blocks.classify(cx, cy)  # (ny, nx)
    corner_block = np.repeat(np.repeat(column_block, 2, axis=0), 2, axis=1)  # (2 ny, 2 nx)
    corner_block = np.broadcast_to(corner_block, (2 * nz, 2 * ny, 2 * nx)).ravel()
    zcorn = _pick(np.stack([d.zcorn for d in decks]), corner_block)
    cell_block = np.broadcast_to(column_block, (nz, ny, nx)).ravel()
    actnum = _pick(np.stack([_actnum(d) for d in decks]), cell_block).astype(np.int32)
    segments: tuple = ()
    if faults:  # the stair-stepped faces of each trace, as FAULTS: where a unit throw would offset cells
        unit = [
            FaultTrace(f.points, throw=1.0, name=f.name or f"F{k + 1}", side=f.side)
            for k, f in enumerate(faults)
        ]
        segments = horizons_to_grdecl(list(stacks[0]), dims, layers, unit, ordering=ordering).faults
    counts = np.bincount(column_block.ravel(), minlength=blocks.num)
    note = f"horizons_to_grdecl_by_block: {blocks.num} fault blocks, columns per block {counts.tolist()}"
    return replace(
        first,
        coord=coord.ravel(),
        zcorn=zcorn,
        faults=segments,
        actnum=actnum,
        notes=(*first.notes, *blocks.notes, note),
        source=f"{first.source} (per fault block)",
    )


def _stepped(decks: list[Deck], coord, pillars, blocks: FaultBlocks, faults: Sequence[FaultTrace]) -> Deck:
    """The deck whose cells are placed by the inclined faults' surfaces at their depth (see
    :func:`horizons_to_grdecl_by_block`)."""
    first = decks[0]
    nx, ny, nz = first.cart_dims
    PX, PY = pillars[..., 0], pillars[..., 1]
    zcs = np.stack([d.zcorn_array() for d in decks])  # (blocks, 2 nz, 2 ny, 2 nx)
    cell_block, cell_depth, missing = _place_cells(zcs, PX, PY, blocks)
    corner_block = np.broadcast_to(cell_block[:, None, :, None, :, None], (nz, 2, ny, 2, nx, 2)).reshape(
        zcs.shape[1:]
    )
    nominal = np.take_along_axis(zcs, corner_block[None], axis=0)[0]
    defined = np.isfinite(cell_depth)
    moved = (cell_block != cell_block[:1]).any(axis=0)
    zcorn, settled = settle_steps(nominal, nominal, missing, defined, moved, PX, PY)
    names = [f.name or f"F{k + 1}" for k, f in enumerate(faults)]
    sides = _fault_sides(faults, PX, PY, cell_depth, missing)
    segments, notes = step_segments(names, sides, zcorn, defined & ~missing)
    actnum = _pick(np.stack([_actnum(d) for d in decks]), cell_block.ravel()).astype(np.int32)
    counts = np.bincount(cell_block[~missing & defined], minlength=blocks.num)
    notes.append(
        f"horizons_to_grdecl_by_block: {blocks.num} fault blocks, each cell placed by the inclined fault "
        f"surfaces at its depth; cells per block {counts.tolist()}"
    )
    note = settle_note(settled)
    if note is not None:
        notes.append(note)
    pinch = (PINCH_THRESHOLD, 1e20) if settled.missing_cells or settled.gap_cells else None
    return replace(
        first,
        coord=coord.ravel(),
        zcorn=zcorn.ravel(),
        faults=tuple(segments),
        actnum=actnum,
        pinch=pinch,
        notes=(*first.notes, *blocks.notes, *notes),
        source=f"{first.source} (per fault block, stair-stepped)",
    )


def _place_cells(zcs: FloatArray, PX, PY, blocks: FaultBlocks):
    """Every cell's block (nz, ny, nx), its centre depth there, and whether it is missing section
    (no block's layering puts it in that block; then its block is the one its plan centre is in).
    Only the columns an inclined surface crosses (:func:`_crossed_columns`) are placed cell by
    cell; the others' cells are all in the block of their plan centre."""
    n_blocks, n2z, n2y, n2x = zcs.shape
    nz, ny, nx = n2z // 2, n2y // 2, n2x // 2
    with np.errstate(invalid="ignore"):
        depth = zcs.reshape(n_blocks, nz, 2, ny, 2, nx, 2).mean(axis=(2, 4, 6))
    cx = 0.25 * (PX[:-1, :-1] + PX[:-1, 1:] + PX[1:, :-1] + PX[1:, 1:])
    cy = 0.25 * (PY[:-1, :-1] + PY[:-1, 1:] + PY[1:, :-1] + PY[1:, 1:])
    plan = np.broadcast_to(blocks.classify(cx, cy), (nz, ny, nx))
    crossed = np.broadcast_to(_crossed_columns(blocks, cx, cy, depth), (nz, ny, nx))
    x, y = np.broadcast_to(cx, (nz, ny, nx))[crossed], np.broadcast_to(cy, (nz, ny, nx))[crossed]
    own = np.zeros((n_blocks, x.size), dtype=bool)  # [b]: the cell's centre in block b's layering is in b
    for b in range(n_blocks):
        z = depth[b][crossed]
        ok = np.isfinite(z)
        own[b, ok] = blocks.classify(x[ok], y[ok], z[ok]) == b
    placed = own.any(axis=0)
    deepest = np.where(own, depth[:, crossed], -np.inf).argmax(axis=0)
    cell_block = plan.copy()
    cell_block[crossed] = np.where(placed, deepest, plan[crossed])
    cell_depth = np.take_along_axis(depth, cell_block[None], axis=0)[0]
    missing = np.zeros((nz, ny, nx), dtype=bool)
    missing[crossed] = ~placed & np.isfinite(cell_depth[crossed])
    return cell_block, cell_depth, missing


def _crossed_columns(blocks: FaultBlocks, cx, cy, depth) -> np.ndarray:
    """Columns (ny, nx) whose centre line may meet an inclined fault's surface within the depths
    of its cells in any block: not on the side of its trace in plan at the shallowest and the
    deepest of those depths, or crossing the surface between them (only the shallowest crossing
    is known, FaultSurface.depth_at: a surface folding back on itself could hide a second one, as
    in :mod:`~gridlib.cornerpoint.stair_steps`)."""
    with np.errstate(invalid="ignore"):
        low = np.nanmin(np.where(np.isfinite(depth), depth, np.inf), axis=(0, 1))
        high = np.nanmax(np.where(np.isfinite(depth), depth, -np.inf), axis=(0, 1))
    defined = np.isfinite(low)
    low, high = np.where(defined, low, 0.0), np.where(defined, high, 0.0)
    crossed = np.zeros(cx.shape, dtype=bool)
    for line, surface in zip(blocks.lines, blocks.surfaces, strict=True):
        if surface is None or surface.is_vertical:
            continue
        _, _, plan = nearest_on_trace(np.column_stack([cx.ravel(), cy.ravel()]), line, True, True)
        side = np.sign(plan.reshape(cx.shape))
        top, base = np.sign(surface.side_value(cx, cy, low)), np.sign(surface.side_value(cx, cy, high))
        crossing = surface.depth_at(cx, cy)
        with np.errstate(invalid="ignore"):
            between = (crossing >= low) & (crossing <= high)
        crossed |= (side == 0) | (top != side) | (base != side) | between
    return crossed & defined


def _fault_sides(faults: Sequence[FaultTrace], PX, PY, cell_depth, missing) -> np.ndarray:
    """(fault, nz, ny, nx) FOOTWALL, HANGING_WALL or MISSING: every cell's side of every fault,
    by its surface at the cell's centre depth (a vertical one: its trace in plan). A missing cell
    is missing for the faults that refuse it its plan-view block (their side at its depth there
    is not their side in plan), or for all if none does."""
    nz, ny, nx = cell_depth.shape
    cx = 0.25 * (PX[:-1, :-1] + PX[:-1, 1:] + PX[1:, :-1] + PX[1:, 1:])
    cy = 0.25 * (PY[:-1, :-1] + PY[:-1, 1:] + PY[1:, :-1] + PY[1:, 1:])
    box = (PX.min(), PX.max(), PY.min(), PY.max())
    hanging = np.empty((len(faults), nz, ny, nx), dtype=bool)
    refuses = np.zeros_like(hanging)
    for f, trace in enumerate(faults):
        sign = 1.0 if trace.side == "left" else -1.0
        open_ends = [not _inside(trace.points[e], box) for e in (0, -1)]
        _, _, side = nearest_on_trace(np.column_stack([cx.ravel(), cy.ravel()]), trace.points, *open_ends)
        in_plan = np.broadcast_to((sign * side > 0).reshape(ny, nx), cell_depth.shape)
        hanging[f] = in_plan
        if is_inclined(trace):
            x, y = np.broadcast_to(cx, cell_depth.shape), np.broadcast_to(cy, cell_depth.shape)
            with np.errstate(invalid="ignore"):
                hanging[f] = sign * trace.surface.side_value(x, y, np.nan_to_num(cell_depth)) > 0.0
            refuses[f] = missing & (hanging[f] != in_plan)
    refuses |= (missing & ~refuses.any(axis=0))[None]
    return np.where(refuses, MISSING, np.where(hanging, HANGING_WALL, FOOTWALL)).astype(np.int8)


def _inside(q: np.ndarray, box) -> bool:
    xmin, xmax, ymin, ymax = box
    return bool(xmin < q[0] < xmax and ymin < q[1] < ymax)


def _has_throw(fault: FaultTrace) -> bool:
    throw = fault.throw
    if callable(throw):
        return True
    return bool(np.any(np.asarray(throw, dtype=np.float64) != 0.0))


def _actnum(deck: Deck) -> np.ndarray:
    nx, ny, nz = deck.cart_dims
    return np.ones(nx * ny * nz, dtype=np.int32) if deck.actnum is None else np.asarray(deck.actnum)


def _pick(values: ArrayLike, which: np.ndarray) -> np.ndarray:
    """``values[which[i], i]`` for every i."""
    v = np.asarray(values)
    return np.take_along_axis(v, which[None, :], axis=0)[0].copy()
