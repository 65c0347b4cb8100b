"""Analytic horizons: plane (dip, azimuth), Gaussian dome, MATLAB's peaks."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ..errors import InputError
from ..grid import FloatArray
from ..reproducible import exp


def plane(
    x: ArrayLike,
    y: ArrayLike,
    *,
    depth: float,
    dip: float = 0.0,
    azimuth: float = 0.0,
    x0: float = 0.0,
    y0: float = 0.0,
) -> FloatArray:
    """A plane through depth ``depth`` (m) at ``(x0, y0)``, dipping ``dip`` degrees towards
    ``azimuth`` (degrees clockwise from north = +y; 90 = east = +x): depth increases along
    the azimuth, z = depth + tan(dip) ((x - x0) sin(azimuth) + (y - y0) cos(azimuth)).

    >>> plane([0.0, 100.0], [0.0, 0.0], depth=1000.0, dip=45.0, azimuth=90.0).round(9).tolist()
    [1000.0, 1100.0]
    """
    x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
    if not 0.0 <= dip < 90.0:
        raise InputError(f"plane: dip must be in [0, 90) degrees, got {dip!r}")
    a = math.radians(azimuth)
    g = math.sin(math.radians(dip)) / math.cos(math.radians(dip))  # tan(dip), from sin and cos
    return depth + g * ((x - x0) * math.sin(a) + (y - y0) * math.cos(a))


def dome(
    x: ArrayLike,
    y: ArrayLike,
    *,
    depth: float,
    relief: float,
    radius: float,
    x0: float = 0.0,
    y0: float = 0.0,
) -> FloatArray:
    """A Gaussian dome: depth ``depth`` (m) at its crest ``(x0, y0)``, ``relief`` (m) deeper far
    from it, z = depth + relief (1 - exp(-r^2 / radius^2)), r the distance to the crest (m).

    >>> dome([0.0, 1e6], [0.0, 0.0], depth=1000.0, relief=50.0, radius=500.0).tolist()
    [1000.0, 1050.0]
    """
    if not radius > 0:
        raise InputError(f"dome: radius must be positive, got {radius!r}")
    x, y = np.broadcast_arrays(np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64))
    r2 = ((x - x0) ** 2 + (y - y0) ** 2) / radius**2
    return depth + relief * (1.0 - exp(-r2))


def peaks(
    x: ArrayLike,
    y: ArrayLike,
    *,
    depth: float = 0.0,
    amplitude: float = 1.0,
    length: float = 1.0,
    x0: float = 0.0,
    y0: float = 0.0,
) -> FloatArray:
    """MATLAB's ``peaks`` as a depth map: z = depth + amplitude P(u, v), u = (x - x0) / length,
    v = (y - y0) / length, P(u, v) = 3 (1-u)^2 exp(-u^2 - (v+1)^2) - 10 (u/5 - u^3 - v^5)
    exp(-u^2 - v^2) - exp(-(u+1)^2 - v^2) / 3 (peaks(n) samples u, v in [-3, 3]).

    The MRST book's ``[y,x,z] = peaks(15); z = z+8`` names MATLAB's X axis y, so its top
    horizon is ``peaks(y, x, depth=8.0)`` at ``x, y = meshgrid(linspace(-3, 3, 15))``
    (z is depth, so the peaks point down).

    >>> round(float(peaks(0.0, 0.0)), 9)  # 8 / (3 e)
    0.981011843
    """
    if not length > 0:
        raise InputError(f"peaks: length must be positive, got {length!r}")
    u = (np.asarray(x, dtype=np.float64) - x0) / length
    v = (np.asarray(y, dtype=np.float64) - y0) / length
    p = (
        3.0 * (1.0 - u) ** 2 * exp(-(u**2) - (v + 1.0) ** 2)
        - 10.0 * (u / 5.0 - u * u * u - v * v * v * v * v) * exp(-(u**2) - v**2)
        - exp(-((u + 1.0) ** 2) - v**2) / 3.0
    )
    return depth + amplitude * p
