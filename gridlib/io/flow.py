"""OPM Flow decks of any grid: :func:`write_flow_deck` writes ``<NAME>.DATA`` and its includes.

Two forms, one writer:

* **native** (corner-point and deck grids): the GRID section is the corner-point deck
  itself (COORD, ZCORN, ACTNUM, PORO, PERMX/Y/Z, NTG, FAULTS, MULTFLT, written by
  :func:`~gridlib.io.grdecl.write_grdecl` into ``<NAME>_GRID.INC``): Flow computes its
  own pore volumes, transmissibilities and well connection factors.
* **connections** (any grid, :class:`ConnectionGrid`): Flow gets our numbers and nothing
  else. Every cell is a flat box of the logical grid ``dims``, at the cell ``index``
  (``cell_flow_index``): COORD has vertical pillars ``spacing`` apart, ZCORN puts the box
  over the cell's own depth range, so that its centre, the mean of its 8 corners, which
  Flow uses for gravity, equilibration and the well connections, is the cell's centre
  depth. The boxes of one logical column are stacked without overlap (a box is shrunk
  about its centre where it would reach into the next one): Flow 2022.10 silently pushes
  a box that overlaps the one above it down, which would move its centre; and it reads
  TOPS for the top layer only, so explicit corners, not DZ and TOPS. MULTX, MULTY and
  MULTZ are 0 in every cell: whatever this layout makes Flow connect by itself (logical
  neighbours, and the fault overlaps of boxes at different depths) has transmissibility
  0. Every connection of the grid is an NNC record with our transmissibility
  (``<NAME>_NNC.INC``; the NNC keyword's value is added to the 0 of a connection the
  layout makes, and no multiplier applies to it), and PORV in the EDIT section
  (``<NAME>_PORV.INC``) overwrites the pore volumes. Wells get our connection factors
  in COMPDAT item 8, since Flow's own would come from the boxes.

  Flow 2022.10 sets connections that are not between logical neighbours (index
  difference 1, nx or nx ny) and have a transmissibility below 1e-6 (deck units) to 0:
  those vanish from the model. :attr:`FlowDeck.vanished` lists them and the NNC
  include says how many; nothing else is lost.

The deck (both forms): RUNSPEC, GRID, EDIT, PROPS (a fluid preset of
:mod:`gridlib.fluids`), SOLUTION (EQUIL with item 9 = 0: every cell's saturation at its
centre depth, the only point the connection form's boxes share with the cell), SUMMARY
(field, and well vectors when there are wells) and SCHEDULE (restart files at every
report step, WELSPECS, COMPORD INPUT, one COMPDAT record per completion, top down,
WCONINJE/WCONPROD and TSTEP), every keyword with a comment saying what its items are.
Without wells or report days the deck only initialises the model.

Units: the deck's (METRIC or FIELD): lengths and depths in m (ft), pressures bar (psia),
rates sm3/day (stb/day), transmissibilities and connection factors cP m3/(day bar)
(cP rb/(day psi)), pore volumes rm3 (rb), permeability mD. z is depth (down).
Cell indices: 0-based linear (i fastest) in Python, 1-based I J K in the deck.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from ..cornerpoint.deck import Deck
from ..errors import InputError
from ..fluids import FLUIDS, deck_tables
from ..grid import FloatArray, IntArray
from ..units import unit_system
from ._atomic import atomic_path
from .grdecl import _format_values, _text_table, write_grdecl

__all__ = ["FORMS", "ConnectionGrid", "FlowDeck", "FlowWell", "Simulation", "write_flow_deck"]

FORMS = ("native", "connections")
WELL_KINDS = ("injector", "producer")
NNC_THRESHOLD = 1e-6  # deck units: Flow 2022.10 zeroes smaller non-neighbour connections
START_DATE = " 1 'JAN' 2020 /"
_CHUNK = 1 << 16  # NNC records formatted per block
_UNIT_TEXT = {
    "METRIC": "METRIC: m, bar, sm3/day, rm3, cP, mD, kg/m3; T and CF in cP m3/(day bar)",
    "FIELD": "FIELD: ft, psia, stb/day, rb, cP, mD, lb/ft3; T and CF in cP rb/(day psi)",
}


@dataclass(frozen=True, eq=False)
class FlowWell:
    """A vertical well and its completions.

    ``cells``: the Flow cells it is completed in (0-based linear indices of the deck's
    box), in the order Flow is to take them (top down). ``factors``: the connection
    factor of each completion (deck units), None to let Flow compute Peaceman's from its
    own grid (native form). ``radius`` (length unit) and ``skin`` go to COMPDAT.
    ``kind``: "injector" (water) or "producer"; ``rate`` (surface rate, water for an
    injector, liquid for a producer) and ``bhp``: the controls, at least one of them;
    with both, the rate is the target and the bottom-hole pressure the limit.
    """

    name: str
    kind: str
    cells: IntArray
    radius: float
    skin: float = 0.0
    factors: FloatArray | None = None
    rate: float | None = None
    bhp: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "cells", np.asarray(self.cells, dtype=np.int64).ravel())
        if self.factors is not None:
            object.__setattr__(self, "factors", np.asarray(self.factors, dtype=np.float64).ravel())


@dataclass(frozen=True)
class Simulation:
    """What the deck simulates: a preset fluid (:mod:`gridlib.fluids`), the initial state
    (pressure at the ``datum`` depth; the oil-water contact ``owc``, None for the water
    preset) and the wells, run over ``report_days`` (days from the start, increasing)."""

    fluid: str
    datum: float
    pressure: float
    owc: float | None = None
    wells: tuple[FlowWell, ...] = ()
    report_days: tuple[float, ...] = ()


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


@dataclass(frozen=True, eq=False)
class FlowDeck:
    """A written deck: the DATA file, its includes, the form, and for the connection form
    the rows of ``pairs`` whose transmissibility Flow sets to 0 (``vanished``)."""

    path: Path
    form: str
    files: tuple[Path, ...]
    vanished: IntArray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    notes: tuple[str, ...] = ()


def write_flow_deck(
    directory: str | os.PathLike,
    name: str,
    grid: Deck | ConnectionGrid,
    simulation: Simulation,
    *,
    units: str = "METRIC",
    header: Sequence[str] = (),
) -> FlowDeck:
    """Write ``<name>.DATA`` and its includes into ``directory``: the native form for a
    :class:`~gridlib.cornerpoint.deck.Deck` (its cell data holding the rock), the connection
    form for a :class:`ConnectionGrid` (module docstring). ``header``: comment lines put
    first (provenance). Every file is written atomically, the DATA file last: a failure
    leaves no DATA file (and removes the includes written by this call)."""
    directory = Path(directory)
    name = name.upper()
    if not name or any(c in name for c in " '/\\") or len(name) > 64:
        raise InputError(f"name: {name!r} cannot name a deck (no spaces, quotes or slashes, at most 64)")
    system = unit_system(units)
    form = "native" if isinstance(grid, Deck) else "connections"
    if form == "native":
        if grid.units is not None and unit_system(grid.units).name != system.name:
            raise InputError(f"units: the deck is in {grid.units}, the simulation in {system.name}")
        dims, active = grid.cart_dims, grid.active
    else:
        dims = tuple(int(v) for v in grid.dims)
        active = _check_connection_grid(grid)
    _check_simulation(simulation, dims, active, form)
    written: list[Path] = []

    def include(suffix: str, blocks: Iterator[bytes]) -> str:
        path = directory / f"{name}_{suffix}.INC"
        with atomic_path(path) as tmp, open(tmp, "wb") as f:
            for block in blocks:
                f.write(block)
        written.append(path)
        return path.name

    try:
        directory.mkdir(parents=True, exist_ok=True)
        vanished = np.zeros(0, dtype=np.int64)
        notes: list[str] = []
        if form == "native":
            path = directory / f"{name}_GRID.INC"
            write_grdecl(path, replace(grid, units=None))
            written.append(path)
            grid_files, edit_files = [path.name], []
        else:
            vanished = _vanished(grid)
            if vanished.size:
                notes.append(
                    f"{vanished.size} connections below {NNC_THRESHOLD:g} {system.transmissibility_label} "
                    "between cells that are not logical neighbours vanish in Flow (it sets them to 0)"
                )
            grid_files = [
                include("GRID", _connection_grid_text(grid)),
                include("NNC", _nnc_text(grid, vanished.size, system.transmissibility_label)),
            ]
            edit_files = [include("PORV", _porv_text(grid))]
        text = _deck_text(name, form, dims, system.name, simulation, grid_files, edit_files, header)
        data = directory / f"{name}.DATA"
        with atomic_path(data) as tmp:
            tmp.write_text(text, encoding="ascii")
    except BaseException:
        for path in written:
            path.unlink(missing_ok=True)
        raise
    return FlowDeck(data, form, (data, *written), vanished, tuple(notes))


# --- checks -----------------------------------------------------------------------------------


def _check_connection_grid(grid: ConnectionGrid) -> np.ndarray:
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


def _check_simulation(sim: Simulation, dims: tuple[int, ...], active: np.ndarray, form: str) -> None:
    if sim.fluid not in FLUIDS:
        raise InputError(f"fluid: expected one of {', '.join(FLUIDS)}, got {sim.fluid!r}")
    days = np.asarray(sim.report_days, dtype=np.float64)
    if days.size and (not np.isfinite(days).all() or days[0] <= 0 or (np.diff(days) <= 0).any()):
        raise InputError(f"report_days: expected increasing positive days, got {list(sim.report_days)}")
    if sim.fluid == "oil-water" and sim.owc is None:
        raise InputError("owc: an oil-water model needs its oil-water contact depth")
    names = [w.name for w in sim.wells]
    for k, well in enumerate(sim.wells):
        where = f"wells[{k}] ({well.name!r})"
        if (
            not well.name
            or len(well.name) > 8
            or not well.name.isascii()
            or any(c in well.name for c in " '/")
        ):
            raise InputError(
                f"{where}: a well name has 1 to 8 ASCII characters, no spaces, quotes or slashes"
            )
        if names.count(well.name) > 1:
            raise InputError(f"{where}: the name is used twice")
        if well.kind not in WELL_KINDS:
            raise InputError(f"{where}: kind must be 'injector' or 'producer', got {well.kind!r}")
        if well.rate is None and well.bhp is None:
            raise InputError(f"{where}: needs a rate or a bottom-hole pressure (bhp)")
        if well.cells.size == 0:
            raise InputError(f"{where}: has no completion")
        if well.cells.min() < 0 or well.cells.max() >= active.size or not active[well.cells].all():
            raise InputError(f"{where}: a completion lies outside the active cells of the {dims} box")
        if np.unique(well.cells).size != well.cells.size:
            raise InputError(f"{where}: a cell is completed twice")
        if form == "connections" and well.factors is None:
            raise InputError(f"{where}: the connection form needs every completion's connection factor")
        if well.factors is not None and (
            well.factors.shape != well.cells.shape
            or not (np.isfinite(well.factors) & (well.factors >= 0)).all()
        ):
            raise InputError(f"{where}: expected one finite, non-negative connection factor per completion")
        if not (well.radius > 0):
            raise InputError(f"{where}: the well radius must be positive")


def _vanished(grid: ConnectionGrid) -> IntArray:
    """Rows of ``pairs`` Flow sets to 0: not logical neighbours and T below the threshold."""
    nx, ny, _ = grid.dims
    g = np.sort(np.asarray(grid.index)[np.asarray(grid.pairs, dtype=np.int64)], axis=1)
    step = g[:, 1] - g[:, 0]
    neighbour = (step == 1) | (step == nx) | (step == nx * ny)
    return np.flatnonzero(~neighbour & (np.asarray(grid.trans) < NNC_THRESHOLD))


# --- the connection form's includes -----------------------------------------------------------


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
            f"depth: Flow cells {a} and {b} of one logical column are not ordered top down "
            f"(centre depths {cd[bad]!r} and {cd[bad + 1]!r})"
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


def _keyword(name: str, values: np.ndarray, comment: str = "", integer: bool = False) -> Iterator[bytes]:
    yield (f"{name}\n" + (f"-- {comment}\n" if comment else "")).encode("ascii")
    yield from _format_values(values, integer)
    yield b"/\n\n"


def _connection_grid_text(grid: ConnectionGrid) -> Iterator[bytes]:
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
    yield from _keyword(
        "COORD", coord, f"vertical pillars {grid.spacing!r} apart (the lateral layout is cosmetic)"
    )
    yield from _keyword("ZCORN", zcorn, "each box from its top to its bottom (no cell: zero thickness)")
    yield from _keyword("ACTNUM", actnum, "1: a cell of the grid", integer=True)
    yield from _keyword("PORO", full(grid.poro), "porosity (the pore volumes are PORV in EDIT)")
    for axis, key in enumerate(("PERMX", "PERMY", "PERMZ")):
        yield from _keyword(key, full(perm[:, axis]), "mD (for the reader: the connections are NNCs)")
    for key in ("MULTX", "MULTY", "MULTZ"):
        yield from _keyword(key, np.zeros(total), "no connection of its own between the boxes")


def _porv_text(grid: ConnectionGrid) -> Iterator[bytes]:
    nx, ny, nz = grid.dims
    porv = np.zeros(nx * ny * nz)
    porv[np.asarray(grid.index, dtype=np.int64)] = grid.porv
    yield b"-- gridlib's pore volumes (EDIT: they replace what Flow computes from the boxes)\n"
    yield from _keyword("PORV", porv, "pore volume of every cell (reservoir volume unit)")


def _nnc_text(grid: ConnectionGrid, n_vanished: int, label: str) -> Iterator[bytes]:
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
    table = _text_table(distinct.tolist(), True)
    wi = table.shape[1] + 1
    trans = np.asarray(grid.trans, dtype=np.float64)
    for lo in range(0, m, _CHUNK):
        hi = min(lo + _CHUNK, m)
        codes = np.searchsorted(distinct, ijk[lo:hi])
        values = _text_table(trans[lo:hi].tolist(), False)
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


# --- the DATA file ----------------------------------------------------------------------------


def _num(value: float) -> str:
    """A number as a person writes it: integers without a decimal point, else the shortest
    text that reads back to the same float."""
    v = float(value)
    return str(int(v)) if v.is_integer() and abs(v) < 1e15 else repr(v)


def _rows(rows: list[list[float]]) -> list[str]:
    return [" " + " ".join(_num(v) for v in row) for row in rows]


def _deck_text(
    name: str,
    form: str,
    dims: tuple[int, ...],
    units: str,
    sim: Simulation,
    grid_files: list[str],
    edit_files: list[str],
    header: Sequence[str],
) -> str:
    nx, ny, nz = dims
    oil = sim.fluid == "oil-water"
    max_completions = max((w.cells.size for w in sim.wells), default=1)
    nw = len(sim.wells)
    how = {
        "native": "native: Flow computes pore volumes, transmissibilities and well factors from the grid",
        "connections": "connections: gridlib's pore volumes, transmissibilities and well factors, "
        "every connection an NNC",
    }[form]
    out = [f"-- {line.encode('ascii', 'replace').decode('ascii')}" for line in header]  # decks are ASCII
    out += [
        f"-- form {how}",
        f"-- units {_UNIT_TEXT.get(units, units)}",
        f"-- fluid: gridlib's preset {sim.fluid!r} (gridlib.fluids)",
        "",
        "RUNSPEC",
        "",
        "TITLE",
        f" {name} ({'connection' if form == 'connections' else form} form)",
        "",
        "DIMENS",
        "-- NX NY NZ",
        f" {nx} {ny} {nz} /",
        "",
        "-- phases",
        *(["OIL"] if oil else []),
        "WATER",
        "",
        units,
        "",
        "TABDIMS",
        "-- saturation tables, PVT tables, saturation rows, pressure rows",
        " 1 1 20 20 /",
        "",
        "EQLDIMS",
        "-- equilibration regions",
        " 1 /",
        "",
        "WELLDIMS",
        "-- wells, connections per well, groups, wells per group",
        f" {max(nw, 1)} {max_completions} 1 {max(nw, 1)} /",
        "",
        "START",
        START_DATE,
        "",
        "UNIFOUT",
        "",
        "GRID",
        "",
        "INIT",
        "-- write the INIT file (pore volumes, transmissibilities) for ResInsight and the tests",
        "",
    ]
    for f in grid_files:
        out += ["INCLUDE", f" '{f}' /", ""]
    if edit_files:
        out += ["EDIT", ""]
        for f in edit_files:
            out += ["INCLUDE", f" '{f}' /", ""]
    out += _props(sim.fluid, units)
    out += _solution(sim)
    out += _summary(sim)
    out += _schedule(sim, dims)
    out += ["END", ""]
    return "\n".join(out)


def _props(fluid: str, units: str) -> list[str]:
    tables = deck_tables(fluid, units)
    out = ["PROPS", "", f"-- gridlib's fluid preset {fluid!r} in {units} units (see gridlib.fluids)", ""]
    comments = {
        "SWOF": "Sw krw kro Pcow: Corey curves, Swc 0.2, Sorw 0.2, no capillary pressure",
        "PVDO": "P Bo viscosity: dead oil",
        "PVTW": "Pref Bw compressibility viscosity viscosibility",
        "DENSITY": "oil water gas at surface conditions",
        "ROCK": "Pref pore compressibility",
    }
    for key, rows in tables.items():
        text = _rows(rows)
        text[-1] += " /"
        out += [key, f"-- {comments[key]}", *text, ""]
    return out


def _solution(sim: Simulation) -> list[str]:
    owc = sim.owc if sim.owc is not None else sim.datum - 1.0  # water: every cell below the contact
    return [
        "SOLUTION",
        "",
        "EQUIL",
        "-- datum depth, pressure at datum, OWC, Pcow at OWC, GOC, Pcgo at GOC, RSVD, RVVD, N",
        "-- N = 0: each cell's initial saturation at its centre depth",
        f" {_num(sim.datum)} {_num(sim.pressure)} {_num(owc)} 0 1* 1* 1* 1* 0 /",
        "",
        "RPTRST",
        "-- the initial state in the restart file",
        " 'BASIC=2' /",
        "",
    ]


def _summary(sim: Simulation) -> list[str]:
    oil = sim.fluid == "oil-water"
    field_vectors = ["FPR", "FWIP", "FWPR", "FWPT", "FWIR", "FWIT"]
    well_vectors = ["WBHP", "WWPR", "WWIR", "WWPT", "WWIT"]
    if oil:
        field_vectors = ["FOIP", "FOPR", "FOPT", "FWCT", *field_vectors]
        well_vectors = ["WOPR", "WOPT", "WWCT", *well_vectors]
    out = ["SUMMARY", "", "-- field: average pressure, in place, rates and totals"]
    out += field_vectors
    if sim.wells:
        out += ["", "-- every well: bottom-hole pressure, rates and totals"]
        for key in well_vectors:
            out += [key, "/"]
    return [*out, ""]


def _schedule(sim: Simulation, dims: tuple[int, ...]) -> list[str]:
    nx, ny, _ = dims
    out = [
        "SCHEDULE",
        "",
        "RPTRST",
        "-- a restart file at every report step (ResInsight)",
        " 'BASIC=2' /",
        "",
    ]
    if sim.wells:
        out += [
            "WELSPECS",
            "-- name, group, I J of the wellhead, BHP reference depth (top completion), phase",
        ]
        for w in sim.wells:
            g = int(w.cells[0])
            phase = "WATER" if w.kind == "injector" or sim.fluid == "water" else "OIL"
            out.append(f" '{w.name}' 'G' {g % nx + 1} {g // nx % ny + 1} 1* '{phase}' /")
        out += ["/", "", "COMPORD", "-- completions in the order given (top down)"]
        out += [f" '{w.name}' 'INPUT' /" for w in sim.wells] + ["/", ""]
        out += [
            "COMPDAT",
            "-- name, I J K1 K2, status, sat. table, connection factor (1*: Flow's Peaceman), diameter,",
            "-- Kh, skin, D factor, direction",
        ]
        for w in sim.wells:
            factors = [None] * w.cells.size if w.factors is None else w.factors.tolist()
            for g, cf in zip(w.cells.tolist(), factors, strict=True):
                i, j, k = g % nx + 1, g // nx % ny + 1, g // (nx * ny) + 1
                item = "1*" if cf is None else repr(cf)
                rest = f"{_num(2.0 * w.radius)} 1* {_num(w.skin)} 1* 'Z'"
                out.append(f" '{w.name}' {i} {j} {k} {k} 'OPEN' 1* {item} {rest} /")
        out += ["/", ""]
        injectors = [w for w in sim.wells if w.kind == "injector"]
        producers = [w for w in sim.wells if w.kind == "producer"]
        if injectors:
            out += ["WCONINJE", "-- name, phase, status, control, surface rate, reservoir rate, BHP limit"]
            for w in injectors:
                control = "RATE" if w.rate is not None else "BHP"
                rate = "1*" if w.rate is None else _num(w.rate)
                bhp = "1*" if w.bhp is None else _num(w.bhp)
                out.append(f" '{w.name}' 'WATER' 'OPEN' '{control}' {rate} 1* {bhp} /")
            out += ["/", ""]
        if producers:
            out += ["WCONPROD", "-- name, status, control, oil, water, gas, liquid, reservoir rates, BHP"]
            for w in producers:
                control = "LRAT" if w.rate is not None else "BHP"
                rate = "1*" if w.rate is None else _num(w.rate)
                bhp = "1*" if w.bhp is None else _num(w.bhp)
                out.append(f" '{w.name}' 'OPEN' '{control}' 3* {rate} 1* {bhp} /")
            out += ["/", ""]
    if sim.report_days:
        steps = np.diff(np.concatenate([[0.0], np.asarray(sim.report_days, dtype=np.float64)]))
        out += ["TSTEP", "-- report steps (days): " + " ".join(_num(d) for d in sim.report_days)]
        out += [" " + " ".join(_num(s) for s in steps) + " /", ""]
    return out
