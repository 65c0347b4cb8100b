"""Stage ``study``: a study's variants as one table (``study.csv``), one xarray Dataset
(``study.nc``, one dimension per varied key plus ``realisation``) and its pictures
(:mod:`gridlib.io.study_pictures`: ``study.png``, the main figures against each varied key,
one line per combination of the other keys' values with the realisations' spread; for a
simulated study also ``study_profiles.png`` and ``study_tornado.png``).

The table's columns: ``variant``, one per varied key (its dotted name), ``realisation``,
``seed``, then every figure of the variants' ``summary.json`` (the columns of
``results/summary.csv`` first, then any other number the summaries hold; the lists of
fault and well names and the case's hash are left out).

Units: a varied key's column header, its study.nc coordinate and its study.png axis carry its
unit (``faults.0.throw [m]``; the case schema's ``x-quantity``, :mod:`gridlib.config.key_units`)
in the base case's unit system (METRIC for a grid gridlib builds, a deck's own: ``ft`` for a
FIELD deck), the figures' theirs (:mod:`gridlib.io.summary_table`).
"""

from __future__ import annotations

import json
import os
from collections.abc import Mapping, Sequence
from typing import Any

from ..config.key_units import KeyQuantity, key_quantity
from ..errors import InputError
from ..io.datasets import damaged
from ..io.netcdf import write_dataset
from ..io.picture_style import DPI
from ..io.pictures import save_figure
from ..io.study_pictures import profiles_figure, study_figure, tornado_figure
from ..io.summary_table import COLUMNS, column_units, read_summaries, unit_text, write_csv
from ..study import read_manifest
from .common import log

NOT_FIGURES = ("case", "seed", "case_sha256")


def _scalar(value: Any) -> Any:
    """A value as a table cell: numbers, text and booleans as they are, others as JSON."""
    return value if isinstance(value, int | float | str | bool) else json.dumps(value)


def study_rows(
    manifest: Mapping[str, Any], summaries: Sequence[Mapping[str, Any]]
) -> tuple[list[str], list[dict]]:
    """The table's columns and its rows, in the manifest's order of the variants."""
    keys = list(manifest["keys"])
    by_name = {s["case"]: s for s in summaries}
    figures = [c for c in COLUMNS if c not in NOT_FIGURES]
    for s in summaries:
        for name, value in s.items():
            if (
                name not in figures
                and name not in NOT_FIGURES
                and isinstance(value, int | float | str | bool)
            ):
                figures.append(name)
    present = [f for f in figures if any(f in s for s in summaries)]
    rows = []
    for v in manifest["variants"]:
        summary = by_name[v["name"]]
        row = {"variant": v["name"]}
        row |= {k: _scalar(v["values"][k]) for k in keys}
        row |= {"realisation": v["realisation"], "seed": v["seed"]}
        row |= {f: summary.get(f, "") for f in present}
        rows.append(row)
    return ["variant", *keys, "realisation", "seed", *present], rows


def key_units(
    manifest: Mapping[str, Any], rows: Sequence[Mapping[str, Any]]
) -> dict[str, dict[str, list[str]]]:
    """Each varied key's units over the variants (``rows``), each with the unit systems it
    applies to (as :func:`~gridlib.io.summary_table.column_units`; one unit where the variants
    share a system, as a study's usually do); empty for a key without a unit. What a key measures
    is the manifest's ``key_quantities``, its unit system each variant's ``unit_system``."""
    stated = manifest.get("key_quantities") or {}
    out: dict[str, dict[str, list[str]]] = {}
    for key in manifest["keys"]:
        quantity = KeyQuantity(**stated[key]) if key in stated else key_quantity(key)
        found: dict[str, list[str]] = {}
        out[key] = found
        if quantity.quantity is None:
            continue
        for row in rows:
            system = row.get("unit_system")
            if system in ("", None):
                raise InputError(
                    f"the summary of variant {row.get('variant', '?')} has no unit_system (written by "
                    "an older gridlib: build the study again)"
                )
            systems = found.setdefault(str(quantity.unit(str(system))), [])
            if system not in systems:
                systems.append(str(system))
    return out


def key_header(key: str, units: Mapping[str, Sequence[str]]) -> str:
    """A varied key with its unit: ``faults.0.throw [m]`` (the key alone where it has none)."""
    return f"{key} [{unit_text(units)}]" if units else key


def study_dataset(manifest: Mapping[str, Any], columns: list[str], rows: list[dict]):
    """The table as an xarray Dataset over one dimension per varied key plus ``realisation``
    (a zipped study fills the combinations it does not have with NaN, or "" for text); every
    figure and every varied key's coordinate with a unit has its ``units``
    (``units_by_unit_system`` where the variants' unit systems differ: then each variant's
    values are in its ``unit_system``)."""
    import pandas as pd

    keys = list(manifest["keys"])
    frame = pd.DataFrame(rows, columns=columns)
    for name in columns:
        if frame[name].dtype == object and name not in keys:
            frame[name] = frame[name].replace("", float("nan"))
            numeric = pd.to_numeric(frame[name], errors="coerce")
            if numeric.notna().sum() == frame[name].notna().sum():
                frame[name] = numeric
    ds = frame.set_index([*keys, "realisation"]).to_xarray()
    for name in ds.data_vars:
        if ds[name].dtype == object:
            ds[name] = ds[name].fillna("").astype(str)
    for name in ds.data_vars:
        units = column_units(str(name), rows)
        if len(units) == 1:
            ds[name].attrs["units"] = next(iter(units))
        elif units:  # variants in different unit systems: each in its own (unit_system)
            ds[name].attrs["units_by_unit_system"] = unit_text(units)
    for key, units in key_units(manifest, rows).items():
        if units:
            ds[key].attrs["units" if len(units) == 1 else "units_by_unit_system"] = unit_text(units)
    ds.attrs = {"study": manifest["study"], "combine": manifest["combine"], "varied_keys": json.dumps(keys)}
    return ds


def plot_study(outputs: Mapping[str, str], dataset) -> None:
    """The study's pictures (:mod:`gridlib.io.study_pictures`) from its Dataset: study.png
    (``outputs["png"]``), and, where ``outputs`` names them (a simulated study),
    study_profiles.png (``profiles``) and study_tornado.png (``tornado``)."""
    save_figure(study_figure(dataset), outputs["png"], dpi=DPI)
    if "profiles" in outputs:
        save_figure(profiles_figure(dataset), outputs["profiles"], dpi=DPI)
    if "tornado" in outputs:
        save_figure(tornado_figure(dataset), outputs["tornado"], dpi=DPI)


def stage_study(
    manifest_file: str | os.PathLike, summaries: Sequence[str | os.PathLike], outputs: Mapping[str, str]
) -> None:
    """study.csv, study.nc and study.png (``outputs`` keys ``csv``, ``nc``, ``png``; and
    ``profiles``, ``tornado`` for a simulated study: :func:`plot_study`) from the
    study's manifest (results/<study>/variants.yaml) and its variants' summary.json files."""
    manifest = read_manifest(manifest_file)
    loaded = read_summaries(summaries)
    missing = sorted({v["name"] for v in manifest["variants"]} - {s["case"] for s in loaded})
    if missing:
        raise damaged(manifest_file, f"variants {', '.join(missing)} have no summary.json among the inputs")
    columns, rows = study_rows(manifest, loaded)
    labels = {key: key_header(key, units) for key, units in key_units(manifest, rows).items()}
    write_csv(
        outputs["csv"],
        [labels.get(c, c) for c in columns],
        [{labels.get(name, name): value for name, value in row.items()} for row in rows],
    )
    dataset = study_dataset(manifest, columns, rows)
    write_dataset(outputs["nc"], dataset)
    plot_study(outputs, dataset)
    log.info("wrote the table of study %s (%d variants)", manifest["study"], len(rows))
