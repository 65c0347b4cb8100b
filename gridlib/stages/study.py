"""Stage ``study``: a study's variants as one table (``study.csv``), one xarray Dataset
(``study.nc``, one dimension per varied key plus ``realisation``) and one picture
(``study.png``: the main figures against each varied key, realisations as points with
their spread).

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
from ..io.pictures import save_figure
from ..io.summary_table import COLUMNS, column_units, header, read_summaries, unit_text, write_csv
from ..study import read_manifest
from .common import log

NOT_FIGURES = ("case", "seed", "case_sha256")
# The figures study.png draws against every varied key (those the variants have).
PLOTTED = ("cells", "fault_connections", "pore_volume", "mean_porosity", "median_trans")


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


def _positions(values: list[Any]) -> tuple[list[float], list[str]]:
    """x positions of a key's values: the numbers themselves, else their order."""
    if all(isinstance(v, int | float) and not isinstance(v, bool) for v in values):
        return [float(v) for v in values], [str(v) for v in values]
    return [float(i) for i in range(len(values))], [str(v) for v in values]


def plot_study(path: str | os.PathLike, manifest: Mapping[str, Any], rows: list[dict]) -> None:
    """For each varied key (columns) the main figures (rows) against its values: every variant a
    point, the mean over the other keys' values and the realisations as a line, the spread of
    the realisations (min to max per value) as a bar."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    keys = list(manifest["keys"])
    units = key_units(manifest, rows)
    figures = [f for f in PLOTTED if any(isinstance(r.get(f), int | float) for r in rows)]
    fig, axes = plt.subplots(
        len(figures), len(keys), figsize=(3.6 * len(keys), 2.4 * len(figures)), squeeze=False
    )
    for j, key in enumerate(keys):
        values = list(dict.fromkeys(r[key] for r in rows))
        xs, ticks = _positions(values)
        where = dict(zip(values, xs, strict=True))
        for i, figure in enumerate(figures):
            ax = axes[i][j]
            pts = [(where[r[key]], float(r[figure])) for r in rows if isinstance(r.get(figure), int | float)]
            x, y = np.array(pts).T
            ax.plot(x, y, "o", ms=3, alpha=0.6, color="tab:blue", label="variants")
            mean = [y[x == p].mean() for p in xs]
            low = [y[x == p].min() for p in xs]
            high = [y[x == p].max() for p in xs]
            ax.errorbar(
                xs, mean, yerr=[np.subtract(mean, low), np.subtract(high, mean)], color="k", capsize=3, lw=1
            )
            ax.set_xticks(xs, ticks, fontsize=7)
            if i == len(figures) - 1:
                ax.set_xlabel(key_header(key, units[key]))
            if j == 0:
                ax.set_ylabel(header(figure, rows).replace("_", " "), fontsize=8)
            ax.tick_params(labelsize=7)
    fig.suptitle(f"study {manifest['study']}: {len(rows)} variants", fontsize=10)
    fig.tight_layout()
    save_figure(fig, path)


def stage_study(
    manifest_file: str | os.PathLike, summaries: Sequence[str | os.PathLike], outputs: Mapping[str, str]
) -> None:
    """study.csv, study.nc and study.png (``outputs`` keys ``csv``, ``nc``, ``png``) from the
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
    write_dataset(outputs["nc"], study_dataset(manifest, columns, rows))
    plot_study(outputs["png"], manifest, rows)
    log.info("wrote the table of study %s (%d variants)", manifest["study"], len(rows))
