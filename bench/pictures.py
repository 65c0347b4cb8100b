"""Benchmark: the CPU of each picture of a case's ``pictures`` stage (and of its quality picture),
side by side between checkouts, in warm processes.

Run:  .venv/bin/python bench/pictures.py [--cases waterflood_pebi,waterflood_cp,spe9,faulted_picks]
                                        [--checkout DIR ...] [--repeat 5] [--folder DIR]
                                        [--profile CASE]

The sample cases' stage files are built once (``run_case``, this checkout) in ``--folder``
(default a scratch folder). Then, per checkout (``--checkout``, default this one), alternating,
one Python process per checkout (``PYTHONPATH`` the checkout) imports the plotting stack, draws
every case's pictures once (warm-up: fonts, colour maps, VTK's first window) and then
``--repeat`` times, timing each step's CPU (user + system of the process, ``time.process_time``):

* ``scene``: the stage files read (:func:`gridlib.stages.pictures.read_scene`);
* ``3d``: the pyvista scene built and its screenshot saved (``render_grid``);
* ``histograms``: the histograms' figure built and saved;
* ``plan+section build``: both matplotlib figures built (``case_figures``);
* ``plan save``, ``section save``: each one's ``savefig`` (draw, text layout, PNG encoding);
* ``residuals``: the pick residuals' figure built and saved (cases with picks);
* ``quality``: the quality stage's histograms built and saved;
* ``stage``: the whole ``pictures`` stage (``run_stage``), for comparison with the sum.

It prints the median (and the least) CPU seconds per step, case and checkout, with the load
average before and after. ``--profile CASE``: a cProfile of 3 warm runs of CASE's pictures stage (and quality
picture) in this process, by phase: figure build, layout, draw, text layout, PNG encoding, VTK
render (cumulative seconds of the functions that mark each phase).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CASES = "waterflood_pebi,waterflood_cp,spe9,faulted_picks"
STEPS = (
    "scene",
    "3d",
    "histograms",
    "plan+section build",
    "plan save",
    "section save",
    "residuals",
    "quality",
    "stage",
)


def build(cases: list[str], folder: Path) -> None:
    """The cases' stage files in ``folder/<case>`` (once)."""
    from gridlib.stages.pipeline import run_case

    for name in cases:
        if not (folder / name / "grid.nc").exists():
            run_case(ROOT / "config" / "cases" / f"{name}.yaml", folder / name)


def draw_once(name: str, folder: Path, scratch: Path, steps: bool = True) -> dict[str, float]:
    """Each step's CPU seconds for one drawing of the case's pictures (see the docstring);
    without ``steps``, the quality picture and the stage only."""
    from gridlib.artifacts import case_paths
    from gridlib.config import load_case
    from gridlib.io.quality_histograms import plot_quality
    from gridlib.stages.pipeline import run_stage

    case = load_case(ROOT / "config" / "cases" / f"{name}.yaml")
    paths = case_paths(name, folder / name)
    times: dict[str, float] = {}

    def timed(step: str, call):
        start = time.process_time()
        out = call()
        times[step] = times.get(step, 0.0) + time.process_time() - start
        return out

    if paths["quality"].exists():
        values = {k: v.values for k, v in read_netcdf_quality(paths["quality"]).items()}
        timed("quality", lambda: plot_quality(scratch / "q.png", values, case.data.get("qc", []), name))
    drawn = ("png", "histograms", "plan", "section", "residuals")
    stage_paths = {**paths, **{k: scratch / f"stage_{k}.png" for k in drawn}}
    timed("stage", lambda: run_stage("pictures", case, stage_paths))
    if steps:
        draw_steps(case, paths, scratch, timed)
    return times


def draw_steps(case, paths, scratch: Path, timed) -> None:
    """The pictures stage's steps one by one, each ``timed`` (see the docstring)."""
    from gridlib.io.picture_style import DPI
    from gridlib.io.pictures import plot_histograms, render_grid, save_figure
    from gridlib.stages import pictures as stage

    with_section = paths["section"].exists()
    scene = timed(
        "scene",
        lambda: stage.read_scene(
            case,
            paths["grid"],
            paths["geometry"],
            paths["petrophysics"] if paths["petrophysics"].exists() else None,
            paths["transmissibility"] if paths["transmissibility"].exists() else None,
            paths["wells"] if paths["wells"].exists() else None,
        ),
    )
    timed("3d", lambda: render_grid(scratch / "a.png", **stage.view_arguments(case, scene, paths["faults"])))
    poro = None if scene.rock is None else scene.rock["poro"]
    timed(
        "histograms",
        lambda: plot_histograms(
            scratch / "h.png", scene.geo, poro, scene.grid.griddim, scene.title, scene.units, scene.trans
        ),
    )
    figures = timed("plan+section build", lambda: stage.case_figures(case, scene, with_section=with_section))
    for key, figure in figures.items():
        timed(
            f"{key} save", lambda figure=figure, key=key: save_figure(figure, scratch / f"{key}.png", dpi=DPI)
        )
    if paths["residuals"].exists():
        timed(
            "residuals",
            lambda: save_figure(
                stage.pick_residuals_figure(case, paths["horizons"]), scratch / "r.png", dpi=DPI
            ),
        )


def read_netcdf_quality(path: Path):
    """The quality measures of ``quality.nc`` (cell variables)."""
    import xarray as xr

    with xr.open_dataset(path) as ds:
        return {k: ds[k].load() for k in ds.data_vars if ds[k].ndim == 1}


def child(cases: list[str], folder: Path, repeat: int) -> None:
    """Warm up, then ``repeat`` drawings of every case; prints {case: {step: [seconds]}}."""
    runs: dict[str, dict[str, list[float]]] = {c: {} for c in cases}
    with tempfile.TemporaryDirectory() as tmp:
        for name in cases:
            draw_once(name, folder, Path(tmp))
        for _ in range(repeat):
            for name in cases:
                for step, seconds in draw_once(name, folder, Path(tmp)).items():
                    runs[name].setdefault(step, []).append(seconds)
    print(json.dumps(runs))


def profile(name: str, folder: Path) -> None:
    """cProfile of 3 warm drawings of ``name``'s pictures by phase (module docstring)."""
    import cProfile
    import pstats

    with tempfile.TemporaryDirectory() as tmp:
        draw_once(name, folder, Path(tmp), steps=False)
        profiler = cProfile.Profile(time.process_time)
        profiler.enable()
        for _ in range(3):
            draw_once(name, folder, Path(tmp), steps=False)
        profiler.disable()
    stats = pstats.Stats(profiler)
    stats.sort_stats("cumulative").print_stats(45)
    phases = {  # phase: (function, a part of its file's name, "" for C methods)
        "savefig": ("print_figure", "backend_bases"),
        "figure draw": ("draw", "figure.py"),
        "constrained layout": ("do_constrained_layout", "_constrained_layout"),
        "text layout": ("_get_layout", "text.py"),
        "new ticks": ("_get_tick", "axis.py"),
        "mathtext parse": ("parse", "mathtext"),
        "PNG encode": ("encode", ""),
        "VTK render": ("Render", ""),
        "3-D screenshot": ("screenshot", "pyvista"),
    }
    for phase, (function, file_part) in phases.items():
        total = max(
            (
                v[3]
                for (file, _, fn), v in stats.stats.items()
                if (fn == function and file_part in file) or fn.startswith(f"<method '{function}'")
            ),
            default=0.0,
        )
        print(f"{phase:>20}: {total / 3:.3f} s per drawing ({function})")


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--cases", default=CASES)
    parser.add_argument("--checkout", action="append", default=[])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--folder", type=Path, default=Path(tempfile.gettempdir()) / "gridlib-bench-pictures")
    parser.add_argument("--profile")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    cases = args.cases.split(",")
    if args.child:
        child(cases, args.folder, args.repeat)
        return
    build(cases, args.folder)
    if args.profile:
        profile(args.profile, args.folder)
        return
    checkouts = [Path(c).resolve() for c in args.checkout] or [ROOT]
    print(f"load average before: {os.getloadavg()}")
    results: dict[Path, list[dict]] = {c: [] for c in checkouts}
    for _ in range(max(1, args.repeat // 2)):  # alternate: each process draws twice per case
        for checkout in checkouts:
            env = {**os.environ, "PYTHONPATH": str(checkout), "OMP_NUM_THREADS": "1"}
            command = [
                sys.executable,
                __file__,
                "--child",
                "--cases",
                args.cases,
                "--folder",
                str(args.folder),
            ]
            out = subprocess.run(
                [*command, "--repeat", "2"], env=env, check=True, capture_output=True, text=True
            )
            results[checkout].append(json.loads(out.stdout.strip().splitlines()[-1]))
    print(f"load average after: {os.getloadavg()}")
    print("CPU seconds per step, median (min) (" + " | ".join(str(c) for c in checkouts) + ")")
    for name in cases:
        print(f"\n{name}")
        for step in STEPS:
            cells = []
            for checkout in checkouts:
                seconds = [s for run in results[checkout] for s in run[name].get(step, [])]
                cells.append(
                    f"{statistics.median(seconds):6.3f} ({min(seconds):.3f})" if seconds else " " * 14
                )
            print(f"  {step:>20}: " + " | ".join(cells))


if __name__ == "__main__":
    main()
