"""The Snakemake workflow end to end on the sample cases, in a scratch directory.

One run of every sample case (two cores), then: every artifact opens in the
tools people use (xarray, xugrid, pyvista, OPM Flow for grid.grdecl), every
figure equals the reviewed golden summary (tests/regression/), a second run
does nothing, an edited case reruns only its own jobs, the same case and seed
give identical arrays, and the report opens on the cases.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
import time
import zipfile
from pathlib import Path

import numpy as np
import pytest
import pyvista as pv
import xarray as xr
import yaml
from artifacts import assert_same_files
from flow_tools import rest_of_deck
from variants import other_machine, run_python

import gridlib as gl
from gridlib.config import load_case
from gridlib.io import read_geometry_netcdf as read_geometry
from gridlib.io import read_netcdf

ROOT = Path(__file__).resolve().parents[2]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile")]
GREEDY = ["--scheduler", "greedy"]  # as workflow/profiles/default (make run)
GOLDEN = ROOT / "tests" / "regression"
CASES = sorted(p.stem for p in (ROOT / "config" / "cases").glob("*.yaml"))
SAMPLES = {c: load_case(ROOT / "config" / "cases" / f"{c}.yaml") for c in CASES}
# Relative tolerance of the float figures against the golden summaries: the grids are
# deterministic; the margin covers numpy/BLAS versions summing in other orders.
RTOL = 1e-9


def _snakemake(workdir: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        # --force-use-threads as workflow/profiles/default (make run): the sample study's variants
        # (config/studies/) run in warm worker processes; its greedy scheduler too (Snakemake's
        # default solves an integer program in a CBC process for each choice of jobs).
        [*SNAKEMAKE, "--directory", str(workdir), "--cores", "2", "--force-use-threads", *GREEDY, *args],
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
    pictures = ["", "_histograms", "_plan", "_quality"] + (["_section"] if SAMPLES[case].is_3d else [])
    for picture in pictures:
        assert (folder / f"{case}{picture}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    for rule in ("grid", "geometry", "export"):
        log = (workflow_run / "results" / "logs" / case / f"{rule}.log").read_text()
        benchmark = _benchmark(workflow_run / "results" / "benchmarks" / case / f"{rule}.tsv")
        _assert_benchmark_is_the_logged_stage(benchmark, log)


def _benchmark(path: Path) -> dict[str, str]:
    """A benchmark file's one record (Snakemake's tab-separated header and values)."""
    header, values = path.read_text().splitlines()
    return dict(zip(header.split("\t"), values.split("\t"), strict=True))


def _assert_benchmark_is_the_logged_stage(benchmark: dict[str, str], log: str) -> None:
    """A `run:` job's benchmark record holds what its own process used (the workflow records it,
    gridlib.stages.job_usage), not samples of Snakemake's processes: its peak memory and CPU
    time are those the stage's log gives (to their rounding, plus what the job's process did
    around the stage), its wall time at least the stage's."""
    seconds, cpu, peak = re.findall(r": ([\d.]+) s, ([\d.]+) s of CPU, peak memory (\d+) MiB", log)[-1]
    assert float(benchmark["s"]) >= float(seconds) - 0.06, (benchmark, log)
    assert float(peak) - 0.51 <= float(benchmark["max_rss"]) < float(peak) + 2, (benchmark, log)
    assert float(cpu) - 0.06 <= float(benchmark["cpu_time"]) < float(cpu) + 0.5, (benchmark, log)
    assert float(benchmark["io_out"]) > 0 and benchmark["max_vms"] == "-", benchmark


@pytest.mark.parametrize("case", CASES)
def test_the_3d_view_of_every_case_says_what_it_shows(workflow_run, case):
    """The 3-D view's scene as the pictures stage builds it, read from its objects: axes in the
    case's length unit with depth, the colour bar's quantity and unit, the stated vertical
    exaggeration (3-D grids), one actor and legend entry per fault with faces, the wells named."""
    from gridlib.io.grid_view import grid_scene
    from gridlib.stages.pictures import read_scene, view_arguments

    folder = workflow_run / "results" / case
    given = {key: folder / f"{key}.nc" for key in ("petrophysics", "transmissibility", "wells")}
    scene = read_scene(
        SAMPLES[case],
        folder / "grid.nc",
        folder / "geometry.nc",
        **{k: p for k, p in given.items() if p.exists()},
    )
    arguments = view_arguments(SAMPLES[case], scene, folder / f"{case}_faults.vtp")
    plotter = grid_scene(**arguments, window_size=(320, 240))
    try:
        unit = {"METRIC": "m", "FIELD": "ft"}[
            json.loads((folder / "summary.json").read_text())["unit_system"]
        ]
        axes = plotter.renderer.cube_axes_actor
        assert (axes.x_title, axes.y_title) == (f"x (east) [{unit}]", f"y (north) [{unit}]")
        plain = f"depth [{unit}]" if scene.grid.dim == 3 else f"cell area [{unit}2]"
        quantity = "porosity [fraction]" if given["petrophysics"].exists() else plain
        assert list(plotter.scalar_bars.keys()) == [quantity]
        if scene.grid.griddim == 3:
            assert axes.z_title == f"depth [{unit}]"
            assert re.fullmatch(r"vertical exaggeration \d+x", plotter.actors["exaggeration"].GetInput())
        faults = pv.read(folder / f"{case}_faults.vtp")
        names = list(faults.field_data["fault_names"])
        drawn = [names[k - 1] for k in np.unique(faults.cell_data["fault"])] if faults.n_cells else []
        assert sorted(k[len("fault ") :] for k in plotter.actors if k.startswith("fault ")) == sorted(drawn)
        legend = plotter.legend
        entries = (
            [legend.GetEntryString(k) for k in range(legend.GetNumberOfEntries())]
            if legend is not None
            else []
        )
        assert entries == drawn
        vertical = [w["name"] for w in SAMPLES[case].data.get("wells", []) if "point" in w]
        if vertical:
            labels = plotter.actors["well labels-labels"].GetMapper().GetInputAlgorithm().GetInput()
            array = labels.GetPointData().GetAbstractArray("labels")
            assert set(vertical) <= {array.GetValue(k) for k in range(array.GetNumberOfValues())}
    finally:
        plotter.close()


@pytest.mark.parametrize("case", CASES)
def test_every_case_has_a_plan_view_and_section_that_say_what_they_show(workflow_run, case):
    """The plan view and cross-section of every sample case, drawn again in process from the
    run's stage files as the pictures stage draws them, read from the figure objects: axes
    and colour bars labelled with the case's units, every fault and well of the case named
    on the plan, every well on the section (its default line runs through them), the faults
    it crosses named, scale bar and north arrow, contour levels inside the top's depth range,
    the vertical exaggeration stated."""
    import matplotlib.pyplot as plt

    from gridlib.io import picture_style as style
    from gridlib.io.cross_section import EXAGGERATION
    from gridlib.io.plan_view import FAULT_NAME, WELL_NAME
    from gridlib.io.section_cut import cut_grid
    from gridlib.stages import case_outputs
    from gridlib.stages.pictures import case_figures, read_scene, section_line

    loaded = load_case(workflow_run / "config" / "cases" / f"{case}.yaml")
    paths = case_outputs(case, workflow_run / "results" / case)
    optional = {k: paths[k] for k in ("petrophysics", "transmissibility", "wells") if paths[k].exists()}
    scene = read_scene(loaded, paths["grid"], paths["geometry"], **optional)
    figures = case_figures(loaded, scene, with_section=loaded.is_3d)
    unit = {"FIELD": "ft", "METRIC": "m"}[scene.units.name]
    wells = sorted(w["name"] for w in loaded.data.get("wells", []))

    def named(ax, gid):
        return sorted(t.get_text() for t in ax.texts if t.get_gid() == gid)

    plan, plan_bar = figures["plan"].axes
    assert (plan.get_xlabel(), plan.get_ylabel()) == (f"x [{unit}]", f"y [{unit}]")
    assert named(plan, FAULT_NAME) == sorted(scene.fault_names)
    assert named(plan, WELL_NAME) == wells
    (scale,) = style.named(plan, style.SCALE_BAR)
    assert scale.txt_label.get_text().endswith(f" {unit}")
    assert len(style.named(plan, style.NORTH_ARROW)) == 1
    if not loaded.is_3d:
        assert plan_bar.get_ylabel() in ("porosity [fraction]", f"cell area [{unit}2]")
        assert "section" not in figures
        return
    assert plan_bar.get_ylabel() == f"top depth [{unit}]"
    lines = [c for c in plan.collections if type(c).__name__ == "TriContourSet" and not c.filled]
    top = [c for c in plan.collections if type(c).__name__ == "TriContourSet" and c.filled]
    if top:  # a top that is not flat: its levels inside the depth range
        lo, hi = top[0].levels[0], top[0].levels[-1]
        assert all(lo < level < hi for c in lines for level in c.levels)
    section, section_bar = figures["section"].axes
    assert (section.get_xlabel(), section.get_ylabel()) == (
        f"distance along the section [{unit}]",
        f"depth [{unit}]",
    )
    assert section_bar.get_ylabel() in ("porosity [fraction]", "zone", "layer", f"depth [{unit}]")
    assert section.get_ylim()[0] > section.get_ylim()[1]  # depth down
    (exaggeration,) = named(section, EXAGGERATION)
    assert re.fullmatch(r"vertical exaggeration (1|2|5|10)x", exaggeration)
    assert named(section, WELL_NAME) == wells
    crossed = np.unique(
        cut_grid(scene.grid, section_line(loaded, scene, scene.well_tracks(loaded))).fault_ids
    )
    assert named(section, FAULT_NAME) == sorted(scene.fault_names[k - 1] for k in crossed)
    for figure in figures.values():
        plt.close(figure)


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


@pytest.mark.parametrize("case", ["anticline", "faulted_pebi"])
def test_every_netcdf_artifact_is_compressed_and_opens_lazily(workflow_run, case):
    """chunks={}: dask arrays in the file's compressed chunks, equal to an eager read."""
    paths = sorted((workflow_run / "results" / case).glob("*.nc"))
    assert {p.name for p in paths} >= {"grid.nc", "geometry.nc", "petrophysics.nc", f"{case}.nc"}
    for path in paths:
        with xr.open_dataset(path, chunks={}) as lazy, xr.open_dataset(path) as eager:
            for name in eager.variables:
                variable = lazy[name].variable
                if eager[name].dtype.kind in "biuf" and eager[name].ndim and eager[name].size:
                    assert variable.encoding.get("zstd") or variable.encoding.get("zlib"), (path.name, name)
                    if name not in lazy.indexes:
                        assert type(variable.data).__module__.startswith("dask"), (path.name, name)
                        row = eager[name].dtype.itemsize * int(np.prod(eager[name].shape[1:]))
                        assert variable.data.chunks[0][0] * row <= 1 << 20, (path.name, name)
                floats = eager[name].dtype.kind == "f"
                same = np.array_equal(lazy[name].values, eager[name].values, equal_nan=floats)
                assert same, (path.name, name)


def test_the_summary_table_lists_every_case(workflow_run):
    lines = (workflow_run / "results" / "summary.csv").read_text().splitlines()
    assert lines[0].startswith("case,grid_type,griddim,cells")
    assert [line.split(",")[0] for line in lines[1:]] == CASES


def test_the_sample_study_is_built(workflow_run):
    """config/studies/waterflood_throw.yaml: 2 throws x 2 realisations of waterflood_pebi."""
    study = workflow_run / "results" / "waterflood_throw"
    lines = (study / "study.csv").read_text().splitlines()
    assert lines[0].startswith("variant,faults.0.throw [m],realisation,seed,")
    variants = [f"throw-{t}_r{r}" for t in (0, 30) for r in (0, 1)]
    assert [line.split(",")[0] for line in lines[1:]] == variants
    assert (study / "throw-30_r1" / "flow" / "THROW-30_R1.DATA").is_file()
    with xr.open_dataset(study / "study.nc") as ds:
        assert dict(ds.sizes) == {"faults.0.throw": 2, "realisation": 2}


def test_the_grid_choice_study_is_built_and_simulated(workflow_run):
    """config/studies/grid_choice.yaml: three grids of y_faults_pillars as whole `grid` sections
    (pillars, stair steps, PEBI) at 80 and 40 m, two realisations, each variant simulated; the
    corner-point variants keep a GRDECL file, the PEBI ones do not (a rule each)."""
    import csv

    study = workflow_run / "results" / "grid_choice"
    with (study / "study.csv").open() as f:
        rows = list(csv.DictReader(f))
    labels = [f"{g}-{s}m" for g in ("pillars", "stairs", "pebi") for s in (80, 40)]
    assert [r["variant"] for r in rows] == [f"grid-{lab}_r{k}" for lab in labels for k in (0, 1)]
    for r in rows:  # a variant's job in a warm worker: its own figures, not the worker's so far
        log = (workflow_run / "results" / "logs" / "grid_choice" / f"{r['variant']}.log").read_text()
        benchmark = _benchmark(
            workflow_run / "results" / "benchmarks" / "grid_choice" / f"{r['variant']}.tsv"
        )
        _assert_benchmark_is_the_logged_stage(benchmark, log)
    assert [r["grid"] for r in rows] == [lab for lab in labels for _ in (0, 1)]
    assert {r["simulation"] for r in rows} == {"ok"}
    assert [r["grid_type"] for r in rows] == ["cornerpoint"] * 8 + ["pebi"] * 4
    for r in rows:
        assert (study / r["variant"] / "grid.grdecl").is_file() == (r["grid_type"] == "cornerpoint")
    # every deck has the same wells, controls and report steps (only the grid differs)
    decks = [(study / v / "flow" / f"{v.upper()}.DATA").read_text() for v in (r["variant"] for r in rows)]
    controls = {d[d.index("WCONINJE") :] for d in decks}
    assert len(controls) == 1 and "TSTEP" in next(iter(controls))
    assert {tuple(re.findall(r"^ '(\w+)' 'G' ", d, re.MULTILINE)) for d in decks} == {("INJ", "PROD")}


def test_the_readmes_study_example_runs_on_the_sample_study(workflow_run, monkeypatch, capsys):
    """README.md's ```py block (a study's table and dataset read back) as written, in the
    folder the workflow ran in."""
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    (code,) = [b for b in re.findall(r"```py\n(.*?)```", readme, flags=re.S) if "study.csv" in b]
    monkeypatch.chdir(workflow_run)
    exec(compile(code, "README.md", "exec"), {})
    out = capsys.readouterr().out
    assert "faults.0.throw" in out and "throw-30_r1" in out, out


def test_the_report_opens_on_the_cases_with_the_rule_graph_last(workflow_run):
    """The report (as README.md says to make it): its menu lists the cases' pictures first,
    then the summary table (Snakemake sorts categories by name); its landing page is the
    workflow's description (metadata given: not the rule graph), the cases' pictures linked
    first, then the summary table, then the studies (a subcategory each)."""
    config = f"cases={workflow_run / 'config' / 'cases'}/*.yaml"
    report = workflow_run / "results" / "report.zip"
    metadata = ROOT / "workflow" / "report" / "metadata.yaml"
    result = _snakemake(
        workflow_run, "--config", config, "--report", str(report), "--report-metadata", str(metadata)
    )
    assert result.returncode == 0, result.stderr[-2000:]
    assert report.stat().st_size > 10_000
    with zipfile.ZipFile(report) as z:
        html = z.read("report/report.html").decode()

    def variable(name: str):  # the report's data: one line of JSON each (the last: vendored JS has its own)
        return json.loads(re.findall(rf"^\s*var {name} = (.*);$", html, flags=re.M)[-1])

    categories = variable("categories")
    assert sorted(categories)[:2] == ["1. Cases", "2. Summary"]  # the menu's order
    assert sorted(categories["1. Cases"]) == CASES  # one subcategory per case
    for case in CASES:
        pictures = {Path(p).name for p in categories["1. Cases"][case]}
        assert {f"{case}.png", f"{case}_histograms.png"} <= pictures, case
        assert (f"{case}_residuals.png" in pictures) == (case == "faulted_picks"), case
    assert categories["2. Summary"] == {"Other": ["results/summary.csv"]}
    assert variable("metadata") == {"cases": len(CASES)}  # metadata: the landing page is the description
    description = variable("workflow_desc")
    assert "Error" not in description and "WARNING" not in description
    sections = re.findall(r"<h1>(.*?)</h1>", description)
    assert sections == ["Cases", "Summary", "Studies"]
    study = {Path(p).name for p in categories["4. Studies"]["waterflood_throw"]}  # a section per study
    assert {"study.csv", "study.png"} <= study
    for case in CASES:
        assert f"showResultInfo('results/{case}/{case}.png')" in description
    assert description.index("showResultInfo('results/summary.csv')") > description.index("anticline.png")


def test_grdecl_outputs_are_read_by_opm_flow(workflow_run, tmp_path):
    from flow_tools import flow_executable
    from test_flow_export import run_flow_on_grdecl

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
    assert len(case_jobs) == 5  # grid, geometry, quality, export and pictures (and the summary table)


def test_every_case_with_rock_has_a_flow_deck_and_snakemake_simulate_runs_flow(workflow_run, tmp_path):
    """Every case with rock on a 3-D grid has flow/<NAME>.DATA (native for corner-point and deck
    grids, the connection form otherwise) with its provenance, which Flow's dry run reads without
    a warning, with our pore volumes; `snakemake simulate` runs OPM Flow on the cases with a
    `simulation` section, with a log and a benchmark, and a second run does nothing."""
    from flow_tools import flow_executable, read_keywords, run_flow_dry

    for case, sample in SAMPLES.items():
        folder = workflow_run / "results" / case
        deck = folder / "flow" / f"{case.upper()}.DATA"
        assert deck.is_file() == sample.writes_flow_deck, case
        if not deck.is_file():
            continue
        text = deck.read_text()
        summary = json.loads((folder / "summary.json").read_text())
        assert f"case sha256 {summary['case_sha256']}" in text and f"gridlib {gl.__version__}" in text
        form = "native" if sample.writes_grdecl else "connections"
        assert f"-- form {form}" in text, case
        assert (workflow_run / "results" / "logs" / case / f"flow_deck.{case.upper()}.log").is_file()
    flow_executable()
    for case, sample in SAMPLES.items():  # Flow reads every deck, warns about nothing, has our PORV
        if not sample.writes_flow_deck:
            continue
        folder = workflow_run / "results" / case
        result = run_flow_dry(folder / "flow" / f"{case.upper()}.DATA", tmp_path / case)
        prt = Path(f"{result}.PRT").read_text()
        assert [line.split()[1] for line in prt.splitlines() if line.startswith("Warnings")][-1] == "0", case
        with xr.open_dataset(folder / "transmissibility.nc") as ds:
            index, porv = ds["cell_flow_index"].values, ds["porv"].values
        flow_porv = read_keywords(Path(f"{result}.INIT"))["PORV"].astype(np.float64)
        np.testing.assert_allclose(flow_porv[index], porv, rtol=1e-6, err_msg=case)
    config = ["--config", f"cases={workflow_run / 'config' / 'cases'}/*.yaml"]
    result = _snakemake(workflow_run, "simulate", *config)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    simulated = [case for case, sample in SAMPLES.items() if sample.has_simulation]
    assert sorted(simulated) == [
        "inclined_pebi",
        "trajectories_cp",
        "trajectories_pebi",
        "waterflood_cp",
        "waterflood_pebi",
        "y_faults_pillars",
        "y_faults_stairs",
    ]
    for case in simulated:
        folder = workflow_run / "results" / case / "flow"
        figures = json.loads((folder / "summary.json").read_text())
        days = SAMPLES[case].data["simulation"]["report_days"]
        assert figures["simulated_days"] == days[-1] and figures["report_days"] == days
        assert figures["field"]["FOPT"] > 0 and figures["case_sha256"] == SAMPLES[case].sha256
        assert (folder / f"{case}_wells.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        series = pv.PVDReader(folder / f"{case}_flow.pvd")
        assert series.time_values == [0.0, *days]  # the initial state and every report step
        assert series.read()[0].n_cells == read_netcdf(folder.parent / "grid.nc").grid.num_cells
        for suffix in (".PRT", ".SMSPEC", ".UNSMRY", ".EGRID", ".INIT", ".UNRST"):
            assert (folder / f"{case.upper()}{suffix}").is_file(), suffix
        assert (workflow_run / "results" / "logs" / case / "simulate.log").is_file()
        assert (workflow_run / "results" / "benchmarks" / case / "simulate.tsv").is_file()
        assert not list(folder.glob(".*.run-*"))
    again = _snakemake(workflow_run, "simulate", *config, "--dry-run")
    assert "Nothing to be done" in again.stdout + again.stderr


# Cases whose numbers go through random fields, fault throws, PEBI sites, well rings, formula
# horizons, METIS and well paths: the places where BLAS, SIMD code or threads could change a bit.
DETERMINISM_CASES = (
    "anticline",
    "composite_wells",
    "faulted_pebi",
    "faulted_picks",
    "peaks",
    "trajectories_pebi",
)


def test_same_case_and_seed_give_identical_files_on_another_machine(workflow_run, tmp_path):
    """Every Snakemake job ran with one thread. The same case files run again in a fresh
    process with two BLAS/OpenMP/gridlib threads, an older CPU's BLAS kernels and numpy's
    SIMD code switched off (tests/variants.py): every variable and attribute of every
    netCDF file, the GRDECL, VTU and VTP files and summary.json are identical. (The run
    draws no pictures: its PNG files are not compared, tests/artifacts.py.)"""
    cases = workflow_run / "config" / "cases"
    again = tmp_path / "again"
    run_python(
        f"import sys; sys.path.insert(0, {str(ROOT / 'tests')!r})\n"
        "from artifacts import run_case_without_pictures\n"
        f"cases, again = {str(cases)!r}, {str(again)!r}\n"
        f"for name in {DETERMINISM_CASES!r}:\n"
        "    run_case_without_pictures(f'{cases}/{name}.yaml', f'{again}/{name}')\n",
        other_machine(),
    )
    for case in DETERMINISM_CASES:
        names = assert_same_files(workflow_run / "results" / case, again / case)
        assert {"grid.nc", "geometry.nc", f"{case}.nc", f"{case}.vtu", "summary.json"} <= set(names)
        decks = [name for name in names if name.startswith("flow/")]
        assert bool(decks) == SAMPLES[case].writes_flow_deck, (case, decks)


# --- the transmissibility stage -----------------------------------------------------------


def _expected_connections(grid, writes_grdecl: bool) -> tuple[np.ndarray, np.ndarray]:
    """The cell pairs of the grid's interior faces (sorted, unique) and the kind each should get:
    logical neighbours (index step 1, nx, nx ny), else for decks a pair of one column (pinch)
    or a fault pair; without logical indices, fault-tagged faces (fault) or other."""
    nb = grid.faces.neighbors
    inner = np.flatnonzero((nb >= 0).all(axis=1))
    pairs = np.sort(nb[inner], axis=1)
    if grid.cells.index_map is not None and grid.cart_dims is not None:
        dims = list(grid.cart_dims) + [1] * (3 - len(grid.cart_dims))
        g = grid.cells.index_map[pairs]
        step = g[:, 1] - g[:, 0]
        column = g[:, 0] % (dims[0] * dims[1]) == g[:, 1] % (dims[0] * dims[1])
        kind = np.where(np.isin(step, [1, dims[0], dims[0] * dims[1]]), 0, 1)
        if writes_grdecl:
            kind = np.where((kind == 1) & column, 2, kind)
    else:
        kind = np.where(grid.faces.tag[inner] > 0, 1, 3)
    unique, inverse = np.unique(pairs, axis=0, return_inverse=True)
    kinds = np.full(unique.shape[0], 127)
    np.minimum.at(kinds, inverse.ravel(), kind)
    return unique, kinds


@pytest.mark.parametrize("case", CASES)
def test_transmissibility_files_hold_every_interior_face(workflow_run, case):
    folder = workflow_run / "results" / case
    path = folder / "transmissibility.nc"
    if not SAMPLES[case].has_petrophysics:
        assert not path.exists()  # no rock, no transmissibilities
        return
    summary = json.loads((folder / "summary.json").read_text())
    data = read_netcdf(folder / "grid.nc")
    grid = data.grid
    with xr.open_dataset(path) as ds:
        assert ds.attrs["case_sha256"] == summary["case_sha256"]
        assert ds.attrs["gridlib_version"] == gl.__version__
        assert ds.attrs["unit_system"] == summary["unit_system"] == ("FIELD" if case == "spe9" else "METRIC")
        assert ds["trans"].attrs["units"] == ds.attrs["trans_units"]
        assert ds["porv"].attrs["units"] == ("rb" if case == "spe9" else "rm3")
        cells, trans, kind = (ds[v].values for v in ("connection_cells", "trans", "connection_kind"))
        face, porv, flow_index = (ds[v].values for v in ("connection_face", "porv", "cell_flow_index"))
        variables = {v: ds[v].values for v in ds.data_vars}
        dims = tuple(int(v) for v in ds.attrs["flow_dims"])
    pairs, kinds = _expected_connections(grid, SAMPLES[case].writes_grdecl)
    np.testing.assert_array_equal(cells, pairs)  # one connection per pair of cells sharing a face
    np.testing.assert_array_equal(np.bincount(kind, minlength=4), np.bincount(kinds, minlength=4))
    assert summary["connections"] == trans.size and (trans > 0).all() and np.isfinite(trans).all()
    for k, name in enumerate(("neighbor", "fault", "pinch", "other")):
        assert summary[f"{name}_connections"] == int((kind == k).sum())
    assert summary["median_trans"] == pytest.approx(np.median(trans), rel=1e-11)
    nb = np.sort(grid.faces.neighbors[face], axis=1)
    np.testing.assert_array_equal(nb, cells)  # the face lies between the two cells
    assert porv.shape == (grid.num_cells,) and (porv > 0).all()
    assert porv.sum() == pytest.approx(summary["total_porv"], rel=1e-11)
    if grid.cart_dims is not None:  # the logical box: a deck's, or cart_dims
        np.testing.assert_array_equal(flow_index, grid.cells.index_map)
        assert dims == tuple(grid.cart_dims)
    else:  # layered: k is the layer
        lay = grid.layering
        np.testing.assert_array_equal(flow_index, lay.column + lay.areal.num_cells * lay.layer)
        assert dims == (lay.areal.num_cells, 1, lay.num_layers)
    assert np.unique(flow_index).size == grid.num_cells and flow_index.max() < np.prod(dims)
    with xr.open_dataset(folder / f"{case}.nc") as one:  # the self-describing file carries them all
        for name, values in variables.items():
            np.testing.assert_array_equal(one[name].values, values, err_msg=name)
        assert one["trans"].attrs["units"] == one.attrs["trans_units"]
    faults = pv.read(folder / f"{case}_faults.vtp")
    fault_faces = np.flatnonzero(grid.faces.tag > 0)
    want = np.zeros(grid.num_faces)
    want[face] = trans  # sample cases: one face per connection
    np.testing.assert_array_equal(faults.cell_data["trans"], want[fault_faces])
    assert (workflow_run / "results" / "logs" / case / "transmissibility.log").is_file()
    assert (workflow_run / "results" / "benchmarks" / case / "transmissibility.tsv").is_file()


FLOW_DECK = """\
-- OPM Flow dry run of a case's grid.grdecl written again with the case's rock
RUNSPEC
DIMENS
 {nx} {ny} {nz} /
OIL
WATER
{units}
TABDIMS
 1 1 20 20 /
EQLDIMS
 1 /
START
 1 'JAN' 2020 /
UNIFOUT
GRID
INIT
INCLUDE
 'rock.grdecl' /
{rest}"""


@pytest.mark.parametrize("case", ["anticline", "spe9"])
def test_corner_point_transmissibilities_equal_opm_flow(workflow_run, case, tmp_path):
    """The case's grid.grdecl with its PERMX/PERMY/PERMZ/NTG/PORO, through Flow's dry run: the same
    connections, T and pore volumes (Flow's INIT holds float32: 1e-6 relative)."""
    from flow_tools import flow_connections, flow_executable, read_keywords, run_flow_dry

    flow_executable()
    folder = workflow_run / "results" / case
    deck = gl.read_grdecl(folder / "grid.grdecl")
    index = read_netcdf(folder / "grid.nc").grid.cells.index_map
    rock = {}
    with xr.open_dataset(folder / "petrophysics.nc") as petro:
        for key in ("PORO", "PERMX", "PERMY", "PERMZ", "NTG"):
            rock[key] = np.zeros(deck.num_cells)
            rock[key][index] = petro[key.lower()].values
    gl.write_grdecl(tmp_path / "rock.grdecl", deck, rock)
    with xr.open_dataset(folder / "transmissibility.nc") as ds:
        units = ds.attrs["unit_system"]
        pairs = np.sort(ds["cell_flow_index"].values[ds["connection_cells"].values], axis=1)
        ours = dict(zip(map(tuple, pairs.tolist()), ds["trans"].values.tolist(), strict=True))
        porv = ds["porv"].values
    finite = deck.zcorn[np.isfinite(deck.zcorn)]
    nx, ny, nz = deck.cart_dims
    text = FLOW_DECK.format(
        nx=nx, ny=ny, nz=nz, units=units, rest=rest_of_deck(finite.min(), finite.max() + 1)
    )
    (tmp_path / "CASE.DATA").write_text(text)
    result = run_flow_dry(tmp_path / "CASE.DATA", tmp_path / "out")
    flow = flow_connections(result)
    assert sorted(ours) == sorted(flow)
    both = sorted(flow)
    np.testing.assert_allclose([ours[p] for p in both], [flow[p] for p in both], rtol=1e-6)
    init = read_keywords(result.with_suffix(".INIT"))
    np.testing.assert_allclose(porv, init["PORV"].astype(np.float64)[index], rtol=1e-6)


def test_pebi_lateral_transmissibility_is_k_area_over_site_distance(workflow_run):
    """faulted_pebi (dipping layers, faults with throw, well rings; NTG 1, PERMX = PERMY): the T of
    every connection between two columns is K A / d to 1e-12, A the area of the faces between
    the two cells, d the distance of their sites, K the harmonic mean of their permeabilities."""
    from gridlib.transmissibility import face_connections
    from gridlib.units import METRIC

    folder = workflow_run / "results" / "faulted_pebi"
    stored = read_netcdf(folder / "grid.nc")
    grid, site = stored.grid, stored.cell_data["site"]
    geo = read_geometry(folder / "geometry.nc")
    with xr.open_dataset(folder / "petrophysics.nc") as petro:
        k, ky, ntg = petro["permx"].values, petro["permy"].values, petro["ntg"].values
    assert np.array_equal(k, ky) and (ntg == 1.0).all()
    with xr.open_dataset(folder / "transmissibility.nc") as ds:
        cells, trans = ds["connection_cells"].values, ds["trans"].values
    conn = face_connections(grid.faces.neighbors, cells)
    area = np.bincount(conn[conn >= 0], geo.face_areas[conn >= 0], cells.shape[0])
    a, b = cells[:, 0], cells[:, 1]
    lateral = grid.layering.column[a] != grid.layering.column[b]
    assert lateral.sum() > 0.7 * cells.shape[0]
    d = np.hypot(*(site[a] - site[b])[lateral].T)
    k_ab = 2.0 * k[a] * k[b] / (k[a] + k[b])
    expected = k_ab[lateral] * area[lateral] / d * METRIC.darcy_constant
    np.testing.assert_allclose(trans[lateral], expected, rtol=1e-12)
    away = np.hypot(*(geo.cell_centroids[:, :2] - site).T)  # centroids would not do: cells off their site
    assert (away[a[lateral]] > 1e-3 * d).sum() > 100


def test_a_case_without_stage_files_keeps_one_file_that_every_reader_opens(workflow_run, tmp_path):
    """outputs.stage_files and vtu false: the per-stage files are gone after the run (and the
    VTU is not written), a second run does
    nothing, and {case}.nc gives every reader the same arrays the stage files held (the
    geometry's face vectors recomputed from the grid, to the bit)."""
    from gridlib.io.rock_file import read_rock
    from gridlib.io.transmissibility_file import CELL_VARS, CONNECTION_VARS, read_transmissibility

    cases = tmp_path / "config" / "cases"
    cases.mkdir(parents=True)
    data = yaml.safe_load((ROOT / "config" / "cases" / "anticline.yaml").read_text())
    data["outputs"] = {"stage_files": False, "vtu": False}
    (cases / "anticline.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    config = ["--config", f"cases={cases}/*.yaml", "studies=[]"]
    result = _snakemake(tmp_path, *config)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    folder, kept = tmp_path / "results" / "anticline", workflow_run / "results" / "anticline"
    stage_files = (
        "horizons.nc",
        "grid.nc",
        "geometry.nc",
        "petrophysics.nc",
        "coarse.nc",
        "transmissibility.nc",
        "quality.nc",
    )
    assert [name for name in stage_files if (folder / name).exists()] == []
    assert not (folder / "anticline.vtu").exists() and (kept / "anticline.vtu").exists()
    assert all((kept / name).exists() for name in stage_files)
    # the Flow deck's GRID include holds the grid: grid.grdecl is a stage file here
    assert not (folder / "grid.grdecl").exists() and (folder / "flow" / "ANTICLINE_GRID.INC").exists()
    assert (kept / "grid.grdecl").exists() and (folder / "flow" / "ANTICLINE.DATA").exists()
    assert "Nothing to be done" in (lambda r: r.stdout + r.stderr)(_snakemake(tmp_path, *config, "--dry-run"))

    one = folder / "anticline.nc"
    with xr.open_dataset(one) as ds:
        assert "face_normal" not in ds and "face_centroid" not in ds and "face_area" in ds
    with xr.open_dataset(one) as ds, xr.open_dataset(kept / "grid.nc") as grid_ds:
        assert all(np.array_equal(ds[n].values, grid_ds[n].values) for n in grid_ds.data_vars), "grid.nc"
    stored = read_netcdf(one)
    geo = read_geometry(kept / "geometry.nc")
    for field in ("cell_volumes", "cell_centroids", "face_areas", "face_normals", "face_centroids"):
        assert np.array_equal(getattr(stored.geometry, field), getattr(geo, field)), field
    rock, rock_one = read_rock(kept / "petrophysics.nc"), read_rock(one)
    assert rock.keys() == rock_one.keys() and all(np.array_equal(rock[k], rock_one[k]) for k in rock)
    names = CONNECTION_VARS + CELL_VARS
    t, t_one = read_transmissibility(kept / "transmissibility.nc")[0], read_transmissibility(one)[0]
    assert all(np.array_equal(t[n].values, t_one[n].values) for n in names)
    with xr.open_dataset(kept / "coarse.nc") as coarse:
        assert np.array_equal(stored.cell_data["block"], coarse["partition"].values)


def test_stages_read_uncompressed_artifacts_of_older_gridlib(workflow_run, tmp_path):
    """Artifacts written before compression (contiguous, unfiltered netCDF-4) still feed the
    stages: the transmissibility and export stages on uncompressed copies of anticline's stage
    files give the same connections, {case}.nc variables and summary."""
    from gridlib.config import load_case
    from gridlib.stages import stage_export, stage_transmissibility

    kept = workflow_run / "results" / "anticline"
    old = tmp_path / "old"
    old.mkdir()
    for name in ("grid.nc", "geometry.nc", "petrophysics.nc", "coarse.nc"):
        with xr.open_dataset(kept / name) as ds:
            ds = ds.load()
        for variable in ds.variables.values():
            variable.encoding = {}  # contiguous, no filter: as gridlib wrote them before
        del ds.attrs["gridlib_digest"]  # and without a digest
        ds.to_netcdf(old / name, engine="netcdf4")
        with xr.open_dataset(old / name) as ds:
            assert not any(ds[v].encoding.get(f) for v in ds.variables for f in ("zstd", "zlib", "shuffle"))
    case = load_case(workflow_run / "config" / "cases" / "anticline.yaml")
    trans = tmp_path / "transmissibility.nc"
    stage_files = {key: old / f"{key}.nc" for key in ("grid", "geometry", "petrophysics")}
    stage_transmissibility(case, **stage_files, transmissibility=trans, grdecl=kept / "grid.grdecl")
    with xr.open_dataset(trans) as got, xr.open_dataset(kept / "transmissibility.nc") as want:
        assert all(np.array_equal(got[v].values, want[v].values) for v in want.data_vars)
    outputs = {k: str(tmp_path / f"out.{k}") for k in ("nc", "vtu", "summary")}
    outputs["faults"] = str(tmp_path / "faults.vtp")
    quality = kept / "quality.nc"
    stage_export(
        case, **stage_files, coarse=old / "coarse.nc", transmissibility=trans, quality=quality, **outputs
    )
    with xr.open_dataset(outputs["nc"]) as got, xr.open_dataset(kept / "anticline.nc") as want:
        assert set(got.data_vars) == set(want.data_vars)
        assert all(np.array_equal(got[v].values, want[v].values) for v in want.data_vars)
    assert json.loads(Path(outputs["summary"]).read_text()) == json.loads((kept / "summary.json").read_text())


def _expected_units(system: str, griddim: int) -> dict[str, str]:
    """The ``units`` of every physical variable gridlib writes, written out by hand: a FIELD
    deck's in feet (spe9), every other sample case's in metres; a 2-D grid's cells measure
    areas and its faces lengths."""
    length = {"FIELD": "ft", "METRIC": "m"}[system]
    cell, face = (f"{length}3", f"{length}2") if griddim == 3 else (f"{length}2", length)
    coordinates = ("node_x", "node_y", "node_z", "cell_centroid", "face_centroid", "depth", "site")
    units = dict.fromkeys(coordinates, length)
    units |= dict.fromkeys(("cell_volume", "volume", "pore_volume", "cell_normal"), cell)
    units |= dict.fromkeys(("face_area", "face_normal"), face)
    units |= {
        "bulk_volume": f"{length}3",
        "poro": "1",
        "ntg": "1",
        "permx": "mD",
        "permy": "mD",
        "permz": "mD",
    }
    units |= {"porv": {"FIELD": "rb", "METRIC": "rm3"}[system]}
    units |= {"trans": {"FIELD": "cP rb/(day psi)", "METRIC": "cP m3/(day bar)"}[system]}
    # wells.nc (cases with trajectory wells): paths, measured depths and connection factors
    well_lengths = ("well_radius", "path_xyz", "path_md", "perforation_md", "completion_length")
    well_lengths += tuple(f"completion_{k}" for k in ("entry_md", "exit_md", "entry", "exit", "axis_length"))
    units |= dict.fromkeys(well_lengths, length)
    units |= {"well_skin": "1", "completion_factor": units["trans"]}
    # quality.nc, {case}.nc: the cell-quality measures, in degrees or 1 in every unit system (flags: none)
    angles = [f"{a}angle_{b}" for a in ("min", "max") for b in ("topbase", "topbase_proj", "sides")]
    units |= dict.fromkeys((*angles, "twist", "orientation_error", "k_orientation_error"), "degree")
    units |= dict.fromkeys(("aspect_ratio", "face_nonplanarity"), "1")
    return units


# horizons.nc: only for grids gridlib builds, in metres; the names of its horizons, the fault
# block of each lattice node and each pick's horizon and block are no quantity.
HORIZONS_UNITS = {"depth": "m", "depth_by_block": "m", "x": "m", "y": "m"}
HORIZONS_UNITS |= dict.fromkeys(("pick_x", "pick_y", "pick_depth", "pick_residual"), "m")
HORIZONS_NAMES = ("horizon", "source", "method", "block", "pick_horizon", "pick_block")


def _base_name(name: str) -> str:
    """A UGRID footprint's or layered view's variable: the name of what it shows."""
    for prefix in ("mesh2d_", "areal_"):
        name = name.removeprefix(prefix) if name != "mesh2d" else name
    return name.removesuffix("_layered")


@pytest.mark.parametrize("case", CASES)
def test_every_physical_variable_of_every_netcdf_file_has_its_unit(workflow_run, case):
    """Issue 24, item 7: every variable of every netCDF file of a case carries the unit of its
    values in the case's unit system (spe9: FIELD, ft, ft2, ft3, rb, mD, cP rb/(day psi)), or is
    no physical quantity (indices, flags, topology: no units, as CF wants)."""
    from gridlib.io.quantities import quantity_of

    folder = workflow_run / "results" / case
    summary = json.loads((folder / "summary.json").read_text())
    system = summary["unit_system"]
    assert system == ("FIELD" if case == "spe9" else "METRIC")
    expected = _expected_units(system, summary["griddim"])
    paths = sorted(folder.glob("*.nc"))
    assert {"grid.nc", "geometry.nc", f"{case}.nc"} <= {p.name for p in paths}
    seen = set()
    for path in paths:
        with xr.open_dataset(path, decode_cf=False) as ds:
            if path.name not in ("horizons.nc", "petrophysics.nc"):  # these are always METRIC/any
                assert ds.attrs["unit_system"] == system, path.name
            for name in ds.variables:
                base = _base_name(str(name))
                if path.name == "horizons.nc":
                    assert ds[name].attrs.get("units") == HORIZONS_UNITS.get(name), name
                    assert name in HORIZONS_UNITS or name in HORIZONS_NAMES, name
                elif base in expected:
                    assert ds[name].attrs.get("units") == expected[base], (path.name, name)
                    seen.add(expected[base])
                else:
                    assert quantity_of(str(name)) is None, (path.name, name)  # KeyError: undecided
                    assert "units" not in ds[name].attrs, (path.name, name)
    if case == "spe9":
        assert {"ft", "ft2", "ft3", "rb", "mD", "cP rb/(day psi)", "1"} <= seen
        with xr.open_dataset(folder / "spe9.nc") as ds:
            assert ds.attrs["unit_system"] == "FIELD" and ds.attrs["porv_units"] == "rb"


def _units_in_header(column: str, row: dict[str, str]) -> str | None:
    """The unit a summary.csv/study.csv header gives for ``row``: ``name [unit]`` or
    ``name [unit: SYSTEM[ n-D][ / ...]; ...]``; None for a column without a unit."""
    if " [" not in column:
        return None
    text = column.split(" [", 1)[1].removesuffix("]")
    if ": " not in text:
        return text
    for part in text.split("; "):
        unit, where = part.rsplit(": ", 1)
        for condition in where.split(" / "):
            words = condition.split()
            if words[0] == row["unit_system"] and (len(words) == 1 or words[1] == f"{row['griddim']}-D"):
                return unit
    raise AssertionError(f"{column}: no unit for {row['unit_system']} {row['griddim']}-D")


def test_summary_and_study_tables_give_every_figure_its_unit(workflow_run):
    """summary.csv mixes spe9 (FIELD) with METRIC cases and the 2-D twisted: each row's unit in
    the header, by its unit_system and griddim; the study of one METRIC case: one unit per
    column, the same in study.nc."""
    import csv

    with open(workflow_run / "results" / "summary.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    by_case = {r["case"]: r for r in rows}
    header = list(rows[0])

    def unit(case: str, figure: str) -> str | None:
        column = next(c for c in header if c.split(" [")[0] == figure)
        return _units_in_header(column, by_case[case])

    assert [unit("spe9", f) for f in ("total_volume", "pore_volume", "total_porv", "mean_permx")] == [
        "ft3",
        "ft3",
        "rb",
        "mD",
    ]
    assert (
        unit("spe9", "max_trans") == "cP rb/(day psi)" and unit("anticline", "max_trans") == "cP m3/(day bar)"
    )
    assert [unit("anticline", f) for f in ("total_volume", "total_porv", "mean_porosity")] == [
        "m3",
        "rm3",
        "1",
    ]
    assert unit("twisted", "total_volume") == "m2" and unit("twisted", "cells") is None
    assert by_case["twisted"]["unit_system"] == "METRIC"  # every row says its system
    study = workflow_run / "results" / "waterflood_throw"
    with open(study / "study.csv", newline="") as f:
        columns = next(csv.reader(f))
    assert {
        "pore_volume [m3]",
        "total_porv [rm3]",
        "median_trans [cP m3/(day bar)]",
        "mean_porosity [1]",
    } <= set(columns)
    with xr.open_dataset(study / "study.nc") as ds:
        assert ds["pore_volume"].attrs["units"] == "m3" and ds["total_porv"].attrs["units"] == "rm3"
        assert ds["median_trans"].attrs["units"] == "cP m3/(day bar)" and "units" not in ds["cells"].attrs
