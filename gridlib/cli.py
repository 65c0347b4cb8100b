"""The ``gridlib`` command: build a case without Snakemake, describe or check a grid file.

    gridlib build CASE.yaml OUTDIR   # every stage's artifacts (grid.nc, ..., CASE.vtu) in OUTDIR
    gridlib info FILE                # a deck (GRDECL/DATA), an EGRID or a gridlib netCDF file
    gridlib check FILE               # process (decks), compute the geometry, check every invariant
    gridlib flow-deck RESULTS_DIR OUT_DIR [--form native|connections] [--case CASE.yaml]
                                     # a built case's OPM Flow deck (<NAME>.DATA + includes)

Errors in the input end with one message naming the file (and key, keyword or
line) and exit status 2; a grid that fails ``check`` exits with status 1. ``info`` and ``check``
say the file's unit system (``units: FIELD``: a deck's units keyword, a netCDF file's
``unit_system``) and give every figure its unit in it (``total volume: 1.2e+07 ft3``).
"""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from . import io
from .checks import check_deck_grid, check_grid
from .cornerpoint import process_grdecl
from .cornerpoint.pore_volume import zero_pore_volume
from .errors import GridError, InputError
from .geometry import compute_geometry
from .io.dask_on_demand import defer_dask_import
from .stages.common import notes_on_console
from .stages.flow_deck import flow_deck_from_results
from .stages.pipeline import run_case
from .units import UnitSystem, unit_system

GRID_KINDS = (
    "deck",
    "grid",
)  # what info and check read: a deck (GRDECL, DATA, EGRID) or a gridlib netCDF file


def _describe_grid(grid, out: list[str]) -> None:
    sizes = f"{grid.num_cells:,d} cells, {grid.num_faces:,d} faces, {grid.num_nodes:,d} nodes"
    out.append(f"grid: {grid.griddim}-D, {sizes}")
    if grid.cart_dims is not None:
        out.append(f"logical dimensions: {' x '.join(str(d) for d in grid.cart_dims)}")
    n_fault = int((grid.faces.tag > 0).sum())
    if n_fault:
        out.append(f"fault faces: {n_fault:,d}")
    out.append(f"history: {', '.join(grid.history)}")


def _deck_units(units: str | None) -> tuple[UnitSystem, str]:
    """A deck's unit system and its ``units:`` line (ECLIPSE's default where it gives none)."""
    if units:
        return unit_system(units), f"units: {units}"
    return unit_system(None), "units: not given (ECLIPSE default METRIC)"


def _file_units(attrs: dict[str, object]) -> tuple[UnitSystem, str]:
    """A gridlib netCDF file's unit system and its ``units:`` line."""
    if "unit_system" in attrs:
        system = unit_system(str(attrs["unit_system"]))
        return system, f"units: {system.name}"
    return unit_system(None), "units: not recorded (a file of an older gridlib: METRIC)"


def _depth_range(z: np.ndarray, system: UnitSystem) -> str | None:
    z = z[np.isfinite(z)]
    unit = system.unit("length")
    return f"depth range: {z.min():.6g} to {z.max():.6g} {unit}" if z.size else None


def info(path: Path) -> str:
    """A human-readable summary of a deck, EGRID or netCDF file."""
    out = [f"{path}"]
    kind = io.kind_of(path, GRID_KINDS)
    if kind == "deck":
        deck = io.read(path, kind="deck")
        nx, ny, nz = deck.cart_dims
        active = int(deck.active.sum())
        out.append(f"corner-point deck: {nx} x {ny} x {nz} = {deck.num_cells:,d} cells, {active:,d} active")
        zero_pv = int(zero_pore_volume(deck).sum())
        if zero_pv:
            out.append(f"of them with zero pore volume (inactive, as in OPM Flow): {zero_pv:,d}")
        system, units = _deck_units(deck.units)
        out.append(units)
        if deck.cell_data:
            out.append(f"cell keywords: {', '.join(sorted(deck.cell_data))}")
        if deck.faults:
            names = sorted({f.name for f in deck.faults})
            out.append(f"faults: {len(names)} ({len(deck.faults)} FAULTS lines): {', '.join(names[:20])}")
        if deck.nnc is not None:
            out.append(f"NNCs in the file: {deck.nnc.shape[0]:,d}")
        depths = _depth_range(deck.zcorn, system)
        out += [depths] if depths else []
        out += [f"note: {n}" for n in deck.notes]
    else:
        data = io.read(path, kind="grid")
        _describe_grid(data.grid, out)
        system, units = _file_units(data.attrs)
        out.append(units)
        depths = _depth_range(data.grid.nodes.coords[:, 2], system) if data.grid.dim == 3 else None
        out += [depths] if depths else []
        for key in ("case_name", "gridlib_version", "case_sha256", "seed"):
            if key in data.attrs:
                out.append(f"{key}: {data.attrs[key]}")
        if data.cell_data:
            out.append(f"cell data: {', '.join(sorted(data.cell_data))}")
    return "\n".join(out)


def check(path: Path) -> str:
    """Process (for decks), compute the geometry and check every invariant; raises GridError.
    A deck's degenerate cells (:func:`~gridlib.checks.check_deck_grid`) are listed as notes."""

    out = [f"{path}"]
    if io.kind_of(path, GRID_KINDS) == "deck":
        deck = io.read(path, kind="deck")
        system, units = _deck_units(deck.units)
        result = process_grdecl(deck)
        grid = result.grid
        _describe_grid(grid, out)
        out.append(units)
        out.append(f"non-neighbour connections: {result.nnc.num:,d}")
        bulk = f"{result.bulk_volumes.sum():.9g} {system.unit('volume')}"
        out.append(f"bulk volume (ECLIPSE convention): {bulk}")
        out += [f"note: {n}" for n in result.notes]
    else:
        data = io.read(path, kind="grid")
        grid = data.grid
        _describe_grid(grid, out)
        system, units = _file_units(data.attrs)
        out.append(units)
    geo = compute_geometry(grid)
    if io.kind_of(path, GRID_KINDS) == "deck":  # a deck's degenerate cells are kept and named
        out += [f"note: {n}" for n in check_deck_grid(grid, geo).notes(grid)]
    else:
        check_grid(grid, geo)
    measure = "total volume" if grid.griddim == 3 else "total area"
    out.append(f"{measure}: {geo.cell_volumes.sum():.9g} {system.unit('cell_measure', grid.griddim)}")
    out.append("OK: every invariant holds")
    return "\n".join(out)


def build(case_file: Path, outdir: Path) -> str:
    """Run every stage the case needs (horizons, grid, geometry, petrophysics, coarsen,
    export) into ``outdir``; returns the list of files written. The stages' notes are printed
    on stderr as they come, once each; a failing stage leaves ``outdir`` as it was."""
    logger = logging.getLogger("gridlib")
    console = notes_on_console(case_file.stem)
    level = logger.level
    logger.addHandler(console)
    logger.setLevel(logging.INFO)
    try:
        return "\n".join(str(p) for p in run_case(case_file, outdir))
    finally:
        logger.removeHandler(console)
        logger.setLevel(level)


def flow_deck(results_dir: Path, out_dir: Path, form: str | None, case: Path | None = None) -> str:
    """Write the OPM Flow deck of the case built in ``results_dir`` into ``out_dir``."""
    deck = flow_deck_from_results(results_dir, out_dir, form, case)
    lines = [str(p) for p in deck.files] + [f"note: {n}" for n in deck.notes]
    form = "connection" if deck.form == "connections" else deck.form
    return "\n".join([f"{form} form:", *lines])


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="gridlib", description=__doc__, formatter_class=argparse.RawTextHelpFormatter
    )
    sub = parser.add_subparsers(dest="command", required=True)
    b = sub.add_parser("build", help="build a case's artifacts without Snakemake")
    b.add_argument("case", type=Path)
    b.add_argument("outdir", type=Path)
    i = sub.add_parser("info", help="summarise a deck, EGRID or netCDF grid file")
    i.add_argument("file", type=Path)
    c = sub.add_parser("check", help="process and check a deck or netCDF grid file")
    c.add_argument("file", type=Path)
    f = sub.add_parser("flow-deck", help="write a built case's OPM Flow deck")
    f.add_argument(
        "results_dir", type=Path, help="the case's results folder (grid.nc, transmissibility.nc, ...)"
    )
    f.add_argument("out_dir", type=Path, help="where <NAME>.DATA and its includes go")
    f.add_argument(
        "--form",
        choices=("native", "connections"),
        help="native (corner-point and deck cases; their default) or connections (any case)",
    )
    f.add_argument("--case", type=Path, help="the case file (default: the one recorded in the artifacts)")
    args = parser.parse_args(argv)
    defer_dask_import()  # numpy-backed datasets only: no need to import dask
    try:
        if args.command == "build":
            text = build(args.case, args.outdir)
        elif args.command == "info":
            text = info(args.file)
        elif args.command == "flow-deck":
            text = flow_deck(args.results_dir, args.out_dir, args.form, args.case)
        else:
            text = check(args.file)
    except InputError as exc:
        print(f"gridlib: {exc}", file=sys.stderr)
        return 2
    except GridError as exc:
        print(f"gridlib: {args.command}: {exc}", file=sys.stderr)
        return 1
    except OSError as exc:
        print(f"gridlib: {exc}", file=sys.stderr)
        return 2
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
