"""Benchmark: the cells 100 deviated wells of 3 km cross in a 1e6-cell faulted corner-point grid.

Run:  .venv/bin/python bench/wells.py [--dims 200 200 25] [--phys 5000 3000 15] [--wells 100]
                                      [--repeat 3] [--peer-python PY] [--profile]

Grid: ``make_model3(dims, phys)`` (bench/cornerpoint.py's anticline cut by two faults, with
inactive cells), here on a 5 km x 3 km area so that 3 km laterals fit (cells 25 x 15 x 0.6 m),
processed by ``process_grdecl`` (not timed). Wells: 3 km of hole each, all of it near the
reservoir: a heel at a random point of the middle of the area, in the middle of the reservoir,
and a lateral surveyed every 30 m, its inclination swinging between 87 and 93 degrees (400 m
period: it crosses the layers up and down, 3.3 m either way) and its azimuth turning by up to
30 degrees, turned into a path by minimum curvature with points every 10 m along the arcs.
Times ``cell_index(grid, geometry)`` once and ``path_cells`` for every well (CPU and wall
seconds; the median of ``--repeat`` runs), and prints the pieces and cells found.

Then the connections (directional Peaceman factors, ``well_connections``) of every well.

Target (issue 26, not asserted): index + intersections + factors of 100 wells <= 5 s.

If xtgeo (>= 4.27, ``Well.get_cell_intersections``) is importable (here, or by
``--peer-python``), it reads the deck written as GRDECL (not timed) and its intersections of
the same wells (active cells only) are timed, with its default sampling step (1 m) and a fine
one (5 cm). The fine ones are compared with ours: the wells where its runs (cells in order)
are ours, once the runs shorter than its step (which it may step over) are left out of both,
and the MD and depth differences at the runs' entries.
"""

from __future__ import annotations

import argparse
import cProfile
import json
import pstats
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from gridlib import compute_geometry
from gridlib.completions import vertical_well_cells
from gridlib.cornerpoint.generators import make_model3
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.grdecl import write_grdecl
from gridlib.wells.connections import well_connections
from gridlib.wells.intersect import cell_index, path_cells
from gridlib.wells.path import WellPath
from gridlib.wells.survey import minimum_curvature

FINE = 0.05  # xtgeo's fine sampling step (m): it may step over the runs shorter than that

XTGEO = """
import json, sys, time
import numpy as np, pandas as pd
path, wells_npz, out = sys.argv[1], sys.argv[2], sys.argv[3]
try:
    import xtgeo
except ImportError:
    print(json.dumps({}))
    raise SystemExit
grid = xtgeo.grid_from_file(path, fformat="grdecl")
data = np.load(wells_npz)
wells = []
for name in sorted(data.files, key=lambda n: int(n[1:])):
    p = data[name]
    df = pd.DataFrame({"X_UTME": p[:, 0], "Y_UTMN": p[:, 1], "Z_TVDSS": p[:, 2], "MD": p[:, 3]})
    wells.append(xtgeo.Well(0.0, p[0, 0], p[0, 1], name, df, mdlogname="MD"))
times = {}
for step in (1.0, FINE):  # its default sampling step, then a fine one (compared with ours)
    t, c = time.perf_counter(), time.process_time()
    found = [w.get_cell_intersections(grid, sampling_step=step, active_only=True, zerobased=True)
             for w in wells]
    times[step] = (time.perf_counter() - t, time.process_time() - c)
arrays = {}
for i, r in enumerate(found):
    arrays[f"w{i}"] = np.column_stack([r.I, r.J, r.K, r.ENTRY_MD, r.EXIT_MD, r.ENTRY_TVD]).astype(float)
np.savez(out, **arrays)
print(json.dumps({"version": xtgeo.__version__, "times": list(times.values())}))
""".replace("FINE", repr(FINE))


def lateral_wells(
    grid, geo, n: int, phys, length: float = 3000.0, station: float = 30.0, step: float = 10.0, seed: int = 0
) -> list[WellPath]:
    """``n`` laterals of ``length`` (module docstring): surveys with a station every ``station``,
    by minimum curvature with points every ``step`` along the arcs."""
    rng = np.random.default_rng(seed)
    md = np.arange(0.0, length + station / 2, station)
    wells = []
    while len(wells) < n:
        heel = np.array([rng.uniform(0.3, 0.7) * phys[0], rng.uniform(0.3, 0.7) * phys[1], 0.0])
        column = vertical_well_cells(grid, geo, heel[:2])
        if column.size == 0:
            continue
        heel[2] = geo.cell_centroids[column, 2].mean()  # the middle of the reservoir there
        towards = np.degrees(np.arctan2(phys[0] / 2 - heel[0], phys[1] / 2 - heel[1]))  # from north
        azimuth = towards + rng.uniform(-60.0, 60.0) + rng.uniform(-30.0, 30.0) * md / length
        inclination = 90.0 + 3.0 * np.sin(2 * np.pi * md / 400.0 + rng.uniform(0, 2 * np.pi))
        stations = np.column_stack([md, inclination, azimuth % 360.0])
        wells.append(minimum_curvature(heel, stations, name=f"w{len(wells)}", step=step))
    return wells


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    parser.add_argument("--dims", type=int, nargs=3, default=[200, 200, 25])
    parser.add_argument("--phys", type=float, nargs=3, default=[5000.0, 3000.0, 15.0])
    parser.add_argument("--wells", type=int, default=100)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--peer-python", default=sys.executable, help="interpreter with xtgeo")
    parser.add_argument("--profile", action="store_true")
    args = parser.parse_args()

    deck = make_model3(args.dims, args.phys)
    cp = process_grdecl(deck)
    grid = cp.grid
    geo = compute_geometry(grid)
    wells = lateral_wells(grid, geo, args.wells, args.phys)
    print(
        f"make_model3({args.dims}, {args.phys}): {grid.num_cells:,d} active cells, {grid.num_faces:,d} faces "
        f"({int((grid.faces.tag > 0).sum()):,d} on faults); {len(wells)} wells of "
        f"{wells[0].length:.0f} m, {wells[0].xyz.shape[0]} points each"
    )

    def run():
        index = cell_index(grid, geo)
        found = [path_cells(grid, geo, w, index=index) for w in wells]
        return index, found

    walls, cpus, index_walls = [], [], []
    for _ in range(args.repeat):
        t, c = time.perf_counter(), time.process_time()
        index = cell_index(grid, geo)
        index_walls.append(time.perf_counter() - t)
        found = [path_cells(grid, geo, w, index=index) for w in wells]
        walls.append(time.perf_counter() - t)
        cpus.append(time.process_time() - c)
    pieces = sum(f.num for f in found)
    runs = sum(int(f.run[-1]) + 1 for f in found if f.num)
    inside = sum(float(f.length.sum()) for f in found)
    print(
        f"  {pieces:,d} pieces in {runs:,d} runs; {inside / 1000:.1f} km of "
        f"{len(wells) * wells[0].length / 1000:.1f} km of hole inside cells"
    )
    print(
        f"  cell_index + path_cells: median {statistics.median(walls):.2f} s wall (min {min(walls):.2f}), "
        f"{statistics.median(cpus):.2f} s CPU; the index alone {statistics.median(index_walls):.2f} s wall"
    )
    # factors: a lognormal permeability (kv/kh 0.1) and NTG 0.8, Peaceman per direction
    rng = np.random.default_rng(7)
    kh = np.exp(rng.normal(np.log(150.0), 0.8, grid.num_cells))
    perm = np.column_stack([kh, kh, 0.1 * kh])
    ntg = np.full(grid.num_cells, 0.8)
    factor_walls, factor_cpus = [], []
    for _ in range(args.repeat):
        t, c = time.perf_counter(), time.process_time()
        conns = [well_connections(grid, geo, perm, ntg, f, 0.108, 0.0, units="metric") for f in found]
        factor_walls.append(time.perf_counter() - t)
        factor_cpus.append(time.process_time() - c)
    total = statistics.median(walls) + statistics.median(factor_walls)
    print(
        f"  well_connections (factors): median {statistics.median(factor_walls):.2f} s wall, "
        f"{statistics.median(factor_cpus):.2f} s CPU for {sum(w.cell.size for w in conns):,d} connections"
    )
    verdict = "met" if total <= 5.0 else "NOT met"
    print(f"    index + intersections + factors {total:.2f} s; target <= 5 s: {verdict}")
    if args.profile:
        profile = cProfile.Profile()
        profile.runcall(run)
        pstats.Stats(profile).sort_stats("tottime").print_stats(15)
    peer(args, deck, grid, wells, found)


def peer(args, deck, grid, wells, found) -> None:
    """xtgeo's intersections of the same wells, timed in ``--peer-python``."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "model3.grdecl"
        write_grdecl(path, deck)
        np.savez(Path(tmp) / "wells.npz", **{w.name: np.column_stack([w.xyz, w.md]) for w in wells})
        out = Path(tmp) / "out.npz"
        done = subprocess.run(
            [args.peer_python, "-c", XTGEO, str(path), str(Path(tmp) / "wells.npz"), str(out)],
            capture_output=True,
            text=True,
        )
        lines = done.stdout.strip().splitlines()
        result = json.loads(lines[-1]) if done.returncode == 0 and lines else {}
        if not result:
            print("  (xtgeo not importable: no peer timing; see --peer-python)")
            if done.returncode and done.stderr.strip():
                print("  " + done.stderr.strip().splitlines()[-1])
            return
        theirs = np.load(out)
        (wall, cpu), (fine_wall, fine_cpu) = result["times"]
        print(
            f"  xtgeo {result['version']} Well.get_cell_intersections: {wall:.2f} s wall, {cpu:.2f} s CPU "
            f"(sampling step 1 m, its default); {fine_wall:.2f} s wall, {fine_cpu:.2f} s CPU (step {FINE} m)"
        )
        compare(deck, grid, found, [theirs[f"w{i}"] for i in range(len(wells))], FINE)


def compare(deck, grid, found, theirs, step: float) -> None:
    """Wells whose runs (cells in order) are xtgeo's once the runs shorter than its sampling step
    (which it may step over) are left out of both, and the differences of MD and depth at the
    entries of the runs that follow a run of both."""
    nx, ny, _ = deck.cart_dims
    same, short, d_md, d_z = 0, 0, [], []
    for f, t in zip(found, theirs, strict=True):
        start = np.r_[0, np.flatnonzero(np.diff(f.run)) + 1]
        end = np.r_[start[1:] - 1, f.num - 1]
        ours = np.column_stack([grid.cells.index_map[f.cell[start]], f.entry_md[start], f.entry[start, 2]])
        glob = t[:, 0] + nx * (t[:, 1] + ny * t[:, 2])
        mine = _long_runs(ours, f.exit_md[end] - f.entry_md[start], step)
        other = _long_runs(np.column_stack([glob, t[:, 3], t[:, 5]]), t[:, 4] - t[:, 3], step)
        short += int(np.sum(f.exit_md[end] - f.entry_md[start] < step))
        if np.array_equal(mine[:, 0], other[:, 0]):
            same += 1
            follows = mine[:, 3] == 1
            d_md.append(np.abs(mine[follows, 1] - other[follows, 1]))
            d_z.append(np.abs(mine[follows, 2] - other[follows, 2]))
    d_md, d_z = np.concatenate(d_md), np.concatenate(d_z)
    nz = deck.cart_dims[2]
    q = deck.zcorn_array().reshape(2 * nz, ny, 2, nx, 2)  # the corners of every top and base
    half_twist = 0.5 * np.abs(q[:, :, 0, :, 0] + q[:, :, 1, :, 1] - q[:, :, 0, :, 1] - q[:, :, 1, :, 0]).max()
    print(
        f"    the same runs as ours in {same} of {len(found)} wells, once the runs shorter than its "
        f"{step:g} m step are left out of both (of ours, {short})"
    )
    print(
        f"    there, at the entry of the {d_md.size:,d} runs after a run of both, MD differences median "
        f"{np.median(d_md):.2g} m, max {d_md.max():.3g} m; depth differences max {d_z.max():.3g} m (the"
        f" largest half twist of a top or base, which xtgeo fills otherwise, is {half_twist:.3g} m; a"
        " grazing crossing turns a depth difference into a larger MD difference)"
    )


def _long_runs(runs: np.ndarray, length: np.ndarray, step: float) -> np.ndarray:
    """The runs (rows: cell, entry MD, entry depth) at least ``step`` long, those of one cell in a
    row (a short run left out between them) joined, with a fourth column: 1 where the run before
    it was kept (its entry is then comparable)."""
    keep = length >= step
    follows = np.r_[True, keep[:-1]][keep]
    runs = runs[keep]
    new = np.r_[True, runs[1:, 0] != runs[:-1, 0]]
    return np.column_stack([runs[new], follows[new]])


if __name__ == "__main__":
    main()
