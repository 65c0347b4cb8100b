"""Stage ``wells``: the connections of a case's trajectory and survey wells, as ``wells.nc``.

For every deviated well of the case (:func:`gridlib.case.wells.case_well_paths`) and every path
of it (the main path, then its branches), each open MD interval (its ``perforations``; the whole
path by default) is followed through the grid (:func:`gridlib.wells.intersect.path_cells`, one
spatial index for all wells), its pieces turned into one connection per cell with the
directional factor of the piece's lengths along the cell's axes
(:func:`gridlib.wells.connections.well_connections`), and the paths of a multilateral merged
into one well (:func:`gridlib.wells.connections.merge_connections`: a cell two branches cross is
one connection, the factors summed; rows in MD order of first entry).

The factors are Peaceman's, in the grid's unit system (METRIC: cP m3/(day bar)), with the
well's ``radius`` (default 0.1 m in the case's length unit) and ``skin``, the rock of
``petrophysics.nc`` (PERMX/Y/Z, NTG) and the cells' extents: for corner-point and deck grids
those OPM Flow takes from the deck's corners
(:func:`~gridlib.transmissibility.peaceman.deck_cell_extents` of ``grid.grdecl``), as the
flow-deck stage does for vertical wells, so that an axis-aligned piece gets COMPDAT's own
factor; for other grids the grid's (:func:`~gridlib.transmissibility.peaceman.cell_extents`).
A case without rock gets the paths and the cells they cross, without factors (NaN).

A well none of whose open intervals crosses an active cell is an InputError naming the well
(its path misses the grid, or its perforations lie where the grid has no cell); an interval
that crosses none while others do is named in a note.

A deck grid with MAPAXES lies on the map as its MAPAXES place it (:mod:`gridlib.cornerpoint.map_axes`),
while the grid and every stage file stay in the deck's own x, y: the wells' paths, given on the
map as RMS, xtgeo and OPM Flow's well trajectories give them, are moved into the grid's frame
before they are followed, and wells.nc holds them there (with the grid they are drawn on).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, fields, replace

import numpy as np

from ..case.wells import WELL_RADIUS, CaseWellPath, case_well_paths
from ..config import Case
from ..cornerpoint.map_axes import MapAxes
from ..errors import InputError
from ..geometry import Geometry
from ..grid import Grid
from ..io.grdecl import read_grdecl
from ..io.wells_file import WellRecord, write_wells
from ..transmissibility.peaceman import deck_cell_extents
from ..units import UnitSystem
from ..wells.connections import WellConnections, merge_connections, well_connections
from ..wells.intersect import CellIndex, PathCells, cell_index, path_cells
from ..wells.path import WellPath
from .common import log
from .inputs import read_grid_inputs


def stage_wells(
    case: Case,
    *,
    grid: str | os.PathLike,
    geometry: str | os.PathLike,
    wells: str | os.PathLike,
    petrophysics: str | os.PathLike | None = None,
    grdecl: str | os.PathLike | None = None,
) -> tuple[WellRecord, ...]:
    """Write ``wells`` (``wells.nc``) from the case's deviated wells and its stage files
    ``grid``, ``geometry``, ``petrophysics`` (without it: no factors) and, for corner-point and
    deck cases, ``grdecl`` (the extents Flow uses); returns the wells written."""
    inputs = read_grid_inputs(grid, geometry, petrophysics)
    mesh, geo, rock, units = inputs.stored.grid, inputs.geometry, inputs.rock, inputs.units
    index = cell_index(mesh, geo)
    well_list = case_well_paths(case)
    if inputs.map_axes is not None and not inputs.map_axes.is_identity and well_list:
        log.info(
            "note: the deck's MAPAXES places its grid on the map: the wells' paths, given on the map, "
            "are followed (and written) in the grid's own x, y (origin (%s, %s) %s on the map)",
            *(f"{v:.10g}" for v in inputs.map_axes.origin),
            units.unit("length"),
        )
        well_list = tuple(_in_grid_frame(w, inputs.map_axes) for w in well_list)
    pieces = [_pieces(case, well, mesh, geo, index) for well in well_list]
    extents = None
    if grdecl is not None and mesh.cells.index_map is not None:  # Flow's, of the cells the wells cross
        crossed = np.unique(np.concatenate([np.zeros(0, np.int64)] + [p.cell for w in pieces for p in w]))
        extents = np.zeros((mesh.num_cells, 3))
        extents[crossed] = deck_cell_extents(read_grdecl(grdecl), mesh.cells.index_map[crossed])
    if rock is None:
        perm, ntg = np.ones((mesh.num_cells, 3)), np.ones(mesh.num_cells)
    else:
        perm, ntg = np.column_stack([rock["permx"], rock["permy"], rock["permz"]]), rock["ntg"]
    model = _Model(mesh, geo, perm, ntg, rock is not None, extents, units)
    records = tuple(_record(case, w, p, model) for w, p in zip(well_list, pieces, strict=True))
    write_wells(
        wells,
        records,
        units,
        attrs={**case.provenance()},
        cart_dims=mesh.cart_dims,
        index_map=mesh.cells.index_map,
        has_factors=rock is not None,
    )
    for r in records:
        log.info("%s: %d connections", r.name, r.connections.cell.size)
    log.info("wrote %s (%d wells)", wells, len(records))
    return records


def _in_grid_frame(well: CaseWellPath, axes: MapAxes) -> CaseWellPath:
    """``well`` with its paths' x, y moved from the map into the grid's frame (MD and depths
    unchanged)."""
    moved = [WellPath(axes.xyz_to_grid(p.xyz), p.md, p.name) for p in well.paths]
    return replace(well, path=moved[0], branches=tuple(moved[1:]))


@dataclass(frozen=True, eq=False)
class _Model:
    """What the wells' factors come from: the grid and its geometry, the permeability (nc, 3)
    and NTG per cell (without rock, a unit rock whose factors become NaN), the cells' extents
    (None: the grid's), the unit system."""

    grid: Grid
    geo: Geometry
    perm: np.ndarray
    ntg: np.ndarray
    has_rock: bool
    extents: np.ndarray | None
    units: UnitSystem


def _pieces(case: Case, well: CaseWellPath, grid: Grid, geo: Geometry, index: CellIndex) -> list[PathCells]:
    """The pieces of each of ``well``'s paths inside the cells, where the path is open (its
    perforations), one :class:`PathCells` per path."""
    per_path = []
    for path, intervals in zip(well.paths, well.perforations, strict=True):
        found = [path_cells(grid, geo, path.between(float(a), float(b)), index=index) for a, b in intervals]
        for (a, b), f in zip(intervals, found, strict=True):
            if f.cell.size == 0 and len(intervals) > 1:
                log.info(
                    "note: %s: well '%s', path '%s': the open interval MD %g to %g crosses no active cell",
                    case.path,
                    well.name,
                    path.name,
                    a,
                    b,
                )
        per_path.append(_joined(found))
    return per_path


def _record(case: Case, well: CaseWellPath, pieces: list[PathCells], model: _Model) -> WellRecord:
    """One well's connections from its paths' ``pieces`` (module docstring), as a record of
    ``wells.nc``."""
    radius = WELL_RADIUS * model.units.length_from_metric if well.radius is None else well.radius
    per_path = [_connections(case, well, model, p, radius) for p in pieces if p.cell.size]
    if not per_path:
        open_md = "; ".join(
            f"{path.name} MD {f[0, 0]:g} to {f[-1, 1]:g}"
            for path, f in zip(well.paths, well.perforations, strict=True)
        )
        raise InputError(
            f"{case.path}: {well.key}: well '{well.name}' crosses no active cell of the grid where it is "
            f"open ({open_md}): its path misses the grid, or its perforations lie outside it"
            + _elevation_hint(well, model.grid)
        )
    connections = per_path[0] if len(per_path) == 1 else _in_md_order(merge_connections(*per_path))
    if not model.has_rock:
        connections = replace(connections, factor=np.full(connections.cell.size, np.nan))
    return WellRecord(
        name=well.name,
        paths=well.paths,
        connections=connections,
        parents=well.parents,
        perforations=well.perforations,
        radius=float(radius),
        skin=well.skin,
    )


def _elevation_hint(well: CaseWellPath, grid: Grid) -> str:
    """A hint for a path given in elevations (z up, negative below the datum): all of it above
    the grid and its mirror image -z reaching into the grid's depths; else ''."""
    z = np.concatenate([p.xyz[:, 2] for p in well.paths])
    depth = grid.nodes.coords[:, 2]
    top, bottom = float(depth.min()), float(depth.max())
    if not (z.max() < min(top, 0.0) and -z.max() <= bottom and -z.min() >= top):
        return ""
    return (
        f"; its z ({z.min():g} to {z.max():g}) is above the grid (depth {top:g} to {bottom:g}) and -z in "
        "it: z is depth, positive down, not elevation"
    )


def _connections(
    case: Case, well: CaseWellPath, model: _Model, pieces: PathCells, radius: float
) -> WellConnections:
    try:
        return well_connections(
            model.grid,
            model.geo,
            model.perm,
            model.ntg,
            pieces,
            radius,
            well.skin,
            units=model.units,
            extents=model.extents,
        )
    except InputError as exc:
        raise InputError(f"{case.path}: {well.key}: well '{well.name}': {exc}") from None


def _in_md_order(c: WellConnections) -> WellConnections:
    """``c``'s rows by MD of first entry (a multilateral's branches interleaved as their MDs
    fall; ties in the order of ``c``)."""
    order = np.argsort(c.entry_md, kind="stable")
    return WellConnections(**{f.name: getattr(c, f.name)[order] for f in fields(WellConnections)})


def _joined(pieces: list[PathCells]) -> PathCells:
    """The pieces of one path's open intervals as one :class:`PathCells`, in MD order, their runs
    numbered on (a run does not reach across intervals)."""
    if len(pieces) == 1:
        return pieces[0]
    shift = np.cumsum([0] + [int(p.run.max()) + 1 if p.run.size else 0 for p in pieces[:-1]])
    return PathCells(
        cell=np.concatenate([p.cell for p in pieces]),
        entry_md=np.concatenate([p.entry_md for p in pieces]),
        exit_md=np.concatenate([p.exit_md for p in pieces]),
        entry=np.concatenate([p.entry for p in pieces]),
        exit=np.concatenate([p.exit for p in pieces]),
        run=np.concatenate([p.run + s for p, s in zip(pieces, shift, strict=True)]),
    )
