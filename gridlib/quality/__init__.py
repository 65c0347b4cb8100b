"""Per-cell quality measures of any grid (docs/quality.md).

xtgeo's set (``Grid.get_gridquality_properties``: the same names, definitions and units) for
the cells that are corner-point hexahedra, NaN for the others; and, for every grid, the
face-orientation errors of a two-point flux, the aspect ratio and the faces' non-planarity.

The table of measures (:data:`MEASURES`) is defined here and costs nothing to import (the
file formats name their variables from it); :func:`cell_quality` and :func:`deck_quality`
(:mod:`gridlib.quality.measures`) are imported on first use.
"""

from __future__ import annotations

from dataclasses import dataclass

from .._lazy import lazy_exports


@dataclass(frozen=True)
class Measure:
    """One per-cell quality quantity."""

    name: str  # xtgeo's name where xtgeo has it
    unit: str  # a quantity of gridlib.units ("angle": degrees; "dimensionless": flags, ratios)
    description: str
    hexahedral_only: bool  # NaN for cells that are not corner-point hexahedra


_A, _D = "angle", "dimensionless"
MEASURES: tuple[Measure, ...] = (
    Measure("minangle_topbase", _A, "smallest corner angle of the top and base faces", True),
    Measure("maxangle_topbase", _A, "largest corner angle of the top and base faces", True),
    Measure("minangle_topbase_proj", _A, "smallest corner angle of top and base in plan view", True),
    Measure("maxangle_topbase_proj", _A, "largest corner angle of top and base in plan view", True),
    Measure("minangle_sides", _A, "smallest corner angle of the four side faces", True),
    Measure("maxangle_sides", _A, "largest corner angle of the four side faces", True),
    Measure("collapsed", _D, "1 where the thickness on a pillar is below 1e-5", True),
    Measure("faulted", _D, "1 where a corner node is split by a fault", True),
    Measure("negative_thickness", _D, "1 where the bottom is above the top on a pillar", True),
    Measure("concave_proj", _D, "0 convex in plan view, else 1 + the corner inside the others", True),
    Measure("twist", _A, "turn of the base against the top about the cell's vertical axis", True),
    Measure("orientation_error", _A, "largest angle between face normal and centre line", False),
    Measure("k_orientation_error", _A, "largest angle between K n and the centre line", False),
    Measure("aspect_ratio", _D, "largest over smallest centroid-to-face distance", False),
    Measure("face_nonplanarity", _D, "largest node distance from a face's plane / sqrt(area)", False),
)
MEASURE = {m.name: m for m in MEASURES}
XTGEO_NAMES = tuple(m.name for m in MEASURES[:10])


_EXPORTS = {"cell_quality": ".measures", "deck_quality": ".measures"}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = ["MEASURE", "MEASURES", "XTGEO_NAMES", "Measure", "cell_quality", "deck_quality"]
