"""Stage ``simulate`` (optional): OPM Flow runs the case's deck ``flow/<NAME>.DATA``.

Flow runs with one thread and its default tolerances into a temporary folder next to the
deck; only a run that reaches the last report step has its files moved into ``flow/``
(``<NAME>.PRT``, ``.SMSPEC``, ``.UNSMRY``, ``.EGRID``, ``.INIT``, ``.UNRST``: ResInsight
opens them), then the stage writes, atomically:

* ``summary`` (``flow/summary.json``): the field figures at the end of the run (totals,
  in place, average pressure, water cut), the wells' end figures, and the last FIP report
  of the PRT file;
* ``wells`` (``flow/{case}_wells.png``): every well's surface rates and bottom-hole pressure
  over time;
* ``pvd`` (``flow/{case}_flow.pvd``): the results as a time series for ParaView, one VTU per
  report step of the restart file (``flow/{case}_flow/{case}_flow_<step>.vtu``, step 0 the
  initial state; the PVD's time is days since the start): the grid (the case's own cells, not
  the connection form's boxes; z is elevation) with every solution array Flow wrote, lower
  case (``pressure``, ``swat``, ``sgas``, ``rs``, ...; through ``cell_flow_index``) and the
  cells' centroid ``depth`` (:func:`write_result_pvd`).

A failed run leaves nothing behind and ends in an :class:`~gridlib.errors.InputError`
naming the case file and quoting Flow's message. Units: the deck's (METRIC: sm3, sm3/day,
bar; FIELD: stb, stb/day, psia).
"""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import tempfile
from collections.abc import Sequence
from itertools import chain
from pathlib import Path
from typing import Any

import numpy as np

from ..case.simulation import case_simulation
from ..config import Case
from ..errors import InputError
from ..geometry import compute_geometry
from ..io.atomic import atomic_path
from ..io.flow_responses import initial_oil_in_place
from ..io.flow_results import FlowSummary, active_positions, read_fip_report, read_summary, restart_steps
from ..io.netcdf import read_netcdf
from ..io.pictures import save_figure
from ..io.pvd import write_vtu_series
from ..io.transmissibility_file import read_transmissibility
from ..units import FIELD, METRIC, UnitSystem, unit_system
from .common import log

FLOW_OUTPUTS = (".PRT", ".DBG", ".SMSPEC", ".UNSMRY", ".EGRID", ".INIT", ".UNRST", ".INFOSTEP")
FIELD_FIGURES = ("FOPT", "FWPT", "FWIT", "FOIP", "FWIP", "FPR", "FWCT")
WELL_FIGURES = ("WOPT", "WWPT", "WWIT", "WBHP", "WWCT")


def flow_command() -> str:
    """The ``flow`` executable (OPM Flow); InputError if it is not on the PATH."""
    exe = shutil.which("flow")
    if exe is None:
        raise InputError(
            "OPM Flow ('flow') is not installed (Debian/Ubuntu: apt-get install libopm-simulators-bin)"
        )
    return exe


# Variables by which Open MPI (Flow's MPI) finds a job launcher: inside a SLURM job, MPI_Init
# would try to join the job step through SLURM's PMI and abort where Open MPI was built without it.
_LAUNCHER_VARIABLES = ("SLURM_", "PMI_", "PMIX_", "OMPI_")

# Open MPI 4 (Debian's Flow) has a process started without mpirun (a singleton) start its
# runtime daemon and probe the network transports before Flow reads the deck: 0.3 s of waiting
# in every run, a quarter of a small study variant's Flow job. Isolated and with the ob1
# messaging layer it starts in 0.05 s; one rank sends no messages, so the results are the same
# (a study variant's UNSMRY byte for byte). Other MPIs ignore these names.
_ISOLATED_SINGLETON = {"OMPI_MCA_ess_singleton_isolated": "1", "OMPI_MCA_pml": "ob1"}


def flow_environment(
    session_base: str | os.PathLike, environ: dict[str, str] | None = None
) -> dict[str, str]:
    """The environment Flow runs in: this process's (or ``environ``) without the variables of
    a job launcher (SLURM, PMI, Open MPI), so that Flow is one MPI process of its own (a
    singleton) anywhere, in a SLURM job as on a laptop, an isolated one (no runtime daemon)
    whose session directory is under ``session_base``.

    Every isolated singleton is Open MPI's job family 0: its session directory is always
    ``<base>/ompi.<host>.<uid>/jf.0/1``, made at its start and removed at its end, so two runs
    at once (two jobs of a workflow) with one base remove each other's and one stops in
    MPI_Init; each run needs a base of its own (:func:`run_flow` makes one)."""
    source = os.environ if environ is None else environ
    env = {k: v for k, v in source.items() if not k.startswith(_LAUNCHER_VARIABLES)}
    return {**env, **_ISOLATED_SINGLETON, "OMPI_MCA_orte_tmpdir_base": os.fspath(session_base)}


def run_flow(deck: Path, out_dir: Path, options: tuple[str, ...] = ()) -> subprocess.CompletedProcess:
    """Flow on ``deck`` with its output in ``out_dir`` (one thread, ``options`` added), run in
    the deck's folder as one process (:func:`flow_environment`, with a session directory base
    of its own, removed after the run).

    The output is written synchronously: with Flow's default asynchronous writer (a thread of
    its own) the summary's MINISTEP counters depend on the two threads' timing, so two runs
    of one deck on a loaded machine wrote different UNSMRY files (5 of 6 runs, 2 cores shared);
    written synchronously, 8 of 8 were identical, byte for byte."""
    deck, out_dir = Path(deck).resolve(), Path(out_dir).resolve()
    command = [flow_command(), "--threads-per-process=1", "--enable-async-ecl-output=false"]
    with tempfile.TemporaryDirectory(prefix="gridlib-mpi-session-") as session_base:
        return subprocess.run(
            [*command, *options, f"--output-dir={out_dir}", deck.name],
            capture_output=True,
            text=True,
            cwd=deck.parent,
            env=flow_environment(session_base),
        )


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


_MESSAGE = re.compile(r"^(Error:|Problem:|Exception|Program threw|.*\b[Ee]xception\b|.*Assertion .* failed)")


def flow_message(result: subprocess.CompletedProcess, prt: Path) -> str:
    """What Flow said went wrong: its error and exception lines (stdout, stderr, the PRT file),
    else the last lines it printed; Open MPI's notes are left out."""
    text = "\n".join([result.stdout or "", result.stderr or ""])
    if prt.is_file():
        text += "\n" + prt.read_text(errors="replace")
    lines = [line.strip() for line in text.splitlines() if line.strip() and "MPI" not in line]
    said = (line for line in lines if _MESSAGE.match(line) and line.rstrip(":") not in ("Problem", "Error"))
    found = list(dict.fromkeys(said))
    if not found:
        found = lines[-3:] or [f"exit status {result.returncode}"]
    return " | ".join(found[:4])


def stage_simulate(
    case: Case,
    *,
    flow_deck: str | os.PathLike,
    grid: str | os.PathLike,
    transmissibility: str | os.PathLike,
    flow_summary: str | os.PathLike,
    flow_wells: str | os.PathLike,
    flow_pvd: str | os.PathLike | None = None,
    options: tuple[str, ...] = (),
) -> FlowSummary:
    """Run Flow on the case's deck ``flow_deck``; write ``flow_summary`` (the figures, JSON),
    ``flow_wells`` (the wells' picture) and ``flow_pvd`` (the results on the grid of ``grid``
    and ``transmissibility``, a time series); returns the summary. ``options``: more command-line options of
    ``flow``."""
    deck = Path(flow_deck)
    if not deck.is_file():
        raise InputError(f"{case.path}: simulation: the deck {deck} is missing (run the export first)")
    if not case.has_simulation:
        raise InputError(f"{case.path}: simulation: the case has no simulation section (nothing to run)")
    days = list(case_simulation(case).report_days)
    name = deck.stem
    try:
        flow_command()
    except InputError as exc:
        raise InputError(f"{case.path}: simulation: {exc}") from None
    tmp = Path(tempfile.mkdtemp(prefix=f".{name}.run-", dir=deck.parent))
    try:
        result = run_flow(deck, tmp, options)
        base = tmp / name
        reason = failure_reason(result, base, days)
        if reason is not None:
            raise InputError(f"{case.path}: simulation: {deck.name}: {reason}")
        summary = read_summary(base)
        fip = read_fip_report(f"{base}.PRT")
        for line in (result.stdout or "").splitlines():
            if "time (seconds)" in line or line.startswith("Overall"):
                log.info("flow: %s", line.strip())
        figures = simulation_figures(case, summary, fip, deck)
        with atomic_path(flow_summary) as path:
            path.write_text(json.dumps(figures, indent=2) + "\n")
        plot_wells(Path(flow_wells), summary, f"{case.name}: wells", deck_unit_system(deck))
        if flow_pvd is not None:
            write_result_pvd(Path(flow_pvd), base, grid, transmissibility)
        # Flow's own files join the deck last: a run that fails above leaves none of them
        for suffix in FLOW_OUTPUTS:
            produced = Path(f"{base}{suffix}")
            if produced.is_file():
                os.replace(produced, deck.parent / produced.name)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    log.info(
        "simulated %s to day %g: %s",
        case.name,
        figures["simulated_days"],
        ", ".join(f"{k} {figures['field'][k]:.6g}" for k in figures["field"]),
    )
    return summary


def _figure(value: float) -> float:
    return float(f"{float(value):.8g}")  # the file holds float32: 8 digits are all there is


def deck_unit_system(deck: Path) -> UnitSystem:
    """The unit system of a deck gridlib wrote (FIELD or METRIC, in its first lines)."""
    head = deck.read_text(errors="replace")[:4000]
    return FIELD if re.search(r"^FIELD\s*$", head, re.M) else METRIC


def simulation_figures(case, summary: FlowSummary, fip: dict, deck: Path) -> dict[str, Any]:
    """The figures of ``flow/summary.json``: the field's and the wells' at the last step."""
    system = deck_unit_system(deck)
    units = (system.surface_volume_label, system.rate_label, system.pressure_label)
    field = {k: _figure(summary[k][-1]) for k in FIELD_FIGURES if (k, "") in summary.values}
    wells = {
        w: {k: _figure(summary[(k, w)][-1]) for k in WELL_FIGURES if (k, w) in summary.values}
        for w in summary.wells
    }
    out: dict[str, Any] = {
        "case": case.name,
        "case_sha256": case.sha256,
        "deck": deck.name,
        "units": f"{system.name} ({', '.join(units)})",
        "simulated_days": _figure(summary.time[-1]) if summary.time.size else 0.0,
        "report_days": [_figure(t) for t in summary.time[summary.report]],
        "time_steps": int(summary.time.size),
        "field": field,
        "wells": wells,
        "fip_report": fip,
    }
    if "FOPT" in field and "FOIP" in field:  # the study's definition (gridlib.io.flow_responses)
        initial = initial_oil_in_place(summary)
        out["oil_recovery"] = _figure(summary["FOPT"][-1] / initial) if initial > 0 else 0.0
    return out


def plot_wells(path: Path, summary: FlowSummary, title: str, units: UnitSystem) -> None:
    """:func:`wells_figure` saved as ``path``."""
    save_figure(wells_figure(summary, title, units), path)


def wells_figure(summary: FlowSummary, title: str, units: UnitSystem):
    """A matplotlib figure: surface rates (left) and bottom-hole pressures (right) of every
    well over time, the axes labelled with their units in ``units`` (the deck's)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (rates, bhp) = plt.subplots(1, 2, figsize=(12, 4.2))
    t = summary.time
    for well in summary.wells:
        for key, label in (("WOPR", "oil"), ("WWPR", "water"), ("WWIR", "water injected")):
            values = summary.values.get((key, well))
            if values is not None and np.abs(values).max() > 0:
                rates.plot(t, values, label=f"{well} {label}")
        if ("WBHP", well) in summary.values:
            bhp.plot(t, summary[("WBHP", well)], label=well)
    rates.set_xlabel("time [day]")
    rates.set_ylabel(f"surface rate [{units.rate_label}]")
    bhp.set_xlabel("time [day]")
    bhp.set_ylabel(f"bottom-hole pressure [{units.pressure_label}]")
    for ax in (rates, bhp):
        if ax.has_data():
            ax.legend(fontsize=8)
    fig.suptitle(f"{title} ({units.name})")
    fig.tight_layout()
    return fig


def write_result_pvd(
    path: Path, case_base: Path, grid_nc: str | os.PathLike, transmissibility_nc: str | os.PathLike
) -> Path:
    """Flow's results (``case_base``.UNRST, .EGRID) on the case's grid as a ParaView time series
    (:func:`gridlib.io.pvd.write_vtu_series`): per report step, every solution array of the
    restart file under its keyword in lower case, in the run's units, and the cells' centroid
    ``depth`` (the VTU's z is elevation: :func:`gridlib.io.vtu.vtk_points`); times in days."""
    grid = read_netcdf(grid_nc).grid
    variables, _ = read_transmissibility(transmissibility_nc)
    position = active_positions(Path(f"{case_base}.EGRID"), variables["cell_flow_index"].values)
    centroids = compute_geometry(grid).cell_centroids
    static: dict[str, np.ndarray] = {"depth": centroids[:, 2]} if centroids.shape[1] == 3 else {}
    steps = restart_steps(case_base)
    first = next(steps, None)
    if first is None:
        raise InputError(f"{case_base}.UNRST: no report step")
    system = unit_system(first.units) if first.units != "unknown" else None
    length = system.length_label if system is not None else "?"
    units = {k.lower(): _restart_unit(k, system) for k in first.cells} | {k: length for k in static}
    note = f"OPM Flow results ({first.units}); cell arrays: " + ", ".join(
        f"{k} [{u}]" for k, u in units.items()
    )
    note += f"; timestep: days since the start; z: elevation [{length}] = -depth"
    series = (
        (step.step, step.days, {k.lower(): v[position] for k, v in step.cells.items()} | static)
        for step in chain([first], steps)
    )
    return write_vtu_series(path, grid, series, note=note)


_SATURATIONS = ("SWAT", "SGAS", "SOIL")


def _restart_unit(keyword: str, system: UnitSystem | None) -> str:
    """The unit of a restart solution array: pressures in the run's, saturations fractions
    ("1"), else "?" (as Flow wrote it, in the run's unit system)."""
    if keyword in _SATURATIONS:
        return "1"
    if keyword == "PRESSURE" and system is not None:
        return system.pressure_label
    return "?"
