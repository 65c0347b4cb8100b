"""Benchmark: Gaussian random fields at depositional coordinates on about 1e6 corner-point cells.

Run:  .venv/bin/python bench/petrophysics.py [--dims 200 200 25] [--repeat 3] [--modes 1000]
                                              [--plain-cells 100000] [--irregular]

Builds ``make_model3(dims)`` (an anticline cut by two faults, with inactive
cells) with ``process_grdecl`` (not timed), then times, each the median of
``--repeat`` runs:

* ``depositional_coordinates`` (columns from the deck's pillars, w = k dz_ref);
* one ``gaussian_field`` (gstools' randomisation method with ``--modes`` modes,
  including the draw of the modes, summed in the factorised columns x layers
  form; make_model3's columns lie on a lattice, so x and y split too, unless
  ``--irregular`` moves every column centre by up to 1 m at random, as the
  pillars of a real deck would be: one trigonometric term per column);
* a whole rock: two fields (porosity, and permeability partly correlated with
  it), ``normal_porosity``, ``lognormal_permeability``, ``make_rock``;

and the peak memory the field allocates (tracemalloc, numpy's arrays
included) and the process's max RSS, plus, for comparison, gstools' plain summation at the physical
centroids of ``--plain-cells`` cells, scaled to all cells (it is linear in the
number of cells). Target (issue 5): at most 5 s for the field on this 2-core
machine.
"""

from __future__ import annotations

import argparse
import resource
import statistics
import time
import tracemalloc

import numpy as np

from gridlib.cornerpoint.generators import make_model3
from gridlib.cornerpoint.process import process_grdecl
from gridlib.geometry import compute_geometry
from gridlib.petrophysics import (
    Variogram,
    depositional_coordinates,
    gaussian_field,
    lognormal_permeability,
    make_rock,
    normal_porosity,
)


def median_time(fn, repeat: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dims", type=int, nargs=3, default=[200, 200, 25])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--modes", type=int, default=1000)
    ap.add_argument("--plain-cells", type=int, default=100_000)
    ap.add_argument("--irregular", action="store_true", help="columns off the lattice (general path)")
    args = ap.parse_args()

    deck = make_model3(args.dims)
    grid = process_grdecl(deck).grid
    nz = args.dims[2]
    dz_ref = 15.0 / nz  # make_model3's 15 m thickness over nz layers
    print(f"make_model3({args.dims}): {grid.num_cells:,} active cells, {np.prod(args.dims[:2]):,} columns")
    variogram = Variogram("exponential", var=1.0, len_scale=[200.0, 100.0, 2.0], angles=[30.0])

    t_dep, u = median_time(
        lambda: depositional_coordinates(grid, coord=deck.coord, dz_ref=dz_ref), args.repeat
    )
    if args.irregular:
        jitter = np.random.default_rng(0).uniform(-1.0, 1.0, u.column_xy.shape)
        u = depositional_coordinates(grid, column_xy=u.column_xy + jitter, dz_ref=dz_ref)
        print("columns moved off the lattice by up to 1 m (the general path)")
    t_grf, field = median_time(lambda: gaussian_field(u, variogram, seed=1, mode_no=args.modes), args.repeat)

    def rock():
        z1 = gaussian_field(u, variogram, seed=1, mode_no=args.modes)
        z2 = gaussian_field(u, variogram, seed=2, mode_no=args.modes)
        poro = normal_porosity(z1, mean=0.2, std=0.04, bounds=(0.02, 0.4))
        perm = lognormal_permeability(0.8 * z1 + 0.6 * z2, median=100.0, sigma=1.0)
        return make_rock(poro, perm, kv_kh=0.1)

    t_rock, _ = median_time(rock, args.repeat)

    tracemalloc.start()
    gaussian_field(u, variogram, seed=1, mode_no=args.modes)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()

    print(f"depositional_coordinates: {t_dep:.3f} s")
    print(f"gaussian_field ({args.modes} modes): {t_grf:.3f} s, peak {peak / 2**20:.0f} MiB allocated")
    print(f"rock (2 fields + transforms): {t_rock:.3f} s")
    print(f"field mean {field.mean():+.4f}, variance {field.var():.4f} (target 0, 1)")
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"max RSS of this process so far: {rss:.0f} MiB (mostly make_model3 + process_grdecl)")

    if args.plain_cells:
        n = min(args.plain_cells, grid.num_cells)
        cents = compute_geometry(grid).cell_centroids[:n]
        t_plain, _ = median_time(lambda: gaussian_field(cents, variogram, seed=1, mode_no=args.modes), 1)
        scaled = t_plain * grid.num_cells / n
        print(
            f"gstools' plain sum at {n:,} centroids: {t_plain:.2f} s, i.e. about {scaled:.0f} s for all "
            f"{grid.num_cells:,} cells ({scaled / t_grf:.0f}x the factorised sum)"
        )


if __name__ == "__main__":
    main()
