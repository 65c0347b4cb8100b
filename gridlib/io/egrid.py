"""ECLIPSE EGRID files (binary, or formatted FEGRID) read with resfo into a :class:`Deck`.

Only the main grid is read (keywords up to the first ENDGRID); local grid
refinements that follow are noted and skipped. COORD and ZCORN are stored as
float32 in the file and converted exactly to float64. ``Deck.nnc`` gets the
file's non-neighbour connections (NNC1/NNC2, as 0-based linear cell indices).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..cornerpoint.deck import Deck
from ..cornerpoint.layer_overlaps import without_layer_overlaps
from .eclipse_text import DeckError

_UNIT_NAMES = {1: "METRIC", 2: "FIELD", 3: "LAB", 4: "PVT-M"}


def _text(value) -> str:
    items = [v.decode("latin-1") if isinstance(v, bytes) else str(v) for v in np.atleast_1d(value)]
    return " ".join(i.strip() for i in items if i.strip())


def read_egrid(path: str | os.PathLike) -> Deck:
    """Read the main grid of an EGRID file.

    Lengths are in the file's GRIDUNIT (metres or feet); z is depth.
    """
    import resfo

    path = Path(path)
    if not path.is_file():
        raise DeckError(f"{path}: no such file")
    kw: dict[str, np.ndarray] = {}
    lgr = 0
    try:
        for entry in resfo.lazy_read(path):
            key = entry.read_keyword().strip()
            if key == "ENDGRID":
                kw.setdefault("ENDGRID", np.zeros(0))
                continue
            if key == "LGR":
                lgr += 1
            if "ENDGRID" in kw and (lgr or key not in ("NNCHEAD", "NNC1", "NNC2")):
                continue  # local grids and what follows them
            if key not in kw:
                kw[key] = np.asarray(entry.read_array())
    except (resfo.ResfoParsingError, OSError, ValueError, UnicodeDecodeError) as exc:
        raise DeckError(f"{path}: not a readable EGRID file ({exc})") from None
    for needed in ("GRIDHEAD", "COORD", "ZCORN"):
        if needed not in kw:
            raise DeckError(f"{path}: {needed} is missing (not a corner-point EGRID?)")
    dual = int(kw["FILEHEAD"][5]) if "FILEHEAD" in kw and kw["FILEHEAD"].size > 5 else 0
    if dual in (1, 2) or ("ACTNUM" in kw and int(kw["ACTNUM"].max(initial=0)) > 1):
        kind = {1: "DUALPORO", 2: "DUALPERM"}.get(dual, "ACTNUM values 2 and 3")
        raise DeckError(
            f"{path}: a dual-porosity grid ({kind}: matrix and fracture cells) is not read: gridlib "
            "reads single-porosity grids"
        )
    head = kw["GRIDHEAD"]
    if int(head[0]) != 1:
        raise DeckError(f"{path}: GRIDHEAD type {int(head[0])} is not a corner-point grid")
    dims = (int(head[1]), int(head[2]), int(head[3]))
    notes = []
    if lgr:
        notes.append(f"{lgr} local grid refinements after the main grid were not read")
    nnc = None
    if "NNC1" in kw and "NNC2" in kw:
        nnc = np.column_stack([kw["NNC1"], kw["NNC2"]]).astype(np.int64) - 1
    gridunit = _text(kw["GRIDUNIT"]) if "GRIDUNIT" in kw else None
    deck = Deck(
        dims,
        kw["COORD"].astype(np.float64),
        kw["ZCORN"].astype(np.float64),
        kw["ACTNUM"].astype(np.int32) if "ACTNUM" in kw else None,
        mapaxes=kw["MAPAXES"].astype(np.float64) if "MAPAXES" in kw else None,
        mapunits=_text(kw["MAPUNITS"]) if "MAPUNITS" in kw else None,
        gridunit=gridunit,
        units={"METRES": "METRIC", "FEET": "FIELD", "CM": "LAB"}.get((gridunit or "").split(" ")[0]),
        source=str(path),
        notes=tuple(notes),
        nnc=nnc,
    )
    return without_layer_overlaps(deck)
