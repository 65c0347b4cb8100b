"""Fuzz: seeded mutations of the sample case files end in one InputError line naming the case file,
or load; never another exception (a KeyError, a TypeError, a numpy error)."""

from __future__ import annotations

import copy
import math
import random
from pathlib import Path
from typing import Any

import pytest
import yaml

import gridlib as gl
from gridlib.config import load_case, named_file

CASES = Path(__file__).resolve().parents[1] / "config" / "cases"
SAMPLES = sorted(CASES.glob("*.yaml"))
MUTATIONS = 100
REPLACEMENTS = (
    math.nan,
    math.inf,
    -math.inf,
    1e300,
    -1e300,
    10**30,
    -1,
    0,
    0.5,
    "text",
    "",
    None,
    True,
    [],
    {},
    [1, 2],
    {"x": 1},
)


def _absolute_files(data: dict[str, Any], case: Path) -> dict[str, Any]:
    """The case's data with the files it names absolute: the mutant lives in a temporary folder."""
    data = copy.deepcopy(data)
    grid = data.get("grid", {})
    if "file" in grid:
        grid["file"] = str(named_file(case, grid["file"]).resolve())
    for surface in data.get("horizons", {}).get("surfaces", []):
        for key in ("points", "surface"):
            if key in surface:
                surface[key] = str(named_file(case, surface[key]).resolve())
    for fault in data.get("faults", []):
        if "sticks" in fault:
            fault["sticks"] = str(named_file(case, fault["sticks"]).resolve())
    for well in data.get("wells", []):
        for spec in (well, *well.get("branches", [])):
            if isinstance(spec.get("trajectory"), str):
                spec["trajectory"] = str(named_file(case, spec["trajectory"]).resolve())
            elif isinstance(spec.get("trajectory"), dict):
                spec["trajectory"]["file"] = str(named_file(case, spec["trajectory"]["file"]).resolve())
            if "file" in spec.get("survey", {}):
                spec["survey"]["file"] = str(named_file(case, spec["survey"]["file"]).resolve())
    return data


def _leaves(node: Any, keys: tuple = ()) -> list[tuple]:
    """The key paths of every value in ``node`` (mappings and lists, and their items)."""
    out = [keys] if keys else []
    if isinstance(node, dict):
        for k, v in node.items():
            out += _leaves(v, (*keys, k))
    elif isinstance(node, list):
        for k, v in enumerate(node):
            out += _leaves(v, (*keys, k))
    return out


def _get(node: Any, keys: tuple) -> Any:
    for k in keys:
        node = node[k]
    return node


def _mutant(rng: random.Random) -> tuple[str, str]:
    """(file name, text) of one mutation of a sample case, and what the mutation was in the name."""
    sample = rng.choice(SAMPLES)
    data = _absolute_files(yaml.safe_load(sample.read_text()), sample)
    keys = rng.choice(_leaves(data))
    parent, last = _get(data, keys[:-1]), keys[-1]
    kind = rng.choice(("drop", "replace", "replace", "swap", "scale", "duplicate", "break"))
    if kind == "drop":
        del parent[last]
    elif kind == "replace":
        parent[last] = copy.deepcopy(rng.choice(REPLACEMENTS))
    elif kind == "swap":
        other = rng.choice(_leaves(data))
        if other[: len(keys)] != keys and keys[: len(other)] != other:
            a, b = _get(data, keys), _get(data, other)
            parent[last] = copy.deepcopy(b)
            _get(data, other[:-1])[other[-1]] = copy.deepcopy(a)
    elif kind == "scale" and isinstance(parent[last], int | float) and not isinstance(parent[last], bool):
        parent[last] = parent[last] * rng.choice((-1, 0, 1e6, 1e-9, 10**12))
    name = data.get("name") if isinstance(data.get("name"), str) and data.get("name") else "case"
    text = yaml.safe_dump(data, sort_keys=False)
    if kind == "duplicate":
        lines = text.splitlines(keepends=True)
        top = [k for k, line in enumerate(lines) if line[:1].isalpha()]
        k = rng.choice(top)
        text = "".join(lines[: k + 1] + [lines[k]] + lines[k + 1 :])
    elif kind == "break":
        cut = rng.randrange(len(text))
        text = text[:cut] + rng.choice(("", ": [", "\t", "}", "&a *b", "- -", "'")) + text[cut:]
    return f"{name if '/' not in name else 'case'}.yaml", text


def test_mutated_case_files_end_in_input_error_or_load(tmp_path):
    rng = random.Random(24)
    outcomes = {"refused": 0, "loaded": 0}
    for k in range(MUTATIONS):
        file_name, text = _mutant(rng)
        folder = tmp_path / f"m{k}"
        folder.mkdir()
        path = folder / file_name
        try:
            path.write_text(text)
        except OSError:  # a name no file system takes
            path = folder / "case.yaml"
            path.write_text(text)
        try:
            load_case(path)
        except gl.InputError as exc:
            message = str(exc)
            assert message.startswith(str(path)), message
            assert "\n" not in message and "np.float64(" not in message, message
            outcomes["refused"] += 1
        except Exception as exc:
            pytest.fail(f"mutant {k} ({path}) raised {type(exc).__name__}: {exc}\n{text}")
        else:
            outcomes["loaded"] += 1
    assert outcomes["refused"] > MUTATIONS // 2 and outcomes["loaded"] > 0, outcomes
