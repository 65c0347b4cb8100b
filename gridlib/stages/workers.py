"""Warm worker processes for many small cases (the variants of a study).

A new Python process per variant costs more than a small variant's stages: importing
gridlib, xarray, gstools, VTK and matplotlib takes 3-6 s of CPU, building a 400-cell
variant about 1 s. :func:`run_in_worker` builds a case in a pool of worker processes that
live as long as the calling process (the Snakemake process that parsed the workflow), so
that each worker pays for the imports once: the workers are forked from a fork server that
has imported them already (:data:`PRELOAD`, :mod:`gridlib.stages.worker_imports`: every
stage's modules and libraries and the study table's). Every case still runs all its stages through
:func:`gridlib.stages.run_case`, writing the same staged artifacts (each atomically), with
its log in its own file. A study's table (:func:`study_table`) runs there too: its pictures
need matplotlib, which the workers have imported.
"""

from __future__ import annotations

import multiprocessing
import os
import threading
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any

from .job_usage import JobUsage, Meter

# What the fork server imports before it forks the workers: one module, whose import imports
# the rest (the fork server's preload takes module names only).
PRELOAD = ("gridlib.stages.worker_imports",)

_lock = threading.Lock()
_pool: ProcessPoolExecutor | None = None


def _executor(workers: int) -> ProcessPoolExecutor:
    global _pool
    with _lock:
        if _pool is None:
            context = multiprocessing.get_context("forkserver")
            context.set_forkserver_preload(list(PRELOAD))
            _pool = ProcessPoolExecutor(max_workers=max(1, workers), mp_context=context)
        return _pool


def _build(case_file: str, folder: str, log_file: str) -> JobUsage:
    from .common import run_logged
    from .pipeline import run_case

    try:
        with Meter() as meter:
            run_logged(log_file, run_case, case_file, folder, threads=1, label=Path(case_file).stem)
    except SystemExit:  # run_logged's exit for a failure: one line on stderr, the rest in the log
        raise RuntimeError(f"{case_file} failed (log: {log_file})") from None
    return meter.usage


def _table(
    manifest: str, summaries: list[str], outputs: dict[str, str], simulations: list[str], log_file: str
) -> JobUsage:
    from .common import run_logged
    from .study import stage_study

    try:
        with Meter() as meter:
            run_logged(
                log_file,
                stage_study,
                manifest,
                summaries,
                outputs,
                simulations,
                threads=1,
                outputs=list(outputs.values()),
            )
    except SystemExit:  # as in _build
        raise RuntimeError(f"{manifest}: the study's table failed (log: {log_file})") from None
    return meter.usage


def _in_worker(workers: int, job: Callable[..., JobUsage], *args: Any) -> JobUsage:
    """``job(*args)`` in one of ``workers`` warm worker processes; waits for it; what the job
    used of its worker. A pool whose worker died is replaced for the next job."""
    global _pool
    pool = _executor(workers)
    try:
        return pool.submit(job, *args).result()
    except BrokenProcessPool:
        with _lock:
            if _pool is pool:
                _pool = None
        raise


def run_in_worker(
    case_file: str | os.PathLike, folder: str | os.PathLike, log_file: str | os.PathLike, workers: int
) -> JobUsage:
    """Build the case ``case_file`` into ``folder`` (all stages, as ``gridlib build``) in one
    of ``workers`` warm worker processes, logging to ``log_file``; waits for it. What the build
    used of its worker process (:mod:`gridlib.stages.job_usage`: its CPU, its peak memory from
    its start, the bytes it read and wrote)."""
    return _in_worker(workers, _build, str(case_file), str(folder), str(log_file))


def run_in_process(
    case_file: str | os.PathLike, folder: str | os.PathLike, log_file: str | os.PathLike
) -> JobUsage:
    """As :func:`run_in_worker`, in this process (when no pool is wanted, e.g. inside a job)."""
    return _build(str(case_file), str(folder), str(log_file))


def study_table(
    manifest: str | os.PathLike,
    summaries: Sequence[str | os.PathLike],
    outputs: Mapping[str, str | os.PathLike],
    simulations: Sequence[str | os.PathLike],
    log_file: str | os.PathLike,
    workers: int | None = None,
) -> JobUsage:
    """A study's table and pictures (:func:`gridlib.stages.study.stage_study` of the study's
    manifest, its variants' ``summaries`` and ``simulations``, into ``outputs`` by name),
    logging to ``log_file``: in one of ``workers`` warm worker processes (which have imported
    matplotlib and pandas already: 1.5 s of a 3 s job in a process of its own), or in this
    process where ``workers`` is None. What the job used of the process it ran in."""
    args = (
        str(manifest),
        [str(s) for s in summaries],
        {key: str(path) for key, path in outputs.items()},
        [str(s) for s in simulations],
        str(log_file),
    )
    if workers is None:
        return _table(*args)
    return _in_worker(workers, _table, *args)
