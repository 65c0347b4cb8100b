"""The connection list a two-point flux simulator needs: cell pairs and their transmissibility."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..grid import FloatArray, IntArray
from ..threads import in_slices
from ..units import METRIC, UnitSystem

# Connection kinds (Connections.kind)
NEIGHBOR = 0  # logical ijk neighbours (i, i+1 / j, j+1 / k, k+1) sharing a face
FAULT = 1  # a face across non-matching cells (fault throw): not logical neighbours
PINCH = 2  # across removed or inactive thin layers, no face (PINCH, MINPV)
OTHER = 3  # any other pair: unstructured grids, explicit NNC keywords
KIND_NAMES = ("neighbor", "fault", "pinch", "other")


@dataclass(frozen=True, eq=False)
class Connections:
    """Every connection of a grid with a non-zero transmissibility, arrays read-only.

    ``cells`` (n, 2): the two cells (rows of the grid; first < second), sorted by
    (first, second). ``global_cells`` (n, 2): their 0-based linear ijk indices (i
    fastest) where the grid is logically Cartesian, else None. ``trans`` (n,): the
    transmissibility in the transmissibility unit of ``units``, a unit system of
    :mod:`gridlib.units` (METRIC cP m3/(day bar), FIELD cP rb/(day psi), LAB cP
    cm3/(h atm), PVT-M cP m3/(day atm)). ``kind`` (n,) int8: NEIGHBOR 0, FAULT 1, PINCH 2, OTHER 3.
    ``face`` (n,): the face of the grid the connection crosses (the first, where two
    cells share several faces), -1 for pinch and explicit connections. ``notes``:
    what was applied, ignored or adjusted, for the reader of the results.
    """

    cells: IntArray
    global_cells: IntArray | None
    trans: FloatArray
    kind: np.ndarray
    face: IntArray
    units: UnitSystem = METRIC
    notes: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        for name, dtype in (
            ("cells", np.int64),
            ("trans", np.float64),
            ("kind", np.int8),
            ("face", np.int64),
        ):
            arr = np.ascontiguousarray(getattr(self, name), dtype=dtype)
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)
        if self.global_cells is not None:
            g = np.ascontiguousarray(self.global_cells, dtype=np.int64)
            g.flags.writeable = False
            object.__setattr__(self, "global_cells", g)
        n = self.trans.size
        if self.cells.shape != (n, 2) or self.kind.shape != (n,) or self.face.shape != (n,):
            raise ValueError("Connections: cells (n, 2), trans, kind and face (n,) must agree")

    @property
    def num(self) -> int:
        return int(self.trans.size)

    def counts(self) -> dict[str, int]:
        """Number of connections of each kind, by name."""
        c = np.bincount(self.kind, minlength=len(KIND_NAMES))
        return {name: int(c[k]) for k, name in enumerate(KIND_NAMES)}

    def __repr__(self) -> str:
        kinds = ", ".join(f"{v} {k}" for k, v in self.counts().items() if v)
        return f"Connections({self.num} in {self.units.name}: {kinds})"


def assemble(
    cells: IntArray,
    trans: FloatArray,
    kind: np.ndarray,
    face: IntArray,
    *,
    index_map: IntArray | None,
    units: UnitSystem,
    notes: list[str] | tuple[str, ...] = (),
) -> Connections:
    """Connections from one entry per face or pair: pairs ordered (first < second), entries of
    the same pair added (their faces are parallel paths; the smallest kind and the first
    entry's face kept), zero transmissibilities dropped, sorted by pair."""
    cells = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
    lo, hi = np.minimum(cells[:, 0], cells[:, 1]), np.maximum(cells[:, 0], cells[:, 1])
    return assemble_ordered(lo, hi, trans, kind, face, index_map=index_map, units=units, notes=notes)


def assemble_ordered(
    lo: IntArray,
    hi: IntArray,
    trans: FloatArray,
    kind: np.ndarray,
    face: IntArray,
    *,
    index_map: IntArray | None,
    units: UnitSystem,
    notes: list[str] | tuple[str, ...] = (),
) -> Connections:
    """:func:`assemble` of entries between cells ``lo`` <= ``hi``. Its elementwise steps run
    in blocks on the threads (the same bits for any number of threads)."""
    lo, hi = np.asarray(lo, dtype=np.int64), np.asarray(hi, dtype=np.int64)
    trans = np.asarray(trans, dtype=np.float64)
    kind = np.asarray(kind, dtype=np.int8)
    face = np.asarray(face, dtype=np.int64)
    n = trans.size
    key = _pair_keys(lo, hi)
    order, repeated, positive = _sorted_entries(key, trans)
    del key
    if not repeated.any():  # one entry per pair: nothing to add up
        pick = order[positive]
        total = None
    else:
        first = ~repeated
        group = np.cumsum(first) - 1  # the pair of each sorted entry
        starts = np.flatnonzero(first)
        total = np.bincount(group, trans[order], starts.size)
        kmin = np.minimum.reduceat(kind[order], starts) if n else kind[:0]
        keep = total > 0.0
        pick = order[starts[keep]]
        total, kmin = total[keep], kmin[keep]
    del order, repeated, positive
    m = pick.size
    pairs = np.empty((m, 2), dtype=np.int64)
    glob = None if index_map is None else np.empty((m, 2), dtype=np.int64)
    index_map = None if index_map is None else np.asarray(index_map, dtype=np.int64)
    picked = [np.empty(m), np.empty(m, dtype=np.int8)] if total is None else [total, kmin]
    out_face = np.empty(m, dtype=np.int64)

    def gathered(rows: slice) -> None:
        p = pick[rows]
        for side, cell in enumerate((lo[p], hi[p])):
            pairs[rows, side] = cell
            if glob is not None:
                glob[rows, side] = index_map[cell]
        if total is None:
            picked[0][rows] = trans[p]
            picked[1][rows] = kind[p]
        out_face[rows] = face[p]

    in_slices(gathered, m, 32)  # blocks of a few MB, in the CPU's cache
    return Connections(pairs, glob, picked[0], picked[1], out_face, units, tuple(notes))


def _pair_keys(lo: IntArray, hi: IntArray) -> IntArray:
    """lo (max(hi) + 1) + hi: one integer per pair, ordered as the pairs (lo, hi) are."""
    width = int(hi.max(initial=0)) + 1
    key = np.empty(lo.size, dtype=np.int64)

    def keys(rows: slice) -> None:
        np.multiply(lo[rows], width, out=key[rows])
        key[rows] += hi[rows]

    in_slices(keys, lo.size)
    return key


def _sorted_entries(key: IntArray, trans: FloatArray) -> tuple[IntArray, np.ndarray, np.ndarray]:
    """The entries in the order of ``key`` (stable: entries of one pair keep their given
    order), whether each sorted entry repeats the pair before it, and whether its
    transmissibility is positive."""
    order = np.argsort(key, kind="stable")
    n = key.size
    repeated = np.zeros(n, dtype=bool)
    positive = np.empty(n, dtype=bool)

    def sorted_rows(rows: slice) -> None:
        before = order[max(rows.start - 1, 0) : rows.stop]
        k = key[before]
        np.equal(k[1:], k[:-1], out=repeated[rows.start + (rows.start == 0) : rows.stop])
        np.greater(trans[before[rows.start > 0 :]], 0.0, out=positive[rows])

    in_slices(sorted_rows, n)
    return order, repeated, positive


def face_connections(neighbors: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """The connection (row of ``cells``) each face's two cells form, -1 for boundary faces and
    pairs without a connection (T = 0)."""
    nb = np.sort(np.asarray(neighbors, dtype=np.int64), axis=1)
    pairs = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
    out = np.full(nb.shape[0], -1, dtype=np.int64)
    if not pairs.size:
        return out
    width = int(max(pairs.max(), nb.max())) + 1
    key = pairs[:, 0] * width + pairs[:, 1]
    order = np.argsort(key, kind="stable")
    inner = np.flatnonzero(nb[:, 0] >= 0)
    face_key = nb[inner, 0] * width + nb[inner, 1]
    pos = np.minimum(np.searchsorted(key[order], face_key), key.size - 1)
    found = key[order][pos] == face_key
    out[inner[found]] = order[pos[found]]
    return out
