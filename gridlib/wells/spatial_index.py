"""A spatial index over a 3-D grid's cells: their bounding boxes binned on a uniform 3-D lattice.

Built once per grid (:func:`cell_index`) and reused for every well: the cells near a set of
segments (:func:`segment_cells`) or holding a set of points (:func:`point_cells`) are found
by looking up the bins the query touches, with no loop over cells or queries.

Bins are boxes of a uniform lattice over the grid's bounding box, twice the median cell
extent along each axis (so a reservoir grid of thin layers gets flat bins), enlarged where
needed so that there are at most 8 bins per cell. A cell no larger than a bin along every
axis (nearly all of them) is listed once, in the bin of its box's lower corner, so a query
looks from one bin below its own lower corner up; a larger cell is listed in every bin its
box overlaps, and reported once, from the bin holding the lower corner of its overlap with
the query. Bounding boxes are padded by 1e-9 of the grid's extent (plus a few ulps of its
coordinates), so that points on a cell's surface, computed with rounding, are still in its
box. Lengths in the grid's unit; z is depth.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..arrays import frozen_array
from ..connectivity import offsets, ragged_arange, repeat_ids
from ..errors import GridError
from ..geometry import Geometry
from ..grid import FloatArray, Grid, IntArray

BINS_PER_CELL = 8  # at most this many bins per cell (the lattice is coarsened beyond)
BIN_CELLS = 2.0  # a bin is this many median cell extents along each axis
PAD = 1e-9  # bounding boxes grow by this fraction of the grid's extent


@dataclass(frozen=True, eq=False)
class CellIndex:
    """Padded cell bounding boxes ``lo``/``hi`` (nc, 3) and the lattice of bins: ``origin`` (3,),
    bin ``size`` (3,), ``shape`` (bins per axis, x fastest in a bin's number), the cells listed
    in bin b, ``cells[pos[b]:pos[b + 1]]``, and which cells are ``big`` (larger than a bin,
    listed in every bin they overlap; the others in the bin of their lower corner)."""

    lo: FloatArray
    hi: FloatArray
    origin: FloatArray
    size: FloatArray
    shape: tuple[int, int, int]
    pos: IntArray
    cells: IntArray
    big: np.ndarray
    pad: float

    def __post_init__(self) -> None:
        for name, ndim in (("lo", 2), ("hi", 2), ("origin", 1), ("size", 1)):
            object.__setattr__(self, name, frozen_array(getattr(self, name), np.float64, name, ndim))
        for name in ("pos", "cells"):
            object.__setattr__(self, name, frozen_array(getattr(self, name), np.int64, name, 1))
        object.__setattr__(self, "big", frozen_array(self.big, np.bool_, "big", 1))

    @property
    def num_cells(self) -> int:
        return self.lo.shape[0]


def cell_boxes(grid: Grid) -> tuple[FloatArray, FloatArray]:
    """The bounding box (lo, hi), (nc, 3) each, of every cell of a 3-D grid: the extremes of
    its faces' nodes."""
    npos, fpos = grid.faces.node_pos, grid.cells.face_pos
    if np.any(np.diff(npos) == 0) or np.any(np.diff(fpos) == 0):
        raise GridError("cell_index: every face needs nodes and every cell faces")
    lo = np.empty((grid.num_cells, 3))
    hi = np.empty((grid.num_cells, 3))
    for axis in range(3):
        v = np.ascontiguousarray(grid.nodes.coords[:, axis])[grid.faces.nodes]
        face_lo = np.minimum.reduceat(v, npos[:-1])
        face_hi = np.maximum.reduceat(v, npos[:-1])
        del v
        lo[:, axis] = np.minimum.reduceat(face_lo[grid.cells.faces], fpos[:-1])
        hi[:, axis] = np.maximum.reduceat(face_hi[grid.cells.faces], fpos[:-1])
    return lo, hi


def cell_index(grid: Grid, geometry: Geometry | None = None) -> CellIndex:
    """The spatial index of a 3-D grid's cells (module docstring). ``geometry`` is not needed
    (the boxes come from the nodes); when given, it must be the grid's (one volume per cell)."""
    if grid.griddim != 3 or grid.dim != 3:
        raise GridError("cell_index: a well path needs a 3-D grid")
    if geometry is not None and geometry.cell_volumes.size != grid.num_cells:
        raise GridError("cell_index: the geometry is not this grid's (a different number of cells)")
    lo, hi = cell_boxes(grid)
    glo, ghi = lo.min(axis=0), hi.max(axis=0)
    extent = float(np.max(ghi - glo))
    pad = PAD * extent + 8.0 * float(np.spacing(np.max(np.abs(np.concatenate([glo, ghi])))))
    lo -= pad
    hi += pad
    glo, ghi = glo - pad, ghi + pad
    span = ghi - glo
    size = BIN_CELLS * np.median(hi - lo, axis=0)
    size = np.where(size > 0, size, span)
    shape = np.maximum(np.ceil(span / size), 1)
    while float(np.prod(shape)) > BINS_PER_CELL * grid.num_cells:  # coarsen: a few steps at most
        size = size * 1.25
        shape = np.maximum(np.ceil(span / size), 1)
    shape = tuple(int(n) for n in shape)
    big = np.any(hi - lo > size, axis=1)
    index = CellIndex(lo, hi, glo, size, shape, np.zeros(2, np.int64), np.zeros(0, np.int64), big, pad)
    large = np.flatnonzero(big)
    box, big_bins = _box_bins(index, lo[large], hi[large])
    cell = np.concatenate([np.flatnonzero(~big), large[box]])
    bins = np.concatenate([_bin_of(index, lo[~big]), big_bins])
    order = np.argsort(bins, kind="stable")
    pos = offsets(np.bincount(bins, minlength=int(np.prod(shape))))
    return CellIndex(lo, hi, glo, size, shape, pos, cell[order], big, pad)


def _bin_range(index: CellIndex, lo: FloatArray, hi: FloatArray) -> tuple[IntArray, IntArray]:
    """The first and last bin along each axis, (k, 3) each, that boxes lo..hi overlap
    (clipped to the lattice)."""
    top = np.asarray(index.shape) - 1
    first = np.clip(np.floor((lo - index.origin) / index.size), 0, top).astype(np.int64)
    last = np.clip(np.floor((hi - index.origin) / index.size), 0, top).astype(np.int64)
    return first, last


def _bin_of(index: CellIndex, p: FloatArray) -> IntArray:
    """The bin holding each point p (k, 3), clipped to the lattice."""
    ijk = _bin_range(index, p, p)[0]
    return ijk[:, 0] + index.shape[0] * (ijk[:, 1] + index.shape[1] * ijk[:, 2])


def _box_bins(index: CellIndex, lo: FloatArray, hi: FloatArray) -> tuple[IntArray, IntArray]:
    """(box, bin) for every bin each box lo..hi (k, 3) overlaps, box-major; boxes wholly
    outside the lattice overlap none."""
    inside = np.all(hi >= index.origin, axis=1) & np.all(
        lo <= index.origin + index.size * index.shape, axis=1
    )
    first, last = _bin_range(index, lo, hi)
    n = np.where(inside[:, None], last - first + 1, 0)
    counts = n[:, 0] * n[:, 1] * n[:, 2]
    box = repeat_ids(offsets(counts))
    local = ragged_arange(np.zeros_like(counts), counts)
    nx, ny = n[box, 0], n[box, 1]
    i = first[box, 0] + local % nx
    j = first[box, 1] + (local // nx) % ny
    k = first[box, 2] + local // (nx * ny)
    return box, i + index.shape[0] * (j + index.shape[1] * k)


def box_cells(index: CellIndex, lo: FloatArray, hi: FloatArray) -> tuple[IntArray, IntArray]:
    """(box, cell): every cell whose bounding box overlaps box lo..hi (k, 3), once, box-major."""
    box, bins = _box_bins(index, lo - index.size, hi)  # from a bin below: small cells' corners
    n = index.pos[bins + 1] - index.pos[bins]
    box = np.repeat(box, n)
    cell = index.cells[ragged_arange(index.pos[bins], n)]
    bins = np.repeat(bins, n)
    overlap = np.all(index.lo[cell] <= hi[box], axis=1) & np.all(index.hi[cell] >= lo[box], axis=1)
    box, cell, bins = box[overlap], cell[overlap], bins[overlap]
    big = index.big[cell]
    corner = np.maximum(index.lo[cell[big]], lo[box[big]])  # the overlap's lower corner: one bin
    once = ~big
    once[big] = _bin_of(index, corner) == bins[big]
    return box[once], cell[once]


def point_cells(index: CellIndex, p: FloatArray) -> tuple[IntArray, IntArray]:
    """(point, cell): every cell whose bounding box holds point p (k, 3), point-major."""
    return box_cells(index, p, p)


def segment_cells(index: CellIndex, a: FloatArray, b: FloatArray) -> tuple[IntArray, IntArray]:
    """(segment, cell): every cell whose bounding box the segment a -> b (k, 3 each) passes
    through, once, sorted by segment then cell.

    Segments are cut into pieces at most one bin long along every axis; each piece's box is
    looked up (:func:`box_cells`) and the cells kept whose box the piece really crosses (slab
    test)."""
    d = b - a
    cuts = np.maximum(np.ceil(np.max(np.abs(d) / index.size, axis=1)), 1).astype(np.int64)
    seg = repeat_ids(offsets(cuts))
    k = ragged_arange(np.zeros_like(cuts), cuts)
    t0, t1 = k / cuts[seg], (k + 1) / cuts[seg]
    p = a[seg] + t0[:, None] * d[seg]
    q = np.where((k + 1 == cuts[seg])[:, None], b[seg], a[seg] + t1[:, None] * d[seg])
    sub, cell = box_cells(index, np.minimum(p, q), np.maximum(p, q))
    hit = _slab(index.lo[cell], index.hi[cell], p[sub], q[sub])
    key = np.unique(seg[sub[hit]] * index.num_cells + cell[hit])
    return key // index.num_cells, key % index.num_cells


def _slab(lo: FloatArray, hi: FloatArray, p: FloatArray, q: FloatArray) -> np.ndarray:
    """Whether each segment p -> q meets the box lo..hi (all (k, 3)): the slab test."""
    d = q - p
    with np.errstate(divide="ignore", invalid="ignore"):
        ta = (lo - p) / d
        tb = (hi - p) / d
    flat = d == 0  # parallel to a slab: inside it or not at all
    inside = (p >= lo) & (p <= hi)
    t_in = np.where(flat, np.where(inside, -np.inf, np.inf), np.minimum(ta, tb)).max(axis=1)
    t_out = np.where(flat, np.where(inside, np.inf, -np.inf), np.maximum(ta, tb)).min(axis=1)
    return (t_in <= t_out) & (t_out >= 0.0) & (t_in <= 1.0)
