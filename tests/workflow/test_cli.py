"""The gridlib command: build, info, check, flow-deck; errors are one line and a status."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from gridlib.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_info_of_a_deck(decks_dir, capsys):
    assert main(["info", str(decks_dir / "reek" / "REEK_GRDECL.DATA")]) == 0
    out = capsys.readouterr().out
    assert "40 x 64 x 14 = 35,840 cells, 35,838 active" in out
    assert "faults: 6 (136 FAULTS lines)" in out and "units: METRIC" in out
    assert re.search(r"^depth range: [0-9.]+ to [0-9.]+ m$", out, re.M)


def test_check_of_a_deck_and_an_egrid(decks_dir, capsys):
    assert main(["check", str(decks_dir / "spe9" / "SPE9_CP.DATA")]) == 0
    out = capsys.readouterr().out
    assert "9,000 cells, 28,335 faces" in out and out.rstrip().endswith("OK: every invariant holds")
    # FIELD: 24 x 25 columns of 300 ft x 300 ft, layers 359 ft thick in all: 1.9386e10 ft3
    assert "units: FIELD" in out and "bulk volume (ECLIPSE convention): 1.9386e+10 ft3" in out
    assert "total volume: 1.9386e+10 ft3" in out
    assert main(["check", str(decks_dir / "reek" / "REEK.EGRID")]) == 0
    assert "non-neighbour connections: 2,944" in capsys.readouterr().out


def test_build_then_info_and_check_of_the_netcdf(tmp_path, capsys):
    assert main(["build", str(ROOT / "config" / "cases" / "honeycomb.yaml"), str(tmp_path)]) == 0
    assert (tmp_path / "honeycomb.vtu").is_file()
    assert main(["info", str(tmp_path / "grid.nc")]) == 0
    out = capsys.readouterr().out
    assert "case_name: honeycomb" in out and "units: METRIC" in out
    assert re.search(r"^depth range: [0-9.]+ to [0-9.]+ m$", out, re.M)
    assert main(["check", str(tmp_path / "grid.nc")]) == 0
    out = capsys.readouterr().out
    assert "total volume: 80.5403626" in out
    assert "units: METRIC" in out and "total volume: 80.5403626 m3" in out


def test_flow_deck_of_a_built_case_in_either_form(tmp_path, capsys):
    case = ROOT / "config" / "cases" / "peaks.yaml"
    assert main(["build", str(case), str(tmp_path / "peaks")]) == 0
    assert "form native" in (tmp_path / "peaks" / "flow" / "PEAKS.DATA").read_text()  # the build's own
    capsys.readouterr()
    assert main(["flow-deck", str(tmp_path / "peaks"), str(tmp_path / "deck"), "--form", "connections"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0] == "connection form:" and out[1] == str(tmp_path / "deck" / "PEAKS.DATA")
    assert sorted(p.name for p in (tmp_path / "deck").iterdir()) == [
        "PEAKS.DATA",
        "PEAKS_GRID.INC",
        "PEAKS_NNC.INC",
        "PEAKS_PORV.INC",
    ]
    assert main(["flow-deck", str(tmp_path / "peaks"), str(tmp_path / "native")]) == 0
    assert capsys.readouterr().out.startswith("native form:")
    other = ROOT / "config" / "cases" / "anticline.yaml"
    assert main(["flow-deck", str(tmp_path / "peaks"), str(tmp_path / "x"), "--case", str(other)]) == 2
    assert "case 'anticline', but" in capsys.readouterr().err
    assert main(["flow-deck", str(tmp_path / "nothing"), str(tmp_path / "x")]) == 2
    assert "grid.nc not found" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_errors_are_one_message_and_a_status(tmp_path, capsys):
    assert main(["info", str(tmp_path / "none.DATA")]) == 2
    assert capsys.readouterr().err.strip() == f"gridlib: {tmp_path / 'none.DATA'}: no such file"
    bad = tmp_path / "bad.grdecl"
    bad.write_text("SPECGRID\n 2 2 1 1 F /\nCOORD\n 1 2 3 /\n")
    assert main(["check", str(bad)]) == 2
    assert "bad.grdecl:3: COORD: has 3 values, expected 54" in capsys.readouterr().err
    assert main(["info", str(tmp_path / "x.txt")]) == 2
    assert "unknown file type" in capsys.readouterr().err


def test_the_console_script_is_installed():
    exe = shutil.which("gridlib", path=str(Path(sys.executable).parent))
    if exe is None:
        pytest.fail("the 'gridlib' command is not installed beside this Python (pip install -e .)")
    done = subprocess.run([exe, "--help"], capture_output=True, text=True, check=True)
    assert "gridlib build CASE.yaml OUTDIR" in done.stdout
