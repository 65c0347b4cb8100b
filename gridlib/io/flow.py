"""OPM Flow decks of any grid: :func:`write_flow_deck` writes ``<NAME>.DATA`` and its includes.

Two forms, one writer:

* **native** (corner-point and deck grids): the GRID section is the corner-point deck
  itself (COORD, ZCORN, ACTNUM, PORO, PERMX/Y/Z, NTG, FAULTS, MULTFLT, written by
  :func:`~gridlib.io.grdecl.write_grdecl` into ``<NAME>_GRID.INC``), and the deck's
  EDIT section where it has one (PORV, TRANX/TRANY/TRANZ operations, EDITNNC, in
  ``<NAME>_EDIT.INC``, :func:`~gridlib.io.grdecl.write_edit_grdecl`): Flow computes its
  own transmissibilities, well connection factors and pore volumes (but where PORV gives them).
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
  in COMPDAT item 8, since Flow's own would come from the boxes. (Trajectory wells get
  them in both forms: Flow 2022.10 computes factors for wells along a cell axis only.)

  Flow 2022.10 sets connections that are not between logical neighbours (index
  difference 1, nx or nx ny) and have a transmissibility below 1e-6 (deck units) to 0:
  those vanish from the model. :attr:`FlowDeck.vanished` lists them and the NNC
  include says how many; nothing else is lost.

  The connection form's grid, its boxes and the text of its includes are in
  :mod:`gridlib.io.flow_connections`.

The deck (both forms): RUNSPEC, GRID, EDIT, PROPS (a fluid preset of
:mod:`gridlib.fluids`), SOLUTION (EQUIL with item 9 = 0: every cell's saturation at its
centre depth, the only point the connection form's boxes share with the cell), SUMMARY
(field, and well vectors when there are wells) and SCHEDULE (restart files at every
report step, WELSPECS, COMPORD INPUT, one COMPDAT record per completion in the order
given (vertical wells top down, trajectory wells by measured depth) with its direction,
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
from ..units import METRIC, UnitSystem, unit_system
from .atomic import atomic_path
from .flow_connections import (
    NNC_THRESHOLD,
    ConnectionGrid,
    box_corners,
    box_depths,
    check_connection_grid,
    connection_grid_text,
    nnc_text,
    porv_text,
    vanished_connections,
)
from .grdecl import write_edit_grdecl, write_grdecl

__all__ = [
    "FORMS",
    "NNC_THRESHOLD",
    "ConnectionGrid",
    "FlowDeck",
    "FlowWell",
    "Simulation",
    "box_corners",
    "box_depths",
    "write_flow_deck",
]

FORMS = ("native", "connections")
WELL_KINDS = ("injector", "producer")
START_DATE = " 1 'JAN' 2020 /"


@dataclass(frozen=True, eq=False)
class FlowWell:
    """A well and its completions (connections), one COMPDAT record each.

    ``cells``: the Flow cells it is completed in (0-based linear indices of the deck's
    box), in the order Flow is to take them (COMPORD INPUT): a vertical well's top down, a
    trajectory well's in measured-depth order (a multilateral's branches merged into one
    well, as ``wells.nc`` gives them). ``factors``: the connection factor of each
    completion (deck units), None to let Flow compute Peaceman's from its own grid (native
    form, for wells along the cells' axes only). ``directions``: the axis each completion
    runs along, 0, 1, 2 for COMPDAT's 'X', 'Y', 'Z' (one per completion; None: all 'Z',
    a vertical well). ``radius`` (length unit) and ``skin`` go to COMPDAT.
    ``reference_depth``: the depth (length unit) of the bottom-hole pressure (WELSPECS item 5; None: 1*,
    which Flow takes as the depth of the first connection). ``kind``: "injector" (water)
    or "producer"; ``rate`` (surface rate, water for an injector, liquid for a producer)
    and ``bhp``: the controls, at least one of them; with both, the rate is the target and
    the bottom-hole pressure the limit.
    """

    name: str
    kind: str
    cells: IntArray
    radius: float
    skin: float = 0.0
    factors: FloatArray | None = None
    rate: float | None = None
    bhp: float | None = None
    directions: IntArray | None = None
    reference_depth: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "cells", np.asarray(self.cells, dtype=np.int64).ravel())
        if self.factors is not None:
            object.__setattr__(self, "factors", np.asarray(self.factors, dtype=np.float64).ravel())
        if self.directions is not None:
            object.__setattr__(self, "directions", np.asarray(self.directions).ravel())


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
    units: UnitSystem | str = METRIC,
    header: Sequence[str] = (),
) -> FlowDeck:
    """Write ``<name>.DATA`` and its includes into ``directory``: the native form for a
    :class:`~gridlib.cornerpoint.deck.Deck` (its cell data holding the rock), the connection
    form for a :class:`ConnectionGrid` (module docstring). ``units``: the deck's unit system
    (METRIC or FIELD), a :class:`~gridlib.units.UnitSystem` or its name. ``header``: comment
    lines put first (provenance). Every file is written atomically, the DATA file last: a
    failure leaves no DATA file (and removes the includes written by this call)."""
    directory = Path(directory)
    name = name.upper()
    if not name or any(c in name for c in " '/\\") or len(name) > 64:
        raise InputError(f"name: {name!r} cannot name a deck (no spaces, quotes or slashes, at most 64)")
    units = unit_system(units)
    form = "native" if isinstance(grid, Deck) else "connections"
    if form == "native":
        if grid.units is not None and unit_system(grid.units) != units:
            raise InputError(f"units: the deck is in {grid.units}, the simulation in {units.name}")
        dims, active = grid.cart_dims, grid.active
    else:
        dims = tuple(int(v) for v in grid.dims)
        active = check_connection_grid(grid)
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
            write_grdecl(path, replace(grid, units=None), edit=False)
            written.append(path)
            grid_files, edit_files = [path.name], []
            edit_path = write_edit_grdecl(directory / f"{name}_EDIT.INC", grid)
            if edit_path is not None:
                written.append(edit_path)
                edit_files.append(edit_path.name)
        else:
            vanished = vanished_connections(grid)
            if vanished.size:
                notes.append(
                    f"{vanished.size} connections below {NNC_THRESHOLD:g} {units.transmissibility_label} "
                    "between cells that are not logical neighbours vanish in Flow (it sets them to 0)"
                )
            grid_files = [
                include("GRID", connection_grid_text(grid)),
                include("NNC", nnc_text(grid, vanished.size, units.transmissibility_label)),
            ]
            edit_files = [include("PORV", porv_text(grid))]
        text = _deck_text(name, form, dims, units, simulation, grid_files, edit_files, header)
        data = directory / f"{name}.DATA"
        with atomic_path(data) as tmp:
            tmp.write_text(text, encoding="ascii")
    except BaseException:
        for path in written:
            path.unlink(missing_ok=True)
        raise
    return FlowDeck(data, form, (data, *written), vanished, tuple(notes))


# --- checks -----------------------------------------------------------------------------------


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
        d = well.directions
        if d is not None and (
            d.shape != well.cells.shape or not np.issubdtype(d.dtype, np.integer) or ((d < 0) | (d > 2)).any()
        ):
            raise InputError(f"{where}: expected one direction per completion, 0, 1 or 2 (X, Y or Z)")
        if well.reference_depth is not None and not np.isfinite(well.reference_depth):
            raise InputError(f"{where}: the reference depth must be finite")


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
    units: UnitSystem,
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
        f"-- units {_units_text(units)}",
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
        units.name,
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


def _units_text(u: UnitSystem) -> str:
    """The deck's units, as its header comment names them."""
    labels = (u.length_label, u.pressure_label, u.rate_label, u.reservoir_volume_label)
    labels += (u.viscosity_label, u.permeability_label, u.density_label)
    return f"{u.name}: {', '.join(labels)}; T and CF in {u.transmissibility_label}"


def _props(fluid: str, units: UnitSystem) -> list[str]:
    tables = deck_tables(fluid, units)
    out = ["PROPS", "", f"-- gridlib's fluid preset {fluid!r} in {units.name} units (see gridlib.fluids)", ""]
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
            "-- name, group, I J of the first connection, BHP reference depth (1*: the first",
            "-- connection's), phase",
        ]
        for w in sim.wells:
            g = int(w.cells[0])
            phase = "WATER" if w.kind == "injector" or sim.fluid == "water" else "OIL"
            depth = "1*" if w.reference_depth is None else _num(w.reference_depth)
            out.append(f" '{w.name}' 'G' {g % nx + 1} {g // nx % ny + 1} {depth} '{phase}' /")
        out += [
            "/",
            "",
            "COMPORD",
            "-- connections in the order given (vertical wells top down, trajectories by measured depth)",
        ]
        out += [f" '{w.name}' 'INPUT' /" for w in sim.wells] + ["/", ""]
        out += [
            "COMPDAT",
            "-- name, I J K1 K2, status, sat. table, connection factor (1*: Flow's Peaceman), diameter,",
            "-- Kh, skin, D factor, direction",
        ]
        for w in sim.wells:
            out += _compdat(w, nx, ny)
        out += ["/", ""]
        for kind, keyword, comment, rate_control, record in _CONTROLS:
            out += _controls([w for w in sim.wells if w.kind == kind], keyword, comment, rate_control, record)
    if sim.report_days:
        steps = np.diff(np.concatenate([[0.0], np.asarray(sim.report_days, dtype=np.float64)]))
        out += ["TSTEP", "-- report steps (days): " + " ".join(_num(d) for d in sim.report_days)]
        out += [" " + " ".join(_num(s) for s in steps) + " /", ""]
    return out


def _compdat(well: FlowWell, nx: int, ny: int) -> list[str]:
    """The COMPDAT records of ``well``, one per connection: 1-based I J K (K1 = K2), its
    connection factor (1*: Flow's Peaceman) and direction."""
    g = well.cells
    i, j, k = g % nx + 1, g // nx % ny + 1, g // (nx * ny) + 1
    n = g.size
    factors = ["1*"] * n if well.factors is None else [repr(cf) for cf in well.factors.tolist()]
    axes = np.full(n, 2) if well.directions is None else well.directions
    rest = f"{_num(2.0 * well.radius)} 1* {_num(well.skin)} 1*"
    return [
        f" '{well.name}' {a} {b} {c} {c} 'OPEN' 1* {cf} {rest} '{'XYZ'[d]}' /"
        for a, b, c, cf, d in zip(i.tolist(), j.tolist(), k.tolist(), factors, axes.tolist(), strict=True)
    ]


# Per kind of well: its control keyword, the keyword's comment, the control by rate, a record.
_CONTROLS = (
    (
        "injector",
        "WCONINJE",
        "-- name, phase, status, control, surface rate, reservoir rate, BHP limit",
        "RATE",
        " '{name}' 'WATER' 'OPEN' '{control}' {rate} 1* {bhp} /",
    ),
    (
        "producer",
        "WCONPROD",
        "-- name, status, control, oil, water, gas, liquid, reservoir rates, BHP",
        "LRAT",
        " '{name}' 'OPEN' '{control}' 3* {rate} 1* {bhp} /",
    ),
)


def _controls(wells: list[FlowWell], keyword: str, comment: str, rate_control: str, record: str) -> list[str]:
    """WCONINJE or WCONPROD for ``wells`` (none: no keyword): each well controlled by its rate
    (``rate_control``) if it has one, else by its bottom-hole pressure, the other a limit or
    defaulted (``1*``); ``record`` is the text of a well's record with {name}, {control},
    {rate} and {bhp}."""
    if not wells:
        return []
    out = [keyword, comment]
    for w in wells:
        control = rate_control if w.rate is not None else "BHP"
        rate = "1*" if w.rate is None else _num(w.rate)
        bhp = "1*" if w.bhp is None else _num(w.bhp)
        out.append(record.format(name=w.name, control=control, rate=rate, bhp=bhp))
    return [*out, "/", ""]
