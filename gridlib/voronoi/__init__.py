"""Voronoi (PEBI) grids: the dual of a triangulation (``pebi``) and fault/well-conforming
PEBI grids generated from sites (``pebi_grid``).

The package is named ``voronoi`` so that ``gridlib.pebi`` stays the MRST-named
function and ``import gridlib.voronoi.dual`` works.
"""

from .areal import areal_path
from .domain import rectangle
from .dual import pebi
from .fault_network import Fault
from .pebi_grid import PebiGrid, PebiTuning, pebi_grid
from .quality import PebiQuality, grid_quality
from .wells import Rings, Well

__all__ = [
    "Fault",
    "PebiGrid",
    "PebiQuality",
    "PebiTuning",
    "Rings",
    "Well",
    "areal_path",
    "grid_quality",
    "pebi",
    "pebi_grid",
    "rectangle",
]
