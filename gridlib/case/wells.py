"""A case's wells (``wells``) as gridlib objects: the deviated wells' paths
(:func:`case_well_paths`: a trajectory file or a survey, with branches, perforations, radius and
skin) and, for pebi grids, every well as a :class:`~gridlib.voronoi.Well` the sites follow
(:func:`pebi_wells`: a point well's ``point``, ``rings`` and ``fault_side``, a map ``path`` with
``spacing``, a deviated well's plan view inside the reservoir).

Files are relative to the case file; lengths, depths and MD in the case's length unit (m; a
FIELD deck's ft), z depth. What is read and checked, and how branches join their parents:
:mod:`gridlib.config.well_paths` (the checks run when the case is loaded, so these calls do not
fail on a case that loaded).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..config import Case
from ..config.files import pebi_outline
from ..config.well_paths import is_deviated, well_paths
from ..pillars.horizon_maps import DepthFunction
from ..voronoi import Rings, Well, areal_path
from ..wells.path import WellPath

WELL_RADIUS = 0.1  # m: a well's radius where the case gives none (in a FIELD case, its value in ft)


@dataclass(frozen=True, eq=False)
class CaseWellPath:
    """A trajectory or survey well of a case.

    ``path`` is its main path and ``branches`` its laterals in the case's order; ``parents[b]``
    is the path branch ``b`` starts on (0 the main path, ``b' + 1`` branch ``b'``);
    ``perforations[p]`` the open MD intervals (k, 2), sorted, of path ``p`` (0 the main path,
    ``b + 1`` branch ``b``; the whole path where the case gives none). ``radius`` (None: the
    default, 0.1 m in the case's length unit) and ``skin`` give its connection factors. ``key``
    names it in messages (``wells[2]``), ``spacing`` its PEBI sites' spacing (None: the cell
    size).
    """

    name: str
    path: WellPath
    branches: tuple[WellPath, ...]
    parents: tuple[int, ...]
    perforations: tuple[np.ndarray, ...]
    radius: float | None
    skin: float
    key: str
    spacing: float | None = None

    @property
    def paths(self) -> tuple[WellPath, ...]:
        """The main path, then the branches."""
        return (self.path, *self.branches)


def case_well_paths(case: Case) -> tuple[CaseWellPath, ...]:
    """The case's trajectory and survey wells, in the case's order (point and map-path wells
    are left out)."""
    wells = []
    for k, spec in enumerate(case.data.get("wells", [])):
        if not is_deviated(spec):
            continue
        key = f"wells[{k}]"
        read = well_paths(case.path, spec, key)
        radius = spec.get("radius")
        spacing = spec.get("spacing")
        wells.append(
            CaseWellPath(
                name=str(spec["name"]),
                path=read.paths[0],
                branches=read.paths[1:],
                parents=read.parents,
                perforations=read.perforations,
                radius=None if radius is None else float(radius),
                skin=float(spec.get("skin", 0.0)),
                key=key,
                spacing=None if spacing is None else float(spacing),
            )
        )
    return tuple(wells)


def pebi_wells(case: Case, top: DepthFunction | None = None, base: DepthFunction | None = None) -> list[Well]:
    """The case's wells as voronoi Wells (the cell sites follow them): point wells with their
    rings, map paths, and, given the reservoir's ``top`` and ``base`` depth functions (m, z
    down; ``f(x, y)``), each trajectory or survey well as the plan view of the parts of its
    paths between them (:func:`~gridlib.voronoi.areal_path`; a vertical part a point), inside
    the domain by half a cell (:func:`deviated_plan_view`). A deviated well that never enters
    the reservoir there gets no sites (its wells stage names it if no cell connects)."""
    wells = []
    deviated = {w.key: w for w in case_well_paths(case)} if top is not None and base is not None else {}
    for k, spec in enumerate(case.data.get("wells", [])):
        if is_deviated(spec):
            well = deviated.get(f"wells[{k}]")
            parts = [] if well is None else deviated_plan_view(case, well, top, base)
            if parts:
                wells.append(Well(None, well.name, path=parts, spacing=well.spacing))
            continue
        rings = None
        if "rings" in spec:
            r = spec["rings"]
            rings = Rings(r["inner"], r.get("outer"), r.get("growth"), r.get("count"), r.get("sectors"))
        path, spacing = spec.get("path"), spec.get("spacing")
        side = spec.get("fault_side")
        wells.append(
            Well(spec.get("point"), spec["name"], rings=rings, path=path, spacing=spacing, fault_side=side)
        )
    return wells


PLAN_TOLERANCE = 0.1  # of the site spacing: a path's plan view is simplified within this


def deviated_plan_view(
    case: Case, well: CaseWellPath, top: DepthFunction, base: DepthFunction
) -> list[np.ndarray]:
    """The plan view ((k, 2) polylines, k = 1 a point) of the parts of ``well``'s paths (main
    and branches, all of them: perforations do not change the grid) between ``top`` and
    ``base``, simplified within :data:`PLAN_TOLERANCE` of its sites' spacing (a file's
    centimetre noise or a survey's dense points along a straight stretch make no sites of
    their own), clipped to the pebi domain shrunk by half a cell (sites on the outline would
    make cells of no width there)."""
    import shapely

    grid = case.data["grid"]
    size = float(grid["cell_size"])
    spacing = well.spacing or size
    domain = grid["domain"]
    area = pebi_outline(domain)
    inner = area.buffer(-0.5 * size)
    parts = []
    for path in well.paths:
        for part in areal_path(path.xyz, top, base, tolerance=PLAN_TOLERANCE * spacing):
            shape = shapely.Point(part[0]) if part.shape[0] == 1 else shapely.LineString(part)
            clipped = shape.intersection(inner)
            for piece in getattr(clipped, "geoms", [clipped]):
                if not piece.is_empty and piece.geom_type in ("Point", "LineString"):
                    parts.append(np.asarray(piece.coords, dtype=np.float64)[:, :2])
    return parts
