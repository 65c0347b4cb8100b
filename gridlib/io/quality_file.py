"""``quality.nc``: the per-cell quality measures of a case's grid (:mod:`gridlib.quality`).

One float64 variable over the ``cell`` dimension per measure of
:data:`gridlib.quality.MEASURES` the grid has (``k_orientation_error`` only with rock), named
as the measure (xtgeo's names where xtgeo has the measure), each with its ``units`` (``degree``
for angles, ``1`` for ratios: the same in every unit system; none for the flags), ``long_name`` (the
measure's description) and ``hexahedral_only`` (1: NaN on cells that are not corner-point
hexahedra). The global attribute ``qc`` holds the results of the case's ``qc:`` rules
(a JSON list, :func:`gridlib.stages.quality.check_rules`), ``unit_system`` the grid's; the
others are the case's provenance. ``{case}.nc`` holds the same variables.
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping
from functools import partial
from typing import Any

import numpy as np
import xarray as xr

from ..quality import MEASURE, MEASURES, Measure
from ..units import METRIC
from .datasets import damaged, open_artifact, read_variable
from .deferred import Deferred, deferring
from .netcdf import write_dataset
from .quantities import FLAG_NAMES

FLAGS = FLAG_NAMES  # the flags of xtgeo's set: counted, not binned; no units


def measure_units(measure: Measure) -> str | None:
    """The ``units`` of a measure's values (degree, 1): the same in every unit system; None for
    a flag (:data:`FLAGS`: no physical quantity, no ``units``, as CF wants for flags)."""
    return None if measure.name in FLAGS else METRIC.unit(measure.unit)


def quality_variables(values: Mapping[str, np.ndarray], dim: str = "cell") -> dict[str, xr.DataArray]:
    """The variables of ``quality.nc`` (also written into ``{case}.nc``), in the order of
    :data:`~gridlib.quality.MEASURES`, with their attributes."""
    return {
        m.name: xr.DataArray(
            np.asarray(values[m.name], dtype=np.float64), dims=(dim,), attrs=measure_attrs(m)
        )
        for m in MEASURES
        if m.name in values
    }


def measure_attrs(measure: Measure) -> dict[str, Any]:
    """The attributes of a measure's variable: ``units`` (none for a flag), ``long_name`` and
    ``hexahedral_only``."""
    units = measure_units(measure)
    return {
        **({} if units is None else {"units": units}),
        "long_name": measure.description,
        "hexahedral_only": np.int8(measure.hexahedral_only),
    }


def write_quality(
    path: str | os.PathLike,
    values: Mapping[str, np.ndarray],
    attrs: Mapping[str, Any],
    qc: list[dict[str, Any]] | None = None,
) -> None:
    """``quality.nc``: the measures ``values`` (name -> one value per cell), the results of
    the case's qc rules ``qc`` and the provenance ``attrs``; atomically."""
    unknown = sorted(set(values) - set(MEASURE))
    if unknown:
        raise ValueError(f"write_quality: {', '.join(unknown)}: no measure of gridlib.quality")
    ds = xr.Dataset(
        quality_variables(values),
        attrs={**attrs, "title": "gridlib cell quality", "qc": json.dumps(qc or [])},
    )
    write_dataset(path, ds)


def read_quality(path: str | os.PathLike) -> tuple[dict[str, np.ndarray], list[dict[str, Any]]]:
    """The measures of ``quality.nc`` (or of a ``{case}.nc`` that holds them) by name, in the
    order of :data:`~gridlib.quality.MEASURES`, and the results of its qc rules (an empty
    list where the file has none); one InputError naming the file if it holds no measure or
    measures of different lengths."""
    with open_artifact(path) as ds:
        values = {m.name: read_variable(ds, m.name, "f", 1) for m in MEASURES if m.name in ds.variables}
        text = str(ds.attrs.get("qc", "[]"))
    return values, _checked(path, {name: v.shape for name, v in values.items()}, text)


def deferred_quality(
    path: str | os.PathLike,
) -> tuple[dict[str, np.ndarray | Deferred], list[dict[str, Any]]]:
    """:func:`read_quality` with each measure a :class:`~gridlib.io.deferred.Deferred` float64
    array, read from ``path`` each time it is used (a writer holds one at a time), unless the
    measures are small enough to be read at once (:func:`~gridlib.io.deferred.deferring`);
    the same errors, raised here (or by a read of a measure whose data turns out damaged)."""
    with open_artifact(path) as ds:
        shapes = {m.name: ds[m.name].shape for m in MEASURES if m.name in ds.variables}
        text = str(ds.attrs.get("qc", "[]"))
        qc = _checked(path, shapes, text)
        float64 = np.dtype(np.float64).itemsize
        if not deferring(sum(int(np.prod(shape)) for shape in shapes.values()) * float64):
            return {name: _measure(ds, name) for name in shapes}, qc
    values = {
        name: Deferred(shape, np.dtype(np.float64), partial(_read_measure, path, name), f"{path}: {name}")
        for name, shape in shapes.items()
    }
    return values, qc


def _read_measure(path: str | os.PathLike, name: str) -> np.ndarray:
    with open_artifact(path) as ds:
        return _measure(ds, name)


def _measure(ds: xr.Dataset, name: str) -> np.ndarray:
    return np.asarray(read_variable(ds, name, "f", 1), dtype=np.float64)


def _checked(path: str | os.PathLike, shapes: Mapping[str, tuple[int, ...]], qc: str) -> list[dict[str, Any]]:
    """The qc results of ``qc`` (JSON), or the InputError of a file with no measure, with
    measures of different lengths or a ``qc`` that is not JSON."""
    if not shapes:
        raise damaged(path, "not a quality file: it holds no measure of gridlib.quality")
    sizes = {int(np.prod(shape)) for shape in shapes.values()}
    if len(sizes) > 1:
        raise damaged(path, f"its measures differ in length ({sorted(sizes)})")
    try:
        return json.loads(qc)
    except json.JSONDecodeError:
        raise damaged(path, "its attribute 'qc' is not JSON") from None
