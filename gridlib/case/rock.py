"""A case's rock (``petrophysics``): porosity (fraction), permeability (mD) and NTG (fraction).

Each property is a constant, one value per layer, a Gaussian random field at depositional
coordinates, or, for deck grids, the deck's own keyword. Fields are seeded with the case's
seed (porosity), seed + 1 (permeability) and seed + 2 (NTG).

Where the keys come from (:func:`case_rock`):

* every grid but a deck: ``porosity``; ``permeability`` (PERMX = PERMY; default
  Carman-Kozeny from the porosity); PERMZ = ``kv_kh`` x PERMX (default 0.1); ``ntg``
  (default 1);
* a deck grid: the deck's rock, each key the case gives replacing its keywords only:
  ``porosity`` PORO, ``permeability`` PERMX and PERMY, ``kv_kh`` PERMZ (= kv_kh x PERMX),
  ``ntg`` NTG (the table in config/README.md). What neither gives defaults as in OPM Flow
  2022.10 (PERMY and PERMZ to PERMX, NTG to 1); a deck without any permeability keyword
  gets the defaults of the other grids (Carman-Kozeny, kv_kh 0.1), and one without PORO
  needs ``porosity``. So a case that gives ``permeability`` but not ``kv_kh`` keeps the
  deck's PERMZ.
"""

from __future__ import annotations

from dataclasses import replace
from functools import partial
from typing import Any

import numpy as np

from ..cell_names import cell_names
from ..config import Case
from ..cornerpoint.deck import Deck
from ..errors import InputError
from ..petrophysics import (
    Rock,
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
from ..units import UnitSystem
from .deck import read_case_deck

KV_KH = 0.1  # the default vertical over horizontal permeability (grids without a deck's)
# petrophysics.nc's names of the deck's rock keywords
ROCK_KEYWORDS = {"PORO": "poro", "PERMX": "permx", "PERMY": "permy", "PERMZ": "permz", "NTG": "ntg"}


def _deck_keyword(case: Case, key: str, what: str, grid, deck: Deck | None = None) -> np.ndarray:
    if case.data["grid"]["type"] != "deck":
        raise InputError(f"{case.path}: {what}.deck: only deck grids carry keywords")
    deck = read_case_deck(case) if deck is None else deck
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
        return _deck_keyword(case, spec["deck"], what, ctx["grid"], ctx.get("deck"))
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


def case_rock_keys(case: Case) -> tuple[str, ...]:
    """The keys the case's ``petrophysics`` section gives (porosity, permeability, kv_kh, ntg,
    dz_ref): a deck case's rock is its deck's but for these."""
    return tuple(case.data.get("petrophysics") or {})


def case_rock(case: Case, grid, geometry) -> Rock:
    """The case's Rock on ``grid`` (with its geometry for the depositional coordinates)."""
    return case_rock_with_sources(case, grid, geometry)[0]


def case_rock_with_sources(case: Case, grid, geometry) -> tuple[Rock, dict[str, str]]:
    """The case's Rock on ``grid`` and where each of its arrays came from ({"poro": "the deck's
    PORO", "permz": "petrophysics.kv_kh x permx (kv_kh 0.1)", ...}; see the module docstring)."""
    spec = case.data.get("petrophysics") or {}
    ctx: dict[str, Any] = {"grid": grid, "offset": {"porosity": 0, "permeability": 1, "ntg": 2}}
    ctx["layer"] = layer_index(grid)
    if any("field" in (spec.get(k) or {}) for k in ("porosity", "permeability", "ntg")):
        ctx["where"] = depositional_coordinates(
            grid, dz_ref=spec.get("dz_ref"), centroids=geometry.cell_centroids
        )
    deck_rock: dict[str, np.ndarray] = {}
    if case.data["grid"]["type"] == "deck":
        ctx["deck"] = read_case_deck(case)
        deck_rock = _rock_of_deck(case, ctx["deck"], grid)
    given: dict[str, tuple[np.ndarray, str]] = {}  # deck keyword -> the case's values, their source
    if "porosity" in spec:
        poro = _property(case, spec["porosity"], "petrophysics.porosity", "porosity", ctx)
        given["PORO"] = (poro, "petrophysics.porosity")
    elif "PORO" in deck_rock:
        poro = deck_rock["PORO"]
    else:
        raise InputError(f"{case.path}: petrophysics.porosity: the deck gives no PORO: give the porosity")
    perm_spec = spec.get("permeability")
    if perm_spec is None and "PERMX" not in deck_rock:
        perm_spec = {"carman_kozeny": {}}
    if perm_spec is not None:
        if "carman_kozeny" in perm_spec:
            permx = carman_kozeny(poro, **perm_spec["carman_kozeny"])
        else:
            permx = _property(case, perm_spec, "petrophysics.permeability", "permeability", ctx)
        given["PERMX"] = given["PERMY"] = (permx, "petrophysics.permeability")
    if "kv_kh" in spec or not deck_rock.keys() & {"PERMX", "PERMY", "PERMZ"}:
        kv_kh = float(spec.get("kv_kh", KV_KH))
        permx = given["PERMX"][0] if "PERMX" in given else deck_rock["PERMX"]
        given["PERMZ"] = (kv_kh * permx, f"petrophysics.kv_kh x permx (kv_kh {kv_kh:g})")
    if "ntg" in spec:
        given["NTG"] = (_property(case, spec["ntg"], "petrophysics.ntg", "ntg", ctx), "petrophysics.ntg")

    values: dict[str, np.ndarray] = {}
    sources: dict[str, str] = {}
    for keyword, name in ROCK_KEYWORDS.items():
        if keyword in given:
            values[name], sources[name] = given[keyword]
        elif keyword in deck_rock:
            values[name], sources[name] = deck_rock[keyword], f"the deck's {keyword}"
        elif keyword in ("PERMY", "PERMZ"):  # as OPM Flow: PERMY and PERMZ default to PERMX
            values[name], sources[name] = values["permx"], f"permx (the deck gives no {keyword})"
        else:
            values[name], sources[name] = np.ones(grid.num_cells), "1 (default)"
    try:
        return make_rock(**values, num_cells=grid.num_cells), sources
    except InputError as exc:
        raise InputError(f"{case.path}: petrophysics: {exc}") from None


def _rock_of_deck(case: Case, deck: Deck, grid) -> dict[str, np.ndarray]:
    """The deck's rock keywords on the grid's cells, checked as OPM Flow would use them
    (:mod:`gridlib.petrophysics.ranges`): negative or undefined values are one InputError naming
    the deck, the keyword and the cells (i, j, k), 1-based; PORO or NTG above 1 are kept (the
    petrophysics stage notes them)."""
    index = grid.cells.index_map
    out = {keyword: deck.cell_data[keyword][index] for keyword in ROCK_KEYWORDS if keyword in deck.cell_data}
    check_rock_values(out, deck.source, partial(cell_names, index_map=index, cart_dims=grid.cart_dims))
    return out


def deck_with_rock(deck: Deck, index: np.ndarray, rock: dict[str, np.ndarray], units: UnitSystem) -> Deck:
    """``deck`` with the case's PORO, PERMX, PERMY, PERMZ and NTG (``rock``, per grid cell:
    ``petrophysics.nc``) on its cells ``index`` (0 on cells outside the grid, which Flow then
    leaves inactive too: no pore volume), in ``units``; every other keyword (MULT*, MULTPV,
    PORV, FLUXNUM, MULTNUM, ...), setting (FAULTS, MULTFLT, PINCH, MINPV, MULTREGT, NNC) and
    EDIT operation (TRANX/TRANY/TRANZ, EDITNNC) stays as the deck gives it."""

    def on_deck(values: np.ndarray) -> np.ndarray:
        full = np.zeros(deck.num_cells)  # cells outside the grid (inactive, collapsed) are never read
        full[index] = values
        return full

    cell_data = {**deck.cell_data, **{key: on_deck(rock[name]) for key, name in ROCK_KEYWORDS.items()}}
    return replace(deck, cell_data=cell_data, units=units.name)
