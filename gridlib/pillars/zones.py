"""Zones between horizons: the layers of each zone and the depths of their interfaces.

A *zone* lies between two consecutive horizons of a stack (top first); it is
divided proportionally into its number of layers, dz = (z_{h+1} - z_h) / n at
every pillar, so that a zone of zero thickness gives layers of zero thickness
(collapsed cells, removed by the engine). Shared by the corner-point front end
(``horizons_to_grdecl``) and the 2.5D one (``extrude``).
"""

from __future__ import annotations

import numbers
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import InputError
from ..grid import FloatArray

__all__ = ["check_layers", "is_integer", "layer_levels"]


def is_integer(v: Any) -> bool:
    """An integer value: an int (not a bool) or an integral float, numpy's included."""
    if isinstance(v, bool | np.bool_):
        return False
    if isinstance(v, numbers.Integral):
        return True
    return isinstance(v, numbers.Real) and float(v).is_integer()


def check_layers(layers: int | Sequence[int], n_zones: int, who: str = "horizons_to_grdecl") -> list[int]:
    """The number of layers of each of ``n_zones`` zones from one positive integer or one per zone;
    errors name ``who``."""
    what = f"{who}: layers must be a positive integer or one per zone ({n_zones} zones)"
    if is_integer(layers):
        values = [int(layers)] * n_zones  # type: ignore[arg-type]
    else:
        try:
            values = list(layers)  # type: ignore[arg-type]
        except TypeError:
            raise InputError(f"{what}, got {layers!r}") from None
        if len(values) != n_zones:
            raise InputError(f"{what}, got {len(values)} values: {layers!r}")
        if not all(is_integer(v) for v in values):
            raise InputError(f"{what}, got {layers!r}")
        values = [int(v) for v in values]
    bad = [z for z, v in enumerate(values) if v < 1]
    if bad:
        raise InputError(f"{what}; zone {bad[0]} has {values[bad[0]]}")
    return values


def layer_levels(H: FloatArray, nlay: Sequence[int]) -> FloatArray:
    """Depths of every layer interface, top first: (sum(nlay) + 1, *H.shape[1:]), from the horizons
    ``H`` (n_horizons, ...) at the pillars; zone h has ``nlay[h]`` proportional layers and its top
    interface is exactly horizon h, even where horizon h + 1 is undefined.

    >>> layer_levels(np.array([[0.0, 10.0], [4.0, 10.0]]), [2]).tolist()
    [[0.0, 10.0], [2.0, 10.0], [4.0, 10.0]]
    """
    levels = []
    for h in range(H.shape[0] - 1):
        t = (np.arange(nlay[h]) / nlay[h]).reshape(-1, *(1,) * (H.ndim - 1))
        with np.errstate(invalid="ignore"):
            lev = H[h][None] + t * (H[h + 1] - H[h])[None]
        lev[0] = H[h]  # exactly the horizon
        levels.append(lev)
    levels.append(H[-1][None])
    return np.concatenate(levels)
