"""All of a case's stages in order, in one folder (what ``gridlib build`` and a study's
variant jobs run): the stages of :data:`gridlib.artifacts.STAGES` the case has."""

from __future__ import annotations

import contextlib
import os
import re
import shutil
from collections.abc import Callable, Iterable, Iterator, Mapping
from importlib import import_module
from pathlib import Path
from typing import Any

from .. import artifacts
from ..config import Case, load_case
from ..errors import GridError, InputError
from ..io.shared_reads import shared_reads

_BEFORE = ".before-run"  # the suffix of the hard links that keep an output as it was before a run
_NUMPY_SCALAR = re.compile(r"np\.(?:float|int|uint|bool|complex)\w*\(([^()]*)\)")


def case_outputs(name: str, folder: str | os.PathLike) -> dict[str, Path]:
    """The paths of a case's artifacts in ``folder`` (the workflow's results/{case}/ layout), by
    key (:func:`gridlib.artifacts.case_paths`)."""
    return artifacts.case_paths(name, folder)


def run_case(case: Case | str | os.PathLike, folder: str | os.PathLike, simulate: bool = False) -> list[Path]:
    """Run every stage the case (a loaded case or its file) needs into ``folder``; returns the
    artifacts written. With ``simulate``, OPM Flow also runs the deck of a case with a
    ``simulation`` section (the stages run only when asked).

    A failing stage raises its error (an InputError or GridError naming the case file and the
    stage) and leaves ``folder`` as it was before the run: the files it held put back, those
    the run wrote removed. A file one stage wrote is read once by the later stages that read
    it (:mod:`gridlib.io.shared_reads`)."""
    if not isinstance(case, Case):
        case = load_case(case)
    paths = artifacts.case_paths(case.name, folder)
    folder = Path(folder)
    new_folder = not folder.exists()
    folder.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []
    try:
        with restored_on_failure(_results(folder, paths), sweep=folder), shared_reads():
            for stage in artifacts.STAGES:
                if not stage.when(case) or (stage.on_request and not simulate):
                    continue
                outputs = [a.key for a in stage.outputs_of(case)]
                keys = artifacts.stage_inputs(stage, case) + tuple(outputs)
                _call(stage, case, {key: paths[key] for key in keys})
                written += [paths[key] for key in outputs]
    except BaseException:
        if new_folder:
            with contextlib.suppress(OSError):
                folder.rmdir()
        raise
    dropped = {paths[key] for key in artifacts.dropped(case)}  # outputs.stage_files: false
    for path in dropped:
        path.unlink(missing_ok=True)
    return [p for p in written if p not in dropped]


def run_stage(name: str, case: Case | str | os.PathLike, paths: Mapping[str, str | os.PathLike]) -> Any:
    """Run the stage ``name`` of :data:`gridlib.artifacts.STAGES` for ``case`` (loaded, or its
    file) with the paths of its inputs and outputs taken from ``paths`` (artifact key -> path;
    other keys are ignored); returns what the stage function returns. An InputError or GridError
    raised in the stage names the case file and the stage; the stage's outputs are then as they
    were before (:func:`restored_on_failure`).

    The Snakemake rules run their stage so (``stage_job`` of ``workflow/rules/common.smk``)."""
    if not isinstance(case, Case):
        case = load_case(case)
    stage = next((s for s in artifacts.STAGES if s.name == name), None)
    if stage is None:
        raise ValueError(f"no stage {name!r} (stages: {', '.join(s.name for s in artifacts.STAGES)})")
    if not stage.when(case):
        raise ValueError(f"{case.path}: the case has no {name} stage (its sections do not ask for it)")
    outputs = tuple(a.key for a in stage.outputs_of(case))
    keys = artifacts.stage_inputs(stage, case) + outputs
    with restored_on_failure([Path(paths[key]) for key in outputs if key in paths]):
        return _call(stage, case, {key: Path(paths[key]) for key in keys if key in paths})


def _call(stage: artifacts.Stage, case: Case, paths: dict[str, Path]) -> Any:
    """The stage's function on ``case`` and ``paths``; an InputError or GridError raised inside
    it names the case file and the stage (:func:`in_stage_message`)."""
    try:
        return stage_function(stage)(case, **paths)
    except (InputError, GridError) as exc:
        exc.args = (in_stage_message(str(exc), case, stage.name),)
        raise


def in_stage_message(message: str, case: Case, stage: str) -> str:
    """``message`` of an error raised in ``stage`` of ``case`` as the user reads it: prefixed
    with the case file and the stage where it does not name the case file already (a deck's
    own messages name the deck, line and keyword; those of the builders name the case's keys),
    numpy scalars written as plain numbers."""
    message = _NUMPY_SCALAR.sub(r"\1", message)
    if str(case.path) in message:
        return message
    return f"{case.path}: stage {stage}: {message}"


@contextlib.contextmanager
def restored_on_failure(paths: Iterable[Path], sweep: Path | None = None) -> Iterator[None]:
    """Run the body; if it raises, put every one of ``paths`` back as it was before (the file it
    was, or no file), and remove every file under ``sweep`` that the body created, so that a
    failure leaves no result half-written. The files are kept by hard links (no copy), which
    the atomic writers (:mod:`gridlib.io.atomic`) leave intact since they replace a file rather
    than write into it."""
    paths = list(dict.fromkeys(Path(p) for p in paths))
    before = set(_entries(sweep)) if sweep is not None else set()
    kept = {path: _keep(path) for path in paths if path.is_file() or path.is_dir()}
    try:
        yield
    except BaseException:
        for path in paths:
            if path.is_dir() and not path.is_symlink():  # a directory artifact: put back whole
                shutil.rmtree(path)
                if path in kept:
                    os.replace(kept[path], path)
            elif path not in kept:
                path.unlink(missing_ok=True)
            elif kept[path].is_dir():
                os.replace(kept[path], path)
            elif path.exists() and os.path.samefile(path, kept[path]):  # untouched (rename would keep both)
                kept[path].unlink()
            else:
                os.replace(kept[path], path)
        if sweep is not None:
            created = set(_entries(sweep)) - before - set(kept.values())
            for path in sorted(created, key=lambda p: len(p.parts), reverse=True):  # files, then folders
                with contextlib.suppress(OSError):
                    path.rmdir() if path.is_dir() else path.unlink()
        raise
    else:
        for backup in kept.values():
            shutil.rmtree(backup) if backup.is_dir() else backup.unlink(missing_ok=True)


def _keep(path: Path) -> Path:
    """A hard link (a copy where the file system has none) to ``path`` beside it; of a folder
    (a directory artifact), a folder of hard links to its files."""
    backup = path.with_name(f".{path.name}{_BEFORE}")
    if path.is_dir():
        shutil.rmtree(backup, ignore_errors=True)
        shutil.copytree(path, backup, copy_function=_link_or_copy)
        return backup
    backup.unlink(missing_ok=True)
    try:
        os.link(path, backup)
    except OSError:
        shutil.copy2(path, backup)
    return backup


def _link_or_copy(source: str, target: str) -> None:
    try:
        os.link(source, target)
    except OSError:
        shutil.copy2(source, target)


def _is_result(path: Path) -> bool:
    return path.is_file() and not any(part.endswith(_BEFORE) for part in path.parts)


def _results(folder: Path, paths: Mapping[str, Path]) -> list[Path]:
    """What a run in ``folder`` may replace: its files, but those in a directory artifact's
    folder (``exchange/``), which is kept whole."""
    folders = [paths[a.key] for a in artifacts.artifacts().values() if a.directory]
    files = [p for p in folder.rglob("*") if _is_result(p) and not any(d in p.parents for d in folders)]
    return sorted(files) + [d for d in folders if d.is_dir()]


def _entries(folder: Path) -> list[Path]:
    """The files and folders under ``folder``."""
    return list(folder.rglob("*")) if folder.is_dir() else []


def stage_function(stage: artifacts.Stage) -> Callable[..., Any]:
    """The function of ``stage``, imported where the table names it as ``"module:function"``."""
    if not isinstance(stage.function, str):
        return stage.function
    module, _, name = stage.function.partition(":")
    return getattr(import_module(module), name)
