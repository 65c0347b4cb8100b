"""The README's Python examples run as written and print what the README says."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[2] / "README.md"


def test_readme_python_examples_run(tmp_path, monkeypatch, capsys):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert len(blocks) == 4, "README: library, corner-point, PEBI and horizons/rock examples"
    monkeypatch.chdir(tmp_path)
    outputs = []
    for code in blocks:
        exec(compile(code, str(README), "exec"), {})
        outputs.append(capsys.readouterr().out.strip())
    assert abs(float(outputs[0]) - 2e7) <= 1e-9 * 2e7  # the 2e7 m3 the README promises
    assert (tmp_path / "layered.nc").is_file() and (tmp_path / "layered.vtu").is_file()
    assert outputs[1] == "24 106 14 0.494"  # the seed's figures, as the README says
    # each printed line is what the README says it prints
    text = README.read_text()
    for out in outputs[1:]:
        assert f"prints `{out}`" in text, out
    assert outputs[2] == "943 5658 63 30.0"  # the PEBI example: mean thickness exactly 30 m
    assert outputs[3] == "2500 2050.0 21.7"  # the plane recovered exactly; Carman-Kozeny 21.7 mD
