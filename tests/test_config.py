"""Case files: validation errors name the file and key; sample cases build the seed's grids."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

import gridlib as gl
from gridlib.case.simple_grids import build_grid
from gridlib.config import load_case

CASES = Path(__file__).resolve().parents[1] / "config" / "cases"


def _write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / f"{name}.yaml"
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    ("case", "cells", "volume"),
    [("ellipsoid", 2128, 17.024), ("honeycomb", 120, 80.540362552), ("twisted", 600, 60000.0)],
)
def test_sample_cases_build_the_seed_grids(case, cells, volume):
    grid = build_grid(load_case(CASES / f"{case}.yaml"))
    geo = gl.compute_geometry(grid)
    assert grid.num_cells == cells
    assert geo.cell_volumes.sum() == pytest.approx(volume, rel=1e-10)
    gl.check_grid(grid, geo)


def test_radial_case_is_the_seed_radial_grid_in_layers():
    case = load_case(CASES / "radial_well.yaml")
    grid = build_grid(case)
    assert grid.num_cells == 241 * 5
    geo = gl.compute_geometry(grid)
    assert geo.cell_volumes.sum() == pytest.approx(3.06146745892 * 10.0, rel=1e-10)
    assert grid.nodes.coords[:, 2].min() == 1500.0
    assert case.provenance()["case_sha256"] == case.sha256 and case.seed == 0


def test_defaults_are_filled_in(tmp_path):
    path = _write(tmp_path, "c", "name: c\ngrid: {type: cartesian, dims: [2, 2]}\n")
    case = load_case(path)
    assert case.data["seed"] == 0 and case.data["grid"]["twist"] == 0


def test_defaults_fill_absent_sections_and_the_items_of_lists(tmp_path):
    """The schema's defaults are the only defaults: an absent ``outputs`` section gets its
    keys' defaults, and each fault (an item of a list) its ``throw`` and ``side``."""
    faults = [
        "  - {name: F, trace: [[0.5, 0], [0.5, 2]]}",
        "  - {name: G, trace: [[0, 1], [2, 1]], side: left, throw: 3}",
    ]
    text = CARTESIAN + "faults:\n" + "\n".join(faults) + "\n"
    case = load_case(_write(tmp_path, "c", text))
    assert case.data["outputs"] == {
        "stage_files": True,
        "vtu": True,
        "pictures": True,
        "roff_format": "binary",
    }
    assert case.keeps_stage_files and case.writes_vtu and case.writes_pictures
    first, second = case.data["faults"]
    assert (first["throw"], first["side"]) == (0, "right")
    assert (second["throw"], second["side"]) == (3, "left")


CARTESIAN = "name: c\ngrid: {type: cartesian, dims: [2, 2]}\n"
BAD_CASES = [
    (
        CARTESIAN + "colour: red\n",
        r"\(top level\): Additional properties are not allowed \('colour' was unexpected",
    ),
    (CARTESIAN.replace("[2, 2]", "[2, 0]"), r"grid\.dims\[1\]: 0 is less than the minimum of 1"),
    (CARTESIAN.replace("}", ", lenghts: [1, 1]}"), r"grid: .*'lenghts' was unexpected"),
    ("name: c\ngrid: {type: hexagonal}\n", r"grid\.type: 'hexagonal' is not one of"),
    ("name: c\ngrid: {type: tensor, x: [0, 1], y: {start: 0, stop: 1}}\n", r"grid\.y: 'num' is a required"),
    (CARTESIAN.replace("name: c", "name: other"), r"name: 'other' must equal the file name 'c'"),
    ("name: c\ngrid: [1, 2\n", r"c\.yaml: line \d+: not valid YAML"),
    ("- 1\n- 2\n", r"a case must be a mapping"),
    (
        "name: c\ngrid:\n  type: layered\n  areal: {sites: {pattern: radial, sectors: 8}}\n"
        "  layers: {num_layers: 1}\n",
        r"grid\.areal\.sites: 'radii' is a required property",
    ),
]


@pytest.mark.parametrize(("text", "message"), BAD_CASES)
def test_bad_case_files_name_the_file_and_key(tmp_path, text, message):
    path = _write(tmp_path, "c", text)
    with pytest.raises(gl.InputError, match=message) as info:
        load_case(path)
    assert str(path) in str(info.value)


def test_grid_errors_name_the_case_file(tmp_path):
    path = _write(
        tmp_path,
        "c",
        CARTESIAN + "domain: {ellipsoid: {center: [1, 1], semi_axes: [0.1, 0.1]}}\n",
    )  # inside the grid's box, between its cell centroids: only the grid stage finds it empty
    with pytest.raises(gl.InputError, match=r"c\.yaml: grid: domain: no cell centroid lies inside"):
        build_grid(load_case(path))
    path.write_text(CARTESIAN + "domain: {ellipsoid: {center: [9, 9], semi_axes: [1, 1]}}\n")
    with pytest.raises(gl.InputError, match=r"c\.yaml: domain\.ellipsoid: lies outside the grid along x"):
        load_case(path)  # outside the grid's box: refused when the case is read
    with pytest.raises(gl.InputError, match=r"nope\.yaml: case file not found"):
        load_case(tmp_path / "nope.yaml")


def _schema_keys(node, keys: set[str]) -> set[str]:
    """Every property name anywhere in the schema (through $defs, allOf/if/then, oneOf)."""
    if isinstance(node, dict):
        for name, sub in node.get("properties", {}).items():
            keys.add(name)
            _schema_keys(sub, keys)
        for key, sub in node.items():
            if key != "properties":
                _schema_keys(sub, keys)
    elif isinstance(node, list):
        for sub in node:
            _schema_keys(sub, keys)
    return keys


def test_config_readme_documents_every_key_of_the_schema():
    import re

    from gridlib.config import load_schema

    readme = (CASES.parent / "README.md").read_text()
    schema_keys = _schema_keys(load_schema(), set())
    study_keys = _schema_keys(load_schema("study.schema.yaml"), set())
    documented = set(re.findall(r"`([a-z_0-9]+)`", readme))
    missing = sorted((schema_keys | study_keys) - documented)
    assert not missing, f"config/README.md does not mention {missing}"
    table_keys = set(re.findall(r"^\| `([a-z_0-9]+)` \|", readme, flags=re.M))
    schema_keys |= study_keys
    config_schema = CASES.parents[1] / "workflow" / "schemas" / "config.schema.yaml"
    config_keys = set(yaml.safe_load(config_schema.read_text())["properties"])  # config.yaml's own keys
    unknown = sorted(table_keys - schema_keys - config_keys)
    assert not unknown, f"config/README.md documents keys the schema does not have: {unknown}"


def test_every_sample_case_is_valid_and_documented():
    readme = (CASES.parents[1] / "README.md").read_text()
    for path in sorted(CASES.glob("*.yaml")):
        case = load_case(path)
        assert f"`{case.name}`" in readme, f"README.md's case table does not list {case.name}"


def test_a_key_given_twice_names_the_line_in_case_and_study_files(tmp_path):
    from gridlib.study import load_study

    case = _write(tmp_path, "c", CARTESIAN + "seed: 1\nseed: 2\n")
    with pytest.raises(gl.InputError, match=r"c\.yaml: line 4: key 'seed' given twice \(first at line 3\)"):
        load_case(case)
    study = tmp_path / "s.yaml"
    base = (CASES / "waterflood_pebi.yaml").resolve()
    study.write_text(f"name: s\nbase: {base}\nvary: {{faults.0.throw: [0, 30]}}\nvary: {{seed: [1]}}\n")
    with pytest.raises(gl.InputError, match=r"s\.yaml: line 4: key 'vary' given twice \(first at line 3\)"):
        load_study(study, tmp_path / "results")
    anchors = "base: &b {type: cartesian, dims: [2, 2]}\nname: c\ngrid: {<<: *b, dims: [3, 3]}\n"
    with pytest.raises(gl.InputError, match=r"\(top level\): Additional properties .*'base'"):
        load_case(_write(tmp_path, "c", anchors))  # a merge key's keys may be given again


def test_a_study_variant_is_checked_like_a_case(tmp_path):
    from gridlib.study import load_study

    study = tmp_path / "s.yaml"
    base = (CASES / "waterflood_pebi.yaml").resolve()
    study.write_text(f"name: s\nbase: {base}\nvary: {{petrophysics.ntg.constant: [0.9, 90]}}\n")
    with pytest.raises(
        gl.InputError,
        match=r"s\.yaml: vary\.petrophysics\.ntg\.constant: variant '.*': "
        r"petrophysics\.ntg\.constant: 90 is above 1",
    ):
        load_study(study, tmp_path / "results")


def test_deck_dimensions_follow_includes_and_read_egrid_heads(tmp_path):
    from gridlib.io.grdecl.dimens import deck_dimensions

    (tmp_path / "inc").mkdir()
    (tmp_path / "inc" / "grid.inc").write_text("-- the grid\nSPECGRID\n  7 5\n 3 1 F /\n")
    deck = tmp_path / "D.DATA"
    deck.write_text("RUNSPEC\nTITLE\n a deck /\nGRID\nINCLUDE\n 'inc/grid.inc' /\n")
    assert deck_dimensions(deck) == (7, 5, 3)
    deck.write_text("GRID\nINCLUDE\n 'inc/none.inc' /\n")
    assert deck_dimensions(deck) is None  # the reader names the missing include
    deck.write_text("DIMENS\n 2*10 3 /\n")
    assert deck_dimensions(deck) is None  # a repeat count: the reader reads it
    reek = Path(__file__).parent / "data" / "decks" / "reek" / "REEK.EGRID"
    assert deck_dimensions(reek) == (40, 64, 14)


@pytest.mark.parametrize(
    "name",
    [
        "peaks",
        "anticline",
        "twisted",
        "ellipsoid",
        "radial_well",
        "waterflood_pebi",
        "faulted_pebi",
        "composite_wells",
    ],
)
def test_size_estimates_are_the_cells_built(name):
    """Cartesian and corner-point counts are exact (inactive cells included), a radial layered
    grid's too; a PEBI grid's is an estimate (-7 %, +16 % and +2 % of the cells the three sample
    PEBI cases build: within 20 %)."""
    from gridlib.case.grid import build_case_grid
    from gridlib.case.horizons import case_horizons
    from gridlib.config.size import estimated_cells

    case = load_case(CASES / f"{name}.yaml")
    cells, _ = estimated_cells(case.data, case.path)
    built = build_case_grid(case, case_horizons(case) if case.has_horizons else None).grid
    dims = built.cart_dims
    count = int(np.prod(dims)) if case.grid_type == "cornerpoint" else built.num_cells
    if name == "ellipsoid":  # the fictitious domain removes cells after the box is built
        count = int(np.prod(dims))
    if case.grid_type == "pebi":
        assert abs(cells - count) <= 0.2 * count, (cells, count)
    else:
        assert cells == count


def test_the_memory_limit_is_the_machine_or_the_config(tmp_path):
    from gridlib.config.size import GIB, max_memory_bytes, physical_memory

    assert max_memory_bytes() == physical_memory() > GIB
    assert max_memory_bytes(2.5) == int(2.5 * GIB)
    path = _write(tmp_path, "c", "name: c\ngrid: {type: cartesian, dims: [1000, 1000, 100]}\n")
    with pytest.raises(gl.InputError, match=r"c\.yaml: grid\.dims: 100,000,000 cells need about 102 GiB"):
        load_case(path, max_memory_gb=64)
    assert load_case(path, max_memory_gb=200).data["grid"]["dims"] == [1000, 1000, 100]


def test_a_study_takes_the_memory_limit_of_the_workflow(tmp_path):
    from gridlib.study import load_study

    study = tmp_path / "s.yaml"
    study.write_text(f"name: s\nbase: {(CASES / 'twisted.yaml').resolve()}\nvary: {{grid.twist: [0.01]}}\n")
    assert len(load_study(study, tmp_path / "results").variants) == 1
    with pytest.raises(
        gl.InputError, match=r"s\.yaml: base: .*twisted\.yaml: grid\.dims: 600 cells need about"
    ):
        load_study(study, tmp_path / "results", max_memory_gb=1e-6)
