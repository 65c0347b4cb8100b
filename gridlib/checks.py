"""``check_grid``: the invariants every valid grid satisfies, whatever built it (structured,
corner-point, PEBI, layered, glued); a :class:`~gridlib.errors.GridError` names each violated
invariant and its first offending cells, faces or nodes.

Topology (any grid):
  * indices in range: cell faces in [0, nf), face nodes in [0, nn), neighbours
    in [-1, nc); no face with two outside neighbours or the same cell twice;
  * ``cells.faces`` is the transpose of ``faces.neighbors``: every interior
    face appears once in each of its two cells, a boundary face once;
  * faces have exactly 2 nodes (2-D) or at least 3 distinct nodes (3-D);
  * no two faces with the same set of nodes; no node used by no face;
  * cells have at least 3 (2-D) or 4 (3-D) faces.
Geometry:
  * all coordinates finite; face areas and cell volumes positive;
  * closure: for every cell, ``|sum_f s_f N_f| <= tol * sum_f A_f`` with the
    outward signs s_f. This catches flipped faces, wrong node order and
    missing half-faces (hanging nodes on straight edges are fine).

Broken and degenerate: topology, non-finite coordinates and faces of no area are *broken*: no
grid may have them. A cell whose volume is not positive or whose faces do not close is
*degenerate*: :func:`check_grid` refuses it (for the grids gridlib builds it is a bug), while
:func:`check_deck_grid` returns such cells as :class:`DegenerateCells` to be kept and named: a
deck written by a geomodeller may hold thin wedges beside faults that OPM Flow runs, since Flow
takes its volumes from each cell's eight corners, not from the polyhedron.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .cell_names import cell_names
from .connectivity import cell_node_cycles_2d, half_face_cells, repeat_ids
from .errors import GridError
from .geometry import Geometry, compute_geometry
from .grid import FloatArray, Grid, IntArray

_MAX_LISTED = 5
NAMED_DEGENERATE = 100  # degenerate cells named in a note (all are flagged in grid.nc)
_ROWS = 1 << 18  # faces per block of the duplicate-face search
_CELLS = 1 << 18  # cells per block of the closure test


def _ids(mask: np.ndarray) -> str:
    """The first indices where ``mask`` holds, the rest counted."""
    return _ids_of(np.flatnonzero(mask))


def _ids_of(idx: np.ndarray) -> str:
    """The first of the 0-based indices ``idx``, the rest counted."""
    more = f" and {idx.size - _MAX_LISTED} more" if idx.size > _MAX_LISTED else ""
    return f"{idx[:_MAX_LISTED].tolist()}{more}"


def _where(grid: Grid, cells: np.ndarray) -> str:
    """`` (cells (i, j, k), ...)`` naming ``cells`` for a grid with logical indices (a deck's),
    else nothing: the message's own numbers are all there is."""
    idx, dims = grid.cells.index_map, grid.cart_dims
    cells = np.unique(np.asarray(cells, dtype=np.int64))
    cells = cells[(cells >= 0) & (cells < grid.num_cells)]
    if idx is None or dims is None or not cells.size:
        return ""
    return f" (cells {cell_names(cells, idx, dims)})"


def _of_faces(grid: Grid, faces: np.ndarray) -> str:
    """:func:`_where` for the cells on either side of ``faces`` (a mask or face numbers)."""
    f = np.flatnonzero(faces) if np.asarray(faces).dtype == bool else np.asarray(faces, dtype=np.int64)
    return _where(grid, grid.faces.neighbors[f].ravel())


def topology_violations(grid: Grid) -> list[str]:
    """Human-readable list of violated topological invariants (empty if valid)."""
    nc, nf, nn = grid.num_cells, grid.num_faces, grid.num_nodes
    out: list[str] = []
    cf, nb, fn = grid.cells.faces, grid.faces.neighbors, grid.faces.nodes
    bad = (cf < 0) | (cf >= nf)
    if bad.any():
        out.append(f"cells.faces refers to faces outside [0, {nf}) at half-faces {_ids(bad)}")
    bad = (fn < 0) | (fn >= nn)
    if bad.any():
        out.append(f"faces.nodes refers to nodes outside [0, {nn}) at entries {_ids(bad)}")
    bad = ((nb < -1) | (nb >= nc)).any(axis=1)
    if bad.any():
        out.append(f"faces.neighbors outside [-1, {nc}) at faces {_ids(bad)}")
    if out:
        return out  # the remaining checks index with these arrays
    bad = (nb < 0).all(axis=1)
    if bad.any():
        out.append(f"faces with no cell on either side: {_ids(bad)}")
    bad = (nb[:, 0] == nb[:, 1]) & (nb[:, 0] >= 0)
    if bad.any():
        out.append(f"faces with the same cell on both sides: {_ids(bad)}{_of_faces(grid, bad)}")

    # cells.faces must be exactly the transpose of faces.neighbors: every half-face names a
    # neighbour of its face, and each face has as many half-faces, summing to the same cells
    # (with distinct neighbours, a repeated cell would change the sum). O(n); the sorting
    # diagnosis below runs only when this fails.
    hc = half_face_cells(grid)
    inside = nb >= 0
    names_neighbor = all(  # a block of half-faces at a time: no gathers of them all
        ((nb[cf[b], 0] == hc[b]) | (nb[cf[b], 1] == hc[b])).all()
        for b in (slice(start, start + _ROWS) for start in range(0, cf.size, _ROWS))
    )
    same_count = np.bincount(cf, minlength=nf) == inside.sum(axis=1)
    same_sum = np.bincount(cf, weights=hc, minlength=nf) == np.where(inside, nb, 0).sum(axis=1)
    if not (names_neighbor and same_count.all() and same_sum.all()):
        out += _transpose_violations(cf, hc, nb, nc, nf, grid)

    counts = grid.faces.num_nodes
    if grid.griddim == 2:
        bad = counts != 2
        if bad.any():
            out.append(f"2-D faces must have 2 nodes; faces {_ids(bad)} do not")
    else:
        bad = counts < 3
        if bad.any():
            out.append(f"3-D faces need at least 3 nodes; faces {_ids(bad)} have fewer{_of_faces(grid, bad)}")
    repeating, dups = _repeated_and_duplicate_faces(counts, fn, grid.faces.node_pos)
    if repeating.size:
        out.append(f"faces repeating a node: {repeating[:_MAX_LISTED].tolist()}{_of_faces(grid, repeating)}")
    if dups.size:
        out.append(
            f"faces with the same nodes as another face: {dups[:_MAX_LISTED].tolist()}{_of_faces(grid, dups)}"
        )

    used = np.zeros(nn, dtype=bool)
    used[fn] = True
    if not used.all():
        out.append(f"nodes used by no face: {_ids(~used)}")
    need = 3 if grid.griddim == 2 else 4
    bad = grid.cells.num_faces < need
    if bad.any():
        out.append(f"cells with fewer than {need} faces: {_ids(bad)}{_where(grid, np.flatnonzero(bad))}")
    if grid.griddim == 2 and not out:
        try:  # every 2-D cell (planar or on a surface) is one closed, consistently oriented cycle
            cell_node_cycles_2d(grid)
        except GridError as exc:
            out.append(f"2-D cell boundaries are not oriented cycles ({exc})")
    return out


def _transpose_violations(
    cf: np.ndarray, hc: np.ndarray, nb: np.ndarray, nc: int, nf: int, grid: Grid
) -> list[str]:
    """Which (face, cell) half-faces ``cells.faces`` lacks, has in excess or lists twice."""
    out: list[str] = []
    from_cells = np.sort(cf * (nc + 1) + hc)
    inside = nb >= 0
    from_faces = np.sort((np.repeat(np.arange(nf), 2) * (nc + 1) + nb.ravel())[inside.ravel()])
    c_keys, c_counts = np.unique(from_cells, return_counts=True)
    for what, keys in (
        ("half-faces missing from cells.faces (face, cell)", np.setdiff1d(from_faces, c_keys)),
        ("cells list faces they are not a neighbour of (face, cell)", np.setdiff1d(c_keys, from_faces)),
        ("cells list the same face twice (face, cell)", c_keys[c_counts > 1]),
    ):
        if keys.size:
            pairs = [(int(k // (nc + 1)), int(k % (nc + 1))) for k in keys[:_MAX_LISTED]]
            out.append(f"{what}: {pairs}{_where(grid, [c for _, c in pairs])}")
    return out


def _repeated_and_duplicate_faces(
    counts: np.ndarray, nodes: np.ndarray, pos: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Faces that repeat a node, and faces whose node set equals that of an earlier face.

    Faces are taken a node count at a time as (faces, k) tables sorted along each row.
    Duplicate rows are found by sorting a 64-bit hash of each row; rows whose hash is
    shared (duplicates, or a collision) are compared exactly, so the answer is exact.
    """
    repeating, candidates, rows_of = [], [], []
    multipliers = np.random.default_rng(0x5EED).integers(1, 2**62, size=int(counts.max(initial=0)) + 1)
    multipliers |= 1  # odd: multiplication is a bijection modulo 2**64

    def sorted_rows(faces: np.ndarray, k: int) -> np.ndarray:
        return np.sort(nodes[pos[faces][:, None] + np.arange(k)], axis=1)

    for k in np.unique(counts[counts > 0]):  # faces without nodes are reported by their count
        faces = np.flatnonzero(counts == k)
        h = np.empty(faces.size, dtype=np.uint64)
        for start in range(0, faces.size, _ROWS):  # in blocks: a few rows' tables at a time
            block = faces[start : start + _ROWS]
            rows = sorted_rows(block, k)
            if k > 1:
                repeating.append(block[(rows[:, 1:] == rows[:, :-1]).any(axis=1)])
            with np.errstate(over="ignore"):
                weighted = rows.astype(np.uint64) * multipliers[:k].astype(np.uint64)
                h[start : start + _ROWS] = weighted.sum(axis=1, dtype=np.uint64)
        hs = np.sort(h)
        twice = hs[1:][hs[1:] == hs[:-1]]
        if twice.size:
            pick = np.flatnonzero(np.isin(h, twice))  # ascending face number: the first is kept
            candidates.append(faces[pick])
            rows_of.append(sorted_rows(faces[pick], k))
    empty = np.zeros(0, dtype=np.int64)
    rep = np.sort(np.concatenate(repeating)) if repeating else empty
    dups = []
    for faces, rows in zip(candidates, rows_of, strict=True):
        _, first, inverse = np.unique(rows, axis=0, return_index=True, return_inverse=True)
        dups.append(faces[first[inverse.reshape(-1)] != np.arange(faces.size)])
    return rep, (np.sort(np.concatenate(dups)) if dups else empty)


@dataclass(frozen=True, eq=False)
class DegenerateCells:
    """Cells whose geometry is degenerate but whose topology is sound (:func:`check_deck_grid`):
    ``non_positive_volume`` (their polyhedral volumes ``volumes``) and ``not_closed`` (their
    outward normals sum to ``closure`` x their surface area, above the tolerance), cell numbers
    ascending."""

    non_positive_volume: IntArray
    volumes: FloatArray
    not_closed: IntArray
    closure: FloatArray

    @property
    def cells(self) -> IntArray:
        """Every degenerate cell, ascending."""
        return np.union1d(self.non_positive_volume, self.not_closed)

    def __len__(self) -> int:
        return int(self.cells.size)

    def flags(self, num_cells: int) -> np.ndarray:
        """Per cell of the grid: 0 sound, +1 polyhedral volume not positive, +2 not closed (int8)."""
        out = np.zeros(num_cells, dtype=np.int8)
        out[self.non_positive_volume] |= 1
        out[self.not_closed] |= 2
        return out

    def notes(self, grid: Grid, limit: int = NAMED_DEGENERATE) -> tuple[str, ...]:
        """One note per kind of degeneracy naming its cells, the first ``limit`` of them ((i, j, k)
        where the grid knows them; the rest counted)."""
        idx, dims = grid.cells.index_map, grid.cart_dims
        out = []
        if self.non_positive_volume.size:
            cells = self.non_positive_volume
            volumes = ", ".join(f"{v:.4g}" for v in self.volumes[:3]) + (", ..." if cells.size > 3 else "")
            out.append(
                f"{cells.size} cells with a non-positive polyhedral volume (kept; the simulator's "
                f"volume is their ECLIPSE bulk volume): {cell_names(cells, idx, dims, limit)} "
                f"(polyhedral volumes {volumes})"
            )
        if self.not_closed.size:
            out.append(
                f"{self.not_closed.size} cells whose faces do not close (sum of outward normals / "
                f"surface area up to {float(self.closure.max()):.2e}; kept): "
                f"{cell_names(self.not_closed, idx, dims, limit)}"
            )
        return tuple(out)


def degenerate_cells(grid: Grid, geometry: Geometry, tol: float) -> DegenerateCells:
    """The cells of ``grid`` (valid topology, sizes matching ``geometry``) whose polyhedral volume
    (area in 2-D) is not positive, or whose outward face normals do not sum to zero within
    ``tol`` times their surface area (not tested on surface grids: the edge normals of a curved
    surface need not close)."""
    vol = geometry.cell_volumes
    small = np.flatnonzero(~(vol > 0))
    empty = np.zeros(0, dtype=np.int64)
    if grid.is_surface:
        return DegenerateCells(small, vol[small], empty, np.zeros(0))
    found = [_not_closed(grid, geometry, tol, start) for start in range(0, grid.num_cells, _CELLS)]
    open_ = np.concatenate([cells for cells, _ in found])
    return DegenerateCells(small, vol[small], open_, np.concatenate([closure for _, closure in found]))


def _not_closed(grid: Grid, geometry: Geometry, tol: float, start: int) -> tuple[IntArray, FloatArray]:
    """The cells of the block of :data:`_CELLS` cells from ``start`` whose outward face normals
    do not sum to zero within ``tol`` times their surface area, and those sums over the area.
    A block at a time, so that no per-half-face array of the whole grid is made; each cell's sums
    add its half-faces in the same order as over the whole grid (the same bits)."""
    pos = grid.cells.face_pos[start : start + _CELLS + 1]
    hc = repeat_ids(pos - pos[0])
    cf = grid.cells.faces[pos[0] : pos[-1]]
    s = np.where(grid.faces.neighbors[cf, 0] == hc + start, 1.0, -1.0)
    n = pos.size - 1
    net = np.stack([np.bincount(hc, s * geometry.face_normals[cf, i], n) for i in range(grid.dim)])
    surface = np.bincount(hc, geometry.face_areas[cf], n)
    defect = np.sqrt((net**2).sum(axis=0))
    open_ = np.flatnonzero(defect > tol * surface)
    return open_ + start, defect[open_] / surface[open_]


def _geometry_problems(
    grid: Grid, geometry: Geometry, tol: float
) -> tuple[list[str], DegenerateCells | None]:
    """What is broken in the geometry (sizes, face areas) and, if nothing is, the degenerate cells."""
    if geometry.cell_volumes.shape != (grid.num_cells,) or geometry.face_areas.shape != (grid.num_faces,):
        return [
            f"the geometry has {geometry.cell_volumes.size} cells and {geometry.face_areas.size} faces, "
            f"the grid {grid.num_cells} and {grid.num_faces}"
        ], None
    bad = geometry.face_areas <= 0
    broken = [f"faces with non-positive area: {_ids(bad)}{_of_faces(grid, bad)}"] if bad.any() else []
    return broken, degenerate_cells(grid, geometry, tol)


def _degenerate_violations(grid: Grid, cells: DegenerateCells, tol: float) -> list[str]:
    """Degenerate cells as violations (the strict check of :func:`check_grid`)."""
    out = []
    if cells.non_positive_volume.size:
        what = "area" if grid.griddim == 2 else "volume"
        ids = cells.non_positive_volume
        first = ", ".join(f"{v:.6g}" for v in cells.volumes[:3].tolist())
        out.append(
            f"cells with non-positive {what}: {_ids_of(ids)}{_where(grid, ids[:_MAX_LISTED])} "
            f"(first {what}s {first})"
        )
    if cells.not_closed.size:
        ids = cells.not_closed
        out.append(
            f"cells not closed (sum of outward normals / surface area up to {float(cells.closure.max()):.2e} "
            f"> {tol:g}): {_ids_of(ids)}{_where(grid, ids[:_MAX_LISTED])}; a face is flipped, misordered "
            "or missing"
        )
    return out


def _broken(grid: Grid, geometry: Geometry | None, tol: float) -> tuple[list[str], DegenerateCells | None]:
    """Topology and geometry problems that no grid may have, and the degenerate cells (None when
    something is broken before they could be found)."""
    if grid.num_cells == 0:
        return ["the grid has no cells (every cell inactive or removed)"], None
    problems = topology_violations(grid)
    if problems:
        return problems, None
    coords = grid.nodes.coords
    if not np.all(np.isfinite(coords)):
        return [f"nodes with NaN or infinite coordinates: {_ids(~np.isfinite(coords).all(axis=1))}"], None
    if geometry is None:
        try:
            geometry = compute_geometry(grid, face_centroids=False)  # the checks use none
        except GridError as exc:
            return [str(exc)], None
    return _geometry_problems(grid, geometry, tol)


def _raise(grid: Grid, problems: list[str]) -> None:
    """One GridError listing ``problems``, the grid described by its size (no repr)."""
    if problems:
        what = f"{grid.griddim}-D grid of {grid.num_cells:,d} cells and {grid.num_faces:,d} faces"
        raise GridError(f"check_grid: {len(problems)} problem(s) in the {what}: {'; '.join(problems)}")


def check_grid(grid: Grid, geometry: Geometry | None = None, *, tol: float = 1e-10) -> None:
    """Raise one :class:`GridError` listing every violated invariant, or return None.

    ``geometry`` is computed if not given. ``tol`` is the closure tolerance
    relative to each cell's surface area. Every grid gridlib builds passes it: a degenerate
    cell there is a bug (:func:`check_deck_grid` keeps those of a deck).
    """
    problems, cells = _broken(grid, geometry, tol)
    if cells is not None:
        problems += _degenerate_violations(grid, cells, tol)
    _raise(grid, problems)


def check_deck_grid(grid: Grid, geometry: Geometry | None = None, *, tol: float = 1e-10) -> DegenerateCells:
    """:func:`check_grid` for the grid of a deck someone else wrote: what is broken (topology,
    non-finite coordinates, faces of no area) raises one :class:`GridError`; cells whose geometry
    is merely degenerate (polyhedral volume not positive, faces not closing within ``tol`` of
    their surface area: thin wedges with collapsed corners beside faults, as geomodelling exports
    make them) are returned, to be kept and named. A simulator does not use that geometry: its
    pore volumes come from the ECLIPSE bulk volume of each cell's eight corners."""
    problems, cells = _broken(grid, geometry, tol)
    _raise(grid, problems)
    assert cells is not None
    return cells
