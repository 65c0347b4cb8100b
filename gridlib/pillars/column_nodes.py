"""The points on the pillars of the column engine: every distinct depth of a pillar is one node,
numbered by rank along its pillar, then pillar (level-major, as ``make_layered_grid``), with a fast
path for the pillars where every column agrees."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..connectivity import offsets, ragged_arange
from ..grid import FloatArray, IntArray
from .pillar_points import depth_resolution, points_on_pillars, unique_points


@dataclass(frozen=True, eq=False)
class LevelMajor:
    """Node ids of the points on the pillars, numbered by rank along their pillar, then pillar
    (``make_layered_grid``'s level-major order: the nodes of a layer interface are close in
    memory). The first ``dense`` ranks, which every pillar has, are numbered in closed form,
    ``rank * n_pillars + pillar``; the points of higher ranks (on pillars with more points than
    the others: faults, masks) by the position of their key ``rank * n_pillars + pillar`` in the
    sorted ``tail``, after the dense ones."""

    n_pillars: int
    dense: int
    tail: IntArray

    @classmethod
    def of(cls, count: IntArray) -> LevelMajor:
        """The numbering of pillars with ``count[p]`` points."""
        n = count.size
        dense = int(count.min()) if n else 0
        extra = count - dense
        tall = np.flatnonzero(extra)
        rank = ragged_arange(np.full(tall.size, dense), extra[tall])
        tail = rank * n + np.repeat(tall, extra[tall])
        tail.sort()
        return cls(n, dense, tail)

    @property
    def num(self) -> int:
        return self.dense * self.n_pillars + self.tail.size

    def ids(self, rank: IntArray, pillar: IntArray | int) -> IntArray:
        """The id of the point of rank ``rank`` on pillar ``pillar`` (broadcast together)."""
        ids = rank * self.n_pillars + pillar
        if self.tail.size:
            high = np.flatnonzero(ids.reshape(-1) >= self.dense * self.n_pillars)
            flat = ids.reshape(-1)
            flat[high] = self.dense * self.n_pillars + np.searchsorted(self.tail, flat[high])
        return ids

    def keys(self, ids: IntArray) -> IntArray:
        """``rank * n_pillars + pillar`` of the points ``ids`` (1-D)."""
        keys = ids.copy()
        high = np.flatnonzero(ids >= self.dense * self.n_pillars)
        keys[high] = self.tail[ids[high] - self.dense * self.n_pillars]
        return keys

    def rank(self, ids: IntArray) -> IntArray:
        return self.keys(ids) // self.n_pillars


@dataclass(frozen=True, eq=False)
class PillarNodes:
    """The distinct points on the pillars: their ids (:class:`LevelMajor`), depths ``z`` in that
    order, and ``offset`` (n_pillars + 1,) of the pillar-major numbering ``offset[p] + rank`` in
    which the general pillar-pair engine works (``pm_to_ids`` maps those to ours)."""

    ids: LevelMajor
    z: FloatArray
    offset: IntArray

    @property
    def num_nodes(self) -> int:
        return self.z.size

    def pm_to_ids(self, pm: IntArray) -> IntArray:
        pillar = np.searchsorted(self.offset, pm, "right") - 1
        return self.ids.ids(pm - self.offset[pillar], pillar)

    def coords(self, xy: FloatArray, lines: FloatArray | None, n_extra: int) -> FloatArray:
        """(num_nodes + n_extra, 3) node coordinates, the ``n_extra`` last rows left to fill."""
        n, dense, tail = self.ids.n_pillars, self.ids.dense, self.ids.tail
        n_dense = dense * n
        out = np.empty((self.num_nodes + n_extra, 3))
        if lines is None:
            out[:n_dense].reshape(dense, n, 3)[:, :, :2] = xy  # the dense ranks: every pillar in order
            out[n_dense : self.num_nodes, :2] = xy[tail % n]
            out[: self.num_nodes, 2] = self.z
        else:
            pillar = np.concatenate([np.tile(np.arange(n), dense), tail % n])
            points_on_pillars(lines, pillar, self.z, out=out[: self.num_nodes])
        return out


class NodeCoords:
    """``self[pm]``: the coordinates of points given by pillar-major ids (as the general engine
    asks for them), without the whole coordinate array."""

    def __init__(self, pts: PillarNodes, xy: FloatArray, lines: FloatArray | None) -> None:
        self.pts, self.xy, self.lines = pts, xy, lines

    def __getitem__(self, pm: IntArray) -> FloatArray:
        pts = self.pts
        ids = pts.pm_to_ids(pm)
        pillar, z = pts.ids.keys(ids) % pts.ids.n_pillars, pts.z[ids]
        if self.lines is None:
            return np.column_stack([self.xy[pillar], z])
        return points_on_pillars(self.lines, pillar, z)


def number_points(
    z: FloatArray, ring: IntArray, used: np.ndarray | None, nn2: int
) -> tuple[PillarNodes, IntArray]:
    """The distinct points on every pillar and the node (n_levels, n_corners) of every corner.

    ``used`` (n_levels, n_corners): the corners of active cells (None: all).
    Fast path: on a pillar where every corner has the same depth as one
    reference corner at every level (no fault, no masked junk) and those depths
    do not decrease, the points are the reference's distinct depths in level
    order (distinct beyond the pillar's depth resolution). The other pillars
    number the depths of their used corners with
    :func:`~gridlib.pillars.pillar_points.unique_points`, which decides
    distinctness the same way. Unused corners of those get node -1. Node ids
    grow with depth along every pillar.
    """
    n_corners = z.shape[1]
    ref = np.full(nn2, -1, dtype=np.int64)
    ref[ring] = np.arange(n_corners)  # any corner of the pillar will do
    has = ref >= 0
    differ = np.zeros(n_corners, dtype=bool)
    ref_of_corner = ref[ring]
    with np.errstate(invalid="ignore"):
        for level in z:  # a level at a time: small temporaries
            differ |= level != level[ref_of_corner]  # NaN differs from everything
        zp = np.take(z, ref, axis=1)  # (n_levels, nn2); junk where a pillar has no corner
        regular = has & (np.diff(zp, axis=0) >= 0).all(axis=0) & np.isfinite(zp).all(axis=0)
    regular[ring[differ]] = False

    new = np.ones(zp.shape, dtype=bool)
    with np.errstate(invalid="ignore"):  # junk (NaN, inf) on pillars that are not regular: unused
        rho = depth_resolution(np.maximum(np.abs(zp[0]), np.abs(zp[-1])))
        np.greater(zp[1:] - zp[:-1], rho, out=new[1:])  # equal up to rounding: one point
    rank = np.cumsum(new, axis=0)
    rank -= 1
    count = np.where(regular, rank[-1] + 1, 0)

    irr_corner = np.flatnonzero(~regular[ring])
    irr = None
    if irr_corner.size:
        sub = np.ones((z.shape[0], irr_corner.size), bool) if used is None else used[:, irr_corner]
        lev, q = np.nonzero(sub)
        q = irr_corner[q]
        irr = unique_points(ring[q], z[lev, q], nn2)
        count += np.diff(irr.offset)
    ids = LevelMajor.of(count)

    table = ids.ids(rank, np.arange(nn2))  # (n_levels, nn2): node of every level of a regular pillar
    if irr is None and has.all() and ids.num == table.size:  # every level a point of its own
        z_ids = zp.reshape(-1)
    else:
        z_ids = np.empty(ids.num)
        first = new & regular  # the first level at every point of a regular pillar
        z_ids[table[first]] = zp[first]
    if irr is not None:
        irr_rank = np.arange(irr.num_nodes) - irr.offset[irr.pillar]
        irr_ids = ids.ids(irr_rank, irr.pillar)
        z_ids[irr_ids] = irr.z
    node_of = np.take(table, ring, axis=1)
    if irr is not None:
        node_of[:, irr_corner] = -1
        node_of[lev, q] = irr_ids[irr.node_of_corner]
    return PillarNodes(ids, z_ids, offsets(count)), node_of
