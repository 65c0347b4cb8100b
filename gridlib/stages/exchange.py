"""Stage ``exchange``: the case in the files other geomodelling tools open.

* ``{case}.roff`` (cornerpoint and deck cases: the grids with logical (i, j, k) corner-point
  geometry): the grid of ``grid.grdecl`` (COORD, ZCORN, ACTNUM) as a ROFF grid
  (:mod:`gridlib.io.roff`; binary, or ASCII with ``outputs.roff_format: ascii``) with its
  parameters in the same file, as RMS exports a grid with its parameters: ``PORO``, ``PERMX``,
  ``PERMY``, ``PERMZ``, ``NTG`` (float32; -999.0 in inactive cells, RMS's undefined value) and,
  where the grid has zones, ``ZONE`` (int32, 1 = the top zone, every cell) and the subgrids:
  one per zone, the zones' layer counts from the top. A cornerpoint case's zones are its
  intervals between consecutive horizons (``grid.layers``); a deck case's are the subgrids of
  its ROFF grid file, if it is one (a GRDECL or EGRID deck has none). Pebi, layered, cartesian
  and tensor grids have no ROFF form (ROFF grids are logical corner-point grids): they get no
  ``{case}.roff`` (their ``{case}.vtu`` and ``{case}.nc`` hold them).
* ``exchange/`` (cases with horizons): ``<horizon>.gri``, each horizon of ``horizons.nc`` as
  an IRAP binary surface (depth, positive down, as RMS and xtgeo store depth surfaces;
  undefined nodes as IRAP's 1e30), and ``faults.pol`` where the case has faults
  (:func:`fault_polylines`). The folder is written whole or not at all (a temporary folder
  beside it, then renamed), so that Snakemake sees it as one output.

ROFF and IRAP carry no unit: lengths are the case's (metres, or a FIELD deck's feet).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..config import Case
from ..cornerpoint.deck import Deck
from ..io.grdecl import read_grdecl
from ..io.netcdf import read_netcdf
from ..io.rock_file import read_rock
from ..io.roff import read_roff_grid, write_roff_grid
from .common import log

UNDEFINED = -999.0  # RMS's (and xtgeo's ROFF) undefined value
ROFF_NAMES = {"poro": "PORO", "permx": "PERMX", "permy": "PERMY", "permz": "PERMZ", "ntg": "NTG"}


def zone_layers(case: Case, nz: int) -> list[int] | None:
    """The layer count of each zone from the top (None where the grid has no zones): a
    cornerpoint case's ``grid.layers`` per interval between horizons; a deck case's ROFF
    grid's subgrids."""
    spec = case.data["grid"]
    if case.grid_type == "cornerpoint":
        layers = spec["layers"]
        counts = list(layers) if isinstance(layers, list) else [int(layers)] * (nz // int(layers))
        return counts if sum(counts) == nz else None
    if case.grid_type == "deck" and Path(spec["file"]).suffix.lower() in (".roff", ".roffasc"):
        from ..case.deck import deck_path

        subgrids = read_roff_grid(deck_path(case)).subgrids
        return None if subgrids is None else subgrids.tolist()
    return None


def roff_parameters(
    deck: Deck, index_map: np.ndarray, rock: dict[str, np.ndarray] | None, zones: list[int] | None
) -> dict[str, np.ndarray]:
    """The ROFF parameters of the grid: the rock of its active cells (``index_map``: the
    deck's cell of each), UNDEFINED elsewhere, and ZONE (1-based, from the top) per layer."""
    nx, ny, nz = deck.cart_dims
    out: dict[str, np.ndarray] = {}
    for name, values in (rock or {}).items():
        full = np.full(nx * ny * nz, UNDEFINED)
        full[index_map] = values
        out[ROFF_NAMES.get(name, name.upper())] = full
    if zones is not None:
        zone_of_layer = np.repeat(np.arange(1, len(zones) + 1, dtype=np.int32), zones)
        out["ZONE"] = np.repeat(zone_of_layer, nx * ny)
    return out


def stage_exchange(
    case: Case,
    *,
    grid: str | os.PathLike,
    grdecl: str | os.PathLike | None = None,
    petrophysics: str | os.PathLike | None = None,
    horizons: str | os.PathLike | None = None,
    roff: str | os.PathLike | None = None,
    exchange: str | os.PathLike | None = None,
) -> None:
    """Write ``roff`` ({case}.roff: the grid of ``grdecl`` with the rock of ``petrophysics``
    and the zones) and ``exchange`` (the folder of IRAP binary horizons from ``horizons`` and
    the faults' polygons), those the case has."""
    if roff is not None:
        if grdecl is None:
            raise ValueError(f"{case.path}: {{case}}.roff is written from grid.grdecl")
        deck = read_grdecl(grdecl)
        index_map = read_netcdf(grid).grid.cells.index_map
        zones = zone_layers(case, deck.cart_dims[2])
        rock = read_rock(petrophysics) if petrophysics is not None else None
        params = roff_parameters(deck, index_map, rock, zones)
        binary = case.data["outputs"]["roff_format"] == "binary"
        _write_atomic(Path(roff), deck, zones, params, binary)
        log.info(
            "wrote %s (%s; subgrids %s; parameters %s)",
            roff,
            "binary" if binary else "ASCII",
            zones,
            ", ".join(params) or "none",
        )
    if exchange is not None:
        from .exchange_files import write_exchange_folder

        write_exchange_folder(case, Path(exchange), horizons)


def _write_atomic(path: Path, deck: Deck, zones, params, binary: bool) -> None:
    from ..io.atomic import write_keeping_suffix

    write_keeping_suffix(
        path, lambda tmp: write_roff_grid(tmp, deck, subgrids=zones, binary=binary, parameters=params)
    )
