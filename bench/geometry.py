"""Benchmark: compute_geometry on about 1e6 cells (Cartesian hexahedra and layered PEBI).

Run:  .venv/bin/python bench/geometry.py [--repeat 3]

Prints, per grid, the build time, the median compute_geometry time over the
repeats, and the peak extra memory allocated during compute_geometry (numpy
allocations traced by tracemalloc). Target (issue 2): 1e6 hexahedra in at most
1.5 s and under 1 GiB extra on the project's 2-core machine.
"""

from __future__ import annotations

import argparse
import statistics
import time
import tracemalloc

import numpy as np

import gridlib as gl


def timed(fn, *args, **kwargs):
    t0 = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - t0


def peak_extra_mib(fn, *args) -> float:
    tracemalloc.start()
    base = tracemalloc.get_traced_memory()[0]
    fn(*args)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return (peak - base) / 2**20


def hexagonal_sites(n_target: int) -> np.ndarray:
    """About n_target sites on a hexagonal lattice (unit spacing)."""
    ny = int(np.sqrt(n_target / 1.1547))
    nx = int(n_target / ny)
    j, i = np.meshgrid(np.arange(ny), np.arange(nx), indexing="ij")
    x = i + 0.5 * (j % 2)
    y = j * np.sqrt(3.0) / 2.0
    return np.column_stack([x.ravel(), y.ravel()])


def bench(name: str, build, repeat: int) -> None:
    grid, t_build = timed(build)
    times = [timed(gl.compute_geometry, grid)[1] for _ in range(repeat)]
    mem = peak_extra_mib(gl.compute_geometry, grid)
    print(
        f"{name:<34s} cells={grid.num_cells:>9,d} faces={grid.num_faces:>9,d}  "
        f"build {t_build:6.2f} s  geometry median {statistics.median(times):6.3f} s "
        f"(min {min(times):.3f}, max {max(times):.3f})  peak extra {mem:7.1f} MiB"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    bench("cart_grid([100, 100, 100])", lambda: gl.cart_grid([100, 100, 100]), args.repeat)

    def layered_pebi():
        sites = hexagonal_sites(100_000)
        areal, t_pebi = timed(lambda: gl.pebi(gl.triangle_grid(sites)))
        print(f"  (areal PEBI of {len(sites):,d} sites: {t_pebi:.2f} s)")
        return gl.make_layered_grid(areal, 10)

    bench("layered PEBI, 1e5 sites x 10 layers", layered_pebi, args.repeat)


if __name__ == "__main__":
    main()
