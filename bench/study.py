"""Benchmark: a study of 48 variants of a small case, against the same variants as case files.

Run:  .venv/bin/python bench/study.py [--base config/cases/faulted_pebi.yaml] [--cores 2]
                                     [--modes study,spawned,cases] [--keep DIR]

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
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[1]
MODES = ("study", "spawned", "cases")


def _snakemake(work: Path, *args: str) -> float:
    command = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(work)]
    t0 = time.perf_counter()
    run = subprocess.run([*command, *args, "--quiet"], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if run.returncode != 0:
        sys.exit(f"snakemake failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}")
    return wall


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--base", type=Path, default=ROOT / "config" / "cases" / "faulted_pebi.yaml")
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--modes", default=",".join(MODES), help="comma-separated, of " + ", ".join(MODES))
    parser.add_argument("--keep", type=Path, help="run in this folder and keep the results")
    args = parser.parse_args()
    base = args.base.resolve()
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


def _cells(work: Path) -> str:
    import json

    counts = [json.loads(p.read_text())["cells"] for p in (work / "results").glob("**/summary.json")]
    return f"{min(counts):,d} to {max(counts):,d} cells" if counts else "no summaries"


if __name__ == "__main__":
    main()
