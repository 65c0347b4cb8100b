"""Workflow stages as plain functions: case file (and earlier artifacts) in, artifacts out.

Each stage reads its inputs, calls gridlib and writes its outputs atomically
with the case's provenance (gridlib version, case file hash, seed). The
Snakemake scripts in ``workflow/scripts`` are one-line wrappers around these,
so the same stages run from Python or from the ``gridlib build`` command.

Stages: horizons -> grid -> geometry -> petrophysics -> coarsen and
transmissibility -> export (with the OPM Flow deck, :mod:`.flow_deck`), then summary
over all cases; optionally simulate (OPM Flow runs the deck).
"""

from .coarsen import stage_coarsen
from .common import run_logged
from .export import stage_export
from .flow_deck import stage_flow_deck
from .geometry import stage_geometry
from .grid import stage_grid
from .horizons import stage_horizons
from .petrophysics import stage_petrophysics
from .pipeline import case_outputs, run_case
from .simulate import stage_simulate
from .summary import stage_summary
from .transmissibility import stage_transmissibility

__all__ = [
    "case_outputs",
    "run_case",
    "run_logged",
    "stage_coarsen",
    "stage_export",
    "stage_flow_deck",
    "stage_geometry",
    "stage_grid",
    "stage_horizons",
    "stage_petrophysics",
    "stage_simulate",
    "stage_summary",
    "stage_transmissibility",
]
