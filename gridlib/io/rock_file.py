"""``petrophysics.nc``: a case's rock, one value per cell of its ``grid.nc``.

Variables over the ``cell`` dimension: ``poro`` and ``ntg`` (fractions), ``permx``,
``permy`` and ``permz`` (mD), each with its ``units`` and, where the petrophysics stage
knows it, its ``source`` (e.g. "the deck's PORO", "petrophysics.porosity").
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np
import xarray as xr

from ..units import METRIC
from .datasets import damaged, open_artifact, read_variable
from .netcdf import write_dataset
from .quantities import quantity_of
from .shared_reads import own_arrays, read_once

PROPERTIES = ("poro", "permx", "permy", "permz", "ntg")
# Fractions and mD in every unit system (gridlib.units), so the file needs none.
UNITS = {name: METRIC.unit(quantity_of(name)) for name in PROPERTIES}


def write_rock(
    path: str | os.PathLike, rock, attrs: dict[str, Any], sources: dict[str, str] | None = None
) -> None:
    """``petrophysics.nc``: the rock's arrays (with their ``source`` where given) and ``attrs``."""
    sources = sources or {}
    data = {
        name: xr.DataArray(
            values,
            dims=("cell",),
            attrs={"units": UNITS[name], **({"source": sources[name]} if name in sources else {})},
        )
        for name, values in rock.cell_data().items()
    }
    write_dataset(path, xr.Dataset(data, attrs={**attrs, "title": "gridlib petrophysics"}))


@read_once(own_arrays)
def read_rock(path: str | os.PathLike) -> dict[str, np.ndarray]:
    """The rock arrays of ``petrophysics.nc`` by name (:data:`PROPERTIES`), one value per cell
    each; one InputError naming the file if it is damaged or incomplete, or holds a value the
    petrophysics stage never writes (negative or not finite: the stage's
    :class:`~gridlib.petrophysics.Rock` refuses them). Checked here, so that such a file is
    blamed, not the deck whose keywords its values replace later."""
    with open_artifact(path) as ds:
        rock = {name: read_variable(ds, name, "f", 1) for name in PROPERTIES}
    sizes = {values.size for values in rock.values()}
    if len(sizes) > 1:
        raise damaged(path, f"its variables {', '.join(PROPERTIES)} differ in length ({sorted(sizes)})")
    for name, values in rock.items():
        bad = int(np.count_nonzero(~(np.isfinite(values) & (values >= 0))))
        if bad:
            raise damaged(path, f"variable '{name}' has {bad} negative or undefined values")
    return rock
