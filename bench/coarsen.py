"""Benchmark: coarsening a faulted corner-point grid of about 1e6 cells.

Run:  .venv/bin/python bench/coarsen.py [--dims 200 200 25] [--blocks 1000] [--repeat 3]

Builds ``make_model3(dims)`` with process_grdecl and its geometry, then times
(median of ``--repeat`` runs):

* ``partition_metis`` into ``--blocks`` blocks, with transmissibility-like face
  weights (area / distance between the cell centroids) and pore-volume cell
  weights, including the split into connected blocks;
* ``partition_ui`` + ``process_partition`` ([20, 20, 5] blocks);
* ``coarse_grid`` of that partition (coarse faces, geometry, the block grid);
* ``upscale_permeability`` (harmonic-arithmetic) of a random field.

Target (issue 5): METIS and the coarse grid at most 5 s each on this 2-core machine.
"""

from __future__ import annotations

import argparse
import statistics
import time
import tracemalloc

import numpy as np

import gridlib as gl
from gridlib.coarsen import (
    coarse_grid,
    partition_metis,
    partition_ui,
    process_partition,
    upscale_permeability,
)


def timed(fn, *args, **kwargs):
    t0 = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - t0


def report(name: str, fn, repeat: int):
    results = [timed(fn) for _ in range(repeat)]
    times = [t for _, t in results]
    tracemalloc.start()
    fn()
    peak = tracemalloc.get_traced_memory()[1] / 2**20
    tracemalloc.stop()
    print(
        f"  {name:<40s} median {statistics.median(times):6.3f} s (min {min(times):.3f}, "
        f"max {max(times):.3f})  peak extra {peak:6.0f} MiB"
    )
    return results[-1][0]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    parser.add_argument("--dims", type=int, nargs=3, default=[200, 200, 25])
    parser.add_argument("--blocks", type=int, default=1000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()

    r = gl.process_grdecl(gl.make_model3(args.dims))
    g = r.grid
    geo = gl.compute_geometry(g)
    print(f"make_model3({args.dims}): {g.num_cells:,d} cells, {g.num_faces:,d} faces")
    nb = g.faces.neighbors
    inner = (nb >= 0).all(axis=1)
    dist = np.ones(g.num_faces)
    d = geo.cell_centroids[nb[inner, 1]] - geo.cell_centroids[nb[inner, 0]]
    dist[inner] = np.maximum(np.linalg.norm(d, axis=1), 1e-9)
    trans = geo.face_areas / dist
    rng = np.random.default_rng(0)
    poro = rng.uniform(0.1, 0.3, g.num_cells)
    perm = np.exp(rng.normal(4.0, 1.0, (g.num_cells, 3)))

    part = report(
        f"partition_metis ({args.blocks} blocks)",
        lambda: partition_metis(g, args.blocks, face_weights=trans, cell_weights=poro * geo.cell_volumes),
        args.repeat,
    )
    print(f"    -> {np.unique(part).size} connected blocks")
    ui = report(
        "partition_ui [20, 20, 5] + process", lambda: process_partition(g, partition_ui(g, [20, 20, 5])), 1
    )
    cg = report("coarse_grid", lambda: coarse_grid(g, ui, geo), args.repeat)
    print(f"    -> {cg.num_blocks} blocks, {cg.faces.num:,d} coarse faces, {cg.grid.num_faces:,d} fine faces")
    report(
        "upscale_permeability (harmonic-arithmetic)",
        lambda: upscale_permeability(cg, perm, geo.cell_volumes),
        args.repeat,
    )


if __name__ == "__main__":
    main()
