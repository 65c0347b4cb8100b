"""Connection factors of deviated well pieces: Peaceman's factor per cell axis, combined.

A straight piece of a well path inside one cell, of vector ``v`` (exit minus entry), gets
the connection (transmissibility) factor that OPM Flow computes for the trajectory
keywords COMPTRAJ/WELTRAJ (opm-common, ``WellConnections::loadCOMPTRAJ``, from
ResInsight's completion export, ``RicWellPathExportCompletionDataFeatureImpl::
calculateTransmissibilityData``):

1. **Cell axes** (:func:`cell_axes`). In a logically Cartesian cell, I = c_E - c_W and
   J = c_N - c_S join the centroids of opposite sides. The third axis is the unit normal
   K = I x J / |I x J| of the plane they span (not the T -> B vector), and the first two
   are symmetrised into an orthonormal pair in that plane:
   x = (I + J x K) / |.|, y = (J - I x K) / |.|, z = K
   (ResInsight's ``RigCellGeometryTools::findCellLocalXYZ``, copied into opm-common's
   ``RigEclipseWellLogExtractor``). x . y = I.J - I.J = 0 exactly in exact arithmetic, so
   the axes are a rotation of the global ones, and they are exactly the global axes in a
   box cell. Side centroids here are area-weighted (as :func:`~gridlib.transmissibility.
   peaceman.cell_extents` uses them); ResInsight takes the mean of a side's 4 corners:
   the same for parallelogram sides. Cells of grids that are not logically Cartesian
   (PEBI, layered, tetrahedral: no ``cells.face_tag``), and logical cells that miss a
   side, use the global axes (x east, y north, z down).
2. **Lengths per axis** (:func:`axis_lengths`): |L_x|, |L_y|, |L_z| with v = L_x x + L_y y
   + L_z z, the coordinates of ``v`` in the basis of the unit axes (ResInsight solves this
   3 x 3 system, ``RigWellPathIntersectionTools::calculateLengthInCell``; here by Cramer's
   rule, exact for the global axes). For orthonormal axes these are the projections, and
   L_x^2 + L_y^2 + L_z^2 = |v|^2.
3. **A factor per axis** (:func:`trajectory_factors`): COMPDAT's factor of a completion
   along that axis (:func:`~gridlib.transmissibility.peaceman.connection_factor`), with the
   completed length replaced by the piece's length along the axis:

       CF_x = 2 pi sqrt(ky kz) L_x / (ln(r0_x / min(r_w, r0_x)) + S),  r0_x from (ky, dy), (kz, dz NTG)
       CF_y = 2 pi sqrt(kz kx) L_y / (ln(r0_y / min(r_w, r0_y)) + S),  r0_y from (kz, dz NTG), (kx, dx)
       CF_z = 2 pi sqrt(kx ky) L_z NTG / (ln(r0_z / min(r_w, r0_z)) + S),  r0_z from (kx, dx), (ky, dy)

   in the unit system's factor unit. NTG multiplies L_z and the cell's dz wherever dz
   enters r0; the skin S enters every axis' denominator (opm-common ``permThickness``,
   ``connectionFactor``, ``effectiveExtent``). (dx, dy, dz) are the cell's extents: Flow's
   for a deck (``extents=`` :func:`~gridlib.transmissibility.peaceman.deck_cell_extents`),
   else :func:`~gridlib.transmissibility.peaceman.cell_extents` (the bounding box in x, y
   and the thickness V / A in grids that are not logically Cartesian). In such grids the z
   factor takes the PEBI form r0 = 0.174 sqrt(A) (A = V / dz, the horizontal area), as
   :func:`~gridlib.transmissibility.peaceman.well_index`'s "auto" form does for vertical
   wells.
4. **The combination**: CF = sqrt(CF_x^2 + CF_y^2 + CF_z^2) (opm-common ``std::hypot`` of
   the three; ResInsight ``RigTransmissibilityEquations::totalConnectionFactor``). A piece
   along one axis through a whole cell therefore has exactly COMPDAT's factor for that
   direction, NTG and skin included.

ResInsight's own export differs in two details this module does not follow (Flow's
COMPTRAJ is the reference): it leaves NTG off dz in r0 (and off L_x, L_y unless "lateral
NTG" is chosen), and it takes ln(r0 / r_w) without Flow's min(r_w, r0).

**Direction** (the COMPDAT item a factor is written with): the axis with the largest share
L_a / d_a of the cell's extent, as ResInsight's ``calculateCellMainDirection``: x only if
its share is strictly the largest, y only if strictly larger than x's and z's, else z.

Conventions: z is depth (down); lengths (coordinates, extents, radii) in the unit
system's length unit; permeability in mD; factors in the unit system's transmissibility
unit (METRIC cP m3/(day bar)).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..geometry import Geometry
from ..grid import E, FloatArray, Grid, IntArray, N, S, W
from ..transmissibility.peaceman import (
    completion_cells,
    completion_rock,
    connection_factor,
    horizontal_area,
    side_centroids,
)
from ..units import METRIC, UnitSystem, unit_system

__all__ = ["axis_lengths", "cell_axes", "main_direction", "trajectory_factors"]


def cell_axes(grid: Grid, geometry: Geometry, cells: ArrayLike) -> FloatArray:
    """Unit axes (n, 3, 3) of cells (rows of a 3-D ``grid``): ``axes[i, a]`` is cell i's
    x (a = 0), y (1) or z (2) axis as a unit vector in (x, y, depth) coordinates. Logically
    Cartesian cells: ResInsight's orthonormal axes from the vectors between opposite side
    centroids; other cells: the global axes (module docstring).

    >>> import gridlib as gl
    >>> g = gl.cart_grid([1, 1, 1], [4.0, 2.0, 1.0])
    >>> cell_axes(g, gl.compute_geometry(g), [0])[0].tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    if grid.griddim != 3 or grid.dim != 3:
        raise InputError("cells: well paths cross the cells of 3-D grids only (use well_index in 2-D)")
    rows = completion_cells(cells, grid.num_cells)
    axes = np.tile(np.eye(3), (rows.size, 1, 1))
    if grid.cells.face_tag is None or rows.size == 0:
        return axes
    centre, found = side_centroids(grid, geometry, rows)
    i_vec = centre[:, E] - centre[:, W]
    j_vec = centre[:, N] - centre[:, S]
    k_vec = _unit(np.cross(i_vec, j_vec))
    x = _unit(i_vec + np.cross(j_vec, k_vec))
    y = _unit(j_vec - np.cross(i_vec, k_vec))
    logical = np.stack([x, y, k_vec], axis=1)
    ok = found & np.isfinite(logical).all(axis=(1, 2))
    axes[ok] = logical[ok]
    return axes


def axis_lengths(axes: ArrayLike, vectors: ArrayLike) -> FloatArray:
    """Lengths (n, 3) of pieces ``vectors`` (n, 3) along their cells' ``axes`` (n, 3, 3):
    the absolute coordinates of each vector in the basis of its cell's unit axes (axes that
    are not unit vectors are normalised; for orthonormal axes these are the projections).

    >>> axis_lengths([[[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]]], [[3.0, -4.0, 12.0]]).tolist()
    [[3.0, 4.0, 12.0]]
    """
    a = np.asarray(axes, dtype=np.float64)
    v = np.asarray(vectors, dtype=np.float64)
    if a.ndim != 3 or a.shape[1:] != (3, 3) or v.shape != (a.shape[0], 3):
        raise InputError(f"axes, vectors: expected shapes (n, 3, 3) and (n, 3), got {a.shape} and {v.shape}")
    if not (np.isfinite(a).all() and np.isfinite(v).all()):
        raise InputError("axes, vectors: values must be finite")
    u = _unit(a)
    x, y, z = u[:, 0], u[:, 1], u[:, 2]
    yz, zx, xy = np.cross(y, z), np.cross(z, x), np.cross(x, y)
    det = _dot(x, yz)
    bad = ~(np.abs(det) > 0)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError(f"axes: the axes of piece {i} are degenerate (linearly dependent or zero)")
    coordinates = np.column_stack([_dot(v, yz), _dot(v, zx), _dot(v, xy)]) / det[:, None]
    return np.abs(coordinates)


def trajectory_factors(
    grid: Grid,
    geometry: Geometry,
    permeability: ArrayLike | None,
    cells: ArrayLike,
    lengths: ArrayLike,
    radius: ArrayLike,
    skin: ArrayLike = 0.0,
    *,
    ntg: ArrayLike | None = None,
    extents: ArrayLike | None = None,
    units: UnitSystem | str = METRIC,
) -> tuple[FloatArray, IntArray]:
    """Connection factors (n,) of well pieces in ``cells`` (rows of a 3-D ``grid``) with
    ``lengths`` (n, 3) along the cells' axes (:func:`axis_lengths`), and each piece's
    direction (n,): 0, 1, 2 for x, y, z (:func:`main_direction`).

    ``permeability`` (mD, per cell; the diagonal is used), ``ntg`` (nc,) in [0, 1];
    ``radius`` (> 0) and ``skin``: one value or one per piece; ``extents`` (n, 3): the
    cells' (dx, dy, dz) without NTG (default :func:`~gridlib.transmissibility.peaceman.
    cell_extents`; Flow's for a deck: :func:`~gridlib.transmissibility.peaceman.
    deck_cell_extents`). The formulas and their sources: module docstring. A piece along
    one axis through the whole cell has exactly :func:`~gridlib.transmissibility.peaceman.
    well_index`'s factor for that direction.

    >>> import gridlib as gl
    >>> g = gl.cart_grid([1, 1, 1], [100.0, 100.0, 10.0])
    >>> lengths = [[0.0, 0.0, 10.0], [6.0, 0.0, 8.0]]
    >>> cf, axis = trajectory_factors(g, gl.compute_geometry(g), 100.0, [0, 0], lengths, 0.1)
    >>> round(float(cf[0]), 9), axis.tolist()  # as well_index's vertical completion
    (10.131361493, [2, 2])
    """
    if grid.griddim != 3:
        raise InputError("cells: well paths cross the cells of 3-D grids only (use well_index in 2-D)")
    rows = completion_cells(cells, grid.num_cells)
    n = rows.size
    length = np.array(lengths, dtype=np.float64)
    if length.shape != (n, 3) or not np.isfinite(length).all() or (length < 0).any():
        raise InputError(
            f"lengths: expected finite, non-negative lengths along (x, y, z) per piece, shape ({n}, 3)"
        )
    k, ext, net = completion_rock(grid, geometry, permeability, rows, ntg=ntg, extents=extents)
    pebi = np.full(n, grid.cells.face_tag is None)
    area = horizontal_area(geometry, rows, ext, pebi)
    across = ext.copy()
    across[:, 2] *= net  # NTG on dz wherever it enters r0
    along = length.copy()
    along[:, 2] *= net  # and on the length along z
    u = unit_system(units)
    squares = []
    for a in range(3):  # a loop over the three axes, vectorised over the pieces
        e = across.copy()
        e[:, a] = along[:, a]
        cf = connection_factor(k, e, np.full(n, a), radius, skin, u, pebi=pebi if a == 2 else None, area=area)
        squares.append(cf * cf)
    factor = np.sqrt((squares[0] + squares[1]) + squares[2])
    return factor, main_direction(length, ext)


def main_direction(lengths: ArrayLike, extents: ArrayLike) -> IntArray:
    """The direction (0, 1, 2 for x, y, z) of pieces with ``lengths`` (n, 3) along the axes of
    cells of ``extents`` (n, 3): the axis with the largest share L_a / d_a, x only when its
    share is strictly the largest, y only when strictly larger than x's and z's, else z
    (ResInsight's ``calculateCellMainDirection``). A zero extent counts as an infinite share
    where the length along it is positive, none where it is 0.

    >>> extents = [[100.0, 50.0, 5.0], [100.0, 50.0, 5.0]]
    >>> main_direction([[50.0, 5.0, 1.0], [10.0, 10.0, 1.0]], extents).tolist()
    [0, 2]
    """
    length = np.asarray(lengths, dtype=np.float64)
    ext = np.asarray(extents, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        share = np.where(ext > 0, length / ext, np.where(length > 0, np.inf, 0.0))
    sx, sy, sz = share.T
    x = (sx > sy) & (sx > sz)
    y = ~x & (sy > sx) & (sy > sz)
    return np.where(x, 0, np.where(y, 1, 2)).astype(np.int64)


def _dot(a: FloatArray, b: FloatArray) -> FloatArray:
    """Row-wise dot products of (..., 3) arrays, summed in a fixed order."""
    return (a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]) + a[..., 2] * b[..., 2]


def _unit(v: FloatArray) -> FloatArray:
    """``v`` (..., 3) divided by its length (NaN for zero vectors)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return v / np.sqrt(_dot(v, v))[..., None]
