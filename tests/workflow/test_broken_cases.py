"""A corpus of broken case files: each run stops with one message naming the case file and the
key, and leaves nothing under results/{case}/."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

HORIZONS = """horizons:
  lattice: {x: {start: 0, stop: 1000, num: 11}, y: {start: 0, stop: 800, num: 9}}
  surfaces:
    - {name: top, plane: {depth: 1000}}
    - {name: base, plane: {depth: 1040}}
"""
PEBI = (
    HORIZONS
    + """grid:
  type: pebi
  domain: {rectangle: [0, 0, 1000, 800]}
  cell_size: 100
  layers: 2
"""
)

BROKEN = {
    "misspelled_key": (
        "grid: {type: cartesian, dims: [2, 2], lenghts: [1, 1]}\n",
        r"grid: Additional properties are not allowed ('lenghts' was unexpected)",
    ),
    "wrong_type": (
        "grid: {type: cartesian, dims: [2, ten]}\n",
        "grid.dims[1]: 'ten' is not of type 'integer'",
    ),
    "missing_points_file": (
        PEBI.replace("{name: base, plane: {depth: 1040}}", "{name: base, points: base_picks.xyz}"),
        "horizons.surfaces[1].points: file 'base_picks.xyz' not found",
    ),
    "crossing_horizons": (
        PEBI.replace("plane: {depth: 1040}", "plane: {depth: 990, dip: 5, azimuth: 90}"),
        "horizons cross: horizons 'top' and 'base' cross at 18 nodes",
    ),
    "fault_outside": (
        PEBI + "faults:\n  - {name: FX, trace: [[2000, 0], [2000, 800]], throw: 5}\n",
        "faults[0].trace: fault 'FX' lies entirely outside the domain",
    ),
    "well_outside": (
        PEBI + "wells:\n  - {name: P9, point: [1500, 400], rings: {inner: 1, outer: 50}}\n",
        "wells[0].point: well 'P9' at (1500, 400) lies outside the domain",
    ),
    "zero_layers": (PEBI.replace("layers: 2", "layers: 0"), "grid.layers: 0 is less than the minimum of 1"),
    "simulated_well_outside": (
        "grid: {type: cartesian, dims: [4, 4, 2], lengths: [400, 400, 20], origin: [0, 0, 1000]}\n"
        "petrophysics: {porosity: {constant: 0.2}, permeability: {constant: 100}}\n"
        "wells:\n  - {name: W, point: [500, 100]}\n"
        "simulation: {wells: [{name: W, type: producer, bhp: 50}], report_days: [10]}\n",
        "wells[0].point: well 'W' at (500, 100) lies outside the domain",
    ),
    "simulated_well_unknown": (
        PEBI
        + "petrophysics: {porosity: {constant: 0.2}}\n"
        + "wells:\n  - {name: P1, point: [500, 400]}\n"
        + "simulation: {wells: [{name: P2, type: producer, bhp: 50}], report_days: [10]}\n",
        "simulation.wells[0].name: 'P2' is not among the case's wells (wells: P1)",
    ),
    "unknown_grid_type": (
        "grid: {type: hexahedral, dims: [2, 2]}\n",
        "grid.type: 'hexahedral' is not one of",
    ),
    "malformed_yaml": ("grid: {type: cartesian, dims: [2, 2]\n", "not valid YAML"),
}


@pytest.mark.parametrize("name", sorted(BROKEN))
def test_a_broken_case_fails_clearly_and_leaves_nothing(tmp_path, name):
    text, message = BROKEN[name]
    case = tmp_path / "config" / f"{name}.yaml"
    case.parent.mkdir()
    case.write_text(f"name: {name}\n{text}")
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "snakemake",
            "-s",
            str(ROOT / "Snakefile"),
            "--directory",
            str(tmp_path),
            "--cores",
            "1",
            "--config",
            f"cases=[{case}]",
            "studies=[]",
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    out = result.stdout + result.stderr
    assert result.returncode != 0
    lines = [line for line in out.splitlines() if str(case) in line and message in line]
    assert lines, f"no line names {case} and says {message!r}:\n{out[-3000:]}"
    folder = tmp_path / "results" / name
    left = [p for p in folder.rglob("*") if p.is_file()] if folder.exists() else []
    assert left == [], f"{name} left {left}"


def test_every_broken_case_of_a_run_is_named_in_that_run(tmp_path):
    """Three case files, two broken (and one valid): both broken ones are named, one line each,
    with no traceback; the run stops before any job, so no case leaves a results folder."""
    config = tmp_path / "config"
    config.mkdir()
    files = {}
    for name in ("wrong_type", "fault_outside"):
        text, message = BROKEN[name]
        files[name] = (config / f"{name}.yaml", message)
        files[name][0].write_text(f"name: {name}\n{text}")
    good = config / "good.yaml"
    good.write_text("name: good\ngrid: {type: cartesian, dims: [2, 2]}\n")
    cases = ",".join(str(p) for p in sorted([good, *(f for f, _ in files.values())]))
    result = subprocess.run(
        [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(tmp_path),
         "--cores", "1", "--config", f"cases=[{cases}]", "studies=[]"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    out = result.stdout + result.stderr
    assert result.returncode != 0
    for path, message in files.values():
        assert [line for line in out.splitlines() if line == f"{path}: {message}"], out[-3000:]
    assert "2 problem(s) in the case files; nothing was run" in out
    assert "Traceback" not in out and 'File "' not in out, out[-3000:]
    assert not (tmp_path / "results").exists() or not any((tmp_path / "results").rglob("*.*"))
