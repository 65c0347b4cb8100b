"""A deck case as the tests build it: a small faulted anisotropic deck written in a folder,
a case file on it, and its stages run as the workflow runs them (``tests/stages``); any case's
stages run in this process as the workflow's rules run them, each with its own log
(:func:`run_as_the_workflow`)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml
from flow_tools import rest_of_deck

from gridlib import artifacts
from gridlib.config import load_case
from gridlib.cornerpoint.generators import simple_grdecl
from gridlib.io.grdecl import write_grdecl
from gridlib.io.transmissibility_file import read_transmissibility
from gridlib.stages import case_outputs, run_logged, run_stage

DIMS = (6, 5, 4)  # nx even: the fault of simple_grdecl lies between columns 3 and 4
SEED = 3


def anisotropic_rock(rng: np.random.Generator, keywords: tuple[str, ...]) -> dict[str, np.ndarray]:
    """Random rock and region keywords, one value per cell (those named in ``keywords``)."""
    nx, ny, nz = DIMS
    nc = nx * ny * nz
    j, k = np.arange(nc) // nx % ny, np.arange(nc) // (nx * ny)
    every = {
        "PORO": rng.uniform(0.1, 0.3, nc),
        "PERMX": rng.lognormal(4, 1, nc),
        "PERMY": rng.lognormal(3, 1, nc),
        "PERMZ": rng.lognormal(1, 1, nc),
        "NTG": rng.uniform(0.3, 0.9, nc),
        "FLUXNUM": 1.0 + (k >= 2),
        "MULTNUM": 3.0 + (j >= 2),
    }
    return {key: every[key] for key in keywords}


GRID_KEYWORDS = """EQUALS
 'MULTZ' 0.25 1 6 1 5 1 1 /
 'MULTX-' 0.5 2 3 1 5 2 4 /
/
FAULTS
 'F1' 3 3 1 5 1 4 X /
/
MULTFLT
 'F1' 0.3 /
/
MULTREGT
 3 4 0.45 XYZ ALL 1* /
 1 2 0.6 XYZ ALL F /
/
"""


def write_deck(folder: Path, keywords: tuple[str, ...], grid: str = GRID_KEYWORDS) -> Path:
    """ANISO.DATA in ``folder``: the faulted deck (throw 12 m) with ``keywords`` of
    :func:`anisotropic_rock` and the GRID-section text ``grid``, METRIC, oil-water."""
    folder.mkdir(parents=True, exist_ok=True)
    deck = simple_grdecl(DIMS, 12.0, phys_dims=(600.0, 500.0, 40.0))
    deck = replace(
        deck,
        coord=deck.coord + np.tile([0, 0, 1000.0], 2 * (DIMS[0] + 1) * (DIMS[1] + 1)),
        zcorn=deck.zcorn + 1000.0,
    )  # below the surface, as the Flow deck's equilibrium expects
    write_grdecl(folder / "ANISO.GRDECL", deck, anisotropic_rock(np.random.default_rng(SEED), keywords))
    nx, ny, nz = DIMS
    text = f"RUNSPEC\nDIMENS\n {nx} {ny} {nz} /\nOIL\nWATER\nMETRIC\nTABDIMS\n 1 1 20 20 /\n"
    text += "GRIDOPTS\n 'NO' 1 /\n"  # NRMULT > 0: MULTREGT's default region set is MULTNUM
    text += "EQLDIMS\n 1 /\nSTART\n 1 'JAN' 2020 /\nUNIFOUT\nGRID\nINIT\nINCLUDE\n 'ANISO.GRDECL' /\n"
    text += grid + rest_of_deck(float(deck.zcorn.min()), float(deck.zcorn.max()) + 1)
    (folder / "ANISO.DATA").write_text(text)
    return folder / "ANISO.DATA"


def write_case(folder: Path, name: str, petrophysics: dict | None = None) -> Path:
    data = {"name": name, "grid": {"type": "deck", "file": "ANISO.DATA"}}
    if petrophysics is not None:
        data["petrophysics"] = petrophysics
    path = folder / f"{name}.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def build(case: Path, out: Path, flow_deck: bool = False) -> dict[str, Path]:
    """The stages of a deck case into ``out``, as the workflow runs them."""
    out.mkdir(parents=True, exist_ok=True)
    paths = {k: out / f"{k}.nc" for k in ("grid", "geometry", "petrophysics", "transmissibility")}
    paths["grdecl"] = out / "grid.grdecl"
    loaded = load_case(case)
    stages = ["grid", "geometry", "petrophysics"]
    if flow_deck:
        paths["flow_deck"] = out / "flow" / f"{loaded.flow_name}.DATA"
        stages += ["transmissibility", "flow_deck"]
    for stage in stages:
        run_stage(stage, loaded, paths)
    return paths


def run_as_the_workflow(case_file: Path, results: Path) -> Path:
    """Every stage of the case (those it has, not those run on request) into
    ``results/<case>/``, each as its Snakemake rule runs it (common.smk's stage_job: through
    run_logged, its log ``results/logs/<case>/<stage>[.<NAME>].log``), one after the other in
    this process, without a Python start-up per stage; returns the case's folder. A failing
    stage fails the test with its log."""
    case = load_case(case_file)
    folder = results / case.name
    folder.mkdir(parents=True, exist_ok=True)
    paths = case_outputs(case.name, folder)
    for stage in artifacts.STAGES:
        outputs = stage.outputs_of(case)
        if not outputs or stage.on_request:
            continue
        tag = f".{case.flow_name}" if any("NAME" in a.wildcards for a in outputs) else ""
        log = results / "logs" / case.name / f"{stage.name}{tag}.log"
        try:
            run_logged(
                log,
                run_stage,
                stage.name,
                case,
                paths,
                threads=stage.threads,
                outputs=[paths[a.key] for a in outputs],
                name=f"stage_{stage.name}",
                label=f"{case.name}: {stage.name}",
            )
        except SystemExit:
            pytest.fail(f"{case.name}: stage {stage.name} failed:\n{log.read_text()[-3000:]}")
    return folder


def assert_close(ours: dict, ref: dict, what: str) -> None:
    assert set(ours) == set(ref), (what, sorted(set(ours) ^ set(ref))[:5])
    keys = list(ref)
    a, b = np.array([ours[p] for p in keys]), np.array([ref[p] for p in keys])
    worst = int(np.argmax(np.abs(a - b) / np.abs(b)))
    assert np.all(np.abs(a - b) <= 1e-6 * np.abs(b)), (what, keys[worst], a[worst], b[worst])


def assert_stage_file_equals_flow(path: Path, ref: dict, ref_porv: np.ndarray) -> tuple[np.ndarray, dict]:
    """transmissibility.nc at ``path`` holds Flow's connections ``ref`` ({(g1, g2): T}) and pore
    volumes ``ref_porv`` (INIT's PORV, per active cell) within 1e-6; returns its cells' linear
    indices (``cell_flow_index``) and its attributes."""
    variables, attrs = read_transmissibility(path)
    glob = variables["cell_flow_index"].values
    pairs = np.sort(glob[variables["connection_cells"].values], axis=1)
    ours = dict(zip(map(tuple, pairs.tolist()), variables["trans"].values.tolist(), strict=True))
    assert_close(ours, ref, str(path))
    flow_porv = ref_porv[glob].astype(np.float64)
    assert np.all(np.abs(variables["porv"].values - flow_porv) <= 1e-6 * flow_porv)
    return glob, attrs
