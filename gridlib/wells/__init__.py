"""Deviated and horizontal wells: their paths (:mod:`.path`; surveys by minimum curvature,
:mod:`.survey`), the cells a path crosses, and the connection factors of those cells
(:mod:`.factors`, :mod:`.connections`).

Names are imported on first use, so that importing the package costs little.
"""

from .._lazy import lazy_exports

_EXPORTS: dict[str, str] = {
    "CellIndex": ".cell_index",
    "PathCells": ".intersect",
    "WellPath": ".path",
    "cell_index": ".cell_index",
    "minimum_curvature": ".survey",
    "path_cells": ".intersect",
    "WellConnections": ".connections",
    "merge_connections": ".connections",
    "well_connections": ".connections",
    "axis_lengths": ".factors",
    "cell_axes": ".factors",
    "main_direction": ".factors",
    "trajectory_factors": ".factors",
}

__all__ = sorted(_EXPORTS)

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
