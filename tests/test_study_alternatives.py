"""Studies that vary a whole section: a varied key whose values are mappings with a ``label``
(gridlib.study.Alternative), as the sample study config/studies/grid_choice.yaml varies its
grid (pillars, stair steps, PEBI; two cell sizes). Fast: loading and checking only, no grid
is built and Flow does not run (tests/workflow/test_study.py builds studies)."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from gridlib.errors import InputError
from gridlib.study import artifact_groups, load_study, manifest_text

ROOT = Path(__file__).resolve().parents[1]
SAMPLE = ROOT / "config" / "studies" / "grid_choice.yaml"
BASE = ROOT / "config" / "cases" / "y_faults_pillars.yaml"
LABELS = ["pillars-80m", "pillars-40m", "stairs-80m", "stairs-40m", "pebi-80m", "pebi-40m"]
PEBI_80 = {"type": "pebi", "domain": {"rectangle": [0, 0, 1200, 800]}, "cell_size": 80, "layers": 5}


@pytest.fixture(scope="module")
def results(tmp_path_factory) -> Path:
    return tmp_path_factory.mktemp("run") / "results"


@pytest.fixture(scope="module")
def sample(results):
    """The sample study, every variant checked as a case in results/grid_choice/<variant>/."""
    return load_study(SAMPLE, results)


def test_the_sample_study_names_its_variants_by_the_labels(sample):
    assert sample.keys == ("grid",)
    assert [v.name for v in sample.variants] == [f"grid-{lab}_r{r}" for lab in LABELS for r in (0, 1)]
    assert [v.values for v in sample.variants] == [{"grid": lab} for lab in LABELS for r in (0, 1)]
    assert [v.seed for v in sample.variants] == [7, 10] * 6  # seed 7, realisation r: 7 + 3 r


def test_a_variant_holds_the_whole_section_without_its_label(sample):
    spec = yaml.safe_load(SAMPLE.read_text())
    for k, v in enumerate(sample.variants):
        given = spec["vary"]["grid"][k // 2]
        assert v.data["grid"] == {key: value for key, value in given.items() if key != "label"}
    pebi = sample.variants[8]
    assert pebi.name == "grid-pebi-80m_r0" and pebi.data["grid"] == PEBI_80
    # everything else is the base case's (the sticks file named from the variant's folder)
    base = yaml.safe_load(BASE.read_text())
    same = [k for k in base if k not in ("name", "seed", "grid", "faults")]
    assert [pebi.data[k] for k in same] == [base[k] for k in same]
    assert pebi.data["faults"][0] == base["faults"][0]


def test_variants_find_the_base_case_fault_sticks(sample, results):
    for v in sample.variants:
        folder = sample.case_file(results, v.name).parent
        sticks = (folder / v.data["faults"][1]["sticks"]).resolve()
        assert sticks == (BASE.parent / "data" / "y_branch_sticks.pol").resolve()


def test_corner_point_and_pebi_variants_are_two_groups_of_artifacts(sample):
    groups = artifact_groups(sample)
    assert [[v.name for v in members] for _, members in groups] == [
        [v.name for v in sample.variants[:8]],
        [v.name for v in sample.variants[8:]],
    ]
    (cp, _), (pebi, _) = groups
    assert sorted(set(cp) - set(pebi)) == ["grdecl", "roff"] and set(pebi) <= set(cp)


def test_the_manifest_lists_the_labels(sample):
    doc = yaml.safe_load(manifest_text(sample))
    assert doc["keys"] == ["grid"] and doc["key_quantities"] == {"grid": {"quantity": None}}
    assert [v["values"]["grid"] for v in doc["variants"]] == [lab for lab in LABELS for _ in (0, 1)]


def _study(tmp_path: Path, grid_values: list, key: str = "grid") -> Path:
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump({"name": "s", "base": str(BASE), "vary": {key: grid_values}}))
    return path


CP = {"type": "cornerpoint", "dims": [15, 10], "layers": 5, "fault_geometry": "pillars"}
BROKEN = {
    "a number among sections": (
        [{"label": "cp", **CP}, 50],
        "vary.grid[1]: 50 is not a mapping, and item 0 is a mapping with a label: the values of a key "
        "are all mappings with a label (whole sections or list items) or none is",
    ),
    "a section without a label": (
        [CP, {"label": "pebi", **PEBI_80}],
        "vary.grid[0]: this mapping has no label, and item 1 is a mapping with a label",
    ),
    "a label with a space": (
        [{"label": "corner point", **CP}],
        "vary.grid[0].label: corner point must be text of letters, digits, '.', '_' and '-' "
        "(it names the variants)",
    ),
    "a number as label": ([{"label": 3, **CP}], "vary.grid[0].label: 3 must be text of letters"),
    "a label twice": (
        [{"label": "g", **CP}, {"label": "g", **PEBI_80}],
        "vary.grid[1].label: 'g' is also the label of item 0",
    ),
}


@pytest.mark.parametrize("problem", sorted(BROKEN))
def test_a_broken_alternative_is_one_line_naming_the_file_key_and_item(tmp_path, problem):
    values, message = BROKEN[problem]
    path = _study(tmp_path, values)
    with pytest.raises(InputError) as caught:
        load_study(path, tmp_path / "results", check=False)
    text = str(caught.value)
    assert text.startswith(f"{path}: {message}") and "\n" not in text


def test_a_checked_alternative_that_is_not_a_grid_names_the_variant(tmp_path):
    path = _study(tmp_path, [{"label": "odd", "type": "cornerpoint", "layers": 5}])
    with pytest.raises(InputError, match=r"s\.yaml: vary\.grid: variant 'grid-odd_r0': grid"):
        load_study(path, tmp_path / "results")


def test_an_unlabelled_mapping_value_is_still_one_value(tmp_path):
    """A mapping without a label is a value like any other (a throw ramp), named by position."""
    path = _study(tmp_path, [10, {"start": 0, "end": 15}], key="faults.0.throw")
    study = load_study(path, tmp_path / "results", check=False)
    assert [v.name for v in study.variants] == ["throw-10_r0", "throw-v1_r0"]
    assert study.variants[1].data["faults"][0]["throw"] == {"start": 0, "end": 15}
    assert study.variants[1].values == {"faults.0.throw": {"start": 0, "end": 15}}


def test_a_labelled_fault_replaces_the_whole_list_item(tmp_path):
    steep = {"label": "steep", "name": "F1", "trace": [[520, -50], [620, 850]], "dip": 80, "throw": 20}
    path = _study(tmp_path, [steep], key="faults.0")
    (variant,) = load_study(path, tmp_path / "results", check=False).variants
    assert variant.name == "faults-steep_r0"  # the key's last name that is not an index
    assert variant.data["faults"][0] == {k: x for k, x in steep.items() if k != "label"}
    assert variant.values == {"faults.0": "steep"}


def test_the_workflow_builds_each_kind_of_variant_by_a_rule_of_its_own(tmp_path):
    """A dry run of the sample study: the corner-point variants are jobs of study_grid_choice
    and declare grid.grdecl and the ROFF file, the PEBI variants jobs of study_grid_choice__2
    without them (a rule's outputs are one list: both kinds in one rule would leave the PEBI
    variants' jobs missing files)."""
    command = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(tmp_path)]
    config = ["--config", "cases=[]", f"studies={SAMPLE}"]
    run = subprocess.run([*command, "-n", "--cores", "1", *config], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    jobs = re.findall(
        r"rule (study_grid_choice\w*):\n\s+input: \S+/(grid-[\w.-]+)\.yaml\n\s+output: (.*)", run.stdout
    )
    rules = {variant: rule for rule, variant, _ in jobs}
    outputs = {variant: {Path(p).name for p in files.split(", ")} for _, variant, files in jobs}
    assert rules == {
        f"grid-{lab}_r{r}": "study_grid_choice" + ("__2" if "pebi" in lab else "")
        for lab in LABELS
        for r in (0, 1)
    }
    for variant, files in outputs.items():
        kept = {"grid.grdecl", f"{variant}.roff"} & files
        assert kept == (set() if "pebi" in variant else {"grid.grdecl", f"{variant}.roff"})
        assert {"summary.json", "flow", "grid.nc"} <= files


def test_variants_find_the_base_case_trajectory_files(tmp_path):
    """A trajectory file named by the base case, also in the {file: ...} form and in a
    branch, is named from the variant's folder (it was left relative to the base case file)."""
    cases = ROOT / "config" / "cases"
    base = yaml.safe_load((cases / "trajectories_cp.yaml").read_text())
    base["wells"][0]["branches"] = [{"trajectory": {"file": "data/trajectories/p1h.xyz"}}]
    copy = tmp_path / "cases" / "t.yaml"  # the base with a branch, beside the sample's data
    copy.parent.mkdir()
    (copy.parent / "data").symlink_to(cases / "data")
    copy.write_text(yaml.safe_dump(base))
    study = tmp_path / "s.yaml"
    study.write_text(yaml.safe_dump({"name": "s", "base": "cases/t.yaml", "vary": {"grid.layers": [2]}}))
    loaded = load_study(study, tmp_path / "results", check=False)
    (variant,) = loaded.variants
    folder = loaded.case_file(tmp_path / "results", variant.name).parent
    well, target = variant.data["wells"][0], (cases / "data" / "trajectories" / "p1h.xyz").resolve()
    assert (folder / well["trajectory"]).resolve() == target
    assert (folder / well["branches"][0]["trajectory"]["file"]).resolve() == target


@pytest.mark.parametrize("layers_first", [True, False])
def test_a_key_inside_a_varied_section_changes_the_variants_section(tmp_path, layers_first):
    """`grid.layers` beside `grid` (sections): each variant's section with the layers of its
    combination, whichever key the study lists first."""
    sections = [{"label": "cp", **CP}, {"label": "pebi", **PEBI_80}]
    vary = (
        {"grid.layers": [2, 4], "grid": sections}
        if layers_first
        else {"grid": sections, "grid.layers": [2, 4]}
    )
    path = tmp_path / "s.yaml"
    path.write_text(yaml.safe_dump({"name": "s", "base": str(BASE), "vary": vary}, sort_keys=False))
    study = load_study(path, tmp_path / "results", check=False)
    got = {(v.values["grid"], v.values["grid.layers"]): v.data["grid"] for v in study.variants}
    assert got == {
        (section["label"], n): {k: x for k, x in section.items() if k != "label"} | {"layers": n}
        for section in sections
        for n in (2, 4)
    }
