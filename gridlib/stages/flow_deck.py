"""Part of stage ``export``: the case's OPM Flow deck, ``flow/<NAME>.DATA`` (NAME: the case
name in upper case) with its includes, written by :func:`gridlib.io.flow.write_flow_deck`.

Which form (``form=None``, the workflow's choice): **native** for cornerpoint and deck
cases (the case's ``grid.grdecl`` with the PORO, PERMX/Y/Z and NTG of ``petrophysics.nc``
and the deck's FAULTS, MULTFLT, MULT*, region arrays, MULTREGT, NNC, PINCH and MINPV, and
its EDIT section, PORV, TRANX/TRANY/TRANZ operations and EDITNNC: Flow computes everything
itself; a deck case's rock is its deck's but for what the case
replaces, so Flow computes what it computes on the deck), the **connection form** for
every other grid (``transmissibility.nc``'s pore volumes and connections; cell centre
depths from ``geometry.nc``). ``form="connections"`` also writes a corner-point case in the
connection form: pore volumes and transmissibilities of ``transmissibility.nc`` (Flow's
own, by construction), each cell's box between the mean depth of its 4 top and of its
4 bottom corners (so its centre is Flow's), and well factors as Flow computes them
(:func:`~gridlib.transmissibility.deck_well_index`): the two forms then give the same
simulation.

Cases get a deck when they have rock (``petrophysics``, or a deck case's own) on a 3-D grid: without rock
there are no pore volumes or transmissibilities, and a 2-D grid has no depth and
transmissibilities per metre of thickness; those cases get no deck.

What the deck simulates comes from the case's ``simulation`` section (fluid preset,
initial state, wells, report days), in the case's unit system (METRIC; a deck's own,
e.g. FIELD). Without it, the deck has the oil-water preset and no wells and only
initialises the model; defaults of the initial state: datum at the top of the model,
pressure hydrostatic (the preset's water from 1 atm at the surface, to 0.01 bar or psi),
oil-water contact at the base of the model (both rounded outwards to whole metres or
feet). Wells at a point are completed in every cell their vertical line
crosses (:func:`~gridlib.completions.vertical_well_cells`), top down, with radius 0.1 m
unless the case says. Their connection factors in the connection form: Peaceman's as
Flow computes it for corner-point cases, :func:`~gridlib.transmissibility.well_index`
(the PEBI form for vertical wells in PEBI cells) for the others. Wells with a trajectory
or survey are completed as ``wells.nc`` (stage ``wells``) says: its cells in measured-depth
order, each connection's factor and direction, in both forms; the bottom-hole pressure is
referred to the depth of the first connection's cell centre.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..artifacts import artifacts, case_paths
from ..case.rock import deck_with_rock
from ..case.simulation import CaseSimulation, SimulatedWell, case_simulation
from ..completions import vertical_well_cells
from ..config import Case, load_case
from ..cornerpoint.corners import corner_depths
from ..cornerpoint.deck import Deck
from ..errors import InputError
from ..fluids import PRESET_UNIT_SYSTEMS, water_gradient
from ..geometry import Geometry
from ..grid import Grid
from ..io.flow import ConnectionGrid, FlowDeck, FlowWell, Simulation, write_flow_deck
from ..io.grdecl import read_grdecl
from ..io.netcdf import read_geometry_netcdf, read_netcdf
from ..io.netcdf_parts import check_same_cells, length_of, read_attrs, read_extra
from ..io.rock_file import read_rock
from ..io.transmissibility_file import CELL_VARS, CONNECTION_VARS, read_transmissibility
from ..io.wells_file import WellRecord, read_wells
from ..transmissibility import deck_well_index, well_index
from ..units import ATM, UnitSystem, unit_system
from ..version import __version__
from .common import log

WELL_RADIUS = 0.1  # m, the default well radius


def stage_flow_deck(
    case: Case,
    *,
    grid: str | os.PathLike,
    geometry: str | os.PathLike,
    petrophysics: str | os.PathLike,
    transmissibility: str | os.PathLike,
    flow_deck: str | os.PathLike,
    grdecl: str | os.PathLike | None = None,
    wells: str | os.PathLike | None = None,
    form: str | None = None,
) -> FlowDeck:
    """Write the case's OPM Flow deck ``flow_deck`` (``<folder>/<NAME>.DATA``) and its includes
    next to it, from its stage files ``grid``, ``geometry``, ``petrophysics``,
    ``transmissibility``, (cornerpoint and deck cases) ``grdecl`` and (cases with trajectory
    wells) ``wells``; ``form``: "native", "connections" or None (native for cornerpoint and
    deck cases, connections otherwise)."""
    if not case.writes_flow_deck:
        raise InputError(f"{case.path}: petrophysics: an OPM Flow deck needs rock properties on a 3-D grid")
    flow_deck = Path(flow_deck)
    if flow_deck.suffix != ".DATA" or flow_deck.stem != case.flow_name:
        raise InputError(f"{flow_deck}: the deck of case '{case.name}' is named {case.flow_name}.DATA")
    corner = case.writes_grdecl
    form = form or ("native" if corner else "connections")
    if form not in ("native", "connections"):
        raise InputError(f"form: expected 'native' or 'connections', got {form!r}")
    if form == "native" and not corner:
        raise InputError(
            f"{case.path}: grid.type: a {case.grid_type} grid has no native form "
            "(Flow reads corner-point grids only): use the connection form"
        )
    if corner and grdecl is None:
        raise InputError(f"{case.path}: grid: a {case.grid_type} grid's deck needs its grid.grdecl")
    stored = read_netcdf(grid)
    mesh = stored.grid
    # What is read is what the deck's form needs: a corner-point deck's depths come from its
    # corners and its T are Flow's own, so geometry only for vertical wells, connections only
    # for the connection form.
    spec = case_simulation(case)
    vertical = any(not w.has_trajectory for w in spec.wells)
    geo = read_geometry_netcdf(geometry) if (not corner or vertical) else None
    records = _trajectory_records(case, spec, wells, grid, mesh.num_cells)
    rock = read_rock(petrophysics)
    names = CONNECTION_VARS + CELL_VARS if form == "connections" else CELL_VARS
    variables, tattrs = read_transmissibility(transmissibility, names)
    counts = {
        geometry: length_of(geometry, "cell_volume"),
        petrophysics: rock["poro"].size,
        f"{transmissibility}: porv": variables["porv"].size,
    }
    check_same_cells(grid, mesh.num_cells, counts)
    system = unit_system(str(tattrs["unit_system"]))
    if system not in PRESET_UNIT_SYSTEMS:
        raise InputError(
            f"{case.path}: grid.file: the deck is in {system.name} units; OPM Flow decks are written "
            "for METRIC and FIELD cases"
        )
    deck = None
    if corner:
        deck = deck_with_rock(read_grdecl(grdecl), mesh.cells.index_map, rock, system)
        deck = replace(deck, source=f"grid.grdecl of case '{case.name}' with its rock")  # no path
    flow_index = variables["cell_flow_index"].values
    depth, thickness = _depths(mesh, geo, deck)
    model = _Model(mesh, geo, rock, deck, flow_index, system, records)
    sim = _simulation(case, model, depth, thickness, form)
    header = _header(case)
    if form == "native":
        written = write_flow_deck(flow_deck.parent, case.flow_name, deck, sim, units=system, header=header)
    else:
        cell_volumes = (
            geo.cell_volumes if geo is not None else read_extra(geometry, ("cell_volume",))["cell_volume"]
        )
        layout = ConnectionGrid(
            dims=tuple(int(v) for v in tattrs["flow_dims"]),
            index=flow_index,
            porv=variables["porv"].values,
            depth=depth,
            thickness=thickness,
            poro=rock["poro"],
            permeability=np.column_stack([rock["permx"], rock["permy"], rock["permz"]]),
            pairs=variables["connection_cells"].values,
            trans=variables["trans"].values,
            spacing=_spacing(cell_volumes, thickness),
        )
        try:
            written = write_flow_deck(
                flow_deck.parent, case.flow_name, layout, sim, units=system, header=header
            )
        except InputError as exc:
            raise InputError(f"{case.path}: {exc}") from None
    log.info("wrote %s (%s form, %d wells)", written.path, written.form, len(sim.wells))
    for note in written.notes:
        log.info("note: %s", note)
    return written


def _header(case: Case) -> list[str]:
    return [
        f"{case.flow_name}: OPM Flow deck of gridlib case '{case.name}', written by gridlib {__version__}",
        f"case file {case.path}",
        f"case sha256 {case.sha256}",
    ]


def _depths(grid: Grid, geo: Geometry | None, deck: Deck | None) -> tuple[np.ndarray, np.ndarray]:
    """Centre depth and vertical extent of every cell: for a corner-point deck as Flow takes
    them (the mean of the 8 corners; the mean depth of the 4 bottom minus the 4 top
    corners), else the centroid's depth and the mean thickness V / A (A the horizontal
    area, half the sum of |n_z| over the cell's faces)."""
    if deck is not None:
        p = corner_depths(deck, grid.cells.index_map)
        top = (((p[:, 0] + p[:, 1]) + p[:, 2]) + p[:, 3]) / 4.0
        bottom = (((p[:, 4] + p[:, 5]) + p[:, 6]) + p[:, 7]) / 4.0
        return (top + bottom) / 2.0, bottom - top
    pos = grid.cells.face_pos
    owner = np.repeat(np.arange(grid.num_cells), np.diff(pos))
    plan = 0.5 * np.bincount(owner, np.abs(geo.face_normals[grid.cells.faces, 2]), grid.num_cells)
    with np.errstate(divide="ignore", invalid="ignore"):
        thickness = np.where(plan > 0, geo.cell_volumes / plan, 0.0)
    return geo.cell_centroids[:, 2].copy(), thickness


def _spacing(volumes: np.ndarray, thickness: np.ndarray) -> float:
    """The boxes' lateral size: the square root of the median horizontal cell area, rounded
    to 3 significant digits (cosmetic: the connection form's boxes have no other use)."""
    area = float(np.median(volumes / np.maximum(thickness, 1e-300)))
    return float(f"{np.sqrt(area):.3g}") if area > 0 else 1.0


@dataclass(frozen=True)
class _Model:
    """What a deck's wells are placed on: the grid (its geometry where read), the rock per cell
    (``petrophysics.nc``), the deck with that rock (corner-point and deck cases), each cell's
    0-based linear index in the deck's logical box, and the unit system."""

    grid: Grid
    geo: Geometry | None
    rock: dict[str, np.ndarray]
    deck: Deck | None
    flow_index: np.ndarray
    system: UnitSystem
    records: dict[str, WellRecord]


def _simulation(case: Case, model: _Model, depth: np.ndarray, thickness: np.ndarray, form: str) -> Simulation:
    """The deck's simulation (:class:`~gridlib.io.flow.Simulation`): the case's `simulation`
    section with the initial state's defaults from the cells' ``depth`` and ``thickness``
    (datum at the top, hydrostatic pressure, the oil-water contact at the base) and its wells'
    cells, directions and connection factors (vertical wells' in the connection form only)."""
    spec = case_simulation(case)
    system = model.system
    fluid, initial = spec.fluid, spec.initial
    top = float(np.floor((depth - thickness / 2.0).min()))  # whole length units: a deck a person reads
    base = float(np.ceil((depth + thickness / 2.0).max()))
    datum = top if initial.datum is None else initial.datum
    hydrostatic = round(ATM / 1e5 * system.pressure_from_metric + water_gradient(system) * datum, 2)
    pressure = hydrostatic if initial.pressure is None else initial.pressure
    owc = None if fluid == "water" else (base if initial.owc is None else initial.owc)
    wells = tuple(
        _trajectory_well(case, w, model, depth) if w.has_trajectory else _vertical_well(case, w, model, form)
        for w in spec.wells
    )
    return Simulation(fluid, datum, pressure, owc, wells, spec.report_days)


def _vertical_well(case: Case, w: SimulatedWell, model: _Model, form: str) -> FlowWell:
    """A vertical well at its point, completed top down in every cell its line crosses; its
    factors in the connection form (Flow computes them in the native form)."""
    grid, geo, rock, deck, system = model.grid, model.geo, model.rock, model.deck, model.system
    key = f"{case.path}: {w.key}"
    axes = None if deck is None else deck.map_axes  # the point is on the map, the grid in its own frame
    cells = vertical_well_cells(
        grid, geo, w.point if axes is None else tuple(axes.to_grid(np.array(w.point)))
    )
    if cells.size == 0:
        raise InputError(
            f"{key}.name: well '{w.name}' at ({w.point[0]:g}, {w.point[1]:g}) lies outside every "
            "active cell of the grid"
        )
    radius = WELL_RADIUS * system.length_from_metric if w.radius is None else w.radius
    factors = None
    try:
        if form == "connections":
            if deck is not None:
                factors = deck_well_index(deck, grid.cells.index_map[cells], radius, w.skin)
            else:
                perm = np.column_stack([rock["permx"], rock["permy"], rock["permz"]])
                factors = well_index(grid, geo, perm, cells, radius, w.skin, ntg=rock["ntg"], units=system)
    except InputError as exc:
        raise InputError(f"{key}.radius: well '{w.name}': {exc}") from None
    in_box = model.flow_index[cells]
    return FlowWell(w.name, w.kind, in_box, radius, w.skin, factors, w.rate, w.bhp)


def _trajectory_well(case: Case, w: SimulatedWell, model: _Model, depth: np.ndarray) -> FlowWell:
    """A well along its path: the connections of ``wells.nc`` (cells in measured-depth order,
    branches merged), their factors and directions in both forms (Flow 2022.10 computes
    factors for wells along the cells' axes only), the bottom-hole pressure referred to the
    depth of the first connection's cell centre, which is where Flow puts the connection."""
    record = model.records[w.name]
    c = record.connections
    radius = WELL_RADIUS * model.system.length_from_metric if record.radius is None else record.radius
    return FlowWell(
        w.name,
        w.kind,
        model.flow_index[c.cell],
        radius,
        record.skin,
        c.factor,
        w.rate,
        w.bhp,
        directions=c.direction,
        reference_depth=float(depth[c.cell[0]]),
    )


def _trajectory_records(
    case: Case,
    spec: CaseSimulation,
    wells: str | os.PathLike | None,
    grid: str | os.PathLike,
    num_cells: int,
) -> dict[str, WellRecord]:
    """The ``wells.nc`` records of the simulated trajectory wells, by name (none: {}), their
    cells checked against ``grid``'s ``num_cells``."""
    deviated = [w for w in spec.wells if w.has_trajectory]
    if not deviated:
        return {}
    if wells is None:
        raise InputError(
            f"{case.path}: {deviated[0].key}.name: well '{deviated[0].name}' has a trajectory: its deck "
            "needs wells.nc (the stage 'wells')"
        )
    records = {r.name: r for r in read_wells(wells)}
    for w in spec.wells:
        if w.has_trajectory and (w.name not in records or records[w.name].connections.cell.size == 0):
            raise InputError(f"{case.path}: {w.key}.name: well '{w.name}' has no connection in {wells}")
    for r in records.values():
        outside = r.connections.cell[(r.connections.cell < 0) | (r.connections.cell >= num_cells)]
        if outside.size:
            raise InputError(
                f"{wells}: well '{r.name}' connects cell {int(outside.max())}, but {grid} has {num_cells} "
                "cells: wells.nc is another grid's (run the stage 'wells' again)"
            )
    return records


def flow_deck_from_results(
    results_dir: str | os.PathLike,
    out_dir: str | os.PathLike,
    form: str | None = None,
    case_file: str | os.PathLike | None = None,
) -> FlowDeck:
    """The deck of a built case (``gridlib flow-deck``): its artifacts in ``results_dir``, its
    case file (default: the one recorded in them, as it was given to the build, relative to
    the directory the build ran in), which must not have changed since; the deck goes to
    ``out_dir``."""
    stage_files = ("grid", "geometry", "petrophysics", "transmissibility")
    where = Path(results_dir)
    names = {key: where / artifacts()[key].path for key in stage_files}  # not named after the case
    for path in names.values():
        if not path.is_file():
            raise InputError(
                f"{results_dir}: {path.name} not found (a built case with petrophysics is needed)"
            )
    attrs = read_attrs(names["transmissibility"])
    if case_file is None:
        case_file = Path(str(attrs.get("case_file", "")))
        if not case_file.is_file():
            raise InputError(
                f"{names['transmissibility']}: case_file: '{case_file}' not found (give the case file)"
            )
    case = load_case(case_file)
    if case.name != attrs.get("case_name"):
        raise InputError(
            f"{case_file}: name: case '{case.name}', but {results_dir} holds case '{attrs.get('case_name')}'"
        )
    if case.sha256 != attrs.get("case_sha256"):
        raise InputError(
            f"{case_file}: changed since {results_dir} was built (its SHA-256 differs): build the case again"
        )
    paths = case_paths(case.name, results_dir)
    grdecl = paths["grdecl"] if case.writes_grdecl else None
    wells = paths["wells"] if case.has_deviated_wells else None
    deck = artifacts()["flow_deck"].path_in(out_dir, case.name).name
    return stage_flow_deck(
        case,
        **{key: paths[key] for key in stage_files},
        flow_deck=Path(out_dir) / deck,
        grdecl=grdecl,
        wells=wells,
        form=form,
    )
