"""Stage ``study``: a study's variants as one table (``study.csv``), one xarray Dataset
(``study.nc``, one dimension per varied key plus ``realisation``) and its pictures
(:mod:`gridlib.io.study_pictures`: ``study.png``, the main figures against each varied key,
one line per combination of the other keys' values with the realisations' spread; for a
simulated study also ``study_profiles.png`` and ``study_tornado.png``).

The table's columns: ``variant``, one per varied key (its dotted name), ``realisation``,
``seed``, then every figure of the variants' ``summary.json`` (the columns of
``results/summary.csv`` first, then any other number the summaries hold; the lists of
fault and well names and the case's hash are left out).

A simulated study (``simulate: true``) adds, per variant, ``simulation`` (``ok`` or
``failed``), ``simulation_reason`` (Flow's, one line), ``simulation_messages`` (Flow's PRT
file, relative to the study's folder) and the scalar responses of its ``responses.json``
(:mod:`gridlib.io.flow_responses`; NaN for a failed variant), their units in the header
(``FOPT [sm3]``); study.nc also gets the series of the responses over ``time`` (days, the
report days), named ``<response>_series`` where a scalar has the response's name (``FOPT``:
the total at the end; ``FOPT_series``: over time; ``FOPR``: over time).

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
from ..io.flow_responses import Responses, read_responses, response_units
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


SIMULATION_COLUMNS = ("simulation", "simulation_reason", "simulation_messages")
# study.nc's name of a series whose scalar (its value at the end) has the response's name
SERIES_SUFFIX = "_series"


def study_rows(
    manifest: Mapping[str, Any],
    summaries: Sequence[Mapping[str, Any]],
    responses: Mapping[str, Responses] | None = None,
) -> tuple[list[str], list[dict]]:
    """The table's columns and its rows, in the manifest's order of the variants; with
    ``responses`` (variant -> its responses: a simulated study) the simulation's columns and
    the scalar responses after the figures."""
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
    columns = ["variant", *keys, "realisation", "seed", *present]
    if responses is None:
        return columns, rows
    names = list(dict.fromkeys(name for r in responses.values() for name in r.scalars))
    for row in rows:
        r = responses[row["variant"]]
        row |= {
            "simulation": r.status,
            "simulation_reason": r.reason or "",
            "simulation_messages": f"{row['variant']}/{r.messages}" if r.messages else "",
        }
        row |= {name: r.scalars.get(name, float("nan")) for name in names}
    return [*columns, *SIMULATION_COLUMNS, *names], rows


def response_headers(responses: Mapping[str, Responses]) -> dict[str, str]:
    """Each response with its unit, as the table's header names it: ``FOPT [sm3]``."""
    return {
        name: f"{name} [{unit_text(units)}]"
        for name, units in response_units(list(responses.values())).items()
    }


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


def study_dataset(
    manifest: Mapping[str, Any],
    columns: list[str],
    rows: list[dict],
    responses: Mapping[str, Responses] | None = None,
):
    """The table as an xarray Dataset over one dimension per varied key plus ``realisation``
    (a zipped study fills the combinations it does not have with NaN, or "" for text); every
    figure and every varied key's coordinate with a unit has its ``units``
    (``units_by_unit_system`` where the variants' unit systems differ: then each variant's
    values are in its ``unit_system``). With ``responses`` (a simulated study) the scalar
    responses have their units and the series are variables over those dimensions and
    ``time`` (:func:`series_dataset`)."""
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
    if responses is not None:
        series = series_dataset(manifest, rows, responses)
        clashing = {n: f"{n}{SERIES_SUFFIX}" for n in series.data_vars if n in ds.variables}
        ds = ds.merge(series.rename(clashing), join="outer")
        for name, units in response_units(list(responses.values())).items():
            for variable in (name, clashing.get(name)):
                if variable in ds.variables:
                    attr = "units" if len(units) == 1 else "units_by_unit_system"
                    ds[variable].attrs[attr] = unit_text(units)
    ds.attrs = {"study": manifest["study"], "combine": manifest["combine"], "varied_keys": json.dumps(keys)}
    return ds


def series_dataset(
    manifest: Mapping[str, Any], rows: Sequence[Mapping[str, Any]], responses: Mapping[str, Responses]
):
    """The responses' series as an xarray Dataset over the study's dimensions (one per varied
    key, then ``realisation``) and ``time`` (days: the union of the variants' report days; NaN
    where a variant has no value, e.g. a failed one)."""
    import pandas as pd

    keys = list(manifest["keys"])
    names = list(dict.fromkeys(n for r in responses.values() for n in r.series if n != "time"))
    records = []
    for row in rows:
        series = responses[row["variant"]].series
        where = {k: row[k] for k in [*keys, "realisation"]}
        for i, day in enumerate(series.get("time", [])):
            records.append(where | {"time": day} | {n: series[n][i] for n in names if n in series})
    index = [*keys, "realisation", "time"]
    if not records:  # no variant has a series (all failed): the time axis is empty
        return pd.DataFrame(columns=[*index, *names]).set_index(index).to_xarray()
    frame = pd.DataFrame(records, columns=[*index, *names]).astype({n: float for n in names})
    return frame.set_index(index).to_xarray()


def plot_study(outputs: Mapping[str, str], dataset) -> None:
    """The study's pictures (:mod:`gridlib.io.study_pictures`) from its Dataset: study.png
    (``outputs["png"]``), and, where ``outputs`` names them (a simulated study),
    study_profiles.png (``profiles``) and study_tornado.png (``tornado``)."""
    save_figure(study_figure(dataset), outputs["png"], dpi=DPI)
    if "profiles" in outputs:
        save_figure(profiles_figure(dataset), outputs["profiles"], dpi=DPI)
    if "tornado" in outputs:
        save_figure(tornado_figure(dataset), outputs["tornado"], dpi=DPI)


def read_simulations(
    manifest_file: str | os.PathLike, manifest: Mapping[str, Any], simulations: Sequence[str | os.PathLike]
) -> dict[str, Responses] | None:
    """The responses of every variant of a simulated study (their ``simulation/`` folders, each
    in ``results/<study>/<variant>/``), by variant; None for a study that does not simulate."""
    if "simulation" not in manifest:
        return None
    found = {os.path.basename(os.path.dirname(os.path.abspath(f))): f for f in simulations}
    missing = sorted({v["name"] for v in manifest["variants"]} - set(found))
    if missing:
        raise damaged(manifest_file, f"variants {', '.join(missing)} have no simulation among the inputs")
    return {
        v["name"]: read_responses(os.path.join(found[v["name"]], "responses.json"))
        for v in manifest["variants"]
    }


def stage_study(
    manifest_file: str | os.PathLike,
    summaries: Sequence[str | os.PathLike],
    outputs: Mapping[str, str],
    simulations: Sequence[str | os.PathLike] = (),
) -> None:
    """study.csv, study.nc and study.png (``outputs`` keys ``csv``, ``nc``, ``png``; and
    ``profiles``, ``tornado`` for a simulated study: :func:`plot_study`) from the study's
    manifest (results/<study>/variants.yaml), its variants' summary.json files and, for a
    simulated study, their ``simulation/`` folders (each with its responses.json)."""
    manifest = read_manifest(manifest_file)
    loaded = read_summaries(summaries)
    missing = sorted({v["name"] for v in manifest["variants"]} - {s["case"] for s in loaded})
    if missing:
        raise damaged(manifest_file, f"variants {', '.join(missing)} have no summary.json among the inputs")
    responses = read_simulations(manifest_file, manifest, simulations)
    columns, rows = study_rows(manifest, loaded, responses)
    labels = {key: key_header(key, units) for key, units in key_units(manifest, rows).items()}
    if responses is not None:
        labels |= response_headers(responses)
    write_csv(
        outputs["csv"],
        [labels.get(c, c) for c in columns],
        [{labels.get(name, name): value for name, value in row.items()} for row in rows],
    )
    dataset = study_dataset(manifest, columns, rows, responses)
    write_dataset(outputs["nc"], dataset)
    plot_study(outputs, dataset)
    log.info("wrote the table of study %s (%d variants)", manifest["study"], len(rows))
