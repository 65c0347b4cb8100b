"""What :func:`~gridlib.voronoi.pebi_grid.pebi_grid` returns: a PEBI grid and what generated
each of its cells (the site kinds)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..grid import Grid

BACKGROUND, PADDING_SITE, FAULT, FAULT_TIP, WELL, ADDED, WELL_SIDE = range(7)  # PebiGrid.site_kind


@dataclass(frozen=True, eq=False)
class PebiGrid:
    """A PEBI grid and what generated it.

    ``grid``: the 2-D :class:`Grid` (``faces.tag`` = fault id on fault faces, 0
    elsewhere). ``cell_well`` (nc,): 0, or the 1-based well id of the cell.
    ``fault_names``, ``well_names``: names by id - 1. ``sites`` (nc, 2): the
    generating point of every cell (m). ``notes``: what was adjusted (clipped
    or extended faults, sites added). ``site_kind`` (nc,): what generated each
    cell: ``BACKGROUND`` 0, ``PADDING_SITE`` 1, ``FAULT`` 2 (a mirrored pair),
    ``FAULT_TIP`` 3, ``WELL`` 4, ``ADDED`` 5 (where a concave boundary cut a cell),
    ``WELL_SIDE`` 6 (the mirrored rows beside a well path; not the well's cells).
    ``site_size`` (nc,): the target size of each cell (m), the square root of the area
    it is meant to have: the lattice spacing for background sites, the step along the
    trace for fault sites (in an acute wedge, the wedge's step; its first step is longer),
    sqrt(arc spacing x radial width) for well rings, the step along a well path (also for its
    side rows), the
    cell size for added sites. ``fault_traces``: for every fault (by id - 1) the pieces of
    trace its faces follow, as segments (k, 2, 2) in metres: the input clipped to the
    domain, with the extensions and joins the notes name.
    """

    grid: Grid
    cell_well: np.ndarray
    fault_names: tuple[str, ...]
    well_names: tuple[str, ...]
    sites: np.ndarray
    notes: tuple[str, ...]
    site_kind: np.ndarray | None = None
    site_size: np.ndarray | None = None
    fault_traces: tuple[np.ndarray, ...] = ()

    def __repr__(self) -> str:
        return (
            f"PebiGrid(cells={self.grid.num_cells}, faces={self.grid.num_faces}, "
            f"faults={list(self.fault_names)}, wells={list(self.well_names)})"
        )
