"""Benchmark: pebi_grid with 1e5 hexagonal background sites, 10 faults and 5 radial wells (issue 4).

Run:  .venv/bin/python bench/pebi.py [--repeat 3] [--sites 100000]

The domain is an irregular, non-convex outline at UTM coordinates (offset
(5.3e5, 6.7e6) m) sized for ``--sites`` hexagonal sites 25 m apart; four of
the ten faults cross others, four reach the boundary, the others end inside;
each well has 32 rings of 30 sites out to 130 m. Prints the median wall time of
``pebi_grid`` over the repeats, the peak memory (numpy allocations traced by
tracemalloc, and the maximum resident set size of a child process that builds
the grid once, with the size it had before building), and the quality report.
Target (issue 4, 2-D part): at most 3 s on the project's 2-core machine.

Then the 2.5D step: the grid extruded in 10 layers between two horizons with
every fault given a throw (about 1e6 cells), timed with compute_geometry;
target at most 4 s for both.
"""

from __future__ import annotations

import argparse
import json
import resource
import statistics
import subprocess
import sys
import time
import tracemalloc

import numpy as np

from gridlib import compute_geometry
from gridlib.pillars.extrude import extrude
from gridlib.pillars.fault_traces import FaultTrace
from gridlib.voronoi import Fault, Rings, Well, grid_quality, pebi_grid

OFFSET = np.array([5.3e5, 6.7e6])
SPACING = 25.0  # m


def case(n_sites: int = 100_000):
    """Domain, cell size, faults and wells of the benchmark (metres, UTM-sized coordinates)."""
    area = n_sites * np.sqrt(3) / 2 * SPACING**2  # a hexagonal cell covers sqrt(3)/2 h^2
    th = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    r = 1 + 0.12 * np.sin(3 * th) + 0.08 * np.cos(5 * th)
    base = np.column_stack([1.3 * r * np.cos(th), r * np.sin(th)])
    x, y = base[:, 0], base[:, 1]
    scale = np.sqrt(area / (0.5 * abs(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))))
    domain = base * scale + OFFSET

    def fault(points, name):
        return Fault(np.asarray(points) * scale + OFFSET, name)

    faults = [
        fault([(-1.2, -0.3), (0.2, 0.25), (1.0, 0.5)], "F1"),  # crosses F2 and F7, leaves the domain
        fault([(-0.5, -0.9), (-0.1, 0.0), (0.1, 0.9)], "F2"),  # crosses F1, F4 and F8, both ends outside
        fault([(0.3, -0.8), (0.6, 0.1)], "F3"),
        fault([(-0.9, 0.4), (-0.3, 0.55), (0.15, 0.95)], "F4"),  # crosses F2
        fault([(0.5, -0.5), (1.1, -0.2)], "F5"),
        fault([(-1.0, -0.6), (-0.6, -0.45)], "F6"),  # leaves the domain
        fault([(0.7, 0.55), (0.9, 0.1), (1.05, -0.1)], "F7"),  # crosses F1
        fault([(-0.4, -0.55), (0.35, -0.35)], "F8"),  # crosses F2
        fault([(-0.8, 0.05), (-0.45, 0.25)], "F9"),
        fault([(0.55, -0.65), (0.75, -0.45)], "F10"),
    ]
    rings = Rings(inner=0.2, outer=0.0325 * scale)  # 130 m at 1e5 sites; 30 sectors (2 pi r / 25 m)
    points = [(-0.76, 0.16), (0.4, 0.45), (0.05, -0.65), (0.95, 0.25), (-0.35, 0.7)]
    wells = [Well(np.asarray(p) * scale + OFFSET, f"W{k + 1}", rings=rings) for k, p in enumerate(points)]
    return domain, SPACING, faults, wells


def _status_kib(key: str) -> int | None:
    """VmRSS / VmHWM of this process from /proc (Linux), in KiB."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith(key + ":"):
                    return int(line.split()[1])
    except OSError:  # no /proc (not Linux): no resident-memory figure
        return None
    return None


def child(n_sites: int) -> None:
    """Build once in this process and report its resident set size before and at its peak (KiB).

    ru_maxrss survives exec on Linux (it would report the parent's size), so the peak is
    read from /proc/self/status (VmHWM of this process image) where available.
    """
    args = case(n_sites)
    before = _status_kib("VmRSS") or resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    pebi_grid(*args)
    peak = _status_kib("VmHWM") or resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(json.dumps({"before_kib": before, "peak_kib": peak}))


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--sites", type=int, default=100_000)
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args.sites)
        return
    domain, h, faults, wells = case(args.sites)
    pg = pebi_grid(domain, h, faults, wells)  # warm-up (imports, caches)
    times = []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        pg = pebi_grid(domain, h, faults, wells)
        times.append(time.perf_counter() - t0)
    tracemalloc.start()
    pebi_grid(domain, h, faults, wells)
    traced = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    cmd = [sys.executable, __file__, "--child", "--sites", str(args.sites)]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True)
    rss = json.loads(out.stdout.strip().splitlines()[-1])
    g = pg.grid
    kinds = np.bincount(pg.site_kind, minlength=6)
    print(
        f"pebi_grid: {g.num_cells:,d} cells ({kinds[0]:,d} background, {kinds[2] + kinds[3]:,d} fault, "
        f"{kinds[4]:,d} well), {g.num_faces:,d} faces, {g.num_nodes:,d} nodes, "
        f"{int((g.faces.tag > 0).sum()):,d} fault faces"
    )
    print(
        f"  time: median {statistics.median(times):.3f} s over {args.repeat} runs "
        f"(min {min(times):.3f}, max {max(times):.3f})"
    )
    print(
        f"  memory: numpy peak {traced:.0f} MiB (tracemalloc); a child process building it once peaks at "
        f"{rss['peak_kib'] / 1024:.0f} MiB resident, {(rss['peak_kib'] - rss['before_kib']) / 1024:.0f} MiB "
        f"more than before pebi_grid"
    )
    print("  notes: " + "; ".join(pg.notes))
    print("quality:")
    print("  " + str(grid_quality(pg)).replace("\n", "\n  "))
    print_by_kind(pg)

    extrusion(pg, faults, args.repeat)


def print_by_kind(pg) -> None:
    """The smallest cells by what generated them, in m2 and relative to their target size h
    (``PebiGrid.site_size``): well rings are small by design (the first ring at 0.2 m), not slivers."""
    geo = compute_geometry(pg.grid)
    area = geo.cell_volumes
    rel = area / pg.site_size**2
    names = ("background", "padding", "fault", "fault tip", "well", "added")
    print("  smallest cells by kind (area m2, area / h2):")
    for k, name in enumerate(names):
        sel = np.flatnonzero(pg.site_kind == k)
        if sel.size:
            i, j = sel[np.argmin(area[sel])], sel[np.argmin(rel[sel])]
            print(
                f"    {name:10s} {sel.size:7,d} cells: min area {area[i]:.4g} m2 "
                f"(h {pg.site_size[i]:.3g} m), min area / h2 {rel[j]:.3g}"
            )


def layered_horizons(pg, faults):
    """The 2.5D case: a domed top, a base 50-80 m below it, and every fault's throw (8-17 m,
    hanging wall on its right, cells classified by their PEBI sites)."""
    areal = pg.grid
    x0, y0 = areal.nodes.coords.mean(axis=0)
    span = float(np.ptp(areal.nodes.coords, axis=0).max())

    def top(x, y):
        return 2000.0 + 80.0 * np.exp(-(((x - x0) / span) ** 2 + ((y - y0) / span) ** 2) * 8.0)

    def base(x, y):
        return top(x, y) + 50.0 + 30.0 * (x - x0) / span

    throws = [FaultTrace(f.points, throw=8.0 + k, name=f.name) for k, f in enumerate(faults)]
    return [top, base], throws


def extrusion(pg, faults, repeat: int) -> None:
    """The 2.5D step: 10 layers between the horizons of :func:`layered_horizons`, first with
    the faults as tagged (conforming) faces only, then with every fault given a throw."""
    areal = pg.grid
    horizons, throws = layered_horizons(pg, faults)
    for label, traces in (("faults tagged, no throw", ()), ("every fault with a throw", throws)):
        times, geo_times = [], []
        for _ in range(repeat):
            t0 = time.perf_counter()
            r = extrude(areal, horizons, layers=10, faults=traces, centres=pg.sites)
            t1 = time.perf_counter()
            compute_geometry(r.grid)
            geo_times.append(time.perf_counter() - t1)
            times.append(t1 - t0)
        g = r.grid
        total = [a + b for a, b in zip(times, geo_times, strict=True)]
        print(
            f"extrude ({label}): {g.num_cells:,d} cells, {g.num_faces:,d} faces, "
            f"{int((g.faces.tag > 0).sum()):,d} fault faces, {r.nnc.num:,d} NNCs"
        )
        print(
            f"  extrude median {statistics.median(times):.3f} s, compute_geometry median "
            f"{statistics.median(geo_times):.3f} s, together median {statistics.median(total):.3f} s "
            f"(min {min(total):.3f}, max {max(total):.3f}) over {repeat} runs; target 4 s"
        )


if __name__ == "__main__":
    main()
