"""The one grid model shared by every grid type in gridlib.

A grid is an immutable value: a :class:`Grid` holding :class:`Cells`, :class:`Faces`
and :class:`Nodes`, each a frozen dataclass of numpy arrays. Arrays passed in are
adopted without a copy when their dtype and layout already fit, and made read-only:
the grid owns them from then on.
Every builder and operation is a function returning a new grid. The layout is
MRST's unstructured grid (MRST book, ch. 3.4), translated to 0-based indices.

Conventions
-----------
Indices
    All indices are 0-based ``int64``. ``-1`` in ``faces.neighbors`` means "outside".
Offsets
    Ragged lists are stored as a flat array plus an offset array of length n+1:
    the faces of cell ``c`` are ``cells.faces[cells.face_pos[c]:cells.face_pos[c+1]]``
    and the nodes of face ``f`` are ``faces.nodes[faces.node_pos[f]:faces.node_pos[f+1]]``.
Coordinates
    ``nodes.coords`` is (nn, d) float64 in metres, d = 2 (planar) or 3.
    **z is depth, positive downwards** (as in MRST and ECLIPSE). With z down, the
    frame (x east, y north, z down) is left-handed; nothing in gridlib assumes a
    handedness, orientation is defined purely by node order as below.
Orientation
    In 3D a face's nodes are listed in cyclic order; by the right-hand rule that
    order defines the face normal, which points from ``neighbors[f, 0]`` to
    ``neighbors[f, 1]``. In 2D a face is an edge n0 -> n1 with normal
    (dy, -dx): it points to the right of the direction of travel, so
    ``neighbors[f, 0]`` lies on the left. Either column of a boundary face may
    hold the -1 (MRST's ``removeCells`` leaves ``(c, -1)`` and ``(-1, c)`` rows);
    consumers use the half-face sign ``+1 if cell == neighbors[f, 0] else -1``.
Dimension
    ``griddim`` is 3 for volumetric grids (faces are polygons) and 2 for planar
    grids and for surface grids embedded in 3D (faces are edges with 2 nodes).
Tags
    ``cells.face_tag`` (int8, per half-face, optional) gives the logical
    direction of a half-face in a logically Cartesian grid:
    0..5 = W, E, S, N, T, B (West = -i, East = +i, South = -j, North = +j,
    Top = -k i.e. shallower, Bottom = +k i.e. deeper).
    ``faces.tag`` (int32, per face) is 0 for an ordinary face and > 0 for a
    face on a fault (the fault's id).
Logical indices
    ``cart_dims`` is the logical box (nx, ny[, nz]) and ``cells.index_map`` the
    linear index of each cell in that box, i fastest (then j, then k).
Layering
    Grids extruded from an areal grid (``make_layered_grid``) keep that areal
    grid in ``layering`` with, per cell, its areal column and its layer
    (layer 0 is the top). This is the footprint written as a UGRID mesh.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import NDArray

from .arrays import frozen_array
from .errors import GridError

W, E, S, N, T, B = range(6)

IntArray = NDArray[np.int64]
FloatArray = NDArray[np.float64]


def _adopt_ragged(obj: object, pos_field: str, data_field: str, owner: str) -> None:
    """Adopt ``obj``'s offsets and flat data (int64, read-only) and check that the offsets
    start at 0, never decrease and end at the data's length."""
    pos = frozen_array(getattr(obj, pos_field), np.int64, f"{owner}.{pos_field}", 1)
    data = frozen_array(getattr(obj, data_field), np.int64, f"{owner}.{data_field}", 1)
    _check_offsets(pos, data.size, f"{owner}.{pos_field}")
    object.__setattr__(obj, pos_field, pos)
    object.__setattr__(obj, data_field, data)


def _adopt_per(obj: object, field_: str, dtype: type, num: int, owner: str, per: str) -> None:
    """Adopt ``obj``'s 1-D array ``field_`` (read-only ``dtype``), which holds one entry per ``per``."""
    arr = frozen_array(getattr(obj, field_), dtype, f"{owner}.{field_}", 1)
    if arr.size != num:
        raise GridError(f"{owner}.{field_} must have one entry per {per}")
    object.__setattr__(obj, field_, arr)


def _check_offsets(pos: NDArray, n_data: int, name: str) -> None:
    if pos.size == 0 or pos[0] != 0 or pos[-1] != n_data:
        raise GridError(
            f"{name}: offsets must start at 0 and end at {n_data}, "
            f"got {pos[:1].tolist()}...{pos[-1:].tolist()}"
        )
    if np.any(np.diff(pos) < 0):
        raise GridError(f"{name}: offsets must be non-decreasing")


def _check_range(arr: NDArray, lo: int, hi: int, name: str, what: str) -> None:
    if arr.size and (arr.min() < lo or arr.max() >= hi):
        bad = arr[(arr < lo) | (arr >= hi)][0]
        raise GridError(f"{name}: index {bad} outside [{lo}, {hi}) (there are {hi} {what})")


@dataclass(frozen=True, eq=False)
class Cells:
    """Cells as ragged lists of faces (half-faces)."""

    face_pos: IntArray
    faces: IntArray
    face_tag: NDArray[np.int8] | None = None
    index_map: IntArray | None = None

    def __post_init__(self) -> None:
        _adopt_ragged(self, "face_pos", "faces", "cells")
        if self.face_tag is not None:
            _adopt_per(self, "face_tag", np.int8, self.faces.size, "cells", "half-face")
        if self.index_map is not None:
            _adopt_per(self, "index_map", np.int64, self.num, "cells", "cell")

    @property
    def num(self) -> int:
        return self.face_pos.size - 1

    @property
    def num_faces(self) -> IntArray:
        """Number of faces of each cell."""
        return np.diff(self.face_pos)


@dataclass(frozen=True, eq=False)
class Faces:
    """Faces as ragged lists of nodes, with their two neighbouring cells."""

    node_pos: IntArray
    nodes: IntArray
    neighbors: IntArray
    tag: NDArray[np.int32] | None = None

    def __post_init__(self) -> None:
        _adopt_ragged(self, "node_pos", "nodes", "faces")
        neighbors = frozen_array(self.neighbors, np.int64, "faces.neighbors", 2)
        if neighbors.shape != (self.num, 2):
            raise GridError(f"faces.neighbors must have shape ({self.num}, 2), got {neighbors.shape}")
        object.__setattr__(self, "neighbors", neighbors)
        if self.tag is None:
            object.__setattr__(self, "tag", np.zeros(self.num, np.int32))
        _adopt_per(self, "tag", np.int32, self.num, "faces", "face")

    @property
    def num(self) -> int:
        return self.node_pos.size - 1

    @property
    def num_nodes(self) -> IntArray:
        """Number of nodes of each face."""
        return np.diff(self.node_pos)


@dataclass(frozen=True, eq=False)
class Nodes:
    """Node coordinates, (nn, d) float64, z is depth."""

    coords: FloatArray

    def __post_init__(self) -> None:
        object.__setattr__(self, "coords", frozen_array(self.coords, np.float64, "nodes.coords", 2))
        if self.coords.shape[1] not in (2, 3):
            raise GridError(f"nodes.coords must have 2 or 3 columns, got {self.coords.shape[1]}")
        finite = np.isfinite(self.coords).all(axis=1)
        if not finite.all():
            raise GridError(f"nodes.coords: node {int(np.flatnonzero(~finite)[0])} is NaN or infinite")

    @property
    def num(self) -> int:
        return self.coords.shape[0]


@dataclass(frozen=True, eq=False)
class Layering:
    """The areal grid a layered grid was extruded from.

    ``column[c]`` is the areal cell below which cell ``c`` lies and ``layer[c]``
    its layer (0 = top). ``num_layers`` is the number of layers of the extrusion.
    """

    areal: Grid
    column: IntArray
    layer: IntArray
    num_layers: int

    def __post_init__(self) -> None:
        object.__setattr__(self, "column", frozen_array(self.column, np.int64, "layering.column", 1))
        _adopt_per(self, "layer", np.int64, self.column.size, "layering", "cell of layering.column")

    def subset(self, cells: IntArray) -> Layering:
        return Layering(self.areal, self.column[cells], self.layer[cells], self.num_layers)


@dataclass(frozen=True, eq=False)
class Grid:
    """An unstructured grid of any type (see the module docstring for conventions)."""

    cells: Cells
    faces: Faces
    nodes: Nodes
    griddim: int
    cart_dims: tuple[int, ...] | None = None
    history: tuple[str, ...] = ()
    layering: Layering | None = field(default=None)

    def __post_init__(self) -> None:
        if self.griddim not in (2, 3):
            raise GridError(f"griddim must be 2 or 3, got {self.griddim}")
        if self.griddim > self.nodes.coords.shape[1]:
            raise GridError("griddim 3 needs 3-D node coordinates")
        if self.cart_dims is not None:
            try:
                object.__setattr__(self, "cart_dims", tuple(int(d) for d in self.cart_dims))
            except (TypeError, ValueError) as exc:
                raise GridError(f"cart_dims must be integers, got {self.cart_dims!r}") from exc
        object.__setattr__(self, "history", tuple(self.history))
        if self.layering is not None and self.layering.column.size != self.cells.num:
            raise GridError("layering must have one column/layer entry per cell")
        _check_range(self.cells.faces, 0, self.faces.num, "cells.faces", "faces")
        _check_range(self.faces.nodes, 0, self.nodes.num, "faces.nodes", "nodes")
        _check_range(self.faces.neighbors, -1, self.cells.num, "faces.neighbors", "cells")

    @property
    def num_cells(self) -> int:
        return self.cells.num

    @property
    def num_faces(self) -> int:
        return self.faces.num

    @property
    def num_nodes(self) -> int:
        return self.nodes.num

    @property
    def dim(self) -> int:
        """Number of coordinate components (2 or 3)."""
        return self.nodes.coords.shape[1]

    @property
    def is_surface(self) -> bool:
        """A 2-D grid whose nodes live in 3-D (a triangulated horizon, say)."""
        return self.griddim == 2 and self.dim == 3

    def with_history(self, name: str, **changes: object) -> Grid:
        """A copy with ``name`` appended to the history and fields replaced."""
        return replace(self, history=(*self.history, name), **changes)

    def __repr__(self) -> str:
        kind = "surface" if self.is_surface else f"{self.griddim}D"
        dims = f", cart_dims={self.cart_dims}" if self.cart_dims else ""
        return (
            f"Grid({kind}, cells={self.num_cells}, faces={self.num_faces}, "
            f"nodes={self.num_nodes}{dims}, history={list(self.history)})"
        )
