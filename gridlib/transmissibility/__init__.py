"""Transmissibilities: the connection list (cell pairs, T) a two-point flux simulator needs.

* :func:`transmissibility`: any grid, from its geometry (MRST's ``computeTrans``);
* :func:`deck_transmissibility`: corner-point decks, ECLIPSE's conventions as OPM Flow
  applies them (NEWTRAN, multipliers, PINCH and MINPV connections);
* :class:`Connections`: the result, in a unit system of :mod:`gridlib.units`;
  :func:`face_connections`: the connection each face's two cells form.
"""

from .connections import FAULT, KIND_NAMES, NEIGHBOR, OTHER, PINCH, Connections, face_connections
from .deck_connections import deck_transmissibility
from .peaceman import cell_extents, deck_cell_extents, deck_well_index, well_index
from .tpfa import transmissibility

__all__ = [
    "FAULT",
    "KIND_NAMES",
    "NEIGHBOR",
    "OTHER",
    "PINCH",
    "Connections",
    "cell_extents",
    "deck_cell_extents",
    "deck_transmissibility",
    "deck_well_index",
    "face_connections",
    "transmissibility",
    "well_index",
]
