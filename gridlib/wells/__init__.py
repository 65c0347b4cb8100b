"""Deviated and horizontal wells: their paths (:mod:`.path`; surveys by minimum curvature,
:mod:`.survey`), the cells a path crosses, and the connection factors of those cells
(:mod:`.factors`, :mod:`.connections`).

Names are imported on first use, so that importing the package costs little.
"""

from .._lazy import lazy_exports

_EXPORTS: dict[str, str] = {
    "CellIndex": ".intersect",
    "PathCells": ".intersect",
    "WellConnections": ".connections",
    "WellPath": ".path",
    "axis_lengths": ".factors",
    "cell_axes": ".factors",
    "cell_index": ".intersect",
    "main_direction": ".factors",
    "merge_connections": ".connections",
    "minimum_curvature": ".survey",
    "path_cells": ".intersect",
    "trajectory_factors": ".factors",
    "well_connections": ".connections",
}

__all__ = sorted(_EXPORTS)

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
