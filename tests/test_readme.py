"""The README's Python examples run as written and print what the README says."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_examples_run(tmp_path, monkeypatch, capsys):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert len(blocks) == 2, "README has a library example and a corner-point example"
    monkeypatch.chdir(tmp_path)
    outputs = []
    for code in blocks:
        exec(compile(code, str(README), "exec"), {})
        outputs.append(capsys.readouterr().out.strip())
    assert abs(float(outputs[0]) - 2e7) <= 1e-9 * 2e7  # the 2e7 m3 the README promises
    assert (tmp_path / "layered.nc").is_file() and (tmp_path / "layered.vtu").is_file()
    assert outputs[1] == "24 106 14 0.494"  # the seed's figures, as the README says
    assert "prints `24 106 14 0.494`" in README.read_text()
