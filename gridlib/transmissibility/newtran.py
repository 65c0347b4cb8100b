"""ECLIPSE's corner-point transmissibilities (NEWTRAN) as OPM Flow computes them.

For a face between cells i and j of a processed corner-point grid:

* the centre of a cell is the plain mean of its 8 corners (from COORD and ZCORN), the
  same point for every direction;
* the centre of a cell's face is the mean of the 4 corners of its own *logical* face
  (W/E/S/N/T/B), even across a fault, where it is not the centre of the overlap;
* the area vector A is that of the actual face polygon (the overlap on faults),
  ½ sum p_k x p_k+1 over its nodes, used by both halves; between two cells of one
  column it is the upper cell's bottom quad of 4 corners (the processed grid may
  hold extra nodes there, where fault faces cross its edges, which Flow's does not);
* T_i = K_i |A . d_i| / (d_i . d_i), d_i from the cell centre to its face centre and
  K_i its PERMX, PERMY or PERMZ by the face's logical axis (diagonal only); NTG
  multiplies the I and J halves; T = 1 / (1/T_i + 1/T_j), 0 if a half is below
  1e-30 m3.

Lengths are in the deck's unit, permeability in mD; the result is converted to the
deck's transmissibility unit (:mod:`gridlib.units`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import partial

import numpy as np

from ..cornerpoint.corners import corner_points, depth_sign
from ..cornerpoint.deck import Deck
from ..geometry import cross
from ..grid import B, E, FloatArray, Grid, IntArray, N, S, T, W
from ..threads import concurrently, in_order
from ..units import MILLIDARCY, UnitSystem
from .pinch import minpv_connections

# Corners (a + 2b + 4c) of each logical face W, E, S, N, T, B (grid.W..grid.B)
FACE_CORNERS = np.array([[0, 2, 4, 6], [1, 3, 5, 7], [0, 1, 4, 5], [2, 3, 6, 7], [0, 1, 2, 3], [4, 5, 6, 7]])
# Each face's area vector is ½ (p[q0] - p[q1]) x (p[q2] - p[q3]) for its row q here: its two
# diagonals, taken so that the two cells of a matching face compute the same bits.
AREA_DIAGONALS = np.array(
    [[0, 6, 2, 4], [1, 7, 3, 5], [0, 5, 4, 1], [2, 7, 6, 3], [0, 3, 1, 2], [4, 7, 5, 6]]
)
HALF_MINIMUM = 1e-30  # m3: below this a half-transmissibility makes the connection 0 (Flow)
_BLOCK = 1 << 16  # faces per block of vector_areas
_LAYER_TASKS = 4  # blocks of layers of structured_halves, shared out among the threads
_CELL_BLOCK = 1 << 13  # cells of a layer worked on at once by structured_halves (the cache)
_FACE_BLOCK = 1 << 16  # faces sorted out at once by _sorted_faces (temporaries of about 0.5 MB)
_FACE_THREADS = 2  # at most: _sorted_faces runs beside structured_halves
_BOUNDED = 1e150  # coordinates at most this big: differences and their products are finite
_AXIS_OF_FACE = np.array([0, 0, 1, 1, 2, 2])  # W, E -> x; S, N -> y; T, B -> z


def quad_vector_area(p0: FloatArray, p1: FloatArray, p2: FloatArray, p3: FloatArray) -> FloatArray:
    """½ (p0 - p2) x (p1 - p3): the area vector of the quad p0 p1 p2 p3 (rows), planar or not."""
    return 0.5 * cross((p0 - p2).T, (p1 - p3).T).T


def vector_areas(grid: Grid, faces: IntArray) -> FloatArray:
    """½ sum p_k x p_k+1 over the node cycle of each of ``faces``: (m, 3) area vectors.

    Quadrilaterals (most faces) by the cross product of their diagonals, in blocks; the
    other polygons by the sum over their edges, relative to their first node (translation
    invariant, as the diagonals are)."""
    pos = grid.faces.node_pos
    counts = pos[faces + 1] - pos[faces]
    out = np.empty((faces.size, 3))
    quad = np.flatnonzero(counts == 4)
    coords = grid.nodes.coords
    for s in range(0, quad.size, _BLOCK):
        rows = quad[s : s + _BLOCK]
        nodes = grid.faces.nodes[pos[faces[rows]][:, None] + np.arange(4)]
        p = coords[nodes]  # (m, 4, 3)
        out[rows] = quad_vector_area(p[:, 0], p[:, 1], p[:, 2], p[:, 3])
    other = np.flatnonzero(counts != 4)
    if other.size:
        f, cnt = faces[other], counts[other]
        owner = np.repeat(np.arange(other.size), cnt)
        idx = np.arange(int(cnt.sum())) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        start = np.repeat(pos[f], cnt)
        # relative to each polygon's first node: in map coordinates (x ~ 5e5 m) the sum of the
        # edges' cross products cancels to a sliver's area, and rounding left 2e-6 of it
        origin = coords[grid.faces.nodes[start]]
        p = coords[grid.faces.nodes[start + idx]] - origin
        q = coords[grid.faces.nodes[start + (idx + 1) % np.repeat(cnt, cnt)]] - origin
        c = cross(p.T, q.T)  # (3, entries)
        out[other] = np.stack([np.bincount(owner, c[k], other.size) for k in range(3)], axis=1) * 0.5
    return out


def logical_sides(ga: IntArray, gb: IntArray, dims: tuple[int, int, int]) -> tuple[np.ndarray, np.ndarray]:
    """The logical side W, E, S, N, T, B on which cells ga see their face with cells gb
    (linear ijk indices), and the side gb sees it on. Read off the two cells' (i, j)
    columns: every face of a corner-point grid lies on a pillar pair (cells of columns i and
    i + 1, or j and j + 1: E/W or N/S sides) or between two cells of one column (the upper
    cell's B, the lower's T)."""
    nx, ny, _ = dims
    di = gb % nx - ga % nx
    dj = (gb // nx) % ny - (ga // nx) % ny
    below = gb // (nx * ny) > ga // (nx * ny)  # in one column: b under a
    ta = np.select([di > 0, di < 0, dj > 0, dj < 0, below], [E, W, N, S, B], T)
    tb = ta ^ 1  # the opposite side: W <-> E, S <-> N, T <-> B
    return ta.astype(np.int8), tb.astype(np.int8)


def half_transmissibilities(area: FloatArray, d: FloatArray, kdd: FloatArray) -> FloatArray:
    """K |A . d| / (d . d) per connection, from component-major area vectors and d (3, n)
    and K / (d . d) (n,) (:func:`centre_to_faces`)."""
    dot = area[0] * d[0]
    dot += area[1] * d[1]
    dot += area[2] * d[2]
    np.abs(dot, out=dot)
    dot *= kdd
    return dot


def combine(ta: FloatArray, tb: FloatArray, units: UnitSystem) -> FloatArray:
    """The harmonic combination of two halves (mD x deck length), in the deck's unit;
    0 where a half is below ``HALF_MINIMUM`` m3."""
    si = MILLIDARCY * units.length
    floor = HALF_MINIMUM / si
    small = ta < floor
    small |= tb < floor
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        t = ta * tb
        t /= ta + tb
    t[small] = 0.0
    t *= si / units.transmissibility
    return t


# -------------------------------------------------------------------------- every cell at once


def structured_halves(
    deck: Deck, perm: Sequence[FloatArray], ntg: FloatArray, sign: int | None = None
) -> list[FloatArray]:
    """The half-transmissibility K |A . d| / (d . d) (mD x deck length) of every logical
    face W, E, S, N, T, B (six arrays, of a few MB each rather than one) of every cell of
    the deck (linear ijk order),
    with A the area vector of the cell's own quadrilateral face (:data:`AREA_DIAGONALS`):
    what a connection between two cells needs where their shared face is that whole
    quadrilateral. Computed on the (k, c, j, b, i, a) layout of ZCORN layer by layer,
    without gathers, a block of cells at a time (small enough for the CPU's cache), in
    blocks of layers on the threads; inactive cells get whatever their corners give
    (never used). Where every pillar is vertical (most decks: DX/DY/DZ boxes, vertical
    pillars of corner-point models), the x and y parts of the corners, centres and areas
    are the same in every layer and computed once (:class:`_VerticalColumns`: the same
    operations on the same numbers, so the same bits). ``sign``: the deck's
    :func:`~gridlib.cornerpoint.corners.depth_sign`, if known."""
    nx, ny, nz = deck.cart_dims
    layer = nx * ny
    corners = _LayerCorners(deck, sign)
    columns = _VerticalColumns.of(corners)
    halves = [np.empty(nx * ny * nz) for _ in range(6)]
    block = max(1, min(layer, _CELL_BLOCK))

    def layers(ks: range) -> None:
        p = np.empty((3, 8, layer))
        for k in ks:
            z = corners.depths(k)
            if columns is None:
                corners.fill(k, p, z)
            for start in range(0, layer, block):
                here = slice(start, min(start + block, layer))
                cells = slice(k * layer + here.start, k * layer + here.stop)
                k_face = _face_permeability([k[cells] for k in perm], ntg[cells])
                if columns is not None:
                    columns.halves(z[:, :, here], here, k_face, [h[cells] for h in halves])
                    continue
                d, kdd = centre_to_faces(p[:, :, here], k_face)
                for f in range(6):
                    halves[f][cells] = half_transmissibilities(face_area(p[:, :, here], f), d[:, f], kdd[f])

    chunks = [c for c in np.array_split(np.arange(nz), min(nz, _LAYER_TASKS)) if c.size]
    concurrently(*(lambda ks=range(c[0], c[-1] + 1): layers(ks) for c in chunks))
    return halves


class _LayerCorners:
    """The corner coordinates of the cells of one layer at a time, (3, 8 corners, nx ny) in
    the frame of :func:`~gridlib.cornerpoint.corners.corner_points` (the same bits)."""

    def __init__(self, deck: Deck, sign: int | None = None) -> None:
        self.nx, self.ny, _ = deck.cart_dims
        self.sign = depth_sign(deck) if sign is None else sign
        self.zcorn = deck.zcorn_array()
        pil = deck.pillars()  # (ny+1, nx+1, 2, 3)
        nx, ny = self.nx, self.ny

        def corner_columns(end: int, comp: int) -> FloatArray:  # (4 corners a + 2b, layer)
            return np.stack([pil[b : b + ny, a : a + nx, end, comp].ravel() for b in (0, 1) for a in (0, 1)])

        self.top = [corner_columns(0, c) for c in range(3)]
        bot = [corner_columns(1, c) for c in range(3)]
        span = bot[2] - self.top[2]
        self.flat = span == 0.0
        self.span = np.where(self.flat, 1.0, span)
        self.dxy = [bot[0] - self.top[0], bot[1] - self.top[1]]

    def depths(self, k: int) -> FloatArray:
        """(2 top/bottom, 4 corners a + 2b, nx ny): the ZCORN depths of layer k's corners."""
        nx, ny = self.nx, self.ny
        z = self.zcorn[2 * k : 2 * k + 2].reshape(2, ny, 2, nx, 2)
        return z.transpose(0, 2, 4, 1, 3).reshape(2, 4, -1)

    def fill(self, k: int, p: FloatArray, z: FloatArray | None = None) -> None:
        z = self.depths(k) if z is None else z
        top = self.top
        with np.errstate(invalid="ignore", over="ignore"):
            for c in (0, 1):  # top, bottom corners: slots 4 c + (a + 2b)
                t = np.where(self.flat, 0.0, (z[c] - top[2]) / self.span)
                rows = slice(4 * c, 4 * c + 4)
                np.multiply(t, self.dxy[0], out=p[0, rows])
                p[0, rows] += top[0]
                np.multiply(t, self.dxy[1], out=p[1, rows])
                p[1, rows] += top[1]
                np.multiply(z[c], self.sign, out=p[2, rows])


@dataclass(frozen=True, eq=False)
class _VerticalColumns:
    """What :func:`structured_halves` needs of the x and y coordinates where every pillar
    is vertical: per column (nx ny), for each logical face f, the x, y parts of d (from the
    cell centre to the face centre), d_x² + d_y², the x, y parts of the face's diagonals
    u, v (:data:`AREA_DIAGONALS`) and its area's z part ½ (u_x v_y - u_y v_x).

    :class:`_LayerCorners` puts a corner at x = t (x_bottom - x_top) + x_top, which is x_top
    exactly when the pillar is vertical, t finite (|span| >= 1 or a flat pillar, finite
    depths) and x_top not -0; each quantity below is then computed by the very operations
    of :func:`centre_to_faces` and :func:`face_area` on the same numbers.

    ``vanishing[f]``: which of the three terms A_x d_x, A_y d_y, A_z d_z of face f's A . d are
    0 in every column whatever the depths (a factor exactly 0 in every column: d_x, or both
    u_y and v_y for A_x = ½ (u_y v_z - u_z v_y), ...; on a rectilinear grid, all but one
    term of each face). Where the coordinates are at most ``_BOUNDED`` in magnitude, every
    other factor is finite, so such a term is ±0 and adds nothing: :meth:`halves` leaves it
    out, and A . d is the same up to the sign of a zero, which its absolute value drops."""

    sign: int
    d_xy: FloatArray  # (2, 6, m)
    dd_xy: FloatArray  # (6, m)
    uv_xy: FloatArray  # (6, 4, m): u_x, u_y, v_x, v_y
    area_z: FloatArray  # (6, m)
    vanishing: tuple[tuple[bool, bool, bool], ...]  # (6 faces, x y z terms)

    @classmethod
    def of(cls, corners: _LayerCorners) -> _VerticalColumns | None:
        top_xy = np.stack(corners.top[:2])  # (2, 4, m)
        negative_zero = (top_xy == 0.0) & np.signbit(top_xy)
        vertical = (corners.dxy[0] == 0.0).all() and (corners.dxy[1] == 0.0).all()
        finite_t = (corners.flat | (np.abs(corners.span) >= 1.0)).all()
        if not (vertical and finite_t) or negative_zero.any():
            return None
        p = np.concatenate([top_xy, top_xy], axis=1)  # (2, 8, m): top and bottom corners alike
        d, _ = centre_to_faces(np.concatenate([p, np.zeros_like(p[:1])]), np.zeros((6, p.shape[2])))
        d_xy = np.ascontiguousarray(d[:2])
        dd_xy = d_xy[0] * d_xy[0]
        dd_xy += d_xy[1] * d_xy[1]
        a, b, c, e = AREA_DIAGONALS.T
        uv_xy = np.stack([p[0, a] - p[0, b], p[1, a] - p[1, b], p[0, c] - p[0, e], p[1, c] - p[1, e]], axis=1)
        area_z = 0.5 * (uv_xy[:, 0] * uv_xy[:, 3] - uv_xy[:, 1] * uv_xy[:, 2])
        bounded = bool(np.abs(top_xy).max(initial=0.0) <= _BOUNDED)
        vanishing = tuple(
            (
                bounded and bool((d_xy[0, f] == 0.0).all() or ((uv[1] == 0.0) & (uv[3] == 0.0)).all()),
                bounded and bool((d_xy[1, f] == 0.0).all() or ((uv[0] == 0.0) & (uv[2] == 0.0)).all()),
                bounded and bool((area_z[f] == 0.0).all()),
            )
            for f, uv in enumerate(uv_xy)
        )
        return cls(corners.sign, d_xy, dd_xy, uv_xy, area_z, vanishing)

    def halves(self, z: FloatArray, here: slice, k_face: FloatArray, out: Sequence[FloatArray]) -> None:
        """The six halves (6, m) of the cells ``here`` of a layer with corner depths z
        (2, 4, m) into ``out``: :func:`centre_to_faces`, :func:`face_area` and
        :func:`half_transmissibilities` on the z parts only."""
        pz = np.multiply(z.reshape(8, -1), self.sign)  # corner slots 4 c + (a + 2b)
        centre = pz[0].copy()
        for c in range(1, 8):
            centre += pz[c]
        centre /= 8.0
        d_z = np.empty((6, pz.shape[1]))
        for f, (a, b, c, e) in enumerate(FACE_CORNERS):
            v = d_z[f]
            np.add(pz[a], pz[b], out=v)
            v += pz[c]
            v += pz[e]
            v /= 4.0
            v -= centre
        dd = d_z * d_z
        dd += self.dd_xy[:, here]
        kdd = np.empty_like(dd)
        with np.errstate(divide="ignore", invalid="ignore"):
            np.divide(k_face, dd, out=kdd)
        kdd[~(dd > 0.0)] = 0.0
        d_x, d_y = self.d_xy[0, :, here], self.d_xy[1, :, here]
        uv = self.uv_xy[:, :, here]
        bounded = pz.max(initial=0.0) <= _BOUNDED and pz.min(initial=0.0) >= -_BOUNDED  # NaN: not
        for f, (a, b, c, e) in enumerate(AREA_DIAGONALS):
            zero_x, zero_y, zero_z = self.vanishing[f] if bounded else (False, False, False)
            dot = out[f]
            terms = 0  # terms added to dot so far
            if not (zero_x and zero_y):
                u_z, v_z = pz[a] - pz[b], pz[c] - pz[e]
                u_x, u_y, v_x, v_y = uv[f]
            if not zero_x:
                area_x = u_y * v_z
                area_x -= u_z * v_y
                area_x *= 0.5
                np.multiply(area_x, d_x[f], out=dot)
                terms += 1
            if not zero_y:
                area_y = u_z * v_x
                area_y -= u_x * v_z
                area_y *= 0.5
                area_y *= d_y[f]
                terms += _add_term(dot, area_y, terms)
            if not zero_z:
                terms += _add_term(dot, self.area_z[f, here] * d_z[f], terms)
            if not terms:
                dot[...] = 0.0
            np.abs(dot, out=dot)
            dot *= kdd[f]


def _add_term(dot: FloatArray, term: FloatArray, terms: int) -> int:
    """dot += term, or dot = term when it holds no term yet: 1 (a term added)."""
    if terms:
        dot += term
    else:
        dot[...] = term
    return 1


def _face_permeability(perm: Sequence[FloatArray], ntg: FloatArray) -> FloatArray:
    """(6, nc): the permeability each logical face's half uses, from PERMX, PERMY, PERMZ
    (``perm``) and NTG (on W, E, S, N)."""
    k_face = np.empty((6, ntg.size))
    for f, axis in enumerate(_AXIS_OF_FACE):
        if f < 4:
            np.multiply(perm[axis], ntg, out=k_face[f])
        else:
            k_face[f] = perm[axis]
    return k_face


def centre_to_faces(p: FloatArray, k_face: FloatArray) -> tuple[FloatArray, FloatArray]:
    """d (3, 6, m) from the centre of each cell with corners p (3, 8, m) to the centres of
    its faces W, E, S, N, T, B, and K / (d . d) (6, m) (0 where d . d is not positive)."""
    centre = p[:, 0].copy()
    for c in range(1, 8):
        centre += p[:, c]
    centre /= 8.0
    d = np.empty((3, 6, p.shape[2]))
    for f, (a, b, c, e) in enumerate(FACE_CORNERS):
        v = d[:, f]
        np.add(p[:, a], p[:, b], out=v)
        v += p[:, c]
        v += p[:, e]
        v /= 4.0
        v -= centre
    dd = d[0] * d[0]
    dd += d[1] * d[1]
    dd += d[2] * d[2]
    kdd = np.empty_like(dd)
    with np.errstate(divide="ignore", invalid="ignore"):
        np.divide(k_face, dd, out=kdd)
    kdd[~(dd > 0.0)] = 0.0
    return d, kdd


def face_area(p: FloatArray, f: int) -> FloatArray:
    """The area vector (3, m) of logical face f of cells with corners p (3, 8, m):
    ½ of the cross product of its diagonals (:data:`AREA_DIAGONALS`)."""
    a, b, c, e = AREA_DIAGONALS[f]
    return 0.5 * cross(p[:, a] - p[:, b], p[:, c] - p[:, e])


def gathered_half_data(
    deck: Deck, cells: IntArray, perm: Sequence[FloatArray], ntg: FloatArray, sign: int | None = None
):
    """For ``cells`` (linear ijk indices): d (3, 6, m), K / (d . d) (6, m) and the area
    vector of the bottom face (3, m), from their corners gathered one by one
    (:func:`~gridlib.cornerpoint.corners.corner_points`: the same bits as the layers of
    :func:`structured_halves`)."""
    p = np.ascontiguousarray(corner_points(deck, cells, sign).transpose(2, 1, 0))
    k_face = _face_permeability([k[cells] for k in perm], ntg[cells])
    d, kdd = centre_to_faces(p, k_face)
    return d, kdd, face_area(p, B)


@dataclass(frozen=True, eq=False)
class RawConnections:
    """Connections before multipliers: grid cells a, b; their logical face tags ta, tb (the
    side of the connection each is on); the face (-1 for none); whether the two cells are
    one above the other (``column``); the NEWTRAN transmissibility in deck units; the linear
    ijk indices ga, gb of a, b. One part of the connection list (:func:`newtran_connections`)."""

    a: IntArray
    b: IntArray
    ta: IntArray
    tb: IntArray
    face: IntArray
    column: np.ndarray
    trans: FloatArray
    ga: IntArray
    gb: IntArray

    def cells(self, rows: slice = slice(None)) -> tuple[IntArray, IntArray]:
        return self.a[rows], self.b[rows]


@dataclass(frozen=True, eq=False)
class NeighbourPairs:
    """Connections between cells g (``lower``: linear ijk indices, ascending) and their +axis
    neighbours g + stride whose shared corners coincide: their face, their NEWTRAN
    transmissibility in deck units. The lower cell is on its side 2 axis + 1 (E, N, B), the
    other on 2 axis (W, S, T); ``cell_of`` gives the grid cell of each linear index. One part
    of the connection list (:func:`newtran_connections`), without cell-sized copies."""

    axis: int
    stride: int
    lower: IntArray
    face: IntArray
    trans: FloatArray
    cell_of: IntArray

    def cells(self, rows: slice = slice(None)) -> tuple[IntArray, IntArray]:
        g = self.lower[rows]
        return self.cell_of[g], self.cell_of[g + self.stride]


def newtran_connections(
    deck: Deck,
    grid: Grid,
    perm: Sequence[FloatArray],
    ntg: FloatArray,
    units: UnitSystem,
    pinch_active: bool,
    notes: list[str],
) -> list[NeighbourPairs | RawConnections]:
    """Every connection of a processed deck with its NEWTRAN transmissibility (no multipliers),
    in parts: the matching +i, +j and +k neighbour pairs (each in ascending order of the
    lower cell), the pairs from the grid's other faces, then the MINPV connections if any.

    Pairs of logical neighbours whose shared corners coincide (the full quadrilateral is
    their face: most of any deck) are computed from the per-cell data alone; the rest
    (fault faces, faces between cells of a column that do not quite match, connections
    across removed layers) from the grid's faces. Connections across zero-thickness
    layers are kept only with PINCH; MINPV connections are added (:mod:`.pinch`)."""
    nx, ny, _ = deck.cart_dims
    layer = nx * ny
    nc = deck.num_cells
    glob = grid.cells.index_map
    cell_of = np.full(nc, -1, dtype=np.int64)
    cell_of[glob] = np.arange(glob.size)
    strides = (1, nx, layer)

    in_grid = cell_of >= 0
    sign, *simple = concurrently(
        lambda: depth_sign(deck),
        *(lambda axis=axis: _matched(deck, in_grid, axis).ravel() for axis in range(3)),
    )
    halves, (faces_of, (f, a, b, ga, gb)) = concurrently(  # independent: side by side on the threads
        lambda: structured_halves(deck, perm, ntg, sign),
        partial(_sorted_faces, grid, simple, strides),
    )

    def simple_pairs(axis: int, halves: list[FloatArray], faces: tuple[IntArray, IntArray]):
        """The pairs of cells and their +axis neighbours whose shared corners coincide: each
        half from its own cell's face (the same quadrilateral, the same bits)."""
        stride = strides[axis]
        g = np.flatnonzero(simple[axis])
        t = combine(halves[2 * axis + 1][g], halves[2 * axis][g + stride], units)  # E|W, N|S, B|T
        return NeighbourPairs(axis, stride, g, _faces_of_pairs(g, *faces), t, cell_of)

    ta, tb = logical_sides(ga, gb, deck.cart_dims)
    column = (ta >= T) & (tb >= T)
    across = column & (np.abs(gb - ga) > layer)  # across collapsed cells (PINCH)
    if across.any() and not pinch_active:
        keep = ~across
        f, a, ta, b, tb, ga, gb, column = (x[keep] for x in (f, a, ta, b, tb, ga, gb, column))
        notes.append(f"{int(across.sum())} connections across zero-thickness layers left out (no PINCH)")

    def other_pairs(f, a, ta, b, tb, column):
        """Fault faces, near-matching column faces, PINCH and MINPV connections: T from the
        grid's face polygons (or the upper cell's bottom quad between cells of a column)."""
        ga, gb = glob[a], glob[b]
        involved = np.unique(np.concatenate([ga, gb]))
        d, kdd, bottom = gathered_half_data(deck, involved, perm, ntg, sign)
        ia, ib = np.searchsorted(involved, ga), np.searchsorted(involved, gb)
        area = np.empty((3, f.size))
        lateral = np.flatnonzero(~column)
        area[:, lateral] = vector_areas(grid, f[lateral]).T
        vertical = np.flatnonzero(column)
        area[:, vertical] = bottom[:, np.where(ta == B, ia, ib)[vertical]]  # the upper cell's bottom
        t = combine(
            half_transmissibilities(area, d[:, ta, ia], kdd[ta, ia]),
            half_transmissibilities(area, d[:, tb, ib], kdd[tb, ib]),
            units,
        )
        return RawConnections(a, b, ta, tb, f, column, t, ga, gb)

    tasks = [partial(simple_pairs, axis, halves, faces_of[axis]) for axis in range(3)]
    tasks.append(partial(other_pairs, f, a, ta, b, tb, column))
    del halves, faces_of, f, a, ta, b, tb, ga, gb, column  # the tasks hold what they need
    parts = concurrently(*tasks)
    del tasks
    up, low = _minpv_pairs(deck, cell_of, parts, notes)
    if up.size:
        n = up.size
        parts.append(
            other_pairs(
                np.full(n, -1),
                up,
                np.full(n, B, dtype=np.int8),
                low,
                np.full(n, T, dtype=np.int8),
                np.ones(n, dtype=bool),
            )
        )
    return parts


def _sorted_faces(
    grid: Grid, simple: list[np.ndarray], strides: tuple[int, int, int]
) -> tuple[list[tuple[IntArray, IntArray]], tuple[IntArray, IntArray, IntArray, IntArray, IntArray]]:
    """The interior faces of ``grid`` sorted out: per axis, the faces joining +axis neighbours
    whose shared corners coincide (``simple[axis]`` of the lower cell), as (lower cells
    ascending, faces); and the other interior faces f with their cells a, b
    (``neighbors[f]``) and those cells' linear ijk indices ga, gb. A block of faces at a
    time, on the threads (small temporaries, each block's results kept in block order)."""
    # a boundary face's missing cell (-1) gets an index no stride away from any cell's
    padded = np.append(grid.cells.index_map, -(1 << 62) // 2)
    blocks = [(s, min(s + _FACE_BLOCK, grid.num_faces)) for s in range(0, grid.num_faces, _FACE_BLOCK)]
    found = list(in_order(partial(_sort_face_block, grid, padded, simple, strides), blocks, _FACE_THREADS))
    faces = []
    for axis in range(3):
        lower, face = (np.concatenate([block[0][axis][k] for block in found]) for k in (0, 1))
        if lower.size > 1 and not (lower[1:] > lower[:-1]).all():  # the engine's order is ascending
            order = np.argsort(lower, kind="stable")
            lower, face = lower[order], face[order]
        faces.append((lower, face))
    rest = tuple(np.concatenate([block[1][k] for block in found]) for k in range(5))
    return faces, rest


def _sort_face_block(
    grid: Grid,
    padded: IntArray,
    simple: list[np.ndarray],
    strides: tuple[int, int, int],
    start: int,
    stop: int,
):
    """:func:`_sorted_faces` of the faces start..stop-1 (``padded``: the grid's index map and
    one far-off index for -1). ``simple[axis]`` is False on the last row along the axis, so
    a lower cell g marked there has g + stride as its +axis neighbour, and the face of the
    two cells is the one on that side."""
    nb = grid.faces.neighbors[start:stop]
    a, b = nb[:, 0], nb[:, 1]
    ga, gb = padded[a], padded[b]
    lo = np.minimum(ga, gb)
    step = gb - ga
    np.abs(step, out=step)
    is_simple = np.zeros(stop - start, dtype=bool)
    found = []
    for axis, stride in enumerate(strides):
        hit = np.flatnonzero(step == stride)
        hit = hit[simple[axis][lo[hit]]]
        is_simple[hit] = True
        found.append((lo[hit], hit + start))
    is_simple |= a < 0
    is_simple |= b < 0  # boundary faces: not among the rest either
    rest = np.flatnonzero(~is_simple)
    return found, (rest + start, a[rest], b[rest], ga[rest], gb[rest])


def _faces_of_pairs(g: IntArray, lower: IntArray, faces: IntArray) -> IntArray:
    """The face of each pair of lower cell ``g`` (ascending) from the ascending ``lower`` cells
    of ``faces`` (the last one of a cell that has several), -1 where ``g`` has none."""
    if lower.size == g.size and (lower.size < 2 or (lower[1:] > lower[:-1]).all()):
        return faces  # one face per pair, every pair found (lower is a subset of g): the same cells
    at = np.searchsorted(lower, g, side="right") - 1
    found = at >= 0
    found[found] = lower[at[found]] == g[found]
    return np.where(found, faces[np.maximum(at, 0)] if faces.size else -1, -1)


def _matched(deck: Deck, in_grid: np.ndarray, axis: int) -> np.ndarray:
    """(nz, ny, nx) whether cell (k, j, i) and its +axis neighbour are both in the grid and
    share all four corners of their common face exactly (False on the last row)."""
    nx, ny, nz = deck.cart_dims
    z = deck.zcorn_array().reshape(nz, 2, ny, 2, nx, 2)
    g = in_grid.reshape(nz, ny, nx)
    out = np.zeros((nz, ny, nx), dtype=bool)
    if axis == 0:
        low, high, inner = z[:, :, :, :, :-1, 1], z[:, :, :, :, 1:, 0], (slice(None), slice(None), slice(-1))
        corners = [(c, slice(None), b) for c in (0, 1) for b in (0, 1)]  # (c, j, b, i)
    elif axis == 1:
        low, high, inner = z[:, :, :-1, 1], z[:, :, 1:, 0], (slice(None), slice(-1))
        corners = [(c, slice(None), slice(None), a) for c in (0, 1) for a in (0, 1)]  # (c, j, i, a)
    else:
        low, high, inner = z[:-1, 1], z[1:, 0], (slice(-1),)
        corners = [(slice(None), b, slice(None), a) for b in (0, 1) for a in (0, 1)]  # (j, b, i, a)
    with np.errstate(invalid="ignore"):
        same = out[inner]
        same[...] = g[inner]
        if axis == 0:
            same &= g[:, :, 1:]
        elif axis == 1:
            same &= g[:, 1:]
        else:
            same &= g[1:]
        for corner in corners:  # the four shared corners, one comparison each
            at = (slice(None), *corner)
            same &= low[at] == high[at]
    return out


def _minpv_pairs(deck: Deck, cell_of: IntArray, parts, notes: list[str]):
    """Grid cells (upper, lower) of Flow's MINPV connections not already joined by a face
    (any of the connections in ``parts``)."""
    pairs = minpv_connections(deck)
    if pairs.size == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    n_cells = int(cell_of.max()) + 1
    existing = np.concatenate([np.minimum(*p.cells()) * n_cells + np.maximum(*p.cells()) for p in parts])
    up, low = cell_of[pairs[:, 0]], cell_of[pairs[:, 1]]
    ok = (up >= 0) & (low >= 0)
    key = np.minimum(up, low) * n_cells + np.maximum(up, low)
    if existing.size:  # a column of one cell per layer has no face connections to exclude
        existing.sort()
        at = np.minimum(np.searchsorted(existing, key), existing.size - 1)
        ok &= existing[at] != key
    up, low = up[ok], low[ok]
    if up.size:
        notes.append(f"{up.size} connections across cells removed by MINPV (as OPM Flow makes them)")
    return up, low
