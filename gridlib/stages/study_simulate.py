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
import time
from collections.abc import Sequence
from pathlib import Path

from ..errors import InputError
from ..io.atomic import atomic_directory
from ..io.flow_responses import Responses, failed_responses, flow_responses, write_responses
from ..io.flow_results import read_summary
from .simulate import deck_unit_system, failure_reason, flow_command, run_flow

SIMULATION_FOLDER = "simulation"


def variant_deck(flow_folder: str | os.PathLike) -> Path:
    """The one deck (``<NAME>.DATA``) in a variant's ``flow/`` folder."""
    decks = sorted(Path(flow_folder).glob("*.DATA"))
    if len(decks) != 1:
        found = ", ".join(d.name for d in decks) or "none"
        raise InputError(f"{flow_folder}: expected one OPM Flow deck (*.DATA), found {found}")
    return decks[0]


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
