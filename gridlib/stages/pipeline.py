"""All of a case's stages in order, in one folder (what ``gridlib build`` and a study's
variant jobs run): the stages of :data:`gridlib.artifacts.STAGES` the case has."""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from importlib import import_module
from pathlib import Path
from typing import Any

from .. import artifacts
from ..config import Case, load_case


def case_outputs(name: str, folder: str | os.PathLike) -> dict[str, Path]:
    """The paths of a case's artifacts in ``folder`` (the workflow's results/{case}/ layout), by
    key (:func:`gridlib.artifacts.case_paths`)."""
    return artifacts.case_paths(name, folder)


def run_case(case: Case | str | os.PathLike, folder: str | os.PathLike, simulate: bool = False) -> list[Path]:
    """Run every stage the case (a loaded case or its file) needs into ``folder``; returns the
    artifacts written. With ``simulate``, OPM Flow also runs the deck of a case with a
    ``simulation`` section (the stages run only when asked)."""
    if not isinstance(case, Case):
        case = load_case(case)
    paths = artifacts.case_paths(case.name, folder)
    Path(folder).mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    for stage in artifacts.STAGES:
        if not stage.when(case) or (stage.on_request and not simulate):
            continue
        outputs = [a.key for a in stage.outputs_of(case)]
        keys = artifacts.stage_inputs(stage, case) + tuple(outputs)
        stage_function(stage)(case, **{key: paths[key] for key in keys})
        written += [paths[key] for key in outputs]
    dropped = {paths[key] for key in artifacts.dropped(case)}  # outputs.stage_files: false
    for path in dropped:
        path.unlink(missing_ok=True)
    return [p for p in written if p not in dropped]


def run_stage(name: str, case: Case | str | os.PathLike, paths: Mapping[str, str | os.PathLike]) -> Any:
    """Run the stage ``name`` of :data:`gridlib.artifacts.STAGES` for ``case`` (loaded, or its
    file) with the paths of its inputs and outputs taken from ``paths`` (artifact key -> path;
    other keys are ignored); returns what the stage function returns.

    The Snakemake rules run their stage so (``workflow/scripts/stage.py``)."""
    if not isinstance(case, Case):
        case = load_case(case)
    stage = next((s for s in artifacts.STAGES if s.name == name), None)
    if stage is None:
        raise ValueError(f"no stage {name!r} (stages: {', '.join(s.name for s in artifacts.STAGES)})")
    keys = artifacts.stage_inputs(stage, case) + tuple(a.key for a in stage.outputs_of(case))
    return stage_function(stage)(case, **{key: Path(paths[key]) for key in keys if key in paths})


def stage_function(stage: artifacts.Stage) -> Callable[..., Any]:
    """The function of ``stage``, imported where the table names it as ``"module:function"``."""
    if not isinstance(stage.function, str):
        return stage.function
    module, _, name = stage.function.partition(":")
    return getattr(import_module(module), name)
