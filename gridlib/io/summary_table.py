"""``results/summary.csv``: every case's ``summary.json`` as one row (and the table writer the
study's ``study.csv`` shares); the ``summary.json`` files read back.

Units are in the header: a column of a physical figure (:data:`gridlib.io.quantities.COLUMNS`)
is named ``<figure> [<unit>]``, e.g. ``pore_volume [m3]``, when every row has that unit. Each
row's values are in its case's unit system (the ``unit_system`` column) and, for volumes and
areas, of its grid's dimension (``griddim``: a 2-D grid's cell "volume" is an area); where rows
differ, the header gives each unit with the rows it applies to, e.g. ``total_volume [m3:
METRIC; ft3: FIELD]`` or ``total_face_area [m2: METRIC 3-D; m: METRIC 2-D]``. Counts have no
unit. :func:`figure_name` gives back the figure's name of a header.
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Mapping, Sequence
from typing import Any

from ..errors import InputError
from ..units import unit_system
from .atomic import atomic_path
from .datasets import damaged, read_json_artifact
from .quantities import COLUMNS as COLUMN_QUANTITIES

COLUMNS = (
    "case",
    "grid_type",
    "griddim",
    "cells",
    "faces",
    "nodes",
    "total_volume",
    "total_bulk_volume",
    "pore_volume",
    "mean_porosity",
    "mean_permx",
    "fault_faces",
    "nnc",
    "coarse_blocks",
    "unit_system",
    "connections",
    "neighbor_connections",
    "fault_connections",
    "pinch_connections",
    "other_connections",
    "min_trans",
    "median_trans",
    "max_trans",
    "total_porv",
    "orientation_median",
    "orientation_p95",
    "orientation_max",
    "k_orientation_median",
    "k_orientation_p95",
    "k_orientation_max",
    "seed",
)


def column_units(name: str, rows: Sequence[Mapping[str, Any]]) -> dict[str, list[str]]:
    """The units of figure ``name`` over the ``rows`` (summary.json contents) that hold it, each
    with the rows' unit systems (and grid dimensions, where the unit depends on them) it applies
    to; empty for a figure without a unit (a count, a name, an unknown figure)."""
    quantity = COLUMN_QUANTITIES.get(name)
    if quantity is None:
        return {}
    rows = [r for r in rows if r.get(name, "") not in ("", None)]
    per_dim = quantity in ("cell_measure", "face_measure") and len({r.get("griddim", 3) for r in rows}) > 1
    found: dict[str, list[str]] = {}
    for row in rows:
        if "unit_system" not in row or row["unit_system"] in ("", None):
            raise InputError(
                f"the summary of case {row.get('case', '?')} has no unit_system (written by an older "
                "gridlib: build the case again)"
            )
        system = unit_system(str(row["unit_system"]))
        griddim = int(row.get("griddim", 3))
        where = f"{system.name} {griddim}-D" if per_dim else system.name
        rows_of = found.setdefault(system.unit(quantity, griddim), [])
        if where not in rows_of:
            rows_of.append(where)
    return found


def header(name: str, rows: Sequence[Mapping[str, Any]]) -> str:
    """The header of column ``name``: the name and its unit (see the module's docstring)."""
    units = column_units(name, rows)
    return f"{name} [{unit_text(units)}]" if units else name


def unit_text(units: Mapping[str, Sequence[str]]) -> str:
    """:func:`column_units` as text: the unit where there is one, else each with its rows
    (``m3: METRIC; ft3: FIELD``)."""
    if len(units) == 1:
        return next(iter(units))
    return "; ".join(f"{unit}: {' / '.join(where)}" for unit, where in units.items())


def figure_name(column: str) -> str:
    """The figure's name of a header: ``pore_volume [m3]`` -> ``pore_volume``."""
    return column.split(" [", 1)[0]


def write_csv(path: str | os.PathLike, columns: Sequence[str], rows: Sequence[Mapping[str, Any]]) -> None:
    """``rows`` as a CSV table of ``columns`` (other keys left out, missing ones empty), the
    columns' units in the header (:func:`header`), atomically."""
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerow([header(c, rows) for c in columns])
    writer = csv.DictWriter(buffer, fieldnames=list(columns), extrasaction="ignore", lineterminator="\n")
    writer.writerows(rows)
    with atomic_path(path) as tmp:
        tmp.write_text(buffer.getvalue())


def read_summaries(paths: Sequence[str | os.PathLike]) -> list[dict[str, Any]]:
    """The ``summary.json`` files (each a JSON object), in order; one InputError naming the
    file that is missing, not UTF-8 JSON or not an object (:func:`~gridlib.io.datasets.damaged`)."""
    out = []
    for path in paths:
        summary = read_json_artifact(path)
        if not isinstance(summary, dict) or "case" not in summary:
            raise damaged(path, "not a case's summary (a JSON object with 'case')")
        out.append(summary)
    return out
