"""gridlib.stages.pipeline.run_case (the CLI's and the studies' way through every stage)."""

from __future__ import annotations

from pathlib import Path

import yaml
from artifacts import run_case_without_pictures

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
    pictures = ("png", "histograms", "plan", "section")
    assert {out[k] for k in ("nc", "faults", *pictures, "summary", "flow_deck")} <= set(map(Path, written))
    assert read_netcdf(out["nc"]).grid.num_cells > 0


def test_the_anticline_vtu_is_the_right_way_up(tmp_path):
    """The case's VTU stores elevation (z = -depth): the crest, the shallowest cell, is the
    highest; its ``depth`` is the geometry's centroid depth; VTK's polyhedra have our volumes.
    (Built without pictures: the test reads {case}.nc and the VTU.)"""
    import numpy as np
    import pyvista as pv

    from gridlib.geometry import compute_geometry

    data = yaml.safe_load((ROOT / "config" / "cases" / "anticline.yaml").read_text())
    data["outputs"] = {"stage_files": False, "vtu": True}
    case = tmp_path / "anticline.yaml"
    case.write_text(yaml.safe_dump(data, sort_keys=False))
    run_case_without_pictures(case, tmp_path / "out")
    out = case_outputs("anticline", tmp_path / "out")
    grid = read_netcdf(out["nc"]).grid
    geo = compute_geometry(grid)
    mesh = pv.read(out["vtu"])
    np.testing.assert_array_equal(mesh.points[:, 2], -grid.nodes.coords[:, 2])
    np.testing.assert_array_equal(mesh.cell_data["depth"], geo.cell_centroids[:, 2])
    top = mesh.cell_centers().points[:, 2]
    assert top[np.argmin(mesh.cell_data["depth"])] == top.max()
    volumes = mesh.compute_cell_sizes(length=False, area=False, volume=True).cell_data["Volume"]
    assert volumes.min() > 0
    # warped faces: VTK triangulates them its own way, up to half a per cent from our volumes
    np.testing.assert_allclose(volumes, geo.cell_volumes, rtol=1e-2)


def test_a_stage_the_case_does_not_have_is_named(tmp_path):
    """run_stage of a stage the case's sections do not ask for (here coarsen, wells) is one
    error naming the case and the stage, not a missing-argument TypeError from the stage."""
    import pytest

    from gridlib.config import load_case
    from gridlib.stages import run_stage

    case = load_case(Path(__file__).parents[2] / "config" / "cases" / "twisted.yaml")
    paths = case_outputs(case.name, tmp_path)
    for name in ("coarsen", "wells"):
        with pytest.raises(ValueError, match=rf"twisted.yaml: the case has no {name} stage"):
            run_stage(name, case, paths)
