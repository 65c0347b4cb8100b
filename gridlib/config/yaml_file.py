"""Case and study files as YAML: a key given twice in one mapping is an error, not "the last wins"."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from ..errors import InputError

_BASE_LOADER: type = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


class DuplicateKeyError(yaml.YAMLError):
    """A mapping gives ``key`` twice: at 1-based ``line`` and, before it, at ``first_line``."""

    def __init__(self, key: Any, line: int, first_line: int) -> None:
        super().__init__(f"key {key!r} given twice")
        self.key, self.line, self.first_line = key, line, first_line


class UniqueKeyLoader(_BASE_LOADER):  # type: ignore[misc, valid-type]
    """YAML's safe loader (the C one where PyYAML has it) refusing a key given twice in one
    mapping, as the YAML specification requires of mappings (PyYAML keeps the last value)."""

    def construct_mapping(self, node: yaml.MappingNode, deep: bool = False) -> dict[Any, Any]:
        seen: dict[Any, int] = {}
        for key_node, _ in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":
                continue  # `<<: *anchor`: keys given beside it override the merged ones
            key = self.construct_object(key_node, deep=True)
            line = key_node.start_mark.line + 1
            try:
                if key in seen:
                    raise DuplicateKeyError(key, line, seen[key])
                seen[key] = line
            except TypeError:
                continue  # an unhashable key: the base class says so
        return super().construct_mapping(node, deep=deep)


def parse_yaml(raw: bytes, path: Path) -> Any:
    """The YAML document ``raw`` read from ``path``; InputError naming the file and line (of a
    syntax error, or of a key given twice: ``c.yaml: line 7: key 'grid' given twice (first at
    line 2)``)."""
    try:
        return yaml.load(raw, Loader=UniqueKeyLoader)
    except DuplicateKeyError as exc:
        raise InputError(
            f"{path}: line {exc.line}: key {_shown(exc.key)} given twice (first at line {exc.first_line}); "
            "give each key once"
        ) from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" line {mark.line + 1}" if mark is not None else ""
        raise InputError(f"{path}:{where}: not valid YAML ({getattr(exc, 'problem', exc)})") from None
    except (ValueError, OverflowError, RecursionError) as exc:  # e.g. a date like 2024-02-30
        raise InputError(f"{path}: not valid YAML ({exc})") from None


def _shown(key: Any) -> str:
    return f"'{key}'" if isinstance(key, str) else repr(key)
