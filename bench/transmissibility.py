"""Benchmark: transmissibilities of a 1e6-cell faulted deck and of a 1e6-cell layered PEBI grid.

Run:  .venv/bin/python bench/transmissibility.py [--dims 200 200 25] [--repeat 3] [--peer-python PY]
                                                 [--sites 100000] [--no-pebi] [--profile]

Deck: ``make_model3(dims)`` (bench/cornerpoint.py's anticline cut by two faults, with
inactive cells) with lognormal PERMX = PERMY, PERMZ = PERMX / 10, NTG, MULTX 0.5 on a box of
columns and the first fault's faces listed under FAULTS with MULTFLT 0.1, written as a
GRDECL file, read back and processed (not timed). Times
``deck_transmissibility(deck, cp)`` alone: the median of ``--repeat`` runs (min-max),
and its peak extra memory (numpy allocations traced by tracemalloc, one more run).
``--profile`` prints cProfile's heaviest functions of one run.

If xtgeo is importable (here, or by ``--peer-python``, a separate virtualenv with
``pip install xtgeo``), xtgeo reads the same file (grid, PERMX/Y/Z, NTG: not timed) and
its ``Grid.get_cell_transmissibilities`` (4.27; ``get_transmissibilities`` before) is
timed the same way, with the ratio to ours. xtgeo applies no MULT* or MULTFLT, so its
values are compared with ours on the neighbour connections the multipliers do not touch.

PEBI: bench/pebi.py's grid (``--sites`` sites, 10 faults, 5 wells) extruded in 10 layers
with every fault thrown (about 1e6 cells), its geometry, then
``transmissibility(grid, geometry, K, ntg, centres=sites at the centroid depth,
distance="normal")`` (as the workflow's transmissibility stage calls it) timed
the same way (grid and geometry not timed).

Targets (issue "Transmissibilities for every grid", not asserted): deck_transmissibility
<= 0.5 s and >= 3x faster than xtgeo; PEBI <= 1 s; peak extra memory <= 1 GiB.
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

XTGEO = """
import json, statistics, sys, time
import numpy as np
path, out, repeat = sys.argv[1], sys.argv[2], int(sys.argv[3])
try:
    import xtgeo
except ImportError:
    print(json.dumps({}))
    raise SystemExit
t = time.perf_counter()
grid = xtgeo.grid_from_file(path, fformat="grdecl")
props = {k: xtgeo.gridproperty_from_file(path, fformat="grdecl", name=k, grid=grid)
         for k in ("PERMX", "PERMY", "PERMZ", "NTG")}
read = time.perf_counter() - t
method = getattr(grid, "get_cell_transmissibilities", None) or grid.get_transmissibilities
times = []
for _ in range(repeat):
    t = time.perf_counter()
    res = method(props["PERMX"], props["PERMY"], props["PERMZ"], ntg=props["NTG"])
    times.append(time.perf_counter() - t)
tx, ty, tz, nnc = res[:4]
arrays = {k: np.ma.filled(p.values.astype(np.float64), 0.0) for k, p in (("x", tx), ("y", ty), ("z", tz))}
np.savez(out, **arrays)
print(json.dumps({"version": xtgeo.__version__, "method": method.__name__, "read": read,
                  "times": times, "nnc": int(len(nnc))}))
"""


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
        conn, times, peak = timed_runs(lambda: deck_transmissibility(deck, cp), args.repeat)
        ours = statistics.median(times)
        print(f"  {conn!r}")
        print(f"  deck_transmissibility  {summary(times)}, peak extra memory {peak:.0f} MiB (tracemalloc)")
        print(
            f"    target <= 0.5 s: {'met' if ours <= 0.5 else 'NOT met'}; "
            f"<= 1 GiB: {'met' if peak <= 1024 else 'NOT met'}"
        )
        if args.profile:
            profile = cProfile.Profile()
            profile.runcall(deck_transmissibility, deck, cp)
            pstats.Stats(profile).sort_stats("tottime").print_stats(12)
        peer(args, path, deck, conn, ours)


def peer(args, path: Path, deck, conn, ours: float) -> None:
    """xtgeo's transmissibilities of the same file, timed in ``--peer-python``."""
    out = path.with_suffix(".npz")
    done = subprocess.run(
        [args.peer_python, "-c", XTGEO, str(path), str(out), str(args.repeat)], capture_output=True, text=True
    )
    lines = done.stdout.strip().splitlines()
    result = json.loads(lines[-1]) if done.returncode == 0 and lines else {}
    if not result:
        print("  (xtgeo not importable: no peer timing; see --peer-python)")
        if done.returncode:
            print("  " + done.stderr.strip().splitlines()[-1] if done.stderr.strip() else "")
        return
    theirs = statistics.median(result["times"])
    print(
        f"  xtgeo {result['version']} {result['method']}  {summary(result['times'])} "
        f"(after reading the file in {result['read']:.1f} s), {result['nnc']:,d} NNCs"
    )
    print(
        f"    xtgeo / deck_transmissibility = {theirs / ours:.2f}x "
        f"(target >= 3x: {'met' if theirs >= 3 * ours else 'NOT met'})"
    )
    compare_with_xtgeo(deck, conn, np.load(out))


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
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--peer-python", default=sys.executable, help="interpreter with xtgeo")
    parser.add_argument("--sites", type=int, default=100_000)
    parser.add_argument("--no-pebi", action="store_true", help="skip the PEBI grid")
    parser.add_argument("--profile", action="store_true", help="cProfile one deck_transmissibility")
    args = parser.parse_args()
    bench_deck(args)
    if not args.no_pebi:
        bench_pebi(args)


if __name__ == "__main__":
    main()
