"""Benchmark: a 1e6-cell corner-point grid cut by three faults, vertical and inclined.

Run:  .venv/bin/python bench/inclined_faults.py [--dims 200 200] [--layers 10 15] [--dip 60]
          [--horizons planes|dome] [--relax-distance R] [--repeat 1]
          [--modes vertical pillars stair_steps]

The case (written to a scratch folder as a case file, as a user would) is 3 x 2 km, 200 x 200
columns in 25 layers of two zones between three horizons (``--horizons planes``: dipping 2
degrees east; ``dome``: the dome of bench/cases/million.yaml), with three faults: F1 crossing
the model from south to north, F2 and F3 from the east and west boundaries ending inside it (a
tip each), 25, 15 and 20 m of throw. Each mode builds the same case:

* ``vertical``: the faults as today (``dip`` 90, the default);
* ``pillars``: every fault dipping ``--dip`` degrees, ``grid.fault_geometry: pillars``
  (pillars in the fault surfaces, inclining back to vertical away from them);
* ``stair_steps``: the same faults, ``fault_geometry: stair_steps`` (vertical pillars, cells
  assigned to a fault block by the surface at their own depth).

Timed separately, each the median of ``--repeat`` runs in this process: the horizons
(:func:`gridlib.case.horizons.case_horizons`), the grid (:func:`gridlib.case.grid.build_case_grid`:
the pillar lattice, ZCORN, ``process_grdecl``) and ``compute_geometry``; then the ratio of
each inclined mode's grid + geometry time to the vertical case's (issue 25's target: within
2x) and the grid's orientation figures (:mod:`gridlib.orientation`: median, 95th percentile
and maximum angle between face normal and the line joining the cell centroids), which show
what each mode costs in K-orthogonality. A mode the installed gridlib cannot build (a case key
it does not know, or a grid it refuses, e.g. pillars that would cross with the relax
distance given) is reported as such. No peer builds inclined-fault grids from a dip or
sticks in Python (xtgeo and resdata read such grids, they do not make them), so none is timed.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

import yaml

import gridlib as gl
from gridlib.case.grid import build_case_grid
from gridlib.case.horizons import case_horizons
from gridlib.config import load_case
from gridlib.errors import InputError
from gridlib.orientation import grid_face_angles, orientation_figures

MODES = ("vertical", "pillars", "stair_steps")


def case_data(
    dims: list[int],
    layers: list[int],
    mode: str,
    dip: float,
    relax_distance: float | None = None,
    horizons: str = "planes",
) -> dict[str, Any]:
    """The benchmark case in ``mode`` (module docstring)."""
    faults: list[dict[str, Any]] = [
        {"name": "F1", "trace": [[1000, -100], [1450, 2100]], "throw": 25},
        {"name": "F2", "trace": [[3100, 1000], [1500, 600]], "throw": {"start": 15, "end": 0}},
        {"name": "F3", "trace": [[-100, 1500], [1200, 1700]], "throw": {"start": 20, "end": 0}},
    ]
    grid: dict[str, Any] = {"type": "cornerpoint", "dims": dims, "layers": layers}
    if mode != "vertical":
        faults = [f | {"dip": dip} for f in faults]
        grid["fault_geometry"] = mode
        if mode == "pillars" and relax_distance is not None:
            grid["relax_distance"] = relax_distance
    depths = (("top", 2000, 120, 1200), ("middle", 2030, 125, 1250), ("base", 2080, 130, 1300))
    if horizons == "dome":
        centre = {"x0": 1500, "y0": 1000}
        surfaces = [
            {"name": n, "dome": {"depth": z, "relief": r, "radius": a} | centre} for n, z, r, a in depths
        ]
    else:
        surfaces = [{"name": n, "plane": {"depth": z, "dip": 2.0, "azimuth": 90}} for n, z, _, _ in depths]
    return {
        "name": f"inclined_{mode}",
        "seed": 11,
        "horizons": {
            "ordering": "erode",
            "lattice": {
                "x": {"start": 0, "stop": 3000, "num": 121},
                "y": {"start": 0, "stop": 2000, "num": 81},
            },
            "surfaces": surfaces,
        },
        "faults": faults,
        "grid": grid,
    }


def timed(fn, *args):
    t0 = time.perf_counter()
    out = fn(*args)
    return out, time.perf_counter() - t0


def summary(times: list[float]) -> str:
    return f"median {statistics.median(times):7.3f} s (min {min(times):.3f}, max {max(times):.3f})"


def run_mode(folder: Path, args: argparse.Namespace, mode: str):
    """Build the case of ``mode`` ``args.repeat`` times: prints the timings and figures, returns
    the median grid + geometry time (None if this gridlib cannot build the mode)."""
    path = folder / f"inclined_{mode}.yaml"
    data = case_data(args.dims, args.layers, mode, args.dip, args.relax_distance, args.horizons)
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    try:
        case = load_case(path)
    except InputError as exc:
        print(f"{mode}: not built: this gridlib does not take the case ({exc})")
        return None
    hz, grids, geoms = [], [], []
    for _ in range(args.repeat):
        horizons, t = timed(case_horizons, case)
        hz.append(t)
        try:
            built, t = timed(build_case_grid, case, horizons)
        except InputError as exc:
            print(f"{mode}: not built: {exc}")
            return None
        grids.append(t)
        geo, t = timed(gl.compute_geometry, built.grid)
        geoms.append(t)
    g = built.grid
    tagged = int((g.faces.tag > 0).sum())
    print(
        f"{mode}: {g.num_cells:,d} cells, {g.num_faces:,d} faces ({tagged:,d} on faults), "
        f"{g.num_nodes:,d} nodes, {0 if built.nnc is None else built.nnc.num:,d} NNCs"
    )
    print(f"  horizons          {summary(hz)}")
    print(f"  build_case_grid   {summary(grids)}")
    print(f"  compute_geometry  {summary(geoms)}")
    figures = orientation_figures(grid_face_angles(g, geo).angles)
    print(
        "  orientation (normal to centroid line): "
        + ", ".join(f"{k} {v:.3g} deg" for k, v in figures.items())
    )
    return statistics.median(grids) + statistics.median(geoms)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    parser.add_argument("--dims", type=int, nargs=2, default=[200, 200])
    parser.add_argument("--layers", type=int, nargs="+", default=[10, 15], help="layers per zone (2 zones)")
    parser.add_argument("--dip", type=float, default=60.0, help="degrees from horizontal")
    parser.add_argument("--horizons", choices=("planes", "dome"), default="planes")
    parser.add_argument(
        "--relax-distance", type=float, default=None, help="pillars mode (m; default: the case's default)"
    )
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--modes", nargs="+", choices=MODES, default=list(MODES))
    args = parser.parse_args()
    times: dict[str, float | None] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for mode in args.modes:
            times[mode] = run_mode(Path(tmp), args, mode)
    base = times.get("vertical")
    if base:
        for mode, t in times.items():
            if mode != "vertical" and t is not None:
                print(
                    f"{mode}: grid + geometry {t:.3f} s = {t / base:.2f}x the vertical faults' {base:.3f} s"
                )


if __name__ == "__main__":
    main()
