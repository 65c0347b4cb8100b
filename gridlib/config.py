"""Case files: loading, validation against the case schema, provenance.

A case is a YAML file validated against ``gridlib/schemas/case.schema.yaml``
(the same file the workflow uses as ``workflow/schemas/case.schema.yaml``).
Every problem is reported as one :class:`~gridlib.errors.InputError` naming the
file and the key path, e.g. ``config/cases/x.yaml: grid.dims[1]: 0 is less
than the minimum of 1``.
"""

from __future__ import annotations

import copy
import hashlib
import os
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import jsonschema
import yaml

from .errors import InputError

SCHEMA_FILE = "case.schema.yaml"


def load_schema(name: str = SCHEMA_FILE) -> dict[str, Any]:
    """The JSON schema shipped with gridlib (as a dict)."""
    text = resources.files("gridlib").joinpath("schemas", name).read_text(encoding="utf-8")
    return yaml.safe_load(text)


@dataclass(frozen=True)
class Case:
    """A validated case: its data (with defaults filled in) and provenance."""

    name: str
    path: Path
    sha256: str
    data: dict[str, Any] = field(repr=False)

    @property
    def seed(self) -> int:
        return int(self.data.get("seed", 0))

    def provenance(self) -> dict[str, object]:
        """Attributes every output of this case carries."""
        from . import __version__

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
    return error.message


def validate(data: Any, schema: dict[str, Any], source: str) -> None:
    """Raise InputError naming ``source`` and the key path of the most relevant error."""
    validator = jsonschema.Draft202012Validator(schema)
    errors = list(validator.iter_errors(data))
    if not errors:
        return
    best = jsonschema.exceptions.best_match(errors)
    # Prefer the deepest error: it names the offending key rather than a oneOf/if branch.
    deepest = max(errors, key=lambda e: (len(list(e.absolute_path)), e is best))
    chosen = deepest if len(list(deepest.absolute_path)) > len(list(best.absolute_path)) else best
    while chosen.context:  # descend into oneOf/anyOf to the specific failure
        chosen = max(chosen.context, key=lambda e: len(list(e.absolute_path)))
    raise InputError(f"{source}: {_key_path(chosen)}: {_describe(chosen)}")


def _fill_defaults(data: Any, schema: dict[str, Any], root: dict[str, Any]) -> Any:
    """Fill ``default`` values of object properties (following $ref, allOf/if/then)."""
    if "$ref" in schema:
        ref = schema["$ref"].split("/")[-1]
        schema = {**root["$defs"][ref], **{k: v for k, v in schema.items() if k != "$ref"}}
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


def load_case(path: str | os.PathLike) -> Case:
    """Read and validate a case file; defaults are filled in."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: case file not found")
    raw = p.read_bytes()
    try:
        data = yaml.safe_load(raw)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" line {mark.line + 1}" if mark is not None else ""
        raise InputError(f"{p}:{where}: not valid YAML ({getattr(exc, 'problem', exc)})") from exc
    if not isinstance(data, dict):
        raise InputError(f"{p}: a case must be a mapping of keys (name, grid, ...)")
    schema = load_schema()
    validate(data, schema, str(p))
    if data["name"] != p.stem:
        raise InputError(f"{p}: name: '{data['name']}' must equal the file name '{p.stem}'")
    data = _fill_defaults(copy.deepcopy(data), schema, schema)
    return Case(name=data["name"], path=p, sha256=hashlib.sha256(raw).hexdigest(), data=data)
