"""Benchmark: one 1e6-cell case through every stage of the Snakemake workflow.

Run:  .venv/bin/python bench/workflow.py [--case bench/cases/million.yaml] [--keep DIR]

Runs ``snakemake --cores 2`` on the case in a scratch directory (the same
Snakefile and rules as ``make run``), then prints the wall time of the whole run
and every rule's ``benchmark:`` record (results/benchmarks/<case>/<rule>.tsv:
seconds, peak resident memory ``max_rss`` in MiB), and the sizes of the
artifacts. The default case is a faulted anticline, 200 x 200 x 25 corner-point
cells, with random porosity and permeability fields and 1000 METIS blocks.
"""

from __future__ import annotations

import argparse
import csv
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
STAGES = ("horizons", "grid", "geometry", "petrophysics", "coarsen", "export")


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--case", type=Path, default=ROOT / "bench" / "cases" / "million.yaml")
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--keep", type=Path, help="run in this folder and keep the results")
    args = parser.parse_args()
    case = args.case.resolve()
    with tempfile.TemporaryDirectory() as tmp:
        work = args.keep.resolve() if args.keep else Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        command = [
            sys.executable,
            "-m",
            "snakemake",
            "-s",
            str(ROOT / "Snakefile"),
            "--directory",
            str(work),
            "--cores",
            str(args.cores),
            "--config",
            f"cases={case}",
            "studies=[]",  # the case alone, not the sample studies
            "--quiet",
        ]
        t0 = time.perf_counter()
        run = subprocess.run(command, capture_output=True, text=True)
        wall = time.perf_counter() - t0
        if run.returncode != 0:
            sys.exit(f"snakemake failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}")
        name = _case_name(case)
        print(f"{name}: snakemake --cores {args.cores}, every stage: {wall:.1f} s wall (includes start-up)")
        bench = work / "results" / "benchmarks" / name
        total = 0.0
        for tsv in sorted(bench.glob("*.tsv"), key=_stage_order):
            with tsv.open() as f:
                row = next(csv.DictReader(f, delimiter="\t"))
            seconds = float(row["s"])
            total += seconds
            print(f"  {tsv.stem:13s} {seconds:7.2f} s   max_rss {float(row['max_rss']):7.0f} MiB")
        print(f"  {'sum of rules':13s} {total:7.2f} s")
        folder = work / "results" / name
        sizes = ", ".join(f"{p.name} {p.stat().st_size / 2**20:.1f} MiB" for p in sorted(folder.iterdir()))
        print(f"  artifacts: {sizes}")


def _case_name(path: Path) -> str:
    from gridlib.config import load_case

    return load_case(path).name


def _stage_order(path: Path) -> int:
    return STAGES.index(path.stem) if path.stem in STAGES else len(STAGES)


if __name__ == "__main__":
    main()
