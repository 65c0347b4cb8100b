"""The workflow's configuration flags as the docs write them on the command line."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _dry_run(tmp_path: Path, *config: str) -> subprocess.CompletedProcess:
    case = ROOT / "config" / "cases" / "waterflood_pebi.yaml"
    command = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(tmp_path)]
    command += ["-n", "--cores", "1", "--config", f"cases=[{case}]", "studies=[]", *config]
    return subprocess.run(command, capture_output=True, text=True, timeout=300)


@pytest.mark.parametrize(("flag", "simulated"), [("true", True), ("True", True), ("false", False)])
def test_simulate_is_a_boolean_as_yaml_or_python_writes_it(tmp_path, flag, simulated):
    result = _dry_run(tmp_path, f"simulate={flag}")
    assert result.returncode == 0, result.stderr[-2000:]
    assert ("rule simulate_case:" in result.stdout) == simulated


def test_a_flag_that_is_no_boolean_is_one_line_naming_the_key(tmp_path):
    result = _dry_run(tmp_path, "simulate=maybe")
    assert result.returncode != 0
    assert "config: simulate: 'maybe' is not of type 'boolean'" in result.stderr.splitlines()
