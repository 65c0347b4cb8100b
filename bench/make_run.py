"""Benchmark: the wait of ``make run`` (every sample case and study from a clean results folder)
against the same work done in one Python process, for one or more checkouts side by side.

Run:  .venv/bin/python bench/make_run.py [--checkout DIR ...] [--cores 2] [--repeat 1]

Each checkout (default: this one; give the previous commit's as a second, e.g.
``git worktree add /tmp/previous HEAD~1``) runs, in turn and alternating when repeated:

* ``make run``: ``snakemake --cores N --workflow-profile workflow/profiles/default`` with the
  checkout's Snakefile and its gridlib (``PYTHONPATH``), into an empty scratch folder; its wall
  time (parse and start-up included), its jobs and the sum of their wall times (each job's
  ``benchmark:`` file, ``s``);
* in one process: the same work by the library's own functions in a fresh interpreter, timed
  around each call (imports once, before): ``run_case`` of every case, and of every study
  variant (after ``materialise``), each simulated variant's Flow run
  (``simulate_variant``), each study's table (``stage_study``) and the summary table
  (``stage_summary``).

It prints, per checkout, the wall time of ``make run``, the in-process sum, their ratio, and the
per-job overhead: (sum of the jobs' wall times - the in-process sum) / jobs, what a job costs
beyond its work (process start, imports, Snakemake's bookkeeping). The two runs of a checkout
follow each other, and the checkouts alternate, so that all figures of one invocation share the
machine's load (printed before and after: this VM's speed varies by 2x between days).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Timing:
    """One checkout's run: ``make run``'s wall time, its jobs' count and summed wall time, its
    CPU time (Snakemake's process and every process it waited for), and the in-process sum of
    the same work, wall and CPU (seconds)."""

    wall: float
    jobs: int
    job_seconds: float
    cpu: float
    in_process: float
    in_process_cpu: float

    @property
    def ratio(self) -> float:
        return self.wall / self.in_process

    @property
    def overhead(self) -> float:
        """Seconds a job costs beyond its work."""
        return (self.job_seconds - self.in_process) / self.jobs


def _environment(checkout: Path) -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(checkout), env.get("PYTHONPATH", "")]).rstrip(os.pathsep)
    env["PATH"] = os.pathsep.join([str(Path(sys.executable).parent), env.get("PATH", "")])
    return env


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def make_run(checkout: Path, work: Path, cores: int) -> tuple[float, int, float, float]:
    """``make run``'s Snakemake in ``work`` with ``checkout``'s workflow and gridlib: wall
    time, jobs, the sum of the jobs' benchmark seconds, and CPU time."""
    command = [
        sys.executable,
        "-m",
        "snakemake",
        "-s",
        str(checkout / "Snakefile"),
        "--directory",
        str(work),
        "--cores",
        str(cores),
        "--workflow-profile",
        str(checkout / "workflow" / "profiles" / "default"),
        "--quiet",
    ]
    t0, cpu0 = time.perf_counter(), _children_cpu()
    # cwd: `python -m` puts the working directory first on sys.path, before PYTHONPATH: run from a
    # checkout's root, every checkout's Snakemake would import that checkout's gridlib
    run = subprocess.run(command, capture_output=True, text=True, env=_environment(checkout), cwd=work)
    wall, cpu = time.perf_counter() - t0, _children_cpu() - cpu0
    if run.returncode != 0:
        sys.exit(f"{checkout}: snakemake failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}")
    seconds = []
    for tsv in (work / "results" / "benchmarks").rglob("*.tsv"):
        with tsv.open() as f:
            seconds.append(float(next(csv.DictReader(f, delimiter="\t"))["s"]))
    return wall, len(seconds), sum(seconds), cpu


def in_process(checkout: Path, work: Path) -> tuple[float, float]:
    """The in-process sum of the same work, wall and CPU, in a fresh interpreter using ``checkout``'s gridlib
    (this file's :func:`_work_in_this_process`)."""
    command = [sys.executable, str(Path(__file__).resolve()), "--in-process", str(checkout), str(work)]
    run = subprocess.run(command, capture_output=True, text=True, env=_environment(checkout))
    if run.returncode != 0:
        sys.exit(f"{checkout}: the in-process run failed:\n{run.stderr[-3000:]}")
    sums = json.loads(run.stdout.splitlines()[-1])
    return sums["wall"], sums["cpu"]


def _work_in_this_process(checkout: Path, work: Path) -> tuple[float, float]:
    """What ``make run`` does, by the library's functions in this process (the configuration's
    cases and studies of ``checkout``, results under ``work``): seconds spent in them, wall and
    CPU (this process's and OPM Flow's)."""
    import yaml

    from gridlib.config import load_case
    from gridlib.stages import run_case, stage_summary
    from gridlib.stages.study import stage_study
    from gridlib.stages.study_simulate import simulate_variant
    from gridlib.study import load_studies, materialise

    config = yaml.safe_load((checkout / "config" / "config.yaml").read_text())
    results = work / "results"
    cases = sorted(checkout.glob(config["cases"]))
    studies = load_studies(sorted(checkout.glob(config.get("studies", "config/studies/*.yaml"))), results)
    spent = [0.0, 0.0]

    def timed(function, *args, **kwargs):
        t0, cpu0 = time.perf_counter(), time.process_time() + _children_cpu()
        result = function(*args, **kwargs)
        spent[0] += time.perf_counter() - t0
        spent[1] += time.process_time() + _children_cpu() - cpu0
        return result

    summaries = []
    for path in cases:
        case = timed(load_case, path)
        timed(run_case, case, results / case.name)
        summaries.append(results / case.name / "summary.json")
    for study in studies.values():
        materialise(study, results)
        simulated = study.simulation.simulate
        for variant in study.variants:
            folder = study.case_file(results, variant.name).parent
            timed(run_case, study.case_file(results, variant.name), folder)
            if simulated:
                timed(
                    simulate_variant,
                    folder / "flow",
                    folder / "simulation",
                    study_file=str(study.path),
                    variant=variant.name,
                    report_days=[float(d) for d in variant.data["simulation"].get("report_days", [])],
                    times=list(study.simulation.times),
                    water_cut=study.simulation.water_cut,
                    on_failure=study.simulation.on_failure,
                )
        folder = study.folder(results)
        outputs = {"csv": "study.csv", "nc": "study.nc", "png": "study.png"}
        if simulated:
            outputs |= {"profiles": "study_profiles.png", "tornado": "study_tornado.png"}
        timed(
            stage_study,
            folder / "variants.yaml",
            [folder / v.name / "summary.json" for v in study.variants],
            {key: str(folder / name) for key, name in outputs.items()},
            [folder / v.name / "simulation" for v in study.variants] if simulated else [],
        )
    timed(stage_summary, summaries, results / "summary.csv")
    return spent[0], spent[1]


def _load() -> str:
    return " ".join(f"{x:.1f}" for x in os.getloadavg())


def main() -> None:
    if len(sys.argv) == 4 and sys.argv[1] == "--in-process":
        wall, cpu = _work_in_this_process(Path(sys.argv[2]), Path(sys.argv[3]))
        print(json.dumps({"wall": wall, "cpu": cpu}))
        return
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument(
        "--checkout",
        type=Path,
        action="append",
        help="a checkout of the project (repeatable; default: this one)",
    )
    parser.add_argument("--cores", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=1, help="runs of each checkout (alternating)")
    args = parser.parse_args()
    checkouts = [c.resolve() for c in args.checkout or [ROOT]]
    print(f"load average before: {_load()}")
    timings: dict[Path, list[Timing]] = {c: [] for c in checkouts}
    for _ in range(args.repeat):
        for checkout in checkouts:
            with tempfile.TemporaryDirectory() as a, tempfile.TemporaryDirectory() as b:
                wall, jobs, job_seconds, cpu = make_run(checkout, Path(a), args.cores)
                alone, alone_cpu = in_process(checkout, Path(b))
            timing = Timing(wall, jobs, job_seconds, cpu, alone, alone_cpu)
            timings[checkout].append(timing)
            print(
                f"{checkout}: make run {wall:.1f} s wall, {cpu:.1f} s CPU ({jobs} jobs, "
                f"{job_seconds:.1f} job-s); in one process {alone:.1f} s wall, {alone_cpu:.1f} s CPU; "
                f"ratio {timing.ratio:.2f} (CPU {cpu / alone_cpu:.2f}), "
                f"per-job overhead {timing.overhead:.2f} s ({(cpu - alone_cpu) / jobs:.2f} s CPU)",
                flush=True,
            )
    print(f"load average after: {_load()}")
    if args.repeat > 1:
        for checkout, runs in timings.items():
            print(
                f"{checkout}: medians: make run {statistics.median(t.wall for t in runs):.1f} s, "
                f"in one process {statistics.median(t.in_process for t in runs):.1f} s, "
                f"ratio {statistics.median(t.ratio for t in runs):.2f}, "
                f"per-job overhead {statistics.median(t.overhead for t in runs):.2f} s"
            )


if __name__ == "__main__":
    main()
