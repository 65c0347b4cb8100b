"""gridlib.artifacts: the one table of stages and artifacts that run_case, the Snakemake rules and
the studies derive from; a stage added through it alone (one entry and one function) runs in
both run_case and Snakemake."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from gridlib import artifacts
from gridlib.config import load_case
from gridlib.stages import case_outputs, run_case
from gridlib.study import artifacts_of

ROOT = Path(__file__).resolve().parents[2]
PICTURES = ["png", "histograms", "plan", "section"]  # stage pictures' artifacts (section: 3-D grids)

# A plugin module of a user's own: one stage (its function and its entry), nothing else.
TOY_STAGE = '''
from pathlib import Path

from gridlib.artifacts import Artifact, Stage, register_stage
from gridlib.io.netcdf import read_netcdf


def stage_cell_count(case, *, grid, geometry, cell_count):
    """The number of cells of the case's grid, as text."""
    Path(cell_count).write_text(f"{case.name}: {read_netcdf(grid).grid.num_cells} cells\\n")


register_stage(
    Stage(
        "cell_count",
        stage_cell_count,
        ("grid", "geometry"),
        (Artifact("cell_count", "cell_count.txt"),),
        doc="The grid's number of cells.",
    ),
    after="geometry",
)
'''

CASE = {
    "name": "toy",
    "grid": {"type": "cartesian", "dims": [4, 3, 2], "lengths": [40.0, 30.0, 4.0]},
    # The stage's run is what these tests are about; the pictures (most of a small case's build,
    # read by no test here) are drawn by the sample cases' run in test_workflow.py.
    "outputs": {"pictures": False},
}


@pytest.fixture
def toy(tmp_path, monkeypatch):
    """The toy stage's module in ``tmp_path`` (importable there), the table restored after the
    test, and a 24-cell case file."""
    (tmp_path / "toy_stage.py").write_text(TOY_STAGE)
    monkeypatch.setattr(artifacts, "STAGES", artifacts.STAGES)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "toy_stage", raising=False)
    case = tmp_path / "config" / "toy.yaml"
    case.parent.mkdir()
    case.write_text(yaml.safe_dump(CASE, sort_keys=False))
    return case


def test_a_stage_added_through_the_table_runs_in_run_case(toy, tmp_path):
    import toy_stage  # noqa: F401  (registers the stage)

    names = [stage.name for stage in artifacts.STAGES]
    assert names.index("cell_count") == names.index("geometry") + 1
    written = run_case(toy, tmp_path / "out")
    assert tmp_path / "out" / "cell_count.txt" in written
    assert (tmp_path / "out" / "cell_count.txt").read_text() == "toy: 24 cells\n"


def test_a_stage_added_through_the_table_runs_in_snakemake(toy, tmp_path):
    env = {**os.environ, "PYTHONPATH": f"{tmp_path}:{ROOT}"}
    command = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(tmp_path)]
    config = ["--config", f"cases=[{toy}]", "studies=[]", "plugins=[toy_stage]"]
    result = subprocess.run(  # run: jobs in Snakemake's threads, as make run's profile has them
        [*command, "--cores", "1", "--force-use-threads", *config],
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
    )
    assert result.returncode == 0, result.stderr[-3000:]
    assert (tmp_path / "results" / "toy" / "cell_count.txt").read_text() == "toy: 24 cells\n"
    assert "rule cell_count:" in result.stderr + result.stdout
    log = (tmp_path / "results" / "logs" / "toy" / "cell_count.log").read_text()
    assert "stage_cell_count: " in log  # the run's cost, logged under the stage's name
    assert "run in the job server" in log  # a local run's jobs: in its warm process (the plugin's too)
    again = subprocess.run(
        [*command, "--cores", "1", "-n", *config], capture_output=True, text=True, timeout=300, env=env
    )
    assert "Nothing to be done" in again.stdout + again.stderr  # the stage's output is up to date


def test_a_plugin_that_does_not_import_stops_the_run_naming_it(tmp_path):
    result = subprocess.run(
        [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(tmp_path)]
        + ["--cores", "1", "-n", "--config", "cases=[]", "studies=[]", "plugins=[no_such_plugin]"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode != 0
    assert "config: plugins: cannot import 'no_such_plugin'" in result.stderr


def test_every_sample_case_has_the_artifacts_of_its_sections():
    """What the table says each sample case builds (the stage files, grid.grdecl for corner-point
    and deck grids, wells.nc where it has trajectory or survey wells, the exports with their
    paths, the Flow deck where it has rock)."""
    expected = {
        "anticline": "horizons grid grdecl geometry petrophysics coarse transmissibility QUALITY flow_deck",
        "composite_wells": "horizons grid geometry QUALITY",
        "ellipsoid": "grid geometry QUALITY",
        "faulted_pebi": "horizons grid geometry petrophysics coarse transmissibility QUALITY flow_deck",
        "spe9": "grid grdecl geometry petrophysics coarse transmissibility QUALITY flow_deck",
        "trajectories_cp": "horizons grid grdecl geometry petrophysics transmissibility QUALITY wells "
        "flow_deck",
    }
    expected = {name: keys.replace("QUALITY", "quality quality_png") for name, keys in expected.items()}
    for name, keys in expected.items():
        case = load_case(ROOT / "config" / "cases" / f"{name}.yaml")
        got = [a.key for a in artifacts.case_artifacts(case)]
        stage_files = keys.split()
        wells = "wells" in stage_files
        exports = ["nc", "vtu", "faults"] + (["well_paths"] if wells else []) + ["summary"] + PICTURES
        exchange = (["roff"] if "grdecl" in stage_files else []) + (
            ["exchange"] if "horizons" in stage_files else []
        )
        assert got == [k for k in stage_files if k != "flow_deck"] + exports + exchange + (
            ["flow_deck"] if "flow_deck" in stage_files else []
        ), name
        assert artifacts.dropped(case) == ()
        assert ("wells" in artifacts.stage_inputs(artifacts.producers()["flow_deck"], case)) == wells


def test_a_case_without_stage_files_drops_them_and_its_grdecl_where_its_flow_deck_repeats_it():
    case = load_case(ROOT / "config" / "cases" / "anticline.yaml")
    dropping = type(case)(
        case.name,
        case.path,
        case.sha256,
        {**case.data, "outputs": {**case.data["outputs"], "stage_files": False}},
    )
    assert artifacts.dropped(dropping) == (
        "horizons",
        "grid",
        "grdecl",
        "geometry",
        "petrophysics",
        "coarse",
        "transmissibility",
        "quality",
    )
    no_deck = {**dropping.data}
    del no_deck["petrophysics"], no_deck["coarsen"]
    bare = type(case)(case.name, case.path, case.sha256, no_deck)
    # grid.grdecl is its only GRDECL: kept
    assert artifacts.dropped(bare) == ("horizons", "grid", "geometry", "quality")
    assert artifacts_of(dropping.data) == (
        "quality_png",
        "nc",
        "vtu",
        "faults",
        "summary",
        *PICTURES,
        "roff",
        "exchange",
        "flow",
    )


def test_paths_and_simulation_artifacts_come_from_the_table(tmp_path):
    paths = case_outputs("anticline", tmp_path)
    assert paths["flow_deck"] == tmp_path / "flow" / "ANTICLINE.DATA"
    assert paths["flow_wells"] == tmp_path / "flow" / "anticline_wells.png"
    assert paths["histograms"] == tmp_path / "anticline_histograms.png"
    assert paths["plan"] == tmp_path / "anticline_plan.png"
    assert paths["section"] == tmp_path / "anticline_section.png"
    simulate = artifacts.producers()["flow_summary"]
    assert simulate.on_request and simulate.inputs == ("flow_deck", "grid", "transmissibility")


def test_an_artifact_written_by_two_stages_is_refused(monkeypatch):
    monkeypatch.setattr(artifacts, "STAGES", artifacts.STAGES)
    twin = artifacts.Stage("twin", "x:y", (), (artifacts.Artifact("grid", "other.nc"),))
    with pytest.raises(ValueError, match="stage 'twin': artifact 'grid' is another stage's output"):
        artifacts.register_stage(twin)


def test_a_stage_reads_only_what_earlier_stages_write(monkeypatch):
    monkeypatch.setattr(artifacts, "STAGES", artifacts.STAGES)
    early = artifacts.Stage("early", "x:y", ("geometry",), (artifacts.Artifact("early", "early.txt"),))
    with pytest.raises(
        ValueError, match="stage 'early': its inputs 'geometry' are no earlier stage's outputs"
    ):
        artifacts.register_stage(early, after="horizons")
    with pytest.raises(ValueError, match="stage 'early': no stage 'nowhere' to follow"):
        artifacts.register_stage(early, after="nowhere")
    before = artifacts.STAGES
    artifacts.register_stage(early, after="geometry")
    assert [s.name for s in artifacts.STAGES].index("early") == 3 and len(artifacts.STAGES) == len(before) + 1


def test_the_residuals_picture_is_for_horizons_given_by_picks():
    """{case}_residuals.png: every sample case with a horizon from picks, no other; its report
    category is the cases' pictures, which the report's menu lists first."""
    cases = [load_case(p) for p in sorted((ROOT / "config" / "cases").glob("*.yaml"))]
    with_residuals = [c.name for c in cases if "residuals" in [a.key for a in artifacts.case_artifacts(c)]]
    assert with_residuals == ["faulted_picks"]
    pictures = artifacts.producers()["residuals"]
    assert "horizons" in pictures.inputs and pictures.name == "pictures"
    reported = [a.report.category for s in artifacts.STAGES for a in s.outputs if a.report is not None]
    assert set(reported) <= {artifacts.PICTURES, artifacts.SIMULATIONS}
    order = [artifacts.PICTURES, artifacts.SUMMARY, artifacts.SIMULATIONS, artifacts.STUDIES]
    assert sorted(order) == order
