"""The deck file of a ``deck`` grid case (``grid.file``, relative to the case file)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from ..config import Case, named_file
from ..cornerpoint.deck import Deck
from ..errors import InputError
from ..io.grdecl.vocabulary import vocabulary
from ..io.registry import find_format, read

_GRID_SECTIONS = frozenset({"GRID", "EDIT"})


def deck_path(case: Case) -> Path:
    """The case's deck file; an InputError naming the case if it is missing."""
    name = case.data["grid"]["file"]
    path = named_file(case.path, name)
    if not path.is_file():
        raise InputError(f"{case.path}: grid.file: '{name}' not found (looked for {path})")
    return path


def read_case_deck(case: Case) -> Deck:
    """The case's deck (GRDECL text, a DATA deck or EGRID, by the file's suffix); a text deck
    is read with ``grid.unknown_keywords`` (``error``, the default, or ``skip``).

    Only the arrays a GRID or EDIT section may hold are kept (PORO, PERMX, NTG, MULT*, FLUXNUM,
    MULTNUM, ...): those of PROPS and REGIONS alone (SATNUM, EQLNUM, SWL, ...) belong to the
    deck's own tables and regions, not to the grid the case writes (its Flow deck's GRID
    include), and are listed in the deck's notes.
    """
    path = deck_path(case)
    if find_format(path, "deck").name != "grdecl":
        return read(path, kind="deck")
    deck = read(path, kind="deck", unknown_keywords=case.data["grid"]["unknown_keywords"])
    return _grid_arrays(deck)


def _grid_arrays(deck: Deck) -> Deck:
    known = vocabulary()
    grid = {
        name: values
        for name, values in deck.cell_data.items()
        if (info := known.get(name)) is None or info.sections & _GRID_SECTIONS
    }
    if len(grid) == len(deck.cell_data):
        return deck
    dropped = ", ".join(name for name in deck.cell_data if name not in grid)
    return replace(
        deck, cell_data=grid, notes=(*deck.notes, f"PROPS/REGIONS arrays not used by the case: {dropped}")
    )
