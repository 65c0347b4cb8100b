"""Benchmark: transmissibilities of a 1e6-cell faulted deck and of a 1e6-cell layered PEBI grid.

Run:  .venv/bin/python bench/transmissibility.py [--dims 200 200 25] [--repeat 5]
                                                 [--sites 100000] [--no-pebi] [--profile]

Deck: ``make_model3(dims)`` (bench/cornerpoint.py's anticline cut by two faults, with
inactive cells) with lognormal PERMX = PERMY, PERMZ = PERMX / 10, NTG, MULTX 0.5 on a box of
columns and the first fault's faces listed under FAULTS with MULTFLT 0.1, written as a
GRDECL file, read back and processed (not timed); xtgeo (if importable: the ``test``
extra) reads the same file (grid, PERMX/Y/Z, NTG: not timed).

Then, in this one interpreter, alternating, ``--repeat`` times each:
``deck_transmissibility(deck, cp)`` (ours first, so its first call is the first in the
process: what a user who calls it once waits) and xtgeo's
``Grid.get_cell_transmissibilities`` (4.27; ``get_transmissibilities`` before). Printed:
each one's first call and median (min-max), and the ratios xtgeo / ours of both (wall
time; CPU time too, summed over our threads, the fairer figure on a busy machine); then
the peak extra memory of one more of ours (numpy allocations traced by tracemalloc).
``--profile`` prints cProfile's heaviest functions of one run. xtgeo applies no MULT* or
MULTFLT, so its values are compared with ours on the neighbour connections the
multipliers do not touch.

PEBI: bench/pebi.py's grid (``--sites`` sites, 10 faults, 5 wells) extruded in 10 layers
with every fault thrown (about 1e6 cells), its geometry, then
``transmissibility(grid, geometry, K, ntg, centres=sites at the centroid depth,
distance="normal")`` (as the workflow's transmissibility stage calls it) timed
the same way (grid and geometry not timed).

Targets (not asserted): deck_transmissibility <= 0.5 s and >= 3x faster than xtgeo, median
and first call (issue 30); PEBI <= 1 s; peak extra memory <= 1 GiB.

Where deck_transmissibility's time goes (issue 30; ``--profile`` and CPU times of each step
with GRIDLIB_NUM_THREADS=1, side by side with main 6270751 on the 2-core VM):

* 6270751, a warm call about 0.5 s CPU: the six halves of every cell 0.12-0.15 s; the scan
  of the 2.5e6 faces plus three cell-sized lookup tables for the faces of matching pairs
  0.10 s; sort and gathers of the result (``assemble``) 0.08-0.10 s; ZCORN matching 0.05 s;
  joining the parts and the serial passes over them (global indices, side multipliers,
  kinds, ``column_stack``) 0.07 s; the rock's (nc, 3) copy and checks 0.03 s; depth sign
  0.02 s.
* The first call imports nothing of weight (``concurrent.futures`` on first use); it adds
  fresh memory. A page a process touches for the first time is a page fault, and numpy asks
  for transparent huge pages on large arrays (madvise; THP defrag "madvise" here), so a
  fault may first compact memory: allocating and touching 118 MiB in a fresh interpreter
  took 30-250 ms (sys 20-220 ms), the second time 18 ms. A new thread's heap is fresh memory
  too. On 6270751 this was 0.1-0.5 s of sys time, varying with the state of the host.
* Removed since: the halves leave out the terms of A . d that vanish in every column (two of
  three per face on a rectilinear grid; the same bits); the face scan reads the cells through
  an index map padded for -1, in blocks of 65,536 faces; the faces of matching pairs come
  from the engine's ascending face order, and those pairs are kept as lower cell, face and
  T only; multipliers, kinds and ordered pairs are written part by part in blocks on the
  threads (no joined copies, no per-tag scans on neighbour parts); no (nc, 3) permeability
  copy, the rock checked by two reductions per keyword;
  ``assemble`` drops its keys before gathering the result in blocks on the threads. A warm
  call is about 0.35-0.4 s of user CPU, peak traced memory 300 -> 225 MiB.
* The system time then still followed the host: in this bench's interpreter (after the
  deck's reading and xtgeo's), 0.74-0.80 s on the first call and 0.05-0.4 s on the next,
  for the same 0.40 s of user time. Arrays of 32 MiB and more are fresh pages on every call
  (glibc maps them anew: the halves are now six arrays of 8 MB), smaller ones on the first.
  ``deck_transmissibility`` now runs with numpy's huge-page advice off
  (:mod:`gridlib.pages`): 0.18-0.23 s on the first call, 0.05-0.13 s on the next.
* The floor: the result is 2.4e6 connections x 49 bytes = 118 MB written into fresh pages
  (the first touch above), after reading ZCORN (64 MB), the faces' cells (40 MB) and the
  rock (32 MB); at this VM's ~9 GB/s, 30-40 ms of memory traffic. What is left is numpy
  passes (each bit for bit as before: no reordered arithmetic), so on a loaded machine,
  where our threads find no free core, the wall time follows the CPU time.
"""

from __future__ import annotations

import argparse
import cProfile
import pstats
import statistics
import sys
import tempfile
import time
import tracemalloc
from dataclasses import replace
from pathlib import Path

import numpy as np

from gridlib import compute_geometry
from gridlib.cornerpoint.deck import FaultSegment
from gridlib.cornerpoint.generators import make_model3
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.grdecl import read_grdecl, write_grdecl
from gridlib.pillars.extrude import extrude
from gridlib.transmissibility import NEIGHBOR, deck_transmissibility, transmissibility
from gridlib.voronoi import pebi_grid

sys.path.insert(0, str(Path(__file__).parent))
from pebi import case as pebi_case
from pebi import layered_horizons


def summary(times: list[float]) -> str:
    return f"median {statistics.median(times):6.3f} s (min {min(times):.3f}, max {max(times):.3f})"


def timed_runs(fn, repeat: int) -> tuple[object, list[float], float]:
    """``fn()`` ``repeat`` times (median etc. of the wall times), then once more under
    tracemalloc: the result, the times and the peak of traced allocations (MiB)."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    del out
    tracemalloc.start()
    out = fn()
    peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    return out, times, peak


def faulted_deck(dims: list[int]):
    """make_model3 with rock, MULTX on a box and the first fault's faces under FAULTS + MULTFLT."""
    deck = make_model3(dims)
    nx, ny, nz = deck.cart_dims
    n = deck.num_cells
    rng = np.random.default_rng(0)
    permx = np.round(10.0 ** rng.normal(2.0, 0.5, n), 3)  # lognormal, median 100 mD
    i, j, _ = np.unravel_index(np.arange(n), (nx, ny, nz), order="F")
    multx = np.where((i >= nx // 4) & (i < nx // 2) & (j >= ny // 4) & (j < ny // 2), 0.5, 1.0)
    # make_model3 drops the block i < 0.6 nx, j < 0.5 ny by 2 m: its east and north sides are a fault
    i1, j1 = int(np.floor(0.6 * nx + 0.5)), int(np.floor(0.5 * ny + 0.5))
    faults = (
        FaultSegment("F1", i1 - 1, i1 - 1, 0, j1 - 1, 0, nz - 1, "X"),
        FaultSegment("F1", 0, i1 - 1, j1 - 1, j1 - 1, 0, nz - 1, "Y"),
    )
    cell_data = {
        "PERMX": permx,
        "PERMY": permx,
        "PERMZ": permx / 10.0,
        "NTG": np.round(0.6 + 0.4 * rng.random(n), 3),
        "MULTX": multx,
    }
    return replace(deck, cell_data=cell_data, faults=faults, multflt={"F1": 0.1}, units="METRIC")


def bench_deck(args) -> None:
    deck = faulted_deck(args.dims)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "model3.grdecl"
        write_grdecl(path, deck)
        deck = replace(read_grdecl(path), units="METRIC")
        cp = process_grdecl(deck)
        g = cp.grid
        print(
            f"make_model3({args.dims}) + PERMX/Y/Z, NTG, MULTX on a box, MULTFLT 0.1 on F1: "
            f"{g.num_cells:,d} active cells, {g.num_faces:,d} faces "
            f"({int((g.faces.tag > 0).sum()):,d} on faults), GRDECL {path.stat().st_size / 2**20:.0f} MiB"
        )
        theirs = xtgeo_call(path)
    ours_times, their_times, ours_cpu, their_cpu = [], [], [], []
    for _ in range(args.repeat):  # alternating: both see the same state of the machine
        t0, c0 = time.perf_counter(), time.process_time()
        conn = deck_transmissibility(deck, cp)
        ours_times.append(time.perf_counter() - t0)
        ours_cpu.append(time.process_time() - c0)
        if theirs is not None:
            t0, c0 = time.perf_counter(), time.process_time()
            result = theirs[0]()
            their_times.append(time.perf_counter() - t0)
            their_cpu.append(time.process_time() - c0)
    tracemalloc.start()
    deck_transmissibility(deck, cp)
    peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    ours = statistics.median(ours_times)
    print(f"  {conn!r}")
    print(
        f"  deck_transmissibility  first call {ours_times[0]:6.3f} s, {summary(ours_times)}, "
        f"peak extra memory {peak:.0f} MiB (tracemalloc)"
    )
    print(f"    CPU time (all threads): first call {ours_cpu[0]:6.3f} s, {summary(ours_cpu)}")
    print(
        f"    target <= 0.5 s: {'met' if ours <= 0.5 else 'NOT met'}; "
        f"<= 1 GiB: {'met' if peak <= 1024 else 'NOT met'}"
    )
    if args.profile:
        profile = cProfile.Profile()
        profile.runcall(deck_transmissibility, deck, cp)
        pstats.Stats(profile).sort_stats("tottime").print_stats(12)
    if theirs is None:
        print("  (xtgeo not importable: no peer timing; install the test extra)")
        return
    _, version, name, nnc = theirs
    median = statistics.median(their_times)
    print(
        f"  xtgeo {version} {name}  first call {their_times[0]:6.3f} s, {summary(their_times)}, "
        f"{nnc(result):,d} NNCs"
    )
    print(f"    CPU time: first call {their_cpu[0]:6.3f} s, {summary(their_cpu)}")
    for what, t_theirs, t_ours in (("median", median, ours), ("first call", their_times[0], ours_times[0])):
        print(
            f"    xtgeo / deck_transmissibility, {what}: {t_theirs / t_ours:.2f}x "
            f"(target >= 3x: {'met' if t_theirs >= 3 * t_ours else 'NOT met'})"
        )
    cpu_ratio = statistics.median(their_cpu) / statistics.median(ours_cpu)
    print(
        f"    CPU time xtgeo / ours: median {cpu_ratio:.2f}x, first call {their_cpu[0] / ours_cpu[0]:.2f}x "
        "(what the wall times approach on a loaded machine, where our threads find no free core)"
    )
    tx, ty, tz = result[:3]
    arrays = {k: np.ma.filled(p.values.astype(np.float64), 0.0) for k, p in (("x", tx), ("y", ty), ("z", tz))}
    compare_with_xtgeo(deck, conn, arrays)


def xtgeo_call(path: Path):
    """(a zero-argument call of xtgeo's transmissibilities of the deck at ``path``, xtgeo's
    version, the method's name, the NNC count of a result), or None without xtgeo. The grid
    and properties are read here, untimed."""
    try:
        import xtgeo
    except ImportError:
        return None
    grid = xtgeo.grid_from_file(path, fformat="grdecl")
    props = [
        xtgeo.gridproperty_from_file(path, fformat="grdecl", name=k, grid=grid)
        for k in ("PERMX", "PERMY", "PERMZ", "NTG")
    ]
    method = getattr(grid, "get_cell_transmissibilities", None) or grid.get_transmissibilities
    return (
        lambda: method(props[0], props[1], props[2], ntg=props[3]),
        xtgeo.__version__,
        method.__name__,
        lambda result: len(result[3]),
    )


def compare_with_xtgeo(deck, conn, arrays) -> None:
    """Our neighbour T against xtgeo's TRANX/Y/Z where no multiplier applies (it applies none)."""
    nx, ny, _ = deck.cart_dims
    g = conn.global_cells
    step = g[:, 1] - g[:, 0]
    multx = deck.cell_data["MULTX"]
    faulted = np.zeros(deck.num_cells, dtype=bool)
    for seg in deck.faults:
        i, j, k = np.meshgrid(
            np.arange(seg.i1, seg.i2 + 1), np.arange(seg.j1, seg.j2 + 1), np.arange(seg.k1, seg.k2 + 1)
        )
        faulted[(i + nx * (j + ny * k)).ravel()] = True
    plain = (conn.kind == NEIGHBOR) & (multx[g[:, 0]] == 1.0) & ~faulted[g[:, 0]] & ~faulted[g[:, 1]]
    rel = []
    for axis, stride in (("x", 1), ("y", nx), ("z", nx * ny)):
        sel = plain & (step == stride)
        t = arrays[axis].reshape(-1, order="F")[g[sel, 0]]  # xtgeo: (nx, ny, nz), at the lower cell
        ok = t > 0
        rel.append(np.abs(t[ok] / conn.trans[sel][ok] - 1.0))
    r = np.concatenate(rel)
    print(
        f"    xtgeo vs ours on {r.size:,d} neighbour connections without multipliers: relative "
        f"difference median {np.median(r):.1e}, 99th percentile {np.percentile(r, 99):.1e}, max {r.max():.1e}"
    )


def bench_pebi(args) -> None:
    domain, h, faults, wells = pebi_case(args.sites)
    pg = pebi_grid(domain, h, faults, wells)
    areal = pg.grid
    horizons, throws = layered_horizons(pg, faults)
    r = extrude(areal, horizons, layers=10, faults=throws, centres=pg.sites)
    grid = r.grid
    geo = compute_geometry(grid)
    rng = np.random.default_rng(1)
    permx = 10.0 ** rng.normal(2.0, 0.5, grid.num_cells)
    perm = np.column_stack([permx, permx, permx / 10.0])
    ntg = 0.6 + 0.4 * rng.random(grid.num_cells)
    centres = np.column_stack([pg.sites[grid.layering.column], geo.cell_centroids[:, 2]])
    print(
        f"layered PEBI grid (bench/pebi.py, {args.sites:,d} sites, 10 layers, every fault thrown): "
        f"{grid.num_cells:,d} cells, {grid.num_faces:,d} faces, {r.nnc.num:,d} NNCs"
    )
    conn, times, peak = timed_runs(
        lambda: transmissibility(grid, geo, perm, ntg, centres=centres, distance="normal"), args.repeat
    )
    print(f"  {conn!r}")
    print(f"  transmissibility  {summary(times)}, peak extra memory {peak:.0f} MiB (tracemalloc)")
    print(
        f"    target <= 1 s: {'met' if statistics.median(times) <= 1.0 else 'NOT met'}; "
        f"<= 1 GiB: {'met' if peak <= 1024 else 'NOT met'}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    parser.add_argument("--dims", type=int, nargs=3, default=[200, 200, 25])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--sites", type=int, default=100_000)
    parser.add_argument("--no-pebi", action="store_true", help="skip the PEBI grid")
    parser.add_argument("--profile", action="store_true", help="cProfile one deck_transmissibility")
    args = parser.parse_args()
    bench_deck(args)
    if not args.no_pebi:
        bench_pebi(args)


if __name__ == "__main__":
    main()
