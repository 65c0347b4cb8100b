"""Stage ``petrophysics``: rock properties per cell as ``petrophysics.nc``.

Porosity (fraction), permeability (mD; ``permz = kv_kh * permx``) and NTG
(fraction), each a constant, one value per layer, a Gaussian random field at
depositional coordinates (so that fault throw does not decorrelate it), or,
for deck grids, the deck's own keyword. Fields are seeded with the case's
seed (porosity), seed + 1 (permeability) and seed + 2 (NTG): the same case
and seed give identical arrays.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np
import xarray as xr

from ..case.rock import case_rock
from ..config import load_case
from ..io.netcdf import read_geometry_netcdf, read_netcdf, write_dataset
from .common import log

PROPERTIES = ("poro", "permx", "permy", "permz", "ntg")
UNITS = {"poro": "1", "permx": "mD", "permy": "mD", "permz": "mD", "ntg": "1"}


def write_rock(path: str | os.PathLike, rock, attrs: dict[str, Any]) -> None:
    data = {
        name: xr.DataArray(values, dims=("cell",), attrs={"units": UNITS[name]})
        for name, values in rock.cell_data().items()
    }
    write_dataset(path, xr.Dataset(data, attrs={**attrs, "title": "gridlib petrophysics"}))


def read_rock(path: str | os.PathLike) -> dict[str, np.ndarray]:
    with xr.open_dataset(path, engine="netcdf4") as ds:
        return {name: ds[name].values for name in PROPERTIES}


def stage_petrophysics(
    case_file: str | os.PathLike,
    grid_nc: str | os.PathLike,
    geometry_nc: str | os.PathLike,
    petrophysics_out: str | os.PathLike,
) -> None:
    """Sample the case's rock properties on its grid; write ``petrophysics.nc``."""
    case = load_case(case_file)
    grid = read_netcdf(grid_nc).grid
    rock = case_rock(case, grid, read_geometry_netcdf(geometry_nc))
    write_rock(petrophysics_out, rock, case.provenance())
    log.info(
        "wrote %s: porosity %.4g-%.4g (mean %.4g), permx %.4g-%.4g mD",
        petrophysics_out,
        rock.poro.min(),
        rock.poro.max(),
        rock.poro.mean(),
        rock.permx.min(),
        rock.permx.max(),
    )
