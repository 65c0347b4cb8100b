"""Corner nodes of a corner-point deck: masking, sanity checks, orientation, node ids.

Inactive cells are masked before anything else (their corners, often junk, are
never read). Active corners must be finite. z-up decks are negated to depth.
Every corner gets the id of its distinct depth (distinct beyond rounding:
:mod:`~gridlib.pillars.pillar_points`) on its pillar (ids grow with
depth along a pillar), computed a few pillar rows at a time so that the
temporaries stay small.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..connectivity import offsets
from ..errors import InputError
from ..grid import FloatArray, IntArray
from ..pillars.pillar_points import PillarPoints, points_on_pillars, sorted_points_rows, unique_points_rows
from .deck import Deck

_BLOCK = 1 << 18  # candidate depths numbered per block of pillar rows
_LOWEST, _HIGHEST = np.iinfo(np.int64).min, np.iinfo(np.int64).max  # bit patterns: no corner


@dataclass(frozen=True, eq=False)
class CornerNodes:
    """Node ids of every cell corner and the nodes' coordinates.

    ``table[a + 2b + 4c, k, j + 1, i + 1]`` is the node of corner (a, b, c) of
    cell (i, j, k): a, b select the pillar (i + a, j + b), c the top (0) or
    bottom (1). It is -1 for cells that are not kept and on a ring of padding
    cells around the model, so that the pillar pairs on the model's edge slice
    like interior ones. ``kept`` marks active cells that are not collapsed on
    all four pillars; ``cells`` numbers them in (k, j, i) order on the padded
    (k, j + 1, i + 1) layout (-1 elsewhere).
    """

    table: IntArray  # (8, nz, ny + 2, nx + 2)
    kept: np.ndarray  # (nz, ny, nx)
    cells: IntArray  # (nz, ny + 2, nx + 2)
    points: PillarPoints
    xyz: FloatArray  # (n_nodes, 3), z is depth
    lines: FloatArray  # (n_pillars, 2, 3) pillars with z as depth
    left_handed: bool
    notes: tuple[str, ...]
    layered: bool  # every pillar layered (no throw anywhere): see _deck_interfaces

    def without(self, drop: np.ndarray) -> CornerNodes:
        """The same nodes with the kept cells ``drop`` (a mask in kept-cell order) removed."""
        kept = self.kept.copy()
        kept[kept] = ~drop
        table = self.table.copy()
        inner = table[:, :, 1:-1, 1:-1]
        inner[:, ~kept] = -1
        cells = np.full_like(self.cells, -1)
        cells[:, 1:-1, 1:-1][kept] = np.arange(int(np.count_nonzero(kept)))
        return replace(self, table=table, kept=kept, cells=cells)


def _cell(nx: int, ny: int, flat_corner: int) -> str:
    """1-based (i, j, k) of the cell owning a ZCORN entry of the (2nz, 2ny, 2nx) array."""
    kc, rest = divmod(flat_corner, 4 * nx * ny)
    jc, ic = divmod(rest, 2 * nx)
    return f"({ic // 2 + 1}, {jc // 2 + 1}, {kc // 2 + 1})"


def corner_nodes(deck: Deck, tolerance: float = 0.0) -> CornerNodes:
    src = deck.source
    nx, ny, nz = deck.cart_dims
    notes: list[str] = []
    active = deck.active.reshape(nz, ny, nx)
    if not active.any():
        raise InputError(f"{src}: no active cells (ACTNUM is all 0)")
    zc = deck.zcorn_array()
    _check_finite(zc, active, src)
    lines = deck.pillars().reshape(-1, 2, 3).copy()
    col_active = active.any(axis=0)
    pil_used = np.zeros((ny + 1, nx + 1), dtype=bool)
    for a in (0, 1):
        for b in (0, 1):
            pil_used[b : b + ny, a : a + nx] |= col_active
    bad_pillars = pil_used.ravel() & ~np.isfinite(lines).all(axis=(1, 2))
    if bad_pillars.any():
        jp, ip = divmod(int(np.flatnonzero(bad_pillars)[0]), nx + 1)
        raise InputError(
            f"{src}: COORD: pillar ({ip + 1}, {jp + 1}) of an active cell is NaN or infinite "
            f"({int(bad_pillars.sum())} such pillars)"
        )

    sign = _depth_sign(zc, active, src)
    if sign < 0:
        lines[:, :, 2] = -lines[:, :, 2]
        notes.append("z decreases with depth in this deck (z up): z was negated to depth")
    if tolerance < 0:
        raise InputError(f"process_grdecl: tolerance must be >= 0, got {tolerance}")

    table, points, layered = _number_corners(zc, active, sign, tolerance)
    inner = table[:, :, 1:-1, 1:-1]
    kept = active & ~(inner[:4] == inner[4:]).all(axis=0)
    collapsed = int(np.count_nonzero(active & ~kept))
    if collapsed:  # as ECLIPSE and Flow: no volume, no cell
        notes.append(
            f"{collapsed} ACTNUM-active cells of zero thickness (top and bottom corners the same on all "
            "four pillars) were removed"
        )
    inner[:, ~kept] = -1
    cells = np.full(table.shape[1:], -1, dtype=np.int64)
    cells[:, 1:-1, 1:-1][kept] = np.arange(int(np.count_nonzero(kept)))  # (k, j, i) order
    xyz = points_on_pillars(lines, points.pillar, points.z)

    left = _left_handed(lines, active, nx, ny)
    if left:
        notes.append("the deck is left-handed in plan view: every face was reversed")
    return CornerNodes(table, kept, cells, points, xyz, lines, left, tuple(notes), layered)


def _check_finite(zc: FloatArray, active: np.ndarray, src: str) -> None:
    """Active cells must have finite corner depths (inactive ones may hold junk)."""
    finite = np.isfinite(zc)
    if finite.all():
        return
    nz, ny, nx = active.shape
    act2 = np.repeat(np.repeat(np.repeat(active, 2, axis=0), 2, axis=1), 2, axis=2)
    bad = act2 & ~finite
    if bad.any():
        n_bad = len(np.unique(np.flatnonzero(bad.reshape(nz, 2, ny, 2, nx, 2).any(axis=(1, 3, 5)))))
        raise InputError(
            f"{src}: ZCORN: active cell {_cell(nx, ny, int(np.flatnonzero(bad)[0]))} has a non-finite "
            f"corner depth ({n_bad} active cells have NaN or infinite corners)"
        )


def _depth_sign(zc: FloatArray, active: np.ndarray, src: str) -> int:
    """-1 if z grows upwards (most active cells have bottom above top), else 1.

    Raises if an active cell still has a top corner below its bottom corner. A few layers
    at a time (small temporaries).
    """
    sign, inverted = majority_depth_sign(zc, active)
    nz, ny, nx = active.shape
    if inverted >= 0:
        kc, jc, ic = np.unravel_index(inverted, (nz, 2 * ny, 2 * nx))
        raise InputError(
            f"{src}: ZCORN: cell ({ic // 2 + 1}, {jc // 2 + 1}, {kc + 1}) has a top corner "
            "below its bottom corner"
        )
    return sign


def majority_depth_sign(zc: FloatArray, active: np.ndarray) -> tuple[int, int]:
    """The depth sign of ZCORN ``zc`` (-1 if most active cells' corners have their bottom above
    their top: z up; else 1) and the flat index in ``zc``'s (nz, 2ny, 2nx) top corners of the
    first active corner going the other way (-1: none). A few layers at a time."""
    nz, ny, nx = active.shape
    per_layer = 4 * nx * ny  # corners of a layer: (2 ny, 2 nx)
    step = max(1, _BLOCK // per_layer)
    count, first = [0, 0], [-1, -1]  # cell corners going up, down: how many, the first (flat index)
    for k0 in range(0, nz, step):
        k1 = min(k0 + step, nz)
        act = np.repeat(active[k0:k1], 2, axis=2)[:, :, None, :]  # (k, j, 1, ic)
        with np.errstate(invalid="ignore", over="ignore"):  # inactive corners may be junk
            dz = (zc[2 * k0 + 1 : 2 * k1 : 2] - zc[2 * k0 : 2 * k1 : 2]).reshape(k1 - k0, ny, 2, 2 * nx)
            moves = (dz < 0, dz > 0)  # bottom minus top, per corner
        for way, moved in enumerate(moves):
            moved &= act
            n = np.count_nonzero(moved)
            if n and first[way] < 0:
                first[way] = k0 * per_layer + int(np.flatnonzero(moved)[0])
            count[way] += n
    sign = -1 if count[0] > count[1] else 1
    return sign, (first[1] if sign < 0 else first[0])


def _number_corners(
    zc: FloatArray, active: np.ndarray, sign: int, tolerance: float
) -> tuple[IntArray, PillarPoints, bool]:
    """Node ids of all corners (the padded table of :class:`CornerNodes`), the points, and
    whether every pillar is layered (:func:`_deck_interfaces`).

    A deck whose pillars are all layered is numbered at once from its interface
    depths, without a sort (:func:`_number_interfaces`). Otherwise each pillar's
    candidate depths form one row of four runs, one per adjacent column, each in
    layer order (so already sorted in a valid deck); rows are sorted and numbered a
    block of pillar rows at a time. Both give the same ids and depths
    (:func:`~gridlib.pillars.pillar_points.sorted_points_rows`).
    """
    nz, ny, nx = active.shape
    interfaces = _deck_interfaces(zc, active, sign, tolerance)
    if interfaces is not None:
        return (*_number_interfaces(interfaces, active), True)
    table = np.full((8, nz, ny + 2, nx + 2), -1, dtype=np.int64)
    per_row = 8 * nz
    step = max(1, _BLOCK // ((nx + 1) * per_row))
    counts, depths = [], []
    next_id = 0
    for j0 in range(0, ny + 1, step):
        j1 = min(j0 + step, ny + 1)
        rows = _pillar_rows(zc, active, sign, j0, j1)
        ids, count, z = unique_points_rows(rows.reshape(-1, per_row), tolerance, next_id)
        _scatter_ids(table, ids.reshape(rows.shape), j0, j1)
        counts.append(count)
        depths.append(z)
        next_id += z.size
    count = np.concatenate(counts)
    pillar = np.repeat(np.arange(count.size, dtype=np.int64), count)
    points = PillarPoints(np.zeros(0, np.int64), offsets(count), pillar, np.concatenate(depths))
    return table, points, False


def _deck_interfaces(zc: FloatArray, active: np.ndarray, sign: int, tolerance: float) -> FloatArray | None:
    """The depth (nz + 1, ny + 1, nx + 1) of every layer interface on every pillar (NaN: no
    active cell there) if every pillar is *layered*, else None (found at the first
    interface where a pillar is not: a faulted deck is told at once).

    A pillar is layered when, at every interface, the corners of the (up to eight) active
    cells meeting there have the same depth, bit for bit, and these depths do not decrease
    down the interfaces. Then the pillar has no throw and no gap between layers, and its
    points are its interface depths; a deck whose pillars are all layered has no fault
    (every pillar pair is a plain quad per layer: :func:`~.faces.structured_lateral`). A
    pillar holding both 0.0 and -0.0 is not called layered (a sort may keep either as the
    point). Corners are taken as :func:`_pillar_rows` gives them to the sort (depth sign)
    and rounded as :func:`~gridlib.pillars.pillar_points.unique_points_rows` rounds them
    (``tolerance``), an interface at a time (small temporaries).
    """
    nz, ny, nx = active.shape
    interfaces = np.empty((nz + 1, ny + 1, nx + 1))
    last = np.full((ny + 1, nx + 1), -np.inf)  # the deepest interface so far (all of them grow)
    zeros = np.zeros((2, ny + 1, nx + 1), dtype=bool)  # pillars with a 0.0, a -0.0
    hi, lo = np.empty((2, ny + 1, nx + 1), dtype=np.int64)
    for level in range(nz + 1):
        hi.fill(_LOWEST)
        lo.fill(_HIGHEST)
        for k, c in ((level, 0), (level - 1, 1)):  # tops of layer L, bottoms of layer L - 1
            if not 0 <= k < nz:
                continue
            z = zc[2 * k + c]
            if sign < 0:
                z = -z
            if tolerance > 0:
                z = np.round(z / tolerance) * tolerance
            bits = z.view(np.int64)
            for b in (0, 1):
                for a in (0, 1):
                    corner = bits[b::2, a::2]
                    at = (slice(b, b + ny), slice(a, a + nx))
                    np.maximum(hi[at], corner, out=hi[at], where=active[k])
                    np.minimum(lo[at], corner, out=lo[at], where=active[k])
        some = lo <= hi
        if (hi != lo)[some].any():
            return None
        depth = np.where(some, hi.view(np.float64), np.nan)
        with np.errstate(invalid="ignore"):
            if (depth < last).any():
                return None
        np.copyto(last, depth, where=some)
        zero = depth == 0.0
        zeros[0] |= zero & np.signbit(depth)
        zeros[1] |= zero & ~np.signbit(depth)
        interfaces[level] = depth
    return None if (zeros[0] & zeros[1]).any() else interfaces


def _number_interfaces(interfaces: FloatArray, active: np.ndarray) -> tuple[IntArray, PillarPoints]:
    """:func:`_number_corners`'s table and points from the interface depths of a deck whose
    pillars are all layered."""
    nz, ny, nx = active.shape
    ids, count, z = sorted_points_rows(np.ascontiguousarray(interfaces.reshape(nz + 1, -1).T))
    level_ids = np.ascontiguousarray(ids.T).reshape(nz + 1, ny + 1, nx + 1)
    table = np.full((8, nz, ny + 2, nx + 2), -1, dtype=np.int64)
    for slot in range(8):
        a, b, c = slot & 1, (slot >> 1) & 1, slot >> 2
        np.copyto(table[slot, :, 1:-1, 1:-1], level_ids[c : c + nz, b : b + ny, a : a + nx], where=active)
    pillar = np.repeat(np.arange(count.size, dtype=np.int64), count)
    return table, PillarPoints(np.zeros(0, np.int64), offsets(count), pillar, z)


def _row_range(j0: int, j1: int, b: int, ny: int) -> tuple[int, int]:
    """Pillar rows in [j0, j1) that have a cell at row j - b."""
    return max(j0, b), min(j1, ny + b)


def _pillar_rows(zc: FloatArray, active: np.ndarray, sign: int, j0: int, j1: int) -> FloatArray:
    """Candidate depths on pillar rows j0..j1-1, shape (j1 - j0, nx + 1, 2, 2, nz, 2).

    ``[j - j0, i, b, a, k, c]`` is corner (a, b, c) of cell (i - a, j - b, k),
    which lies on pillar (i, j); NaN where that cell is inactive or missing.
    """
    nz, ny, nx = active.shape
    # The ZCORN rows 2j - 1 and 2j lie on pillar row j: transpose those rows once so
    # that every corner column (all its layers) is contiguous, and mask inactive cells.
    jc0, jc1 = max(2 * j0 - 1, 0), min(2 * j1 - 1, 2 * ny)
    columns = np.ascontiguousarray(zc[:, jc0:jc1].transpose(1, 2, 0))  # (jc, ic, kc)
    act = active[:, np.arange(jc0, jc1) // 2].transpose(1, 2, 0)  # (jc, i, k)
    if not act.all():
        np.copyto(columns.reshape(jc1 - jc0, nx, 2, nz, 2), np.nan, where=~act[:, :, None, :, None])
    if sign < 0:
        np.negative(columns, out=columns)
    rows = np.full((j1 - j0, nx + 1, 2, 2, 2 * nz), np.nan)
    for b in (0, 1):
        lo, hi = _row_range(j0, j1, b, ny)
        for a in (0, 1):
            rows[lo - j0 : hi - j0, a : a + nx, b, a] = columns[2 * lo - b - jc0 : 2 * hi - b - jc0 : 2, a::2]
    return rows.reshape(j1 - j0, nx + 1, 2, 2, nz, 2)


def _scatter_ids(table: IntArray, ids: IntArray, j0: int, j1: int) -> None:
    """Write the ids of pillar rows j0..j1-1 (laid out as :func:`_pillar_rows`) into the table."""
    _, _, nyp, nxp = table.shape
    ny, nx = nyp - 2, nxp - 2
    for b in (0, 1):
        lo, hi = _row_range(j0, j1, b, ny)
        if lo >= hi:
            continue
        for a in (0, 1):
            for c in (0, 1):
                dst = table[a + 2 * b + 4 * c, :, lo - b + 1 : hi - b + 1, 1 : nx + 1]
                dst[...] = ids[lo - j0 : hi - j0, a : a + nx, b, a, :, c].transpose(2, 0, 1)


def _left_handed(lines: FloatArray, active: np.ndarray, nx: int, ny: int) -> bool:
    """Majority vote over active columns: does (i, j) turn clockwise in plan view?"""
    mid = lines.mean(axis=1)[:, :2].reshape(ny + 1, nx + 1, 2)
    ei = mid[:-1, 1:] - mid[:-1, :-1]
    ej = mid[1:, :-1] - mid[:-1, :-1]
    cross = (ei[..., 0] * ej[..., 1] - ei[..., 1] * ej[..., 0])[active.any(axis=0)]
    return bool((cross < 0).sum() > (cross > 0).sum())


def depth_sign(deck: Deck) -> int:
    """-1 for a deck whose z grows upwards (process_grdecl negates it), else 1."""
    nx, ny, nz = deck.cart_dims
    return _depth_sign(deck.zcorn_array(), deck.active.reshape(nz, ny, nx), deck.source)


def corner_depths(deck: Deck, cells: IntArray, sign: int | None = None) -> FloatArray:
    """Depths (n, 8) of the eight corners ``a + 2b + 4c`` of ``cells`` (linear ijk indices):
    the z of :func:`corner_points` (the same bits) without the x, y it would compute.

    >>> from gridlib.cornerpoint.generators import simple_grdecl
    >>> corner_depths(simple_grdecl([2, 1, 1]), [1])[0, [4, 7]].round(6).tolist()
    [0.5, 0.45]
    """
    nx, ny, nz = deck.cart_dims
    g = np.asarray(cells, dtype=np.int64).ravel()
    i, j, k = g % nx, (g // nx) % ny, g // (nx * ny)
    zc = deck.zcorn_array()
    if sign is None:
        sign = _depth_sign(zc, deck.active.reshape(nz, ny, nx), deck.source)
    out = np.empty((g.size, 8))
    for corner in range(8):
        a, b, c = corner & 1, (corner >> 1) & 1, corner >> 2
        out[:, corner] = sign * zc[2 * k + c, 2 * j + b, 2 * i + a]
    return out


def corner_points(deck: Deck, cells: IntArray, sign: int | None = None) -> FloatArray:
    """Coordinates (n, 8, 3) of the eight corners of ``cells`` (linear ijk indices, i fastest),
    in the frame of :func:`~gridlib.cornerpoint.process_grdecl` (z is depth: z-up decks are
    negated).

    Corner ``a + 2b + 4c`` lies on pillar (i + a, j + b) at the cell's top (c = 0) or bottom
    (c = 1) depth from ZCORN; its x, y are the pillar line's at that depth (the pillar's
    top point where both ends of the pillar have the same depth), as ECLIPSE and OPM Flow
    place corners. ``sign``: :func:`depth_sign` of the deck, if known.

    >>> from gridlib.cornerpoint.generators import simple_grdecl
    >>> corner_points(simple_grdecl([2, 1, 1]), [1])[0, [4, 7]].round(6).tolist()  # bottom corners
    [[0.5, 0.0, 0.5], [1.0, 1.0, 0.45]]
    """
    nx, ny, _ = deck.cart_dims
    g = np.asarray(cells, dtype=np.int64).ravel()
    i, j = g % nx, (g // nx) % ny
    if sign is None:
        sign = depth_sign(deck)
    depth = corner_depths(deck, g, sign)
    lines = deck.pillars().reshape(-1, 2, 3)
    out = np.empty((g.size, 8, 3))
    for corner in range(8):
        a, b = corner & 1, (corner >> 1) & 1
        z = sign * depth[:, corner]  # the deck's own z again (exactly: sign is +-1)
        line = lines[(j + b) * (nx + 1) + i + a]  # (n, 2, 3): top and bottom points
        top, bottom = line[:, 0], line[:, 1]
        span = bottom[:, 2] - top[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(span != 0.0, (z - top[:, 2]) / span, 0.0)
        out[:, corner, 0] = top[:, 0] + t * (bottom[:, 0] - top[:, 0])
        out[:, corner, 1] = top[:, 1] + t * (bottom[:, 1] - top[:, 1])
        out[:, corner, 2] = depth[:, corner]
    return out
