"""A well's connections: one row per cell it is completed in, with its connection factor.

:func:`well_connections` turns the pieces of a path inside cells
(:class:`~gridlib.wells.intersect.PathCells`: straight sub-segments in MD order, grouped
in runs, a run being a stay in one cell) into connections:

1. each piece's lengths along its cell's axes (:func:`~gridlib.wells.factors.cell_axes`,
   :func:`~gridlib.wells.factors.axis_lengths`, of the chord exit - entry), **summed per
   run**: a run that bends inside its cell counts the length of each of its pieces along
   each axis. (OPM's COMPTRAJ and ResInsight take the chord from the cell's entry to its
   exit; the two agree for a straight run and differ by the bend of a curved one.)
2. per run the factor and direction of :func:`~gridlib.wells.factors.trajectory_factors`,
   with the radius and skin of the run's first piece.
3. per cell, one connection: a cell entered in two runs (a path that leaves and comes
   back, or, through :func:`merge_connections`, two branches of a multilateral) has the
   **sum** of its runs' factors, lengths and lengths per axis, as ResInsight combines the
   completions of one cell (``RicWellPathExportCompletionDataFeatureImpl::
   combineEclipseCellCompletions``: the factors add; the direction is that of the
   completion with the largest factor). OPM's COMPTRAJ instead replaces a cell's earlier
   connection by the later one (``WellConnections::loadCOMPTRAJ``), which drops the first
   visit's flow; the sum is the factor of the two visits' completions in parallel.

Rows are in MD order of their first entry; a connection's entry (MD and point) is its
first run's, its exit its last run's. Lengths in the grid's length unit, factors in the
unit system's transmissibility unit (:mod:`gridlib.units`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from ..arrays import frozen_array
from ..errors import InputError
from ..geometry import Geometry
from ..grid import FloatArray, Grid, IntArray
from ..units import UnitSystem
from .factors import axis_lengths, cell_axes, trajectory_factors

if TYPE_CHECKING:
    from .intersect import PathCells

__all__ = ["WellConnections", "merge_connections", "well_connections"]

_FIELDS = {  # name: (dtype, trailing shape)
    "cell": (np.int64, ()),
    "entry_md": (np.float64, ()),
    "exit_md": (np.float64, ()),
    "entry": (np.float64, (3,)),
    "exit": (np.float64, (3,)),
    "length": (np.float64, ()),
    "axis_length": (np.float64, (3,)),
    "factor": (np.float64, ()),
    "direction": (np.int64, ()),
}


@dataclass(frozen=True, eq=False)
class WellConnections:
    """The connections of one well, one row per connected cell, in MD order of first entry.

    ``cell`` (n,) rows of the grid; ``entry_md``, ``exit_md`` (n,) the MD where the well
    first enters the cell and last leaves it, ``entry``, ``exit`` (n, 3) those points
    (x, y, depth); ``length`` (n,) the MD length completed in the cell (all its runs);
    ``axis_length`` (n, 3) that length along the cell's x, y, z axes; ``factor`` (n,)
    the connection factor (transmissibility unit); ``direction`` (n,) 0, 1, 2 for the
    COMPDAT direction X, Y, Z. Arrays are read-only.
    """

    cell: IntArray
    entry_md: FloatArray
    exit_md: FloatArray
    entry: FloatArray
    exit: FloatArray
    length: FloatArray
    axis_length: FloatArray
    factor: FloatArray
    direction: IntArray

    def __post_init__(self) -> None:
        n = np.asarray(self.cell).shape[0] if np.ndim(self.cell) else -1
        for name, (dtype, tail) in _FIELDS.items():
            arr = frozen_array(
                getattr(self, name), dtype, f"WellConnections.{name}", 1 + len(tail), copy=True
            )
            if arr.shape != (n, *tail):
                raise ValueError(f"WellConnections.{name}: expected shape {(n, *tail)}, got {arr.shape}")
            object.__setattr__(self, name, arr)

    def __len__(self) -> int:
        return int(self.cell.size)


def well_connections(
    grid: Grid,
    geometry: Geometry,
    permeability: ArrayLike | None,
    ntg: ArrayLike | None,
    pieces: PathCells,
    radius: ArrayLike,
    skin: ArrayLike,
    *,
    units: UnitSystem | str,
    extents: ArrayLike | None = None,
) -> WellConnections:
    """The connections of one well from the ``pieces`` of its (completed) path in the cells
    of a 3-D ``grid`` (module docstring).

    ``permeability`` (mD per cell), ``ntg`` (nc,) or None: as
    :func:`~gridlib.wells.factors.trajectory_factors`; ``radius`` (> 0) and ``skin``: one
    value or one per piece (a run takes its first piece's); ``extents`` (nc, 3): every
    cell's (dx, dy, dz) without NTG, e.g. Flow's from
    :func:`~gridlib.transmissibility.peaceman.deck_cell_extents` (default: from the grid,
    :func:`~gridlib.transmissibility.peaceman.cell_extents`); ``units``: the unit system
    of lengths and factors.
    """
    cell, run, first = _runs(pieces)
    m = cell.size
    if m == 0:
        return _empty()
    rw, s = _per_piece(radius, m, "radius"), _per_piece(skin, m, "skin")
    unique, inverse = np.unique(cell, return_inverse=True)
    axes = cell_axes(grid, geometry, unique)[inverse]
    entry = np.asarray(pieces.entry, dtype=np.float64)
    exit_ = np.asarray(pieces.exit, dtype=np.float64)
    per_piece = axis_lengths(axes, exit_ - entry)
    runs = first.size
    along = np.column_stack([np.bincount(run, per_piece[:, a], runs) for a in range(3)])
    entry_md = np.asarray(pieces.entry_md, dtype=np.float64)
    exit_md = np.asarray(pieces.exit_md, dtype=np.float64)
    length = np.bincount(run, exit_md - entry_md, runs)
    last = np.r_[first[1:], m] - 1
    run_cell = cell[first]
    ext = None
    if extents is not None:
        ext = np.asarray(extents, dtype=np.float64)
        if ext.ndim != 2 or ext.shape != (grid.num_cells, 3):
            raise InputError(f"extents: expected (dx, dy, dz) per grid cell, shape ({grid.num_cells}, 3)")
        ext = ext[run_cell]
    factor, direction = trajectory_factors(
        grid, geometry, permeability, run_cell, along, rw[first], s[first], ntg=ntg, extents=ext, units=units
    )
    rows = WellConnections(
        run_cell, entry_md[first], exit_md[last], entry[first], exit_[last], length, along, factor, direction
    )
    return _combine(rows, np.arange(runs))


def merge_connections(*connections: WellConnections) -> WellConnections:
    """The connections of a multilateral well from those of its branches (the parent first):
    a cell that several branches complete is one connection with the sum of their factors,
    lengths and lengths per axis, its entry from the first branch (in argument order) that
    has it, its exit from the last, its direction the one of the largest factor. Rows in
    the order of their first appearance (branch by branch, each in MD order)."""
    if not connections:
        return _empty()
    rows = WellConnections(
        *(np.concatenate([getattr(c, name) for c in connections]) for name in _FIELDS)  # type: ignore[arg-type]
    )
    return _combine(rows, np.arange(len(rows)))


def _combine(rows: WellConnections, key: IntArray) -> WellConnections:
    """One row per cell of ``rows``: sums of length, axis_length and factor; entry of the
    row of smallest ``key``, exit of the largest; direction of the largest factor (the
    smallest key on ties); rows ordered by their smallest key."""
    if len(rows) == 0:
        return rows
    order = np.lexsort((key, rows.cell))
    cell = rows.cell[order]
    start = np.flatnonzero(np.r_[True, cell[1:] != cell[:-1]])
    end = np.r_[start[1:], cell.size] - 1
    lo, hi = order[start], order[end]
    sums = {
        name: np.add.reduceat(getattr(rows, name)[order], start, axis=0)
        for name in ("length", "axis_length", "factor")
    }
    strongest = np.lexsort((key, -rows.factor, rows.cell))[start]  # per cell (same sorted cells)
    out = np.argsort(key[lo], kind="stable")
    return WellConnections(
        cell=cell[start][out],
        entry_md=rows.entry_md[lo][out],
        exit_md=rows.exit_md[hi][out],
        entry=rows.entry[lo][out],
        exit=rows.exit[hi][out],
        length=sums["length"][out],
        axis_length=sums["axis_length"][out],
        factor=sums["factor"][out],
        direction=rows.direction[strongest][out],
    )


def _runs(pieces: PathCells) -> tuple[IntArray, IntArray, IntArray]:
    """The pieces' cells, run ids and the first piece of each run, checked: runs numbered 0,
    1, ... in order, each in one cell."""
    cell = np.asarray(pieces.cell, dtype=np.int64)
    run = np.asarray(pieces.run, dtype=np.int64)
    m = cell.size
    shapes = {
        name: np.shape(getattr(pieces, name))
        for name in ("cell", "run", "entry_md", "exit_md", "entry", "exit")
    }
    expected = {name: (m, 3) if name in ("entry", "exit") else (m,) for name in shapes}
    if shapes != expected:
        raise InputError(f"pieces: inconsistent shapes {shapes} (expected {m} pieces)")
    if m == 0:
        return cell, run, np.zeros(0, dtype=np.int64)
    step = np.diff(run)
    if run[0] != 0 or ((step != 0) & (step != 1)).any():
        raise InputError("pieces: run ids must be 0, 1, ... in MD order")
    first = np.flatnonzero(np.r_[True, step == 1])
    if (cell[1:] != cell[:-1])[step == 0].any():
        raise InputError("pieces: a run's pieces must all be in one cell")
    return cell, run, first


def _per_piece(value: ArrayLike, m: int, what: str) -> FloatArray:
    v = np.asarray(value, dtype=np.float64)
    if v.ndim == 0:
        return np.full(m, float(v))
    if v.shape != (m,):
        raise InputError(f"{what}: expected one value or one per piece ({m}), got shape {v.shape}")
    return v


def _empty() -> WellConnections:
    z = np.zeros(0)
    return WellConnections(
        np.zeros(0, np.int64),
        z,
        z,
        np.zeros((0, 3)),
        np.zeros((0, 3)),
        z,
        np.zeros((0, 3)),
        z,
        np.zeros(0, np.int64),
    )
