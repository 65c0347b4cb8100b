"""Transmissibilities: the connection list (cell pairs, T) a two-point flux simulator needs.

* :func:`transmissibility`: any grid, from its geometry (MRST's ``computeTrans``);
* :func:`deck_transmissibility`: corner-point decks, ECLIPSE's conventions as OPM Flow
  applies them (NEWTRAN, multipliers, PINCH and MINPV connections);
* :class:`Connections`: the result, in a unit system of :mod:`gridlib.units`;
  :func:`face_connections`: the connection each face's two cells form.
"""

from .connections import FAULT, KIND_NAMES, NEIGHBOR, OTHER, PINCH, Connections, face_connections
from .deck import deck_transmissibility
from .tpfa import transmissibility
from .wells import cell_extents, deck_cell_extents, deck_well_index, well_index

__all__ = [
    "FAULT",
    "KIND_NAMES",
    "NEIGHBOR",
    "OTHER",
    "PINCH",
    "Connections",
    "deck_transmissibility",
    "face_connections",
    "transmissibility",
]
__all__ += ["cell_extents", "deck_cell_extents", "deck_well_index", "well_index"]  # wells.py
