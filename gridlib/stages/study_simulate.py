"""A simulated study's Flow job: one variant's OPM Flow deck (its ``flow/`` folder, written by
the variant's grid job) run into ``results/<study>/<variant>/simulation/``.

Flow runs with one thread (``--threads-per-process=1``: the same numbers on any machine),
writing its files synchronously (the same bytes on a loaded machine:
:func:`gridlib.stages.simulate.run_flow`), in the deck's folder; its output goes into a new
folder beside ``simulation/`` that replaces it when complete
(:func:`gridlib.io.atomic.atomic_directory`): Flow's files (``<NAME>.PRT``, ``.SMSPEC``,
``.UNSMRY``, ``.EGRID``, ``.INIT``, ``.UNRST``, ...) and ``responses.json``
(:mod:`gridlib.io.flow_responses`).

A run fails when Flow exits with an error, writes no summary (UNSMRY), or stops before the
variant's last report day (Flow gives up on a time step it cannot converge by cutting it
further; it then ends with an error). With ``on_failure: report`` the folder then holds what
Flow wrote and a ``responses.json`` of status ``failed`` with Flow's reason (one line) and its
message file; with ``stop`` the job fails with one InputError naming the study file, the
variant and the reason (and writes nothing).
"""

from __future__ import annotations

import os
import signal
import subprocess
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..io.atomic import atomic_directory
from ..io.flow_responses import Responses, failed_responses, flow_responses, write_responses
from ..io.flow_results import read_summary
from .simulate import deck_unit_system, flow_command, flow_message, run_flow

SIMULATION_FOLDER = "simulation"


def variant_deck(flow_folder: str | os.PathLike) -> Path:
    """The one deck (``<NAME>.DATA``) in a variant's ``flow/`` folder."""
    decks = sorted(Path(flow_folder).glob("*.DATA"))
    if len(decks) != 1:
        found = ", ".join(d.name for d in decks) or "none"
        raise InputError(f"{flow_folder}: expected one OPM Flow deck (*.DATA), found {found}")
    return decks[0]


def signal_name(number: int) -> str:
    """``SIGABRT`` for 6 (Flow aborts on a failed assertion), else ``signal <number>``."""
    try:
        return signal.Signals(number).name
    except ValueError:
        return f"signal {number}"


def failure_reason(
    result: subprocess.CompletedProcess, case_base: Path, report_days: Sequence[float]
) -> str | None:
    """Why the Flow run of ``result`` (its files ``case_base``.*) failed, in one line; None if
    it reached the last of ``report_days``."""
    prt = Path(f"{case_base}.PRT")
    if result.returncode < 0:
        return f"OPM Flow was killed by {signal_name(-result.returncode)}: {flow_message(result, prt)}"
    if result.returncode != 0:
        return f"OPM Flow ended with status {result.returncode}: {flow_message(result, prt)}"
    if not Path(f"{case_base}.UNSMRY").is_file():
        return f"OPM Flow wrote no summary (UNSMRY): {flow_message(result, prt)}"
    summary = read_summary(case_base)
    end = float(summary.time[-1]) if summary.time.size else 0.0
    if report_days and not np.isclose(end, report_days[-1], rtol=0.0, atol=1e-6):
        return f"OPM Flow stopped at day {end:g} of {report_days[-1]:g}: {flow_message(result, prt)}"
    return None


def simulate_variant(
    flow_folder: str | os.PathLike,
    output: str | os.PathLike,
    *,
    study_file: str,
    variant: str,
    report_days: Sequence[float],
    times: Sequence[float] = (),
    water_cut: float = 0.01,
    on_failure: str = "report",
    log_file: str | os.PathLike | None = None,
) -> Responses:
    """Run the deck of ``flow_folder`` in Flow into the folder ``output`` (atomically) with its
    ``responses.json``; returns the responses. ``report_days``: the variant's (its run must reach
    the last); ``times``, ``water_cut``: the study's ``responses``; ``on_failure``: ``report``
    (a failed run is recorded) or ``stop`` (an InputError naming ``study_file`` and
    ``variant``); ``log_file``: the job's log (Flow's command, wall time, outcome)."""
    deck = variant_deck(flow_folder)
    system = deck_unit_system(deck)
    try:
        flow_command()
    except InputError as exc:  # not a failure of the variant's run: of the machine
        raise InputError(f"{study_file}: simulate: {exc}") from None
    lines = [f"variant {variant}: OPM Flow on {deck}"]
    start = time.perf_counter()
    try:
        with atomic_directory(output) as tmp:
            result = run_flow(deck, tmp)
            lines.append(f"flow exit status {result.returncode}, {time.perf_counter() - start:.2f} s wall")
            base = tmp / deck.stem
            reason = failure_reason(result, base, report_days)
            prt = Path(f"{base}.PRT")
            messages = f"{SIMULATION_FOLDER}/{prt.name}" if prt.is_file() else None
            if reason is None:
                try:
                    responses = flow_responses(read_summary(base), system, times, water_cut, messages)
                except KeyError as exc:
                    reason = f"OPM Flow's summary lacks a vector the study needs ({exc.args[0]})"
            if reason is not None:
                if on_failure == "stop":
                    raise InputError(f"{study_file}: variant '{variant}': simulation failed: {reason}")
                responses = failed_responses(reason, system, messages)
            write_responses(tmp / "responses.json", responses)
        lines.append(f"status {responses.status}" + (f": {responses.reason}" if responses.reason else ""))
        return responses
    except InputError as exc:
        lines.append(f"error: {exc}")
        raise
    finally:
        if log_file is not None:
            Path(log_file).parent.mkdir(parents=True, exist_ok=True)
            Path(log_file).write_text("\n".join(lines) + "\n", encoding="utf-8")
