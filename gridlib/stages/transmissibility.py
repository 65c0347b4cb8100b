"""Stage ``transmissibility``: what a two-point flux simulator needs, as ``transmissibility.nc``.

Per connection (a pair of cells with a non-zero transmissibility; dimension
``connection``): ``connection_cells`` (the two cells, rows of ``grid.nc``, first <
second), ``trans``, ``connection_kind`` (0 neighbor, 1 fault, 2 pinch, 3 other) and
``connection_face`` (the face crossed, -1 for none). Per cell: ``porv``, the pore
volume, and ``cell_flow_index``, the cell's 0-based linear index (i fastest) in the
logical box ``flow_dims`` a simulator sees.

Which computation, by grid type (the ``method`` attribute says which ran):

* **cornerpoint and deck** (the cases that write ``grid.grdecl``):
  :func:`~gridlib.transmissibility.deck_connections.deck_transmissibility` on ``grid.grdecl`` with
  the case's PERMX, PERMY, PERMZ and NTG from ``petrophysics.nc`` (per grid cell, put
  on the deck's cells through ``index_map``; for a deck case the deck's own unless the
  case replaces them) and the deck's MULT*, MULTFLT, MULTREGT with its region arrays,
  PINCH, MINPV, NNC and its EDIT section (TRANX/TRANY/TRANZ operations, EDITNNC):
  ECLIPSE's NEWTRAN as OPM Flow computes it, so the T equal Flow's for that deck. Pore
  volume as Flow (:func:`~gridlib.cornerpoint.pore_volume.pore_volumes`): the ECLIPSE
  bulk volume (``bulk_volume`` of ``grid.nc``) x PORO x NTG x MULTPV, but the PORV of
  the deck's EDIT section where it gives one, whatever porosity or NTG the case gives
  there (a note says so). ``cell_flow_index`` is the grid's
  ``index_map``, ``flow_dims`` the deck's dimensions;
* **pebi**: :func:`~gridlib.transmissibility.transmissibility` with each cell's
  generating site (x, y) at its centroid's depth as the cell centre (``site`` in
  ``grid.nc``, stored by the grid stage) and ``distance="normal"`` (centre to the
  face's plane): the lateral faces are the sites' perpendicular bisectors, so a
  lateral T is K A / d exactly, d the distance of the two sites, also in dipping
  layers and across fault throw;
* **every other grid**: the same with the centroids.

For the last two, the pore volume is the geometric cell volume x porosity x NTG,
and ``cell_flow_index`` is the grid's ``index_map`` in its ``cart_dims`` (cartesian
and tensor grids); for layered grids (pebi, layered) column + n_columns x layer in a
box of n_columns x 1 x n_layers, so that k is the layer; else the cell number itself
(a box of num_cells x 1 x 1). Such grids reach a simulator as a list of connections,
not through its own geometry: the box only numbers the cells. For 2-D grids T and
pore volumes are per metre of thickness.

Units: the grid's ``unit_system`` (METRIC, or a deck's own, e.g. FIELD for SPE9):
T in its transmissibility unit (METRIC cP m3/(day bar), FIELD cP rb/(day psi)),
pore volumes in its reservoir volume unit (rm3, rb), permeability in mD.
The stage runs for cases with petrophysics (T needs permeability, pore volume
porosity).
"""

from __future__ import annotations

import os
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from ..case.rock import case_rock_keys, deck_with_rock
from ..config import Case
from ..cornerpoint.pore_volume import pore_volumes
from ..cornerpoint.process import CornerPointGrid
from ..errors import InputError
from ..geometry import Geometry
from ..grid import Grid
from ..io.grdecl import read_grdecl
from ..io.grid_nnc import read_nnc
from ..io.netcdf import GridDataset, read_geometry_netcdf, read_netcdf, write_dataset
from ..io.netcdf_parts import check_same_cells, length_of, read_attrs
from ..io.rock_file import read_rock
from ..io.transmissibility_file import connections_dataset
from ..pillars.nnc import NNC
from ..transmissibility import Connections, deck_transmissibility, transmissibility
from ..transmissibility.deck_connections import rock_arrays
from ..units import UnitSystem, unit_system
from .common import log


def stage_transmissibility(
    case: Case,
    *,
    grid: str | os.PathLike,
    geometry: str | os.PathLike,
    petrophysics: str | os.PathLike,
    transmissibility: str | os.PathLike,
    grdecl: str | os.PathLike | None = None,
) -> None:
    """Connections, transmissibilities and pore volumes of the grid of the files ``grid`` and
    ``geometry`` with the rock of ``petrophysics``; write ``transmissibility``
    (``transmissibility.nc``). ``grdecl``: the case's ``grid.grdecl`` (cornerpoint and deck
    cases, which need it)."""
    stored = read_netcdf(grid)
    mesh = stored.grid
    rock = read_rock(petrophysics)
    counts = {geometry: length_of(geometry, "cell_volume"), petrophysics: rock["poro"].size}
    check_same_cells(grid, mesh.num_cells, counts)
    attrs = read_attrs(grid)
    if "unit_system" not in attrs:
        raise InputError(f"{grid}: unit_system: attribute missing (written by an older gridlib: rebuild it)")
    system = unit_system(str(attrs["unit_system"]))
    if case.writes_grdecl:
        if grdecl is None:
            raise InputError(f"{case.path}: grid: a {case.grid_type} grid's T need its grid.grdecl")
        conn, porv, method = _deck_case(case, grid, stored, attrs, rock, Path(grdecl), system)
        flow_index, flow_dims = mesh.cells.index_map, tuple(mesh.cart_dims)
    else:  # a deck's T need no geometry of ours; any other grid's need all of it
        geo = read_geometry_netcdf(geometry)
        conn, centres = _grid_case(case, grid, stored, geo, rock, system)
        porv = geo.cell_volumes * rock["poro"] * rock["ntg"] * system.volume_per_cubic_length
        method = f"transmissibility (two-point flux, cell centres: {centres})"
        flow_index, flow_dims = _flow_index(mesh)
    ds = connections_dataset(conn, porv, flow_index, flow_dims, system)
    ds.attrs |= {
        **case.provenance(),
        "title": "gridlib transmissibility",
        "method": method,
        "notes": "; ".join(conn.notes),
    }
    write_dataset(transmissibility, ds)
    counts = ", ".join(f"{v:,d} {k}" for k, v in conn.counts().items() if v)
    log.info(
        "wrote %s: %d connections (%s), T %.6g to %.6g %s, pore volume %.6g %s",
        transmissibility,
        conn.num,
        counts or "none",
        conn.trans.min() if conn.num else 0.0,
        conn.trans.max() if conn.num else 0.0,
        system.transmissibility_label,
        porv.sum(),
        system.reservoir_volume_label,
    )
    for note in conn.notes:
        log.info("note: %s", note)


def _deck_case(
    case: Case,
    grid_nc: str | os.PathLike,
    stored: GridDataset,
    attrs: dict[str, Any],
    rock: dict[str, np.ndarray],
    grdecl: Path,
    system: UnitSystem,
) -> tuple[Connections, np.ndarray, str]:
    """deck_transmissibility of ``grid.grdecl`` with the case's rock; Flow's pore volumes."""
    grid = stored.grid
    deck = read_grdecl(grdecl)
    if grid.cells.index_map is None or tuple(grid.cart_dims or ()) != deck.cart_dims:
        raise InputError(
            f"{grdecl}: SPECGRID: {deck.cart_dims} does not match the grid of {grid_nc} "
            f"(logical dimensions {grid.cart_dims})"
        )
    if "bulk_volume" not in stored.cell_data:
        raise InputError(f"{grid_nc}: bulk_volume: missing (a cornerpoint or deck grid stores it)")
    index = grid.cells.index_map
    deck = deck_with_rock(deck, index, rock, system)
    nnc = read_nnc(grid_nc)
    if nnc is None:
        empty = np.zeros((0, 2), dtype=np.int64)
        nnc = NNC(empty, empty, np.zeros(0, dtype=np.int8), np.zeros(0, dtype=np.int64))
    bulk = stored.cell_data["bulk_volume"]
    cp = CornerPointGrid(grid, nnc, tuple(attrs.get("fault_names", ())), (), bulk)
    conn = deck_transmissibility(deck, cp)
    said: list[str] = []  # PORO or NTG above 1 in the case's rock: the petrophysics stage noted them
    rock_arrays(deck, said)
    conn = replace(conn, notes=tuple(n for n in conn.notes if n not in said))
    porv = pore_volumes(deck, index, bulk)  # Flow's: EDIT PORV, else bulk x PORO x NTG x MULTPV
    if "PORV" in deck.cell_data:
        conn = replace(conn, notes=(*conn.notes, *_porv_notes(case, deck.cell_data["PORV"][index])))
    if (porv == 0).any():  # the grid was built before the rock: its cells stay
        conn = replace(
            conn,
            notes=(
                *conn.notes,
                f"{int((porv == 0).sum())} grid cells have zero pore volume with the case's petrophysics "
                "(OPM Flow would make them inactive)",
            ),
        )
    method = "deck_transmissibility (ECLIPSE NEWTRAN, MULT* and MULTFLT as OPM Flow 2022.10 computes them)"
    return conn, porv, method


def _porv_notes(case: Case, porv: np.ndarray) -> list[str]:
    """What the deck's EDIT PORV (``porv`` per grid cell, NaN where Flow computes it) does to
    the pore volumes, and to the case's porosity or net-to-gross there: nothing (PORV wins)."""
    given = int((~np.isnan(porv)).sum())
    notes = [f"pore volumes: the PORV of the deck's EDIT section in {given} of {porv.size} grid cells"]
    keys = [k for k in ("porosity", "ntg") if k in case_rock_keys(case)]
    if keys and given:
        named = " and ".join(f"petrophysics.{k}" for k in keys)
        verb = "leave" if len(keys) > 1 else "leaves"
        notes.append(
            f"{named} {verb} the pore volume of those {given} cells as the deck's PORV gives it "
            "(as in OPM Flow, PORV wins over PORO and NTG)"
        )
    return notes


def _grid_case(
    case: Case,
    grid_nc: str | os.PathLike,
    stored: GridDataset,
    geo: Geometry,
    rock: dict[str, np.ndarray],
    system: UnitSystem,
) -> tuple[Connections, str]:
    """Two-point flux T of any grid: centroids, or the PEBI sites at the centroids' depth."""
    grid = stored.grid
    d = grid.griddim
    perm = np.column_stack([rock["permx"], rock["permy"], rock["permz"]])[:, :d]
    ntg = None if (rock["ntg"] == 1.0).all() else rock["ntg"]
    centres, what = cell_centres(case, grid_nc, stored, geo)
    distance = "centroid"
    if centres is not None:
        what, distance = f"{what}, distance to the face plane", "normal"
    try:
        conn = transmissibility(grid, geo, perm, ntg, centres=centres, distance=distance, units=system)
    except InputError as exc:
        raise InputError(f"{case.path}: petrophysics: {exc}") from None
    return conn, what


def cell_centres(
    case: Case, grid_nc: str | os.PathLike, stored: GridDataset, geo: Geometry
) -> tuple[np.ndarray | None, str]:
    """The cell centres of the two-point flux of a grid that is not a deck's: for a PEBI grid
    each cell's generating site (x, y) at its centroid's depth, else None (the centroids);
    and what they are, in words."""
    if case.grid_type != "pebi":
        return None, "centroids"
    grid = stored.grid
    site = stored.cell_data.get("site")
    if site is None or site.shape != (grid.num_cells, 2):
        raise InputError(
            f"{grid_nc}: site: the PEBI sites are missing (written by an older gridlib: rebuild it)"
        )
    centres = np.column_stack([site, geo.cell_centroids[:, 2]]) if grid.griddim == 3 else site
    return centres, "generating sites (x, y) at the centroid depth"


def _flow_index(grid: Grid) -> tuple[np.ndarray, tuple[int, ...]]:
    """The cells' linear indices in a logical box: ``index_map`` in ``cart_dims`` where the grid
    has them; for layered grids column + n_columns x layer in (n_columns, 1, n_layers), so that
    k is the layer; else the cell numbers in a box of num_cells x 1 x 1."""
    if grid.cells.index_map is not None and grid.cart_dims is not None:
        dims = tuple(int(v) for v in grid.cart_dims)
        return grid.cells.index_map, dims + (1,) * (3 - len(dims))
    if grid.layering is not None:
        lay = grid.layering
        n = lay.areal.num_cells
        return lay.column + n * lay.layer, (n, 1, int(lay.num_layers))
    return np.arange(grid.num_cells, dtype=np.int64), (grid.num_cells, 1, 1)
