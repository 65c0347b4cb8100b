"""The connection form of an OPM Flow deck (:mod:`gridlib.io.flow`): any grid as flat boxes of a
logical grid with our pore volumes and every connection an NNC record with our transmissibility.

:class:`ConnectionGrid` holds what the form needs; :func:`box_depths` and
:func:`box_corners` lay the boxes out; :func:`connection_grid_text`,
:func:`porv_text` and :func:`nnc_text` give the text of its three includes, block
by block.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from ..cell_names import ijk_text
from ..errors import InputError
from ..grid import FloatArray, IntArray
from .eclipse_text import keyword_text, text_table

__all__ = [
    "NNC_THRESHOLD",
    "ConnectionGrid",
    "box_corners",
    "box_depths",
    "check_connection_grid",
    "connection_grid_text",
    "nnc_text",
    "porv_text",
    "vanished_connections",
]

NNC_THRESHOLD = 1e-6  # deck units: Flow 2022.10 zeroes smaller non-neighbour connections
_CHUNK = 1 << 16  # NNC records formatted per block


@dataclass(frozen=True, eq=False)
class ConnectionGrid:
    """The connection form's grid, per cell of the grid (n cells) and per connection (m).

    ``dims``: the logical box (nx, ny, nz); ``index`` (n,): each cell's 0-based linear
    index in it (``cell_flow_index``), distinct. ``porv`` (n,) pore volumes (reservoir
    volume unit), ``depth`` (n,) centre depths, ``thickness`` (n,) > 0 the height of each
    cell's box (length unit; the true vertical extent where known: only the centre
    matters to Flow). ``poro`` (n,) and ``permeability`` (n, 3) mD are written for the
    reader (Flow's own connections of the layout are switched off). ``pairs`` (m, 2)
    cells (rows), ``trans`` (m,) > 0 their transmissibility. ``spacing``: the lateral
    size of the boxes (cosmetic).
    """

    dims: tuple[int, int, int]
    index: IntArray
    porv: FloatArray
    depth: FloatArray
    thickness: FloatArray
    poro: FloatArray
    permeability: FloatArray
    pairs: IntArray
    trans: FloatArray
    spacing: float = 1.0


def check_connection_grid(grid: ConnectionGrid) -> np.ndarray:
    """The active cells of the box; raises InputError on inconsistent arrays."""
    nx, ny, nz = grid.dims
    total = nx * ny * nz
    index = np.asarray(grid.index, dtype=np.int64)
    n = index.size
    if index.ndim != 1 or n == 0 or index.min() < 0 or index.max() >= total:
        raise InputError(f"index: expected one cell index in [0, {total}) per cell")
    active = np.zeros(total, dtype=bool)
    active[index] = True
    if active.sum() != n:
        raise InputError("index: two cells of the grid share a Flow cell")
    for key in ("porv", "depth", "thickness", "poro"):
        values = np.asarray(getattr(grid, key), dtype=np.float64)
        if values.shape != (n,) or not np.isfinite(values).all():
            raise InputError(f"{key}: expected {n} finite values, one per cell")
    if (np.asarray(grid.porv) <= 0).any() or (np.asarray(grid.thickness) <= 0).any():
        raise InputError("porv, thickness: every cell needs a positive pore volume and thickness")
    if np.asarray(grid.permeability).shape != (n, 3):
        raise InputError(f"permeability: expected ({n}, 3) values (mD)")
    pairs, trans = np.asarray(grid.pairs), np.asarray(grid.trans)
    if pairs.shape != (trans.size, 2) or (pairs.size and (pairs.min() < 0 or pairs.max() >= n)):
        raise InputError(f"pairs: expected (m, 2) cells of the grid (0 to {n - 1}), one pair per T")
    if not (np.isfinite(trans).all() and (trans > 0).all()):
        raise InputError("trans: transmissibilities must be finite and positive")
    if not grid.spacing > 0:
        raise InputError("spacing: must be positive")
    return active


def vanished_connections(grid: ConnectionGrid) -> IntArray:
    """Rows of ``pairs`` Flow sets to 0: not logical neighbours and T below the threshold."""
    nx, ny, _ = grid.dims
    g = np.sort(np.asarray(grid.index)[np.asarray(grid.pairs, dtype=np.int64)], axis=1)
    step = g[:, 1] - g[:, 0]
    neighbour = (step == 1) | (step == nx) | (step == nx * ny)
    return np.flatnonzero(~neighbour & (np.asarray(grid.trans) < NNC_THRESHOLD))


def box_depths(grid: ConnectionGrid) -> tuple[FloatArray, FloatArray]:
    """TOPS and DZ of every cell of the box (i fastest): each grid cell a box of its
    ``thickness`` centred on its ``depth``, shrunk about the centre where it would overlap
    the next grid cell of its logical column; cells of the box without a grid cell get
    DZ = 0 at the bottom of the grid cell above (the top of the one below where none is
    above). Raises InputError if a column's cells are not ordered top down."""
    nx, ny, nz = grid.dims
    nxy = nx * ny
    index = np.asarray(grid.index, dtype=np.int64)
    depth = np.asarray(grid.depth, dtype=np.float64)
    half = 0.5 * np.asarray(grid.thickness, dtype=np.float64)
    order = np.lexsort((index // nxy, index % nxy))  # by column, then k
    col, cd = index[order] % nxy, depth[order]
    same = col[1:] == col[:-1]
    gap = np.where(same, cd[1:] - cd[:-1], np.inf)
    if (gap <= 0).any():
        bad = int(np.flatnonzero(gap <= 0)[0])
        a, b = int(index[order][bad]), int(index[order][bad + 1])
        raise InputError(
            f"depth: Flow cells {ijk_text(a, grid.dims)} and {ijk_text(b, grid.dims)} of one logical "
            f"column are not ordered top down (centre depths {cd[bad]:g} and {cd[bad + 1]:g})"
        )
    h = half[order]
    h[:-1] = np.minimum(h[:-1], 0.5 * gap)
    h[1:] = np.minimum(h[1:], 0.5 * gap)
    top = np.full(nx * ny * nz, np.nan)
    bottom = np.full(nx * ny * nz, np.nan)
    top[index[order]], bottom[index[order]] = cd - h, cd + h
    # cells without a grid cell: zero thickness where the column has got to
    t, b = top.reshape(nz, nxy), bottom.reshape(nz, nxy)
    missing = np.isnan(t)
    if missing.any():
        rows = np.arange(nz)[:, None]
        above = np.maximum.accumulate(np.where(missing, -1, rows), axis=0)
        below = np.minimum.accumulate(np.where(missing, nz, rows)[::-1], axis=0)[::-1]
        cols = np.broadcast_to(np.arange(nxy), (nz, nxy))
        from_above = b[np.maximum(above, 0), cols]
        from_below = t[np.minimum(below, nz - 1), cols]
        fill = np.where(above >= 0, from_above, np.where(below < nz, from_below, np.nanmin(top)))
        t[missing] = fill[missing]
        b[missing] = fill[missing]
    return t.ravel(), (b - t).ravel()


def box_corners(grid: ConnectionGrid) -> tuple[FloatArray, FloatArray]:
    """COORD and ZCORN of the boxes (:func:`box_depths`): vertical pillars on a square lattice
    of ``spacing``, every box flat. Explicit corners, not DZ and TOPS: Flow 2022.10 takes
    TOPS from the top layer only and stacks the others on it by DZ."""
    nx, ny, nz = grid.dims
    tops, dz = box_depths(grid)
    top = tops.reshape(nz, ny, nx)
    bottom = (tops + dz).reshape(nz, ny, nx)
    z = np.stack([top, bottom], axis=1)  # (nz, 2, ny, nx)
    zcorn = np.repeat(np.repeat(z, 2, axis=2), 2, axis=3)  # (nz, 2, 2ny, 2nx): i fastest
    h = float(grid.spacing)
    y, x = np.meshgrid(np.arange(ny + 1) * h, np.arange(nx + 1) * h, indexing="ij")
    z_top, z_bottom = float(tops.min()), float((tops + dz).max())
    if z_bottom <= z_top:
        z_bottom = z_top + 1.0
    coord = np.stack(
        [x, y, np.full_like(x, z_top), x, y, np.full_like(x, z_bottom)], axis=-1
    )  # (ny + 1, nx + 1, 6)
    return coord.ravel(), zcorn.ravel()


def connection_grid_text(grid: ConnectionGrid) -> Iterator[bytes]:
    nx, ny, nz = grid.dims
    total = nx * ny * nz
    index = np.asarray(grid.index, dtype=np.int64)

    def full(values: np.ndarray) -> np.ndarray:
        out = np.zeros(total)
        out[index] = values
        return out

    coord, zcorn = box_corners(grid)
    actnum = np.zeros(total, dtype=np.int64)
    actnum[index] = 1
    perm = np.asarray(grid.permeability, dtype=np.float64)
    yield (
        "-- The connection form's grid (gridlib): each cell of the grid is a flat box of this\n"
        f"-- logical grid, {nx} x {ny} x {nz}, at its true depth (its centre, the mean of its 8\n"
        "-- corners, is the cell's centre depth); boxes of one logical column are stacked without\n"
        "-- overlap. MULTX, MULTY, MULTZ = 0: the connections Flow would make between these boxes\n"
        "-- are switched off; every real connection is an NNC record with gridlib's transmissibility.\n\n"
        f"SPECGRID\n {nx} {ny} {nz} 1 F /\n\n"
    ).encode("ascii")
    yield from keyword_text(
        "COORD", coord, f"vertical pillars {grid.spacing!r} apart (the lateral layout is cosmetic)"
    )
    yield from keyword_text("ZCORN", zcorn, "each box from its top to its bottom (no cell: zero thickness)")
    yield from keyword_text("ACTNUM", actnum, "1: a cell of the grid", integer=True)
    yield from keyword_text("PORO", full(grid.poro), "porosity (the pore volumes are PORV in EDIT)")
    for axis, key in enumerate(("PERMX", "PERMY", "PERMZ")):
        yield from keyword_text(key, full(perm[:, axis]), "mD (for the reader: the connections are NNCs)")
    for key in ("MULTX", "MULTY", "MULTZ"):
        yield from keyword_text(key, np.zeros(total), "no connection of its own between the boxes")


def porv_text(grid: ConnectionGrid) -> Iterator[bytes]:
    nx, ny, nz = grid.dims
    porv = np.zeros(nx * ny * nz)
    porv[np.asarray(grid.index, dtype=np.int64)] = grid.porv
    yield b"-- gridlib's pore volumes (EDIT: they replace what Flow computes from the boxes)\n"
    yield from keyword_text("PORV", porv, "pore volume of every cell (reservoir volume unit)")


def nnc_text(grid: ConnectionGrid, n_vanished: int, label: str) -> Iterator[bytes]:
    nx, ny, _ = grid.dims
    g = np.asarray(grid.index, dtype=np.int64)[np.asarray(grid.pairs, dtype=np.int64)]
    m = g.shape[0]
    head = [
        "-- Every connection of the grid, with gridlib's transmissibility (" + label + ").",
        f"-- {m} connections; Flow adds each value to the 0 of the layout's own connection.",
    ]
    if n_vanished:
        head.append(
            f"-- {n_vanished} of them are below {NNC_THRESHOLD:g} between cells that are not logical "
            "neighbours: Flow sets those to 0."
        )
    yield ("\n".join(head) + "\n\nNNC\n-- I1 J1 K1 I2 J2 K2 TRAN\n").encode("ascii")
    ijk = np.stack([g % nx + 1, g // nx % ny + 1, g // (nx * ny) + 1], axis=2).reshape(m, 6)
    distinct = np.unique(ijk)
    table = text_table(distinct.tolist(), True)
    wi = table.shape[1] + 1
    trans = np.asarray(grid.trans, dtype=np.float64)
    for lo in range(0, m, _CHUNK):
        hi = min(lo + _CHUNK, m)
        codes = np.searchsorted(distinct, ijk[lo:hi])
        values = text_table(trans[lo:hi].tolist(), False)
        wt = values.shape[1]
        rows = np.zeros((hi - lo, 6 * wi + 1 + wt + 3), np.uint8)
        for c in range(6):
            rows[:, c * wi] = ord(" ")
            rows[:, c * wi + 1 : (c + 1) * wi] = table[codes[:, c]]
        rows[:, 6 * wi] = ord(" ")
        rows[:, 6 * wi + 1 : 6 * wi + 1 + wt] = values
        rows[:, -3:] = np.frombuffer(b" /\n", np.uint8)
        yield rows[rows != 0].tobytes()
    yield b"/\n"
