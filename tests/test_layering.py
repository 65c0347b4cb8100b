"""Imports named by strings obey the layering of the import contract, and every public name imports.

import-linter (``lint-imports``, the contract in pyproject.toml) sees import statements only.
gridlib names three kinds of imports as strings, imported on first use: the ``_EXPORTS`` tables
of its packages (:func:`gridlib._lazy.lazy_exports`), the ``"module:function"`` readers and
writers of :data:`gridlib.io.registry.BUILTIN_FORMATS`, and the stage functions of the artifact
table :data:`gridlib.artifacts.STAGES` (imported by :mod:`gridlib.stages.pipeline`). These tests
resolve every such name and hold it to the contract's layers, read from pyproject.toml; and
check that those three are the only places gridlib imports by name.
"""

from __future__ import annotations

import ast
import importlib
import pkgutil
import tomllib
from importlib.util import resolve_name
from pathlib import Path

import pytest

import gridlib
from gridlib.artifacts import STAGES
from gridlib.io.registry import BUILTIN_FORMATS

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = Path(gridlib.__file__).parent


def _contract() -> tuple[str, list[list[str]], str]:
    """The layers contract: its container, its layers (top first, each a list of modules) and
    each layer's separator (``|``: independent siblings, ``:``: siblings that may import each other)."""
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]
    (layers,) = [c for c in contracts if c["type"] == "layers"]
    (container,) = layers["containers"]
    parsed = []
    for layer in layers["layers"]:
        sep = "|" if "|" in layer else ":"
        parsed.append((sep, [m.strip().strip("()") for m in layer.split(sep)]))
    return container, [mods for _, mods in parsed], [sep for sep, _ in parsed]


CONTAINER, LAYERS, SEPARATORS = _contract()


def _layer_of(module: str) -> tuple[str, int]:
    """The top-level module of the container that ``module`` is in, and the index of its layer."""
    top = module.split(".")[1]
    for index, layer in enumerate(LAYERS):
        if top in layer:
            return top, index
    raise AssertionError(f"{module}: {top!r} is in no layer of the import contract (exhaustive = true)")


def may_import(importer: str, imported: str) -> bool:
    """Whether the contract lets ``importer`` import ``imported`` (dotted module names). The
    container itself is in no layer (as for import-linter)."""
    if importer == CONTAINER:
        return True
    (top, low), (other, high) = _layer_of(importer), _layer_of(imported)
    if top == other:
        return True
    return low < high or (low == high and SEPARATORS[low] == ":")


def test_the_layer_rule_is_the_contracts():
    assert may_import("gridlib.stages.grid", "gridlib.io.netcdf")
    assert not may_import("gridlib.io.registry", "gridlib.stages.grid")  # up
    assert not may_import("gridlib.case.grid", "gridlib.study")  # independent siblings
    assert may_import("gridlib.io.registry", "gridlib.io.netcdf") and may_import("gridlib", "gridlib.stages")
    with pytest.raises(AssertionError, match="in no layer"):
        may_import("gridlib.nowhere", "gridlib.grid")


def _modules() -> list[tuple[str, Path]]:
    """Every module of gridlib: its dotted name and its file."""
    out = [(gridlib.__name__, PACKAGE / "__init__.py")]
    for info in pkgutil.walk_packages(gridlib.__path__, gridlib.__name__ + "."):
        path = PACKAGE.joinpath(*info.name.split(".")[1:])
        out.append((info.name, path / "__init__.py" if info.ispkg else path.with_suffix(".py")))
    return out


def _lazy_tables() -> list[tuple[str, str]]:
    """(module, table name) of every ``lazy_exports(__name__, table)`` call in gridlib."""
    found = []
    for module, path in _modules():
        text = path.read_text()
        if "lazy_exports" not in text:  # parsing every module at collection took a second
            continue
        for node in ast.walk(ast.parse(text, str(path))):
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "lazy_exports":
                assert isinstance(node.args[1], ast.Name), f"{path}: lazy_exports needs a named table"
                found.append((module, node.args[1].id))
    return found


def string_named_imports() -> list[tuple[str, str, str]]:
    """(importer, imported module, name) of every import gridlib names by a string."""
    out = []
    for module, table in _lazy_tables():
        package = importlib.import_module(module)
        for name, relative in getattr(package, table).items():
            out.append((module, resolve_name(relative, module), name))
    for fmt in BUILTIN_FORMATS:
        for target in (fmt.reader, fmt.writer):
            if isinstance(target, str):
                imported, _, name = target.partition(":")
                out.append(("gridlib.io.registry", imported, name))
    for stage in STAGES:  # the artifact table's stage functions, imported by the pipeline
        if isinstance(stage.function, str):
            imported, _, name = stage.function.partition(":")
            out.append(("gridlib.stages.pipeline", imported, name))
    return out


def _name(node: ast.AST) -> str | None:
    """The name a Name or Attribute node reads (``import_module``, ``importlib.import_module``)."""
    return node.id if isinstance(node, ast.Name) else node.attr if isinstance(node, ast.Attribute) else None


def test_gridlib_imports_by_name_only_through_lazy_exports_the_format_registry_and_the_pipeline():
    users = set()
    for module, path in _modules():
        text = path.read_text()
        if "import_module" not in text and "__import__" not in text:
            continue
        tree = ast.parse(text, str(path))
        if any(_name(node) in ("import_module", "__import__") for node in ast.walk(tree)):
            users.add(module)
    # the job server (top layer) imports its jobs' libraries and the configuration's plugins
    # ahead of its forks: a warm-up, nothing below it is reached around the layering
    assert users == {
        "gridlib._lazy",
        "gridlib.io.registry",
        "gridlib.stages.pipeline",
        "gridlib.stages.job_server",
    }
    lazy_packages = {module for module, _ in _lazy_tables()}
    assert lazy_packages >= {"gridlib", "gridlib.io", "gridlib.case", "gridlib.stages"}


@pytest.mark.parametrize(("importer", "imported", "name"), string_named_imports())
def test_a_string_named_import_resolves_and_goes_down_the_layers(importer, imported, name):
    assert may_import(importer, imported), (
        f"{importer} names {imported}.{name}, which its layer may not import"
    )
    assert hasattr(importlib.import_module(imported), name), f"{importer}: {imported} has no {name!r}"


def _packages() -> list[str]:
    return [module for module, path in _modules() if path.name == "__init__.py"]


@pytest.mark.parametrize("package", _packages())
def test_every_name_in_a_packages_all_imports(package):
    module = importlib.import_module(package)
    names = getattr(module, "__all__", [])
    assert len(set(names)) == len(names), f"{package}.__all__ repeats a name"
    missing = [name for name in names if not hasattr(module, name)]
    assert not missing, f"{package}.__all__ names {missing}, which do not import"
    assert set(names) <= set(dir(module))  # tab completion offers them
