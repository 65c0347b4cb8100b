"""Simulated studies end to end: every variant's deck through OPM Flow as a job of its own.

One workflow run (two cores, warm workers) of two studies of a 48-cell corner-point waterflood
(6 x 4 columns, 2 layers, 400 days in 3 report steps): ``flood``, 2 x 2 (fault throw x injection
rate, four Flow runs), and ``broken_flood``, whose second variant starts at 20,000 bar, beyond
the oil's PVT table, where Flow gives up (a convergence failure, then an assertion: it aborts).
Then: study.csv's responses equal what resfo reads from each variant's own UNSMRY (and gridlib's
reader), recovery against the variant's own initial oil in place; study.nc holds the series;
the failed variant is reported with Flow's reason and its PRT file while the other finishes;
a second run does nothing and changing one value reruns exactly its variants' grid and Flow
jobs; ``on_failure: stop`` fails the run naming the study file and the variant. The loader's
checks of the keys are one line naming the study file and the key.
"""

from __future__ import annotations

import copy
import csv
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import resfo
import xarray as xr
import yaml
from simulated_study import BASE

from gridlib.errors import InputError
from gridlib.io.flow_results import read_summary
from gridlib.io.summary_table import figure_name
from gridlib.study import load_study

ROOT = Path(__file__).resolve().parents[2]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile")]
GREEDY = ["--scheduler", "greedy"]  # as workflow/profiles/default (make run)

FLOOD = {
    "name": "flood",
    "base": "../cases/tiny_flood.yaml",
    "vary": {"faults.0.throw": [0, 15], "simulation.wells.0.rate": [300, 600]},
    "simulate": True,
    "responses": {"times": [200], "water_cut": 0.01},
    "pictures": False,  # the variants' own pictures: read by no test here (test_study.py)
}
BROKEN = {
    "name": "broken_flood",
    "base": "../cases/tiny_flood.yaml",
    "vary": {"simulation.initial.pressure": [210, 20000]},
    "simulate": True,
    "pictures": False,
}
FAILING = "pressure-20000_r0"
WATER_CUT = 0.01


def _write(path: Path, data: dict) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def _snakemake(workdir: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [*SNAKEMAKE, "--directory", str(workdir), "--cores", "2", "--force-use-threads", *GREEDY, *args]
        + ["--config", "cases=[]", f"studies={workdir / 'config' / 'studies'}/*.yaml"],
        capture_output=True,
        text=True,
        timeout=600,
    )


@pytest.fixture(scope="module")
def study_run(tmp_path_factory) -> Path:
    workdir = tmp_path_factory.mktemp("simulated_study")
    _write(workdir / "config" / "cases" / "tiny_flood.yaml", BASE)
    _write(workdir / "config" / "studies" / "flood.yaml", FLOOD)
    _write(workdir / "config" / "studies" / "broken_flood.yaml", BROKEN)
    result = _snakemake(workdir)
    assert result.returncode == 0, result.stderr[-4000:]
    return workdir


def _rows(workdir: Path, study: str) -> dict[str, dict[str, str]]:
    """study.csv's rows by variant, columns by name (the header's unit left out)."""
    with open(workdir / "results" / study / "study.csv", newline="") as f:
        return {r["variant"]: {figure_name(k): v for k, v in r.items()} for r in csv.DictReader(f)}


def _resfo_summary(base: Path) -> tuple[np.ndarray, dict[tuple[str, str], np.ndarray], list[int]]:
    """Straight from resfo: the time steps' float32 rows, (keyword, well) -> column and the
    rows ending a report step."""

    def text(values) -> list[str]:
        return [(v.decode() if isinstance(v, bytes) else str(v)).strip() for v in values]

    spec = {kw.strip(): v for kw, v in resfo.read(f"{base}.SMSPEC")}
    columns = {
        (kw, name if kw.startswith("W") else ""): i
        for i, (kw, name) in enumerate(zip(text(spec["KEYWORDS"]), text(spec["WGNAMES"]), strict=True))
    }
    rows, reports = [], []
    for kw, value in resfo.read(f"{base}.UNSMRY"):
        if kw.strip() == "SEQHDR" and rows:
            reports.append(len(rows) - 1)
        elif kw.strip() == "PARAMS":
            rows.append(np.asarray(value))
    reports.append(len(rows) - 1)
    table = np.array(rows)
    assert table.dtype == np.float32
    return table, columns, reports


def _expected(base: Path, times: list[float]) -> dict[str, float]:
    """The responses as the docs define them, computed from resfo's float32 values."""
    table, col, reports = _resfo_summary(base)

    def v(kw: str, well: str = "", row: int = -1) -> float:
        return float(table[row, col[(kw, well)]])

    time = table[:, col[("TIME", "")]]
    initial = v("FOPT", row=0) + v("FOIP", row=0)
    out = {k: v(k) for k in ("FOPT", "FWPT", "FWIT", "FPR")}
    out |= {"FOIP0": initial, "oil_recovery": v("FOPT") / initial}
    for t in times:
        (row,) = [r for r in reports if time[r] == t]
        out |= {f"{k}@{t:g}": v(k, row=row) for k in ("FOPT", "FWPT", "FPR")}
        out[f"oil_recovery@{t:g}"] = v("FOPT", row=row) / initial
    for well in ("INJ", "PROD"):
        out |= {f"{k}:{well}": v(k, well) for k in ("WOPT", "WWPT", "WBHP")}
    cut = table[:, col[("WWCT", "PROD")]]
    out["WBT:PROD"] = float(time[np.flatnonzero(cut > WATER_CUT)[0]]) if (cut > WATER_CUT).any() else math.nan
    return out


def _responses(row: dict[str, str]) -> list[str]:
    """The names of a row's responses: the columns after simulation_messages."""
    names = list(row)
    return names[names.index("simulation_messages") + 1 :]


def _flow_base(workdir: Path, study: str, variant: str) -> Path:
    return workdir / "results" / study / variant / "simulation" / variant.upper()


def test_responses_equal_what_resfo_reads_from_each_variants_summary(study_run):
    rows = _rows(study_run, "flood")
    assert sorted(rows) == sorted(
        f"throw-{t}_rate-{q}_r0" for t in FLOOD["vary"]["faults.0.throw"] for q in (300, 600)
    )
    with open(study_run / "results" / "flood" / "study.csv", newline="") as f:
        header = next(csv.reader(f))
    assert header[header.index("simulation") :][:6] == [
        "simulation",
        "simulation_reason",
        "simulation_messages",
        "FOPT [sm3]",
        "FWPT [sm3]",
        "FWIT [sm3]",
    ]
    assert {"FPR [bar]", "oil_recovery [1]", "FOPT@200 [sm3]", "WBHP:PROD [bar]", "WBT:PROD [day]"} <= set(
        header
    )
    breakthrough = []
    for variant, row in rows.items():
        base = _flow_base(study_run, "flood", variant)
        expected = _expected(base, [200])
        assert list(expected) == _responses(row)
        for name, value in expected.items():
            assert float(row[name]) == value or (math.isnan(value) and row[name] == "nan"), (variant, name)
        summary = read_summary(base)  # gridlib's own reader: the same numbers
        assert (
            float(row["FOPT"]) == summary["FOPT"][-1]
            and float(row["WBHP:INJ"]) == summary[("WBHP", "INJ")][-1]
        )
        assert row["simulation"] == "ok" and row["simulation_reason"] == ""
        assert row["simulation_messages"] == f"{variant}/simulation/{variant.upper()}.PRT"
        # recovery from the variant's own initial oil in place: the throw moves oil across the fault
        assert float(row["oil_recovery"]) == float(row["FOPT"]) / float(row["FOIP0"])
        breakthrough.append(float(row["WBT:PROD"]))
    assert all(0 < t <= 400 for t in breakthrough)  # water reaches the producer in every variant
    foip = {v: float(r["FOIP0"]) for v, r in rows.items()}
    assert foip["throw-0_rate-300_r0"] != foip["throw-15_rate-300_r0"]
    assert float(rows["throw-0_rate-600_r0"]["FWIT"]) == 2 * float(rows["throw-0_rate-300_r0"]["FWIT"])


def test_study_nc_holds_the_responses_and_their_series_over_time(study_run):
    with xr.open_dataset(study_run / "results" / "flood" / "study.nc", decode_timedelta=False) as ds:
        assert ds["time"].values.tolist() == [100.0, 200.0, 400.0] and ds["time"].attrs["units"] == "day"
        assert ds["FOPR"].dims == ("faults.0.throw", "simulation.wells.0.rate", "realisation", "time")
        assert ds["FOPT"].dims == ("faults.0.throw", "simulation.wells.0.rate", "realisation")
        assert ds["FOPT_series"].attrs["units"] == ds["FOPT"].attrs["units"] == "sm3"
        assert ds["WWCT:PROD"].attrs["units"] == "1" and ds["FPR_series"].attrs["units"] == "bar"
        at = {"faults.0.throw": 15, "simulation.wells.0.rate": 600, "realisation": 0}
        table, col, reports = _resfo_summary(_flow_base(study_run, "flood", "throw-15_rate-600_r0"))
        for name, (kw, well) in {
            "FOPR": ("FOPR", ""),
            "FOPT_series": ("FOPT", ""),
            "WBHP:PROD_series": ("WBHP", "PROD"),
        }.items():
            assert ds[name].sel(at).values.tolist() == table[reports, col[(kw, well)]].astype(float).tolist()
        assert float(ds["FOPT"].sel(at)) == float(ds["FOPT_series"].sel(at)[-1])


def test_a_failed_variant_is_reported_with_flows_reason_while_the_other_finishes(study_run):
    rows = _rows(study_run, "broken_flood")
    ok, failed = rows["pressure-210_r0"], rows[FAILING]
    assert ok["simulation"] == "ok" and float(ok["oil_recovery"]) > 0
    assert failed["simulation"] == "failed"
    reason = failed["simulation_reason"]
    assert reason.startswith("OPM Flow was killed by SIGABRT: ") and "\n" not in reason
    assert "Solver convergence failure" in reason, reason
    prt = study_run / "results" / "broken_flood" / failed["simulation_messages"]
    assert prt.name == f"{FAILING.upper()}.PRT" and "convergence failure" in prt.read_text()
    responses = _responses(failed)
    assert responses == _responses(ok) and "FOPT" in responses
    assert all(failed[n] == "nan" for n in responses) and all(ok[n] != "nan" for n in responses)
    with xr.open_dataset(study_run / "results" / "broken_flood" / "study.nc") as ds:
        where = {"simulation.initial.pressure": 20000, "realisation": 0}
        assert np.isnan(ds["FOPT"].sel(where)) and np.isnan(ds["FOPR"].sel(where)).all()
        assert str(ds["simulation"].sel(where).values) == "failed"


def _job_counts(result: subprocess.CompletedProcess) -> dict[str, int]:
    counts = {}
    for line in (result.stdout + result.stderr).splitlines():
        parts = line.split()
        if len(parts) == 2 and parts[1].isdigit():
            counts[parts[0]] = int(parts[1])
    return counts


def test_the_pictures_of_a_simulated_study_are_its_table(study_run):
    """study.png, study_profiles.png and study_tornado.png are written; study.png drawn again
    from study.nc: recovery against the throw, one line per injection rate whose points are
    study.csv's; the failed variant of broken_flood is a cross, not a point."""
    import matplotlib.pyplot as plt

    from gridlib.io import study_pictures as sp

    for study in ("flood", "broken_flood"):
        for name in ("study.png", "study_profiles.png", "study_tornado.png"):
            assert (study_run / "results" / study / name).stat().st_size > 5_000, (study, name)
    rows = _rows(study_run, "flood")
    with xr.open_dataset(study_run / "results" / "flood" / "study.nc") as ds:
        fig = sp.study_figure(ds.load())
    try:
        (ax,) = [
            a for a in fig.axes if a.get_ylabel() == "oil recovery [fraction]" and "throw" in a.get_xlabel()
        ]
        means = [line for line in ax.lines if line.get_gid() == sp.MEAN]
        assert [m.get_label() for m in means] == [
            "simulation.wells.0.rate = 300 sm3/day",
            "simulation.wells.0.rate = 600 sm3/day",
        ]
        for line, rate in zip(means, (300, 600), strict=True):
            want = [float(rows[f"throw-{t}_rate-{rate}_r0"]["oil_recovery"]) for t in (0, 15)]
            assert line.get_ydata().tolist() == want
    finally:
        plt.close(fig)
    with xr.open_dataset(study_run / "results" / "broken_flood" / "study.nc") as ds:
        fig = sp.study_figure(ds.load())
    try:
        ax = fig.axes[0]
        (cross,) = [line for line in ax.lines if line.get_gid() == sp.FAILED]
        assert cross.get_xdata().tolist() == [20000]
        points = [line for line in ax.lines if line.get_gid() == sp.REALISATIONS]
        assert [p.get_xdata().tolist() for p in points] == [[210]]
    finally:
        plt.close(fig)


def test_a_second_run_does_nothing_and_one_value_reruns_its_variants_grid_and_flow(study_run):
    again = _snakemake(study_run, "--dry-run")
    assert again.returncode == 0 and "Nothing to be done" in again.stdout + again.stderr, again.stderr[-3000:]
    results = study_run / "results" / "flood"
    before = {p.parent.parent.name: p.stat().st_mtime_ns for p in results.glob("*/simulation/responses.json")}
    edited = copy.deepcopy(FLOOD)
    edited["vary"]["simulation.wells.0.rate"] = [300, 500]  # 600 -> 500: two variants
    _write(study_run / "config" / "studies" / "flood.yaml", edited)
    plan = _snakemake(study_run, "--dry-run", "--quiet", "rules")
    assert plan.returncode == 0, plan.stderr[-3000:]
    assert _job_counts(plan) == {
        "study_flood": 2,
        "study_simulate_flood": 2,
        "study_table_simulated": 1,  # study_table's job with the simulated study's pictures
        "all": 1,
        "total": 6,
    }
    result = _snakemake(study_run)
    assert result.returncode == 0, result.stderr[-3000:]
    after = {p.parent.parent.name: p.stat().st_mtime_ns for p in results.glob("*/simulation/responses.json")}
    assert sorted(n for n in after if before.get(n) != after[n]) == [
        "throw-0_rate-500_r0",
        "throw-15_rate-500_r0",
    ]
    assert {r["simulation.wells.0.rate"] for r in _rows(study_run, "flood").values()} == {"300", "500"}
    assert "Nothing to be done" in _snakemake(study_run, "--dry-run").stdout


def test_on_failure_stop_fails_the_run_naming_the_study_and_the_variant(study_run, tmp_path):
    workdir = tmp_path / "stop"
    shutil.copytree(study_run, workdir, symlinks=True)
    study = _write(workdir / "config" / "studies" / "broken_flood.yaml", BROKEN | {"on_failure": "stop"})
    result = _snakemake(workdir, str(Path("results") / "broken_flood" / "study.csv"))
    assert result.returncode != 0
    line = next((x for x in result.stderr.splitlines() if x.startswith("gridlib: ")), result.stderr[-3000:])
    assert line.startswith(
        f"gridlib: {study}: variant '{FAILING}': simulation failed: OPM Flow was killed by SIGABRT"
    )
    assert not (workdir / "results" / "broken_flood" / FAILING / "simulation").exists()


STUDY_PROBLEMS = {
    "no simulation section": ({"simulate": True}, "simulate", "has no simulation section"),
    "not a report day": (
        {"simulate": True, "responses": {"times": [150]}},
        "responses.times[0]",
        "150 is not a report day",
    ),
    "unknown on_failure": ({"on_failure": "ignore"}, "on_failure", "ignore"),
}


@pytest.mark.parametrize("problem", sorted(STUDY_PROBLEMS))
def test_the_simulation_keys_are_checked_naming_the_study_file_and_key(tmp_path, problem):
    change, key, text = STUDY_PROBLEMS[problem]
    base = copy.deepcopy(BASE)
    if problem == "no simulation section":
        del base["simulation"]
    _write(tmp_path / "config" / "cases" / "tiny_flood.yaml", base)
    spec = {"name": "s", "base": "../cases/tiny_flood.yaml", "vary": {"faults.0.throw": [0]}} | change
    study = _write(tmp_path / "config" / "studies" / "s.yaml", spec)
    with pytest.raises(InputError) as err:
        load_study(study, tmp_path / "results")
    message = str(err.value)
    assert "\n" not in message and message.startswith(f"{study}: {key}") and text in message, message


def test_a_run_that_stops_early_or_writes_no_summary_is_a_failure(study_run, tmp_path):
    """The other two ways a run fails, from a finished variant's files (no Flow run): it ended
    before the variant's last report day, or left no UNSMRY."""
    from gridlib.stages.simulate import failure_reason

    base = _flow_base(study_run, "flood", "throw-0_rate-300_r0")
    done = subprocess.CompletedProcess(["flow"], 0, "", "")
    assert failure_reason(done, base, [100, 200, 400]) is None
    reason = failure_reason(done, base, [100, 200, 400, 800])
    assert reason is not None and reason.startswith("OPM Flow stopped at day 400 of 800: ")
    assert failure_reason(done, tmp_path / base.name, [400]).startswith(
        "OPM Flow wrote no summary (UNSMRY): "
    )
