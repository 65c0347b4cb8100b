"""gridlib: reservoir grids in one unstructured model, in the spirit of MRST.

Every grid type (Cartesian, rectilinear, triangular, tetrahedral, Voronoi/PEBI,
layered 2.5D) is a :class:`Grid` of cells, faces and nodes; see
:mod:`gridlib.grid` for the conventions (0-based indices, -1 = outside,
z is depth, face normals point from ``neighbors[:, 0]`` to ``neighbors[:, 1]``).

>>> import gridlib as gl
>>> g = gl.cart_grid([10, 10, 5], [100.0, 100.0, 10.0])
>>> geo = gl.compute_geometry(g)
>>> round(float(geo.cell_volumes.sum()), 6)
100000.0
>>> gl.check_grid(g, geo)
"""

from importlib.metadata import PackageNotFoundError, version

from .checks import check_grid
from .coarsen import (
    CoarseGrid,
    coarse_grid,
    compress_partition,
    partition_metis,
    partition_ui,
    process_partition,
    upscale_ntg,
    upscale_permeability,
    upscale_porosity,
)
from .cornerpoint import (
    CornerPointGrid,
    Deck,
    FaultSegment,
    FaultTrace,
    Horizon,
    cut_grdecl,
    horizons_to_grdecl,
    make_model3,
    process_grdecl,
    simple_grdecl,
)
from .errors import GridError, InputError
from .geometry import Geometry, compute_geometry
from .glue import glue_2d
from .grid import Cells, Faces, Grid, Layering, Nodes
from .io.egrid import read_egrid
from .io.grdecl import DeckError, read_grdecl, write_grdecl
from .layered import make_layered_grid
from .stratigraphic.columns import ColumnGrid, extrude_columns
from .stratigraphic.extrude import ExtrudedGrid, extrude
from .structured import cart_grid, tensor_grid, translate_grid, twister
from .subgrid import Subgrid, extract_subgrid, remove_cells
from .unstructured import tessellation_grid, tetrahedral_grid, triangle_grid
from .voronoi import Fault, PebiGrid, Rings, Well, grid_quality, pebi, pebi_grid, rectangle

try:
    __version__ = version("gridlib")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0.0.0+unknown"

__all__ = [
    "Cells",
    "CoarseGrid",
    "ColumnGrid",
    "CornerPointGrid",
    "Deck",
    "DeckError",
    "ExtrudedGrid",
    "Faces",
    "Fault",
    "FaultSegment",
    "FaultTrace",
    "Geometry",
    "Grid",
    "GridError",
    "Horizon",
    "InputError",
    "Layering",
    "Nodes",
    "PebiGrid",
    "Rings",
    "Subgrid",
    "Well",
    "__version__",
    "cart_grid",
    "check_grid",
    "coarse_grid",
    "compress_partition",
    "compute_geometry",
    "cut_grdecl",
    "extract_subgrid",
    "extrude",
    "extrude_columns",
    "glue_2d",
    "grid_quality",
    "horizons_to_grdecl",
    "make_layered_grid",
    "make_model3",
    "partition_metis",
    "partition_ui",
    "pebi",
    "pebi_grid",
    "process_grdecl",
    "process_partition",
    "read_egrid",
    "read_grdecl",
    "rectangle",
    "remove_cells",
    "simple_grdecl",
    "tensor_grid",
    "tessellation_grid",
    "tetrahedral_grid",
    "translate_grid",
    "triangle_grid",
    "twister",
    "upscale_ntg",
    "upscale_permeability",
    "upscale_porosity",
    "write_grdecl",
]
