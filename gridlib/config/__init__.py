"""Case files: loading, validation against the case schema, provenance.

A case is a YAML file validated against ``gridlib/schemas/case.schema.yaml``
(the same file the workflow uses as ``workflow/schemas/case.schema.yaml``).
Every problem is reported as one :class:`~gridlib.errors.InputError` naming the
file and the key path, e.g. ``config/cases/x.yaml: grid.dims[1]: 0 is less
than the minimum of 1``.

Its modules, one concept each: :mod:`~gridlib.config.yaml_file` (YAML, a key given twice
refused), :mod:`~gridlib.config.values` (finite numbers, keys as the case spells them),
:mod:`~gridlib.config.checks` (what the schema cannot say), :mod:`~gridlib.config.size`
(cells and peak memory from the case alone), :mod:`~gridlib.config.files` (the files a case
names) and :mod:`~gridlib.config.well_paths` (deviated wells' paths, read and checked).
config/README.md lists every check in the order they run.
"""

from __future__ import annotations

import copy
import functools
import hashlib
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, TypeVar

import jsonschema
import yaml

from ..errors import InputError
from ..version import __version__
from .checks import case_problem, qc_problem, rock_problem, simulation_problem
from .files import case_deck_keywords, deck_cell_keywords, named_file
from .size import max_memory_bytes, size_problem
from .values import non_finite_problem
from .well_paths import is_deviated
from .yaml_file import parse_yaml

T = TypeVar("T")

SCHEMA_FILE = "case.schema.yaml"


def load_schema(name: str = SCHEMA_FILE) -> dict[str, Any]:
    """The JSON schema shipped with gridlib (as a dict; a copy of the one parsed per process)."""
    return copy.deepcopy(shared_schema(name))


@functools.cache
def shared_schema(name: str) -> dict[str, Any]:
    """The schema parsed once per process and shared (do not modify it; :func:`load_schema`
    gives a copy): a study validates every variant, and each stage its case."""
    text = resources.files("gridlib").joinpath("schemas", name).read_text(encoding="utf-8")
    return yaml.load(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))


@dataclass(frozen=True)
class Case:
    """A validated case: its data (with defaults filled in) and provenance."""

    name: str
    path: Path
    sha256: str
    data: dict[str, Any] = field(repr=False)

    @property
    def seed(self) -> int:
        return int(self.data["seed"])

    @property
    def grid_type(self) -> str:
        """``grid.type``: cartesian, tensor, layered, cornerpoint, pebi or deck."""
        return self.data["grid"]["type"]

    @property
    def has_horizons(self) -> bool:
        return "horizons" in self.data

    @property
    def writes_grdecl(self) -> bool:
        """Corner-point and deck grids are also written as GRDECL for simulators."""
        return self.grid_type in ("cornerpoint", "deck")

    @property
    def has_petrophysics(self) -> bool:
        """The case has rock: a `petrophysics` section, given or, for a deck grid whose deck gives
        PORO and PERMX, implied (:func:`check_case_data` adds an empty one: the deck's rock)."""
        return "petrophysics" in self.data

    @property
    def has_coarsening(self) -> bool:
        return "coarsen" in self.data

    @property
    def has_transmissibility(self) -> bool:
        """The transmissibility stage runs: it needs the case's rock properties."""
        return self.has_petrophysics

    @property
    def keeps_stage_files(self) -> bool:
        """``outputs.stage_files``: the per-stage netCDF files stay beside ``{case}.nc``."""
        return bool(self.data["outputs"]["stage_files"])

    @property
    def writes_vtu(self) -> bool:
        """``outputs.vtu``: the grid with its cell data as ``{case}.vtu``."""
        return bool(self.data["outputs"]["vtu"])

    @property
    def writes_pictures(self) -> bool:
        """``outputs.pictures``: the pictures stage runs and the quality stage draws its
        histograms."""
        return bool(self.data["outputs"]["pictures"])

    @property
    def is_3d(self) -> bool:
        """The grid has depth: every type but 2-D cartesian and tensor grids."""
        grid = self.data["grid"]
        if grid["type"] == "cartesian":
            return len(grid["dims"]) == 3
        if grid["type"] == "tensor":
            return "z" in grid
        return True

    @property
    def has_deviated_wells(self) -> bool:
        """The case has a trajectory or survey well (:mod:`gridlib.config.well_paths`): its
        ``wells`` stage writes their connections to ``wells.nc``."""
        return any(is_deviated(well) for well in self.data.get("wells", []))

    @property
    def has_simulation(self) -> bool:
        """The case says what its OPM Flow deck simulates (wells, report steps)."""
        return "simulation" in self.data

    @property
    def writes_flow_deck(self) -> bool:
        """Cases with rock on a 3-D grid get an OPM Flow deck (flow/<NAME>.DATA)."""
        return self.has_petrophysics and self.is_3d

    @property
    def flow_name(self) -> str:
        """The deck's name: the case name in upper case (flow/<NAME>.DATA)."""
        return self.name.upper()

    def provenance(self) -> dict[str, object]:
        """Attributes every output of this case carries."""
        return {
            "gridlib_version": __version__,
            "case_name": self.name,
            "case_file": str(self.path),
            "case_sha256": self.sha256,
            "seed": self.seed,
        }


def _key_path(error: jsonschema.ValidationError) -> str:
    parts = []
    for p in error.absolute_path:
        parts.append(f"[{p}]" if isinstance(p, int) else f".{p}")
    return "".join(parts).lstrip(".") or "(top level)"


def _describe(error: jsonschema.ValidationError) -> str:
    if error.validator == "additionalProperties":
        allowed = sorted(error.schema.get("properties", {}))
        return f"{error.message}; allowed keys: {', '.join(allowed)}"
    keys = _one_of_keys(error)
    if keys is not None:
        given = [k for k in keys if isinstance(error.instance, dict) and k in error.instance]
        return f"give exactly one of {', '.join(keys)} (got {', '.join(given) or 'none'})"
    return error.message


def _one_of_keys(error: jsonschema.ValidationError) -> list[str] | None:
    """The keys of a oneOf whose alternatives each require one key and nothing else (a fault's
    trace or sticks, a well's point or path), else None."""
    alternatives = error.validator_value if error.validator == "oneOf" else None
    if not alternatives or not all(set(a) == {"required"} and len(a["required"]) == 1 for a in alternatives):
        return None
    return [a["required"][0] for a in alternatives]


def _is_integer(checker: Any, value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


# JSON Schema counts 2.0 as an integer; a case's counts (dims, layers, num, seed) are whole
# numbers as written: `dims: [4.0, 4]` is refused here rather than failing in a builder.
CaseValidator = jsonschema.validators.extend(
    jsonschema.Draft202012Validator,
    type_checker=jsonschema.Draft202012Validator.TYPE_CHECKER.redefine("integer", _is_integer),
)


def validate(data: Any, schema: dict[str, Any], source: str) -> None:
    """Raise InputError naming ``source`` and the key path of the most relevant error (an
    integer is an int as YAML reads it: ``4.0`` is not one)."""
    validator = CaseValidator(schema)
    errors = list(validator.iter_errors(data))
    if not errors:
        return
    best = jsonschema.exceptions.best_match(errors)
    # Prefer the deepest error: it names the offending key rather than a oneOf/if branch.
    deepest = max(errors, key=lambda e: (len(list(e.absolute_path)), e is best))
    chosen = deepest if len(list(deepest.absolute_path)) > len(list(best.absolute_path)) else best
    while chosen.context and _one_of_keys(chosen) is None:  # into oneOf/anyOf: the specific failure
        chosen = max(chosen.context, key=lambda e: len(list(e.absolute_path)))
    raise InputError(f"{source}: {_key_path(chosen)}: {_describe(chosen)}")


def with_defaults(data: dict[str, Any]) -> dict[str, Any]:
    """A copy of a case's ``data`` with the schema's defaults filled in (as :func:`load_case`
    does after validating it)."""
    schema = shared_schema(SCHEMA_FILE)
    return _fill_defaults(copy.deepcopy(data), schema, schema)


def section_defaults(name: str) -> dict[str, Any]:
    """A section of the case schema (``$defs``: ``simulation``, ``coarsen``, ...) as its
    defaults alone fill it: what a case without the section means."""
    schema = shared_schema(SCHEMA_FILE)
    return _fill_defaults({}, schema["$defs"][name], schema)


def _fill_defaults(data: Any, schema: dict[str, Any], root: dict[str, Any]) -> Any:
    """Fill ``default`` values of object properties, also in the items of arrays (following
    $ref, allOf/if/then)."""
    if "$ref" in schema:
        ref = schema["$ref"].split("/")[-1]
        schema = {**root["$defs"][ref], **{k: v for k, v in schema.items() if k != "$ref"}}
    if isinstance(data, list) and isinstance(schema.get("items"), dict):
        for item in data:
            _fill_defaults(item, schema["items"], root)
        return data
    if not isinstance(data, dict):
        return data
    for key, sub in schema.get("properties", {}).items():
        if not isinstance(sub, dict):
            continue
        if key not in data and "default" in sub:
            data[key] = copy.deepcopy(sub["default"])
        if key in data:
            data[key] = _fill_defaults(data[key], sub, root)
    for branch in schema.get("allOf", []):
        cond = branch.get("if")
        if cond is None or jsonschema.Draft202012Validator(cond).is_valid(data):
            if "then" in branch:
                _fill_defaults(data, branch["then"], root)
    return data


def load_case(path: str | os.PathLike, max_memory_gb: float | None = None) -> Case:
    """Read and validate a case file; defaults are filled in. ``max_memory_gb``: the memory a
    stage may need (GiB; the workflow's ``max_memory_gb``), default the machine's
    (:func:`gridlib.config.size.max_memory_bytes`)."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: case file not found")
    raw = p.read_bytes()
    data = parse_yaml(raw, p)
    if not isinstance(data, dict):
        raise InputError(f"{p}: a case must be a mapping of keys (name, grid, ...)")
    checked = check_case_data(data, p, str(p), max_memory_gb)
    return Case(name=data["name"], path=p, sha256=hashlib.sha256(raw).hexdigest(), data=checked)


def check_case_data(
    data: dict[str, Any], path: Path, source: str, max_memory_gb: float | None = None
) -> dict[str, Any]:
    """A case's data validated as :func:`load_case` does, as if read from ``path`` (the file
    name must be the case's name; files are looked for beside it); returns a copy with the
    defaults filled in. Problems raise an InputError starting with ``source``.

    In order, each check stopping at the first problem: finite numbers (the schema takes
    ``.nan`` for a number), the schema, the name, the case's keys against each other and the
    files it names (:func:`gridlib.config.checks.case_problem`), its values
    (:func:`~gridlib.config.checks.rock_problem`), its size against ``max_memory_gb``
    (:func:`gridlib.config.size.size_problem`: before any deck is read beyond its dimensions),
    then a deck grid's deck read whole (each of its errors names the deck's file, line and
    keyword) and what its keywords decide (its rock, the simulation, the qc rules' measures)."""
    problem = non_finite_problem(data)
    if problem is not None:
        raise InputError(f"{source}: {problem}")
    schema = shared_schema(SCHEMA_FILE)
    validate(data, schema, source)
    if data["name"] != path.stem:
        raise InputError(f"{source}: name: '{data['name']}' must equal the file name '{path.stem}'")
    data = with_defaults(data)
    problem = case_problem(data, path) or size_problem(data, path, max_memory_bytes(max_memory_gb))
    if problem is not None:
        raise InputError(f"{source}: {problem}")
    try:
        if data["grid"]["type"] == "deck":  # the whole deck read: its errors name file and line now
            deck_cell_keywords(named_file(path, data["grid"]["file"]), data["grid"]["unknown_keywords"])
        data = with_deck_rock(data, path)
        problem = rock_problem(data, path) or simulation_problem(data) or qc_problem(data)
    except InputError as exc:
        raise InputError(f"{source}: grid.file: {exc}") from None
    if problem is not None:
        raise InputError(f"{source}: {problem}")
    return data


DECK_ROCK = ("PORO", "PERMX")  # what a deck must give for its case to have rock without a section


def with_deck_rock(data: dict[str, Any], path: Path) -> dict[str, Any]:
    """``data`` (a case read from ``path``) with an empty ``petrophysics`` section where the
    case is a deck grid without one and its deck gives PORO and PERMX: such a case has the
    deck's rock (:func:`gridlib.case.rock.case_rock`), and its transmissibilities and OPM Flow
    deck, as a user of the deck expects. Other data are returned as they are."""
    grid = data.get("grid", {})
    if grid.get("type") != "deck" or "petrophysics" in data:
        return data
    deck = named_file(path, grid["file"])
    if not deck.is_file():
        return data  # checks.case_problem names the missing file
    if not set(DECK_ROCK) <= case_deck_keywords(path, grid):
        return data
    return {**data, "petrophysics": {}}


def load_cases(paths: Sequence[str | os.PathLike], max_memory_gb: float | None = None) -> dict[str, Case]:
    """Every case file read and validated, keyed by case name.

    All problems are collected before raising: one :class:`InputError` whose message has
    one line per broken file (each naming the file and the key, as :func:`load_case`)
    and per name used twice, so a run with several broken case files names all of them.
    ``max_memory_gb`` as :func:`load_case`.

    >>> load_cases(["no/such/a.yaml", "no/such/b.yaml"])
    Traceback (most recent call last):
    ...
    gridlib.errors.InputError: no/such/a.yaml: case file not found
    no/such/b.yaml: case file not found
    """
    return load_named(paths, functools.partial(load_case, max_memory_gb=max_memory_gb))


def load_named(paths: Sequence[str | os.PathLike], load: Callable[[str | os.PathLike], T]) -> dict[str, T]:
    """``load(path)`` of every path (a value with ``name`` and ``path``), keyed by name: one
    InputError with one line per problem (a broken file, a name used twice), all files read."""
    loaded: dict[str, T] = {}
    problems: list[str] = []
    for path in paths:
        try:
            value = load(path)
        except InputError as exc:
            problems.append(" ".join(str(exc).split("\n")))
            continue
        name = value.name  # type: ignore[attr-defined]
        if name in loaded:
            problems.append(f"{path}: name: '{name}' is also used by {loaded[name].path}")  # type: ignore[attr-defined]
            continue
        loaded[name] = value
    if problems:
        raise InputError("\n".join(problems))
    return loaded
