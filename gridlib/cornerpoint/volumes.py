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


def hexahedron_volumes(xyz: FloatArray, corners: IntArray, chunk: int = 131072) -> FloatArray:
    """Signed 24-tetrahedron volume of hexahedra given by ``corners`` (n, 8) into ``xyz``.

    Positive for cells whose (i, j, k) corner order is right-handed. Each
    face contributes ``h . N / 3`` with ``h`` the mean of its corners and ``N``
    its vector area (half the cross product of its diagonals); coordinates are
    taken relative to each cell's first corner, so UTM-size offsets cost no
    precision.
    """
    n = corners.shape[0]
    out = np.empty(n)
    for start in range(0, n, chunk):  # bounded memory: about 400 bytes per cell in flight
        c = corners[start : start + chunk]
        origin = xyz[c[:, 0]]
        vol = np.zeros(c.shape[0])
        for face in _FACES:
            p = [xyz[c[:, s]] - origin for s in face]
            normal = 0.5 * np.cross(p[2] - p[0], p[3] - p[1])
            hinge = 0.25 * (p[0] + p[1] + p[2] + p[3])
            vol += np.einsum("ij,ij->i", hinge, normal)
        out[start : start + chunk] = vol / 3.0
    return out
