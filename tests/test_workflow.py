"""The Snakemake workflow end to end on the sample cases, in a scratch directory.

One run of every sample case (two cores), then: every artifact opens in the
tools people use (xarray, xugrid, pyvista, OPM Flow for grid.grdecl), every
figure equals the reviewed golden summary (tests/regression/), a second run
does nothing, an edited case reruns only its own jobs, the same case and seed
give identical arrays, and the report zip is produced.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import pyvista as pv
import xarray as xr

import gridlib as gl
from gridlib.io import read_geometry_netcdf as read_geometry
from gridlib.io import read_netcdf

ROOT = Path(__file__).resolve().parents[1]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile")]
GOLDEN = ROOT / "tests" / "regression"
CASES = sorted(p.stem for p in (ROOT / "config" / "cases").glob("*.yaml"))
# Relative tolerance of the float figures against the golden summaries: the grids are
# deterministic; the margin covers numpy/BLAS versions summing in other orders.
RTOL = 1e-9


def _snakemake(workdir: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [*SNAKEMAKE, "--directory", str(workdir), "--cores", "2", *args],
        capture_output=True,
        text=True,
        timeout=900,
    )


def copy_cases(workdir: Path) -> Path:
    """The sample cases and the decks they use, copied so that tests may edit them."""
    cases = workdir / "config" / "cases"
    shutil.copytree(ROOT / "config" / "cases", cases)
    shutil.copytree(ROOT / "config" / "decks", workdir / "config" / "decks")
    return cases


@pytest.fixture(scope="module")
def workflow_run(tmp_path_factory):
    workdir = tmp_path_factory.mktemp("workflow")
    cases = copy_cases(workdir)
    result = _snakemake(workdir, "--config", f"cases={cases}/*.yaml")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return workdir


@pytest.mark.parametrize("case", CASES)
def test_every_case_has_checked_artifacts_that_open(workflow_run, case):
    folder = workflow_run / "results" / case
    summary = json.loads((folder / "summary.json").read_text())
    data = read_netcdf(folder / "grid.nc")
    assert data.grid.num_cells == summary["cells"]
    assert data.attrs["case_name"] == case and len(data.attrs["case_sha256"]) == 64
    assert data.attrs["gridlib_version"] == gl.__version__
    geo = read_geometry(folder / "geometry.nc")
    assert geo.cell_volumes.sum() == pytest.approx(summary["total_volume"], rel=1e-11)
    gl.check_grid(data.grid, geo)
    netcdf = ["grid.nc", "geometry.nc", f"{case}.nc"] + [p.name for p in folder.glob("[pch]*.nc")]
    for name in netcdf:
        with xr.open_dataset(folder / name) as ds:  # every .nc opens with xarray
            assert ds.attrs["case_sha256"] == summary["case_sha256"]
    mesh = pv.read(folder / f"{case}.vtu")
    assert mesh.n_cells == summary["cells"]
    np.testing.assert_array_equal(mesh.cell_data["volume"], geo.cell_volumes)
    if (folder / "petrophysics.nc").exists():
        assert "poro" in mesh.cell_data and "permx" in mesh.cell_data
    faults = pv.read(folder / f"{case}_faults.vtp")
    assert faults.n_cells == summary["fault_faces"]
    for picture in (f"{case}.png", f"{case}_histograms.png"):
        assert (folder / picture).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    for rule in ("grid", "geometry", "export"):
        assert (workflow_run / "results" / "logs" / case / f"{rule}.log").is_file()
        assert (workflow_run / "results" / "benchmarks" / case / f"{rule}.tsv").is_file()


@pytest.mark.parametrize("case", CASES)
def test_figures_equal_the_golden_summaries(workflow_run, case):
    """Regression: make golden regenerates tests/regression/ deliberately (review the diff)."""
    got = json.loads((workflow_run / "results" / case / "summary.json").read_text())
    want = json.loads((GOLDEN / f"{case}.json").read_text())
    want.pop("case_sha256", None)
    for key, expected in want.items():
        if isinstance(expected, float):
            assert got[key] == pytest.approx(expected, rel=RTOL), key
        else:
            assert got[key] == expected, key


def test_the_ugrid_footprint_opens_with_xugrid(workflow_run):
    import xugrid  # a test dependency: a missing install fails here, it never skips

    folder = workflow_run / "results" / "faulted_pebi"
    ds = xugrid.open_dataset(folder / "faulted_pebi.nc")
    assert ds.ugrid.grid.n_face == read_netcdf(folder / "grid.nc").grid.layering.areal.num_cells
    twisted = xugrid.open_dataset(workflow_run / "results" / "twisted" / "twisted.nc")
    assert twisted.ugrid.grid.n_face == 600


def test_the_summary_table_lists_every_case(workflow_run):
    lines = (workflow_run / "results" / "summary.csv").read_text().splitlines()
    assert lines[0].startswith("case,grid_type,griddim,cells")
    assert [line.split(",")[0] for line in lines[1:]] == CASES


def test_the_report_zip_is_produced(workflow_run):
    config = f"cases={workflow_run / 'config' / 'cases'}/*.yaml"
    result = _snakemake(
        workflow_run, "--config", config, "--report", str(workflow_run / "results" / "report.zip")
    )
    assert result.returncode == 0, result.stderr[-2000:]
    assert (workflow_run / "results" / "report.zip").stat().st_size > 10_000


def test_grdecl_outputs_are_read_by_opm_flow(workflow_run, tmp_path):
    from test_flow_export import flow_executable, run_flow_on_grdecl

    flow = flow_executable()
    for case in ("peaks", "anticline", "faulted_picks", "spe9"):
        folder = workflow_run / "results" / case
        ours = read_netcdf(folder / "grid.nc")
        units = "FIELD" if case == "spe9" else "METRIC"
        ref = run_flow_on_grdecl(flow, folder / "grid.grdecl", tmp_path / case, units=units, poro=0.2)
        np.testing.assert_array_equal(np.flatnonzero(ref["ACTNUM"] > 0), ours.grid.cells.index_map)
        bulk = ours.cell_data["bulk_volume"]
        porv = ref["PORV"].astype(np.float64)[ours.grid.cells.index_map]
        factor = 9702 / 1728 if int(ref["INTEHEAD"][2]) == 2 else 1.0  # FIELD decks: rb -> ft3
        np.testing.assert_allclose(porv * factor / 0.2, bulk, rtol=1e-6)  # the wrapper's PORO is 0.2


def test_second_run_does_nothing_and_an_edited_case_reruns_only_itself(workflow_run):
    config = ["--config", f"cases={workflow_run / 'config' / 'cases'}/*.yaml"]
    result = _snakemake(workflow_run, *config, "--dry-run")
    assert "Nothing to be done" in result.stdout + result.stderr
    # Snakemake >= 9.18 compares input checksums, so an edit (not a bare touch) reruns.
    edited = workflow_run / "config" / "cases" / "honeycomb.yaml"
    edited.write_text(edited.read_text() + "# edited\n")
    later = time.time() + 5
    os.utime(edited, (later, later))
    result = _snakemake(workflow_run, *config, "--dry-run")
    out = result.stdout + result.stderr
    jobs = [line.split(":", 1)[1].strip() for line in out.splitlines() if line.strip().startswith("output:")]
    case_jobs = [job for job in jobs if "summary.csv" not in job]
    assert case_jobs and all("/honeycomb/" in job for job in case_jobs), out
    assert len(case_jobs) == 3  # grid, geometry and export of that case (and the summary table)


def test_same_case_and_seed_give_identical_arrays(workflow_run, tmp_path):
    """The anticline (random fields, faults, coarsening) built again elsewhere: identical arrays."""
    from gridlib.stages import run_case

    again = tmp_path / "again"
    run_case(workflow_run / "config" / "cases" / "anticline.yaml", again)
    first = workflow_run / "results" / "anticline"
    for name in ("grid.nc", "geometry.nc", "petrophysics.nc", "coarse.nc", "anticline.nc"):
        with xr.open_dataset(first / name) as a, xr.open_dataset(again / name) as b:
            assert sorted(a.variables) == sorted(b.variables)
            for var in a.variables:
                np.testing.assert_array_equal(a[var].values, b[var].values, err_msg=f"{name}: {var}")
