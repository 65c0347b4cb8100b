"""The console lines of a run: Snakemake's messages and gridlib's own each reach stderr in one
write, so that a line another process writes at the same moment (a job's note, another job's
failure) comes before or after a message, never inside its last line."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from gridlib.errors import InputError
from gridlib.stages.common import run_logged

ROOT = Path(__file__).resolve().parents[2]

# Parses the workflow in this process (as a run does before it makes its handlers), then makes
# Snakemake's console handler on a stream that records each write and prints one message of
# three lines, as Snakemake prints a failed job's exception.
DRIVER = """
import json, logging, sys
from snakemake.cli import main
from snakemake.logging import ColorizingTextHandler

try:
    main(sys.argv[1:])
except SystemExit as exc:
    assert not exc.code, exc.code

class Recorder:
    writes = []
    def write(self, text):
        if text:  # an empty write writes nothing
            self.writes.append(text)
    def flush(self):
        return None

handler = ColorizingTextHandler(nocolor=True, stream=Recorder())
handler.setFormatter(logging.Formatter("%(message)s"))
for message in ("RuleException:\\nCalledProcessError in line 230:\\nexit status 1.", "one line"):
    handler.emit(logging.LogRecord("snakemake", logging.ERROR, "driver", 1, message, None, None))
print(json.dumps(Recorder.writes))
"""


def test_snakemake_prints_each_message_with_its_line_end_in_one_write(tmp_path):
    case = ROOT / "config" / "cases" / "twisted.yaml"
    result = subprocess.run(
        [sys.executable, "-c", DRIVER, "-s", str(ROOT / "Snakefile"), "--directory", str(tmp_path),
         "--list-rules", "--config", f"cases=[{case}]", "studies=[]"],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr[-3000:]
    writes = json.loads(result.stdout.splitlines()[-1])
    assert writes == ["RuleException:\nCalledProcessError in line 230:\nexit status 1.\n", "one line\n"]


class _Writes:
    def __init__(self):
        self.writes: list[str] = []

    def write(self, text):
        self.writes.append(text)

    def flush(self):
        return None


def test_a_failure_of_several_lines_reaches_stderr_in_one_write(tmp_path, monkeypatch):
    stderr = _Writes()
    monkeypatch.setattr(sys, "stderr", stderr)

    def stage():
        raise InputError("case.yaml: grid: first problem\ncase.yaml: rock: second problem")

    with pytest.raises(SystemExit):
        run_logged(tmp_path / "stage.log", stage, label="case: grid")
    assert stderr.writes == ["gridlib: case.yaml: grid: first problem\ncase.yaml: rock: second problem\n"]
