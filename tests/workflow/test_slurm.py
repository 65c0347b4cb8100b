"""The workflow on a real SLURM cluster, through workflow/profiles/slurm as shipped.

Two small sample cases and a small simulated study (two variants of a 48-cell waterflood, each
simulated in OPM Flow) run once locally (two cores) and once on the cluster of the
``slurm_cluster`` fixture (a single-node SLURM started for the session, tests/slurm_cluster.py),
from the same case and study files. The SLURM run must
have submitted its jobs to SLURM (their ids in Snakemake's log, each COMPLETED in the cluster's
job completion log), one job per case (the profile groups a case's stages), one for the summary
table, one per variant of the study and one per variant's Flow run, one for the study's table,
and its results must equal the local run's bit for bit: every variable and attribute of every
netCDF file, the VTU/VTP files and summary.json, each variant's Flow summary (UNSMRY) and
responses.json, study.csv and study.nc. The wall times per case and per variant are
printed beside each other.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml
from artifacts import assert_same_files
from simulated_study import BASE

ROOT = Path(__file__).resolve().parents[2]
PROFILE = ROOT / "workflow" / "profiles" / "slurm"
CASES = ("ellipsoid", "twisted")
# A simulated study of a 48-cell waterflood: no throw and 15 m (one realisation each), each
# variant's deck through OPM Flow as a SLURM job of its own.
STUDY = {"name": "flood", "base": "../bases/tiny_flood.yaml", "vary": {"faults.0.throw": [0, 15]}}
STUDY |= {"simulate": True, "responses": {"times": [200]}}
STUDY |= {"pictures": False}  # the variants' PNGs are not compared; the cases' are drawn on SLURM
VARIANTS = ("throw-0_r0", "throw-15_r0")

SUBMITTED = re.compile(r"submitted with SLURM jobid (\d+)")


def _snakemake(workdir: Path, cases: Path, *args: str, env: dict[str, str] | None = None) -> dict:
    """Run the workflow on ``cases`` in ``workdir``: its log, wall time and when each case was done."""
    start = time.time()
    res = subprocess.run(
        [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(workdir)]
        + ["--config", f"cases={cases}/*.yaml", f"studies={cases.parent / 'studies'}/*.yaml", *args],
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
    study = workdir / "results" / "flood"
    done |= {v: (study / v / "summary.json").stat().st_mtime - start for v in VARIANTS}
    done |= {
        f"{v} Flow": (study / v / "simulation" / "responses.json").stat().st_mtime - start for v in VARIANTS
    }
    return {"log": log, "wall": wall, "done": done, "results": workdir / "results"}


@pytest.fixture(scope="module")
def runs(slurm_cluster, tmp_path_factory):
    base = tmp_path_factory.mktemp("slurm_workflow")
    cases = base / "cases"  # one copy for both runs: the files record the case file's path
    cases.mkdir()
    for case in CASES:
        shutil.copy(ROOT / "config" / "cases" / f"{case}.yaml", cases)
    (base / "studies").mkdir()
    (base / "studies" / "flood.yaml").write_text(yaml.safe_dump(STUDY, sort_keys=False))
    (base / "bases").mkdir()  # the study's base case, not one of the run's cases
    (base / "bases" / "tiny_flood.yaml").write_text(yaml.safe_dump(BASE, sort_keys=False))
    local = _snakemake(base / "local", cases, "--cores", "2", "--force-use-threads", "--scheduler", "greedy")
    on_slurm = _snakemake(base / "slurm", cases, "--workflow-profile", str(PROFILE), env=slurm_cluster.env)
    return local, on_slurm


def test_every_job_ran_as_a_completed_slurm_job(runs, slurm_cluster):
    _, on_slurm = runs
    log = on_slurm["log"]
    ids = SUBMITTED.findall(log)
    # The profile groups each case's stages into one job; the summary table is one more; each
    # variant of the study is one job (all its stages in one process) and its Flow run one more
    # (one thread), the study's table one more.
    assert len(ids) == len(CASES) + 1 + 2 * len(VARIANTS) + 1, log[-3000:]
    for rule in ("study_flood", "study_simulate_flood"):
        assert len(re.findall(rf"^\s*rule {rule}:", log, re.MULTILINE)) == len(VARIANTS), log[-3000:]
    assert "group_case_" in log
    states = slurm_cluster.job_states(ids)
    where = slurm_cluster.log("jobcomp") if slurm_cluster.started else "scontrol show job"
    assert states == dict.fromkeys(ids, "COMPLETED"), f"{where}: {states}"
    # Only the target rule `all` ran in this process; every stage ran inside a SLURM job.
    assert re.findall(r"^localrule (\w+):", log, re.MULTILINE) == ["all"]


@pytest.mark.parametrize("case", CASES + tuple(f"flood/{v}" for v in VARIANTS))
def test_slurm_results_equal_the_local_ones_bit_for_bit(runs, case):
    """The stage jobs ran in a job server (gridlib/stages/job_server.py): the local run's, and
    on SLURM one on the node for each case's job (its first stage job started it): the same
    files as the local run's."""
    local, on_slurm = runs
    if "/" not in case:
        served = [(run["results"] / "logs" / case / "grid.log").read_text() for run in runs]
        assert ["run in the job server" in log for log in served] == [True, True]
    assert_same_files(local["results"] / case, on_slurm["results"] / case)
    if "/" in case:  # Flow's summary and the responses, bit for bit (Flow ran with one thread)
        variant = case.split("/")[1]
        for name in ("responses.json", f"{variant.upper()}.UNSMRY"):
            one, two = (run["results"] / case / "simulation" / name for run in runs)
            assert one.read_bytes() == two.read_bytes(), name
        assert '"status": "ok"' in (local["results"] / case / "simulation" / "responses.json").read_text()
    for table in ("summary.csv", "flood/study.csv"):
        assert (local["results"] / table).read_text() == (on_slurm["results"] / table).read_text()
    assert_same_files(local["results"] / "flood", on_slurm["results"] / "flood")  # study.nc


def test_wall_times_local_and_on_slurm(runs, slurm_cluster, capsys):
    local, on_slurm = runs
    cluster = f"started in {slurm_cluster.start_seconds:.1f} s" if slurm_cluster.started else "running"
    jobs = len(SUBMITTED.findall(on_slurm["log"]))
    lines = [
        f"SLURM cluster {cluster}; {jobs} SLURM jobs through {PROFILE.relative_to(ROOT)}",
        f"{'':<18}{'local (s)':>11}{'SLURM (s)':>11}   (from the run's start to the summary.json;"
        " Flow: to the variant's responses.json)",
    ]
    lines += [
        f"{case:<18}{local['done'][case]:>11.1f}{on_slurm['done'][case]:>11.1f}" for case in local["done"]
    ]
    lines.append(f"{'whole run':<18}{local['wall']:>11.1f}{on_slurm['wall']:>11.1f}")
    with capsys.disabled():
        print("\n" + "\n".join(lines))
    assert all(t > 0 for t in on_slurm["done"].values())
