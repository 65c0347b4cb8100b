"""Stage ``exchange``: the case in the files other geomodelling tools open.

* ``{case}.roff`` (cornerpoint and deck cases: the grids with logical (i, j, k) corner-point
  geometry): the grid of ``grid.grdecl`` (COORD, ZCORN, ACTNUM; in map coordinates where the
  deck has MAPAXES, as RMS exports ROFF: :func:`~gridlib.io.roff.map_coordinates`) as a ROFF grid
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
  undefined nodes as IRAP's 1e30), and where the case has faults ``faults.pol`` (their
  traces on the top horizon) and ``fault_sticks.pol`` (their sticks), RMS/xtgeo polygons
  (:func:`fault_polylines`). The folder is written whole or not at all (a temporary folder
  beside it, then renamed), so that Snakemake sees it as one output.

ROFF and IRAP carry no unit: lengths are the case's (metres, or a FIELD deck's feet).
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np

from ..case.faults import fault_traces
from ..config import Case
from ..connectivity import ragged_arange
from ..cornerpoint.deck import Deck
from ..horizons.surface import Surface
from ..io.atomic import atomic_directory, write_keeping_suffix
from ..io.datasets import open_artifact, read_variable
from ..io.grdecl import read_grdecl
from ..io.horizon_files import read_horizons, read_surface_netcdf
from ..io.irap_binary import write_irap_binary
from ..io.polygons import write_polygons
from ..io.rock_file import read_rock
from ..io.roff import ROFF_SUFFIXES, layer_gaps, map_coordinates, read_roff_subgrids, write_roff_grid
from ..pillars.horizon_maps import depth_function
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
    if case.grid_type == "deck" and Path(spec["file"]).suffix.lower() in ROFF_SUFFIXES:
        from ..case.deck import deck_path

        subgrids = read_roff_subgrids(deck_path(case))
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
        write_case_roff(case, Path(roff), grid, grdecl, petrophysics)
    if exchange is not None:
        if horizons is None:
            raise ValueError(f"{case.path}: exchange/ is written from horizons.nc")
        write_exchange_folder(case, Path(exchange), horizons)


def write_case_roff(
    case: Case,
    roff: Path,
    grid: str | os.PathLike,
    grdecl: str | os.PathLike,
    petrophysics: str | os.PathLike | None,
) -> None:
    """``roff``: the grid of ``grdecl`` (in map coordinates where it has MAPAXES), the rock of
    ``petrophysics`` on the cells of ``grid`` and the case's zones, atomically."""
    deck = read_grdecl(grdecl)
    if deck.mapaxes is not None:
        log.info("note: %s is in map coordinates: the deck's MAPAXES applied", roff)
        deck = map_coordinates(deck)
    with open_artifact(grid) as ds:  # the deck's cell of each grid cell, not the whole grid
        index_map = read_variable(ds, "cell_index_map", "iu", 1).astype(np.int64)
    zones = zone_layers(case, deck.cart_dims[2])
    rock = read_rock(petrophysics) if petrophysics is not None else None
    params = roff_parameters(deck, index_map, rock, zones)
    binary = case.data["outputs"]["roff_format"] == "binary"
    write_keeping_suffix(
        roff, lambda tmp: write_roff_grid(tmp, deck, subgrids=zones, binary=binary, parameters=params)
    )
    gaps = layer_gaps(deck)
    if gaps:
        log.info(
            "note: %s has %d cell corners where a layer's top lies below the bottom of the layer "
            "above (a vertical gap): ROFF holds them exactly (split nodes), but xtgeo 4 refuses "
            "such a grid (docs/roff.md, Limits)",
            roff,
            gaps,
        )
    kind = "binary" if binary else "ASCII"
    log.info("wrote %s (%s; subgrids %s; parameters %s)", roff, kind, zones, ", ".join(params) or "none")


def write_exchange_folder(case: Case, exchange: Path, horizons: str | os.PathLike) -> None:
    """``exchange/``: the horizons of ``horizons`` as IRAP binary surfaces and, where the case
    has faults, ``faults.pol`` and ``fault_sticks.pol``; written whole or not at all."""
    surfaces = horizon_surfaces(horizons)
    with atomic_directory(exchange) as folder:
        for surface in surfaces:
            write_irap_binary(folder / f"{file_stem(surface.name)}.gri", surface)
        if case.data.get("faults"):
            traces, sticks = fault_polylines(case, surfaces[0], surfaces[-1])
            write_polygons(folder / "faults.pol", traces)
            write_polygons(folder / "fault_sticks.pol", sticks)
    log.info("wrote %s: %d horizons (IRAP binary)%s", exchange, len(surfaces), _faults_note(case))


def _faults_note(case: Case) -> str:
    faults = case.data.get("faults") or []
    return f", {len(faults)} faults (faults.pol, fault_sticks.pol)" if faults else ""


def horizon_surfaces(path: str | os.PathLike) -> list[Surface]:
    """Every horizon of ``horizons.nc`` (from the top), named after it."""
    names = [str(v) for v in read_horizons(path)["horizon"].values]
    return [read_surface_netcdf(path, horizon=k, name=name) for k, name in enumerate(names)]


def file_stem(name: str) -> str:
    """A horizon's name as a file name: characters other than letters, digits, ``-``, ``_``
    and ``.`` as ``_``."""
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name) or "horizon"


def fault_polylines(case: Case, top: Surface, base: Surface) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """The case's faults as polylines of (x, y, depth), in the case's order of faults:

    * traces: each fault's trace draped on the top horizon: its segments divided at the top's
      node spacing, each point at the top's (bilinear) depth; where the top is undefined (beyond
      its lattice, where traces of faults crossing the grid end) the trace is cut, each defined
      piece its own polyline;
    * sticks: an inclined fault's (``dip`` or ``sticks``) the sticks of its surface, each from
      its shallowest to its deepest level; a vertical fault's a vertical stick at each vertex of
      its draped trace and at the ends of its pieces, from the top's depth to the base's (where
      both are defined).

    RMS imports the first as polygons and the second as fault sticks (a stick per polyline)."""
    top_fn, base_fn = depth_function(top.to_horizon()), depth_function(base.to_horizon(), 1)
    spacing = min(top.xinc, top.yinc)
    traces: list[np.ndarray] = []
    sticks: list[np.ndarray] = []
    for trace in fault_traces(case, top=top_fn):
        pieces, corners = _draped(np.asarray(trace.points, dtype=np.float64), top_fn, spacing)
        traces += pieces
        if trace.surface is not None:
            levels, pts = trace.surface.levels, trace.surface.points  # (m,), (m, n, 2)
            sticks += [np.column_stack([pts[:, s], levels]) for s in range(pts.shape[1])]
            continue
        if not corners.size:
            continue
        z_base = base_fn(corners[:, 0], corners[:, 1])
        both = np.isfinite(z_base)
        ends = np.stack([corners[both], np.column_stack([corners[both, :2], z_base[both]])], axis=1)
        sticks += list(ends)  # (2, 3) each: top, base
    return traces, sticks


def _draped(xy: np.ndarray, depth, spacing: float) -> tuple[list[np.ndarray], np.ndarray]:
    """A polyline (n, 2) divided at ``spacing`` and draped on ``depth(x, y)``: its defined
    pieces (each (m, 3)), and the points among them that are its vertices or a piece's ends."""
    seg = np.diff(xy, axis=0)
    parts = np.maximum(np.ceil(np.hypot(seg[:, 0], seg[:, 1]) / spacing), 1).astype(np.int64)
    start = np.repeat(np.arange(seg.shape[0]), parts)
    t = (ragged_arange(np.zeros_like(parts), parts) / np.repeat(parts, parts))[:, None]
    pts = np.vstack([xy[start] + t * seg[start], xy[-1:]])
    vertex = np.append(t[:, 0] == 0.0, True)
    z = depth(pts[:, 0], pts[:, 1])
    defined = np.isfinite(z)
    if not defined.any():
        return [], np.zeros((0, 3))
    # runs of defined points: where `defined` switches on, and off
    edges = np.diff(np.concatenate([[0], defined.astype(np.int8), [0]]))
    on, off = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    points = np.column_stack([pts, z])
    pieces = [points[a:b] for a, b in zip(on, off, strict=True)]
    corner = vertex.copy()
    corner[on], corner[off - 1] = True, True
    return pieces, points[corner & defined]
