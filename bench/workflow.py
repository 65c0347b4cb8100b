"""Benchmark: one 1e6-cell case through every stage of the Snakemake workflow.

Run:  .venv/bin/python bench/workflow.py [--case bench/cases/million.yaml] [--keep DIR]

Runs ``snakemake --cores 2`` on the case in a scratch directory (the same
Snakefile and rules as ``make run``), then prints the wall time of the whole run
and every rule's ``benchmark:`` record (results/benchmarks/<case>/<rule>.tsv:
seconds, and the peak resident memory in MiB: the stage's process's high-water mark during the
stage as its log records it, else the record's ``max_rss``, the job's process's own peak), and
the sizes of the artifacts. The default case is a faulted anticline, 200 x 200 x 25 corner-point
cells, with random porosity and permeability fields and 1000 METIS blocks.
"""

from __future__ import annotations

import argparse
import csv
import re
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from gridlib import artifacts

ROOT = Path(__file__).resolve().parents[1]
STAGES = tuple(stage.name for stage in artifacts.STAGES)


@dataclass(frozen=True)
class WorkflowRun:
    """One case through every stage: wall time, each rule's (seconds, peak RSS in MiB) and
    the artifacts' sizes in bytes (files of the case folder and of its flow/ deck)."""

    name: str
    wall: float
    rules: dict[str, tuple[float, float]]
    sizes: dict[str, int]


def run_workflow(case: Path, work: Path, cores: int = 2) -> WorkflowRun:
    """``snakemake --cores`` on ``case`` alone in ``work`` (the repository's Snakefile)."""
    command = [
        sys.executable,
        "-m",
        "snakemake",
        "-s",
        str(ROOT / "Snakefile"),
        "--directory",
        str(work),
        "--cores",
        str(cores),
        "--config",
        f"cases={case}",
        "studies=[]",  # the case alone, not the sample studies
        "job_server=false",  # each stage in its own process: its peak memory is the stage's alone
        "--quiet",
    ]
    t0 = time.perf_counter()
    run = subprocess.run(command, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if run.returncode != 0:
        sys.exit(f"snakemake failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}")
    name = _case_name(case)
    rules = {}
    for tsv in sorted((work / "results" / "benchmarks" / name).glob("*.tsv"), key=_stage_order):
        with tsv.open() as f:
            row = next(csv.DictReader(f, delimiter="\t"))
        log = work / "results" / "logs" / name / f"{tsv.stem}.log"
        peak = _logged_peak(log) or float(row["max_rss"])
        rules[tsv.stem.split(".")[0]] = (float(row["s"]), peak)
    folder = work / "results" / name
    sizes = {str(p.relative_to(folder)): p.stat().st_size for p in sorted(folder.rglob("*")) if p.is_file()}
    return WorkflowRun(name, wall, rules, sizes)


def _logged_peak(log: Path) -> float | None:
    """The peak resident memory (MiB) the stage's log ends with (its process's high-water mark
    while the stage ran, gridlib.stages.job_usage); the benchmark record's max_rss (the job's
    whole process) is the fallback."""
    if not log.is_file():
        return None
    found = re.findall(r"peak memory (\d+) MiB", log.read_text())
    return float(found[-1]) if found else None


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--case", type=Path, default=ROOT / "bench" / "cases" / "million.yaml")
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--keep", type=Path, help="run in this folder and keep the results")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        work = args.keep.resolve() if args.keep else Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        run = run_workflow(args.case.resolve(), work, args.cores)
    print(
        f"{run.name}: snakemake --cores {args.cores}, every stage: {run.wall:.1f} s wall (includes start-up)"
    )
    for rule, (seconds, rss) in run.rules.items():
        print(f"  {rule:16s} {seconds:7.2f} s   max_rss {rss:7.0f} MiB")
    print(f"  {'sum of rules':16s} {sum(s for s, _ in run.rules.values()):7.2f} s")
    sizes = ", ".join(f"{name} {size / 2**20:.1f} MiB" for name, size in run.sizes.items())
    print(f"  artifacts ({sum(run.sizes.values()) / 2**20:.0f} MiB): {sizes}")


def _case_name(path: Path) -> str:
    from gridlib.config import load_case

    return load_case(path).name


def _stage_order(path: Path) -> int:
    stage = path.stem.split(".")[0]
    return STAGES.index(stage) if stage in STAGES else len(STAGES)


if __name__ == "__main__":
    main()
