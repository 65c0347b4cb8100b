"""The Snakemake workflow end to end on the sample cases, in a scratch directory."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import pyvista as pv

import gridlib as gl
from gridlib.io import read_geometry_netcdf as read_geometry
from gridlib.io import read_netcdf

ROOT = Path(__file__).resolve().parents[1]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile")]


def _snakemake(workdir: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [*SNAKEMAKE, "--directory", str(workdir), "--cores", "2", *args],
        capture_output=True,
        text=True,
        timeout=600,
    )


@pytest.fixture(scope="module")
def workflow_run(tmp_path_factory):
    """The workflow on copies of the sample cases (so tests may touch them)."""
    workdir = tmp_path_factory.mktemp("workflow")
    cases = workdir / "cases"
    cases.mkdir()
    for path in (ROOT / "config" / "cases").glob("*.yaml"):
        shutil.copy(path, cases / path.name)
    result = _snakemake(workdir, "--config", f"cases={cases}/*.yaml")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return workdir


EXPECTED = {  # case: (cells, total volume (m3, or m2 for 2-D))
    "ellipsoid": (2128, 17.024),
    "honeycomb": (120, 80.540362552),
    "radial_well": (1205, 30.6146745892),
    "twisted": (600, 60000.0),
}


@pytest.mark.parametrize("case", sorted(EXPECTED))
def test_every_case_has_checked_artifacts(workflow_run, case):
    cells, volume = EXPECTED[case]
    folder = workflow_run / "results" / case
    data = read_netcdf(folder / "grid.nc")
    assert data.grid.num_cells == cells
    assert data.attrs["case_name"] == case and len(data.attrs["case_sha256"]) == 64
    assert data.attrs["gridlib_version"] == gl.__version__
    geo = read_geometry(folder / "geometry.nc")
    assert geo.cell_volumes.sum() == pytest.approx(volume, rel=1e-9)
    gl.check_grid(data.grid, geo)
    mesh = pv.read(folder / f"{case}.vtu")
    assert mesh.n_cells == cells
    np.testing.assert_allclose(mesh.cell_data["volume"], geo.cell_volumes, rtol=0, atol=0)
    for rule in ("grid", "geometry", "export_vtu"):
        assert (workflow_run / "results" / "logs" / case / f"{rule}.log").is_file()
        assert (workflow_run / "results" / "benchmarks" / case / f"{rule}.tsv").is_file()


def test_second_run_does_nothing_and_an_edited_case_reruns_only_itself(workflow_run):
    config = ["--config", f"cases={workflow_run / 'cases'}/*.yaml"]
    result = _snakemake(workflow_run, *config, "--dry-run")
    assert "Nothing to be done" in result.stdout + result.stderr
    # Snakemake >= 9.18 compares input checksums, so an edit (not a bare touch) reruns.
    edited = workflow_run / "cases" / "honeycomb.yaml"
    edited.write_text(edited.read_text() + "# edited\n")
    later = time.time() + 5
    os.utime(edited, (later, later))
    result = _snakemake(workflow_run, *config, "--dry-run")
    out = result.stdout + result.stderr
    jobs = [line.split(":", 1)[1].strip() for line in out.splitlines() if line.strip().startswith("output:")]
    assert jobs and all("/honeycomb/" in job for job in jobs), out
    assert len(jobs) == 3  # grid, geometry and export of that case only


def test_a_bad_case_stops_the_workflow_with_a_clear_message(tmp_path):
    bad = tmp_path / "broken.yaml"
    bad.write_text("name: broken\ngrid: {type: cartesian, dims: [2, -1]}\n")
    result = _snakemake(tmp_path, "--config", f"cases=[{bad}]")
    assert result.returncode != 0
    assert "broken.yaml: grid.dims[1]: -1 is less than the minimum of 1" in result.stdout + result.stderr
    assert not (tmp_path / "results").exists()
