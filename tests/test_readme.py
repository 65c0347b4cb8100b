"""The README's Python example runs as written."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_example_runs(tmp_path, monkeypatch, capsys):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks, "README has no python example"
    monkeypatch.chdir(tmp_path)
    for code in blocks:
        exec(compile(code, str(README), "exec"), {})
    printed = float(capsys.readouterr().out)
    assert abs(printed - 2e7) <= 1e-9 * 2e7  # the 2e7 m3 the README promises
    assert (tmp_path / "layered.nc").is_file() and (tmp_path / "layered.vtu").is_file()
