"""Benchmark: the per-cell quality measures of a faulted corner-point grid of about 1e6 cells,
side by side with gridlib's geometry and xtgeo's ``get_gridquality_properties``.

Run:  .venv/bin/python bench/quality.py [--dims 200 200 25] [--repeat 3]

``make_model3(dims)`` (an anticline cut by two faults, pinched layers, inactive cells; the
deck of bench/cornerpoint.py), rounded to 1/64 so that its values are float32 (what xtgeo
keeps), is processed once; then, in this one process, each the median of ``--repeat`` runs
(CPU seconds of this process, and wall seconds):

* ``compute_geometry`` of the processed grid (the geometry stage's work),
* ``cell_quality(grid, geometry, deck=deck, perm=...)``: every measure of every cell (the
  quality stage's work; target: within 2x of the geometry's time),
* ``cell_quality`` without the deck (the hexahedra recovered from the grid's faces),
* ``deck_quality``: xtgeo's set on every deck cell,
* xtgeo's ``get_gridquality_properties`` on the same grid (read by xtgeo from the GRDECL
  gridlib writes; the read is not timed), if xtgeo can be imported; and the largest
  difference between its values and ours on the active cells.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

import gridlib as gl
from gridlib.cornerpoint.deck import Deck
from gridlib.cornerpoint.generators import make_model3
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.grdecl import write_grdecl
from gridlib.quality import XTGEO_NAMES, cell_quality, deck_quality


def timed(fn, *args, **kwargs):
    c0, t0 = time.process_time(), time.perf_counter()
    out = fn(*args, **kwargs)
    return out, (time.process_time() - c0, time.perf_counter() - t0)


def bench(label: str, repeat: int, fn, *args, **kwargs):
    runs = [timed(fn, *args, **kwargs) for _ in range(repeat)]
    cpu = statistics.median(t[0] for _, t in runs)
    wall = statistics.median(t[1] for _, t in runs)
    print(f"  {label:<34s} CPU {cpu:7.3f} s   wall {wall:7.3f} s")
    return runs[-1][0], cpu


def rounded(deck: Deck) -> Deck:
    rnd = lambda v: np.round(v * 64.0) / 64.0  # noqa: E731
    return Deck(deck.cart_dims, rnd(deck.coord), rnd(deck.zcorn), deck.actnum, source="model3")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    parser.add_argument("--dims", type=int, nargs=3, default=[200, 200, 25])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()

    deck = rounded(make_model3(args.dims))
    grid = process_grdecl(deck).grid
    perm = np.tile([100.0, 100.0, 10.0], (grid.num_cells, 1))
    print(
        f"make_model3({args.dims}): {deck.num_cells:,d} cells, {grid.num_cells:,d} in the grid, "
        f"{grid.num_faces:,d} faces ({int((grid.faces.tag > 0).sum()):,d} on faults)"
    )
    geo, t_geo = bench("compute_geometry", args.repeat, gl.compute_geometry, grid)
    q, t_q = bench("cell_quality (deck, perm)", args.repeat, cell_quality, grid, geo, deck=deck, perm=perm)
    bench("cell_quality (grid's own hexahedra)", args.repeat, cell_quality, grid, geo, perm=perm)
    ours, _ = bench("deck_quality (every deck cell)", args.repeat, deck_quality, deck)
    print(f"  cell_quality / compute_geometry: {t_q / t_geo:.2f}x CPU (target <= 2x)")
    for name in ("orientation_error", "aspect_ratio", "face_nonplanarity", "twist", "maxangle_sides"):
        v = q[name]
        print(f"    {name:<20s} median {np.nanmedian(v):9.4f}  max {np.nanmax(v):10.4f}")

    try:
        import xtgeo
    except ImportError:
        print("  (xtgeo not importable here: pip install xtgeo for its timing)")
        return
    with tempfile.TemporaryDirectory() as tmp:
        path = write_grdecl(Path(tmp) / "model3.grdecl", deck)
        xg = xtgeo.grid_from_file(path, fformat="grdecl")
    props, t_x = bench("xtgeo get_gridquality_properties", args.repeat, xg.get_gridquality_properties)
    print(f"  cell_quality / xtgeo: {t_q / t_x:.2f}x CPU (gridlib computes 5 more measures, xtgeo 10)")
    active = deck.active.astype(bool)
    worst = 0.0
    for prop in props.props:
        theirs = np.ma.filled(prop.values.astype(np.float64), np.nan).ravel(order="F")
        diff = np.abs(ours[prop.name][active] - theirs[active]) / np.maximum(np.abs(theirs[active]), 1.0)
        worst = max(worst, float(np.nanmax(diff)))
    assert set(XTGEO_NAMES) == {p.name for p in props.props}
    print(f"  largest difference from xtgeo on the active cells: {worst:.2e} relative (float32: 6e-8)")


if __name__ == "__main__":
    main()
