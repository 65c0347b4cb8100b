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

from ..config import Case, load_case
from ..errors import InputError
from ..io.netcdf import read_geometry_netcdf, read_netcdf
from ..petrophysics import (
    Variogram,
    carman_kozeny,
    depositional_coordinates,
    gaussian_field,
    layer_index,
    lognormal_permeability,
    make_rock,
    normal_porosity,
    per_layer,
)
from .common import log, write_dataset

PROPERTIES = ("poro", "permx", "permy", "permz", "ntg")
UNITS = {"poro": "1", "permx": "mD", "permy": "mD", "permz": "mD", "ntg": "1"}


def _deck_keyword(case: Case, key: str, what: str, grid) -> np.ndarray:
    from ..case_grid import read_case_deck

    if case.data["grid"]["type"] != "deck":
        raise InputError(f"{case.path}: {what}.deck: only deck grids carry keywords")
    deck = read_case_deck(case)
    if key.upper() not in deck.cell_data:
        have = ", ".join(sorted(deck.cell_data)) or "none"
        raise InputError(f"{case.path}: {what}.deck: the deck has no {key.upper()} (it has {have})")
    return deck.cell_data[key.upper()][grid.cells.index_map]


def _property(case: Case, spec: dict[str, Any], what: str, kind: str, ctx: dict[str, Any]) -> np.ndarray:
    """One property from its spec; ``kind`` is porosity, permeability or ntg."""
    n = ctx["grid"].num_cells
    if "constant" in spec:
        return np.full(n, float(spec["constant"]))
    if "layers" in spec:
        try:
            return per_layer(ctx["layer"], spec["layers"])
        except InputError as exc:
            raise InputError(f"{case.path}: {what}.layers: {exc}") from None
    if "deck" in spec:
        return _deck_keyword(case, spec["deck"], what, ctx["grid"])
    field = spec["field"]
    variogram = Variogram(
        field["model"], 1.0, field["len_scale"], tuple(field.get("angles", ())), field.get("nu", 1.0)
    )
    z = gaussian_field(ctx["where"], variogram, seed=case.seed + ctx["offset"][kind])
    mean, std = field.get("mean"), field.get("std", 0.0)
    if kind == "permeability":
        values = lognormal_permeability(z, median=100.0 if mean is None else mean, sigma=std)
        if "bounds" in field:
            values = np.clip(values, *field["bounds"])
        return values
    bounds = tuple(field.get("bounds", (0.0, 1.0)))
    return normal_porosity(z, mean=0.2 if mean is None else mean, std=std, bounds=bounds)


def case_rock(case: Case, grid, geometry):
    """The case's Rock on ``grid`` (with its geometry for the depositional coordinates)."""
    spec = case.data["petrophysics"]
    ctx: dict[str, Any] = {"grid": grid, "offset": {"porosity": 0, "permeability": 1, "ntg": 2}}
    ctx["layer"] = layer_index(grid)
    needs_field = any("field" in (spec.get(k) or {}) for k in ("porosity", "permeability", "ntg"))
    if needs_field:
        ctx["where"] = depositional_coordinates(
            grid, dz_ref=spec.get("dz_ref"), centroids=geometry.cell_centroids
        )
    poro = _property(case, spec["porosity"], "petrophysics.porosity", "porosity", ctx)
    perm_spec = spec.get("permeability", {"carman_kozeny": {}})
    if "carman_kozeny" in perm_spec:
        permx = carman_kozeny(poro, **perm_spec["carman_kozeny"])
    else:
        permx = _property(case, perm_spec, "petrophysics.permeability", "permeability", ctx)
    ntg = _property(case, spec["ntg"], "petrophysics.ntg", "ntg", ctx) if "ntg" in spec else 1.0
    try:
        return make_rock(poro, permx, kv_kh=spec.get("kv_kh", 0.1), ntg=ntg, num_cells=grid.num_cells)
    except InputError as exc:
        raise InputError(f"{case.path}: petrophysics: {exc}") from None


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
