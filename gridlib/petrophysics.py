"""Petrophysics: porosity, permeability and net-to-gross per cell, in depositional coordinates.

ALGORITHMS.md §6. Sampling a field at *physical* cell centroids shifts it by
the throw across every fault, so layers deposited together get uncorrelated
values (the MRST book's exercise 3.5.1). Here fields are sampled at
**depositional coordinates** u = (x_r, y_r, w) (:func:`depositional_coordinates`):

* (x_r, y_r), the areal position before faulting, is the position of the
  cell's *column* (logical (i, j) of a corner-point grid, the areal cell of a
  layered grid), the same for every layer of it and independent of the throw
  (faults are vertical; for lateral heave pass restored ``column_xy``);
* w, the stratigraphic coordinate, is the position of the cell's *layer* in a
  reference column of layer thicknesses ``dz_ref`` (m): w = 0 at the top of
  layer 0 and w_k = dz_0 + ... + dz_{k-1} + dz_k / 2 at the middle of layer
  k. One number gives w = (k + 1/2) dz_ref; one per layer describes zones
  (e.g. each zone's mean thickness divided by its number of layers, with
  ``numpy.repeat``).

Two cells in the same layer on either side of a fault are thus as close as
lateral neighbours, whatever the throw, and a grid with throw gets exactly the
values of the same grid without it. The layer index is proportional layering
(``horizons_to_grdecl``, ``make_layered_grid``); where a zone is eroded or
onlaps, its truncated layers keep their w (they are pinched, not renumbered),
which is w measured from the zone's conformable surface as long as the
layering was built from it.

Functions are pure (arrays in, arrays out); a :class:`Rock` holds the result.
Units: metres, **z is depth (positive down)**, porosity and NTG as fractions,
permeability in **millidarcy** (mD; 1 mD = 9.869233e-16 m2).

Gaussian random fields
----------------------
:func:`gaussian_field` draws a stationary Gaussian field with a
:class:`Variogram` (gstools' Exponential, Gaussian or Matern covariance,
anisotropic correlation lengths, rotation angles) by gstools' randomisation
method (``gstools.SRF``, Heße et al. 2014): the sum of ``mode_no`` cosine
modes with random wave vectors drawn from the covariance's spectrum, seeded.
The same variogram, seed and positions give the same values, bit for bit (on
one machine and numpy build), and other positions see the same underlying field
to round-off (so a refined or coarsened grid sees the same geology).

At depositional coordinates the positions are a product, columns x layers, and
the modes factorise: cos(k.u) = cos(k_xy.x_r + k_w w) splits into column and
layer terms, so the sum over modes becomes a matrix product of a (columns x
2 modes) by a (2 modes x layers) matrix; when the columns lie on a lattice
(vertical pillars on a rectilinear mesh) k_xy.x_r splits once more into x and
y terms and only the distinct x, y and w need trigonometry. This is gstools'
field exactly (to round-off, checked by the tests) at a cost of O((columns +
layers) modes) or O((nx + ny + layers) modes) trigonometric evaluations
instead of O(cells x modes): 8e5 cells of 200 x 200 columns take about 1 s with
gstools' default of 1000 modes, where gstools' own summation takes 30 to 50 s
on two cores (``bench/petrophysics.py``). Fewer modes are faster and less
accurate (the realised variance scatters by about 1/sqrt(mode_no)); 1000 is
kept. At arbitrary points (an (n, 3) array, e.g. physical centroids) gstools
sums directly.

Porosity and permeability
-------------------------
:func:`normal_porosity` (mean + std Z, clipped), :func:`lognormal_permeability`
(median exp(sigma Z)), :func:`carman_kozeny` (the MRST book's relation, K =
phi^3 d^2 / (72 tau (1 - phi)^2) with grain diameter d = 10 micrometres and
tortuosity factor tau = 0.81: 2.143e-14 m2 = 21.7 mD at phi = 0.2),
:func:`per_layer` (constant, per layer or per zone values) and cubes on a
regular grid (:class:`PropertyCube`, :func:`read_property_cube`,
:func:`sample_cube`) sampled at centroids or at depositional coordinates.

>>> import gridlib as gl
>>> g = gl.cart_grid([20, 10, 5], [200.0, 100.0, 10.0])
>>> u = depositional_coordinates(g, dz_ref=2.0)
>>> v = Variogram("exponential", var=1.0, len_scale=[100.0, 100.0, 4.0])
>>> z = gaussian_field(u, v, seed=42)
>>> poro = normal_porosity(z, mean=0.2, std=0.03)
>>> rock = make_rock(poro, carman_kozeny(poro), kv_kh=0.1)
>>> rock.num_cells, bool(np.array_equal(z, gaussian_field(u, v, seed=42)))
(1000, True)
>>> round(float(carman_kozeny(0.2)), 2)  # mD
21.72
"""

from __future__ import annotations

import math
import numbers
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .errors import InputError
from .grid import Grid
from .io._dataset import load_dataset, save_dataset
from .reproducible import exp, matmul
from .threads import num_threads

__all__ = [
    "MILLIDARCY",
    "VARIOGRAM_MODELS",
    "Depositional",
    "PropertyCube",
    "Rock",
    "Variogram",
    "carman_kozeny",
    "depositional_coordinates",
    "gaussian_field",
    "layer_index",
    "lognormal_permeability",
    "make_rock",
    "normal_porosity",
    "per_layer",
    "read_property_cube",
    "sample_cube",
    "write_property_cube",
]

MILLIDARCY = 9.869233e-16  # m2
VARIOGRAM_MODELS = ("exponential", "gaussian", "matern")
_CHUNK = 2048  # columns per block of the factorised summation: (2048, modes) temporaries
_MAX_THREADS = 8  # blocks are summed by at most this many threads (each block alone: same result)

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]


def _number(value: Any, option: str, *, positive: bool = False, nonnegative: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(float(value)):
        raise InputError(f"{option}: expected a finite number, got {value!r}")
    v = float(value)
    if positive and not v > 0:
        raise InputError(f"{option}: must be positive, got {value!r}")
    if nonnegative and v < 0:
        raise InputError(f"{option}: must be >= 0, got {value!r}")
    return v


# --------------------------------------------------------------------------- variogram


@dataclass(frozen=True)
class Variogram:
    """A covariance model for :func:`gaussian_field` (gstools' definitions).

    ``model``: ``"exponential"`` (C(r) = var exp(-r / l)), ``"gaussian"``
    (var exp(-pi r^2 / (4 l^2)), gstools' scaling: l is the integral scale) or
    ``"matern"`` (smoothness ``nu``; 0.5 is exponential). ``var``: the
    variance (the property's unit squared). ``len_scale`` (m): one length, or
    one per axis of the rotated frame (x, y, w): anisotropy, e.g.
    ``[500, 250, 5]``. ``angles`` (degrees): gstools' rotation of that frame,
    the first about the vertical (counter-clockwise from +x towards +y, i.e.
    from east towards north), then the tilts. ``nu``: Matern only.

    >>> Variogram("spherical")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    gridlib.errors.InputError: variogram.model: unknown model 'spherical'; expected one of exponential, ...
    """

    model: str = "exponential"
    var: float = 1.0
    len_scale: float | tuple[float, ...] = 1.0
    angles: tuple[float, ...] = ()
    nu: float = 1.0

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        if not isinstance(self.model, str) or self.model.lower() not in VARIOGRAM_MODELS:
            raise InputError(
                f"variogram.model: unknown model {self.model!r}; "
                f"expected one of {', '.join(VARIOGRAM_MODELS)}"
            )
        set_(self, "model", self.model.lower())
        set_(self, "var", _number(self.var, "variogram.var", nonnegative=True))
        ls = self.len_scale
        if isinstance(ls, numbers.Real) and not isinstance(ls, bool):
            set_(self, "len_scale", _number(ls, "variogram.len_scale", positive=True))
        else:
            try:
                values = tuple(ls)  # type: ignore[arg-type]
            except TypeError:
                raise InputError(
                    f"variogram.len_scale: expected a length or a list of lengths (m), got {ls!r}"
                ) from None
            if not 1 <= len(values) <= 3:
                raise InputError(f"variogram.len_scale: expected 1 to 3 lengths (m), got {len(values)}")
            set_(self, "len_scale", tuple(_number(v, "variogram.len_scale", positive=True) for v in values))
        try:
            angles = tuple(self.angles)
        except TypeError:
            angles = (self.angles,)  # type: ignore[assignment]
        if len(angles) > 3:
            raise InputError(f"variogram.angles: at most 3 rotation angles (degrees), got {len(angles)}")
        set_(self, "angles", tuple(_number(a, "variogram.angles") for a in angles))
        set_(self, "nu", _number(self.nu, "variogram.nu", positive=True))

    def covmodel(self, dim: int = 3):
        """The gstools covariance model in ``dim`` dimensions."""
        import gstools as gs

        ls = self.len_scale
        if isinstance(ls, tuple) and len(ls) not in (1, dim):
            raise InputError(f"variogram.len_scale: {len(ls)} lengths for a {dim}-D field (give 1 or {dim})")
        n_angles = dim * (dim - 1) // 2
        if len(self.angles) > n_angles:
            raise InputError(f"variogram.angles: a {dim}-D field has at most {n_angles} angles")
        kwargs: dict[str, Any] = {
            "dim": dim,
            "var": self.var,
            "len_scale": list(ls) if isinstance(ls, tuple) else ls,
            "angles": [math.radians(a) for a in self.angles] or 0.0,
        }
        if self.model == "exponential":
            return gs.Exponential(**kwargs)
        if self.model == "gaussian":
            return gs.Gaussian(**kwargs)
        return gs.Matern(nu=self.nu, **kwargs)


# --------------------------------------------------------------------------- depositional coordinates


@dataclass(frozen=True, eq=False)
class Depositional:
    """Depositional coordinates of the cells of a grid, as columns x layers.

    ``column_xy`` (ncol, 2): the pre-fault areal position of every column (m);
    ``w_edges`` (nl + 1,): the stratigraphic coordinate of the layer interfaces
    (m, 0 at the top, increasing downwards); ``column``, ``layer`` (nc,): each
    cell's column and layer. Rows of ``column_xy`` no cell uses may be NaN.
    """

    column_xy: FloatArray
    w_edges: FloatArray
    column: IntArray
    layer: IntArray

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        xy = np.array(self.column_xy, dtype=np.float64)
        w = np.array(self.w_edges, dtype=np.float64)
        col = np.array(self.column, dtype=np.int64)
        lay = np.array(self.layer, dtype=np.int64)
        if xy.ndim != 2 or xy.shape[1] != 2:
            raise InputError(f"depositional coordinates: column_xy must be (ncol, 2), got {xy.shape}")
        if w.ndim != 1 or w.size < 2 or not np.isfinite(w).all() or (np.diff(w) <= 0).any():
            raise InputError("depositional coordinates: w_edges must be finite and strictly increasing")
        if col.shape != lay.shape or col.ndim != 1:
            raise InputError("depositional coordinates: column and layer must be 1-D of equal length")
        if col.size and (col.min() < 0 or col.max() >= xy.shape[0]):
            raise InputError(f"depositional coordinates: column ids must lie in [0, {xy.shape[0]})")
        if lay.size and (lay.min() < 0 or lay.max() >= w.size - 1):
            raise InputError(f"depositional coordinates: layer ids must lie in [0, {w.size - 1})")
        if col.size and not np.isfinite(xy[np.unique(col)]).all():
            raise InputError("depositional coordinates: a column holding cells has no finite (x, y)")
        for name, arr in (("column_xy", xy), ("w_edges", w), ("column", col), ("layer", lay)):
            arr.flags.writeable = False
            set_(self, name, arr)

    @property
    def num_cells(self) -> int:
        return self.column.size

    @property
    def num_layers(self) -> int:
        return self.w_edges.size - 1

    @property
    def layer_w(self) -> FloatArray:
        """w at the middle of every layer (m)."""
        return 0.5 * (self.w_edges[:-1] + self.w_edges[1:])

    @property
    def points(self) -> FloatArray:
        """(nc, 3) = x_r, y_r, w of every cell (m)."""
        xy = self.column_xy[self.column]
        return np.column_stack([xy, self.layer_w[self.layer]])


def _columns_layers(grid: Grid) -> tuple[IntArray, IntArray, int, int]:
    """Per cell its column and layer, the number of columns and of layers."""
    if grid.layering is not None:
        lay = grid.layering
        return lay.column, lay.layer, lay.areal.num_cells, lay.num_layers
    if grid.cart_dims is None:
        raise InputError(
            "depositional coordinates need a logically Cartesian grid (cart_dims and cells.index_map) or a "
            "layered grid (grid.layering); this grid has neither"
        )
    dims = tuple(grid.cart_dims)
    index = grid.cells.index_map
    if index is None:
        if int(np.prod(dims)) != grid.num_cells:
            raise InputError("depositional coordinates: the grid has cart_dims but no cells.index_map")
        index = np.arange(grid.num_cells)
    nxy = dims[0] * (dims[1] if len(dims) > 1 else 1)
    nl = dims[2] if len(dims) > 2 else 1
    return index % nxy, index // nxy, nxy, nl


def layer_index(grid: Grid) -> IntArray:
    """The layer of every cell (0 = top): ``index_map // (nx ny)`` of a logically Cartesian grid,
    ``layering.layer`` of a layered grid.

    >>> import gridlib as gl
    >>> layer_index(gl.cart_grid([2, 1, 3])).tolist()
    [0, 0, 1, 1, 2, 2]
    """
    return _columns_layers(grid)[1]


def depositional_coordinates(
    grid: Grid,
    *,
    dz_ref: float | ArrayLike | None = None,
    column_xy: ArrayLike | None = None,
    coord: ArrayLike | None = None,
    centroids: ArrayLike | None = None,
) -> Depositional:
    """The depositional coordinates (x_r, y_r, w) of the cells of ``grid`` (module docstring).

    Columns and layers: ``cells.index_map`` and ``cart_dims`` of a logically
    Cartesian grid (column = i + nx j, layer = k), or ``grid.layering``.

    The areal position of the columns, the first of:

    * ``column_xy`` (ncol, 2), given (m; e.g. restored positions);
    * a layered grid: the centroids of its areal cells;
    * ``coord``: the corner-point deck's COORD (``deck.coord``): the mean of the
      midpoints of a column's four pillars;
    * the mean (x, y) of the centroids of the column's cells (``centroids``
      (nc, 3), computed with ``compute_geometry`` if not given).

    ``dz_ref`` (m): the reference thickness of every layer (one number, or one
    per layer); default: the median depth difference between the centroids of
    vertically adjacent cells of a column (``centroids`` or computed), or 1 m
    for a single layer.

    >>> import gridlib as gl
    >>> u = depositional_coordinates(gl.cart_grid([2, 1, 2], [20.0, 10.0, 6.0]))
    >>> u.points.tolist()
    [[5.0, 5.0, 1.5], [15.0, 5.0, 1.5], [5.0, 5.0, 4.5], [15.0, 5.0, 4.5]]
    """
    column, layer, ncol, nl = _columns_layers(grid)
    cents = None if centroids is None else np.asarray(centroids, dtype=np.float64)
    if cents is not None and (cents.ndim != 2 or cents.shape[0] != grid.num_cells or cents.shape[1] < 2):
        raise InputError(f"centroids: expected ({grid.num_cells}, 3) cell centroids, got shape {cents.shape}")

    def centroids_() -> FloatArray:
        nonlocal cents
        if cents is None:
            from .geometry import compute_geometry

            cents = compute_geometry(grid).cell_centroids
        return cents

    if column_xy is not None:
        xy = np.asarray(column_xy, dtype=np.float64)
        if xy.shape != (ncol, 2):
            raise InputError(f"column_xy: expected ({ncol}, 2) column positions, got shape {xy.shape}")
    elif grid.layering is not None:
        from .geometry import compute_geometry

        xy = compute_geometry(grid.layering.areal).cell_centroids[:, :2]
    elif coord is not None:
        xy = _pillar_centres(coord, grid.cart_dims)
    else:
        c = centroids_()
        counts = np.bincount(column, minlength=ncol).astype(np.float64)
        with np.errstate(invalid="ignore", divide="ignore"):
            xy = np.column_stack(
                [np.bincount(column, c[:, 0], ncol) / counts, np.bincount(column, c[:, 1], ncol) / counts]
            )
    if dz_ref is None:
        dz = np.full(nl, _median_layer_step(column, layer, ncol, nl, centroids_) if nl > 1 else 1.0)
    else:
        dz = np.asarray(dz_ref, dtype=np.float64)
        if dz.ndim == 0:
            dz = np.full(nl, float(dz))
        if dz.shape != (nl,) or not np.isfinite(dz).all() or (dz <= 0).any():
            raise InputError(f"dz_ref: expected a positive thickness (m) or {nl} of them (one per layer)")
    return Depositional(xy, np.concatenate([[0.0], np.cumsum(dz)]), column, layer)


def _pillar_centres(coord: ArrayLike, cart_dims: tuple[int, ...] | None) -> FloatArray:
    if cart_dims is None or len(cart_dims) != 3:
        raise InputError("coord: pillars need a 3-D logically Cartesian grid (cart_dims nx, ny, nz)")
    nx, ny, _ = cart_dims
    c = np.asarray(coord, dtype=np.float64)
    if c.size != 6 * (nx + 1) * (ny + 1):
        raise InputError(f"coord: expected 6 (nx+1)(ny+1) = {6 * (nx + 1) * (ny + 1)} values, got {c.size}")
    p = c.reshape(ny + 1, nx + 1, 6)
    mid = 0.5 * (p[..., 0:2] + p[..., 3:5])
    col = 0.25 * (mid[:-1, :-1] + mid[:-1, 1:] + mid[1:, :-1] + mid[1:, 1:])  # (ny, nx, 2)
    return col.reshape(nx * ny, 2)


def _median_layer_step(column: IntArray, layer: IntArray, ncol: int, nl: int, centroids) -> float:
    """Median centroid depth difference of vertically adjacent cells of a column (m)."""
    key = column * nl + layer
    order = np.argsort(key, kind="stable")
    k = key[order]
    adjacent = np.flatnonzero(np.diff(k) == 1)
    adjacent = adjacent[(k[adjacent] // nl) == (k[adjacent + 1] // nl)]
    if adjacent.size == 0:
        return 1.0
    z = centroids()[:, 2] if centroids().shape[1] > 2 else np.zeros(column.size)
    step = z[order[adjacent + 1]] - z[order[adjacent]]
    step = step[step > 0]
    return float(np.median(step)) if step.size else 1.0


# --------------------------------------------------------------------------- Gaussian random fields


def gaussian_field(
    where: Depositional | ArrayLike,
    variogram: Variogram,
    *,
    seed: int,
    mean: float = 0.0,
    mode_no: int = 1000,
) -> FloatArray:
    """A Gaussian random field with ``variogram`` and ``mean`` at ``where``, seeded.

    ``where``: :class:`Depositional` coordinates (the fast factorised sum,
    module docstring) or points (n, d), d = 1..3 (m; gstools' own sum, cost
    proportional to n x mode_no). ``seed``: an integer; the same seed,
    variogram and positions give identical values. ``mode_no``: gstools'
    number of randomisation modes (accuracy against speed; default 1000).

    >>> v = Variogram("gaussian", var=4.0, len_scale=50.0)
    >>> points = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [500.0, 0.0, 0.0]])  # m
    >>> f = gaussian_field(points, v, seed=1, mean=10.0)
    >>> f.shape, bool(abs(f[0] - f[1]) < 0.2)
    ((3,), True)
    """
    import gstools as gs

    if not isinstance(variogram, Variogram):
        raise InputError(f"variogram: expected a Variogram, got {type(variogram).__name__}")
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral):
        raise InputError(f"seed: expected an integer, got {seed!r}")
    if isinstance(mode_no, bool) or not isinstance(mode_no, numbers.Integral) or mode_no < 1:
        raise InputError(f"mode_no: expected a positive integer, got {mode_no!r}")
    mean = _number(mean, "mean")
    if isinstance(where, Depositional):
        model = variogram.covmodel(3)
        srf = gs.SRF(model, mode_no=int(mode_no), seed=int(seed))
        if where.num_cells == 0:
            return np.zeros(0)
        values = _factorised(srf, model, where)
        if values is None:  # gstools changed its internals: sum the plain way
            values = srf(where.points.T, mesh_type="unstructured")
        return mean + np.asarray(values, dtype=np.float64)
    try:
        pts = np.asarray(where, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(
            f"gaussian_field: positions must be Depositional or an (n, d) array ({exc})"
        ) from exc
    if pts.ndim == 1:
        pts = pts[:, None]
    if pts.ndim != 2 or not 1 <= pts.shape[1] <= 3:
        raise InputError(
            f"gaussian_field: positions must be an (n, d) array, d = 1..3, got shape {pts.shape}"
        )
    if not np.isfinite(pts).all():
        raise InputError("gaussian_field: positions must be finite")
    model = variogram.covmodel(pts.shape[1])
    srf = gs.SRF(model, mode_no=int(mode_no), seed=int(seed))
    if pts.shape[0] == 0:
        return np.zeros(0)
    return mean + np.asarray(srf(pts.T, mesh_type="unstructured"), dtype=np.float64)


def _factorised(srf: Any, model: Any, u: Depositional) -> FloatArray | None:
    """gstools' randomisation-method sum at columns x layers, by the cos(a + b) identity.

    The field is sqrt(var / N) sum_m z1_m cos(k_m . T u) + z2_m sin(k_m . T u),
    T gstools' (linear) isometrisation. With K = T^t k, phase = K_xy . x_r + K_w w,
    so per column c and layer l: sum_m cos(a_cm) P_ml + sin(a_cm) Q_ml with
    P = z1 cos(b) + z2 sin(b), Q = z2 cos(b) - z1 sin(b), a_cm = K_xy,m . x_c,
    b_ml = K_w,m w_l: matrix products, by :func:`gridlib.reproducible.matmul` so that
    the field has the same bits for any BLAS, CPU and thread count.
    """
    gen = srf.generator
    try:
        k, z1, z2 = gen._cov_sample, gen._z_1, gen._z_2  # gstools.field.generator.RandMeth's modes
        n_modes = gen.mode_no
    except AttributeError:
        return None
    if getattr(model, "nugget", 0.0) or k is None or np.shape(k) != (3, n_modes):
        return None
    T = _isometrization(model)
    K = matmul(T.T, np.asarray(k, dtype=np.float64))  # (3, modes): phase = K . u
    used, col_pos = np.unique(u.column, return_inverse=True)
    xy = u.column_xy[used]
    b = np.outer(u.layer_w, K[2])  # (layers, modes)
    cb, sb = np.cos(b), np.sin(b)
    P = (z1 * cb + z2 * sb).T  # (modes, layers)
    Q = (z2 * cb - z1 * sb).T
    # Columns on a lattice (vertical pillars on a rectilinear mesh: cart_grid, horizons_to_grdecl,
    # make_model3) repeat few x and y values; then a = K_x x_i + K_y y_j splits once more, and
    # cos(a) P + sin(a) Q = cos(K_y y_j) R1_i + sin(K_y y_j) R2_i with R1 = cos(K_x x_i) P +
    # sin(K_x x_i) Q, R2 = cos(K_x x_i) Q - sin(K_x x_i) P: trigonometry of the distinct x and y
    # only, and batched matrix products over (x, y, layer).
    ux, ix = np.unique(xy[:, 0], return_inverse=True)
    uy, iy = np.unique(xy[:, 1], return_inverse=True)
    if ux.size * uy.size <= 2 * used.size and ux.size + uy.size < used.size:
        ax, ay = np.outer(ux, K[0]), np.outer(uy, K[1])
        cx, sx, cy, sy = np.cos(ax), np.sin(ax), np.cos(ay), np.sin(ay)
        G = np.empty((ux.size, uy.size, u.num_layers))
        CS = np.hstack([cy, sy])  # (len(uy), 2 modes)
        rows = max(1, _CHUNK // 32)
        for s in range(0, ux.size, rows):  # one large product per block
            c, sn = cx[s : s + rows, :, None], sx[s : s + rows, :, None]  # (rows, modes, 1)
            R = np.concatenate([c * P + sn * Q, c * Q - sn * P], axis=1)  # (rows, 2 modes, layers)
            n = R.shape[0]
            R = R.transpose(1, 0, 2).reshape(CS.shape[1], n * u.num_layers)
            G[s : s + n] = matmul(CS, R).reshape(uy.size, n, u.num_layers).transpose(1, 0, 2)
        F = G[ix.ravel(), iy.ravel()]
    else:
        F = np.empty((used.size, u.num_layers))
        PQ = np.vstack([P, Q])

        def block(s: int) -> None:
            a = matmul(xy[s : s + _CHUNK], K[:2])  # (chunk, modes)
            F[s : s + _CHUNK] = matmul(np.hstack([np.cos(a), np.sin(a)]), PQ)

        _parallel(block, range(0, used.size, _CHUNK))
    return math.sqrt(model.var / n_modes) * F[col_pos.ravel(), u.layer]


def _isometrization(model: Any) -> FloatArray:
    """gstools' isometrisation matrix of a 3-D model (``model.isometrize(np.eye(3))``), with
    its 3 x 3 products summed term by term instead of by BLAS (whose kernels round
    differently on different CPUs): diag(1, 1/anis) times the derotation, gstools'
    Givens rotations by the negated angles, in gstools' order and signs."""
    from gstools.tools.geometric import givens_rotation, rotation_planes

    angles = -np.asarray(model.angles, dtype=np.float64)
    derotate = np.eye(3)
    for i, (angle, plane) in enumerate(zip(angles, rotation_planes(3), strict=True)):
        derotate = matmul(derotate, givens_rotation(3, plane, (-1) ** i * angle))
    stretch = np.concatenate(([1.0], 1.0 / np.asarray(model.anis, dtype=np.float64)))
    return stretch[:, None] * derotate


def _parallel(fn: Any, starts: range) -> None:
    """fn(s) for every s, on a few threads (numpy releases the GIL in its loops and products);
    every block writes its own rows, so the result does not depend on the number of threads."""
    workers = num_threads(min(len(starts), _MAX_THREADS))
    if workers > 1:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(workers) as pool:
            list(pool.map(fn, starts))
    else:
        for s in starts:
            fn(s)


# --------------------------------------------------------------------------- porosity and permeability


def normal_porosity(
    z: ArrayLike, *, mean: float, std: float, bounds: tuple[float, float] = (0.0, 1.0)
) -> FloatArray:
    """Porosity (fraction) from a standard normal field ``z``: clip(mean + std z, bounds).

    >>> normal_porosity([-10.0, 0.0, 1.0], mean=0.2, std=0.05, bounds=(0.05, 0.4)).tolist()
    [0.05, 0.2, 0.25]
    """
    mean = _number(mean, "porosity mean")
    std = _number(std, "porosity std", nonnegative=True)
    lo, hi = (_number(b, "porosity bounds") for b in bounds)
    if not 0.0 <= lo <= hi <= 1.0:
        raise InputError(f"porosity bounds: expected 0 <= low <= high <= 1, got {bounds!r}")
    return np.clip(mean + std * np.asarray(z, dtype=np.float64), lo, hi)


def lognormal_permeability(z: ArrayLike, *, median: float, sigma: float) -> FloatArray:
    """Lognormal permeability (mD) from a standard normal field ``z``: median exp(sigma z).

    ``median`` (mD) is the geometric mean; ``sigma`` the standard deviation of
    ln K (the arithmetic mean is median exp(sigma^2 / 2)).

    >>> lognormal_permeability([0.0, 1.0], median=100.0, sigma=math.log(10.0)).round(9).tolist()
    [100.0, 1000.0]
    """
    median = _number(median, "permeability median (mD)", positive=True)
    sigma = _number(sigma, "permeability sigma (of ln K)", nonnegative=True)
    return median * exp(sigma * np.asarray(z, dtype=np.float64))


def carman_kozeny(poro: ArrayLike, *, grain_diameter: float = 10e-6, tortuosity: float = 0.81) -> FloatArray:
    """Permeability (mD) from porosity by the Carman-Kozeny relation used in the MRST book:
    K = phi^3 d^2 / (72 tau (1 - phi)^2), ``grain_diameter`` d = 10 micrometres (m) and
    ``tortuosity`` factor tau = 0.81 (the book's ``0.81*72``); converted from m2 by
    1 mD = 9.869233e-16 m2. Porosity must lie in [0, 1).

    >>> k = carman_kozeny(0.2)
    >>> round(float(k), 1), f"{float(k) * MILLIDARCY:.4g} m2"
    (21.7, '2.143e-14 m2')
    """
    d = _number(grain_diameter, "grain_diameter (m)", positive=True)
    tau = _number(tortuosity, "tortuosity", positive=True)
    phi = np.asarray(poro, dtype=np.float64)
    if np.isnan(phi).any() or (phi < 0).any() or (phi >= 1).any():
        raise InputError("carman_kozeny: porosity must lie in [0, 1)")
    return phi * phi * phi * (d * d) / (72.0 * tau * ((1.0 - phi) * (1.0 - phi))) / MILLIDARCY


def per_layer(layer: ArrayLike, values: float | ArrayLike, *, zones: ArrayLike | None = None) -> FloatArray:
    """Cell values from a constant, one value per layer, or one per zone.

    ``layer`` (nc,): every cell's layer (:func:`layer_index`). ``values``: a
    number, or one per layer, or with ``zones`` (the number of layers of each
    zone, top first) one per zone.

    >>> per_layer([0, 1, 2, 3], [0.1, 0.3], zones=[1, 3]).tolist()
    [0.1, 0.3, 0.3, 0.3]
    """
    lay = np.asarray(layer, dtype=np.int64)
    v = np.asarray(values, dtype=np.float64)
    if not np.isfinite(v).all():
        raise InputError("per_layer: values must be finite")
    if v.ndim == 0:
        return np.full(lay.shape, float(v))
    if v.ndim != 1:
        raise InputError(f"per_layer: values must be a number or a list, got shape {v.shape}")
    if zones is not None:
        zn = np.asarray(zones)
        if zn.ndim != 1 or zn.size != v.size or not np.issubdtype(zn.dtype, np.integer) or (zn < 1).any():
            raise InputError(
                f"per_layer: zones must be one positive layer count per value ({v.size}), got {zones!r}"
            )
        v = np.repeat(v, zn)
    if lay.size and (lay.min() < 0 or lay.max() >= v.size):
        what = "the zones' layers" if zones is not None else "values"
        raise InputError(f"per_layer: layer {int(lay.max())} has no value ({v.size} {what})")
    return v[lay]


@dataclass(frozen=True, eq=False)
class Rock:
    """Rock properties per cell: ``poro`` and ``ntg`` (fractions in [0, 1]), ``permx``,
    ``permy``, ``permz`` (mD, >= 0). Arrays are copied, checked and read-only."""

    poro: FloatArray
    permx: FloatArray
    permy: FloatArray
    permz: FloatArray
    ntg: FloatArray

    def __post_init__(self) -> None:
        n = None
        for name in ("poro", "permx", "permy", "permz", "ntg"):
            arr = np.array(getattr(self, name), dtype=np.float64)
            if arr.ndim != 1:
                raise InputError(f"rock.{name}: expected one value per cell (1-D), got shape {arr.shape}")
            n = arr.size if n is None else n
            if arr.size != n:
                raise InputError(f"rock.{name}: {arr.size} values, expected {n} (as poro)")
            if not np.isfinite(arr).all():
                raise InputError(f"rock.{name}: values must be finite")
            low, high = (0.0, 1.0) if name in ("poro", "ntg") else (0.0, np.inf)
            if arr.size and (arr.min() < low or arr.max() > high):
                raise InputError(f"rock.{name}: values must lie in [{low:g}, {high:g}]")
            arr.flags.writeable = False
            object.__setattr__(self, name, arr)

    @property
    def num_cells(self) -> int:
        return self.poro.size

    def cell_data(self) -> dict[str, FloatArray]:
        """The properties by name, e.g. for ``write_netcdf(..., cell_data=rock.cell_data())``."""
        return {k: getattr(self, k) for k in ("poro", "permx", "permy", "permz", "ntg")}


def make_rock(
    poro: float | ArrayLike,
    permx: float | ArrayLike,
    *,
    permy: float | ArrayLike | None = None,
    permz: float | ArrayLike | None = None,
    kv_kh: float = 0.1,
    ntg: float | ArrayLike = 1.0,
    num_cells: int | None = None,
) -> Rock:
    """A :class:`Rock`; numbers are broadcast to every cell (``num_cells``, or the arrays' length).
    ``permy`` defaults to ``permx``, ``permz`` to ``kv_kh`` times ``permx`` (mD).

    >>> r = make_rock(0.25, [100.0, 200.0])
    >>> r.permz.tolist(), r.ntg.tolist()
    ([10.0, 20.0], [1.0, 1.0])
    """
    kv_kh = _number(kv_kh, "kv_kh", nonnegative=True)
    arrays = [np.asarray(a, dtype=np.float64) for a in (poro, permx, ntg) if a is not None]
    for a in (permy, permz):
        if a is not None:
            arrays.append(np.asarray(a, dtype=np.float64))
    sizes = {a.size for a in arrays if a.ndim > 0}
    if num_cells is not None:
        sizes.add(int(num_cells))
    if len(sizes) > 1:
        raise InputError(f"make_rock: the properties have different lengths {sorted(sizes)}")
    n = sizes.pop() if sizes else 1

    def full(a: Any) -> FloatArray:
        return np.broadcast_to(np.asarray(a, dtype=np.float64), (n,)).copy()

    kx = full(permx)
    ky = kx.copy() if permy is None else full(permy)
    kz = kv_kh * kx if permz is None else full(permz)
    return Rock(full(poro), kx, ky, kz, full(ntg))


# --------------------------------------------------------------------------- property cubes


@dataclass(frozen=True, eq=False)
class PropertyCube:
    """Properties on a regular grid of cells: centres ``x`` (nx,), ``y`` (ny,), ``z`` (nz,)
    (m, increasing; z is depth) and ``values``: name -> (nz, ny, nx) array."""

    x: FloatArray
    y: FloatArray
    z: FloatArray
    values: Mapping[str, FloatArray] = field(default_factory=dict)
    source: str = ""

    def __post_init__(self) -> None:
        label = self.source or "property cube"
        axes = []
        for key in ("x", "y", "z"):
            a = np.array(getattr(self, key), dtype=np.float64)
            if a.ndim != 1 or a.size < 1 or not np.isfinite(a).all():
                raise InputError(f"{label}: coordinate {key} must be a finite 1-D axis")
            if a.size > 1:
                d = np.diff(a)
                inc = (a[-1] - a[0]) / (a.size - 1)
                if not (d > 0).all() or np.abs(d - inc).max() > 1e-6 * inc:
                    raise InputError(f"{label}: coordinate {key} must be increasing and regularly spaced")
            a.flags.writeable = False
            object.__setattr__(self, key, a)
            axes.append(a.size)
        shape = (axes[2], axes[1], axes[0])
        vals = {}
        for name, v in dict(self.values).items():
            arr = np.array(v, dtype=np.float64)
            if arr.shape != shape:
                raise InputError(f"{label}: '{name}' has shape {arr.shape}, expected (nz, ny, nx) = {shape}")
            arr.flags.writeable = False
            vals[str(name)] = arr
        if not vals:
            raise InputError(f"{label}: no property values")
        object.__setattr__(self, "values", vals)


def _spacing(a: FloatArray) -> float:
    return float((a[-1] - a[0]) / (a.size - 1)) if a.size > 1 else 1.0


def sample_cube(
    cube: PropertyCube,
    where: Depositional | ArrayLike,
    *,
    names: Sequence[str] | None = None,
    outside: str = "clip",
) -> dict[str, FloatArray]:
    """Values of the cube's cells at every position, by index (piecewise constant).

    ``where``: points (n, 3) (m, z depth; e.g. physical cell centroids): the
    cube cell containing each point; or :class:`Depositional` coordinates:
    (x_r, y_r) as points, and the layer's w normalised by the reference
    column's thickness onto the cube's depth range, k_cube = floor(w / W nz),
    so the cube's layers follow the grid's layers through every fault.
    ``outside``: ``"clip"`` (the nearest cell of the cube) or ``"nan"``.

    >>> cube = PropertyCube([5.0, 15.0], [5.0], [1.0, 3.0], {"poro": [[[0.1, 0.2]], [[0.3, 0.4]]]})
    >>> sample_cube(cube, [[4.0, 5.0, 2.5], [14.0, 5.0, 0.1]])["poro"].tolist()
    [0.3, 0.2]
    """
    if outside not in ("clip", "nan"):
        raise InputError(f"sample_cube: outside must be 'clip' or 'nan', got {outside!r}")
    chosen = list(cube.values) if names is None else list(names)
    missing = [n for n in chosen if n not in cube.values]
    if missing:
        raise InputError(
            f"sample_cube: no property {missing[0]!r} in the cube (has {', '.join(cube.values)})"
        )
    nz, ny, nx = len(cube.z), len(cube.y), len(cube.x)

    def index(coord: FloatArray, axis: FloatArray) -> tuple[IntArray, np.ndarray]:
        h = _spacing(axis)
        i = np.floor((coord - (axis[0] - h / 2)) / h)
        out = (i < 0) | (i > axis.size - 1)
        return np.clip(i, 0, axis.size - 1).astype(np.int64), out

    if isinstance(where, Depositional):
        xy = where.column_xy[where.column]
        i, out_i = index(xy[:, 0], cube.x)
        j, out_j = index(xy[:, 1], cube.y)
        frac = where.layer_w[where.layer] / where.w_edges[-1]
        k = np.minimum(np.floor(frac * nz).astype(np.int64), nz - 1)
        out = out_i | out_j
    else:
        pts = np.asarray(where, dtype=np.float64)
        if pts.ndim != 2 or pts.shape[1] != 3 or not np.isfinite(pts).all():
            raise InputError(f"sample_cube: positions must be a finite (n, 3) array, got shape {pts.shape}")
        i, out_i = index(pts[:, 0], cube.x)
        j, out_j = index(pts[:, 1], cube.y)
        k, out_k = index(pts[:, 2], cube.z)
        out = out_i | out_j | out_k
    flat = (k * ny + j) * nx + i
    result = {}
    for name in chosen:
        v = cube.values[name].ravel()[flat]
        if outside == "nan":
            v = np.where(out, np.nan, v)
        result[name] = v
    return result


def read_property_cube(path: str | os.PathLike, variables: Sequence[str] | None = None) -> PropertyCube:
    """A :class:`PropertyCube` from netCDF: 3-D variables over (z, y, x) (x last) with regular 1-D
    coordinate variables of cell centres (m). A vertical coordinate with ``positive = "up"`` is
    an elevation and is negated to depth. ``variables``: which (default: every 3-D variable)."""

    p = Path(path)
    ds = load_dataset(p)
    names = [str(k) for k, v in ds.data_vars.items() if v.ndim == 3] if variables is None else list(variables)
    if not names:
        raise InputError(f"{p}: no 3-D variable (z, y, x) in the file")
    dims = None
    for name in names:
        if name not in ds.data_vars:
            raise InputError(f"{p}: no variable '{name}' (has {', '.join(map(str, ds.data_vars))})")
        if ds[name].ndim != 3:
            raise InputError(f"{p}: '{name}' must be 3-D (z, y, x), has dims {ds[name].dims}")
        if dims is None:
            dims = ds[name].dims
        elif ds[name].dims != dims:
            raise InputError(f"{p}: '{name}' has dims {ds[name].dims}, the others {dims}")
    assert dims is not None
    axes = {}
    for dim in dims:
        if dim not in ds.variables:
            raise InputError(f"{p}: dimension '{dim}' has no coordinate variable")
        axes[dim] = np.asarray(ds[dim].values, dtype=np.float64)
    zdim, ydim, xdim = dims
    flips = []
    zc = axes[zdim]
    if str(ds[zdim].attrs.get("positive", "down")).lower() == "up":
        zc = -zc
    x, y = axes[xdim], axes[ydim]
    values = {}
    for name in names:
        v = np.asarray(ds[name].values, dtype=np.float64)
        for axis, a in ((0, zc), (1, y), (2, x)):
            if a.size > 1 and a[1] < a[0]:
                v = np.flip(v, axis=axis)
        values[name] = v
    for a in (zc, y, x):
        flips.append(a[::-1] if a.size > 1 and a[1] < a[0] else a)
    zc, y, x = flips
    return PropertyCube(x, y, zc, values, source=str(p))


def write_property_cube(
    path: str | os.PathLike, cube: PropertyCube, attrs: Mapping[str, Any] | None = None
) -> Path:
    """Write a :class:`PropertyCube` as netCDF-4 (z, y, x), atomically."""
    import xarray as xr

    coords = {
        "z": ("z", cube.z, {"units": "m", "positive": "down", "long_name": "depth of the cell centres"}),
        "y": ("y", cube.y, {"units": "m", "standard_name": "projection_y_coordinate"}),
        "x": ("x", cube.x, {"units": "m", "standard_name": "projection_x_coordinate"}),
    }
    data = {name: (("z", "y", "x"), v) for name, v in cube.values.items()}
    ds = xr.Dataset(data, coords=coords, attrs={"title": "gridlib property cube", **dict(attrs or {})})
    return save_dataset(path, ds)
