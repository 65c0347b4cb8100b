"""A case's rock (``petrophysics``): porosity (fraction), permeability (mD; ``permz = kv_kh *
permx``) and NTG (fraction), each a constant, one value per layer, a Gaussian random field at
depositional coordinates, or, for deck grids, the deck's own keyword. Fields are seeded with the
case's seed (porosity), seed + 1 (permeability) and seed + 2 (NTG)."""

from __future__ import annotations

from functools import partial
from typing import Any

import numpy as np

from ..cell_names import cell_names
from ..config import Case
from ..errors import InputError
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
from ..petrophysics.ranges import check_rock_values
from .deck import read_case_deck


def _deck_keyword(case: Case, key: str, what: str, grid) -> np.ndarray:
    if case.data["grid"]["type"] != "deck":
        raise InputError(f"{case.path}: {what}.deck: only deck grids carry keywords")
    deck = read_case_deck(case)
    if key.upper() not in deck.cell_data:
        have = ", ".join(sorted(deck.cell_data)) or "none"
        raise InputError(f"{case.path}: {what}.deck: the deck has no {key.upper()} (it has {have})")
    values = deck.cell_data[key.upper()][grid.cells.index_map]
    # negative or undefined values: an error naming the deck's cells (above 1: the stage's note)
    check_rock_values(
        {key.upper(): values},
        deck.source,
        partial(cell_names, index_map=grid.cells.index_map, cart_dims=grid.cart_dims),
    )
    return values


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
