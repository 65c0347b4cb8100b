"""A case's wells (``wells``) as :class:`~gridlib.voronoi.Well` objects for pebi grids: a well's
``point`` + ``rings`` or ``path`` (and ``spacing``)."""

from __future__ import annotations

from ..config import Case
from ..voronoi import Rings, Well


def pebi_wells(case: Case) -> list[Well]:
    """The case's wells as voronoi Wells (the cell sites follow them)."""
    wells = []
    for spec in case.data.get("wells", []):
        rings = None
        if "rings" in spec:
            r = spec["rings"]
            rings = Rings(r["inner"], r.get("outer"), r.get("growth"), r.get("count"), r.get("sectors"))
        path, spacing = spec.get("path"), spec.get("spacing")
        wells.append(Well(spec.get("point"), spec["name"], rings=rings, path=path, spacing=spacing))
    return wells
