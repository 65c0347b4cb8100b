"""Stage ``grid``: the case's grid, checked, as ``grid.nc`` (and ``grid.grdecl`` for decks).

``grid.nc`` holds the grid, per-cell data of the builder (bulk volume in
ECLIPSE's convention, well id, zone, layer, the PEBI site of each cell), the
non-neighbour connections (``nnc_*`` variables), the fault and well names
(attributes, JSON lists) and the ``unit_system`` of its coordinates (METRIC:
metres; a FIELD deck's grid is in feet).
Corner-point and deck cases also get ``grid.grdecl`` (GRDECL for simulators:
geometry, ACTNUM, FAULTS, and the deck's own cell keywords and GRID-section settings,
MULTREGT with its region sets resolved as GRIDOPTS said, NNC; then, if the deck has
one, the ``EDIT`` keyword and its EDIT section: PORV, the TRANX/TRANY/TRANZ operations
in deck order, EDITNNC; the EDIT section's MULT* arrays are already multiplied into
the GRID values). The transmissibility and flow-deck stages read it back as the deck.

Every grid is checked (:mod:`gridlib.checks`). A grid gridlib builds (cartesian, cornerpoint,
pebi, ...) must pass every invariant: any failure is an error. A ``deck`` case's grid is
someone else's: what is broken (topology, crossing pillars: refused while the deck is read)
is an error naming the deck and the cells, while *degenerate* cells (polyhedral volume not
positive, faces not closing: thin wedges beside faults that OPM Flow runs) are kept, each
named in the stage's notes, flagged in the cell data ``degenerate`` (1: volume not positive,
2: not closed, 3: both; written only when there are any) and counted in ``summary.json``.
The simulator's volume of such a cell is its ECLIPSE bulk volume (``bulk_volume``), which the
pore volumes use; the geometry stage keeps its polyhedral volume.
"""

from __future__ import annotations

import os
from dataclasses import replace

from ..case.grid import CaseGrid, build_case_grid
from ..checks import check_deck_grid, check_grid
from ..config import Case
from ..errors import GridError, InputError
from ..io.grdecl import write_grdecl
from ..io.grdecl.edit import edit_section_contents
from ..io.grid_nnc import nnc_variables
from ..io.horizon_files import read_horizons
from ..io.netcdf import write_netcdf
from ..transmissibility.region_multipliers import with_explicit_region_sets
from ..units import UnitSystem, unit_system
from .common import log


def grid_unit_system(built: CaseGrid) -> UnitSystem:
    """The ECLIPSE unit system of the grid's coordinates: a deck's own (METRIC where it does not
    say, ECLIPSE's default), METRIC (metres) for every grid gridlib builds."""
    units = built.deck.units if built.deck is not None else None
    return unit_system(units)


def checked(case: Case, built: CaseGrid) -> CaseGrid:
    """``built`` after :func:`~gridlib.checks.check_grid` (grids gridlib builds) or, for a deck
    case, :func:`~gridlib.checks.check_deck_grid`: its degenerate cells named in the notes and
    flagged in the cell data ``degenerate``; anything broken raises an InputError naming the
    case and the deck."""
    if case.grid_type != "deck":
        check_grid(built.grid)
        return built
    source = built.deck.source if built.deck is not None else "the deck"
    try:
        degenerate = check_deck_grid(built.grid)
    except GridError as exc:
        raise InputError(f"{case.path}: grid.file: {source}: {exc}") from None
    if not len(degenerate):
        return built
    flags = degenerate.flags(built.grid.num_cells)
    notes = built.notes + degenerate.notes(built.grid)
    return replace(built, cell_data={**built.cell_data, "degenerate": flags}, notes=notes)


def stage_grid(
    case: Case,
    *,
    grid: str | os.PathLike,
    horizons: str | os.PathLike | None = None,
    grdecl: str | os.PathLike | None = None,
) -> None:
    """Build the case's grid (between the horizons of the file ``horizons``), check every
    invariant, write ``grid`` (``grid.nc``) and, for corner-point and deck grids, ``grdecl``
    (``grid.grdecl``)."""
    surfaces = read_horizons(horizons) if horizons else None
    built = checked(case, build_case_grid(case, surfaces))
    for note in built.notes:
        log.info("note: %s", note)
    attrs = {
        **case.provenance(),
        "fault_names": list(built.fault_names),
        "well_names": list(built.well_names),
        "unit_system": grid_unit_system(built).name,
    }
    if built.deck is not None and built.deck.mapaxes is not None:
        # where the grid's own x, y lie on the map: a case's map coordinates (its wells) meet it
        attrs["map_axes"] = [float(v) for v in built.deck.mapaxes]
    write_netcdf(grid, built.grid, cell_data=built.cell_data, extra=nnc_variables(built.nnc), attrs=attrs)
    log.info("wrote %s: %r", grid, built.grid)
    deck = built.deck
    del built  # the grid, most of the memory, is written: the GRDECL needs the deck alone
    if grdecl is not None:
        if deck is None:
            raise ValueError(f"{case.path}: grid.grdecl is only written for cornerpoint and deck grids")
        # grid.grdecl has no RUNSPEC: its MULTREGT records name their region set, which GRIDOPTS
        # may have defaulted
        write_grdecl(grdecl, with_explicit_region_sets(deck))
        carried = edit_section_contents(deck)
        if carried:
            log.info(
                "note: %s ends with the deck's EDIT section (%s), which the transmissibilities and "
                "the OPM Flow deck of this case apply as Flow does",
                grdecl,
                ", ".join(carried),
            )
        log.info("wrote %s", grdecl)
