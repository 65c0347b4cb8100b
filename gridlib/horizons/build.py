"""Horizons from their sources (the computation of the workflow's horizons stage).

A source is a :class:`HorizonSource`: scattered picks, a gridded
:class:`~gridlib.horizons.surface.Surface` or a formula, already read.
:func:`gridlib.io.horizon_files.build_horizons` reads the specifications of a
case (and the files they name) into sources and calls
:func:`horizons_from_sources`.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ..errors import InputError
from ..grid import FloatArray
from ._constants import check_choice
from .analytic import dome, peaks, plane
from .blocks import DepthFunction, FaultBlocks, bounding_box, fault_blocks, footwall_top, with_surfaces
from .dataset import horizon_dataset
from .interpolate import interpolate_points
from .ordering import order_horizons
from .residuals import pick_residuals

SOURCES = ("points", "surface", "plane", "dome", "peaks")
MAX_PASSES = 8  # of the picks' classification by inclined fault surfaces placed at the footwall tops


class HorizonSource(NamedTuple):
    """One horizon's source, read: its ``name``, ``label`` for messages (``horizons[k] ('name')``),
    ``kind`` (one of :data:`SOURCES`), ``data`` (the picks (n, 3), the
    :class:`~gridlib.horizons.surface.Surface`, or the formula's parameters), the ``spec`` it
    came from (its options) and ``source``, what it was read from (a file name or a label)."""

    name: str
    label: str
    kind: str
    data: Any
    spec: Mapping[str, Any]
    source: str


def check_lattice(x: ArrayLike, y: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The lattice axes ``x``, ``y`` as float arrays, checked: finite, 1-D, strictly increasing."""
    xa, ya = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    for key, a in (("x", xa), ("y", ya)):
        if a.ndim != 1 or a.size < 1 or not np.isfinite(a).all() or (np.diff(a) <= 0).any():
            raise InputError(f"horizons: the lattice axis {key} must be finite, 1-D and strictly increasing")
    return xa, ya


def horizons_from_sources(
    loaded: Sequence[HorizonSource],
    xa: FloatArray,
    ya: FloatArray,
    *,
    ordering: str = "error",
    faults: Sequence[Any] = (),
    per_block: bool = False,
    fault_surfaces: Callable[[DepthFunction], Sequence[Any]] | None = None,
    attrs: Mapping[str, Any] | None = None,
) -> xr.Dataset:
    """The horizons Dataset of the sources ``loaded``, top first, on the lattice of axes ``xa``,
    ``ya`` (:func:`check_lattice`); the options as in
    :func:`gridlib.io.horizon_files.build_horizons`, and ``fault_surfaces`` (with ``per_block``):
    the faults placed on a top horizon's depth function (``fault_surfaces(top)`` -> FaultTraces in
    the order of ``faults``, inclined ones with their ``surface``); see :func:`block_surfaces`.

    >>> x, y = np.linspace(0.0, 400.0, 5), np.linspace(0.0, 200.0, 3)
    >>> top = HorizonSource("top", "top", "plane", {"depth": 1000.0}, {}, "plane")
    >>> ds = horizons_from_sources([top], x, y)
    >>> ds.depth.shape, float(ds.depth.max())
    ((1, 3, 5), 1000.0)
    """
    X, Y = np.meshgrid(xa, ya)
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
    by_block, placed = None, None
    if per_block:
        if not faulted:
            raise InputError("horizons: per-fault-block surfaces need fault traces")
        by_block, placed = block_surfaces(
            loaded, depths, fault_blocks(faults, extent), faults, xa, ya, ordering, fault_surfaces, notes
        )
        depths = list(np.take_along_axis(by_block, block[None, None], axis=0)[0])
    ds = horizon_dataset(
        np.stack(depths),
        xa,
        ya,
        names=[item.name for item in loaded],
        ordering=ordering,
        block=block,
        sources=[item.source for item in loaded],
        methods=[_method(item) for item in loaded],
        notes=notes,
        attrs=attrs,
    )
    if by_block is not None:
        ds["depth_by_block"] = _by_block_variable(by_block, faults, extent)
    return ds.assign(_pick_variables(loaded, ds, placed))


def _pick_variables(loaded: Sequence[HorizonSource], ds: xr.Dataset, placed: FaultBlocks | None):
    """The picks of the horizons given by points and their residuals against the final surfaces
    (:mod:`gridlib.horizons.residuals`), as the Dataset's variables over ``pick``: ``pick_horizon``,
    ``pick_x``, ``pick_y``, ``pick_depth``, ``pick_residual``, ``pick_block``. ``placed``: the
    fault blocks the picks went to where every block has its own surfaces (``depth_by_block``)."""
    picks = [
        (k, item.data, None if placed is None else placed.classify(*item.data.T))
        for k, item in enumerate(loaded)
        if item.kind == "points"
    ]
    by_block = ds["depth_by_block"].values if "depth_by_block" in ds else None
    r = pick_residuals(picks, ds["depth"].values, ds["x"].values, ds["y"].values, by_block)
    length = {"units": "m"}
    return {
        "pick_horizon": ("pick", r.horizon, {"long_name": "index of the pick's horizon (top first)"}),
        "pick_x": ("pick", r.x, {**length, "long_name": "x of the pick"}),
        "pick_y": ("pick", r.y, {**length, "long_name": "y of the pick"}),
        "pick_depth": ("pick", r.depth, {**length, "positive": "down", "long_name": "depth of the pick"}),
        "pick_residual": (
            "pick",
            r.residual,
            {
                **length,
                "long_name": "pick depth minus its horizon's surface depth there (NaN: undefined)",
            },
        ),
        "pick_block": (
            "pick",
            r.block,
            {"long_name": "fault block whose surface the pick was compared with (-1: the horizon's depth)"},
        ),
    }


def _method(item: HorizonSource) -> str:
    """How a horizon was made, for the Dataset's ``method``."""
    if item.kind == "points":
        return str(item.spec.get("method", "linear"))
    if item.kind == "surface":
        return f"resampled ({item.spec.get('method', 'linear')})"
    return item.kind


def _by_block_variable(by_block: FloatArray, faults: Sequence[Any], extent) -> xr.DataArray:
    """``depth_by_block`` (fault_block, horizon, y, x), with the traces and the area it was cut in."""
    traces = [np.asarray(getattr(f, "points", f), dtype=np.float64).tolist() for f in faults]
    return xr.DataArray(
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


def block_surfaces(
    loaded: Sequence[HorizonSource],
    depths: Sequence[FloatArray],
    blocks: FaultBlocks,
    faults: Sequence[Any],
    xa: FloatArray,
    ya: FloatArray,
    ordering: str,
    fault_surfaces: Callable[[DepthFunction], Sequence[Any]] | None,
    notes: list[str],
) -> tuple[FloatArray, FaultBlocks]:
    """(block, horizon, y, x): every horizon of every block of ``blocks`` (cut by the traces
    ``faults``) over the whole lattice, from its own picks, ordered; and the blocks that placed
    the picks (``blocks`` with the inclined faults' surfaces where there are such faults).

    A pick goes to the block its position lies in, or, where a fault is inclined, to the block
    on its side of the fault surface at the pick's own depth. An inclined fault's trace is its
    footwall cut-off (where it meets the top horizon of the block on its footwall side), so its
    surface (``fault_surfaces``) needs that block's top, which needs the picks' blocks: the picks
    are first placed in plan, the surfaces built at the footwall tops
    (:func:`~gridlib.horizons.blocks.footwall_top`), the picks placed by them, and so on until
    the tops no longer change (one or two passes; an InputError after MAX_PASSES). The result is
    a fixed point: the surfaces built at its tops place every pick where it is.
    """
    out = _by_block(loaded, depths, blocks, xa, ya, ordering)
    if fault_surfaces is None:
        return out, blocks
    for passes in range(1, MAX_PASSES + 1):
        placed = fault_surfaces(footwall_top(blocks, out[:, 0], xa, ya, faults))
        inclined = [
            f.name for f in placed if getattr(f, "surface", None) is not None and not f.surface.is_vertical
        ]
        if not inclined:
            return out, blocks
        surfaced = with_surfaces(blocks, placed)
        new = _by_block(loaded, depths, surfaced, xa, ya, ordering)
        settled = np.array_equal(new[:, 0], out[:, 0], equal_nan=True)
        out = new
        if settled:
            notes.append(
                f"picks per fault block placed by the surfaces of the inclined faults {inclined} at the "
                f"footwall tops: a fixed point after {passes} pass(es)"
            )
            return out, surfaced
    raise InputError(
        f"horizons: the picks' blocks and the footwall tops of the inclined faults {inclined} do not "
        f"settle in {MAX_PASSES} passes (picks of the top horizon that change sides as its surfaces move); "
        "check the top horizon's picks next to the faults"
    )


def _by_block(loaded, depths, blocks, xa, ya, ordering: str) -> FloatArray:
    """(block, horizon, y, x): every horizon of every block over the whole lattice, ordered."""
    out = np.empty((blocks.num, len(loaded), ya.size, xa.size))
    for k, item in enumerate(loaded):
        if item.kind != "points":
            out[:, k] = depths[k]
            continue
        pts, spec = item.data, item.spec
        of_point = blocks.classify(pts[:, 0], pts[:, 1], pts[:, 2])  # by inclined faults at the depth
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


def _point_options(spec: Mapping[str, Any]) -> dict[str, Any]:
    """The interpolation options of a points horizon, with their defaults."""
    return {
        "method": spec.get("method", "linear"),
        "extrapolation": spec.get("extrapolation", "nan"),
        "smoothing": spec.get("smoothing", 0.0),
        "neighbors": spec.get("neighbors"),
    }


def _make_one(item: HorizonSource, X, Y, xa, ya, faults, extent, notes: list[str]) -> FloatArray:
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
