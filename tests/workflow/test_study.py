"""Studies end to end: a 3 x 2 x 3 study of a small faulted PEBI case through the workflow.

One run (two cores, the variants in warm worker processes), then: study.csv has a row per
variant with its values, finer cells give more cells, a zero throw fewer fault connections
than the largest, realisations differ in porosity and not in the grid, study.nc has one
dimension per varied key plus realisation; a variant equals the same case written by hand;
broken studies stop before any job with one line naming the file and the key; a second run
does nothing and editing one value reruns exactly the variants it adds or changes.
"""

from __future__ import annotations

import copy
import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest
import xarray as xr
import yaml
from artifacts import assert_same_files, run_case_without_pictures

from gridlib.artifacts import case_paths
from gridlib.errors import InputError
from gridlib.io.summary_table import figure_name
from gridlib.stages import run_stage
from gridlib.study import SEED_STEP, load_study

ROOT = Path(__file__).resolve().parents[2]
SNAKEMAKE = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile")]
GREEDY = ["--scheduler", "greedy"]  # as workflow/profiles/default (make run)

# A small version of config/cases/faulted_pebi.yaml: 1 x 0.75 km, 100 m thick in 2 layers (170 and
# 300 cells): the largest throw (40 m) is less than a layer, so that it adds connections.
BASE = {
    "name": "small_pebi",
    "seed": 3,
    "horizons": {
        "lattice": {"x": {"start": 0, "stop": 1000, "num": 21}, "y": {"start": 0, "stop": 750, "num": 16}},
        "surfaces": [
            {"name": "top", "plane": {"depth": 1500, "dip": 2.0, "azimuth": 90}},
            {"name": "base", "plane": {"depth": 1600, "dip": 2.5, "azimuth": 90}},
        ],
    },
    "faults": [
        {"name": "NS", "trace": [[500, -25], [525, 775]], "throw": 20},
        {"name": "EW", "trace": [[-25, 350], [1025, 450]], "throw": 10, "side": "left"},
    ],
    "wells": [{"name": "P1", "point": [225, 175], "rings": {"inner": 2.0, "outer": 30}}],
    "grid": {"type": "pebi", "domain": {"rectangle": [0, 0, 1000, 750]}, "cell_size": 80, "layers": 2},
    "petrophysics": {
        "porosity": {
            "field": {
                "model": "gaussian",
                "len_scale": [200, 200, 10],
                "mean": 0.2,
                "std": 0.04,
                "bounds": [0.05, 0.35],
            }
        },
        "permeability": {"carman_kozeny": {}},
    },
    "coarsen": {"method": "metis", "blocks": 6},
}
# Three throws (none, 20 m and the largest): no test below reads more; a fourth (10 m) cost six
# of the run's variants.
THROWS = [0, 20, 40]
CELL_SIZES = [80, 120]
STUDY = {
    "name": "sweep",
    "base": "../cases/small_pebi.yaml",
    "vary": {"faults.0.throw": THROWS, "grid.cell_size": CELL_SIZES},
    "combine": "product",
    "realisations": 3,
    "seed": 5,
    # The variants' own pictures are read by no test here (the sample grid_choice study of
    # test_workflow.py draws them; tests/stages/test_optional_pictures.py compares the two):
    # this run also checks that a study without them builds through Snakemake.
    "pictures": False,
}


def _write(path: Path, data: dict) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def _snakemake(workdir: Path, study: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [*SNAKEMAKE, "--directory", str(workdir), "--cores", "2", "--force-use-threads", *GREEDY]
        + ["--config", "cases=[]", f"studies={study}", *args],
        capture_output=True,
        text=True,
        timeout=600,
    )


@pytest.fixture(scope="module")
def study_run(tmp_path_factory) -> Path:
    workdir = tmp_path_factory.mktemp("study")
    _write(workdir / "config" / "cases" / "small_pebi.yaml", BASE)
    study = _write(workdir / "config" / "studies" / "sweep.yaml", STUDY)
    result = _snakemake(workdir, study)
    assert result.returncode == 0, result.stderr[-4000:]
    return workdir


def _rows(workdir: Path, units: bool = False) -> list[dict[str, str]]:
    """The rows of study.csv, by column; by figure name (the header's unit left out) unless
    ``units``."""
    with open(workdir / "results" / "sweep" / "study.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    return rows if units else [{figure_name(k): v for k, v in r.items()} for r in rows]


def test_study_csv_has_a_row_per_variant_with_its_values(study_run):
    rows = _rows(study_run)
    assert len(rows) == 18
    header = list(_rows(study_run, units=True)[0])  # the figures' units in the header (issue 24)
    assert header[:5] == ["variant", "faults.0.throw [m]", "grid.cell_size [m]", "realisation", "seed"]
    units = {"pore_volume [m3]", "median_trans [cP m3/(day bar)]", "mean_porosity [1]", "unit_system"}
    assert {"cells", "faces", "nnc", "fault_connections"} | units <= set(header)
    combos = [(int(r["faults.0.throw"]), int(r["grid.cell_size"]), int(r["realisation"])) for r in rows]
    assert sorted(combos) == sorted((t, c, k) for t in THROWS for c in CELL_SIZES for k in range(3))
    for r in rows:
        assert int(r["seed"]) == 5 + SEED_STEP * int(r["realisation"])
        name = f"throw-{r['faults.0.throw']}_cell_size-{r['grid.cell_size']}_r{r['realisation']}"
        assert r["variant"] == name
        assert (study_run / "results" / "sweep" / name / f"{name}.vtu").is_file()
    assert (study_run / "results" / "sweep" / "study.png").stat().st_size > 10_000


def test_finer_cells_more_cells_and_throw_adds_fault_connections(study_run):
    rows = _rows(study_run)

    def figure(name, **where):
        return [float(r[name]) for r in rows if all(r[k] == str(v) for k, v in where.items())]

    for throw in THROWS:
        fine, coarse = (figure("cells", **{"faults.0.throw": throw, "grid.cell_size": c}) for c in CELL_SIZES)
        assert min(fine) > max(coarse)
    for size in CELL_SIZES:
        none = figure("fault_connections", **{"faults.0.throw": 0, "grid.cell_size": size})
        most = figure("fault_connections", **{"faults.0.throw": 40, "grid.cell_size": size})
        assert max(none) < min(most)


def test_realisations_differ_in_porosity_not_in_the_grid(study_run):
    rows = _rows(study_run)
    for throw in THROWS:
        for size in CELL_SIZES:
            same = [r for r in rows if r["faults.0.throw"] == str(throw) and r["grid.cell_size"] == str(size)]
            assert len(same) == 3
            for key in ("cells", "faces", "nodes", "total_volume", "nnc", "fault_faces", "connections"):
                assert len({r[key] for r in same}) == 1, key
            assert len({r["mean_porosity"] for r in same}) == 3
            assert len({r["pore_volume"] for r in same}) == 3


def test_study_nc_has_a_dimension_per_varied_key_and_realisation(study_run):
    with xr.open_dataset(study_run / "results" / "sweep" / "study.nc") as ds:
        assert dict(ds.sizes) == {"faults.0.throw": 3, "grid.cell_size": 2, "realisation": 3}
        assert ds["faults.0.throw"].values.tolist() == THROWS
        assert ds["faults.0.throw"].attrs["units"] == ds["grid.cell_size"].attrs["units"] == "m"
        assert "units" not in ds["realisation"].attrs
        cells = ds["cells"].sel({"faults.0.throw": 20, "grid.cell_size": 80, "realisation": 1})
        row = next(r for r in _rows(study_run) if r["variant"] == "throw-20_cell_size-80_r1")
        assert int(cells) == int(row["cells"])
        where = {"faults.0.throw": 0, "grid.cell_size": 120, "realisation": 2}
        assert str(ds["variant"].sel(where).values) == "throw-0_cell_size-120_r2"


def test_study_png_draws_a_line_per_cell_size_whose_bars_span_its_realisations_only(study_run):
    """study.png's pore volume against throw, drawn again from the run's study.nc: one line per
    cell size, its points study.csv's values of that cell size, each bar from the least to the
    largest of its three realisations (issue 28: the bars spanned both cell sizes)."""
    import matplotlib.pyplot as plt
    import numpy as np

    from gridlib.io import study_pictures

    rows = _rows(study_run)
    with xr.open_dataset(study_run / "results" / "sweep" / "study.nc") as ds:
        fig = study_pictures.study_figure(ds.load())
    try:
        (ax,) = [
            a for a in fig.axes if a.get_ylabel() == "pore volume [10⁶ m3]" and "throw" in a.get_xlabel()
        ]
        means = [line for line in ax.lines if line.get_gid() == study_pictures.MEAN]
        bars = [c for c in ax.collections if c.get_gid() == study_pictures.SPREAD]
        assert [line.get_label() for line in means] == [f"grid.cell_size = {c} m" for c in CELL_SIZES]
        for line, bar, size in zip(means, bars, CELL_SIZES, strict=True):
            pv = [
                [
                    float(r["pore_volume"])
                    for r in rows
                    if r["grid.cell_size"] == str(size) and r["faults.0.throw"] == str(t)
                ]
                for t in THROWS
            ]
            assert line.get_ydata().tolist() == [float(np.mean(p)) for p in pv]
            assert [tuple(s[:, 1]) for s in bar.get_segments()] == [(min(p), max(p)) for p in pv]
    finally:
        plt.close(fig)


def test_a_variant_equals_the_same_case_written_by_hand(study_run, tmp_path):
    name = "throw-20_cell_size-120_r1"
    hand = copy.deepcopy(BASE)
    hand["name"] = name
    hand["seed"] = 5 + SEED_STEP * 1
    hand["faults"][0]["throw"] = 20
    hand["grid"]["cell_size"] = 120
    case_file = _write(tmp_path / f"{name}.yaml", hand)
    run_case_without_pictures(case_file, tmp_path / name)
    compared = assert_same_files(study_run / "results" / "sweep" / name, tmp_path / name, provenance=False)
    assert {"grid.nc", "petrophysics.nc", "transmissibility.nc", f"{name}.nc", f"{name}.vtu"} <= set(compared)


def test_a_second_run_does_nothing_and_an_edit_reruns_only_the_variants_it_changes(study_run):
    study = study_run / "config" / "studies" / "sweep.yaml"
    again = _snakemake(study_run, study, "--dry-run")
    assert again.returncode == 0, again.stderr[-3000:]
    assert "Nothing to be done" in again.stdout + again.stderr
    results = study_run / "results" / "sweep"
    before = {p.parent.name: p.stat().st_mtime_ns for p in results.glob("*/summary.json")}

    edited = copy.deepcopy(STUDY)
    edited["vary"]["faults.0.throw"] = [0, 20, 30]  # 40 -> 30: 2 cell sizes x 3 realisations
    _write(study, edited)
    plan = _snakemake(study_run, study, "--dry-run", "--quiet", "rules")
    assert plan.returncode == 0, plan.stderr[-3000:]
    counts = {}
    for line in (plan.stdout + plan.stderr).splitlines():
        parts = line.split()
        if len(parts) == 2 and parts[1].isdigit():
            counts[parts[0]] = int(parts[1])
    assert counts.get("study_sweep") == 6 and counts.get("study_table") == 1, plan.stdout + plan.stderr

    result = _snakemake(study_run, study)
    assert result.returncode == 0, result.stderr[-3000:]
    after = {p.parent.name: p.stat().st_mtime_ns for p in results.glob("*/summary.json")}
    rebuilt = sorted(n for n in after if before.get(n) != after[n])
    assert rebuilt == sorted(f"throw-30_cell_size-{c}_r{k}" for c in CELL_SIZES for k in range(3))
    rows = _rows(study_run)
    assert len(rows) == 18 and {r["faults.0.throw"] for r in rows} == {"0", "20", "30"}
    assert "Nothing to be done" in _snakemake(study_run, study, "--dry-run").stdout


BROKEN = {
    "unknown key": ({"vary": {"faults.0.thro": [1, 2]}}, "vary.faults.0.thro"),
    "wrong type": ({"vary": {"grid.cell_size": [80, "fine"]}}, "vary.grid.cell_size"),
    "zip of unequal lists": ({"combine": "zip"}, "combine"),
    "missing base": ({"base": "../cases/nowhere.yaml"}, "base"),
}


@pytest.mark.parametrize("problem", sorted(BROKEN))
def test_a_broken_study_is_one_line_naming_the_file_and_key(tmp_path, problem):
    change, key = BROKEN[problem]
    _write(tmp_path / "config" / "cases" / "small_pebi.yaml", BASE)
    study = _write(tmp_path / "config" / "studies" / "sweep.yaml", STUDY | change)
    with pytest.raises(InputError) as err:
        load_study(study, tmp_path / "results")
    message = str(err.value)
    assert "\n" not in message and message.startswith(f"{study}: {key}:"), message
    if problem == "wrong type":
        assert "variant 'cell_size-fine_r0'" in message and "'fine' is not of type" in message
    # Through the workflow: the same line, and nothing runs (no results folder).
    result = _snakemake(tmp_path, study)
    assert result.returncode != 0
    assert message in result.stderr.splitlines(), result.stderr[-2000:]
    assert not (tmp_path / "results" / "sweep").exists()


# A base case naming files (points files; a deck with INCLUDEs), one value varied, the variant's cells.
FILE_BASES = {
    "faulted_picks": ({"grid.layers": [2]}, 4800),  # 40 x 30 columns x 2 zones x 2 layers
    "spe9": ({"petrophysics.kv_kh": [0.01]}, 9000),  # 24 x 25 x 15, all active
}
# The value added to the study's `vary:` after its first build, and the stage reading the base's files.
FILE_BASE_EDITS = {"faulted_picks": (3, "horizons"), "spe9": (0.1, "grid")}


@pytest.mark.parametrize("base", sorted(FILE_BASES))
def test_a_base_case_that_names_files_gives_variants_that_find_them(tmp_path, monkeypatch, base):
    """A base case naming files relative to itself: its variants, checked before their folders
    exist and then built in them, read the base's files (they were refused: the paths, rewritten
    from the variant's folder, were resolved through folders not yet made)."""
    from gridlib.config import load_case, named_file
    from gridlib.study import materialise

    def named_files(case):
        if case.grid_type == "deck":
            return [named_file(case.path, case.data["grid"]["file"])]
        return [named_file(case.path, s["points"]) for s in case.data["horizons"]["surfaces"]]

    vary, cells = FILE_BASES[base]
    base_file = ROOT / "config" / "cases" / f"{base}.yaml"
    spec = {"name": "sweep", "base": str(base_file), "vary": vary}
    study = _write(tmp_path / "config" / "studies" / "sweep.yaml", spec)
    monkeypatch.chdir(tmp_path)  # results/ relative to the working directory, as in the workflow
    loaded = load_study(study, "results")  # each variant checked as a case of results/sweep/<variant>/
    assert not Path("results").exists()
    materialise(loaded, "results")
    variant = loaded.variants[0]
    case = load_case(Path("results") / "sweep" / variant.name / f"{variant.name}.yaml")
    base_files = [p.resolve() for p in named_files(load_case(base_file))]
    assert [p.resolve() for p in named_files(case)] == base_files
    run_case_without_pictures(case, case.path.parent)
    assert json.loads((case.path.parent / "summary.json").read_text())["cells"] == cells

    # An edit of `vary:` adds a variant: checked and written like the first, it finds the files too.
    (key, values), (added, stage) = next(iter(vary.items())), FILE_BASE_EDITS[base]
    _write(study, {**spec, "vary": {key: [*values, added]}})
    edited = load_study(study, "results")
    materialise(edited, "results")
    (new,) = [v for v in edited.variants if v.name not in {v.name for v in loaded.variants}]
    case = load_case(Path("results") / "sweep" / new.name / f"{new.name}.yaml")
    assert [p.resolve() for p in named_files(case)] == base_files
    paths = case_paths(case.name, case.path.parent)
    run_stage(stage, case, paths)  # the stage that reads the base's files
    assert paths[stage].is_file()
