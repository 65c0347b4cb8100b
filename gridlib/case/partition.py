"""A case's coarse partition (``coarsen``): uniform blocks or METIS (weighted by pore volume)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..coarsen import partition_metis, partition_ui, process_partition
from ..config import Case
from ..errors import InputError
from ..geometry import Geometry
from ..grid import Grid


@dataclass(frozen=True)
class Coarsening:
    """The ``coarsen`` section: ``uniform`` blocks (``dims`` per axis) or ``metis`` (``blocks``
    in all), and how permeability is upscaled."""

    method: Literal["uniform", "metis"]
    dims: tuple[int, ...] | None
    blocks: int | None
    permeability: Literal["arithmetic", "harmonic", "geometric", "harmonic-arithmetic"]


def case_coarsening(case: Case) -> Coarsening:
    """The case's ``coarsen`` section (the case must have one)."""
    spec = case.data["coarsen"]
    dims = tuple(int(n) for n in spec["dims"]) if "dims" in spec else None
    blocks = int(spec["blocks"]) if "blocks" in spec else None
    return Coarsening(spec["method"], dims, blocks, spec["permeability"])


def case_partition(
    case: Case, grid: Grid, rock, *, cell_volumes: np.ndarray, geometry: Geometry | None = None
) -> np.ndarray:
    """The coarse block of every cell of ``grid`` (``rock``: the petrophysics arrays, or None).
    METIS weighs the cells by pore volume (``cell_volumes`` x porosity); uniform blocks need
    the whole ``geometry``."""
    coarsening = case_coarsening(case)
    try:
        if coarsening.method == "uniform":
            if geometry is None:
                raise InputError("uniform blocks need the grid's geometry")
            return process_partition(grid, partition_ui(grid, coarsening.dims, geometry))
        weights = None
        if rock is not None:
            weights = np.maximum(rock["poro"] * cell_volumes, 1e-12)
        return partition_metis(grid, coarsening.blocks, cell_weights=weights, seed=case.seed)
    except InputError as exc:
        raise InputError(f"{case.path}: coarsen: {exc}") from None
