"""Workflow stages as plain functions: a loaded case and its artifacts' paths in, artifacts out.

What a case builds is the table :data:`gridlib.artifacts.STAGES`: each stage's function, the
artifacts it reads and writes, and which cases have them. A stage function takes the loaded
:class:`~gridlib.config.Case` and the paths of its inputs and outputs as keyword arguments
named after the artifacts (``stage_grid(case, horizons=..., grid=..., grdecl=...)``); it reads
its inputs, calls gridlib and writes its outputs atomically with the case's provenance (gridlib
version, case file hash, seed). :func:`run_case` runs every stage a case has, in one folder (the
``gridlib build`` command, a study's variants); the Snakemake rules run one stage each
(``stage_job`` of ``workflow/rules/common.smk``, through :func:`run_stage`).

Stages: horizons -> grid -> geometry -> petrophysics -> coarsen, transmissibility and quality
(cell-quality measures, the case's qc rules) -> wells (trajectory and survey wells) -> export ->
pictures, beside flow_deck (the OPM Flow deck), then summary over all cases; on request simulate
(OPM Flow runs the deck).
"""

from .._lazy import lazy_exports

# The stages, imported on first use (PEP 562): a stage's script imports only its own module
# and what that uses (not xarray for the table, not gstools for the export, ...).
_EXPORTS: dict[str, str] = {
    "case_outputs": ".pipeline",
    "run_case": ".pipeline",
    "run_stage": ".pipeline",
    "run_logged": ".common",
    "stage_coarsen": ".coarsen",
    "stage_export": ".export",
    "stage_flow_deck": ".flow_deck",
    "stage_geometry": ".geometry",
    "stage_grid": ".grid",
    "stage_horizons": ".horizons",
    "stage_petrophysics": ".petrophysics",
    "stage_pictures": ".pictures",
    "stage_quality": ".quality",
    "stage_simulate": ".simulate",
    "stage_summary": ".summary",
    "stage_transmissibility": ".transmissibility",
    "stage_wells": ".wells",
}

__all__ = sorted(_EXPORTS)


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
