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

import json
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

ROOT = Path(__file__).resolve().parents[1]
PROFILE = ROOT / "workflow" / "profiles" / "slurm"
CASES = ("ellipsoid", "twisted")
COMPARED_SUFFIXES = (".nc", ".grdecl", ".vtu", ".vtp", ".json")
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


def _assert_same_files(first: Path, second: Path) -> None:
    """Every variable and attribute of every netCDF file, and the other files, identical."""
    names = sorted(p.name for p in first.iterdir() if p.suffix in COMPARED_SUFFIXES)
    assert names == sorted(p.name for p in second.iterdir() if p.suffix in COMPARED_SUFFIXES)
    for name in names:
        where = f"{first.name}/{name}"
        if name.endswith(".nc"):
            with xr.open_dataset(first / name) as a, xr.open_dataset(second / name) as b:
                assert sorted(a.variables) == sorted(b.variables), where
                assert a.attrs.keys() == b.attrs.keys(), where
                for key, value in a.attrs.items():
                    assert np.array_equal(value, b.attrs[key]), f"{where}: attribute {key}"
                for var in a.variables:
                    u, v = a[var].values, b[var].values
                    assert u.dtype == v.dtype and u.shape == v.shape, f"{where}: {var}"
                    same = u.tobytes() == v.tobytes() if u.dtype.kind != "O" else np.array_equal(u, v)
                    assert same, f"{where}: {var}: {np.count_nonzero(u != v)} of {u.size} values differ"
                    assert a[var].attrs.keys() == b[var].attrs.keys(), f"{where}: {var}"
        elif name.endswith(".json"):
            assert json.loads((first / name).read_text()) == json.loads((second / name).read_text()), where
        else:
            assert (first / name).read_bytes() == (second / name).read_bytes(), where


@pytest.mark.parametrize("case", CASES)
def test_slurm_results_equal_the_local_ones_bit_for_bit(runs, case):
    local, on_slurm = runs
    _assert_same_files(local["results"] / case, on_slurm["results"] / case)
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
