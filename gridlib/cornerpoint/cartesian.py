"""Corner-point geometry (COORD, ZCORN) of a Cartesian, block-centred grid: cell sizes DX, DY, DZ
and the depths of the cells' top corners (the TOPS or DEPTHZ of a deck).

>>> import numpy as np
>>> dx, dy, dz = np.full((1, 1, 2), 10.0), np.full((1, 1, 2), 5.0), np.full((1, 1, 2), 2.0)
>>> coord, zcorn = cartesian_to_cornerpoint(dx, dy, dz, np.full((1, 1, 2, 2, 2), 1000.0))
>>> coord.reshape(-1, 6)[:3].tolist()  # the pillars of the first row (j = 0)
[[0.0, 0.0, 1000.0, 0.0, 0.0, 1002.0], [10.0, 0.0, 1000.0, 10.0, 0.0, 1002.0],
 [20.0, 0.0, 1000.0, 20.0, 0.0, 1002.0]]
>>> zcorn.reshape(2, -1).tolist()  # the cells' top corners, then their bottom corners
[[1000.0, 1000.0, 1000.0, 1000.0, 1000.0, 1000.0, 1000.0, 1000.0],
 [1002.0, 1002.0, 1002.0, 1002.0, 1002.0, 1002.0, 1002.0, 1002.0]]
"""

from __future__ import annotations

import numpy as np

__all__ = ["cartesian_to_cornerpoint"]


def cartesian_to_cornerpoint(
    dx: np.ndarray, dy: np.ndarray, dz: np.ndarray, top: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """COORD and ZCORN (flat, ECLIPSE order) of a block-centred grid.

    ``dx``, ``dy``, ``dz`` (nz, ny, nx): the cell sizes, finite and >= 0.
    ``top`` (nz, ny, nx, 2, 2): the depths of every cell's four top corners
    ((j, i) order), finite in the top layer; NaN below it means "the bottom of
    the cell above" and is filled here (``top`` is modified in place).

    Cells are boxes: each cell's four top corners lie at its top depths, its
    bottom at top + DZ. Pillar positions are the running sums of DX along i
    (DY along j), from the top layer for the pillar's top point and from the
    bottom layer for its bottom point (as OPM), so the pillars are vertical
    when DX and DY do not vary with depth. The pillars run from the shallowest
    to the deepest corner of the grid (1 deeper when the grid is flat).
    """
    nz = dz.shape[0]
    for k in range(1, nz):  # a loop over layers, vectorised over each layer
        top[k] = np.where(np.isnan(top[k]), top[k - 1] + dz[k - 1][..., None, None], top[k])
    bottom = top + dz[..., None, None]
    z = np.stack([top, bottom], axis=1)  # (nz, 2, ny, nx, 2b, 2a)
    zcorn = z.transpose(0, 1, 2, 4, 3, 5).reshape(2 * nz, 2 * dz.shape[1], 2 * dz.shape[2]).ravel()

    def pillar_positions(d: np.ndarray, along: int) -> np.ndarray:
        """Running sums of cell sizes along i (along=1) or j (along=0) of one layer, per pillar."""
        run = np.cumsum(d, axis=along)
        run = np.concatenate([np.zeros_like(np.take(run, [0], axis=along)), run], axis=along)
        other = 1 - along
        return np.concatenate([run, np.take(run, [-1], axis=other)], axis=other)

    x_top, x_bot = pillar_positions(dx[0], 1), pillar_positions(dx[-1], 1)
    y_top, y_bot = pillar_positions(dy[0], 0), pillar_positions(dy[-1], 0)
    z_top, z_bot = float(zcorn.min()), float(zcorn.max())
    if z_bot == z_top:
        z_bot = z_top + 1.0
    coord = np.stack(
        [x_top, y_top, np.full_like(x_top, z_top), x_bot, y_bot, np.full_like(x_top, z_bot)], axis=-1
    )
    return coord.ravel(), zcorn
