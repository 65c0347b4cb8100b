"""Regenerate the golden summaries of the sample cases: ``make golden`` (then review the diff).

Every case in config/cases is run through all its stages (gridlib.stages.run_case, the same
code the workflow runs) in a temporary folder; its summary.json, without the case file's
hash, becomes tests/regression/<case>.json. tests/workflow/test_workflow.py compares every figure of
a workflow run with these files.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

from gridlib.stages import run_case

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).parent


def main() -> None:
    cases = sorted((ROOT / "config" / "cases").glob("*.yaml"))
    with tempfile.TemporaryDirectory() as tmp:
        for case in cases:
            run_case(case, Path(tmp) / case.stem)
            summary = json.loads((Path(tmp) / case.stem / "summary.json").read_text())
            summary.pop("case_sha256", None)
            (HERE / f"{case.stem}.json").write_text(json.dumps(summary, indent=2) + "\n")
            print(f"{case.stem}: {summary['cells']} cells", file=sys.stderr)


if __name__ == "__main__":
    main()
