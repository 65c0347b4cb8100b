"""Workflow stages as plain functions: case file (and earlier artifacts) in, artifacts out.

Each stage reads its inputs, calls gridlib and writes its outputs atomically
with the case's provenance (gridlib version, case file hash, seed). The
Snakemake scripts in ``workflow/scripts`` are one-line wrappers around these,
so the same stages run from Python or from the ``gridlib build`` command.

Stages: horizons -> grid -> geometry -> petrophysics -> coarsen and
transmissibility -> export (with the OPM Flow deck, :mod:`.flow_deck`), then summary
over all cases; optionally simulate (OPM Flow runs the deck).
"""

from .._lazy import lazy_exports

# The stages, imported on first use (PEP 562): a stage's script imports only its own module
# and what that uses (not xarray for the table, not gstools for the export, ...).
_EXPORTS: dict[str, str] = {
    "case_outputs": ".pipeline",
    "run_case": ".pipeline",
    "run_logged": ".common",
    "stage_coarsen": ".coarsen",
    "stage_export": ".export",
    "stage_flow_deck": ".flow_deck",
    "stage_geometry": ".geometry",
    "stage_grid": ".grid",
    "stage_horizons": ".horizons",
    "stage_petrophysics": ".petrophysics",
    "stage_simulate": ".simulate",
    "stage_summary": ".summary",
    "stage_transmissibility": ".transmissibility",
}

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


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
