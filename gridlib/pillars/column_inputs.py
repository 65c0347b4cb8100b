"""The inputs of the column engine (:func:`~gridlib.pillars.columns.extrude_columns`), checked:
the corners of the areal cells, the depths at every corner and level, the active cells, the
pillars' lines, the edge tags and fault names, and the orientation of the areal grid."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..connectivity import half_face_cycle_slots, repeat_ids
from ..errors import GridError, InputError
from ..grid import FloatArray, Grid, IntArray


def check_areal(areal: Grid) -> None:
    """Raise a :class:`~gridlib.errors.GridError` unless ``areal`` is a 2-D grid."""
    if not isinstance(areal, Grid) or areal.griddim != 2:
        what = f"a {areal.griddim}-D grid" if isinstance(areal, Grid) else type(areal).__name__
        raise GridError(f"areal: expected a 2-D grid (griddim 2), got {what}")


@dataclass(frozen=True, eq=False)
class ColumnCorners:
    """The corners of the areal cells: ring ``pos``/``ring``, the cell of every corner, and for
    every areal half-face (entry h of ``cells.faces``) the corner of its first and second node
    walking with the cell on the left; ``perm`` maps corners to the caller's order."""

    pos: IntArray
    ring: IntArray
    owner: IntArray
    hf_first: IntArray
    hf_second: IntArray
    perm: IntArray | None = None

    @classmethod
    def of(cls, areal: Grid) -> ColumnCorners:
        if not isinstance(areal, Grid) or areal.griddim != 2:
            check_areal(areal)  # raises
        start, slot = half_face_cycle_slots(areal)
        pos = areal.cells.face_pos
        ring = np.empty_like(start)
        ring[slot] = start
        owner = repeat_ids(pos)
        nxt = np.arange(1, ring.size + 1)
        nxt[pos[1:] - 1] = pos[:-1]
        return cls(pos, ring, owner, slot, nxt[slot])

    @property
    def num(self) -> int:
        return self.ring.size

    def reversed(self) -> ColumnCorners:
        """Every ring walked backwards (a reversal within each cell is its own inverse)."""
        local = np.arange(self.num) - self.pos[self.owner]
        perm = self.pos[self.owner] + (np.diff(self.pos)[self.owner] - 1 - local)
        return ColumnCorners(
            self.pos, self.ring[perm], self.owner, perm[self.hf_first], perm[self.hf_second], perm
        )


def check_depths(z: ArrayLike, n_corners: int) -> FloatArray:
    try:
        arr = np.asarray(z, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"z: expected an array of depths (n_levels, {n_corners}) ({exc})") from exc
    if arr.ndim != 2 or arr.shape[1] != n_corners or arr.shape[0] < 2:
        raise InputError(
            f"z: expected depths of shape (n_levels >= 2, {n_corners}) (one per level and areal cell "
            f"corner), got shape {arr.shape}"
        )
    return arr


def check_active(active: ArrayLike | None, nl: int, nc2: int) -> np.ndarray:
    if active is None:
        return np.ones((nl, nc2), dtype=bool)
    arr = np.asarray(active)
    if arr.shape != (nl, nc2):
        raise InputError(f"active: expected shape (n_layers, n_areal_cells) = ({nl}, {nc2}), got {arr.shape}")
    if arr.dtype != bool:
        if not np.issubdtype(arr.dtype, np.number) or not np.isin(arr, (0, 1)).all():
            raise InputError("active: expected booleans (or 0/1) per layer and areal cell")
        arr = arr != 0
    return arr


def pillar_lines(pillars: ArrayLike | None, nn2: int) -> FloatArray | None:
    if pillars is None:
        return None
    try:
        arr = np.asarray(pillars, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"pillars: expected ({nn2}, 2, 3) top and bottom points ({exc})") from exc
    if arr.shape == (nn2, 6):
        arr = arr.reshape(nn2, 2, 3)
    if arr.shape != (nn2, 2, 3):
        raise InputError(
            f"pillars: expected the top and bottom points (x, y, z) of one pillar per areal node, "
            f"shape ({nn2}, 2, 3) or ({nn2}, 6), got {arr.shape}"
        )
    if not np.isfinite(arr).all():
        raise InputError("pillars: coordinates must be finite")
    return arr


def edge_tags(edge_tag: ArrayLike | None, areal: Grid) -> IntArray:
    if edge_tag is None:
        return np.asarray(areal.faces.tag, dtype=np.int64)
    arr = np.asarray(edge_tag)
    if arr.shape != (areal.num_faces,) or not np.issubdtype(arr.dtype, np.integer) or (arr < 0).any():
        raise InputError(
            f"edge_tag: expected one non-negative integer per areal edge ({areal.num_faces}), "
            f"got {arr.dtype} of shape {arr.shape}"
        )
    return arr.astype(np.int64)


def fault_name_list(fault_names, etag: IntArray) -> list[str]:
    n = int(etag.max(initial=0))
    if fault_names is None:
        return [f"fault_{t}" for t in range(1, n + 1)]
    names = list(fault_names)
    if len(names) < n or not all(isinstance(s, str) for s in names):
        raise InputError(f"fault_names: expected at least {n} names (one per edge tag), got {fault_names!r}")
    return names


def clockwise(areal: Grid, corners: ColumnCorners) -> bool:
    """Whether every ring turns clockwise in plan view (raises if some do and some do not)."""
    pos2, ring = corners.pos, corners.ring
    xy = areal.nodes.coords[:, :2]
    local = xy - xy.mean(axis=0)  # shoelace products lose digits at UTM sizes
    nxt = np.arange(1, ring.size + 1)
    nxt[pos2[1:] - 1] = pos2[:-1]
    a, b = local[ring], local[ring[nxt]]
    area2 = np.bincount(corners.owner, a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1], pos2.size - 1)
    if np.any(area2 == 0):
        raise GridError(f"areal: cell {int(np.flatnonzero(area2 == 0)[0])} has zero area in plan view")
    flip = area2 < 0
    if flip.any() and not flip.all():
        raise GridError(
            f"areal: the grid folds over itself in plan view (cells {np.flatnonzero(flip)[:5].tolist()} "
            "turn clockwise, the others counter-clockwise)"
        )
    return bool(flip[0])


def check_used_depths(z: FloatArray, used, act: np.ndarray, owner: IntArray, pos2: IntArray) -> None:
    """Depths of the corners of active cells (``used`` corners, None: all) must be finite,
    bottoms at or below tops."""
    finite = np.isfinite(z)
    if not finite.all():
        bad = ~finite if used is None else ~finite & used
        if bad.any():
            k, q = np.argwhere(bad)[0]
            raise InputError(
                f"z: level {k}, corner {q} (areal cell {owner[q]}) of an active cell is NaN or infinite "
                f"({int(bad.sum())} such depths; mask undefined cells with active=)"
            )
    with np.errstate(invalid="ignore"):
        inverted = z[1:] < z[:-1]
        if used is not None:
            inverted &= np.take(act, owner, axis=1)
    if inverted.any():
        k, q = np.argwhere(inverted)[0]
        raise InputError(
            f"z: the cell in layer {k} of areal cell {owner[q]} has its bottom above its top at its corner "
            f"{q - pos2[owner[q]]} ({z[k, q]:g} > {z[k + 1, q]:g}); depths must not decrease downwards"
        )
