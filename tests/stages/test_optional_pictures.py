"""``outputs.pictures: false`` (a case) and ``pictures: false`` (a study, for every variant):
no PNG of the case's own, every other artifact written with the same values; a value that is
no boolean is one line naming the file and the key."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import gridlib as gl
from gridlib.artifacts import case_artifacts
from gridlib.config import load_case
from gridlib.stages import run_case
from gridlib.study import load_study

CASES = Path(__file__).resolve().parents[2] / "config" / "cases"
PICTURES = {"png", "histograms", "plan", "section", "quality_png"}
# A small 3-D case with rock: every stage but the deck's simulation runs on it.
CASE = """name: {name}
seed: 3
grid: {{type: cartesian, dims: [6, 5, 2], lengths: [600, 500, 20]}}
petrophysics:
  porosity: {{constant: 0.2}}
  permeability:
    field: {{model: exponential, len_scale: [200, 200, 5], mean: 100, std: 0.5}}
  ntg: {{constant: 1.0}}
{outputs}"""


def _case(tmp_path: Path, name: str, outputs: str = "") -> Path:
    path = tmp_path / f"{name}.yaml"
    path.write_text(CASE.format(name=name, outputs=outputs))
    return path


def _written(case: Path, folder: Path) -> set[str]:
    """The files run_case writes for ``case`` into ``folder``, the case's name as ``{case}``."""
    name = re.compile(re.escape(case.stem), re.IGNORECASE)
    return {name.sub("{case}", p.relative_to(folder).as_posix()) for p in run_case(case, folder)}


def test_a_case_without_pictures_writes_every_other_artifact_with_the_same_values(tmp_path):
    drawn = _case(tmp_path, "drawn")
    plain = _case(tmp_path, "plain", "outputs: {pictures: false}\n")
    assert PICTURES <= {a.key for a in case_artifacts(load_case(drawn))}
    assert not PICTURES & {a.key for a in case_artifacts(load_case(plain))}
    with_pictures = _written(drawn, tmp_path / "drawn")
    without = _written(plain, tmp_path / "plain")
    assert with_pictures - without == {
        "{case}.png",
        "{case}_histograms.png",
        "{case}_plan.png",
        "{case}_section.png",
        "{case}_quality.png",
    }
    assert without < with_pictures
    assert not list((tmp_path / "plain").glob("*.png"))
    for name in ("quality.nc", "transmissibility.nc", "petrophysics.nc"):
        with xr.open_dataset(tmp_path / "drawn" / name) as a, xr.open_dataset(tmp_path / "plain" / name) as b:
            assert list(a.variables) == list(b.variables)
            for var in a.variables:
                np.testing.assert_array_equal(a[var].values, b[var].values, err_msg=f"{name}: {var}")


def _study(tmp_path: Path, extra: str = "") -> Path:
    study = tmp_path / "s.yaml"
    base = (CASES / "waterflood_pebi.yaml").resolve()
    study.write_text(f"name: s\nbase: {base}\nvary: {{faults.0.throw: [0, 30]}}\n{extra}")
    return study


def test_a_study_without_pictures_gives_every_variant_outputs_pictures_false(tmp_path):
    drawn = load_study(_study(tmp_path), tmp_path / "results")
    assert all(PICTURES <= set(v.artifacts) for v in drawn.variants)  # the default: pictures
    plain = load_study(_study(tmp_path, "pictures: false\n"), tmp_path / "results")
    assert [v.data["outputs"]["pictures"] for v in plain.variants] == [False, False]
    for a, b in zip(drawn.variants, plain.variants, strict=True):
        assert set(a.artifacts) - set(b.artifacts) == PICTURES
        assert {"nc", "summary", "quality", "flow"} <= set(b.artifacts)


@pytest.mark.parametrize("where", ["study", "case"])
def test_a_pictures_value_that_is_no_boolean_names_the_file_and_the_key(tmp_path, where):
    if where == "study":
        with pytest.raises(gl.InputError, match=r"s\.yaml: pictures: 'no' is not of type 'boolean'"):
            load_study(_study(tmp_path, "pictures: 'no'\n"), tmp_path / "results")
    else:
        case = _case(tmp_path, "c", "outputs: {pictures: 0}\n")
        with pytest.raises(gl.InputError, match=r"c\.yaml: outputs\.pictures: 0 is not of type 'boolean'"):
            load_case(case)
