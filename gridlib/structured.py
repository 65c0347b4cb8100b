"""Logically Cartesian grids: ``cart_grid``, ``tensor_grid``, ``twister``, ``translate_grid``.

Numbering follows MRST's ``tensorGrid`` so that ported MRST scripts see the
same indices (0-based here):

* nodes: x fastest, then y, then z;
* faces: all x-faces (normal +x), then all y-faces, then all z-faces, each
  block numbered x fastest, then y, then z;
* half-faces per cell: W, E, S, N, T, B in 3-D and W, S, E, N in 2-D, with
  ``cells.face_tag`` holding the direction (0..5 = W, E, S, N, T, B);
* face normals point in the positive axis direction; z is depth, so the
  z-face normal (+z) points down, from the upper cell to the lower one.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike

from .errors import GridError
from .grid import B, Cells, E, Faces, Grid, N, Nodes, S, T, W


def _axis(values: ArrayLike, name: str) -> np.ndarray:
    try:
        v = np.asarray(values, dtype=np.float64).ravel()
    except (TypeError, ValueError) as exc:
        raise GridError(f"tensor_grid: {name} must be a sequence of numbers") from exc
    if v.size < 2:
        raise GridError(f"tensor_grid: {name} needs at least 2 node coordinates, got {v.size}")
    if not np.all(np.isfinite(v)):
        raise GridError(f"tensor_grid: {name} contains NaN or infinite values")
    steps = np.diff(v)
    if np.any(steps <= 0):
        i = int(np.flatnonzero(steps <= 0)[0])
        raise GridError(
            f"tensor_grid: {name} must be strictly increasing; "
            f"{name}[{i + 1}] = {v[i + 1]} <= {name}[{i}] = {v[i]}"
        )
    return v


def tensor_grid(
    x: ArrayLike, y: ArrayLike, z: ArrayLike | None = None, *, depth_z: ArrayLike | None = None
) -> Grid:
    """Rectilinear grid from node coordinates along each axis (metres).

    Cell (i, j[, k]) spans ``[x[i], x[i+1]] x [y[j], y[j+1]] (x [z[k], z[k+1]])``.
    ``depth_z`` (3-D only) is an optional (len(x), len(y)) array of depths added
    to every node column, giving a grid that follows a top surface.

    >>> g = tensor_grid([0, 1, 3], [0, 2])
    >>> g.num_cells, g.num_faces, g.num_nodes
    (2, 7, 6)
    """
    xs, ys = _axis(x, "x"), _axis(y, "y")
    if z is None:
        if depth_z is not None:
            raise GridError("tensor_grid: depth_z needs a z axis (3-D grid)")
        return _tensor_2d(xs, ys).with_history("tensor_grid")
    zs = _axis(z, "z")
    dz = None
    if depth_z is not None:
        try:
            dz = np.asarray(depth_z, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise GridError("tensor_grid: depth_z must be an array of numbers") from exc
        if dz.shape == (xs.size, ys.size) and not np.all(np.isfinite(dz)):
            raise GridError("tensor_grid: depth_z contains NaN or infinite values")
        if dz.shape != (xs.size, ys.size):
            raise GridError(f"tensor_grid: depth_z must have shape ({xs.size}, {ys.size}), got {dz.shape}")
    return _tensor_3d(xs, ys, zs, dz).with_history("tensor_grid")


def cart_grid(dims: Sequence[int], lengths: Sequence[float] | None = None) -> Grid:
    """Regular Cartesian grid of ``dims`` = (nx, ny[, nz]) cells over [0, L] per axis.

    ``lengths`` defaults to ``dims`` (unit cells). Lengths in metres.

    >>> g = cart_grid([3, 2])
    >>> g.num_cells, g.num_faces, g.num_nodes
    (6, 17, 12)
    """
    try:
        d = np.asarray(dims)
    except (TypeError, ValueError) as exc:
        raise GridError(f"cart_grid: dims must be 2 or 3 integers, got {dims!r}") from exc
    if d.ndim != 1 or d.size not in (2, 3):
        raise GridError(f"cart_grid: dims must be 2 or 3 integers, got {dims!r}")
    if not np.issubdtype(d.dtype, np.number) or np.any(d != np.round(d)) or np.any(d < 1):
        raise GridError(f"cart_grid: dims must be positive integers, got {dims!r}")
    d = d.astype(np.int64)
    if np.prod(d.astype(np.float64)) > 2e8:
        raise GridError(
            f"cart_grid: {np.prod(d.astype(np.float64)):.3g} cells is more than gridlib supports (2e8)"
        )
    if lengths is None:
        L = d.astype(np.float64)
    else:
        try:
            L = np.asarray(lengths, dtype=np.float64).ravel()
        except (TypeError, ValueError) as exc:
            raise GridError(f"cart_grid: lengths must be numbers, got {lengths!r}") from exc
        if L.size != d.size:
            raise GridError(f"cart_grid: {d.size} dims but {L.size} lengths")
        if not np.all(np.isfinite(L)) or np.any(L <= 0):
            raise GridError(f"cart_grid: lengths must be positive and finite, got {list(L)}")
    axes = [np.linspace(0.0, L[i], d[i] + 1) for i in range(d.size)]
    return tensor_grid(*axes).with_history("cart_grid")


def _tensor_2d(x: np.ndarray, y: np.ndarray) -> Grid:
    nx, ny = x.size - 1, y.size - 1
    node = np.arange((nx + 1) * (ny + 1), dtype=np.int64).reshape(ny + 1, nx + 1)
    # x-faces run from (i, j) to (i, j+1): normal (dy, -dx) = +x.
    fx = np.stack([node[:-1, :], node[1:, :]], axis=-1).reshape(-1, 2)
    # y-faces run from (i+1, j) to (i, j): normal = +y.
    fy = np.stack([node[:, 1:], node[:, :-1]], axis=-1).reshape(-1, 2)
    nfx = fx.shape[0]

    cell = np.full((ny + 2, nx + 2), -1, dtype=np.int64)
    cell[1:-1, 1:-1] = np.arange(nx * ny).reshape(ny, nx)
    nbx = np.stack([cell[1:-1, :-1], cell[1:-1, 1:]], axis=-1).reshape(-1, 2)
    nby = np.stack([cell[:-1, 1:-1], cell[1:, 1:-1]], axis=-1).reshape(-1, 2)

    FX = np.arange(nfx).reshape(ny, nx + 1)
    FY = nfx + np.arange(nx * (ny + 1)).reshape(ny + 1, nx)
    cf = np.stack([FX[:, :-1], FY[:-1, :], FX[:, 1:], FY[1:, :]], axis=-1).reshape(-1)
    tags = np.tile(np.array([W, S, E, N], dtype=np.int8), nx * ny)

    xx, yy = np.meshgrid(x, y, indexing="xy")
    coords = np.column_stack([xx.ravel(), yy.ravel()])
    nf = nfx + fy.shape[0]
    return Grid(
        cells=Cells(
            face_pos=np.arange(0, 4 * nx * ny + 1, 4),
            faces=cf,
            face_tag=tags,
            index_map=np.arange(nx * ny),
        ),
        faces=Faces(
            node_pos=np.arange(0, 2 * nf + 1, 2),
            nodes=np.concatenate([fx.ravel(), fy.ravel()]),
            neighbors=np.concatenate([nbx, nby]),
        ),
        nodes=Nodes(coords),
        griddim=2,
        cart_dims=(nx, ny),
    )


def _tensor_3d(x: np.ndarray, y: np.ndarray, z: np.ndarray, depth_z: np.ndarray | None) -> Grid:
    nx, ny, nz = x.size - 1, y.size - 1, z.size - 1
    node = np.arange((nx + 1) * (ny + 1) * (nz + 1), dtype=np.int64).reshape(nz + 1, ny + 1, nx + 1)
    # Node order per face chosen so the right-hand normal is +x, +y, +z.
    fx = np.stack([node[:-1, :-1, :], node[:-1, 1:, :], node[1:, 1:, :], node[1:, :-1, :]], axis=-1).reshape(
        -1, 4
    )
    fy = np.stack([node[:-1, :, :-1], node[1:, :, :-1], node[1:, :, 1:], node[:-1, :, 1:]], axis=-1).reshape(
        -1, 4
    )
    fz = np.stack([node[:, :-1, :-1], node[:, :-1, 1:], node[:, 1:, 1:], node[:, 1:, :-1]], axis=-1).reshape(
        -1, 4
    )
    nfx, nfy = fx.shape[0], fy.shape[0]

    cell = np.full((nz + 2, ny + 2, nx + 2), -1, dtype=np.int64)
    cell[1:-1, 1:-1, 1:-1] = np.arange(nx * ny * nz).reshape(nz, ny, nx)
    nbx = np.stack([cell[1:-1, 1:-1, :-1], cell[1:-1, 1:-1, 1:]], axis=-1).reshape(-1, 2)
    nby = np.stack([cell[1:-1, :-1, 1:-1], cell[1:-1, 1:, 1:-1]], axis=-1).reshape(-1, 2)
    nbz = np.stack([cell[:-1, 1:-1, 1:-1], cell[1:, 1:-1, 1:-1]], axis=-1).reshape(-1, 2)

    FX = np.arange(nfx).reshape(nz, ny, nx + 1)
    FY = nfx + np.arange(nfy).reshape(nz, ny + 1, nx)
    FZ = nfx + nfy + np.arange(fz.shape[0]).reshape(nz + 1, ny, nx)
    cf = np.stack(
        [FX[:, :, :-1], FX[:, :, 1:], FY[:, :-1, :], FY[:, 1:, :], FZ[:-1], FZ[1:]], axis=-1
    ).reshape(-1)
    nc = nx * ny * nz
    tags = np.tile(np.array([W, E, S, N, T, B], dtype=np.int8), nc)

    zz, yy, xx = np.meshgrid(z, y, x, indexing="ij")
    if depth_z is not None:
        zz = zz + depth_z.T[None, :, :]
    coords = np.column_stack([xx.ravel(), yy.ravel(), zz.ravel()])
    nf = nfx + nfy + fz.shape[0]
    return Grid(
        cells=Cells(face_pos=np.arange(0, 6 * nc + 1, 6), faces=cf, face_tag=tags, index_map=np.arange(nc)),
        faces=Faces(
            node_pos=np.arange(0, 4 * nf + 1, 4),
            nodes=np.concatenate([fx.ravel(), fy.ravel(), fz.ravel()]),
            neighbors=np.concatenate([nbx, nby, nbz]),
        ),
        nodes=Nodes(coords),
        griddim=3,
        cart_dims=(nx, ny, nz),
    )


def twister(grid_or_coords: Grid | ArrayLike, amplitude: float = 0.03) -> Grid | np.ndarray:
    """Perturb node coordinates with MRST's smooth sine map (a curvilinear test grid).

    Coordinates are normalised to the unit box, then (as in MRST's ``twister``)
    ``x += f(x, y)``, ``y -= f(y, x)`` with ``f(u, v) = a sin(pi u) sin(3 pi (v - 1/2))``,
    and in 3-D the same for the (y, z) and (x, z) pairs; finally mapped back to
    the original bounding box. The boundary of the box is preserved. Unlike
    MRST (which maps back to [0, L]), the box's minimum corner is restored too.
    Accepts a grid (returns a grid) or an (n, 2|3) coordinate array.
    """
    try:
        a = float(amplitude)
    except (TypeError, ValueError) as exc:
        raise GridError(f"twister: amplitude must be a number, got {amplitude!r}") from exc
    if isinstance(grid_or_coords, Grid):
        g = grid_or_coords
        # The perturbation bends pillars, so a layered grid is no longer an extrusion.
        return g.with_history("twister", nodes=Nodes(_twist(g.nodes.coords, a)), layering=None)
    try:
        pts = np.asarray(grid_or_coords, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise GridError("twister: expected a grid or an (n, 2|3) array of numbers") from exc
    if pts.ndim != 2 or pts.shape[1] not in (2, 3):
        raise GridError(f"twister: expected an (n, 2) or (n, 3) array, got shape {pts.shape}")
    return _twist(pts, a)


def _twist(pts: np.ndarray, a: float) -> np.ndarray:
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    span = np.where(hi > lo, hi - lo, 1.0)
    xi = (pts - lo) / span

    def f(u: np.ndarray, v: np.ndarray) -> np.ndarray:
        return a * np.sin(np.pi * u) * np.sin(3.0 * np.pi * (v - 0.5))

    new = xi.copy()
    new[:, 0] = xi[:, 0] + f(xi[:, 0], xi[:, 1])
    new[:, 1] = xi[:, 1] - f(xi[:, 1], xi[:, 0])
    if pts.shape[1] == 3:
        new[:, 1] = new[:, 1] + f(xi[:, 1], xi[:, 2])
        new[:, 2] = xi[:, 2] - f(xi[:, 2], xi[:, 1])
        new[:, 0] = new[:, 0] + f(xi[:, 0], xi[:, 2])
        new[:, 2] = new[:, 2] - f(xi[:, 2], xi[:, 0])
    return lo + new * span


def translate_grid(grid: Grid, shift: ArrayLike) -> Grid:
    """Shift every node by ``shift`` (length = number of coordinate components)."""
    try:
        s = np.asarray(shift, dtype=np.float64).ravel()
    except (TypeError, ValueError) as exc:
        raise GridError(f"translate_grid: shift must be {grid.dim} numbers, got {shift!r}") from exc
    if s.size != grid.dim or not np.all(np.isfinite(s)):
        raise GridError(f"translate_grid: shift must be {grid.dim} finite numbers, got {shift!r}")
    layering = grid.layering
    if layering is not None:  # move the footprint with the grid
        areal = layering.areal
        moved = translate_grid(areal, np.concatenate([s[:2], s[2:]])[: areal.dim])
        layering = replace(layering, areal=moved)
    return grid.with_history("translate_grid", nodes=Nodes(grid.nodes.coords + s), layering=layering)
