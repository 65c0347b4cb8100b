"""Transmissibilities: the connection list (cell pairs, T) a two-point flux simulator needs.

* :func:`transmissibility`: any grid, from its geometry (MRST's ``computeTrans``);
* :class:`Connections`: the result, in a unit system of :mod:`gridlib.units`.
"""

from .connections import FAULT, KIND_NAMES, NEIGHBOR, OTHER, PINCH, Connections
from .tpfa import transmissibility

__all__ = ["FAULT", "KIND_NAMES", "NEIGHBOR", "OTHER", "PINCH", "Connections", "transmissibility"]
