"""Where straight (possibly inclined) pillars meet a depth surface z = f(x, y).

Shared by ``gridlib.pillars.extrude`` (horizons on the pillars of an areal grid) and
``gridlib.cornerpoint.pillar_grdecl`` (horizons and fault sticks on inclined corner-point
pillars). Units are metres; z is depth, positive downwards.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..grid import FloatArray
from .horizon_maps import DepthFunction


def depth_on_pillars(
    f: DepthFunction, lines: FloatArray, who: str, *, unsettled: str = "error"
) -> FloatArray:
    """Depth (n,) where every straight pillar ``lines`` (n, 2, 3: two points x, y, z) meets the
    surface z = f(x, y): the fixed point of z = f(x(z), y(z)), started at the pillar's first point.

    It converges where |grad f| times the pillar's slope (horizontal metres per metre of depth)
    is below 1; otherwise an :class:`~gridlib.errors.InputError` starting with ``who`` says how
    many pillars did not converge (``unsettled="nan"``: their depth is NaN instead). Pillars whose
    two points differ by less than 1e-6 in depth are vertical (OPM's rule). ``f`` returns NaN
    where the surface is undefined; the depth is then NaN.

    >>> lines = np.array([[[0.0, 0.0, 0.0], [1.0, 0.0, 1.0]]])  # 45 degrees towards +x
    >>> z = depth_on_pillars(lambda x, y: 10.0 + 0.5 * x, lines, "example")  # x = z there: z = 20
    >>> round(float(z[0]), 9)
    20.0
    """
    top, bot = lines[:, 0], lines[:, 1]
    dz = bot[:, 2] - top[:, 2]
    vertical = np.abs(dz) < 1e-6
    slope = np.where(vertical[:, None], 0.0, (bot[:, :2] - top[:, :2]) / np.where(vertical, 1.0, dz)[:, None])

    def xy_at(z: np.ndarray) -> np.ndarray:
        d = np.where(np.isfinite(z), z - top[:, 2], 0.0)
        return top[:, :2] + slope * d[:, None]

    p = top[:, :2].copy()
    z = np.asarray(f(p[:, 0], p[:, 1]), dtype=np.float64)
    scale = 1.0 + float(np.nanmax(np.abs(z), initial=0.0))
    change = np.zeros_like(z)
    for _ in range(200):
        p = xy_at(z)
        new = np.asarray(f(p[:, 0], p[:, 1]), dtype=np.float64)
        with np.errstate(invalid="ignore"):
            change = np.abs(new - z)
        z = new
        if not (change > 1e-12 * scale).any():
            return z
    if unsettled == "nan":
        return np.where(change > 1e-12 * scale, np.nan, z)
    bad = int(np.count_nonzero(change > 1e-12 * scale))
    raise InputError(
        f"{who}: the depth where {bad} inclined pillars meet it does not converge "
        "(the horizon is too steep for the pillars' inclination: |grad z| x slope must be below 1)"
    )
