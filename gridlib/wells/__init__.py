"""Deviated and horizontal wells: their paths (:mod:`.path`; surveys by minimum curvature,
:mod:`.survey`), the cells a path crosses, and the connection factors of those cells.

Names are imported on first use, so that importing the package costs little.
"""

from .._lazy import lazy_exports

_EXPORTS: dict[str, str] = {
    "CellIndex": ".intersect",
    "PathCells": ".intersect",
    "WellPath": ".path",
    "cell_index": ".intersect",
    "minimum_curvature": ".survey",
    "path_cells": ".intersect",
}

__all__ = sorted(_EXPORTS)

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
