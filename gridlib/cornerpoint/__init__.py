"""Corner-point grids: ECLIPSE decks in, faulted unstructured grids out (the pillar engine's
Cartesian front end), and generators of test and example decks.

>>> from gridlib.cornerpoint import process_grdecl, simple_grdecl
>>> r = process_grdecl(simple_grdecl([4, 2, 3], 0.12, flat=True))
>>> r.grid.num_cells, r.nnc.num, r.fault_names
(24, 4, ('fault_1',))
"""

from .between_horizons import FaultTrace, Horizon, horizons_to_grdecl
from .deck import FAULT_FACES, Deck, FaultSegment
from .generators import cut_grdecl, make_model3, simple_grdecl
from .pillar_grdecl import horizons_to_pillar_grdecl
from .process import FAULT, NNC, PINCH, CornerPointGrid, process_grdecl

__all__ = [
    "FAULT",
    "FAULT_FACES",
    "NNC",
    "PINCH",
    "CornerPointGrid",
    "Deck",
    "FaultSegment",
    "FaultTrace",
    "Horizon",
    "cut_grdecl",
    "horizons_to_grdecl",
    "horizons_to_pillar_grdecl",
    "make_model3",
    "process_grdecl",
    "simple_grdecl",
]
