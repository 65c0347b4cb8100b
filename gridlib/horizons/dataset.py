"""The horizons Dataset (depth over (horizon, y, x)) and horizons.nc."""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ..errors import InputError
from ..pillars.horizon_maps import Horizon
from ..version import __version__
from .ordering import depth_stack, horizon_names, order_horizons


def horizon_dataset(
    depth: ArrayLike | Sequence[ArrayLike],
    x: ArrayLike,
    y: ArrayLike,
    *,
    names: Sequence[str] | None = None,
    ordering: str = "error",
    block: ArrayLike | None = None,
    sources: Sequence[str] | None = None,
    methods: Sequence[str] | None = None,
    notes: Sequence[str] = (),
    attrs: Mapping[str, Any] | None = None,
) -> xr.Dataset:
    """The horizons Dataset: ``depth`` (horizon, y, x) in m (z is depth, positive down, NaN =
    undefined), ordered by ``ordering``, with coordinates ``horizon`` (names, top first), ``x``,
    ``y`` (m), per-horizon ``source`` and ``method`` labels, an optional ``block`` (y, x) fault
    block id per node, and attributes: ``ordering``, ``notes`` (JSON list), ``gridlib_version``
    and ``attrs`` (provenance: case file hash, seed, ...).

    >>> x, y = np.linspace(0.0, 400.0, 5), np.linspace(0.0, 200.0, 3)
    >>> ds = horizon_dataset([np.full((3, 5), 1000.0), np.full((3, 5), 1020.0)], x, y, names=["top", "base"])
    >>> ds.depth.dims, ds.depth.attrs["units"], [h.z[0, 0] for h in to_horizons(ds)]
    (('horizon', 'y', 'x'), 'm', [np.float64(1000.0), np.float64(1020.0)])
    """
    H, xa, ya = depth_stack(np.asarray(depth, dtype=np.float64), x, y)
    if H.shape[0] < 1:
        raise InputError("horizons: the stack is empty")
    label = horizon_names(names, H.shape[0])
    for k in range(H.shape[0]):
        if np.isnan(H[k]).all():
            raise InputError(f"horizon '{label[k]}': undefined (NaN) everywhere on the lattice")
        if np.isinf(H[k]).any():
            raise InputError(f"horizon '{label[k]}': has infinite depths (use NaN for undefined)")
    for key, a in (("x", xa), ("y", ya)):
        if a.ndim != 1 or not np.isfinite(a).all() or (np.diff(a) <= 0).any():
            raise InputError(f"horizons: the lattice axis {key} must be finite, 1-D and strictly increasing")
    H, order_notes = order_horizons(H, xa, ya, ordering=ordering, names=label)
    n = H.shape[0]
    src = ["" if s is None else str(s) for s in (sources or [""] * n)]
    met = ["" if s is None else str(s) for s in (methods or [""] * n)]
    if len(src) != n or len(met) != n:
        raise InputError(f"horizons: sources and methods need one entry per horizon ({n})")
    coords = {
        "horizon": ("horizon", np.array(label, dtype=object), {"long_name": "horizon, top (youngest) first"}),
        "y": ("y", ya, {"units": "m", "standard_name": "projection_y_coordinate", "axis": "Y"}),
        "x": ("x", xa, {"units": "m", "standard_name": "projection_x_coordinate", "axis": "X"}),
        "source": ("horizon", np.array(src, dtype=object), {"long_name": "input of each horizon"}),
        "method": ("horizon", np.array(met, dtype=object), {"long_name": "how each horizon was made"}),
    }
    data = {
        "depth": (
            ("horizon", "y", "x"),
            H,
            {"units": "m", "positive": "down", "long_name": "depth of the horizon (NaN = undefined)"},
        )
    }
    if block is not None:
        b = np.asarray(block)
        if b.shape != (ya.size, xa.size):
            raise InputError(f"horizons: block must have shape ({ya.size}, {xa.size}), got {b.shape}")
        data["block"] = (("y", "x"), b.astype(np.int32), {"long_name": "fault block of each node"})
    ds_attrs: dict[str, Any] = {
        "Conventions": "CF-1.11",
        "title": "gridlib horizons",
        "gridlib_version": __version__,
        "ordering": ordering,
        "notes": json.dumps([*notes, *order_notes]),
    }
    for key, value in (attrs or {}).items():
        if isinstance(value, bool) or value is None:
            value = json.dumps(value)
        elif not isinstance(value, str | int | float | np.integer | np.floating):
            value = json.dumps(value)
        ds_attrs[str(key)] = value
    return xr.Dataset(data, coords=coords, attrs=ds_attrs)


def to_horizons(ds: xr.Dataset) -> list[Horizon]:
    """Each horizon of the Dataset as a :class:`~gridlib.cornerpoint.between_horizons.Horizon` (x, y axes,
    z[j, i]), top first: the input of :func:`~gridlib.cornerpoint.between_horizons.horizons_to_grdecl`."""
    x, y = ds["x"].values, ds["y"].values
    return [Horizon(x, y, ds["depth"].values[k]) for k in range(ds.sizes["horizon"])]
