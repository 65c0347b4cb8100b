"""Quality report of a planar grid, in particular of a :class:`~gridlib.voronoi.pebi_grid.PebiGrid`.

Orthogonality error of an interior face: the angle (degrees, 0..180) between
the face normal and the line joining its two cells' points, from
``neighbors[:, 0]`` to ``neighbors[:, 1]``. It is given for two choices of the
points: the *sites* (generating points; a PEBI grid's two-point flux is exact
for these, so the error is 0 up to round-off unless something went wrong) and
the *centroids* (what most simulators use to compute transmissibilities).

Sizes relative to the target (``PebiGrid.site_size`` h of every cell): the
smallest cell area / h² and the smallest face length / the smaller h of its
cells. Deliberately small cells (well rings, fault steps refined at junctions)
have a small h, so these show slivers and tiny faces rather than refinement.

>>> from gridlib.voronoi import pebi_grid
>>> q = grid_quality(pebi_grid(((0, 0), (3, 2)), 1.0, pattern="cartesian"))
>>> q.num_cells, q.area_min, q.area_max, round(q.orthogonality_centroids_max, 9)
(6, 1.0, 1.0, 0.0)
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import GridError
from ..geometry import compute_geometry
from ..grid import Grid
from ..orientation import vector_angles
from .pebi_result import PebiGrid


@dataclass(frozen=True)
class PebiQuality:
    """Cell areas (m²), face lengths (m), orthogonality errors (degrees), cells per well."""

    num_cells: int
    num_faces: int
    area_min: float
    area_median: float
    area_max: float
    face_length_min: float
    face_length_median: float
    orthogonality_sites_max: float  # nan when the sites are unknown (a bare Grid)
    orthogonality_centroids_max: float
    orthogonality_centroids_mean: float
    cells_per_well: dict[str, int] = field(default_factory=dict)
    faces_per_fault: dict[str, int] = field(default_factory=dict)
    area_ratio_min: float = float("nan")  # min cell area / its target size squared (PebiGrid only)
    face_ratio_min: float = float("nan")  # min face length / the smaller target size of its cells

    def __str__(self) -> str:
        lines = [
            f"cells {self.num_cells:,d}, faces {self.num_faces:,d}",
            f"cell area   min {self.area_min:.4g}  median {self.area_median:.4g}  max {self.area_max:.4g} m2",
            f"face length min {self.face_length_min:.4g}  median {self.face_length_median:.4g} m",
            f"orthogonality error: sites max {self.orthogonality_sites_max:.3g} deg, centroids max "
            f"{self.orthogonality_centroids_max:.3g} deg, mean {self.orthogonality_centroids_mean:.3g} deg",
        ]
        if np.isfinite(self.area_ratio_min):
            lines.insert(
                3,
                f"relative to each cell's target size h: area / h2 min {self.area_ratio_min:.3g}, "
                f"face length / h min {self.face_ratio_min:.3g}",
            )
        if self.cells_per_well:
            lines.append("cells per well: " + ", ".join(f"{k} {v}" for k, v in self.cells_per_well.items()))
        if self.faces_per_fault:
            lines.append("faces per fault: " + ", ".join(f"{k} {v}" for k, v in self.faces_per_fault.items()))
        return "\n".join(lines)


def grid_quality(obj: object) -> PebiQuality:
    """Quality figures of a :class:`PebiGrid` or of a planar 2-D :class:`Grid`."""
    sites = None
    cells_per_well: dict[str, int] = {}
    faces_per_fault: dict[str, int] = {}
    if isinstance(obj, PebiGrid):
        grid = obj.grid
        sites = obj.sites
        counts = np.bincount(obj.cell_well, minlength=len(obj.well_names) + 1)
        cells_per_well = {name: int(counts[i + 1]) for i, name in enumerate(obj.well_names)}
        fc = np.bincount(grid.faces.tag, minlength=len(obj.fault_names) + 1)
        faces_per_fault = {name: int(fc[i + 1]) for i, name in enumerate(obj.fault_names)}
    elif isinstance(obj, Grid):
        grid = obj
    else:
        raise GridError(f"grid_quality: expected a PebiGrid or a Grid, got {type(obj).__name__}")
    if grid.griddim != 2 or grid.dim != 2:
        raise GridError("grid_quality: needs a planar 2-D grid")
    geo = compute_geometry(grid)
    nb = grid.faces.neighbors
    inner = (nb >= 0).all(axis=1)
    n = geo.face_normals[inner]
    a, b = nb[inner, 0], nb[inner, 1]
    cen = vector_angles(n, geo.cell_centroids[b] - geo.cell_centroids[a]) if inner.any() else np.zeros(1)
    if sites is not None and inner.any():
        site_max = float(vector_angles(n, sites[b] - sites[a]).max())
    else:
        site_max = float("nan")
    area = geo.cell_volumes
    length = geo.face_areas
    area_ratio = face_ratio = float("nan")
    size = getattr(obj, "site_size", None)
    if size is not None:
        area_ratio = float((area / size**2).min())
        h = np.minimum(size[nb[:, 0]], np.where(nb[:, 1] >= 0, size[np.maximum(nb[:, 1], 0)], np.inf))
        face_ratio = float((length / h).min())
    return PebiQuality(
        num_cells=grid.num_cells,
        num_faces=grid.num_faces,
        area_min=float(area.min()),
        area_median=float(np.median(area)),
        area_max=float(area.max()),
        face_length_min=float(length.min()),
        face_length_median=float(np.median(length)),
        orthogonality_sites_max=site_max,
        orthogonality_centroids_max=float(cen.max()),
        orthogonality_centroids_mean=float(cen.mean()),
        cells_per_well=cells_per_well,
        faces_per_fault=faces_per_fault,
        area_ratio_min=area_ratio,
        face_ratio_min=face_ratio,
    )
