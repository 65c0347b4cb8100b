"""pytest plugin: the CPU time of every test and test module, its subprocesses included.

Run (one process, so that the figures do not depend on how xdist spreads the modules):

    CPUTIME_OUT=cpu.json PYTHONPATH=.:bench .venv/bin/python -m pytest -p pytest_cputime \\
        -p no:randomly -q -n 0 [tests/...]

Wall time (``--durations``) varies by 2x with what else runs on the machine; CPU seconds much
less. A test's CPU is this process's user + system time during its setup, call and teardown
(its module fixtures count in the first and last test of the module), plus that of every
process it started that ended meanwhile: Snakemake, its jobs, OPM Flow. This process is made a
child subreaper (Linux), so that processes orphaned by their parent (e.g. the warm worker
processes of a Snakemake run, whose fork server is left behind when Snakemake exits) come to
it when they end and are counted too. Processes of other users of the machine (SLURM's jobs,
run by slurmd) are not counted. ``CPUTIME_OUT`` receives {"modules": {path: [cpu, wall]},
"tests": {nodeid: [cpu, wall]}} in seconds; under pytest-xdist each worker writes
``CPUTIME_OUT.<worker id>`` (e.g. cpu.json.gw0) with the modules it ran and the time each
started (``"starts"``: seconds since the epoch), from which the critical path can be read.
``"collection"`` is [cpu, wall] of the process's collection (imports of every test module and,
for the doctests, of every gridlib module): under xdist each worker collects the whole suite.
"""

from __future__ import annotations

import ctypes
import json
import os
import resource
import time
from collections import defaultdict

import pytest

PR_SET_CHILD_SUBREAPER = 36

_modules: dict[str, list[float]] = defaultdict(lambda: [0.0, 0.0])
_tests: dict[str, list[float]] = {}
_starts: dict[str, float] = {}
_collection: list[float] = []  # CPU and wall seconds of this process's collection


def _reap_orphans() -> None:
    """Wait for the ended processes that became this process's children as orphans."""
    while True:
        try:
            pid, _ = os.waitpid(-1, os.WNOHANG)
        except ChildProcessError:
            return
        if pid == 0:
            return


def _cpu() -> float:
    _reap_orphans()
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def pytest_configure(config: pytest.Config) -> None:
    try:
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_CHILD_SUBREAPER, 1, 0, 0, 0)
    except (OSError, AttributeError):  # not Linux: orphans are not counted
        pass


@pytest.hookimpl(hookwrapper=True)
def pytest_collection(session: pytest.Session):
    cpu, wall = _cpu(), time.perf_counter()
    yield
    if session.items:  # not pytest-xdist's controller, which leaves collection to its workers
        _collection[:] = [_cpu() - cpu, time.perf_counter() - wall]


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem: pytest.Item | None):
    cpu, wall = _cpu(), time.perf_counter()
    yield
    cpu, wall = _cpu() - cpu, time.perf_counter() - wall
    module = os.path.relpath(str(item.path), str(item.config.rootpath))
    _starts.setdefault(module, time.time() - wall)
    _modules[module][0] += cpu
    _modules[module][1] += wall
    _tests[item.nodeid] = [cpu, wall]


def pytest_sessionfinish(session: pytest.Session) -> None:
    out = os.environ.get("CPUTIME_OUT")
    if out and _tests:  # under xdist only the workers run tests: each writes its own file
        worker = os.environ.get("PYTEST_XDIST_WORKER")
        with open(f"{out}.{worker}" if worker else out, "w") as f:
            record = {"modules": dict(_modules), "tests": _tests, "starts": _starts}
            json.dump(record | {"collection": _collection}, f, indent=1)


def pytest_terminal_summary(terminalreporter) -> None:
    total = sum(cpu for cpu, _ in _modules.values())
    terminalreporter.write_sep("=", f"CPU time per module (self + subprocesses): {total:.1f} s in all")
    if _collection:  # under xdist the workers collect: their figures are in their files
        terminalreporter.write_line(f"{_collection[0]:8.1f} s CPU {_collection[1]:8.1f} s wall  (collection)")
    for module, (cpu, wall) in sorted(_modules.items(), key=lambda kv: -kv[1][0])[:40]:
        terminalreporter.write_line(f"{cpu:8.1f} s CPU {wall:8.1f} s wall  {module}")
