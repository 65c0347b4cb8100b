"""Non-neighbour connections found by the pillar engine (both front ends)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..grid import IntArray

FAULT, PINCH = 0, 1


@dataclass(frozen=True, eq=False)
class NNC:
    """Non-neighbour connections: cell pairs that are connected but not logical ijk neighbours.

    ``kind`` is 0 (FAULT: a geometric face joins cells of different layers or
    columns) or 1 (PINCH: cells joined across a thin removed layer, no face);
    ``face`` is the connecting face, or -1 for pinch connections.
    """

    cells: IntArray  # (n, 2) cells of the processed grid
    global_cells: IntArray  # (n, 2) linear ijk indices (i fastest)
    kind: np.ndarray
    face: IntArray

    @property
    def num(self) -> int:
        return self.cells.shape[0]
