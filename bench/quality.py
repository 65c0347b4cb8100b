"""Benchmark: the per-cell quality measures of a faulted corner-point grid of about 1e6 cells,
side by side with gridlib's geometry and xtgeo's ``get_gridquality_properties``.

Run:  .venv/bin/python bench/quality.py [--dims 200 200 25] [--repeat 3] [--no-stages]

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

Then the stages themselves (unless ``--no-stages``), as the workflow runs them: Snakemake
builds bench/cases/million.yaml (the workflow benchmark's faulted 1e6-cell anticline) up to
its quality stage in a scratch folder, and the geometry stage (read grid.nc, compute, check,
write geometry.nc) and the quality stage (read grid.nc, geometry.nc, petrophysics.nc and
grid.grdecl, measure, check the qc rules, write quality.nc and the histograms) are timed one
after the other in this process (the same median of ``--repeat``).
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

import gridlib as gl
from gridlib.cornerpoint.deck import Deck
from gridlib.cornerpoint.generators import make_model3
from gridlib.cornerpoint.process import process_grdecl
from gridlib.io.grdecl import write_grdecl
from gridlib.quality import XTGEO_NAMES, cell_quality, deck_quality
from gridlib.threads import num_threads

ROOT = Path(__file__).resolve().parents[1]
STAGE_CASE = ROOT / "bench" / "cases" / "million.yaml"


def timed(fn, *args, **kwargs):
    c0, t0 = time.process_time(), time.perf_counter()
    out = fn(*args, **kwargs)
    return out, (time.process_time() - c0, time.perf_counter() - t0)


def bench(label: str, repeat: int, fn, *args, **kwargs):
    runs = [timed(fn, *args, **kwargs) for _ in range(repeat)]
    cpu = statistics.median(t[0] for _, t in runs)
    wall = statistics.median(t[1] for _, t in runs)
    print(f"  {label:<36s} CPU {cpu:7.3f} s   wall {wall:7.3f} s")
    return runs[-1][0], (cpu, wall)


def rounded(deck: Deck) -> Deck:
    rnd = lambda v: np.round(v * 64.0) / 64.0  # noqa: E731
    return Deck(deck.cart_dims, rnd(deck.coord), rnd(deck.zcorn), deck.actnum, source="model3")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    parser.add_argument("--dims", type=int, nargs=3, default=[200, 200, 25])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-stages", action="store_true", help="skip the stage timings")
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
    print(
        f"  cell_quality / compute_geometry: {t_q[1] / t_geo[1]:.2f}x wall (target <= 2x), "
        f"{t_q[0] / t_geo[0]:.2f}x CPU; both on up to {num_threads(2)} threads"
    )
    for name in ("orientation_error", "aspect_ratio", "face_nonplanarity", "twist", "maxangle_sides"):
        v = q[name]
        print(f"    {name:<20s} median {np.nanmedian(v):9.4f}  max {np.nanmax(v):10.4f}")

    peer(deck, ours, t_q, args.repeat)
    if not args.no_stages:
        stages(args.repeat)


def peer(deck: Deck, ours: dict[str, np.ndarray], t_q: tuple[float, float], repeat: int) -> None:
    """xtgeo's ``get_gridquality_properties`` on ``deck``: its time and its largest difference
    from ``ours`` (:func:`deck_quality`) on the active cells."""
    try:
        import xtgeo
    except ImportError:
        print("  (xtgeo not importable here: pip install xtgeo for its timing)")
        return
    with tempfile.TemporaryDirectory() as tmp:
        path = write_grdecl(Path(tmp) / "model3.grdecl", deck)
        xg = xtgeo.grid_from_file(path, fformat="grdecl")
    props, t_x = bench("xtgeo get_gridquality_properties", repeat, xg.get_gridquality_properties)
    print(
        f"  cell_quality / xtgeo: {t_q[1] / t_x[1]:.2f}x wall, {t_q[0] / t_x[0]:.2f}x CPU "
        "(gridlib computes 5 more measures, xtgeo 10, on one thread)"
    )
    active = deck.active.astype(bool)
    worst = 0.0
    for prop in props.props:
        theirs = np.ma.filled(prop.values.astype(np.float64), np.nan).ravel(order="F")
        diff = np.abs(ours[prop.name][active] - theirs[active]) / np.maximum(np.abs(theirs[active]), 1.0)
        worst = max(worst, float(np.nanmax(diff)))
    assert set(XTGEO_NAMES) == {p.name for p in props.props}
    print(f"  largest difference from xtgeo on the active cells: {worst:.2e} relative (float32: 6e-8)")


def stages(repeat: int) -> None:
    """The geometry and quality stages on the files of bench/cases/million.yaml."""
    from gridlib.config import load_case
    from gridlib.stages.geometry import stage_geometry
    from gridlib.stages.quality import stage_quality

    case = load_case(STAGE_CASE)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        command = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", tmp]
        command += ["--cores", "2", "--config", f"cases={STAGE_CASE}", "studies=[]", "--until", "quality"]
        run = subprocess.run([*command, "--quiet"], capture_output=True, text=True)
        if run.returncode != 0:
            sys.exit(f"snakemake failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}")
        folder, out = work / "results" / case.name, work / "timed"
        out.mkdir()
        files = {name: folder / f"{name}.nc" for name in ("grid", "geometry", "petrophysics")}
        print(f"{case.name} ({STAGE_CASE.relative_to(ROOT)}): the stages, one after the other")
        _, t_geo = bench(
            "geometry stage", repeat, stage_geometry, case, grid=files["grid"], geometry=out / "g.nc"
        )
        _, t_q = bench(
            "quality stage",
            repeat,
            stage_quality,
            case,
            **files,
            grdecl=folder / "grid.grdecl",
            quality=out / "quality.nc",
            quality_png=out / "quality.png",
        )
    ratio = f"{t_q[1] / t_geo[1]:.2f}x wall (target <= 2x), {t_q[0] / t_geo[0]:.2f}x CPU"
    print(f"  quality stage / geometry stage: {ratio}")


if __name__ == "__main__":
    main()
