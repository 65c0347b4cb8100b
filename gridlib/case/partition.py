"""A case's coarse partition (``coarsen``): uniform blocks or METIS (weighted by pore volume)."""

from __future__ import annotations

import numpy as np

from ..coarsen import partition_metis, partition_ui, process_partition
from ..config import Case
from ..errors import InputError
from ..geometry import Geometry
from ..grid import Grid


def case_partition(
    case: Case, grid: Grid, rock, *, cell_volumes: np.ndarray, geometry: Geometry | None = None
) -> np.ndarray:
    """The coarse block of every cell of ``grid`` (``rock``: the petrophysics arrays, or None).
    METIS weighs the cells by pore volume (``cell_volumes`` x porosity); uniform blocks need
    the whole ``geometry``."""
    spec = case.data["coarsen"]
    try:
        if spec["method"] == "uniform":
            if geometry is None:
                raise InputError("uniform blocks need the grid's geometry")
            return process_partition(grid, partition_ui(grid, spec["dims"], geometry))
        weights = None
        if rock is not None:
            weights = np.maximum(rock["poro"] * cell_volumes, 1e-12)
        return partition_metis(grid, int(spec["blocks"]), cell_weights=weights, seed=case.seed)
    except InputError as exc:
        raise InputError(f"{case.path}: coarsen: {exc}") from None
