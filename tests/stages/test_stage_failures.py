"""Failures that show only inside a stage (issue 24): a deck whose every cell is inactive, a
points file with NaN, a PEBI layout that cannot be honoured, a stage file edited by hand, ...
Each ends, through :func:`gridlib.stages.run_stage` in this process, in one InputError or
GridError naming the case file (and the deck, the keyword and the cells where there are any),
with no numpy repr, and leaves the failing stage's outputs as they were; :func:`run_case` puts
the whole results folder back as it was. One Snakemake run shows a note printed once on the
console and a failure as one line without a traceback."""

from __future__ import annotations

import re
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pytest

from gridlib import artifacts
from gridlib.config import load_case
from gridlib.errors import GridError, InputError
from gridlib.stages import case_outputs, run_case, run_stage

ROOT = Path(__file__).resolve().parents[2]
NUMPY_REPR = re.compile(r"np\.\w+\(|array\(")
BEFORE = b"the results of an earlier run\n"  # what a failing stage's outputs hold before it runs

HORIZONS = """horizons:
  lattice: {x: {start: 0, stop: 1000, num: 11}, y: {start: 0, stop: 800, num: 9}}
  surfaces:
    - {name: top, plane: {depth: 1000}}
    - {name: base, plane: {depth: 1040}}
"""
ROCK = "petrophysics: {porosity: {constant: 0.2}, permeability: {constant: 100}}\n"
DECK_ROCK = "petrophysics: {porosity: {deck: PORO}, permeability: {deck: PERMX}}\n"
PEBI = HORIZONS + "grid: {type: pebi, domain: {rectangle: [0, 0, 1000, 800]}, cell_size: 100, layers: 1}\n"
CORNERPOINT = HORIZONS + "grid: {type: cornerpoint, dims: [5, 4], layers: 2}\n"
CARTESIAN = "grid: {type: cartesian, dims: [3, 2, 2], lengths: [300, 200, 20], origin: [0, 0, 1000]}\n"


def deck(
    actnum: str = "", poro: str = "8*0.2", permx: str = "8*100", coord: Callable[[str], str] = str
) -> str:
    """A 2 x 2 x 2 corner-point deck of 100 m x 100 m x 10 m cells at 1000 m depth."""
    pillars = " ".join(
        f"{i * 100} {j * 100} 1000 {i * 100} {j * 100} 1020" for j in range(3) for i in range(3)
    )
    text = f"SPECGRID\n 2 2 2 1 F /\nCOORD\n {coord(pillars)} /\nZCORN\n 16*1000 16*1010 16*1010 16*1020 /\n"
    text += f"ACTNUM\n {actnum} /\n" if actnum else ""
    return text + f"PORO\n {poro} /\nPERMX\n {permx} /\n"


def deck_case(name: str) -> str:
    return f"grid: {{type: deck, file: {name}.GRDECL}}\n" + DECK_ROCK


def crossed(pillars: str) -> str:
    """The pillars with the bottom of the second one moved past the first: two cells turned inside out."""
    return pillars.replace("100 0 1000 100 0 1020", "100 0 1000 -300 0 1020", 1)


def flip_a_face(grid_nc: Path) -> None:
    """grid.nc with the node order of one interior face reversed (as a hand edit would): its
    normal points the wrong way, so its two cells do not close."""
    from gridlib.io.netcdf import read_netcdf, write_netcdf

    stored = read_netcdf(grid_nc)
    grid = stored.grid
    face = int(np.flatnonzero((grid.faces.neighbors >= 0).all(axis=1))[0])
    nodes = grid.faces.nodes.copy()
    start, stop = grid.faces.node_pos[face], grid.faces.node_pos[face + 1]
    nodes[start:stop] = nodes[start:stop][::-1]
    broken = replace(grid, faces=replace(grid.faces, nodes=nodes))
    write_netcdf(grid_nc, broken, cell_data=stored.cell_data, attrs=dict(stored.attrs))


def nan_in_horizons(horizons_nc: Path) -> None:
    """horizons.nc with the base horizon undefined (NaN) everywhere."""
    from gridlib.io.horizon_files import read_horizons, write_horizons

    ds = read_horizons(horizons_nc).load()
    depth = ds["depth"].values.copy()
    depth[1] = np.nan
    write_horizons(horizons_nc, ds.assign(depth=(ds["depth"].dims, depth)))


@dataclass(frozen=True)
class Failure:
    case: str  # the case file's text after its name
    stage: str  # the stage that fails
    says: tuple[str, ...]  # what the message says besides the case file
    files: tuple[tuple[str, str], ...] = ()  # files beside the case file: (name, text)
    edit: tuple[str, Callable[[Path], None]] | None = None  # an artifact edited before the stage runs


FAILURES = {
    "deck_every_cell_inactive": Failure(
        deck_case("inactive"),
        "grid",
        ("inactive.GRDECL", "no active cells", "ACTNUM"),
        (("inactive.GRDECL", deck(actnum="8*0")),),
    ),
    "deck_every_pore_volume_zero": Failure(
        deck_case("dry"),
        "grid",
        ("dry.GRDECL", "no active cells", "zero pore volume"),
        (("dry.GRDECL", deck(poro="8*0")),),
    ),
    "deck_min_pore_volume_removes_every_cell": Failure(
        deck_case("minpv"),
        "grid",
        ("minpv.GRDECL", "below MINPV"),
        (("minpv.GRDECL", deck() + "MINPV\n 1e9 /\n"),),
    ),
    "deck_pillars_cross": Failure(
        deck_case("crossing"),
        "grid",
        ("crossing.GRDECL", "COORD", "pillars cross", "(1, 1, 1), (1, 1, 2)"),
        (("crossing.GRDECL", deck(coord=crossed)),),
    ),
    "deck_negative_permeability": Failure(
        deck_case("negative"),
        "petrophysics",
        ("negative.GRDECL", "PERMX", "(2, 2, 2)", "-5"),
        (("negative.GRDECL", deck(permx="7*100 -5")),),
    ),
    "deck_negative_porosity": Failure(
        deck_case("negative_poro"),
        "grid",
        ("negative_poro.GRDECL", "negative or infinite pore volume", "(1, 1, 1)"),
        (("negative_poro.GRDECL", deck(poro="-0.1 7*0.2")),),
    ),
    "points_with_nan": Failure(
        CORNERPOINT.replace("{name: base, plane: {depth: 1040}}", "{name: base, points: base.xyz}") + ROCK,
        "horizons",
        ("base.xyz:3", "finite"),
        (("base.xyz", "0 0 1040\n1000 0 1040\n0 800 nan\n1000 800 1040\n"),),
    ),
    "points_too_few": Failure(
        CORNERPOINT.replace("{name: base, plane: {depth: 1040}}", "{name: base, points: base.xyz}") + ROCK,
        "horizons",
        ("horizons[1] ('base')", "undefined"),
        (("base.xyz", "0 0 1040\n1000 0 1040\n"),),
    ),
    "points_collinear": Failure(
        CORNERPOINT.replace("{name: base, plane: {depth: 1040}}", "{name: base, points: base.xyz}") + ROCK,
        "horizons",
        ("horizons[1] ('base')", "collinear"),
        (("base.xyz", "0 0 1040\n500 400 1041\n1000 800 1040\n"),),
    ),
    "points_cross_the_plane_above": Failure(
        CORNERPOINT.replace("{name: base, plane: {depth: 1040}}", "{name: base, points: base.xyz}") + ROCK,
        "horizons",
        ("horizons 'top' and 'base' cross", "(x, y) = (0, 0)"),
        (("base.xyz", "0 0 990\n1000 0 990\n0 800 1050\n1000 800 1050\n500 400 1020\n"),),
    ),
    "pebi_wells_on_one_point": Failure(
        PEBI + "wells:\n  - {name: W1, point: [300, 400]}\n  - {name: W2, point: [300.001, 400]}\n" + ROCK,
        "grid",
        ("well 'W1' (wells[0])", "well 'W2' (wells[1])", "too close"),
    ),
    "grid_file_with_a_flipped_face": Failure(
        CARTESIAN + ROCK,
        "geometry",
        ("stage geometry", "check_grid", "not closed", "a face is flipped"),
        edit=("grid", flip_a_face),
    ),
    "horizons_file_with_nan": Failure(
        CORNERPOINT + ROCK,
        "grid",
        ("horizon 1", "undefined (NaN) everywhere"),
        edit=("horizons", nan_in_horizons),
    ),
}


def write_case(folder: Path, name: str, failure: Failure) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    for file, text in failure.files:
        (folder / file).write_text(text)
    case = folder / f"{name}.yaml"
    case.write_text(f"name: {name}\n{failure.case}")
    return case


def stages_of(case) -> list[artifacts.Stage]:
    return [s for s in artifacts.STAGES if s.when(case) and not s.on_request]


def assert_one_clear_message(exc: Exception, case: Path, failure: Failure) -> None:
    message = str(exc)
    assert str(case) in message, message
    for part in failure.says:
        assert part in message, (part, message)
    assert "\n" not in message and "Traceback" not in message, message
    assert not NUMPY_REPR.search(message), message


@pytest.mark.parametrize("name", sorted(FAILURES))
def test_a_failure_inside_a_stage_names_the_case_and_leaves_its_outputs(tmp_path, name):
    """The stages run in order as the workflow runs them; the failing one raises one error naming
    the case file (and what the table says: the deck, keyword, cells or case keys), and its
    outputs hold what they held before it ran."""
    failure = FAILURES[name]
    case_file = write_case(tmp_path / "config", name, failure)
    case = load_case(case_file)
    paths = case_outputs(name, tmp_path / "results" / name)
    for stage in stages_of(case):
        outputs = [paths[a.key] for a in stage.outputs_of(case)]
        if stage.name == failure.stage:
            if failure.edit is not None:
                failure.edit[1](paths[failure.edit[0]])
            for path in outputs:
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_bytes(BEFORE)
            with pytest.raises((InputError, GridError)) as exc:
                run_stage(stage.name, case_file, paths)
            assert_one_clear_message(exc.value, case_file, failure)
            assert [p.read_bytes() for p in outputs] == [BEFORE] * len(outputs)
            hidden = [
                p for p in paths[stage.outputs_of(case)[0].key].parent.iterdir() if p.name.startswith(".")
            ]
            assert hidden == [], hidden
            return
        run_stage(stage.name, case, paths)
    pytest.fail(f"{name}: no stage failed; the last ran was {stage.name}")


def test_run_case_leaves_the_results_folder_as_it_was(tmp_path):
    """``run_case`` into a folder holding an earlier run's results: the failure (in the
    petrophysics stage, after the grid and geometry stages wrote theirs) puts back every file
    it replaced and removes every file it wrote."""
    name = "deck_negative_permeability"
    failure = FAILURES[name]
    case_file = write_case(tmp_path / "config", name, failure)
    folder = tmp_path / "results" / name
    folder.mkdir(parents=True)
    earlier = {folder / "grid.nc": b"an earlier grid", folder / "notes.txt": b"the user's own file"}
    for path, data in earlier.items():
        path.write_bytes(data)
    with pytest.raises((InputError, GridError)) as exc:
        run_case(case_file, folder)
    assert_one_clear_message(exc.value, case_file, failure)
    assert {p: p.read_bytes() for p in folder.rglob("*")} == earlier


def test_run_case_into_a_new_folder_leaves_no_folder(tmp_path):
    failure = FAILURES["deck_every_cell_inactive"]
    case_file = write_case(tmp_path / "config", "inactive_case", failure)
    with pytest.raises(InputError):
        run_case(case_file, tmp_path / "results" / "inactive_case")
    assert not (tmp_path / "results" / "inactive_case").exists()


def test_snakemake_prints_a_note_once_and_a_failure_as_one_line(tmp_path):
    """One Snakemake run of the grid stage of two deck cases: the note of one (a MULTFLT naming
    no fault) is printed once on the console, prefixed with the case and stage, as well as in
    its log; the failure of the other (every cell inactive) is one line naming the case file
    and the deck, with no traceback, and leaves no grid.nc."""
    config = tmp_path / "config"
    noted = write_case(config, "noted", Failure(deck_case("noted"), "grid", (), (("noted.GRDECL", deck()),)))
    (config / "noted.GRDECL").write_text(deck() + "MULTFLT\n 'NOPE' 0.5 /\n/\n")
    broken = write_case(config, "broken", FAILURES["deck_every_cell_inactive"])
    targets = [f"results/{name}/grid.nc" for name in ("noted", "broken")]
    result = subprocess.run(
        [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(tmp_path),
         "--cores", "2", "--keep-going", *targets, "--config", f"cases=[{noted},{broken}]", "studies=[]"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    out = result.stdout + result.stderr
    assert result.returncode != 0, out[-3000:]
    notes = [line for line in out.splitlines() if "NOPE" in line]
    assert len(notes) == 1 and notes[0].startswith("gridlib: noted: grid: note: "), out[-3000:]
    log = (tmp_path / "results" / "logs" / "noted" / "grid.log").read_text()
    assert notes[0].removeprefix("gridlib: noted: grid: ") in log
    failures = [line for line in out.splitlines() if line.startswith("gridlib:") and str(broken) in line]
    assert len(failures) == 1 and "inactive.GRDECL" in failures[0] and "no active cells" in failures[0], out[
        -3000:
    ]
    assert "Traceback" not in out and 'File "' not in out, out[-3000:]
    assert (tmp_path / "results" / "noted" / "grid.nc").is_file()
    assert not (tmp_path / "results" / "broken" / "grid.nc").exists()


def test_a_stage_failing_at_its_second_file_leaves_the_first_as_it_was(tmp_path, monkeypatch):
    """The grid stage of a deck case writes grid.nc, then grid.grdecl: when the second write
    fails, grid.nc holds what it held before (and no file is left beside it)."""
    import gridlib.stages.grid as grid_stage

    def refuse(path, *args, **kwargs):
        raise InputError(f"{path}: PERMX: not written (the test's failure)")

    monkeypatch.setattr(grid_stage, "write_grdecl", refuse)
    case_file = write_case(
        tmp_path / "config", "two_files", Failure(deck_case("d"), "grid", (), (("d.GRDECL", deck()),))
    )
    paths = case_outputs("two_files", tmp_path / "results" / "two_files")
    paths["grid"].parent.mkdir(parents=True)
    for key in ("grid", "grdecl"):
        paths[key].write_bytes(BEFORE)
    with pytest.raises(InputError, match=r"stage grid: .*grid\.grdecl: PERMX: not written"):
        run_stage("grid", case_file, paths)
    assert sorted(p.name for p in paths["grid"].parent.iterdir()) == ["grid.grdecl", "grid.nc"]
    assert paths["grid"].read_bytes() == paths["grdecl"].read_bytes() == BEFORE


def test_the_horizons_stage_logs_the_repairs_of_its_horizons(tmp_path, caplog):
    """The notes of the horizons (here: ordering 'erode' moving a crossing horizon down) reach the
    stage's log, as the other stages' notes do."""
    failure = FAILURES["points_cross_the_plane_above"]
    text = failure.case.replace("  surfaces:", "  ordering: erode\n  surfaces:")
    case_file = write_case(tmp_path / "config", "eroded", replace(failure, case=text))
    with caplog.at_level("INFO", logger="gridlib"):
        run_stage("horizons", case_file, {"horizons": tmp_path / "horizons.nc"})
    notes = [r.getMessage() for r in caplog.records if r.getMessage().startswith("note:")]
    assert notes == ["note: ordering 'erode': horizon 'base' moved down to a horizon above it at 22 nodes"]


def test_run_logged_prints_notes_once_and_a_failure_as_one_line(tmp_path, capsys):
    """What a Snakemake job prints (a stage rule's job runs its stage through run_logged):
    each note once as it is logged, prefixed with the label; an InputError as its message; an
    unexpected exception as one line naming the log, whose traceback stays in the log."""
    import logging

    from gridlib.stages import run_logged

    log = logging.getLogger("gridlib.stages")

    def noting():
        for text in ("note: rings dropped", "note: rings dropped", "wrote a file", "note: a small angle"):
            log.info(text)

    run_logged(tmp_path / "ok.log", noting, label="case: grid")
    err = capsys.readouterr().err.splitlines()
    assert err == ["gridlib: case: grid: note: rings dropped", "gridlib: case: grid: note: a small angle"]
    assert (tmp_path / "ok.log").read_text().count("note: rings dropped") == 2  # the log keeps every line

    def refusing():
        raise InputError("case.yaml: stage grid: no active cells")

    def failing():
        raise KeyError("a bug")

    with pytest.raises(SystemExit):
        run_logged(tmp_path / "input.log", refusing, label="case: grid")
    assert capsys.readouterr().err == "gridlib: case.yaml: stage grid: no active cells\n"
    with pytest.raises(SystemExit):
        run_logged(tmp_path / "bug.log", failing, label="case: grid")
    (line,) = capsys.readouterr().err.splitlines()
    assert (
        line.startswith("gridlib: case: grid failed: KeyError: 'a bug'") and str(tmp_path / "bug.log") in line
    )
    assert "Traceback (most recent call last)" in (tmp_path / "bug.log").read_text()
