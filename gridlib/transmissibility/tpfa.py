"""Two-point flux transmissibilities of any grid (MRST's ``computeTrans``).

For a face f between cells i and j with area vector N_f (m2, from i to j) and
centroid x_f, the half-transmissibility of cell i is

    T_i = |c_i . K_i N_f| / (c_i . c_i),   c_i = x_f - x_i,

with x_i the cell's centre (its centroid by default; for PEBI grids the generating
site, so that c_i is parallel to N_f and the two-point flux is consistent) and K_i
its permeability tensor; the face's transmissibility is the harmonic combination
T = T_i T_j / (T_i + T_j). The absolute value makes skewed cells (c . K N < 0)
count with their magnitude, as MRST does. NTG multiplies the half-transmissibilities
of lateral faces (between different columns of a layered grid, or the W/E/S/N faces
of a logically Cartesian grid), as ECLIPSE does on I and J faces.

Units: permeability in millidarcy; coordinates in the length unit of ``units``
(metres for METRIC, feet for FIELD, ...); T in that system's transmissibility unit
(:mod:`gridlib.units`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..geometry import Geometry
from ..grid import B, Grid, T
from ..units import METRIC, UnitSystem, unit_system
from .connections import FAULT, NEIGHBOR, OTHER, Connections, assemble


def permeability_tensors(permeability: ArrayLike, num_cells: int, dim: int, what: str = "permeability"):
    """Per-cell permeability (mD) as (nc, dim) diagonal or (nc, dim, dim) full tensors.

    Accepts one isotropic value for all cells, (nc,) isotropic values, (nc, dim) diagonals,
    (nc, dim, dim) or (nc, dim*dim) full tensors, and in 3-D MRST's (nc, 6) upper triangle
    [xx, xy, xz, yy, yz, zz].
    Values must be finite, diagonals non-negative.
    """
    k = np.asarray(permeability, dtype=np.float64)
    if k.ndim == 0:
        k = np.full(num_cells, float(k))
    if k.shape[:1] != (num_cells,):
        raise InputError(
            f"{what}: expected one value or tensor per cell ({num_cells} cells), got shape {k.shape}"
        )
    if not np.isfinite(k).all():
        raise InputError(f"{what}: values must be finite")
    if k.ndim == 1:
        k = np.repeat(k[:, None], dim, axis=1)
    elif k.ndim == 2 and k.shape[1] == dim:
        pass
    elif k.ndim == 2 and k.shape[1] == dim * dim:
        k = k.reshape(num_cells, dim, dim)
    elif k.ndim == 2 and dim == 3 and k.shape[1] == 6:
        xx, xy, xz, yy, yz, zz = k.T
        k = np.stack([np.stack([xx, xy, xz], 1), np.stack([xy, yy, yz], 1), np.stack([xz, yz, zz], 1)], 1)
    elif k.ndim == 3 and k.shape[1:] == (dim, dim):
        pass
    else:
        raise InputError(
            f"{what}: shape {k.shape} is not (nc,), (nc, {dim}), (nc, {dim}, {dim}) or (nc, {dim * dim})"
        )
    diag = k if k.ndim == 2 else np.diagonal(k, axis1=1, axis2=2)
    if (diag < 0).any():
        cell = int(np.flatnonzero((diag < 0).any(axis=1))[0])
        raise InputError(f"{what}: negative permeability in cell {cell}")
    return k


def half_transmissibility(
    k: np.ndarray, cells: np.ndarray, c: list[np.ndarray], n: list[np.ndarray], distance: str
) -> np.ndarray:
    """Half-transmissibilities of ``cells`` (their tensors: rows of ``k``, diagonal (nc, d)
    or full (nc, d, d)) towards faces with area vectors ``n`` and centre-to-face vectors
    ``c``, both given component by component (lists of d arrays), summed in a fixed order.

    ``"centroid"``: |c . K n| / (c . c); ``"normal"``: c replaced by its component along n,
    which reduces to |n . K n| / |c . n|.
    """
    d = len(n)
    if k.ndim == 2:
        kn = [k[cells, j] * n[j] for j in range(d)]
    else:
        kc = k[cells]
        kn = []
        for i in range(d):
            row = kc[:, i, 0] * n[0]
            for j in range(1, d):
                row += kc[:, i, j] * n[j]
            kn.append(row)
    if distance == "normal":
        num = n[0] * kn[0]
        den = c[0] * n[0]
        for j in range(1, d):
            num += n[j] * kn[j]
            den += c[j] * n[j]
    else:
        num = c[0] * kn[0]
        den = c[0] * c[0]
        for j in range(1, d):
            num += c[j] * kn[j]
            den += c[j] * c[j]
    np.abs(num, out=num)
    np.abs(den, out=den)
    with np.errstate(divide="ignore", invalid="ignore"):
        num /= den
    num[~(den > 0.0)] = 0.0
    return num


def harmonic(ta: np.ndarray, tb: np.ndarray) -> np.ndarray:
    """T_a T_b / (T_a + T_b), 0 where either half is 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where((ta > 0.0) & (tb > 0.0), ta * tb / (ta + tb), 0.0)


def lateral_faces(grid: Grid, faces: np.ndarray) -> np.ndarray | None:
    """Whether each of ``faces`` (interior) joins cells side by side rather than one above the
    other: different columns of a layered grid, or W/E/S/N faces of a logical grid; None
    when the grid says neither."""
    a, b = grid.faces.neighbors[faces, 0], grid.faces.neighbors[faces, 1]
    if grid.layering is not None:
        return grid.layering.column[a] != grid.layering.column[b]
    if grid.cells.face_tag is not None:
        tag = np.full(grid.num_faces, -1, dtype=np.int64)
        tag[grid.cells.faces] = grid.cells.face_tag  # the tag seen from either cell: same axis
        return (tag[faces] != T) & (tag[faces] != B)
    return None


def transmissibility(
    grid: Grid,
    geometry: Geometry,
    permeability: ArrayLike,
    ntg: ArrayLike | None = None,
    *,
    centres: ArrayLike | None = None,
    distance: str = "centroid",
    units: UnitSystem | str = METRIC,
) -> Connections:
    """Two-point flux transmissibilities of every interior face of ``grid``.

    ``permeability`` (mD): see :func:`permeability_tensors`. ``ntg``: net-to-gross per
    cell, in [0, 1], on lateral half-transmissibilities (layered or logical grids).
    ``centres`` (nc, d): the cell centres; default the centroids. ``distance``:
    ``"centroid"`` takes c_i from the centre to the face centroid (MRST);
    ``"normal"`` takes its component along the face normal, the distance from the
    centre to the face's plane, so that T_i = (n K n) |N| / dist_i. For PEBI (Voronoi)
    grids pass the generating sites as centres (for a layered PEBI grid: each cell's
    site with its centroid's depth) and ``distance="normal"``: every lateral face is the
    perpendicular bisector of its two sites, T = K A / |x_j - x_i| for isotropic K, and
    the two-point fluxes of a linear pressure field are exact (with face centroids off
    the line between the sites, the centroid variant is not). Connections are one per
    cell pair (faces between the same two cells add up); their kind is NEIGHBOR for
    logical neighbours, FAULT for other pairs across fault-tagged faces or in logical
    grids, OTHER otherwise. ``units``: the unit system of the coordinates and of T, a
    :class:`~gridlib.units.UnitSystem` or its name.

    >>> import gridlib as gl
    >>> g = gl.cart_grid([3, 1, 1], [30.0, 10.0, 2.0])
    >>> c = transmissibility(g, gl.compute_geometry(g), 100.0)
    >>> c.cells.tolist(), [round(float(t), 6) for t in c.trans]  # K A / d: 100 mD 20 m2 / 10 m
    ([[0, 1], [1, 2]], [1.705403, 1.705403])
    """
    units = unit_system(units)
    nc, dim = grid.num_cells, grid.griddim
    k = permeability_tensors(permeability, nc, dim)
    x = geometry.cell_centroids if centres is None else np.asarray(centres, dtype=np.float64)
    if x.shape != (nc, dim) or not np.isfinite(x).all():
        raise InputError(f"centres: expected finite ({nc}, {dim}) cell centres, got shape {x.shape}")
    if distance not in ("centroid", "normal"):
        raise InputError(f"distance: expected 'centroid' or 'normal', got {distance!r}")
    nb = grid.faces.neighbors
    f = np.flatnonzero((nb >= 0).all(axis=1))
    a, b = nb[f, 0], nb[f, 1]
    n = [geometry.face_normals[:, j][f] for j in range(dim)]
    xf = [geometry.face_centroids[:, j][f] for j in range(dim)]
    ta = half_transmissibility(k, a, [xf[j] - x[:, j][a] for j in range(dim)], n, distance)
    tb = half_transmissibility(k, b, [xf[j] - x[:, j][b] for j in range(dim)], n, distance)
    notes = []
    if ntg is not None:
        g = np.asarray(ntg, dtype=np.float64)
        if g.shape != (nc,) or not np.isfinite(g).all() or (g < 0).any() or (g > 1).any():
            raise InputError(f"ntg: expected one value in [0, 1] per cell ({nc} cells)")
        lateral = lateral_faces(grid, f)
        if lateral is None:
            raise InputError(
                "ntg: applies to lateral faces; the grid is neither layered nor logically Cartesian"
            )
        ta = np.where(lateral, ta * g[a], ta)
        tb = np.where(lateral, tb * g[b], tb)
        notes.append("NTG applied to lateral half-transmissibilities")
    trans = harmonic(ta, tb) * units.darcy_constant
    kind = np.full(f.size, OTHER, dtype=np.int8)
    if grid.cells.index_map is not None and grid.cart_dims is not None:
        dims = grid.cart_dims
        step = np.abs(grid.cells.index_map[a] - grid.cells.index_map[b])
        strides = [int(np.prod(dims[:d])) for d in range(len(dims))]
        kind = np.where(np.isin(step, strides), NEIGHBOR, FAULT).astype(np.int8)
    elif grid.faces.tag is not None:
        kind = np.where(grid.faces.tag[f] > 0, FAULT, OTHER).astype(np.int8)
    return assemble(
        np.column_stack([a, b]),
        trans,
        kind,
        f,
        index_map=grid.cells.index_map,
        units=units,
        notes=notes,
    )
