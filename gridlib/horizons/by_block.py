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
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ..cornerpoint.between_horizons import horizons_to_grdecl
from ..cornerpoint.deck import Deck
from ..errors import InputError
from ..pillars.fault_traces import FaultTrace
from ..pillars.horizon_maps import Horizon
from .blocks import FaultBlocks, fault_blocks


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
    their names. Every cell belongs to the block that contains its centre.

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
