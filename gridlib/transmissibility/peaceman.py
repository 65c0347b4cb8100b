"""Well connection factors (well indices): Peaceman's, as OPM Flow computes them for COMPDAT.

A completion of a well of radius r_w in a cell, with skin S, gets the connection
(transmissibility) factor

    CF = 2 pi K_h L / (ln(r0 / min(r_w, r0)) + S),    K_h = sqrt(k1 k2),

with k1, k2 the permeabilities across the well and L the completed length, in SI
(m3), then in the unit system's connection-factor unit (the transmissibility unit:
METRIC cP m3/(day bar), FIELD cP rb/(day psi), LAB cP cm3/(h atm), PVT-M
cP m3/(day atm); :mod:`gridlib.units`). A well radius above r0 makes the logarithm
0, as in Flow (the factor is then 2 pi K_h L / S); a non-positive denominator
is an error.

**Peaceman's form** (Peaceman 1983, SPE J. 23(3), eq. 21 and 24; OPM's
``WellConnections.cpp``) for a hexahedral cell of extents d1, d2 across the well:

    r0 = 0.28 sqrt(sqrt(k2/k1) d1^2 + sqrt(k1/k2) d2^2) / ((k2/k1)^1/4 + (k1/k2)^1/4).

A vertical ("z") well has (k1, d1) = (kx, dx), (k2, d2) = (ky, dy), L = dz; an
"x" well (ky, dy), (kz, dz), L = dx; a "y" well (kz, dz), (kx, dx), L = dy. NTG
multiplies dz wherever it enters, as Flow does: the length of a vertical well,
one of the extents across an x or y well.

**The PEBI form** for a vertical well in a PEBI (Voronoi) cell of horizontal area A:

    r0 = c sqrt(A) 2 / ((ky/kx)^1/4 + (kx/ky)^1/4),   c = e^-gamma / (sqrt(2) 3^3/4) = 0.174166,

the exact equivalent radius of a cell of a regular hexagonal PEBI lattice (sites
on a triangular lattice, spacing a, two-point flux) for isotropic permeability:
r0 = e^-gamma a / (2 sqrt(3)), from the lattice Green's function of the triangular
lattice, whose two-point resistance grows as (ln r + gamma + ln sqrt(12)) /
(sqrt(3) pi) for unit resistors -- the hexagonal counterpart of Peaceman's (1978)
0.2 dx, exactly e^-gamma / (2 sqrt(2)) dx = 0.19851 dx, on the square lattice.
Anisotropy enters as in Peaceman (1983): in coordinates scaled to isotropy the
area is unchanged and the well becomes an ellipse of mean radius r_w ((ky/kx)^1/4 +
(kx/ky)^1/4) / 2. tests/transmissibility/test_peaceman.py checks c against steady two-point flux
solutions around a well on PEBI grids (regular cells: within 2e-4; a well site that
replaced its nearest lattice site: 0.2 %). Limits, from the same solutions: r0 depends
on the cell's surroundings, not only on its area. A well site squeezed in between
lattice sites (not replacing one) keeps about its lattice neighbours' r0, which the
form underestimates (by 25 % for a cell of half a lattice cell's area); the centre
cell of radial rings needs r0 = 0.28 sqrt(A) (6 sectors, growth e^(2 pi / 6)) down to
0.15 sqrt(A) (32 sectors, growth 1.1), against the form's 0.174 sqrt(A).

**Cell extents.** :func:`deck_cell_extents` gives Flow's for corner-point decks,
from the input corners: dx the horizontal distance between the means of the 4 I-
and the 4 I+ corners, dy likewise in J, dz the mean depth of the 4 bottom corners
minus that of the 4 top ones. :func:`cell_extents` gives them for any grid: for
logically Cartesian grids (``cells.face_tag``) the same construction on the cells'
faces (dx the horizontal distance between the area-weighted centroids of the W and
E faces, dy between S and N, dz the depth difference between B and T), which
equals Flow's for cells with planar faces; for other grids MRST's bounding box
(``cellDims``) of the cell's nodes in x and y, and the mean thickness dz = V / A
(A the horizontal area, half the sum of |n_z| over the cell's faces). 2-D grids
have dz = 1: factors per unit thickness.

Conventions: z is depth (down); lengths (coordinates, extents, radii) in the unit
system's length unit; permeability in mD; off-diagonal permeabilities are ignored.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ..connectivity import ragged_arange
from ..cornerpoint.corners import corner_points
from ..cornerpoint.deck import Deck
from ..errors import InputError
from ..geometry import Geometry
from ..grid import B, E, FloatArray, Grid, IntArray, N, S, T, W
from ..reproducible import log
from ..units import METRIC, UnitSystem, unit_system
from .deck_connections import rock_arrays
from .tpfa import permeability_tensors

TWO_PI = 2.0 * np.pi
PEACEMAN = 0.28  # Peaceman's constant of the rectangular block (Flow's)
PEBI_RADIUS = 0.17416564119876626  # e^-gamma / (sqrt(2) 3^(3/4)): r0 / sqrt(A), regular hexagons
FORMS = ("auto", "peaceman", "pebi")
DIRECTIONS = ("x", "y", "z")
# per direction: (k1, k2, length) axes and (d1, d2, length) extents, extents[2] being dz (Flow's order)
_AXES = {0: (1, 2, 0), 1: (2, 0, 1), 2: (0, 1, 2)}


def well_index(
    grid: Grid,
    geometry: Geometry,
    permeability: ArrayLike | None,
    cells: ArrayLike,
    radius: ArrayLike,
    skin: ArrayLike = 0.0,
    direction: str | ArrayLike = "z",
    *,
    ntg: ArrayLike | None = None,
    extents: ArrayLike | None = None,
    form: str = "auto",
    units: UnitSystem | str = METRIC,
) -> FloatArray:
    """Connection factors of completions in ``cells`` (rows of ``grid``), one per completion.

    ``permeability`` (mD, per cell): see :func:`~gridlib.transmissibility.tpfa.permeability_tensors`
    (the diagonal is used). ``radius`` (well radius, > 0), ``skin`` and ``direction``
    ("x", "y" or "z"): one value, or one per completion. ``ntg`` (nc,) in [0, 1].
    ``extents`` (n, 3): dx, dy, dz per completion (default :func:`cell_extents`; for a deck
    :func:`deck_cell_extents`). ``form``: "peaceman" (the rectangular block), "pebi" (vertical
    wells in PEBI cells, from the cell's horizontal area V / dz), "auto" (pebi for vertical
    wells in grids that are not logically Cartesian, peaceman otherwise). See the module
    docstring for the formulas and their sources. Units: those of ``units`` (a
    :class:`~gridlib.units.UnitSystem` or its name).

    >>> import gridlib as gl
    >>> g = gl.cart_grid([1, 1, 1], [100.0, 100.0, 10.0])
    >>> cf = well_index(g, gl.compute_geometry(g), 100.0, [0], 0.1)
    >>> round(float(cf[0]), 9)  # 2 pi 100 mD 10 m 0.0085270170 / ln(0.14 sqrt(2) 100 m / 0.1 m)
    10.131361493
    """
    rows = completion_cells(cells, grid.num_cells)
    k, ext, net = completion_rock(grid, geometry, permeability, rows, ntg=ntg, extents=extents)
    axis = _directions(direction, rows.size)
    if grid.griddim == 2 and (axis != 2).any():
        raise InputError("direction: a 2-D grid has vertical ('z') completions only")
    if form not in FORMS:
        raise InputError(f"form: expected one of {', '.join(FORMS)}, got {form!r}")
    pebi = np.zeros(rows.size, dtype=bool)
    if form == "pebi" or (form == "auto" and grid.cells.face_tag is None):
        pebi = axis == 2
        if form == "pebi" and not pebi.all():
            raise InputError("direction: the PEBI form is for vertical ('z') completions only")
    area = horizontal_area(geometry, rows, ext, pebi)
    ext[:, 2] *= net
    return connection_factor(k, ext, axis, radius, skin, unit_system(units), pebi=pebi, area=area)


def deck_well_index(
    deck: Deck,
    cells: ArrayLike,
    radius: ArrayLike,
    skin: ArrayLike = 0.0,
    direction: str | ArrayLike = "z",
) -> FloatArray:
    """Connection factors of completions in deck cells (0-based linear indices, i fastest),
    as OPM Flow computes them for COMPDAT without a given factor: PERMX/Y/Z and NTG of the
    deck, extents from :func:`deck_cell_extents`; lengths and factors in the deck's units.
    Inactive cells are errors (Flow skips them with a warning)."""
    glob = _deck_cells(deck, cells)
    perm, ntg = rock_arrays(deck)
    ext = deck_cell_extents(deck, glob)
    ext[:, 2] *= ntg[glob]
    axis = _directions(direction, glob.size)
    return connection_factor(perm[glob], ext, axis, radius, skin, unit_system(deck.units))


def completion_rock(
    grid: Grid,
    geometry: Geometry,
    permeability: ArrayLike | None,
    rows: IntArray,
    *,
    ntg: ArrayLike | None = None,
    extents: ArrayLike | None = None,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The checked inputs of completions in cells ``rows``: diagonal permeability (n, 3) mD
    (kz = 0 in 2-D), extents (n, 3) without NTG (``extents`` or :func:`cell_extents`) and
    the NTG (n,) of each completion's cell (1 without ``ntg``). A fresh ``extents`` array."""
    if permeability is None:
        raise InputError("permeability: required, in mD per cell (one value, (nc,), (nc, d) or tensors)")
    nc, dim = grid.num_cells, grid.griddim
    n = rows.size
    k = permeability_tensors(permeability, nc, dim)
    k = (k if k.ndim == 2 else np.diagonal(k, axis1=1, axis2=2))[rows]
    if dim == 2:
        k = np.column_stack([k, np.zeros(n)])
    if extents is None:
        ext = cell_extents(grid, geometry, rows)
    else:
        ext = np.array(extents, dtype=np.float64)
        if ext.shape != (n, 3) or not np.isfinite(ext).all() or (ext < 0).any():
            raise InputError(
                f"extents: expected finite, non-negative (dx, dy, dz) per completion, shape ({n}, 3)"
            )
    if ntg is None:
        return k, ext, np.ones(n)
    g = np.asarray(ntg, dtype=np.float64)
    if g.shape != (nc,) or not np.isfinite(g).all() or (g < 0).any() or (g > 1).any():
        raise InputError(f"ntg: expected one value in [0, 1] per cell ({nc} cells)")
    return k, ext, g[rows]


def horizontal_area(geometry: Geometry, rows: IntArray, extents: FloatArray, pebi: np.ndarray) -> FloatArray:
    """The horizontal area V / dz of the cells ``rows`` where ``pebi`` (0 elsewhere and where
    dz = 0), for the PEBI form; ``extents`` without NTG."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(pebi & (extents[:, 2] > 0), geometry.cell_volumes[rows] / extents[:, 2], 0.0)


def connection_factor(
    k: FloatArray,
    extents: FloatArray,
    axis: IntArray,
    radius: ArrayLike,
    skin: ArrayLike,
    units: UnitSystem,
    *,
    pebi: np.ndarray | None = None,
    area: FloatArray | None = None,
) -> FloatArray:
    """CF per completion from its cell's diagonal permeability ``k`` (n, 3) mD, ``extents``
    (n, 3) with NTG already on dz, the well's axis (0, 1, 2 for x, y, z), radius and skin;
    PEBI form where ``pebi`` (with the horizontal ``area``). Completions without
    permeability across the well, length or horizontal extent get 0."""
    n = axis.size
    rw = _per_completion(radius, n, "radius")
    if (rw <= 0).any():
        i = int(np.flatnonzero(rw <= 0)[0])
        raise InputError(f"radius: the well radius must be positive, completion {i} has {float(rw[i]):g}")
    s = _per_completion(skin, n, "skin")
    rows = np.arange(n)
    order = np.array([_AXES[a] for a in range(3)])[axis]  # (n, 3): k1, k2, along
    k1, k2 = k[rows, order[:, 0]], k[rows, order[:, 1]]
    d1, d2, length = extents[rows, order[:, 0]], extents[rows, order[:, 1]], extents[rows, order[:, 2]]
    kh = np.sqrt(k1 * k2)
    conducting = (kh > 0) & (length > 0)
    k1, k2 = np.where(conducting, k1, 1.0), np.where(conducting, k2, 1.0)
    ratio = k2 / k1
    inv = k1 / k2
    fourth = np.sqrt(np.sqrt(ratio)) + np.sqrt(np.sqrt(inv))
    r0 = PEACEMAN * np.sqrt(np.sqrt(ratio) * (d1 * d1) + np.sqrt(inv) * (d2 * d2)) / fourth
    if pebi is not None and pebi.any():
        r0 = np.where(pebi, PEBI_RADIUS * np.sqrt(area) * 2.0 / fourth, r0)  # area: (n,) where pebi
    conducting &= r0 > 0  # a cell without horizontal extent: no factor
    with np.errstate(divide="ignore", invalid="ignore"):
        denominator = log(r0 / np.minimum(rw, r0)) + s
    bad = conducting & ~(denominator > 0)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError(
            f"radius, skin: ln(r0 / min(radius, r0)) + skin must be positive (Flow would give an infinite "
            f"or negative factor); completion {i}: r0 {r0[i]:.6g}, radius {rw[i]:.6g}, skin {s[i]:.6g}"
        )
    darcy = units.darcy_constant
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(conducting, TWO_PI * kh * length / denominator, 0.0) * darcy


def deck_cell_extents(deck: Deck, cells: ArrayLike) -> FloatArray:
    """Flow's (dx, dy, dz) of deck cells (0-based linear indices) from their 8 input corners
    (:func:`~gridlib.cornerpoint.corners.corner_points`), in the deck's length unit: dx the
    horizontal distance between the means of the I- and the I+ corners, dy of the J- and J+
    corners, dz the mean depth of the bottom corners minus that of the top ones
    (``EclipseGrid::getCellDims``).

    >>> from gridlib.cornerpoint.generators import simple_grdecl
    >>> deck_cell_extents(simple_grdecl([2, 1, 1], flat=True, undisturbed=True), [0]).tolist()
    [[0.5, 1.0, 0.5]]
    """
    p = corner_points(deck, np.asarray(cells, dtype=np.int64).ravel())
    x, y, z = p[:, :, 0], p[:, :, 1], p[:, :, 2]

    def mean4(v: FloatArray, a: int, b: int, c: int, d: int) -> FloatArray:
        return (((v[:, a] + v[:, b]) + v[:, c]) + v[:, d]) / 4.0

    def horizontal(lo: tuple[int, ...], hi: tuple[int, ...]) -> FloatArray:
        ddx = mean4(x, *hi) - mean4(x, *lo)
        ddy = mean4(y, *hi) - mean4(y, *lo)
        return np.sqrt(ddx * ddx + ddy * ddy)

    dx = horizontal((0, 2, 4, 6), (1, 3, 5, 7))
    dy = horizontal((0, 1, 4, 5), (2, 3, 6, 7))
    dz = mean4(z, 4, 5, 6, 7) - mean4(z, 0, 1, 2, 3)
    return np.column_stack([dx, dy, dz])


def cell_extents(grid: Grid, geometry: Geometry, cells: ArrayLike) -> FloatArray:
    """(dx, dy, dz) of grid cells (rows) for the well factors: from the W/E, S/N and T/B faces'
    centroids in logically Cartesian grids, else the nodes' bounding box in x, y and the mean
    thickness V / A (module docstring); dz = 1 in 2-D."""
    rows = np.asarray(cells, dtype=np.int64).ravel()
    pos = grid.cells.face_pos
    counts = pos[rows + 1] - pos[rows]
    owner = np.repeat(np.arange(rows.size), counts)
    faces = grid.cells.faces[ragged_arange(pos[rows], counts)]
    box = _bounding_box(grid, faces, owner, rows.size)
    if grid.griddim == 2:
        thickness = np.ones(rows.size)
    else:
        nz = np.abs(geometry.face_normals[faces, 2])
        plan = 0.5 * np.bincount(owner, nz, rows.size)
        with np.errstate(divide="ignore", invalid="ignore"):
            thickness = np.where(plan > 0, geometry.cell_volumes[rows] / plan, 0.0)
    ext = np.column_stack([box, thickness])
    if grid.cells.face_tag is None:
        return ext
    centre, found = side_centroids(grid, geometry, rows)
    horizontal = slice(0, 2)
    dx = np.hypot(*(centre[:, E, horizontal] - centre[:, W, horizontal]).T)
    dy = np.hypot(*(centre[:, N, horizontal] - centre[:, S, horizontal]).T)
    dz = centre[:, B, 2] - centre[:, T, 2] if grid.griddim == 3 else np.ones(rows.size)
    logical = np.column_stack([dx, dy, dz])
    return np.where(found[:, None], logical, ext)


def side_centroids(grid: Grid, geometry: Geometry, cells: ArrayLike) -> tuple[FloatArray, np.ndarray]:
    """The centroids (n, 6, dim) of the W, E, S, N, T, B sides (``gridlib.grid`` order) of
    cells (rows) of a logically Cartesian grid (``cells.face_tag``): per side the
    area-weighted mean of its faces' centroids (a side split by a fault is several faces).
    ``found`` (n,): the cell has every side (W..N in 2-D); other rows hold NaN or garbage."""
    if grid.cells.face_tag is None:
        raise ValueError("side_centroids: the grid is not logically Cartesian (no cells.face_tag)")
    rows = np.asarray(cells, dtype=np.int64).ravel()
    pos = grid.cells.face_pos
    counts = pos[rows + 1] - pos[rows]
    owner = np.repeat(np.arange(rows.size), counts)
    half = ragged_arange(pos[rows], counts)
    faces = grid.cells.faces[half]
    bins = owner * 6 + grid.cells.face_tag[half].astype(np.int64)
    area = geometry.face_areas[faces]
    total = np.bincount(bins, area, rows.size * 6).reshape(-1, 6)
    dim = grid.dim
    centre = np.stack(
        [np.bincount(bins, area * geometry.face_centroids[faces, d], rows.size * 6) for d in range(dim)],
        axis=-1,
    ).reshape(-1, 6, dim)
    found = (total > 0).all(axis=1) if grid.griddim == 3 else (total[:, :4] > 0).all(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return centre / total[:, :, None], found


def _bounding_box(grid: Grid, faces: IntArray, owner: IntArray, n: int) -> FloatArray:
    """Extents in x and y (n, 2) of the nodes of each owner's faces."""
    npos = grid.faces.node_pos
    counts = npos[faces + 1] - npos[faces]
    node_owner = np.repeat(owner, counts)
    entries = ragged_arange(npos[faces], counts)
    xy = grid.nodes.coords[grid.faces.nodes[entries], :2]
    lo = np.full((n, 2), np.inf)
    hi = np.full((n, 2), -np.inf)
    np.minimum.at(lo, node_owner, xy)
    np.maximum.at(hi, node_owner, xy)
    return hi - lo


def completion_cells(cells: ArrayLike, num_cells: int) -> IntArray:
    """``cells`` as 0-based int64 rows of a grid of ``num_cells`` cells, checked (InputError)."""
    c = np.asarray(cells)
    if c.ndim > 1 or not (c.size == 0 or np.issubdtype(c.dtype, np.integer)):
        raise InputError(f"cells: expected integer cell indices (rows of the grid), got {c.dtype} {c.shape}")
    c = c.astype(np.int64).ravel()
    bad = (c < 0) | (c >= num_cells)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InputError(
            f"cells: completion {i} is in cell {int(c[i])}, which does not exist (the grid has {num_cells} "
            f"cells, 0-based)"
        )
    return c


def _deck_cells(deck: Deck, cells: ArrayLike) -> IntArray:
    nx, ny, _ = deck.cart_dims
    c = completion_cells(cells, deck.num_cells)
    inactive = ~deck.active[c]
    if inactive.any():
        i = int(np.flatnonzero(inactive)[0])
        g = int(c[i])
        raise InputError(
            f"cells: completion {i} is in inactive cell {g} ({g % nx + 1}, {g // nx % ny + 1}, "
            f"{g // (nx * ny) + 1}) of {deck.source}"
        )
    return c


def _directions(direction: str | ArrayLike, n: int) -> IntArray:
    """0, 1, 2 for "x", "y", "z" (any case), one value or one per completion."""
    d = np.char.lower(np.char.strip(np.asarray(direction, dtype=str).ravel()))
    if d.size == 1:
        d = np.repeat(d, n)
    if d.size != n:
        raise InputError(f"direction: expected one value or one per completion ({n}), got {d.size}")
    axis = np.full(n, -1, dtype=np.int64)
    for a, name in enumerate(DIRECTIONS):
        axis[d == name] = a
    if (axis < 0).any():
        i = int(np.flatnonzero(axis < 0)[0])
        raise InputError(f"direction: completion {i} has {str(d[i])!r}; expected 'x', 'y' or 'z'")
    return axis


def _per_completion(value: ArrayLike, n: int, what: str) -> FloatArray:
    v = np.asarray(value, dtype=np.float64)
    if v.ndim == 0:
        v = np.full(n, float(v))
    if v.shape != (n,):
        raise InputError(f"{what}: expected one value or one per completion ({n}), got shape {v.shape}")
    if not np.isfinite(v).all():
        raise InputError(f"{what}: values must be finite")
    return v.ravel()
