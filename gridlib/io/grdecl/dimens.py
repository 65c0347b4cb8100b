"""A deck's grid dimensions (DIMENS or SPECGRID; an EGRID's GRIDHEAD) read without reading the deck.

Used before anything is built to estimate a deck grid's size: the text is scanned line by line
up to the first DIMENS or SPECGRID (following INCLUDE files, relative to the main deck's folder
as ECLIPSE and OPM Flow take them), so a deck whose arrays would not fit in memory is never
parsed. Anything this scanner does not understand gives None: the deck reader, which runs
later, names the problem with its file and line.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path

DIMENSION_KEYWORDS = ("DIMENS", "SPECGRID")
_KEYWORD = re.compile(r"^([A-Z][A-Z0-9_+-]{0,7})\s*(?:--.*)?$")
_MAX_INCLUDE_DEPTH = 32  # as the deck reader
EGRID_SUFFIXES = (".egrid", ".fegrid")


def deck_dimensions(path: Path) -> tuple[int, int, int] | None:
    """(nx, ny, nz) of the deck or EGRID file ``path``: its first DIMENS or SPECGRID (GRIDHEAD
    for an EGRID), or None where it gives none this scan can read (an INCLUDE through a PATHS
    alias, a missing include, a repeat count, ...).

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     deck = Path(d) / "D.DATA"
    ...     _ = deck.write_text("RUNSPEC\\n-- a comment\\nDIMENS\\n 10 20 3 /\\n")
    ...     deck_dimensions(deck)
    (10, 20, 3)
    """
    if path.suffix.lower() in EGRID_SUFFIXES:
        return _egrid_dimensions(path)
    if path.is_file() and _is_binary(path):  # a binary GRDECL: its SPECGRID record
        return _binary_dimensions(path)
    try:
        tokens = _tokens_after_keyword(path, path.parent, 0)
    except (OSError, UnicodeError):
        return None
    if tokens is None:
        return None
    numbers = []
    for token in tokens:
        if token.startswith("/"):
            break
        if not token.isdigit():
            return None
        numbers.append(int(token))
        if len(numbers) == 3:
            return numbers[0], numbers[1], numbers[2]
    return None


def _tokens_after_keyword(path: Path, main_folder: Path, depth: int) -> list[str] | None:
    """The tokens of the record after the first DIMENS or SPECGRID in ``path`` or its includes."""
    lines = _lines(path)
    for line in lines:
        match = _KEYWORD.match(line.strip())
        if match is None:
            continue
        keyword = match.group(1)
        if keyword in DIMENSION_KEYWORDS:
            return _record(lines)
        if keyword == "INCLUDE":
            record = _record(lines)
            if not record or depth >= _MAX_INCLUDE_DEPTH:
                return None
            name = record[0].strip("'\"").replace("\\", "/")
            if "$" in name:
                return None
            included = Path(name) if Path(name).is_absolute() else main_folder / name
            if not included.is_file():
                return None
            found = _tokens_after_keyword(included, main_folder, depth + 1)
            if found is not None:
                return found
    return None


def _lines(path: Path) -> Iterator[str]:
    with open(path, encoding="latin-1") as f:
        for line in f:
            yield line.split("--", 1)[0]


def _record(lines: Iterator[str]) -> list[str]:
    """The tokens up to and with the record's closing slash (quoted names kept whole)."""
    tokens: list[str] = []
    for line in lines:
        for token in re.findall(r"'[^']*'|\"[^\"]*\"|/|[^\s/]+", line):
            tokens.append(token)
            if token == "/":
                return tokens
        if len(tokens) > 64:
            break
    return tokens


def _is_binary(path: Path) -> bool:
    from .binary import is_binary_keyword_file

    try:
        return is_binary_keyword_file(path)
    except OSError:
        return False


def _binary_dimensions(path: Path) -> tuple[int, int, int] | None:
    import resfo

    try:
        for entry in resfo.lazy_read(str(path)):
            if entry.read_keyword().strip() in DIMENSION_KEYWORDS:
                dims = entry.read_array()
                return int(dims[0]), int(dims[1]), int(dims[2])
    except Exception:
        return None
    return None


def _egrid_dimensions(path: Path) -> tuple[int, int, int] | None:
    import resfo

    try:
        for entry in resfo.lazy_read(str(path)):
            if entry.read_keyword().strip() == "GRIDHEAD":
                head = entry.read_array()
                return int(head[1]), int(head[2]), int(head[3])
    except Exception:
        return None
    return None
