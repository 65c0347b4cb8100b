"""Background sites: hexagonal or Cartesian lattices, graded, with optional Cartesian padding.

Lattices
    ``hexagonal``: a triangular lattice of sites (Voronoi cells are regular
    hexagons of width ``h``, area sqrt(3)/2 h²); ``cartesian``: a square lattice
    (square cells of side ``h``). The lattice is centred in the domain's
    bounding box, so that a rectangle whose sides are multiples of ``h`` gets
    exactly square cells (no half cells along the boundary).
Grading (``cell_size`` a callable h(x, y))
    Nested refinement: the lattice starts at the largest h found on a probe of
    the domain and, level by level, every site of the finest level whose h is
    below its spacing / sqrt(2) adds the midpoints of its lattice edges (and,
    for the square lattice, of its squares' diagonals): the finer lattice
    contains the coarser one, so transitions need no special treatment. The
    final spacing is within a factor sqrt(2) of h everywhere; h should vary
    slowly (|grad h| below about 0.5) for smooth transitions.
Boundary
    Lattice sites outside the domain are dropped, and so are those closer to the
    boundary than ``clearance`` (default 0.25) times their spacing: a site that
    close would make a cell only half as wide as its neighbours (the MRST
    book's "layer of small cells at the boundary"); its neighbours' cells reach
    the boundary instead (at most 1.6 spacings wide).
Padding (``padding=k`` rows, numeric cell size only)
    ``k`` rows of sites parallel to every boundary edge, (i + 1/2) h from it and
    about h apart along it, each kept only where its own edge is the nearest
    part of the boundary (plus fans of sites around reflex corners); the lattice
    keeps away from the boundary by (k + 1/4) h. Rectangles get a frame of
    squares around a hexagonal interior (MRST book Fig. 3.38).

>>> from gridlib.voronoi.domain import Domain, rectangle
>>> d = Domain(rectangle(0, 0, 4, 2))
>>> b = background_sites(d, lambda p: np.full(len(p), 1.0), 1.0, "cartesian", None, 0.25)
>>> (b.xy + d.origin).tolist()[:3], b.xy.shape[0]
([[0.5, 0.5], [1.5, 0.5], [2.5, 0.5]], 8)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely
from scipy.spatial import cKDTree

from ..errors import GridError
from ..planar import cross2
from ..reproducible import arctan2
from .domain import Domain

SQRT3_2 = np.sqrt(3.0) / 2.0
_HEX_NEIGHBOURS = np.array([[1, 0], [-1, 0], [0, 1], [0, -1], [1, -1], [-1, 1]], dtype=np.int64)
_SQUARE_NEIGHBOURS = np.array(
    [[1, 0], [-1, 0], [0, 1], [0, -1], [1, 1], [1, -1], [-1, 1], [-1, -1]], dtype=np.int64
)
MAX_SITES = 20_000_000
LATTICE, FINER, PADDING = 0, 1, 2  # kinds of background sites


def _basis(pattern: str) -> np.ndarray:
    if pattern == "hexagonal":
        return np.array([[1.0, 0.0], [0.5, SQRT3_2]])
    return np.eye(2)


def _lattice(domain: Domain, h: float, pattern: str) -> tuple[np.ndarray, np.ndarray]:
    """Integer coordinates and origin of a lattice of spacing h centred on the bounding box.

    A hexagonal site (i, j) lies at origin + h (i + j/2, j sqrt(3)/2); rows are
    generated as columns c = i + floor(j/2), so row j spans the box at x = c + (j mod 2)/2.
    """
    lo, hi = domain.xy.min(axis=0), domain.xy.max(axis=0)
    w, ht = hi - lo
    if pattern == "hexagonal":
        dy = SQRT3_2 * h
        ny = max(1, int(np.floor(ht / dy + 1e-9)))
        nx = max(1, int(np.floor(w / h - 0.5 + 1e-9)))
        origin = lo + 0.5 * np.array([w - (nx - 0.5) * h, ht - (ny - 1) * dy])
    else:
        nx = max(1, int(np.floor(w / h + 1e-9)))
        ny = max(1, int(np.floor(ht / h + 1e-9)))
        origin = lo + 0.5 * np.array([w - (nx - 1) * h, ht - (ny - 1) * h])
    if (nx + 3) * (ny + 2) > MAX_SITES:
        raise GridError(
            f"pebi_grid: a cell size of {h:.4g} m gives more than {MAX_SITES:,d} sites in this domain"
        )
    c, j = np.meshgrid(np.arange(-1, nx + 2), np.arange(-1, ny + 1))
    if pattern == "hexagonal":
        c = c - np.floor_divide(j, 2)
    return np.column_stack([c.ravel(), j.ravel()]), origin


@dataclass(frozen=True, eq=False)
class Background:
    """Background sites (local frame), their spacing (m) and kind, and the coarsest lattice."""

    xy: np.ndarray  # (n, 2)
    spacing: np.ndarray  # (n,)
    kind: np.ndarray  # (n,) LATTICE (on the coarsest lattice), FINER (a refined level) or PADDING
    ij: np.ndarray  # (n, 2) index on the coarsest lattice where kind == LATTICE
    lattice_origin: np.ndarray
    lattice_h: float
    pattern: str

    @property
    def on_lattice(self) -> np.ndarray:
        return self.kind == LATTICE


def background_sites(
    domain: Domain,
    size: Callable[[np.ndarray], np.ndarray],
    constant: float | None,
    pattern: str,
    padding: int | None,
    clearance: float,
) -> Background:
    """Background sites: a (graded) lattice, padding rows, minus what is too close to the boundary."""
    if constant is not None:
        h0 = constant
    else:
        probe = _probe(domain)
        h0 = float(size(probe).max())
        h0 = min(h0, 0.5 * domain.diameter)
    ij, origin = _lattice(domain, h0, pattern)
    level = np.zeros(ij.shape[0], dtype=np.int64)
    basis = _basis(pattern)
    lo, hi = domain.xy.min(axis=0), domain.xy.max(axis=0)
    if constant is None:
        nbr = _HEX_NEIGHBOURS if pattern == "hexagonal" else _SQUARE_NEIGHBOURS
        k = 0
        while True:  # one pass per refinement level (a handful)
            s = h0 / 2**k
            act = np.flatnonzero(level == k)
            xy = origin + s * _on_basis(ij[act], basis)
            inbox = np.all((xy >= lo - s) & (xy <= hi + s), axis=1)
            act, xy = act[inbox], xy[inbox]
            refine = act[size(xy) < s / np.sqrt(2)]
            if refine.size == 0:
                break
            if k >= 40:
                raise GridError("pebi_grid: cell_size(x, y) asks for more than 40 levels of refinement")
            ij = ij * 2
            new = (ij[refine][:, None, :] + nbr[None, :, :]).reshape(-1, 2)
            new = np.unique(new, axis=0)
            level[refine] = k + 1
            ij = np.concatenate([ij, new])
            level = np.concatenate([level, np.full(new.shape[0], k + 1)])
            if ij.shape[0] > MAX_SITES:
                raise GridError(f"pebi_grid: cell_size(x, y) gives more than {MAX_SITES:,d} sites")
            k += 1
        scale = h0 / math.ldexp(1.0, k)
        xy = origin + scale * _on_basis(ij, basis)
        spacing = h0 / np.ldexp(1.0, level)
        coarse = ij >> k  # exact where level == 0 (those indices were doubled k times)
    else:
        xy = origin + h0 * _on_basis(ij, basis)
        spacing = np.full(xy.shape[0], h0)
        coarse = ij
    kind = np.where(level == 0, LATTICE, FINER)
    # (the inner buffers below lie inside the domain: no separate test for sites outside it)
    if padding:
        pad = _padding_sites(domain, h0, int(padding))
        inner = domain.inner_buffer((padding + 0.25) * h0)
        keep = shapely.contains_xy(inner, xy[:, 0], xy[:, 1])
        return Background(
            np.concatenate([xy[keep], pad]),
            np.concatenate([spacing[keep], np.full(pad.shape[0], h0)]),
            np.concatenate([kind[keep], np.full(pad.shape[0], PADDING)]),
            np.concatenate([coarse[keep], np.zeros((pad.shape[0], 2), dtype=np.int64)]),
            origin,
            h0,
            pattern,
        )
    keep = np.ones(xy.shape[0], dtype=bool)
    for s in np.unique(spacing):  # one buffer per refinement level
        sel = spacing == s
        inner = domain.inner_buffer(clearance * s)
        keep[sel] = shapely.contains_xy(inner, xy[sel, 0], xy[sel, 1])
    return Background(xy[keep], spacing[keep], kind[keep], coarse[keep], origin, h0, pattern)


def _on_basis(ij: np.ndarray, basis: np.ndarray) -> np.ndarray:
    """Integer lattice coordinates (n, 2) times the basis rows (2, 2), elementwise (no BLAS)."""
    return ij[:, :1] * basis[0] + ij[:, 1:2] * basis[1]


def _probe(domain: Domain) -> np.ndarray:
    lo, hi = domain.xy.min(axis=0), domain.xy.max(axis=0)
    gx, gy = np.meshgrid(np.linspace(lo[0], hi[0], 65), np.linspace(lo[1], hi[1], 65))
    p = np.column_stack([gx.ravel(), gy.ravel()])
    p = p[domain.inside(p)]
    return np.concatenate([p, domain.xy])


def _padding_sites(domain: Domain, h: float, rows: int) -> np.ndarray:
    """Rows of sites parallel to the boundary edges, (i + 1/2) h inside."""
    if rows < 0:
        raise GridError(f"pebi_grid: padding must be a non-negative number of rows, got {rows}")
    out = []
    m = domain.num_vertices
    inward = np.column_stack([-domain.edge_unit[:, 1], domain.edge_unit[:, 0]])
    off = (np.arange(rows) + 0.5) * h
    for e in range(m):  # loop over boundary edges
        n_along = max(1, int(np.round(domain.edge_len[e] / h)))
        along = (np.arange(n_along) + 0.5) * domain.edge_len[e] / n_along
        p = (
            domain.edge_a[e][None, None, :]
            + along[None, :, None] * domain.edge_unit[e][None, None, :]
            + off[:, None, None] * inward[e][None, None, :]
        ).reshape(-1, 2)
        need = np.repeat(off, n_along)
        out.append((p, need))
    # fans around reflex corners (the boundary turns clockwise there)
    d_in = domain.edge_unit[np.arange(m) - 1]
    d_out = domain.edge_unit
    reflex = np.flatnonzero(cross2(d_in, d_out) < 0)
    for v in reflex:  # loop over reflex corners
        n_in = inward[v - 1]
        n_out = inward[v]
        a0 = float(arctan2(n_in[1], n_in[0]))
        a1 = float(arctan2(n_out[1], n_out[0]))
        da = np.mod(a0 - a1, 2 * np.pi)  # clockwise from n_in to n_out
        for rho in off:
            nf = int(np.round(rho * da / h))
            if nf <= 0:
                continue
            ang = a0 - (np.arange(nf) + 0.5) * da / nf
            p = domain.xy[v] + rho * np.column_stack([np.cos(ang), np.sin(ang)])
            out.append((p, np.full(nf, rho)))
    if not out:
        return np.zeros((0, 2))
    p = np.concatenate([o[0] for o in out])
    need = np.concatenate([o[1] for o in out])
    ok = domain.inside(p)
    p, need = p[ok], need[ok]
    dist = domain.boundary_distance(p)
    ok = dist >= need * (1 - 1e-6)
    p = p[ok]
    pairs = cKDTree(p).query_pairs(0.5 * h, output_type="ndarray")
    if pairs.size:
        drop = np.zeros(p.shape[0], dtype=bool)
        drop[pairs.max(axis=1)] = True
        p = p[~drop]
    return p
