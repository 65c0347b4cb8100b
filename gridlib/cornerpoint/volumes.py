"""Bulk volumes of corner-point cells as ECLIPSE and OPM Flow define them.

Each cell on its own is a hexahedron of its eight corners; each of its six
faces is split into four triangles about the mean of the face's four corners
(24 tetrahedra in all). This is the volume simulators multiply by porosity
for the pore volume (OPM Flow's PORV / PORO / NTG / MULTPV reproduces it to
float32 precision on every deck we have).

It differs from :func:`gridlib.compute_geometry` on the processed grid only
where faces are warped and subdivided: the processed grid's faces are shared
by the cells on both sides of a fault (so volumes add up exactly and cells are
watertight), while each hexahedron here is independent of its neighbours.
For planar faces the two agree to round-off.
"""

from __future__ import annotations

import numpy as np

from ..grid import FloatArray, IntArray

# Corner slots a + 2b + 4c (a: +i, b: +j, c: bottom) of the six faces, each cycle
# with its normal pointing out of the cell in a right-handed (i, j, k) frame.
_FACES = np.array(
    [
        [0, 4, 6, 2],  # W (-i)
        [1, 3, 7, 5],  # E (+i)
        [0, 1, 5, 4],  # S (-j)
        [2, 6, 7, 3],  # N (+j)
        [0, 2, 3, 1],  # T (-k)
        [4, 5, 7, 6],  # B (+k)
    ]
)


def hexahedron_volumes(
    xyz: FloatArray, corners: IntArray, cells: IntArray | None = None, chunk: int = 16384
) -> FloatArray:
    """Signed 24-tetrahedron volume of the hexahedra ``corners[:, cells]`` (all columns if None).

    ``corners`` (8, n) holds node ids into ``xyz``, one row per corner slot
    a + 2b + 4c. Positive for cells whose (i, j, k) corner order is
    right-handed. Each face contributes ``h . N / 3`` with ``h`` the mean of its
    corners and ``N`` its vector area (half the cross product of its
    diagonals); coordinates are taken relative to each cell's first corner, so
    UTM-size offsets cost no precision.
    """
    coords = np.ascontiguousarray(xyz.T)  # component-major: gathers of one component are fast
    n = corners.shape[1] if cells is None else cells.size
    out = np.empty(n)
    for start in range(0, n, chunk):  # blocks of cells small enough to stay in cache
        part = slice(start, start + chunk)
        p = np.take(coords, corners[:, part if cells is None else cells[part]], axis=1)  # (3, 8, m)
        p -= p[:, :1].copy()
        vol = np.zeros(p.shape[2])
        for face in _FACES:
            p0, p1, p2, p3 = (p[:, s] for s in face)
            d, e = p2 - p0, p3 - p1
            nx = 0.5 * (d[1] * e[2] - d[2] * e[1])
            ny = 0.5 * (d[2] * e[0] - d[0] * e[2])
            nz = 0.5 * (d[0] * e[1] - d[1] * e[0])
            h = 0.25 * (p0 + p1 + p2 + p3)
            # Summed in the order numpy's einsum("ij,ij->i") uses for three terms, so
            # that volumes stay bit-identical to those computed with it.
            vol += (h[0] * nx + h[2] * nz) + h[1] * ny
        out[part] = vol / 3.0
    return out
