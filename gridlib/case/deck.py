"""The deck file of a ``deck`` grid case (``grid.file``, relative to the case file)."""

from __future__ import annotations

from pathlib import Path

from ..config import Case
from ..cornerpoint.deck import Deck
from ..errors import InputError
from ..io.registry import find_format, read


def deck_path(case: Case) -> Path:
    """The case's deck file; an InputError naming the case if it is missing."""
    name = case.data["grid"]["file"]
    path = case.path.parent / name
    if not path.is_file():
        raise InputError(f"{case.path}: grid.file: '{name}' not found (looked for {path})")
    return path


def read_case_deck(case: Case) -> Deck:
    """The case's deck (GRDECL text, a DATA deck or EGRID, by the file's suffix); a text deck
    is read with ``grid.unknown_keywords`` (``error``, the default, or ``skip``)."""
    path = deck_path(case)
    options = {}
    if find_format(path, "deck").name == "grdecl":
        options["unknown_keywords"] = case.data["grid"].get("unknown_keywords", "error")
    return read(path, kind="deck", **options)
