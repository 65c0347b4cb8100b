"""Benchmark: a 1e5-cell PEBI case as an OPM Flow deck in connection form, and Flow on it.

Run:  .venv/bin/python bench/flow_deck.py [--sites 10000] [--layers 10] [--repeat 3]
                                          [--days 30 60 90] [--large-sites 0]

The grid is bench/pebi.py's (``--sites`` hexagonal sites, 10 faults crossing and ending
inside, 5 wells with radial rings), extruded in ``--layers`` layers between a domed top
and a base, every fault thrown (about 1.04e5 cells at 1e4 sites and 10 layers), with
lognormal permeability, porosity and NTG; its transmissibilities as the workflow's
transmissibility stage computes them (PEBI sites at the centroid depth, distance to the
face plane; not timed). Two of the wells, a water injector (rate) and a producer (BHP),
completed in every layer with ``well_index``'s PEBI factors (well radius 1 cm: the rings'
centre cells are only about 0.2 m across).

Prints: the time to write the deck (``write_flow_deck``: median of ``--repeat``, min-max)
and the text size of each file; the wall time of Flow's dry run (reading the deck,
building its grid, the NNCs, the pore volumes: its initialisation), and whether it reads
it within a minute; then a simulation over ``--days`` report steps: the wall time, and
Flow's own "Total time" (time stepping only). ``--large-sites N`` also times writing the
deck of the N-site grid (1e5 sites: about 1e6 cells and 4e6 connections; no Flow run).
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from gridlib import compute_geometry
from gridlib.completions import vertical_well_cells
from gridlib.io.flow import ConnectionGrid, FlowWell, Simulation, write_flow_deck
from gridlib.pillars.extrude import extrude
from gridlib.stages.flow_deck import _depths, _spacing
from gridlib.stages.simulate import flow_command
from gridlib.transmissibility import transmissibility, well_index
from gridlib.voronoi import pebi_grid

sys.path.insert(0, str(Path(__file__).parent))
from pebi import case as pebi_case
from pebi import layered_horizons


def model(sites: int, layers: int, days: list[float]):
    """The connection-form grid and the simulation of the benchmark (module docstring)."""
    domain, h, faults, wells = pebi_case(sites)
    pg = pebi_grid(domain, h, faults, wells)
    horizons, throws = layered_horizons(pg, faults)
    r = extrude(pg.grid, horizons, layers=layers, faults=throws, centres=pg.sites)
    grid = r.grid
    geo = compute_geometry(grid)
    rng = np.random.default_rng(1)
    poro = np.clip(rng.normal(0.2, 0.03, grid.num_cells), 0.05, 0.35)
    permx = 10.0 ** rng.normal(2.0, 0.5, grid.num_cells)
    perm = np.column_stack([permx, permx, permx / 10.0])
    ntg = 0.6 + 0.4 * rng.random(grid.num_cells)
    centres = np.column_stack([pg.sites[grid.layering.column], geo.cell_centroids[:, 2]])
    conn = transmissibility(grid, geo, perm, ntg, centres=centres, distance="normal")
    depth, thickness = _depths(grid, geo, None)
    lay = grid.layering
    ncol = lay.areal.num_cells
    layout = ConnectionGrid(
        dims=(ncol, 1, int(lay.num_layers)),
        index=lay.column + ncol * lay.layer,
        porv=geo.cell_volumes * poro * ntg,
        depth=depth,
        thickness=thickness,
        poro=poro,
        permeability=perm,
        pairs=conn.cells,
        trans=conn.trans,
        spacing=_spacing(geo.cell_volumes, thickness),
    )
    flow_wells = []
    for well, kind in zip(wells[:2], ("injector", "producer"), strict=True):
        cells = vertical_well_cells(grid, geo, well.point)
        factors = well_index(grid, geo, perm, cells, 0.01, ntg=ntg)
        control = {"rate": 2000.0, "bhp": 500.0} if kind == "injector" else {"bhp": 150.0}
        flow_wells.append(FlowWell(well.name, kind, layout.index[cells], 0.01, 0.0, factors, **control))
    top = float(np.floor((depth - thickness / 2).min()))
    sim = Simulation("oil-water", top, 210.0, top + 60.0, tuple(flow_wells), tuple(days))
    return grid, conn, layout, sim


def timed(fn, repeat: int):
    times, result = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t)
    return result, times


def summary(times: list[float]) -> str:
    return f"median {statistics.median(times):.2f} s (min {min(times):.2f}, max {max(times):.2f})"


def run_flow(deck: Path, out: Path, dry: bool, timeout: float) -> tuple[float, str, bool]:
    """Flow's wall time on ``deck`` (dry run or simulation), its stdout, whether it finished."""
    cmd = [flow_command(), "--threads-per-process=1", f"--output-dir={out}", deck.name]
    if dry:
        cmd.insert(1, "--enable-dry-run=true")
    t = time.perf_counter()
    try:
        done = subprocess.run(cmd, cwd=deck.parent, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return time.perf_counter() - t, "", False
    return time.perf_counter() - t, done.stdout, done.returncode == 0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    parser.add_argument("--sites", type=int, default=10_000)
    parser.add_argument("--layers", type=int, default=10)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--days", type=float, nargs="+", default=[30.0, 60.0, 90.0])
    parser.add_argument("--large-sites", type=int, default=0)
    args = parser.parse_args()
    grid, conn, layout, sim = model(args.sites, args.layers, args.days)
    print(
        f"PEBI case (bench/pebi.py, {args.sites:,d} sites, {args.layers} layers, every fault thrown): "
        f"{grid.num_cells:,d} cells, {conn.num:,d} connections, box {layout.dims}"
    )
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        deck, times = timed(lambda: write_flow_deck(folder / "deck", "BENCH", layout, sim), args.repeat)
        sizes = ", ".join(f"{p.name} {p.stat().st_size / 2**20:.1f} MiB" for p in deck.files)
        print(f"  write_flow_deck (connection form)  {summary(times)}")
        print(f"  text: {sizes}; {deck.vanished.size} connections vanish in Flow (below 1e-6)")
        wall, out, ok = run_flow(deck.path, folder / "dry", dry=True, timeout=600.0)
        verdict = "within a minute" if ok and wall <= 60.0 else ("NOT within a minute" if ok else "FAILED")
        print(f"  Flow dry run (initialisation): {wall:.1f} s wall: reads it {verdict}")
        wall, out, ok = run_flow(deck.path, folder / "run", dry=False, timeout=1800.0)
        stepping = [
            line.split(":", 1)[1].strip() for line in out.splitlines() if line.startswith("Total time")
        ]
        steps = [line.strip() for line in out.splitlines() if line.startswith("Overall Newton")]
        days = ", ".join(f"{d:g}" for d in args.days)
        print(
            f"  Flow simulation ({days} days, 2 wells): {wall:.1f} s wall"
            f"{', time stepping ' + stepping[-1] + ' s' if stepping else ''}"
            f"{'; ' + steps[-1] if steps else ''}{'' if ok else ' FAILED'}"
        )
    if args.large_sites:
        grid, conn, layout, sim = model(args.large_sites, args.layers, args.days)
        with tempfile.TemporaryDirectory() as tmp:
            deck, times = timed(lambda: write_flow_deck(Path(tmp), "LARGE", layout, sim), args.repeat)
            size = sum(p.stat().st_size for p in deck.files) / 2**20
            print(
                f"large: {grid.num_cells:,d} cells, {conn.num:,d} connections: write_flow_deck "
                f"{summary(times)}, {size:.0f} MiB of text"
            )


if __name__ == "__main__":
    main()
