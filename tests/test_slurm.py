"""The workflow on a real SLURM cluster, through workflow/profiles/slurm as shipped.

Two small sample cases run once locally (two cores) and once on the cluster of the
``slurm_cluster`` fixture (a single-node SLURM started for the session, tests/slurm_cluster.py),
from the same case files. The SLURM run must have submitted its jobs to SLURM (their ids in
Snakemake's log, each COMPLETED in the cluster's job completion log), one job per case (the
profile groups a case's stages) and one for the summary table, and its results must equal
the local run's bit for bit: every variable and attribute of every netCDF file, the VTU/VTP
files and summary.json. The wall times per case are printed beside each other.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest
from artifacts import assert_same_files

ROOT = Path(__file__).resolve().parents[1]
PROFILE = ROOT / "workflow" / "profiles" / "slurm"
CASES = ("ellipsoid", "twisted")

SUBMITTED = re.compile(r"submitted with SLURM jobid (\d+)")


def _snakemake(workdir: Path, cases: Path, *args: str, env: dict[str, str] | None = None) -> dict:
    """Run the workflow on ``cases`` in ``workdir``: its log, wall time and when each case was done."""
    start = time.time()
    res = subprocess.run(
        [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(workdir)]
        + ["--config", f"cases={cases}/*.yaml", *args],
        capture_output=True,
        text=True,
        env=env,
        timeout=900,
    )
    wall = time.time() - start
    log = res.stdout + res.stderr
    (workdir / "snakemake.log").write_text(log)
    assert res.returncode == 0, f"snakemake failed, log {workdir / 'snakemake.log'}:\n{log[-4000:]}"
    done = {case: (workdir / "results" / case / "summary.json").stat().st_mtime - start for case in CASES}
    return {"log": log, "wall": wall, "done": done, "results": workdir / "results"}


@pytest.fixture(scope="module")
def runs(slurm_cluster, tmp_path_factory):
    base = tmp_path_factory.mktemp("slurm_workflow")
    cases = base / "cases"  # one copy for both runs: the files record the case file's path
    cases.mkdir()
    for case in CASES:
        shutil.copy(ROOT / "config" / "cases" / f"{case}.yaml", cases)
    local = _snakemake(base / "local", cases, "--cores", "2")
    on_slurm = _snakemake(base / "slurm", cases, "--workflow-profile", str(PROFILE), env=slurm_cluster.env)
    return local, on_slurm


def test_every_job_ran_as_a_completed_slurm_job(runs, slurm_cluster):
    _, on_slurm = runs
    log = on_slurm["log"]
    ids = SUBMITTED.findall(log)
    # The profile groups each case's stages into one job; the summary table is one more.
    assert len(ids) == len(CASES) + 1, log[-3000:]
    assert "group_case_" in log
    states = slurm_cluster.job_states(ids)
    where = slurm_cluster.log("jobcomp") if slurm_cluster.started else "scontrol show job"
    assert states == dict.fromkeys(ids, "COMPLETED"), f"{where}: {states}"
    # Only the target rule `all` ran in this process; every stage ran inside a SLURM job.
    assert re.findall(r"^localrule (\w+):", log, re.MULTILINE) == ["all"]


@pytest.mark.parametrize("case", CASES)
def test_slurm_results_equal_the_local_ones_bit_for_bit(runs, case):
    local, on_slurm = runs
    assert_same_files(local["results"] / case, on_slurm["results"] / case)
    assert (local["results"] / "summary.csv").read_text() == (on_slurm["results"] / "summary.csv").read_text()


def test_wall_times_local_and_on_slurm(runs, slurm_cluster, capsys):
    local, on_slurm = runs
    cluster = f"started in {slurm_cluster.start_seconds:.1f} s" if slurm_cluster.started else "running"
    jobs = len(SUBMITTED.findall(on_slurm["log"]))
    lines = [
        f"SLURM cluster {cluster}; {jobs} SLURM jobs through {PROFILE.relative_to(ROOT)}",
        f"{'case':<12}{'local (s)':>11}{'SLURM (s)':>11}   (from the run's start to the case's summary.json)",
    ]
    lines += [f"{case:<12}{local['done'][case]:>11.1f}{on_slurm['done'][case]:>11.1f}" for case in CASES]
    lines.append(f"{'whole run':<12}{local['wall']:>11.1f}{on_slurm['wall']:>11.1f}")
    with capsys.disabled():
        print("\n" + "\n".join(lines))
    assert all(t > 0 for t in on_slurm["done"].values())
