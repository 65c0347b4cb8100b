"""gridlib.stages.job_server: stage jobs handed to a warm process write what they write in their
own process, fail as they fail there, and stop when their job's process is stopped.

One server for the module (the stages' modules preloaded, plus a plugin stage that naps); each
job is a small script run as Snakemake runs a stage rule's script (a new Python process with the
server named in its environment, or not). The workflow's own runs go through the server too:
tests/workflow (every sample case, against the golden summaries; the SLURM run, whose jobs run in
their own processes, bit for bit against the local one).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
import yaml
from artifacts import assert_same_files

from gridlib.stages.job_server import PYTHON_ENV, SERVER_ENV, StageJob, start_server

ROOT = Path(__file__).resolve().parents[2]

# A plugin stage that starts a subprocess, writes both process ids and waits for it.
NAP_STAGE = """
import os, subprocess
from pathlib import Path

from gridlib.artifacts import Artifact, Stage, register_stage


def stage_nap(case, *, grid, nap):
    sleeper = subprocess.Popen(["sleep", "60"])
    Path(f"{nap}.pids").write_text(f"{os.getpid()} {sleeper.pid}")
    sleeper.wait()


register_stage(Stage("nap", stage_nap, ("grid",), (Artifact("nap", "nap.txt"),)), after="geometry")
"""

CASE = {"name": "toy", "grid": {"type": "cartesian", "dims": [4, 3, 2], "lengths": [40.0, 30.0, 4.0]}}

# A job's script: the job given as JSON, then whether this process imported the stages itself.
SCRIPT = textwrap.dedent(
    """
    import json, sys
    from gridlib.stages.job_server import StageJob, run_job
    code = run_job(StageJob(**json.loads(sys.argv[1])))
    print("imported the stages:", "gridlib.stages.pipeline" in sys.modules)
    sys.exit(code)
    """
)


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    plugins = tmp_path_factory.mktemp("plugins")
    (plugins / "nap_stage.py").write_text(NAP_STAGE)
    previous = os.environ.get("PYTHONPATH")
    os.environ["PYTHONPATH"] = os.pathsep.join([str(plugins), str(ROOT), *([previous] if previous else [])])
    try:
        started = start_server(["nap_stage"], stages=["grid", "geometry", "nap"])
    finally:
        if previous is None:
            os.environ.pop("PYTHONPATH")
        else:
            os.environ["PYTHONPATH"] = previous
    assert started is not None
    yield started, plugins
    started.stop()
    assert started.process.returncode == 0 and not Path(started.folder).exists()


def _job(folder: Path, case: Path, stage: str, **paths: str) -> StageJob:
    names = {"grid": "grid.nc", "geometry": "geometry.nc", "nap": "nap.txt"}
    return StageJob(
        stage=stage,
        case=str(case),
        paths={key: str(folder / name) for key, name in names.items()} | paths,
        threads=1,
        log=str(folder / f"{stage}.log"),
        outputs=(str(folder / names[stage]),),
        name=f"stage_{stage}",
        label=f"toy: {stage}",
        plugins=("nap_stage",) if stage == "nap" else (),
    )


# A stage rule's job as Snakemake runs it (a thread of its process: here a script calling it),
# then what its process used (the figures of its benchmark file), as JSON.
RULE_SCRIPT = textwrap.dedent(
    """
    import dataclasses, json, sys
    from gridlib.stages.job_server import StageJob, run_stage_job
    end = run_stage_job(StageJob(**json.loads(sys.argv[1])))
    print("imported the stages:", "gridlib.stages.pipeline" in sys.modules)
    print(json.dumps(end.usage and dataclasses.asdict(end.usage)))
    sys.exit(end.status)
    """
)


def _script(
    job: StageJob, env: dict[str, str], plugins: Path, script: str = SCRIPT, **kwargs
) -> subprocess.Popen:
    import json
    from dataclasses import asdict

    env = {**os.environ, "PYTHONPATH": f"{plugins}{os.pathsep}{ROOT}"} | env
    return subprocess.Popen(
        [sys.executable, "-c", script, json.dumps(asdict(job))],
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        **kwargs,
    )


def _run(job: StageJob, env: dict[str, str], plugins: Path, script: str = SCRIPT) -> tuple[int, str, str]:
    process = _script(job, env, plugins, script)
    out, err = process.communicate(timeout=120)
    return process.returncode, out, err


@pytest.fixture
def case(tmp_path) -> Path:
    path = tmp_path / "toy.yaml"
    path.write_text(yaml.safe_dump(CASE, sort_keys=False))
    return path


def test_jobs_in_the_server_write_what_they_write_in_their_own_process(server, case, tmp_path):
    started, plugins = server
    for folder, env, imported in (("served", started.environment(), False), ("own", {}, True)):
        (tmp_path / folder).mkdir()
        for stage in ("grid", "geometry"):
            code, out, err = _run(_job(tmp_path / folder, case, stage), env, plugins)
            assert code == 0, err
            assert out.strip() == f"imported the stages: {imported}", (folder, stage, err)
            log = (tmp_path / folder / f"{stage}.log").read_text()
            assert f"stage_{stage}: " in log  # the stage's cost, under its name
            assert ("run in the job server: process" in log) is not imported, log
    assert assert_same_files(tmp_path / "own", tmp_path / "served") == ["geometry.nc", "grid.nc"]


def test_a_failing_job_fails_as_in_its_own_process(server, case, tmp_path):
    """The geometry stage without its grid: exit status 1 and the same one line on stderr."""
    started, plugins = server
    results = []
    for env in (started.environment(), {}):
        job = _job(tmp_path, case, "geometry", grid=str(tmp_path / "missing.nc"))
        code, _, err = _run(job, env, plugins)
        results.append((code, err))
    (served, own) = results
    assert served == own and served[0] == 1, results
    assert own[1].startswith("gridlib: ") and own[1].count("\n") == 1 and "missing.nc" in own[1], own


def test_a_stopped_job_stops_its_stage_and_what_the_stage_started(server, case, tmp_path):
    started, plugins = server
    assert _run(_job(tmp_path, case, "grid"), started.environment(), plugins)[0] == 0
    script = _script(_job(tmp_path, case, "nap"), started.environment(), plugins)
    pids = tmp_path / "nap.txt.pids"
    _kill_and_see_the_stage_end(script, pids, tmp_path / "nap.txt")


def _kill_and_see_the_stage_end(script: subprocess.Popen, pids: Path, output: Path) -> None:
    """Once the stage has written its pid and its sleeper's into ``pids``, kill the job's
    process ``script`` (as Snakemake ends a job it stops): the stage and what it started end
    within 10 s, without writing ``output``; the stage ran in another process than ``script``."""
    deadline = time.monotonic() + 60
    while not pids.exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    stage, sleeper = (int(p) for p in pids.read_text().split())
    assert stage != script.pid
    script.send_signal(signal.SIGKILL)
    script.communicate(timeout=30)
    deadline = time.monotonic() + 10
    while any(_running(p) for p in (stage, sleeper)) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not _running(stage) and not _running(sleeper)
    assert not output.exists()


def _running(pid: int) -> bool:
    """Whether process ``pid`` exists and has not ended (a zombie has)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except FileNotFoundError:
        return False
    return "\nState:\tZ" not in status


@pytest.mark.parametrize("where", ["another Python", "no socket"])
def test_a_job_the_server_cannot_take_runs_in_its_own_process(server, case, tmp_path, where):
    """A job run by another interpreter (a conda environment's), or naming a server that is
    gone, runs in its own process, as without a server."""
    started, plugins = server
    env = started.environment()
    if where == "another Python":
        env[PYTHON_ENV] = "/some/other/python"
    else:
        env[SERVER_ENV] = str(tmp_path / "gone.sock")
    code, out, err = _run(_job(tmp_path, case, "grid"), env, plugins)
    assert code == 0 and out.strip() == "imported the stages: True", err
    assert "run in the job server" not in (tmp_path / "grid.log").read_text()


def test_a_rule_job_without_a_server_runs_in_a_new_process_and_stops_with_its_caller(server, case, tmp_path):
    """run_stage_job (a stage rule's job, run in a thread of Snakemake's process) never runs the
    stage in the calling process: without a server it starts a new one, which writes what the
    server's child writes, fails with the same line, and is stopped (with what it started) when
    the calling process is."""
    started, plugins = server
    for folder, env in (("served", started.environment()), ("new", {})):
        (tmp_path / folder).mkdir()
        for stage in ("grid", "geometry"):
            code, out, err = _run(_job(tmp_path / folder, case, stage), env, plugins, RULE_SCRIPT)
            assert code == 0 and out.splitlines()[0] == "imported the stages: False", (folder, stage, err)
    assert "run in the job server" not in (tmp_path / "new" / "grid.log").read_text()
    assert assert_same_files(tmp_path / "new", tmp_path / "served") == ["geometry.nc", "grid.nc"]
    failed = _run(
        _job(tmp_path, case, "geometry", grid=str(tmp_path / "missing.nc")), {}, plugins, RULE_SCRIPT
    )
    assert failed[0] == 1 and failed[2].startswith("gridlib: ") and failed[2].count("\n") == 1, failed

    (tmp_path / "grid.nc").write_bytes((tmp_path / "new" / "grid.nc").read_bytes())
    script = _script(_job(tmp_path, case, "nap"), {}, plugins, RULE_SCRIPT)
    pids = tmp_path / "nap.txt.pids"
    _kill_and_see_the_stage_end(script, pids, tmp_path / "nap.txt")


def test_a_rule_job_reports_what_its_process_used(server, case, tmp_path):
    """The figures of a stage job's benchmark file are its own process's: in the server's child,
    its CPU time and peak memory as its log gives them, and the bytes it wrote; in a new
    process, the process's (from os.wait4: its imports too, bytes not known)."""
    import json
    import re

    started, plugins = server
    for folder, env in (("served", started.environment()), ("new", {})):
        (tmp_path / folder).mkdir()
        code, out, err = _run(_job(tmp_path / folder, case, "grid"), env, plugins, RULE_SCRIPT)
        assert code == 0, err
        usage = json.loads(out.splitlines()[1])
        log = (tmp_path / folder / "grid.log").read_text()
        cpu, peak = (
            float(x) for x in re.search(r"s, ([\d.]+) s of CPU, peak memory (\d+) MiB", log).groups()
        )
        assert usage["cpu_seconds"] >= cpu - 0.06, (folder, usage, log)
        assert usage["max_rss_mib"] >= peak - 0.51, (folder, usage, log)
        if folder == "served":
            assert usage["cpu_seconds"] < cpu + 0.5 and usage["max_rss_mib"] < peak + 2, (usage, log)
            assert usage["written_mib"] * 2**20 >= (tmp_path / folder / "grid.nc").stat().st_size
        else:
            assert usage["cpu_seconds"] > cpu and usage["written_mib"] is None, (usage, log)
