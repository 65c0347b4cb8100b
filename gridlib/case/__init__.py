"""A case's YAML data turned into gridlib objects (the layer between the configuration and the
stages): its grid (:mod:`.grid`, with :mod:`.simple_grids` for cartesian, tensor and layered
grids, :mod:`.sites`, :mod:`.axes`), faults (:mod:`.faults`), wells (:mod:`.wells`), deck file
(:mod:`.deck`), horizons (:mod:`.horizons`), rock (:mod:`.rock`, also a deck with the case's
rock), coarse partition (:mod:`.partition`) and what its OPM Flow deck simulates
(:mod:`.simulation`). The stages read artifacts, call these and write artifacts.

Names are imported on first use, so that a stage pays only for the modules it uses.
"""

from .._lazy import lazy_exports

_EXPORTS: dict[str, str] = {
    "CaseGrid": ".grid",
    "CaseSimulation": ".simulation",
    "Coarsening": ".partition",
    "build_case_grid": ".grid",
    "build_grid": ".simple_grids",
    "case_coarsening": ".partition",
    "case_horizons": ".horizons",
    "case_partition": ".partition",
    "case_rock": ".rock",
    "case_rock_keys": ".rock",
    "case_rock_with_sources": ".rock",
    "case_simulation": ".simulation",
    "deck_with_rock": ".rock",
    "fault_traces": ".faults",
    "pebi_wells": ".wells",
    "read_case_deck": ".deck",
}

__all__ = sorted(_EXPORTS)

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
