"""Grid orientation: how far each interior face is from the direction of the line joining its
two cells' centres (K-orthogonality, the condition under which a two-point flux is consistent).

For an interior face f between cells a = ``neighbors[f, 0]`` and b = ``neighbors[f, 1]``, with
area vector n_f (pointing from a to b) and cell centres c_a, c_b:

* the **orientation angle** is the angle between n_f and c_b - c_a, in degrees (0 to 180;
  0 for a Cartesian grid, 90 - dip for the faces along a pillar inclined at dip degrees from
  the horizontal, above 90 only when the centres lie on the wrong sides of the face);
* with a permeability K (diagonal per cell, (kx, ky, kz) along the grid's axes; z is depth),
  the **K-orientation angle** is the larger over the two cells of the angle between K_i n_f
  and c_b - c_a. A grid is K-orthogonal when K_i n_f is along the centre line on *both* sides
  (a two-point flux is then exact for linear pressure in each cell); a face tensor made by
  averaging K_a and K_b could be along the line when neither side is, so each side counts.
  A cell whose K n_f is zero (no permeability across the face) does not count; a face where
  neither does is left out of the K figures.

Faces of zero area are left out (nothing flows through them), and so are faces whose two
centres coincide or are not finite (a deck's degenerate cell of zero volume has no centroid).
Angles come from ``atan2(|n x d|, n . d)``, accurate near 0 (where an ``arccos`` of the
cosine loses half the digits) and the same bits on every machine
(:func:`gridlib.reproducible.arctan2`).

Which centres: the caller's (:func:`face_angles` takes them), by default the cell centroids.
The workflow's ``summary.json`` reports the angles for the centres its transmissibilities use
(:mod:`gridlib.stages.export`): the generating sites of a PEBI grid (at each cell's centroid
depth), the centroids of any other grid. (ECLIPSE's corner-point transmissibilities use the
mean of each cell's 8 corners: the centroid for a parallelepiped cell, close to it for a
mildly distorted one.)

>>> import numpy as np
>>> from gridlib import cart_grid, compute_geometry
>>> g = cart_grid([3, 2, 2])
>>> angles = face_angles(g.faces.neighbors, compute_geometry(g).face_normals,
...                      compute_geometry(g).cell_centroids)
>>> angles.faces.size, orientation_figures(angles.angles)
(20, {'median': 0.0, 'p95': 0.0, 'max': 0.0})
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from .errors import GridError, InputError
from .geometry import Geometry
from .grid import FloatArray, Grid, IntArray
from .reproducible import arctan2

_RAD_TO_DEG = 180.0 / np.pi


def vector_angles(u: ArrayLike, v: ArrayLike) -> FloatArray:
    """The angle (degrees, 0 to 180) between the rows of ``u`` and ``v`` ((n, 2) or (n, 3)),
    NaN where either row is zero.

    >>> vector_angles([[1.0, 0.0], [1.0, 0.0], [1.0, 1.0]], [[2.0, 0.0], [0.0, 3.0], [-1.0, -1.0]]).tolist()
    [0.0, 90.0, 180.0]
    """
    u = np.asarray(u, dtype=np.float64)
    v = np.asarray(v, dtype=np.float64)
    if u.shape != v.shape or u.ndim != 2 or u.shape[1] not in (2, 3):
        raise GridError(f"vector_angles: expected two (n, 2) or (n, 3) arrays, got {u.shape} and {v.shape}")
    dot = _row_dot(u, v)  # the bits of (u * v).sum(axis=1), component by component: faster
    if u.shape[1] == 2:
        sine = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    else:
        c0 = u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1]
        c1 = u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2]
        c2 = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
        sine = np.sqrt(c0 * c0 + c1 * c1 + c2 * c2)
    out = arctan2(sine, dot) * _RAD_TO_DEG
    zero = ~_nonzero_rows(u) | ~_nonzero_rows(v)
    return np.where(zero, np.nan, out)


@dataclass(frozen=True, eq=False)
class FaceAngles:
    """The orientation angles (degrees) of the measured interior faces; see the module docstring."""

    faces: IntArray  # (m,) the faces measured: interior, non-zero area, distinct finite centres
    angles: FloatArray  # (m,) angle(n_f, c_b - c_a)
    k_angles: FloatArray | None = None  # (m,) max over the two cells of angle(K_i n_f, c_b - c_a);
    # NaN where neither cell has permeability across the face; None without a permeability

    def __post_init__(self) -> None:
        for name in ("faces", "angles", "k_angles"):
            arr = getattr(self, name)
            if arr is not None:
                arr.flags.writeable = False


def face_vectors(
    neighbors: ArrayLike, normals: ArrayLike, centres: ArrayLike
) -> tuple[IntArray, FloatArray, FloatArray]:
    """The faces :func:`face_angles` measures (interior, non-zero area, distinct finite centres),
    their area vectors n_f and centre lines c_b - c_a, components first ((d, m) each: every
    operation on them runs over the faces); arguments as :func:`face_angles`'s."""
    nb, n, x = _checked(neighbors, normals, centres)
    xt = np.ascontiguousarray(x.T)  # (d, nc): gathers of one component at a time
    return _block_vectors(nb, n, xt, _finite_centres(xt))


def _checked(
    neighbors: ArrayLike, normals: ArrayLike, centres: ArrayLike
) -> tuple[IntArray, FloatArray, FloatArray]:
    """``neighbors``, ``normals`` and ``centres`` as arrays, or a GridError naming what is wrong."""
    nb = np.asarray(neighbors)
    n = np.asarray(normals, dtype=np.float64)
    x = np.asarray(centres, dtype=np.float64)
    if nb.ndim != 2 or nb.shape[1] != 2 or n.shape != (nb.shape[0], x.shape[-1]) or x.ndim != 2:
        raise GridError(
            f"face_angles: expected neighbors (nf, 2), normals (nf, d) and centres (nc, d), got "
            f"{nb.shape}, {n.shape} and {x.shape}"
        )
    if nb.size and nb.max() >= x.shape[0]:
        raise GridError(
            f"face_angles: neighbors name cell {int(nb.max())}, but there are {x.shape[0]} centres"
        )
    return nb, n, x


def _finite_centres(xt: FloatArray) -> np.ndarray:
    """Per cell whether its centre (a column of ``xt``) is finite, and False at [-1] (outside)."""
    return np.append(np.isfinite(xt).all(axis=0), False)


def _block_vectors(
    nb: IntArray, n: FloatArray, xt: FloatArray, finite: np.ndarray
) -> tuple[IntArray, FloatArray, FloatArray]:
    """:func:`face_vectors` of the faces with neighbours ``nb`` and normals ``n`` (a block of
    the grid's, face numbers counted from its start), centres ``xt`` (d, nc) and their
    :func:`_finite_centres`."""
    faces = np.flatnonzero(finite[nb[:, 0]] & finite[nb[:, 1]])
    a, b = nb[faces, 0], nb[faces, 1]
    nt = np.ascontiguousarray(n.T)
    if faces.size != nb.shape[0]:
        nt = nt[:, faces]
    dt = np.empty_like(nt)
    for i in range(xt.shape[0]):
        np.subtract(xt[i][b], xt[i][a], out=dt[i])
    kept = _nonzero_rows(nt.T) & _nonzero_rows(dt.T)
    if kept.all():
        return faces, nt, dt
    return faces[kept], nt[:, kept], dt[:, kept]


_FACES = 1 << 20  # faces measured at a time: the temporaries of a block, not of every face


def face_angles(
    neighbors: ArrayLike,
    normals: ArrayLike,
    centres: ArrayLike,
    perm: ArrayLike | None = None,
) -> FaceAngles:
    """The orientation angles of every interior face (module docstring): ``neighbors`` (nf, 2)
    as ``grid.faces.neighbors``, ``normals`` (nf, d) area vectors from ``neighbors[:, 0]`` to
    ``neighbors[:, 1]`` (``Geometry.face_normals``), ``centres`` (nc, d) the cell centres,
    ``perm`` (nc, d) optional diagonal permeabilities (kx, ky[, kz]; any unit, >= 0).
    Faces are measured a block at a time (each angle is its face's alone)."""
    nb, n, x = _checked(neighbors, normals, centres)
    k = None if perm is None else checked_perm(perm, x.shape)
    xt = np.ascontiguousarray(x.T)  # (d, nc): gathers of one component at a time
    finite = _finite_centres(xt)
    faces = np.empty(nb.shape[0], dtype=np.int64)  # filled block by block, then cut to the faces measured
    angles = np.empty(nb.shape[0])
    k_angles = np.empty(nb.shape[0]) if k is not None else None
    m = 0
    for start in range(0, nb.shape[0], _FACES):
        block = slice(start, start + _FACES)
        f, nt, dt = _block_vectors(nb[block], n[block], xt, finite)
        nf, d = nt.T, dt.T
        out = slice(m, m + f.size)
        np.add(f, start, out=faces[out])
        angles[out] = vector_angles(nf, d)
        if k_angles is not None:
            a, b = nb[block][f, 0], nb[block][f, 1]
            k_angles[out] = np.fmax(vector_angles(k[a] * nf, d), vector_angles(k[b] * nf, d))
        m += f.size
    return FaceAngles(faces[:m], angles[:m], None if k_angles is None else k_angles[:m])


def _nonzero_rows(u: FloatArray) -> np.ndarray:
    """Rows of ``u`` with a component that is not 0 (NaN counts as not 0)."""
    out = u[:, 0] != 0
    for i in range(1, u.shape[1]):
        out |= u[:, i] != 0
    return out


def _row_dot(u: FloatArray, v: FloatArray) -> FloatArray:
    """Row-wise dot products, component by component (faster than a sum over a short axis)."""
    out = u[:, 0] * v[:, 0]
    for i in range(1, u.shape[1]):
        out += u[:, i] * v[:, i]
    return out


def checked_perm(perm: ArrayLike, shape: tuple[int, ...]) -> FloatArray:
    """``perm`` as float64 of ``shape`` (one diagonal (kx, ky[, kz]) per cell), finite and >= 0;
    a GridError for a wrong shape, an InputError naming the first bad cell."""
    k = np.asarray(perm, dtype=np.float64)
    if k.shape != shape:
        raise GridError(f"face_angles: expected perm {shape} (kx, ky[, kz] per cell), got {k.shape}")
    bad = ~(np.isfinite(k) & (k >= 0)).all(axis=1)
    if bad.any():
        cell = int(np.flatnonzero(bad)[0])
        raise InputError(
            f"face_angles: the permeability of cell {cell} (0-based) is {k[cell].tolist()}: expected "
            "finite values >= 0"
        )
    return k


def grid_face_angles(
    grid: Grid, geometry: Geometry, centres: ArrayLike | None = None, perm: ArrayLike | None = None
) -> FaceAngles:
    """:func:`face_angles` of ``grid`` with its ``geometry``; ``centres`` default to the cell
    centroids."""
    x = geometry.cell_centroids if centres is None else centres
    return face_angles(grid.faces.neighbors, geometry.face_normals, x, perm)


def orientation_figures(angles: ArrayLike) -> dict[str, float]:
    """Median, 95th percentile (linear interpolation) and maximum of ``angles`` (degrees),
    NaN entries left out; all 0 when there is no angle (a grid of one cell).

    >>> orientation_figures([0.0, 10.0, 20.0, float("nan")])
    {'median': 10.0, 'p95': 19.0, 'max': 20.0}
    """
    a = np.asarray(angles, dtype=np.float64)
    a = a[~np.isnan(a)]  # a copy: the order statistics below may reorder it in place (same values)
    if a.size == 0:
        return {"median": 0.0, "p95": 0.0, "max": 0.0}
    median = float(np.median(a, overwrite_input=True))
    return {
        "median": median,
        "p95": float(np.percentile(a, 95.0, overwrite_input=True)),
        "max": float(a.max()),
    }
