"""The deck file of a ``deck`` grid case (``grid.file``, relative to the case file)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

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
        deck = read(path, kind="deck")
    else:
        deck = read(path, kind="deck", unknown_keywords=case.data["grid"]["unknown_keywords"])
    return _grid_arrays(with_parameter_files(case, deck))


def with_parameter_files(case: Case, deck: Deck) -> Deck:
    """``deck`` with the arrays of the case's ``grid.parameters`` (keyword -> a ROFF parameter
    file, or a ROFF grid file holding a parameter of that name; relative to the case file):
    each replaces the deck's own array of that keyword. An InputError names the key where a
    file is missing, holds no such parameter or has other dimensions."""
    from ..io.roff import read_roff_parameters, with_parameters

    given = case.data["grid"].get("parameters") or {}
    arrays = {}
    for keyword, name in given.items():
        path = named_file(case.path, name)
        where = f"{case.path}: grid.parameters.{keyword}: {name}"
        if not path.is_file():
            raise InputError(f"{where}: not found (looked for {path})")
        try:
            found = read_roff_parameters(path, None)
        except InputError as exc:
            raise InputError(f"{case.path}: grid.parameters.{keyword}: {exc}") from None
        arrays[keyword] = _parameter(found, keyword, where)
        if arrays[keyword].size != np.prod(deck.cart_dims):
            raise InputError(
                f"{where}: {arrays[keyword].size} values, the grid has {int(np.prod(deck.cart_dims))} cells "
                f"({' x '.join(map(str, deck.cart_dims))})"
            )
    return with_parameters(deck, arrays, str(case.path)) if arrays else deck


def _parameter(found: dict[str, np.ndarray], keyword: str, where: str) -> np.ndarray:
    """The parameter named ``keyword`` (any case), else a file's only parameter."""
    for name, values in found.items():
        if name.upper() == keyword:
            return values
    if len(found) == 1:
        return next(iter(found.values()))
    names = ", ".join(found) or "none"
    raise InputError(f"{where}: no parameter {keyword} among the file's {len(found)} ({names})")


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
