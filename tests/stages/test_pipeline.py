"""gridlib.stages.pipeline.run_case (the CLI's and the studies' way through every stage)."""

from __future__ import annotations

from pathlib import Path

import yaml

from gridlib.io import read_netcdf
from gridlib.stages import case_outputs, run_case

ROOT = Path(__file__).resolve().parents[2]


def test_run_case_honours_the_case_outputs(tmp_path):
    """outputs.stage_files and vtu false: run_case leaves {case}.nc and the exports, not the
    stage files (nor grid.grdecl, which the Flow deck's GRID include repeats) or the VTU."""
    data = yaml.safe_load((ROOT / "config" / "cases" / "anticline.yaml").read_text())
    data["outputs"] = {"stage_files": False, "vtu": False}
    case = tmp_path / "anticline.yaml"
    case.write_text(yaml.safe_dump(data, sort_keys=False))
    written = run_case(case, tmp_path / "out")
    out = case_outputs("anticline", tmp_path / "out")
    gone = ("horizons", "grid", "grdecl", "geometry", "petrophysics", "coarse", "transmissibility", "vtu")
    assert [k for k in gone if out[k].exists()] == []
    assert all(Path(p).exists() for p in written)
    assert {out[k] for k in ("nc", "faults", "png", "histograms", "summary", "flow_deck")} <= set(
        map(Path, written)
    )
    assert read_netcdf(out["nc"]).grid.num_cells > 0
