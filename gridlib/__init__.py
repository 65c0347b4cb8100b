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

from ._lazy import lazy_exports
from .version import __version__ as __version__

# The public names, imported on first use (PEP 562): `import gridlib` and the workflow's
# `import gridlib.config` stay cheap, and a stage imports only the modules it uses.
_EXPORTS: dict[str, str] = {
    "check_deck_grid": ".checks",
    "check_grid": ".checks",
    "CoarseGrid": ".coarsen",
    "coarse_grid": ".coarsen",
    "compress_partition": ".coarsen",
    "partition_metis": ".coarsen",
    "partition_ui": ".coarsen",
    "process_partition": ".coarsen",
    "upscale_ntg": ".coarsen",
    "upscale_permeability": ".coarsen",
    "upscale_porosity": ".coarsen",
    "CornerPointGrid": ".cornerpoint",
    "Deck": ".cornerpoint",
    "FaultSegment": ".cornerpoint",
    "FaultTrace": ".cornerpoint",
    "Horizon": ".cornerpoint",
    "cut_grdecl": ".cornerpoint",
    "horizons_to_grdecl": ".cornerpoint",
    "horizons_to_pillar_grdecl": ".cornerpoint",
    "make_model3": ".cornerpoint",
    "process_grdecl": ".cornerpoint",
    "simple_grdecl": ".cornerpoint",
    "GridError": ".errors",
    "InputError": ".errors",
    "Geometry": ".geometry",
    "compute_geometry": ".geometry",
    "glue_2d": ".glue",
    "Cells": ".grid",
    "Faces": ".grid",
    "Grid": ".grid",
    "Layering": ".grid",
    "Nodes": ".grid",
    "read_egrid": ".io.egrid",
    "DeckError": ".io.grdecl",
    "read_grdecl": ".io.grdecl",
    "write_grdecl": ".io.grdecl",
    "write_edit_grdecl": ".io.grdecl",
    "make_layered_grid": ".layered",
    "FaceAngles": ".orientation",
    "face_angles": ".orientation",
    "grid_face_angles": ".orientation",
    "orientation_figures": ".orientation",
    "ColumnGrid": ".pillars.columns",
    "extrude_columns": ".pillars.columns",
    "ExtrudedGrid": ".pillars.extrude",
    "extrude": ".pillars.extrude",
    "cart_grid": ".structured",
    "tensor_grid": ".structured",
    "translate_grid": ".structured",
    "twister": ".structured",
    "Subgrid": ".subgrid",
    "extract_subgrid": ".subgrid",
    "remove_cells": ".subgrid",
    "tessellation_grid": ".unstructured",
    "tetrahedral_grid": ".unstructured",
    "triangle_grid": ".unstructured",
    "Fault": ".voronoi",
    "PebiGrid": ".voronoi",
    "Rings": ".voronoi",
    "Well": ".voronoi",
    "grid_quality": ".voronoi",
    "pebi": ".voronoi",
    "pebi_grid": ".voronoi",
    "rectangle": ".voronoi",
}


__all__ = sorted([*_EXPORTS, "__version__"])


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
