"""Horizons from a list of specifications (the workflow's horizons stage)."""

from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ..errors import InputError
from ..grid import FloatArray
from ._constants import check_choice
from .analytic import dome, peaks, plane
from .blocks import bounding_box, fault_blocks
from .dataset import horizon_dataset
from .interpolate import interpolate_points
from .lattice import Surface, read_surface_netcdf
from .points import read_points

_SOURCES = ("points", "surface", "plane", "dome", "peaks")
_POINT_KEYS = {
    "name",
    "points",
    "method",
    "extrapolation",
    "smoothing",
    "neighbors",
    "columns",
    "elevation",
    "null",
}
_SURFACE_KEYS = {"name", "surface", "method", "variable", "horizon", "elevation"}


def build_horizons(
    specs: Sequence[Mapping[str, Any]],
    x: ArrayLike,
    y: ArrayLike,
    *,
    ordering: str = "error",
    faults: Sequence[Any] = (),
    per_block: bool = False,
    base_dir: str | os.PathLike = ".",
    attrs: Mapping[str, Any] | None = None,
) -> xr.Dataset:
    """The horizons Dataset of a list of horizon specifications, top first (the horizons stage).

    Each spec is a mapping with ``name`` and exactly one source:

    * ``points``: a file (CSV/text, :func:`read_points`; with ``columns``,
      ``elevation``, ``null``) or an (n, 3) array, interpolated with ``method``
      (default linear), ``extrapolation`` (default nan), ``smoothing``,
      ``neighbors``, per fault block of ``faults``;
    * ``surface``: an IRAP classic ASCII file (any suffix but ``.nc``) or a
      netCDF file (``variable``, ``horizon``), or a :class:`Surface`, resampled
      with ``method`` ``linear`` (default) or ``nearest``; ``elevation``. A
      gridded surface is taken as it is (``faults`` do not apply): a throw in it
      stays within one of its cells;
    * ``plane``, ``dome`` or ``peaks``: the keyword arguments of :func:`plane`,
      :func:`dome` or :func:`peaks`.

    ``per_block`` (with ``faults``): the picks are of already-faulted surfaces. Each fault
    block then also gets its own surfaces over the whole lattice, from its own picks only,
    extended with each horizon's ``extrapolation`` (give ``trend`` or ``nearest``): the
    variable ``depth_by_block`` (fault_block, horizon, y, x), ordered per block, for
    :func:`~gridlib.horizons.by_block.horizons_to_grdecl_by_block`; ``depth`` is then each
    node's own block's value. Formulas and gridded surfaces are the same in every block.

    Relative paths are relative to ``base_dir``. Errors name the spec, e.g.
    ``horizons[1] ('base'): method: unknown value 'spline'; expected one of ...``.

    >>> x, y = np.linspace(0.0, 400.0, 5), np.linspace(0.0, 200.0, 3)
    >>> top = {"name": "top", "plane": {"depth": 1000.0, "dip": 1.0, "azimuth": 90.0}}
    >>> base = {"name": "base", "dome": {"depth": 1010.0, "relief": 5.0, "radius": 300.0}}
    >>> ds = build_horizons([top, base], x, y)
    >>> ds.depth.shape, list(ds.horizon.values), list(ds.method.values)
    ((2, 3, 5), ['top', 'base'], ['plane', 'dome'])
    """
    if isinstance(specs, Mapping) or not isinstance(specs, Sequence) or not specs:
        raise InputError("horizons: expected a non-empty list of horizon specifications (top first)")
    xa, ya = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    for key, a in (("x", xa), ("y", ya)):
        if a.ndim != 1 or a.size < 1 or not np.isfinite(a).all() or (np.diff(a) <= 0).any():
            raise InputError(f"horizons: the lattice axis {key} must be finite, 1-D and strictly increasing")
    X, Y = np.meshgrid(xa, ya)
    base = Path(base_dir)
    loaded = [_load_one(k, spec, base) for k, spec in enumerate(specs)]
    faulted = faults is not None and len(faults) > 0
    extent = None
    if faulted:  # one area for every horizon, so that all see the same blocks
        point_sets = [item.data for item in loaded if item.kind == "points"]
        extent = bounding_box(X, Y, *(c for pts in point_sets for c in (pts[:, 0], pts[:, 1])))
    depths, notes = [], []
    for item in loaded:
        try:
            depths.append(_make_one(item, X, Y, xa, ya, faults, extent, notes))
        except TypeError as exc:  # bad keyword arguments of a formula
            raise InputError(f"{item.label}: {item.kind}: {exc}") from exc
    block = fault_blocks(faults, extent).classify(X, Y) if faulted else None
    by_block = None
    if per_block:
        if not faulted:
            raise InputError("horizons: per-fault-block surfaces need fault traces")
        by_block = _by_block(loaded, depths, fault_blocks(faults, extent), xa, ya, ordering)
        depths = list(np.take_along_axis(by_block, block[None, None], axis=0)[0])
    methods = [
        str(item.spec.get("method", "linear")) if item.kind == "points"
        else f"resampled ({item.spec.get('method', 'linear')})" if item.kind == "surface"
        else item.kind
        for item in loaded
    ]  # fmt: skip
    ds = horizon_dataset(
        np.stack(depths),
        xa,
        ya,
        names=[item.name for item in loaded],
        ordering=ordering,
        block=block,
        sources=[item.source for item in loaded],
        methods=methods,
        notes=notes,
        attrs=attrs,
    )
    if by_block is not None:
        traces = [np.asarray(getattr(f, "points", f), dtype=np.float64).tolist() for f in faults]
        ds["depth_by_block"] = xr.DataArray(
            by_block,
            dims=("fault_block", "horizon", "y", "x"),
            attrs={
                "units": "m",
                "positive": "down",
                "long_name": "depth of each fault block's surface (from its own picks)",
                "traces": json.dumps(traces),
                "extent": list(extent),
            },
        )
    return ds


def _by_block(loaded, depths, blocks, xa, ya, ordering: str) -> FloatArray:
    """(block, horizon, y, x): every horizon of every block over the whole lattice, ordered."""
    from .ordering import order_horizons

    out = np.empty((blocks.num, len(loaded), ya.size, xa.size))
    for k, item in enumerate(loaded):
        if item.kind != "points":
            out[:, k] = depths[k]
            continue
        pts, spec = item.data, item.spec
        of_point = blocks.classify(pts[:, 0], pts[:, 1])
        for b in range(blocks.num):
            mine = pts[of_point == b]
            if mine.shape[0] < 3:
                raise InputError(
                    f"{item.label}: fault block {b} has {mine.shape[0]} pick(s); a per-block surface "
                    "needs at least 3"
                )
            out[b, k] = interpolate_points(
                mine, xa, ya, **_point_options(spec), name=f"{item.label} (fault block {b})"
            )
    names = [item.name for item in loaded]
    for b in range(blocks.num):
        out[b], _ = order_horizons(out[b], xa, ya, ordering=ordering, names=names)
    return out


class _Loaded(NamedTuple):
    name: str
    label: str  # for messages: horizons[k] ('name')
    kind: str  # one of _SOURCES
    data: Any  # the points (n, 3), the Surface, or the formula's parameters
    spec: Mapping[str, Any]
    source: str


def _load_one(k: int, spec: Any, base: Path) -> _Loaded:
    """One spec checked, its file (if any) read."""
    if not isinstance(spec, Mapping):
        raise InputError(f"horizons[{k}]: expected a mapping, got {type(spec).__name__}")
    name = spec.get("name")
    if not isinstance(name, str) or not name:
        raise InputError(f"horizons[{k}]: name: a non-empty string is required")
    label = f"horizons[{k}] ('{name}')"
    given = [s for s in _SOURCES if s in spec]
    if len(given) != 1:
        raise InputError(f"{label}: give exactly one of {', '.join(_SOURCES)} (got {given or 'none'})")
    kind = given[0]
    allowed = _POINT_KEYS if kind == "points" else _SURFACE_KEYS if kind == "surface" else {"name", kind}
    extra = set(spec) - allowed
    if extra:
        raise InputError(f"{label}: unknown keys {sorted(extra)} for {kind} (allowed: {sorted(allowed)})")
    src = spec[kind]
    if kind in ("plane", "dome", "peaks"):
        if not isinstance(src, Mapping):
            raise InputError(f"{label}: {kind}: expected a mapping of its parameters")
        return _Loaded(name, label, kind, src, spec, f"{kind} {json.dumps(dict(src), sort_keys=True)}")
    if kind == "points":
        if isinstance(src, str | os.PathLike):
            path = base / src
            pts = read_points(
                path,
                columns=spec.get("columns"),
                elevation=bool(spec.get("elevation", False)),
                null=spec.get("null"),
            )
            return _Loaded(name, label, kind, pts, spec, str(path))
        try:
            pts = np.asarray(src, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise InputError(f"{label}: points: not a file name or an (n, 3) array ({exc})") from exc
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise InputError(f"{label}: points: expected an (n, 3) array of x, y, z, got shape {pts.shape}")
        return _Loaded(name, label, kind, pts, spec, "points (array)")
    if isinstance(src, Surface):
        return _Loaded(name, label, kind, src, spec, src.source or f"surface '{src.name}'")
    path = base / src
    elevation = bool(spec.get("elevation", False))
    if path.suffix.lower() == ".nc":
        surf = read_surface_netcdf(
            path, variable=spec.get("variable"), horizon=spec.get("horizon"), elevation=elevation
        )
    else:
        from ..io.irap import read_irap

        surf = read_irap(path, elevation=elevation)
    return _Loaded(name, label, kind, surf, spec, str(path))


def _point_options(spec: Mapping[str, Any]) -> dict[str, Any]:
    """The interpolation options of a points horizon, with their defaults."""
    return {
        "method": spec.get("method", "linear"),
        "extrapolation": spec.get("extrapolation", "nan"),
        "smoothing": spec.get("smoothing", 0.0),
        "neighbors": spec.get("neighbors"),
    }


def _make_one(item: _Loaded, X, Y, xa, ya, faults, extent, notes: list[str]) -> FloatArray:
    spec, kind, data, label = item.spec, item.kind, item.data, item.label
    if kind in ("plane", "dome", "peaks"):
        fn = {"plane": plane, "dome": dome, "peaks": peaks}[kind]
        return fn(X, Y, **data)
    if kind == "points":
        return interpolate_points(
            data,
            xa,
            ya,
            **_point_options(spec),
            faults=faults,
            extent=extent,
            name=label,
            notes=notes,
        )
    method = check_choice(spec.get("method", "linear"), ("linear", "nearest"), f"{label}: method")
    z = data.sample(X, Y, method=method)
    if np.isnan(z).all():
        raise InputError(
            f"{label}: {data.source or 'the surface'} is undefined (NaN) everywhere on the lattice"
        )
    return z
