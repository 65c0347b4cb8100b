"""Damaged artifacts (issue 24, item 5): a stage file cut in half, with its header zeroed or
with 64 bytes flipped in its middle makes every stage that reads it fail with one InputError
naming that file (never a silent success, never another exception), and the workflow's
console shows that one line without a traceback.

One small case (corner-point, from horizons, with rock, coarsening, a deviated well and a Flow
deck) is built once in-process; each test damages one copy of one of its files."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml
from artifacts import run_case_without_pictures

from gridlib import artifacts
from gridlib.config import load_case
from gridlib.errors import InputError
from gridlib.io.datasets import DIGEST, load_artifact, save_dataset
from gridlib.io.netcdf import read_netcdf
from gridlib.io.rock_file import read_rock, write_rock
from gridlib.stages import case_outputs
from gridlib.stages.pipeline import run_stage

CASE = {
    "name": "dented",
    "seed": 3,
    "horizons": {
        "ordering": "erode",
        "lattice": {"x": {"start": 0, "stop": 400, "num": 9}, "y": {"start": 0, "stop": 300, "num": 7}},
        "surfaces": [
            {"name": "top", "dome": {"depth": 1000, "relief": 20, "radius": 300, "x0": 200, "y0": 150}},
            {"name": "base", "dome": {"depth": 1030, "relief": 20, "radius": 300, "x0": 200, "y0": 150}},
        ],
    },
    "faults": [{"name": "F1", "trace": [[150, -10], [180, 310]], "throw": 5}],
    "grid": {"type": "cornerpoint", "dims": [24, 18], "layers": [4]},  # files mostly of data chunks
    "petrophysics": {"porosity": {"layers": [0.2, 0.25, 0.1, 0.3]}, "permeability": {"constant": 100.0}},
    "coarsen": {"method": "uniform", "dims": [2, 2, 1]},
    "wells": [  # a deviated well: wells.nc
        {
            "name": "D1",
            "survey": {"head": [100, 150, 950], "stations": [[950, 0, 90], [1000, 60, 90], [1150, 60, 90]]},
        }
    ],
}

ROOT = Path(__file__).resolve().parents[2]
ADVICE = "delete it and rerun the workflow"

# Every stage file and the {case}.nc export (read by no stage: by read_netcdf, as users do).
FILES = (
    "horizons",
    "grid",
    "geometry",
    "petrophysics",
    "coarse",
    "transmissibility",
    "quality",
    "wells",
    "nc",
)


def _truncate(data: bytes) -> bytes:
    return data[: len(data) // 2]


def _zero_header(data: bytes) -> bytes:
    return bytes(512) + data[512:]


def _flip_middle(data: bytes) -> bytes:
    """64 bytes of the middle half of the file, each XOR-ed with a non-zero byte (seeded)."""
    rng = np.random.default_rng(24)
    out = np.frombuffer(data, dtype=np.uint8).copy()
    where = rng.choice(np.arange(len(data) // 4, 3 * len(data) // 4), size=64, replace=False)
    out[where] ^= rng.integers(1, 256, size=64, dtype=np.uint8)
    return out.tobytes()


DAMAGES: dict[str, Callable[[bytes], bytes]] = {
    "truncated": _truncate,
    "zeroed_header": _zero_header,
    "flipped_bytes": _flip_middle,
}


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> tuple[Path, Path]:
    """The case file and its folder with every artifact, built once (without the pictures
    stage's pictures, two thirds of the time and read by no stage)."""
    root = tmp_path_factory.mktemp("damaged")
    case_file = root / "dented.yaml"
    case_file.write_text(yaml.safe_dump(CASE), encoding="utf-8")
    folder = root / "results" / "dented"
    run_case_without_pictures(case_file, folder)
    return case_file, folder


def readers(key: str) -> list[str]:
    """The stages (run by default) that read the artifact ``key``."""
    return [s.name for s in artifacts.STAGES if key in s.inputs and not s.on_request]


def test_every_stage_file_has_readers_or_is_the_export():
    """The table of stage files above is the stage table's: each is read by some stage."""
    written = {
        a.key for s in artifacts.STAGES if not s.on_request for a in s.outputs if a.path.endswith(".nc")
    }
    assert written == set(FILES)
    assert all(readers(key) for key in FILES if key != "nc")


def _compared(stage: str, paths: dict[str, Path]) -> list[Path]:
    """The files of ``stage`` compared with the undamaged build's (not the pictures, which the
    fixture leaves out; a Flow deck's includes too)."""
    keys = [a.key for s in artifacts.STAGES if s.name == stage for a in s.outputs]
    files = [paths[key] for key in keys if key in paths and paths[key].suffix != ".png"]
    return files + sorted(files[0].parent.glob("*.INC")) if stage == "flow_deck" else files


@pytest.mark.parametrize("damage", DAMAGES)
@pytest.mark.parametrize("key", FILES)
def test_a_damaged_artifact_is_one_error_naming_it(built, tmp_path, key, damage):
    """Every stage that reads the damaged file fails with one InputError naming it; a stage that
    reads none of the damaged bytes (the transmissibility of a corner-point grid needs only the
    number of cells of geometry.nc) may succeed, but then with outputs identical to those of
    the undamaged files; and at least one stage fails."""
    case_file, folder = built
    copy = tmp_path / "dented"
    shutil.copytree(folder, copy)
    inputs = case_outputs("dented", copy)
    target = inputs[key]
    target.write_bytes(DAMAGES[damage](target.read_bytes()))
    outputs = case_outputs("dented", tmp_path / "out")  # the undamaged inputs stay as they were
    case = load_case(case_file)
    failed = []
    for stage in readers(key) if key != "nc" else ["read_netcdf"]:
        try:
            if stage == "read_netcdf":
                read_netcdf(target)
            else:
                written = {a.key for s in artifacts.STAGES if s.name == stage for a in s.outputs}
                run_stage(stage, case, {**inputs, **{k: outputs[k] for k in written}})
        except InputError as error:
            message = str(error)
            # named by the stage that read it (gridlib.stages.pipeline.in_stage_message), and alone
            within = "" if stage == "read_netcdf" else f"{case.path}: stage {stage}: "
            assert message.startswith(f"{within}{target}: damaged or incomplete ("), (stage, message)
            assert message.endswith(f"; {ADVICE}"), (stage, message)
            assert "\n" not in message and "np." not in message, (stage, message)
            assert error.__cause__ is None and error.__suppress_context__, stage
            failed.append(stage)
            continue
        for path in _compared(stage, outputs) if stage != "read_netcdf" else []:
            # no silent misread: a stage that succeeds wrote what the undamaged files give
            pristine = folder / path.relative_to(tmp_path / "out")
            assert path.read_bytes() == pristine.read_bytes(), (stage, path.name)
    assert failed, f"no reader of {target.name} noticed the damage"


def test_the_workflow_names_a_damaged_artifact_in_one_line(built, tmp_path):
    """Snakemake over the built case with 64 bytes of geometry.nc flipped and petrophysics.nc
    gone: the petrophysics job fails, and the console names geometry.nc in one line (the
    variable whose checksum fails included) with no traceback."""
    case_file, folder = built
    config = tmp_path / "config" / case_file.name
    config.parent.mkdir()
    shutil.copy2(case_file, config)  # modification times kept: only what is missing reruns
    results = tmp_path / "results" / "dented"
    shutil.copytree(folder, results)
    (results / "petrophysics.nc").unlink()
    geometry = results / "geometry.nc"
    geometry.write_bytes(_flip_middle(geometry.read_bytes()))
    shutil.copystat(folder / "geometry.nc", geometry)
    result = subprocess.run(
        [sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"), "--directory", str(tmp_path),
         "--cores", "1", "--rerun-triggers", "mtime", "--config", f"cases=[{config}]", "studies=[]"],
        capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    out = result.stdout + result.stderr
    assert result.returncode != 0
    named = [line for line in out.splitlines() if "geometry.nc: damaged or incomplete" in line]
    reason = "HDF error on variable 'face_normal': its checksum fails or its data is cut short"
    damage = f"results/dented/geometry.nc: damaged or incomplete ({reason}); {ADVICE}"
    assert named == [f"gridlib: {config}: stage petrophysics: {damage}"], out[-3000:]
    assert "Traceback" not in out and 'File "' not in out and "zstd" not in out, out[-3000:]


def test_a_rock_file_with_values_no_stage_writes_is_blamed_not_the_deck(built, tmp_path):
    """A petrophysics.nc with a negative permeability (which the petrophysics stage never writes:
    its Rock refuses it) is named by the transmissibility and Flow deck stages; it used to reach
    the deck's checks of PERMX and be blamed on grid.grdecl, whose keywords it replaces."""
    case_file, folder = built
    copy = tmp_path / "dented"
    shutil.copytree(folder, copy)
    paths = case_outputs("dented", copy)
    rock = read_rock(paths["petrophysics"])
    rock["permx"][7] = -rock["permx"][7]

    class Stored:  # write_rock takes what has cell_data(), as a Rock
        @staticmethod
        def cell_data():
            return rock

    write_rock(paths["petrophysics"], Stored, {})
    outputs = case_outputs("dented", tmp_path / "out")
    case = load_case(case_file)
    for stage, key in (("transmissibility", "transmissibility"), ("flow_deck", "flow_deck")):
        with pytest.raises(InputError) as caught:
            run_stage(stage, case, {**paths, key: outputs[key]})
        assert str(caught.value) == (
            f"{case.path}: stage {stage}: {paths['petrophysics']}: damaged or incomplete "
            "(variable 'permx' has 1 negative or undefined "
            f"values); {ADVICE}"
        )


def test_what_fletcher32_leaves_out_is_covered_by_the_digest(tmp_path):
    """One bit changed in a scalar variable (contiguous) or in a string variable (HDF5's global
    heap) reads back silently but for the file's digest; one in the digest attribute's name
    (a checksummed object header) is an HDF error. Every chunked variable has Fletcher32 and
    reads back bit for bit."""
    marker = np.int64(0x1F2E3D4C5B6A7988)
    values = np.random.default_rng(5).normal(size=(300, 3))
    ds = xr.Dataset(
        {
            "values": (("n", "xyz"), values),
            "mesh2d": ((), marker),
            "names": ("h", np.array(["top_horizon", "base_horizon"], dtype=object)),
        },
        attrs={"title": "digest test"},
    )
    path = tmp_path / "a.nc"
    save_dataset(path, ds)
    back = load_artifact(path)
    assert back["values"].encoding["fletcher32"] and back["values"].values.tobytes() == values.tobytes()
    assert DIGEST not in back.attrs and back.attrs == {"title": "digest test"}
    data = path.read_bytes()
    expected = {
        marker.tobytes(): "digest mismatch: an attribute, a scalar or a string variable changed",
        b"base_horizon": "digest mismatch: an attribute, a scalar or a string variable changed",
        DIGEST.encode(): "HDF error: the file is cut short or its bytes are changed",
    }
    for pattern, reason in expected.items():
        assert data.count(pattern) == 1, pattern
        at = data.index(pattern) + 1
        path.write_bytes(data[:at] + bytes([data[at] ^ 1]) + data[at + 1 :])
        with pytest.raises(InputError) as caught:
            load_artifact(path)
        assert (
            str(caught.value) == f"{path}: damaged or incomplete ({reason}); delete it and rerun the workflow"
        )
    save_dataset(path, back)  # a dataset read back is written with a digest of its own
    assert load_artifact(path)["mesh2d"].values == marker


@pytest.mark.parametrize("damage", DAMAGES)
def test_a_damaged_summary_is_one_error_naming_it(built, tmp_path, damage):
    """The summary and study stages read every case's summary.json: a damaged one is named."""
    from gridlib.stages.summary import stage_summary

    _, folder = built
    summary = tmp_path / "summary.json"
    summary.write_bytes(DAMAGES[damage]((folder / "summary.json").read_bytes()))
    with pytest.raises(InputError) as caught:
        stage_summary([folder / "summary.json", summary], tmp_path / "summary.csv")
    assert str(caught.value).startswith(f"{summary}: damaged or incomplete (")
    assert str(caught.value).endswith(ADVICE) and not (tmp_path / "summary.csv").exists()


MANIFEST = {
    "intact": lambda text: text,
    "zeroed_header": lambda text: "\0" * 64 + text[64:],
    "not_a_table": lambda text: "study: s\nvariants: 3\n",
    "variant_renamed": lambda text: text.replace("name: dented", "name: dentex"),
}


@pytest.mark.parametrize("damage", MANIFEST)
def test_a_damaged_study_manifest_is_one_error_naming_it(built, tmp_path, damage):
    """The study stage reads results/<study>/variants.yaml (written when the workflow is parsed):
    unreadable, not a variant table, or naming a variant whose summary is not among the inputs,
    it is one error naming the manifest, and no table is written."""
    import yaml

    from gridlib.stages.study import stage_study

    _, folder = built
    manifest = tmp_path / "variants.yaml"
    doc = {
        "study": "s",
        "keys": ["faults.0.throw"],
        "key_quantities": {"faults.0.throw": {"quantity": "length"}},
        "combine": "product",
        "variants": [{"name": "dented", "values": {"faults.0.throw": 5}, "realisation": 0, "seed": 7}],
    }
    manifest.write_text(MANIFEST[damage](yaml.safe_dump(doc, sort_keys=False)))
    outputs = {key: tmp_path / f"study.{key}" for key in ("csv", "nc", "png")}
    if damage == "intact":
        stage_study(manifest, [folder / "summary.json"], outputs)
        assert outputs["csv"].read_text().splitlines()[1].startswith("dented,5,0,7,")
        return
    with pytest.raises(InputError) as caught:
        stage_study(manifest, [folder / "summary.json"], outputs)
    assert str(caught.value).startswith(f"{manifest}: damaged or incomplete (")
    assert str(caught.value).endswith(ADVICE) and "\n" not in str(caught.value)
    assert not any(path.exists() for path in outputs.values())


def test_what_a_failed_read_writes_to_stderr_is_dropped_and_a_good_reads_passed_on(capfd):
    """_filters_quiet holds back the C library's standard error during a read: dropped when the
    read fails (its one error tells it), passed on when it succeeds; nothing held is left over
    for the next read (one file per process holds it)."""
    from gridlib.io.datasets import _filters_quiet

    with pytest.raises(RuntimeError), _filters_quiet():
        os.write(2, b"zstd: Data corruption detected\n")
        raise RuntimeError("HDF error")
    assert capfd.readouterr().err == ""
    with _filters_quiet():
        os.write(2, b"a note from C\n")
    assert capfd.readouterr().err == "a note from C\n"
    with _filters_quiet():  # the same held file, emptied: only this read's text comes out
        os.write(2, b"another\n")
    assert capfd.readouterr().err == "another\n"
