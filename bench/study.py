"""Benchmark: a study of 48 variants of a small case, against the same variants as case files;
or (``--simulate``) a study of 24 variants, each simulated in OPM Flow.

Run:  .venv/bin/python bench/study.py [--base config/cases/faulted_pebi.yaml] [--cores 2]
                                     [--modes study,spawned,cases] [--keep DIR]
      .venv/bin/python bench/study.py --simulate [--base config/cases/waterflood_pebi.yaml]
                                     [--cores 2] [--keep DIR]

The study varies the base case's cell size (8 values from its own up, about 4,300 to 4,900
cells for faulted_pebi) and its first fault's throw (2 values), 3 realisations each: 48
variants. Each mode runs ``snakemake --cores 2`` in a scratch directory and prints the wall
time of the whole run (start-up and parse included) and per variant:

* ``study``: the study, each variant one job in the warm worker processes of the Snakemake
  process (``--force-use-threads``, as workflow/profiles/default);
* ``spawned``: the study without it: Snakemake spawns a process per variant job, which parses
  the workflow and imports gridlib, xarray, gstools, VTK and matplotlib again;
* ``cases``: the same 48 variants as 48 case files (the variants' own case files, renamed),
  through the per-stage rules: up to 7 jobs, 7 Python processes per case.

``--simulate``: a simulated study (``simulate: true``) of the PEBI waterflood sample case with
cell sizes 24, 26, 28 and 30 m (about 6,200 to 4,000 cells, 5,000 on average) and its first
fault's throw and twice it, 3 realisations each: 24 variants, each a grid job (every stage,
the deck included) and a Flow job (one thread), ``snakemake --cores 2`` with
workflow/profiles/default (as ``make run``). It prints the wall time of the whole run and, per
variant, the grid job's and the Flow job's wall time (Snakemake's benchmark files
``results/benchmarks/<study>/<variant>.tsv`` and ``<variant>.simulation.tsv``) and Flow's own
(``Total time`` in its PRT file), with the machine's load average before and after, and the
CPU time of Snakemake and Flow per variant (not that of the warm workers: ``--cpu``).

Side by side (the machine's speed varies): ``--checkout DIR`` (repeatable) runs the study with
DIR's Snakefile and gridlib (``PYTHONPATH``), e.g. the previous commit's worktree, and
``DIR:no-pictures`` the same with the study's ``pictures: false`` (no PNG of the variants'
own); ``--repeat N`` runs the list N times, alternating, then prints each one's runs.

``--simulate --cpu``: where the CPU of a variant goes, robust to a loaded machine: per checkout
(``--checkout``, alternating, ``--repeat`` times), one warm Python process (the workers'
imports done) builds every third variant of the simulated study (8 of 24: each cell size and
throw, realisation 0) with ``gridlib.stages.run_case`` on one thread (``GRIDLIB_NUM_THREADS=1``,
as the workers build a variant), after one warm-up variant, and runs its deck in OPM Flow; it
prints the median CPU seconds of each stage, of run_case and of Flow (its process's user +
system time).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
MODES = ("study", "spawned", "cases")
SIMULATED_BASE = ROOT / "config" / "cases" / "waterflood_pebi.yaml"
SIMULATED_CELL_SIZES = [24, 26, 28, 30]  # m: about 6,200, 5,300, 4,600 and 4,000 cells


def _snakemake(work: Path, *args: str, checkout: Path = ROOT) -> float:
    command = [sys.executable, "-m", "snakemake", "-s", str(checkout / "Snakefile"), "--directory", str(work)]
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(checkout), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    t0 = time.perf_counter()
    # cwd: `python -m` puts the working directory first on sys.path, before PYTHONPATH: run from a
    # checkout's root, every checkout's Snakemake would import that checkout's gridlib
    run = subprocess.run([*command, *args, "--quiet"], capture_output=True, text=True, env=env, cwd=work)
    wall = time.perf_counter() - t0
    if run.returncode != 0:
        sys.exit(f"snakemake failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}")
    return wall


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument(
        "--base", type=Path, help="the base case (default faulted_pebi; --simulate: waterflood_pebi)"
    )
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--modes", default=",".join(MODES), help="comma-separated, of " + ", ".join(MODES))
    parser.add_argument("--keep", type=Path, help="run in this folder and keep the results")
    parser.add_argument("--simulate", action="store_true", help="the 24-variant simulated study")
    parser.add_argument(
        "--checkout",
        action="append",
        help="--simulate: a checkout to run (repeatable; DIR:no-pictures with pictures: false)",
    )
    parser.add_argument("--repeat", type=int, default=1, help="--simulate: runs of each checkout")
    parser.add_argument("--cpu", action="store_true", help="--simulate: CPU per variant and stage")
    parser.add_argument("--in-process", nargs=2, help=argparse.SUPPRESS)  # --cpu's worker
    args = parser.parse_args()
    if args.in_process:
        _cpu_in_process(Path(args.in_process[0]), args.in_process[1] == "pictures")
        return
    if args.simulate and args.cpu:
        runs = [_run_spec(text) for text in args.checkout or [str(ROOT)]]
        cpu_study((args.base or SIMULATED_BASE).resolve(), runs, args.repeat)
        return
    if args.simulate:
        runs = [_run_spec(text) for text in args.checkout or [str(ROOT)]]
        base = (args.base or SIMULATED_BASE).resolve()
        results: dict[str, list[dict]] = {}
        for repeat in range(args.repeat):
            for label, checkout, pictures in runs:
                keep = (
                    args.keep / f"{repeat}_{len(results.get(label, []))}_{checkout.name}"
                    if args.keep
                    else None
                )
                print(f"== {label} (run {repeat + 1})", flush=True)
                results.setdefault(label, []).append(simulated(base, args.cores, keep, checkout, pictures))
        if len(runs) > 1 or args.repeat > 1:
            print("== side by side (wall per variant; CPU per variant; load average before the run)")
            for label, figures in results.items():
                print(
                    f"{label:40s} "
                    + ", ".join(
                        f"{f['per_variant']:.2f} s ({f['cpu'] / f['n']:.2f} s CPU, load {f['load']:.1f})"
                        for f in figures
                    )
                )
        return
    base = (args.base or ROOT / "config" / "cases" / "faulted_pebi.yaml").resolve()
    data = yaml.safe_load(base.read_text())
    size = float(data["grid"]["cell_size"])
    throw = data["faults"][0]["throw"]
    study = {
        "name": "bench_study",
        "base": str(base),
        "vary": {
            "grid.cell_size": [round(size * (1 + 0.02 * k), 1) for k in range(8)],
            "faults.0.throw": [throw, 2 * throw],
        },
        "realisations": 3,
        "seed": 1,
    }
    cores = ["--cores", str(args.cores)]
    with tempfile.TemporaryDirectory() as tmp:
        top = args.keep.resolve() if args.keep else Path(tmp)
        top.mkdir(parents=True, exist_ok=True)
        study_file = top / "bench_study.yaml"
        study_file.write_text(yaml.safe_dump(study, sort_keys=False))
        walls = {}
        for mode in args.modes.split(","):
            work = top / mode
            shutil.rmtree(work, ignore_errors=True)
            work.mkdir()
            if mode == "study":
                config = ["--config", "cases=[]", f"studies={study_file}"]
                walls[mode] = _snakemake(work, *cores, "--force-use-threads", *config)
            elif mode == "spawned":
                walls[mode] = _snakemake(work, *cores, "--config", "cases=[]", f"studies={study_file}")
            elif mode == "cases":
                # The variants' own case files, written by a dry run, as 48 case files.
                _snakemake(work, *cores, "--config", "cases=[]", f"studies={study_file}", "--dry-run")
                cases = work / "cases"
                cases.mkdir()
                for case in sorted((work / "results" / "bench_study").glob("*/*.yaml")):
                    shutil.copy(case, cases / case.name)
                shutil.rmtree(work / "results")
                walls[mode] = _snakemake(work, *cores, "--config", f"cases={cases}/*.yaml", "studies=[]")
            else:
                sys.exit(f"unknown mode {mode!r} (one of {', '.join(MODES)})")
            cells = _cells(work)
            print(
                f"{mode:8s} 48 variants ({cells}), --cores {args.cores}: {walls[mode]:6.1f} s wall, "
                f"{walls[mode] / 48:5.2f} s per variant",
                flush=True,
            )
        if "study" in walls and "cases" in walls:
            print(f"study vs separate case files: {walls['cases'] / walls['study']:.1f}x faster")


def _run_spec(text: str) -> tuple[str, Path, bool]:
    """``DIR`` or ``DIR:no-pictures``: its label, the checkout and whether the variants draw pictures."""
    folder, _, option = text.partition(":")
    if option not in ("", "no-pictures"):
        sys.exit(f"--checkout {text}: the option after ':' is no-pictures or nothing")
    checkout = Path(folder).resolve()
    if not (checkout / "Snakefile").is_file():
        sys.exit(f"--checkout {text}: no Snakefile in {checkout}")
    return text, checkout, option != "no-pictures"


def simulated_study(base: Path, pictures: bool = True) -> dict:
    """The simulated study's file (the module's docstring): ``base``'s cell sizes
    :data:`SIMULATED_CELL_SIZES` and its first fault's throw and twice it, 3 realisations."""
    throw = yaml.safe_load(base.read_text())["faults"][0]["throw"]
    study = {
        "name": "bench_simulated",
        "base": str(base),
        "vary": {"grid.cell_size": SIMULATED_CELL_SIZES, "faults.0.throw": [throw, 2 * throw]},
        "realisations": 3,
        "seed": 1,
        "simulate": True,
    }
    if not pictures:
        study["pictures"] = False
    return study


def simulated(
    base: Path, cores: int, keep: Path | None, checkout: Path = ROOT, pictures: bool = True
) -> dict:
    """The simulated study (the module's docstring) with ``checkout``'s workflow and gridlib
    (``pictures``: the study's key): prints the whole run and the grid and Flow time per
    variant; returns the run's figures."""
    study = simulated_study(base, pictures)
    with tempfile.TemporaryDirectory() as tmp:
        top = keep.resolve() if keep else Path(tmp)
        work = top / "simulated"
        shutil.rmtree(work, ignore_errors=True)
        work.mkdir(parents=True)
        study_file = top / "bench_simulated.yaml"
        study_file.write_text(yaml.safe_dump(study, sort_keys=False))
        load = os.getloadavg()[0]
        config = ["--config", "cases=[]", f"studies={study_file}"]
        profile = ["--workflow-profile", str(checkout / "workflow" / "profiles" / "default")]  # as make run
        cpu = _children_cpu()
        wall = _snakemake(work, "--cores", str(cores), *profile, *config, checkout=checkout)
        cpu = _children_cpu() - cpu
        rows = _simulated_rows(work / "results", study["name"])
        after = os.getloadavg()[0]
        print(f"{checkout} (pictures: {str(pictures).lower()})")
        print(f"load average {load:.1f} before, {after:.1f} after (1 min; {os.cpu_count()} cores)")
        print(f"{'variant':34s} {'cells':>6s} {'grid job':>9s} {'Flow job':>9s} {'Flow':>7s} status")
        for r in rows:
            print(
                f"{r['variant']:34s} {r['cells']:6d} {r['grid']:8.2f}s {r['flow_job']:8.2f}s "
                f"{r['flow']:6.2f}s {r['status']}"
            )
        n = len(rows)
        for name, key in (("grid job", "grid"), ("Flow job", "flow_job"), ("Flow itself", "flow")):
            values = [r[key] for r in rows]
            print(
                f"{name:12s} per variant: mean {statistics.fmean(values):5.2f} s, median "
                f"{statistics.median(values):5.2f} s, sum {sum(values):6.1f} s"
            )
        cells = [r["cells"] for r in rows]
        print(
            f"simulated study: {n} variants ({min(cells):,d} to {max(cells):,d} cells, mean "
            f"{statistics.fmean(cells):,.0f}), --cores {cores}: {wall:6.1f} s wall, "
            f"{wall / n:5.2f} s per variant; {cpu:6.1f} s CPU (Snakemake and Flow; not the warm workers), "
            f"{cpu / n:5.2f} s per variant",
            flush=True,
        )
        return {"n": n, "wall": wall, "per_variant": wall / n, "cpu": cpu, "load": load}


def cpu_study(base: Path, runs: list[tuple[str, Path, bool]], repeat: int) -> None:
    """``--simulate --cpu`` (the module's docstring): each of ``runs`` in a process of its own,
    alternating, ``repeat`` times."""
    with tempfile.TemporaryDirectory() as tmp:
        study_file = Path(tmp) / "bench_simulated.yaml"
        study = simulated_study(base)
        study_file.write_text(yaml.safe_dump(study, sort_keys=False))
        for r in range(repeat):
            for label, checkout, pictures in runs:
                env = dict(os.environ)
                env["PYTHONPATH"] = os.pathsep.join([str(checkout), env.get("PYTHONPATH", "")]).rstrip(
                    os.pathsep
                )
                load = os.getloadavg()[0]
                command = [sys.executable, str(Path(__file__).resolve()), "--in-process", str(study_file)]
                command.append("pictures" if pictures else "no-pictures")
                run = subprocess.run(command, capture_output=True, text=True, env=env, cwd=tmp)
                if run.returncode != 0:
                    sys.exit(f"{label}: failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}")
                print(f"== {label} (run {r + 1}; load average {load:.1f} before)\n{run.stdout}", flush=True)


def _cpu_in_process(study_file: Path, pictures: bool) -> None:
    """``--cpu``'s worker: this process's gridlib (PYTHONPATH) builds and simulates every third
    variant of ``study_file`` (its case files written under ./results), warm; prints medians."""
    import contextlib
    import importlib

    import gridlib.stages.pipeline as pipeline
    from gridlib.stages.workers import PRELOAD
    from gridlib.study import load_study, materialise

    for module in PRELOAD:  # the warm workers' imports (an older checkout's list may name absent ones)
        with contextlib.suppress(ImportError):
            importlib.import_module(module)
    os.environ["GRIDLIB_NUM_THREADS"] = "1"  # as a worker runs a variant (run_logged, threads=1)
    study = load_study(study_file, "results")
    materialise(study, "results")
    stages: dict[str, list[float]] = {}
    call = pipeline._call

    def timed(stage, case, paths):
        start = time.process_time()
        try:
            return call(stage, case, paths)
        finally:
            stages.setdefault(stage.name, []).append(time.process_time() - start)

    pipeline._call = timed
    variants = study.variants[::3]
    totals, flows = [], []
    for k, variant in enumerate([variants[-1], *variants]):  # the first: warm-up, not counted
        case_file = study.case_file("results", variant.name)
        if not pictures:
            data = yaml.safe_load(case_file.read_text())
            data["outputs"] = {**data.get("outputs", {}), "pictures": False}
            case_file.write_text(yaml.safe_dump(data, sort_keys=False))
        folder = Path("results") / f"run{k}" / variant.name
        start = time.process_time()
        pipeline.run_case(case_file, folder)
        if k == 0:
            stages.clear()
            continue
        totals.append(time.process_time() - start)
        deck = next((folder / "flow").glob("*.DATA"))
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        subprocess.run(
            [
                "flow",
                "--threads-per-process=1",
                "--enable-async-ecl-output=false",
                f"--output-dir={folder / 'sim'}",
                deck.name,
            ],
            cwd=deck.parent,
            capture_output=True,
            check=True,
        )
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        flows.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
    n = len(totals)
    print(f"{n} variants, pictures: {str(pictures).lower()}; median CPU seconds per variant:")
    for name, values in stages.items():
        print(f"  {name:18s} {statistics.median(values):6.3f}")
    grid, flow = statistics.median(totals), statistics.median(flows)
    for name, value in (("run_case", grid), ("OPM Flow", flow), ("variant", grid + flow)):
        print(f"  {name:18s} {value:6.3f}")


def _children_cpu() -> float:
    """CPU seconds of the processes this one has waited for (Snakemake and what it waited for:
    Flow, not the warm workers, whose fork server nobody waits for; ``--cpu`` counts those)."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _simulated_rows(results: Path, name: str) -> list[dict]:
    """Per variant: its cells, the wall time of its grid job and Flow job (Snakemake's benchmark
    files) and Flow's own (the PRT's ``Total time``), and the simulation's status."""
    rows = []
    for summary in sorted((results / name).glob("*/summary.json")):
        variant = summary.parent.name
        bench = results / "benchmarks" / name
        prt = next((summary.parent / "simulation").glob("*.PRT"), None)
        found = re.findall(r"Total time \(seconds\):\s*([0-9.]+)", prt.read_text()) if prt else []
        responses = json.loads((summary.parent / "simulation" / "responses.json").read_text())
        rows.append(
            {
                "variant": variant,
                "cells": json.loads(summary.read_text())["cells"],
                "grid": _benchmark_seconds(bench / f"{variant}.tsv"),
                "flow_job": _benchmark_seconds(bench / f"{variant}.simulation.tsv"),
                "flow": float(found[-1]) if found else float("nan"),
                "status": responses["status"],
            }
        )
    return rows


def _benchmark_seconds(path: Path) -> float:
    """The wall time (s) a Snakemake benchmark file records (its column ``s``)."""
    header, values = path.read_text().splitlines()[:2]
    return float(dict(zip(header.split("\t"), values.split("\t"), strict=True))["s"])


def _cells(work: Path) -> str:
    import json

    counts = [json.loads(p.read_text())["cells"] for p in (work / "results").glob("**/summary.json")]
    return f"{min(counts):,d} to {max(counts):,d} cells" if counts else "no summaries"


if __name__ == "__main__":
    main()
